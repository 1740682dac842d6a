//! The declarative object table a module hands to the dispatcher.

use std::fmt;
use std::ops::RangeInclusive;

use crate::{AccessError, ObjectAddress, Value, ValueType};

/// Access right of an object: `r`, `w` or `rw` in an object map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Access {
    /// `r`: read only.
    ReadOnly,
    /// `w`: write only (a command).
    WriteOnly,
    /// `rw`: read and write.
    ReadWrite,
}

impl fmt::Display for Access {
    /// `r`, `w` or `rw`, as in an object map.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Access::ReadOnly => "r",
            Access::WriteOnly => "w",
            Access::ReadWrite => "rw",
        })
    }
}

impl Access {
    /// Whether a read is allowed.
    pub const fn readable(self) -> bool {
        !matches!(self, Access::WriteOnly)
    }

    /// Whether a write is allowed.
    pub const fn writable(self) -> bool {
        !matches!(self, Access::ReadOnly)
    }
}

/// What an object means to a user, for the object reference a module's
/// documentation is generated from: implemented by a module's object keys.
pub trait Meaning {
    /// One or two sentences: what a read gives, what a write does, the
    /// default.
    fn meaning(&self) -> &'static str;
}

/// Values a write may carry: the range column of an object map.
/// A non-finite double is outside every range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueRange {
    /// Any i32.
    AnyInt,
    /// `min..=max`.
    Int {
        /// Smallest allowed value.
        min: i32,
        /// Largest allowed value.
        max: i32,
    },
    /// One of a listed set (`17, 18, 19`).
    IntSet(&'static [i32]),
    /// Any finite double.
    AnyFinite,
    /// A finite double in `min..=max`.
    Finite {
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
}

impl ValueRange {
    /// Whether `value` lies in this range. The type is checked separately.
    pub fn contains(self, value: Value) -> bool {
        match (self, value) {
            (ValueRange::AnyInt, Value::I32(_)) => true,
            (ValueRange::Int { min, max }, Value::I32(v)) => (min..=max).contains(&v),
            (ValueRange::IntSet(set), Value::I32(v)) => set.contains(&v),
            (ValueRange::AnyFinite, Value::F64(v)) => v.is_finite(),
            (ValueRange::Finite { min, max }, Value::F64(v)) => {
                v.is_finite() && (min..=max).contains(&v)
            }
            _ => false,
        }
    }
}

impl fmt::Display for ValueRange {
    /// The range column of an object map: `any`, `0..=7`, `17, 18, 19`,
    /// `finite`, `-1e9..=1e9`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ValueRange::AnyInt => f.write_str("any"),
            ValueRange::Int { min, max } if min == max => write!(f, "{min}"),
            ValueRange::Int { min, max } => write!(f, "{min}..={max}"),
            ValueRange::IntSet(set) => {
                let items: Vec<String> = set.iter().map(i32::to_string).collect();
                f.write_str(&items.join(", "))
            }
            ValueRange::AnyFinite => f.write_str("finite"),
            ValueRange::Finite { min, max } if max == f64::MAX => write!(f, ">= {}", Short(min)),
            ValueRange::Finite { min, max } if min == -f64::MAX => write!(f, "<= {}", Short(max)),
            ValueRange::Finite { min, max } => write!(f, "{}..={}", Short(min), Short(max)),
        }
    }
}

/// A range bound written short: `1e9` rather than `1000000000`.
struct Short(f64);

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.abs() >= 1e6 {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

/// One row of a module's object table: where the object lives, its type,
/// access and range, and the module's key for it.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectDesc<K> {
    /// The module's own name for the object (an enum variant, typically).
    pub key: K,
    /// The name of the object in its map.
    pub name: &'static str,
    /// DeviceNumber.
    pub device: u16,
    /// The indexes under which the object exists (e.g. `1..=32`).
    pub index: RangeInclusive<u16>,
    /// The subindexes it occupies (one, or a run like `20..=27`).
    pub sub: RangeInclusive<u16>,
    /// Value type.
    pub ty: ValueType,
    /// Access right.
    pub access: Access,
    /// Values a write may carry.
    pub range: ValueRange,
}

impl<K> ObjectDesc<K> {
    /// An object of type `ty` at one subindex.
    #[allow(clippy::too_many_arguments)]
    pub const fn new(
        key: K,
        name: &'static str,
        device: u16,
        index: RangeInclusive<u16>,
        sub: u16,
        ty: ValueType,
        access: Access,
        range: ValueRange,
    ) -> Self {
        Self {
            key,
            name,
            device,
            index,
            sub: sub..=sub,
            ty,
            access,
            range,
        }
    }

    /// An `i` object at one subindex.
    pub const fn int(
        key: K,
        name: &'static str,
        device: u16,
        index: RangeInclusive<u16>,
        sub: u16,
        access: Access,
        range: ValueRange,
    ) -> Self {
        Self::new(key, name, device, index, sub, ValueType::I32, access, range)
    }

    /// A `d` object at one subindex.
    pub const fn double(
        key: K,
        name: &'static str,
        device: u16,
        index: RangeInclusive<u16>,
        sub: u16,
        access: Access,
        range: ValueRange,
    ) -> Self {
        Self::new(key, name, device, index, sub, ValueType::F64, access, range)
    }

    /// The same object spread over the subindexes `first..=last`.
    pub const fn subs(mut self, first: u16, last: u16) -> Self {
        self.sub = first..=last;
        self
    }

    /// The same row under another key (a module appending an extension's
    /// rows to its own table).
    pub fn with_key<K2>(&self, key: K2) -> ObjectDesc<K2> {
        ObjectDesc {
            key,
            name: self.name,
            device: self.device,
            index: self.index.clone(),
            sub: self.sub.clone(),
            ty: self.ty,
            access: self.access,
            range: self.range,
        }
    }

    /// Whether this row answers for `addr` (bus not considered).
    pub fn matches(&self, addr: ObjectAddress) -> bool {
        self.device == addr.device
            && self.index.contains(&addr.index)
            && self.sub.contains(&addr.sub)
    }
}

/// Finds the row for `addr` in a module table: `NoObject` when no row has
/// that device and index, `NoSubindex` when the index exists but not the
/// subindex. The bus number is not looked at.
pub fn lookup<K>(
    table: &[ObjectDesc<K>],
    addr: ObjectAddress,
) -> Result<&ObjectDesc<K>, AccessError> {
    let mut index_exists = false;
    for row in table {
        if row.device == addr.device && row.index.contains(&addr.index) {
            if row.sub.contains(&addr.sub) {
                return Ok(row);
            }
            index_exists = true;
        }
    }
    Err(if index_exists {
        AccessError::NoSubindex
    } else {
        AccessError::NoObject
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bus of the example: the wire carries any bus number (bus 1300's
    /// objects are named in tc-objects, which this layer does not know;
    /// docs/decisions.md, decision 521).
    const EXAMPLE_BUS: u16 = 7;

    #[test]
    fn ranges() {
        assert!(ValueRange::AnyInt.contains(Value::I32(i32::MIN)));
        assert!(!ValueRange::AnyInt.contains(Value::F64(0.0)));
        assert!(ValueRange::Int { min: 0, max: 7 }.contains(Value::I32(7)));
        assert!(!ValueRange::Int { min: 0, max: 7 }.contains(Value::I32(8)));
        assert!(!ValueRange::Int { min: 0, max: 7 }.contains(Value::I32(-1)));
        assert!(ValueRange::IntSet(&[17, 18, 19]).contains(Value::I32(18)));
        assert!(!ValueRange::IntSet(&[17, 18, 19]).contains(Value::I32(20)));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!ValueRange::AnyFinite.contains(Value::F64(bad)));
            assert!(!ValueRange::Finite {
                min: 0.0,
                max: f64::MAX
            }
            .contains(Value::F64(bad)));
        }
        assert!(ValueRange::Finite {
            min: 0.0,
            max: f64::MAX
        }
        .contains(Value::F64(0.0)));
        assert!(!ValueRange::Finite {
            min: 0.0,
            max: f64::MAX
        }
        .contains(Value::F64(-1e-9)));
    }

    #[test]
    fn lookup_distinguishes_object_and_subindex() {
        let table = [
            ObjectDesc::int(1, "a", 1, 1..=32, 1, Access::ReadWrite, ValueRange::AnyInt),
            ObjectDesc::double(
                2,
                "b",
                1,
                1..=32,
                6,
                Access::ReadWrite,
                ValueRange::AnyFinite,
            ),
            ObjectDesc::double(
                3,
                "c",
                3,
                1..=32,
                0,
                Access::ReadOnly,
                ValueRange::AnyFinite,
            )
            .subs(20, 27),
        ];
        let at = |d, i, s| ObjectAddress::new(EXAMPLE_BUS, d, i, s);
        assert_eq!(lookup(&table, at(1, 1, 1)).map(|r| r.key), Ok(1));
        assert_eq!(lookup(&table, at(1, 32, 6)).map(|r| r.key), Ok(2));
        assert_eq!(
            lookup(&table, at(1, 2, 7)).map(|r| r.key),
            Err(AccessError::NoSubindex)
        );
        assert_eq!(
            lookup(&table, at(1, 0, 1)).map(|r| r.key),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            lookup(&table, at(1, 33, 1)).map(|r| r.key),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            lookup(&table, at(2, 1, 1)).map(|r| r.key),
            Err(AccessError::NoObject)
        );
        assert_eq!(lookup(&table, at(3, 1, 27)).map(|r| r.key), Ok(3));
        assert_eq!(
            lookup(&table, at(3, 1, 28)).map(|r| r.key),
            Err(AccessError::NoSubindex)
        );
    }
}
