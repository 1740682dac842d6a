//! Object values: every UOI object is an i32 (`i`) or an f64 (`d`).

use std::fmt;

/// The value type of an object, written `i` or `d` in traces and docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ValueType {
    /// 32-bit signed integer (`i`).
    I32,
    /// 64-bit IEEE double (`d`).
    F64,
}

impl ValueType {
    /// The letter used in traces: `i` or `d`.
    pub const fn letter(self) -> char {
        match self {
            ValueType::I32 => 'i',
            ValueType::F64 => 'd',
        }
    }

    /// Parses the trace letter (`i`/`d`, case-insensitive).
    pub fn from_letter(s: &str) -> Option<Self> {
        match s {
            "i" | "I" => Some(ValueType::I32),
            "d" | "D" => Some(ValueType::F64),
            _ => None,
        }
    }
}

impl fmt::Display for ValueType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// A value read from or written to an object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// An `i` value.
    I32(i32),
    /// A `d` value.
    F64(f64),
}

impl Value {
    /// The type of this value.
    pub const fn value_type(self) -> ValueType {
        match self {
            Value::I32(_) => ValueType::I32,
            Value::F64(_) => ValueType::F64,
        }
    }

    /// The integer, if this is an `i` value.
    pub const fn as_i32(self) -> Option<i32> {
        match self {
            Value::I32(v) => Some(v),
            Value::F64(_) => None,
        }
    }

    /// The double, if this is a `d` value.
    pub const fn as_f64(self) -> Option<f64> {
        match self {
            Value::F64(v) => Some(v),
            Value::I32(_) => None,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::I32(v) => write!(f, "{v}"),
            Value::F64(v) => write!(f, "{v}"),
        }
    }
}
