//! `addipos.Handle`: a handle to one object, as `uoi_init` gives it, with
//! the reads and writes through it.

use std::sync::Arc;

use addipos_host::Descriptor;
use pyo3::prelude::*;
use uoi::ValueType;

use crate::errors;
use crate::link::Link;
use crate::numbers;

/// A handle to one object of a connection (from `Machine.init`).
///
/// Reads and writes through it go to the connection it came from:
/// `h.read_int()` is `m.read_int(h)`. A Clean (1300/0/1/0 = 1) voids every
/// handle issued before it: they raise `addipos.StaleHandle`, and
/// `m.init(...)` gives a working one.
#[pyclass(name = "Handle", module = "addipos", frozen)]
#[derive(Debug)]
pub struct Handle {
    link: Arc<Link>,
    /// The library's handle.
    pub raw: addipos_host::Handle,
    descriptor: Descriptor,
    ty: ValueType,
}

impl Handle {
    /// A handle of `link` to the object `descriptor` names, of type `ty`.
    pub fn new(
        link: Arc<Link>,
        raw: addipos_host::Handle,
        descriptor: Descriptor,
        ty: ValueType,
    ) -> Self {
        Self {
            link,
            raw,
            descriptor,
            ty,
        }
    }
}

/// Reads an i32 object through `h`.
pub fn read_int(link: &Link, py: Python<'_>, h: addipos_host::Handle) -> PyResult<i32> {
    link.call(py, |m| m.read_int(h))
}

/// Reads an f64 object through `h`.
pub fn read_double(link: &Link, py: Python<'_>, h: addipos_host::Handle) -> PyResult<f64> {
    link.call(py, |m| m.read_double(h))
}

/// Writes an i32 object through `h`; a Python int beyond i32 (of any
/// size), or a value that is not an int, is `addipos.Argument`.
pub fn write_int(
    link: &Link,
    py: Python<'_>,
    h: addipos_host::Handle,
    value: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let v = match numbers::saturating_int(value) {
        None => {
            return Err(errors::argument(
                py,
                format!("write_int: {} is not an integer", repr(value)),
            ))
        }
        Some(v) => i32::try_from(v).map_err(|_| {
            errors::argument(
                py,
                format!("write_int: {value} is not a 32-bit integer (-2147483648..2147483647)"),
            )
        })?,
    };
    link.call(py, |m| m.write_int(h, v))
}

/// `repr(value)`, for a message.
pub fn repr(value: &Bound<'_, PyAny>) -> String {
    value
        .repr()
        .map_or_else(|_| "the value".to_string(), |r| r.to_string())
}

/// Writes an f64 object through `h`.
pub fn write_double(
    link: &Link,
    py: Python<'_>,
    h: addipos_host::Handle,
    value: f64,
) -> PyResult<()> {
    link.call(py, |m| m.write_double(h, value))
}

#[pymethods]
impl Handle {
    /// Reads an i32 object (a double object raises `addipos.TypeMismatch`).
    fn read_int(&self, py: Python<'_>) -> PyResult<i32> {
        read_int(&self.link, py, self.raw)
    }

    /// Reads a double object (an i32 object raises `addipos.TypeMismatch`).
    fn read_double(&self, py: Python<'_>) -> PyResult<f64> {
        read_double(&self.link, py, self.raw)
    }

    /// Writes an i32 object.
    fn write_int(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        write_int(&self.link, py, self.raw, value)
    }

    /// Writes a double object.
    fn write_double(&self, py: Python<'_>, value: f64) -> PyResult<()> {
        write_double(&self.link, py, self.raw, value)
    }

    /// Reads the object as its type says: an `int` for an i32 object, a
    /// `float` for a double object.
    fn read(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(match self.ty {
            ValueType::I32 => self.read_int(py)?.into_pyobject(py)?.into_any().unbind(),
            ValueType::F64 => self.read_double(py)?.into_pyobject(py)?.into_any().unbind(),
        })
    }

    /// Writes the object as its type says (`write_int` or `write_double`).
    fn write(&self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        match self.ty {
            ValueType::I32 => self.write_int(py, value),
            ValueType::F64 => {
                let v: f64 = value
                    .extract()
                    .map_err(|_| errors::argument(py, format!("write: {value} is not a number")))?;
                self.write_double(py, v)
            }
        }
    }

    /// Releases the handle (`uoi_clean_handle`): it raises
    /// `addipos.StaleHandle` from now on.
    fn release(&self, py: Python<'_>) -> PyResult<()> {
        let h = self.raw;
        self.link.call(py, move |m| m.release(h))
    }

    /// The object's descriptor: `(bus, device, index, subindex)`.
    #[getter]
    fn descriptor(&self) -> (i32, i32, i32, i32) {
        let d = &self.descriptor;
        (d.bus_number, d.device_number, d.index, d.sub_index)
    }

    /// The object's value type: `"int"` (i32) or `"double"` (f64).
    #[getter]
    fn value_type(&self) -> &'static str {
        match self.ty {
            ValueType::I32 => "int",
            ValueType::F64 => "double",
        }
    }

    /// The library's handle number (the `uoi_handle` of the C library).
    #[getter]
    fn number(&self) -> u32 {
        self.raw.raw()
    }

    fn __repr__(&self) -> String {
        let d = &self.descriptor;
        format!(
            "<addipos.Handle {}/{}/{}/{} {} #{:#010x}>",
            d.bus_number,
            d.device_number,
            d.index,
            d.sub_index,
            self.value_type(),
            self.raw.raw()
        )
    }
}
