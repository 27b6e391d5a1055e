//! `vkpath.Medium` and `render(..., medium=)`: the command line's `--medium` text
//! (`sigma_a=R,G,B:sigma_s=R,G,B:g=G`) read and checked by the library's
//! `vkpath::medium::Medium`, so that Python accepts exactly the media the command line
//! does, with the same messages (docs/media.md).

use pyo3::prelude::*;
use vkpath::medium::Medium;

use crate::errors::argument_error;

/// The medium `text` describes, or a `vkpath.ArgumentError` (a `ValueError`) naming
/// `medium=` and what is wrong, in the words `render --medium` uses.
pub fn medium_of(text: &str) -> PyResult<Medium> {
    text.parse::<Medium>()
        .map_err(|error| argument_error(format!("medium='{text}': {error}")))
}

/// `text` (`--medium`'s) read and checked: `(sigma_a, sigma_s, g)`, the coefficients per
/// scene unit as (R, G, B) and the Henyey-Greenstein anisotropy, each as the renderer
/// stores it (float32). Raises `vkpath.ArgumentError` for text the command line refuses.
#[pyfunction]
pub fn parse_medium(text: &str) -> PyResult<([f32; 3], [f32; 3], f32)> {
    let medium = medium_of(text)?;
    Ok((
        medium.absorption.to_array(),
        medium.scattering.to_array(),
        medium.anisotropy,
    ))
}
