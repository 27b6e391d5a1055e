//! The command line's names of the library's choices (`"mis"`, `"sobol"`, `"agx"`, ...),
//! read through the same `clap::ValueEnum` derivations the command line parses them with,
//! so that Python accepts exactly the command line's spellings.

use clap::ValueEnum;
use pyo3::PyResult;

use crate::errors::argument_error;

/// The value called `name` (as `--option name` would be), or an error naming `option` and
/// the possible values.
pub fn parse<T: ValueEnum>(option: &str, name: &str) -> PyResult<T> {
    T::from_str(name, false).map_err(|_| {
        argument_error(format!(
            "{option}='{name}' is not one of {}",
            possible_values::<T>().join(", ")
        ))
    })
}

/// `parse` for an optional value: `None` stays `None`.
pub fn parse_optional<T: ValueEnum>(option: &str, name: Option<&str>) -> PyResult<Option<T>> {
    name.map(|name| parse(option, name)).transpose()
}

/// The command line's name of `value`.
pub fn name_of<T: ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_owned())
        .unwrap_or_default()
}

/// The names the command line accepts for `T`.
fn possible_values<T: ValueEnum>() -> Vec<String> {
    T::value_variants()
        .iter()
        .filter_map(|v| v.to_possible_value())
        .map(|v| v.get_name().to_owned())
        .collect()
}
