//! The fields of a tool entry and the objects that carry them: which
//! write sets a field of the entry at the group's WKZINDEX, and which
//! writes change tool data in other ways (docs/tool-files.md).

use uoi::{ObjectAddress, ObjectDesc, Value, ValueRange, ValueType};

use crate::object::BusObject;
use crate::otc::OtcObject;
use crate::tc::TcObject;

/// One field of a tool entry. Each is read and written through one object
/// of its group, for the entry at the group's WKZINDEX.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ToolField {
    /// ToolType (3/g/30): 0 milling, 1 turning, 2 grinding, 3 wire.
    ToolType,
    /// RADIUS (1/g/6), units.
    Radius,
    /// WkzLen (1/g/12), units.
    Length,
    /// ToolWearConst (3/g/31), 0.1 µm/m.
    WearConst,
    /// ToolMaxInfeed (3/g/32), 0.1 µm.
    MaxInfeed,
    /// ToolTiltAngle (3/g/33), 0.0001°.
    TiltAngle,
}

impl ToolField {
    /// Every field, in the order tool files list them.
    pub const ALL: [ToolField; 6] = [
        Self::ToolType,
        Self::Radius,
        Self::Length,
        Self::WearConst,
        Self::MaxInfeed,
        Self::TiltAngle,
    ];

    /// The object that carries the field.
    pub const fn object(self) -> BusObject {
        match self {
            Self::ToolType => BusObject::Otc(OtcObject::ToolType),
            Self::Radius => BusObject::Tc(TcObject::Radius),
            Self::Length => BusObject::Tc(TcObject::WkzLen),
            Self::WearConst => BusObject::Otc(OtcObject::ToolWearConst),
            Self::MaxInfeed => BusObject::Otc(OtcObject::ToolMaxInfeed),
            Self::TiltAngle => BusObject::Otc(OtcObject::ToolTiltAngle),
        }
    }

    /// The address of the field's object in group `group`.
    pub const fn address(self, group: u16) -> ObjectAddress {
        match self.object() {
            BusObject::Tc(o) => o.of(group),
            BusObject::Otc(o) => o.of(group),
        }
    }

    /// The value type of the field (that of its object).
    pub const fn value_type(self) -> ValueType {
        self.row_parts().0
    }

    /// The values the field takes (those its object takes).
    pub const fn range(self) -> ValueRange {
        self.row_parts().1
    }

    /// The name of the field's object (`RADIUS`, `ToolType` ...).
    pub const fn object_name(self) -> &'static str {
        self.row_parts().2
    }

    const fn row_parts(self) -> (ValueType, ValueRange, &'static str) {
        const fn parts<K>(r: &ObjectDesc<K>) -> (ValueType, ValueRange, &'static str) {
            (r.ty, r.range, r.name)
        }
        match self.object() {
            BusObject::Tc(o) => parts(o.row()),
            BusObject::Otc(o) => parts(o.row()),
        }
    }

    /// The field a write to `addr` sets directly, if any.
    pub fn of_address(addr: ObjectAddress) -> Option<Self> {
        let object = BusObject::at(addr)?;
        Self::ALL.into_iter().find(|f| f.object() == object)
    }
}

/// What a write does to the tool data besides setting one field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ToolEffect {
    /// Nothing: no tool data changes.
    None,
    /// Sets this field of the entry at the group's WKZINDEX.
    Field(ToolField),
    /// May change many entries: Clean and Reset (every group), a group's
    /// RESET (every entry of the group), OTC switched off (the wear booked
    /// on the current entry's radius or length).
    Many,
}

impl ToolEffect {
    /// What writing `value` to `addr` does to the tool data. OtcOn books
    /// wear on every write but 1 (a write of 0 switches OTC off).
    pub fn of_write(addr: ObjectAddress, value: Value) -> Self {
        match BusObject::at(addr) {
            Some(BusObject::Tc(TcObject::Clean | TcObject::Reset | TcObject::GroupReset)) => {
                Self::Many
            }
            Some(BusObject::Otc(OtcObject::OtcOn)) if value != Value::I32(1) => Self::Many,
            _ => ToolField::of_address(addr).map_or(Self::None, Self::Field),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_field_is_found_at_its_address() {
        for f in ToolField::ALL {
            for g in [1, 32] {
                assert_eq!(ToolField::of_address(f.address(g)), Some(f));
            }
        }
        assert_eq!(ToolField::of_address(TcObject::WkzIndex.of(1)), None);
        assert_eq!(ToolField::Radius.object_name(), "RADIUS");
        assert_eq!(ToolField::ToolType.value_type(), ValueType::I32);
    }

    #[test]
    fn writes_that_change_tool_data() {
        let one = Value::I32(1);
        assert_eq!(
            ToolEffect::of_write(TcObject::Clean.address(), one),
            ToolEffect::Many
        );
        assert_eq!(
            ToolEffect::of_write(TcObject::Reset.address(), one),
            ToolEffect::Many
        );
        assert_eq!(
            ToolEffect::of_write(TcObject::GroupReset.of(3), one),
            ToolEffect::Many
        );
        assert_eq!(
            ToolEffect::of_write(OtcObject::OtcOn.of(3), one),
            ToolEffect::None
        );
        assert_eq!(
            ToolEffect::of_write(OtcObject::OtcOn.of(3), Value::I32(0)),
            ToolEffect::Many
        );
        assert_eq!(
            ToolEffect::of_write(TcObject::Radius.of(2), Value::F64(1.0)),
            ToolEffect::Field(ToolField::Radius)
        );
        assert_eq!(
            ToolEffect::of_write(TcObject::Status.of(2), one),
            ToolEffect::None
        );
    }
}
