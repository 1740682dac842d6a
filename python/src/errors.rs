//! The library's failures as Python exceptions.

use addipos_host::{Error, ErrorCode};
use pyo3::prelude::*;

use crate::pyside;

/// The exception of a failed call: the class of its code, with its code
/// and message.
pub fn to_py(py: Python<'_>, e: &Error) -> PyErr {
    pyside::error(py, e.code().code(), e.message())
}

/// A bad argument (`addipos.Argument`, a `ValueError`).
pub fn argument(py: Python<'_>, message: impl Into<String>) -> PyErr {
    to_py(py, &Error::argument(message))
}

/// The failure of a call on a closed connection (`addipos.Connection`).
pub fn closed() -> Error {
    Error::new(
        ErrorCode::Connection,
        "the connection is closed: open another with addipos.open()",
    )
}
