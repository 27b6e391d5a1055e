//! vkpath's errors as Python exceptions, with the one-line message the command line prints
//! after `vkpath: error: `.

use pyo3::create_exception;
use pyo3::exceptions::PyRuntimeError;
use pyo3::PyErr;

create_exception!(
    vkpath,
    VkpathError,
    PyRuntimeError,
    "What went wrong in vkpath, in the one line the command line prints after `vkpath: error: `."
);

/// The exception for `error`: its message formatted as `main` formats it (`{:#}`, the whole
/// chain of causes on one line).
pub fn to_py(error: impl Into<anyhow::Error>) -> PyErr {
    VkpathError::new_err(format!("{:#}", error.into()))
}

/// A `VkpathError` with this message.
pub fn message(text: impl Into<String>) -> PyErr {
    VkpathError::new_err(text.into())
}
