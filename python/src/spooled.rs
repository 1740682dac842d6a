//! The elements a connection spooled (its spool log), as
//! `addipos.Element` tuples: what the correction made of the programmed
//! path.

use addipos_host::SpoolRecord;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::pyside;

/// One spooled element as an `addipos.Element`: kind (`"LIN"`, `"RAP"`,
/// `"CIR"`), start and end positions, feed, origin (`"Approach"`,
/// `"Corrected"`, ...), for an arc its direction (`True`:
/// counter-clockwise) and centre in its plane, else `None`.
pub fn element(py: Python<'_>, e: &SpoolRecord) -> PyResult<Py<PyAny>> {
    let kind = match (e.arc, e.rapid) {
        (Some(_), _) => "CIR",
        (None, true) => "RAP",
        (None, false) => "LIN",
    };
    let ccw = e.arc.map(|a| a.ccw);
    let centre = e.arc.map(|a| (a.centre[0], a.centre[1]));
    let fields = PyTuple::new(
        py,
        [
            kind.into_pyobject(py)?.into_any(),
            pyside::position(py, e.start)?.into_bound(py),
            pyside::position(py, e.end)?.into_bound(py),
            e.feed.into_pyobject(py)?.into_any(),
            e.origin.name().into_pyobject(py)?.into_any(),
            ccw.into_pyobject(py)?.into_any(),
            centre.into_pyobject(py)?.into_any(),
        ],
    )?;
    pyside::element(py, fields)
}
