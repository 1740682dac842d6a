//! Python ints as the library's numbers: an int of any size is taken, one
//! beyond the 64 bits saturated, so that a value out of range is refused
//! with the library's error (`addipos.Argument`, `addipos.NoObject`, ...)
//! and never with Python's `OverflowError`.

use pyo3::prelude::*;
use pyo3::types::PyInt;

/// `value` as an i64 when it is a Python int (`bool` included), one
/// beyond i64 saturated to `i64::MIN` or `i64::MAX`; `None`: not an int.
pub fn saturating_int(value: &Bound<'_, PyAny>) -> Option<i64> {
    if let Ok(v) = value.extract::<i64>() {
        return Some(v);
    }
    if !value.is_instance_of::<PyInt>() {
        return None;
    }
    let negative = value.lt(0).ok()?;
    Some(if negative { i64::MIN } else { i64::MAX })
}

/// `value` as an i32 if it is an int that fits, else `None`.
pub fn i32_of(value: &Bound<'_, PyAny>) -> Option<i32> {
    saturating_int(value).and_then(|v| i32::try_from(v).ok())
}
