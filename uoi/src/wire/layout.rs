//! Payload layouts of the object layer's own operations (READ, WRITE),
//! declared with `zerocopy` (docs/protocol.md, "Address", "ReadReq",
//! "Value", "WriteReq").

use zerocopy::byteorder::little_endian::{U16, U64};
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

use crate::{ObjectAddress, Value, ValueType};

/// An object address (8 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WireAddr {
    /// BusNumber.
    pub bus: U16,
    /// DeviceNumber.
    pub device: U16,
    /// Index.
    pub index: U16,
    /// SubIndex.
    pub sub: U16,
}

/// `READ` request payload (12 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct ReadReq {
    /// The object.
    pub addr: WireAddr,
    /// Type asked for: `b'i'` or `b'd'`.
    pub ty: u8,
    /// Zero.
    pub pad: [u8; 3],
}

/// A value (12 bytes): type letter and 64 bits (an `i` value sign-extended,
/// a `d` value as IEEE bits). Also the READ answer.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WireValue {
    /// `b'i'` or `b'd'`.
    pub ty: u8,
    /// Zero.
    pub pad: [u8; 3],
    /// The value's bits.
    pub bits: U64,
}

/// `WRITE` request payload (20 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WriteReq {
    /// The object.
    pub addr: WireAddr,
    /// The value.
    pub value: WireValue,
}

impl From<ObjectAddress> for WireAddr {
    fn from(a: ObjectAddress) -> Self {
        Self {
            bus: a.bus.into(),
            device: a.device.into(),
            index: a.index.into(),
            sub: a.sub.into(),
        }
    }
}

impl From<&WireAddr> for ObjectAddress {
    fn from(a: &WireAddr) -> Self {
        ObjectAddress::new(a.bus.get(), a.device.get(), a.index.get(), a.sub.get())
    }
}

impl From<Value> for WireValue {
    fn from(v: Value) -> Self {
        let (ty, bits) = match v {
            Value::I32(i) => (b'i', i64::from(i) as u64),
            Value::F64(d) => (b'd', d.to_bits()),
        };
        Self {
            ty,
            pad: [0; 3],
            bits: bits.into(),
        }
    }
}

/// The value type a type byte names.
pub fn type_from_wire(t: u8) -> Option<ValueType> {
    match t {
        b'i' => Some(ValueType::I32),
        b'd' => Some(ValueType::F64),
        _ => None,
    }
}

impl WireValue {
    /// The value, or `None` for an unknown type byte, non-zero padding or
    /// an `i` value outside the i32 range.
    pub fn value(&self) -> Option<Value> {
        if self.pad != [0; 3] {
            return None;
        }
        let bits = self.bits.get();
        match type_from_wire(self.ty)? {
            ValueType::I32 => i32::try_from(bits as i64).ok().map(Value::I32),
            ValueType::F64 => Some(Value::F64(f64::from_bits(bits))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_have_documented_sizes() {
        assert_eq!(std::mem::size_of::<WireAddr>(), 8);
        assert_eq!(std::mem::size_of::<ReadReq>(), 12);
        assert_eq!(std::mem::size_of::<WireValue>(), 12);
        assert_eq!(std::mem::size_of::<WriteReq>(), 20);
    }

    #[test]
    fn values_round_trip_and_wide_ints_are_refused() {
        for v in [Value::I32(i32::MIN), Value::I32(-1), Value::F64(-0.5)] {
            assert_eq!(WireValue::from(v).value(), Some(v));
        }
        let wide = WireValue {
            ty: b'i',
            pad: [0; 3],
            bits: (1u64 << 40).into(),
        };
        assert_eq!(wide.value(), None);
        let odd = WireValue {
            ty: b'x',
            ..WireValue::from(Value::I32(1))
        };
        assert_eq!(odd.value(), None);
        let padded = WireValue {
            pad: [0, 0, 1],
            ..WireValue::from(Value::I32(1))
        };
        assert_eq!(padded.value(), None);
    }
}
