//! What the extension finds in the Python package around it: the
//! exception classes (through `addipos._error`, which picks the class of
//! a code) and the `Position` tuple. Looked up once, then kept.

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyTuple;

/// The package that defines the exceptions and `Position`.
const PACKAGE: &str = "addipos";

static ERROR_FACTORY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
static POSITION: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// The exception `addipos._error(code, message)` builds: the class of the
/// code (`addipos.Range`, `addipos.StaleHandle`, ...), or `addipos.Error`
/// for a code the package does not know.
pub fn error(py: Python<'_>, code: u32, message: &str) -> PyErr {
    let built = ERROR_FACTORY
        .import(py, PACKAGE, "_error")
        .and_then(|f| f.call1((code, message)));
    match built {
        Ok(exc) => PyErr::from_value(exc),
        Err(e) => e,
    }
}

/// `addipos.Position` of the 8 axes.
pub fn position(py: Python<'_>, p: [f64; 8]) -> PyResult<Py<PyAny>> {
    let class = POSITION.import(py, PACKAGE, "Position")?;
    Ok(class.call1(PyTuple::new(py, p)?)?.unbind())
}

static ELEMENT: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// `addipos.Element` built from its fields, in the order the class
/// declares them.
pub fn element<'py>(py: Python<'py>, fields: Bound<'py, PyTuple>) -> PyResult<Py<PyAny>> {
    let class = ELEMENT.import(py, PACKAGE, "Element")?;
    Ok(class.call1(fields)?.unbind())
}
