//! # `addipos._addipos` — the host library for Python
//!
//! The extension module of the Python package `addipos` (docs/python.md):
//! the host library's Rust API ([`addipos_host::Machine`]) with PyO3. A
//! connection ([`machine::PyMachine`], the class `addipos.Machine`) opens
//! a target string, hands out object handles ([`handle::Handle`]), spools
//! motion and runs the executor; every failure of the library is raised as
//! the exception class the package defines for its code (`addipos.Range`, `addipos.StaleHandle`,
//! ...). Calls that reach the emulator run with the GIL released.
//!
//! The package around it (`python/addipos/__init__.py`) defines the
//! exceptions and the `Position` tuple in Python; [`pyside`] finds them.

mod errors;
mod handle;
mod interruptible;
mod link;
mod machine;
mod numbers;
mod pyside;
mod spooled;
mod words;

use pyo3::prelude::*;

/// Opens a connection to `target` (see docs/python.md, "Targets").
///
/// `record` names a trace file the session is recorded into (instead of
/// `$ADDIPOS_RECORD`); `timeout` is the longest `exec` wait in seconds.
#[pyfunction]
#[pyo3(signature = (target=None, *, record=None, timeout=None))]
fn open(
    py: Python<'_>,
    target: Option<&str>,
    record: Option<std::path::PathBuf>,
    timeout: Option<f64>,
) -> PyResult<machine::PyMachine> {
    machine::PyMachine::open(py, target.unwrap_or(""), record, timeout)
}

/// The extension module.
#[pymodule]
fn _addipos(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(open, m)?)?;
    m.add_class::<machine::PyMachine>()?;
    m.add_class::<handle::Handle>()?;
    Ok(())
}
