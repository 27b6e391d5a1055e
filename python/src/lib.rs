//! `vkpath._vkpath`, the native half of the `vkpath` Python package: scenes and cameras
//! (`scene`), rendering (`render`), and images in and out (`images`, `check`). The Python
//! half (`vkpath/__init__.py`) turns the raw pixels into numpy arrays and the JSON reports
//! into dicts; everything else (defaults, names, messages) is the vkpath library's, so that
//! Python and the command line agree.

use pyo3::prelude::*;

mod arrays;
mod errors;
mod images;
mod medium;
mod names;
mod render;
mod scene;

/// The native module; see the `vkpath` package for the documented API.
#[pymodule]
mod _vkpath {
    #[pymodule_export]
    use crate::errors::VkpathError;
    #[pymodule_export]
    use crate::images::{check, compare, read_exr, read_exr_channels, save};
    #[pymodule_export]
    use crate::medium::parse_medium;
    #[pymodule_export]
    use crate::render::{default_settings, render, Session};
    #[pymodule_export]
    use crate::scene::{Camera, Scene};

    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::types::PyModuleMethods as _;
        m.add("MATERIAL_KEYS", crate::arrays::material_keys())?;
        m.add("LIGHT_KEYS", crate::arrays::LIGHT_KEYS.to_vec())?;
        m.add("__version__", env!("CARGO_PKG_VERSION"))
    }
}
