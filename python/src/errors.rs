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

// `vkpath.ArgumentError`, a `VkpathError` and a `ValueError`: defined in Python
// (`vkpath/__init__.py`), which can give a class two bases, and looked up when raised.
pyo3::import_exception!(vkpath, ArgumentError);

/// A `vkpath.ArgumentError` (a `ValueError` and a `VkpathError`) with this message: an
/// argument of the wrong shape, type or value, named in the message.
pub fn argument_error(text: impl Into<String>) -> PyErr {
    ArgumentError::new_err(text.into())
}
