//! Engineering units as OPC 10000-8 asks for them: the UNECE
//! Recommendation 20 code of the unit, packed into `UnitId`, in the UNECE
//! namespace.

use opcua::types::{EUInformation, ExtensionObject, Range, Variant};

/// The namespace of UNECE unit codes (OPC 10000-8, 5.6.3).
const UNECE: &str = "http://www.opcfoundation.org/UA/units/un/cefact";

/// A unit: its UNECE code, symbol and name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Unit {
    code: &'static str,
    symbol: &'static str,
    name: &'static str,
}

/// Millimetre (UNECE `MMT`).
pub(crate) const MILLIMETRE: Unit = Unit {
    code: "MMT",
    symbol: "mm",
    name: "millimetre",
};

/// Percent (UNECE `P1`).
pub(crate) const PERCENT: Unit = Unit {
    code: "P1",
    symbol: "%",
    name: "percent",
};

impl Unit {
    /// `UnitId`: the code's characters, one byte each, the last one
    /// lowest (OPC 10000-8).
    pub fn id(&self) -> i32 {
        self.code
            .bytes()
            .fold(0i32, |id, b| (id << 8) | i32::from(b))
    }

    /// The `EngineeringUnits` value.
    pub fn value(&self) -> Variant {
        Variant::from(ExtensionObject::from_message(EUInformation {
            namespace_uri: UNECE.into(),
            unit_id: self.id(),
            display_name: self.symbol.into(),
            description: self.name.into(),
        }))
    }
}

/// A `Range` value (`EURange`).
pub(crate) fn range(low: f64, high: f64) -> Variant {
    Variant::from(ExtensionObject::from_message(Range { low, high }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_ids_pack_the_unece_code() {
        // 'M' 'M' 'T' = 0x4D 0x4D 0x54; 'P' '1' = 0x50 0x31.
        assert_eq!(MILLIMETRE.id(), 5_066_068);
        assert_eq!(PERCENT.id(), 20_529);
    }
}
