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

/// The command line's options that the library's settings messages name, with the keyword
/// Python takes for each (`RenderSettings::validate` speaks the command line's language).
const PYTHON_KEYWORDS: [(&str, &str); 12] = [
    ("--width/--height", "width=/height="),
    ("--spp", "spp="),
    ("--max-path-length", "max_path_length="),
    ("--samples-per-frame", "samples_per_frame="),
    ("--tile-size", "tile_size="),
    ("--noise-threshold", "noise_threshold="),
    ("--noise-min-spp", "noise_min_spp="),
    ("--guide-training-spp", "guide_training_spp="),
    ("--guiding", "guiding=True"),
    ("--integrator", "integrator="),
    ("--region", "region="),
    ("--medium", "medium"),
];

/// A settings message with each option the command line knows it by (`--spp 0`) named as
/// Python's keyword (`spp=0`).
pub fn in_python_words(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let option = &rest[at..];
        // The longest option that starts here and ends at a word's end.
        let found = PYTHON_KEYWORDS
            .iter()
            .filter(|(flag, _)| {
                option.starts_with(flag)
                    && !option[flag.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '-')
            })
            .max_by_key(|(flag, _)| flag.len());
        match found {
            Some((flag, keyword)) => {
                out.push_str(keyword);
                rest = &option[flag.len()..];
                // `--spp 0` reads `spp=0`: the value follows the `=` without a space.
                if keyword.ends_with('=') && rest.starts_with(' ') {
                    rest = &rest[1..];
                }
            }
            None => {
                out.push_str("--");
                rest = &option[2..];
            }
        }
    }
    out.push_str(rest);
    out
}
