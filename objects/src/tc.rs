//! The TC module's own objects, devices 0 to 2 (docs/objects.md): one row
//! each, in the order of the reference.

use uoi::{Access, ObjectAddress, ObjectDesc, ValueRange};

use crate::bus::{address_of, AXIS, BOOL, COORD, GROUPS, PLANE_CODES, TOOL_ENTRIES};

/// The TC module's own objects, named as in docs/objects.md. The variants
/// stand in the order of [`TC_OBJECTS`]: a variant's number is its row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TcObject {
    /// 0/1/0 Clean (w, must be 1).
    Clean,
    /// 0/2/0..2 AxisNr X/Y/Z (rw, 0..7).
    AxisNr,
    /// 0/3/0 TcPlane (rw, 17/18/19).
    TcPlane,
    /// 0/11/0 ReInit (w).
    ReInit,
    /// 0/12/0 Reset of every group (w).
    Reset,
    /// 0/20/0 RotAngle in degrees (rw, finite).
    RotAngle,
    /// 0/21/0 RotCenterX (rw, ±1e9).
    RotCenterX,
    /// 0/22/0 RotCenterY (rw, ±1e9).
    RotCenterY,
    /// 1/g/1 ERROR (rw): read bits, write clears.
    Error,
    /// 1/g/2 RESET (w).
    GroupReset,
    /// 1/g/3 STATUS (rw, 0/1).
    Status,
    /// 1/g/4 XAxis (rw, 0..7).
    XAxis,
    /// 1/g/5 YAxis (rw, 0..7).
    YAxis,
    /// 1/g/6 RADIUS of the entry at WKZINDEX (rw, ±1e9).
    Radius,
    /// 1/g/8 WKZINDEX (rw, 0..1023).
    WkzIndex,
    /// 1/g/9 Left (w).
    Left,
    /// 1/g/10 Right (w).
    Right,
    /// 1/g/11 ZAxis (rw, 0..7).
    ZAxis,
    /// 1/g/12 WkzLen of the entry at WKZINDEX (rw, ±1e9).
    WkzLen,
    /// 2/g/1 TransitionMode (rw, 0 circular / 1 linear).
    TransitionMode,
}

const RW: Access = Access::ReadWrite;
const W: Access = Access::WriteOnly;
const ANY: ValueRange = ValueRange::AnyInt;
const FINITE: ValueRange = ValueRange::AnyFinite;
const WKZ: ValueRange = ValueRange::Int {
    min: 0,
    max: TOOL_ENTRIES as i32 - 1,
};
use TcObject as O;

/// The table of the TC module's own objects, row for row as in
/// docs/objects.md.
#[rustfmt::skip]
pub static TC_OBJECTS: [ObjectDesc<TcObject>; 20] = [
    // Device 0: initialisation (global)
    ObjectDesc::int(O::Clean, "Clean", 0, 1..=1, 0, W, ValueRange::IntSet(&[1])),
    ObjectDesc::int(O::AxisNr, "AxisNr", 0, 2..=2, 0, RW, AXIS).subs(0, 2),
    ObjectDesc::int(O::TcPlane, "TcPlane", 0, 3..=3, 0, RW, ValueRange::IntSet(&PLANE_CODES)),
    ObjectDesc::int(O::ReInit, "ReInit", 0, 11..=11, 0, W, ANY),
    ObjectDesc::int(O::Reset, "Reset", 0, 12..=12, 0, W, ANY),
    ObjectDesc::double(O::RotAngle, "RotAngle", 0, 20..=20, 0, RW, FINITE),
    ObjectDesc::double(O::RotCenterX, "RotCenterX", 0, 21..=21, 0, RW, COORD),
    ObjectDesc::double(O::RotCenterY, "RotCenterY", 0, 22..=22, 0, RW, COORD),
    // Device 1: compensation groups and their tool tables
    ObjectDesc::int(O::Error, "ERROR", 1, GROUPS, 1, RW, ANY),
    ObjectDesc::int(O::GroupReset, "RESET", 1, GROUPS, 2, W, ANY),
    ObjectDesc::int(O::Status, "STATUS", 1, GROUPS, 3, RW, BOOL),
    ObjectDesc::int(O::XAxis, "XAxis", 1, GROUPS, 4, RW, AXIS),
    ObjectDesc::int(O::YAxis, "YAxis", 1, GROUPS, 5, RW, AXIS),
    ObjectDesc::double(O::Radius, "RADIUS", 1, GROUPS, 6, RW, COORD),
    ObjectDesc::int(O::WkzIndex, "WKZINDEX", 1, GROUPS, 8, RW, WKZ),
    ObjectDesc::int(O::Left, "Left", 1, GROUPS, 9, W, ANY),
    ObjectDesc::int(O::Right, "Right", 1, GROUPS, 10, W, ANY),
    ObjectDesc::int(O::ZAxis, "ZAxis", 1, GROUPS, 11, RW, AXIS),
    ObjectDesc::double(O::WkzLen, "WkzLen", 1, GROUPS, 12, RW, COORD),
    // Device 2: TC extensions
    ObjectDesc::int(O::TransitionMode, "TransitionMode", 2, GROUPS, 1, RW, BOOL),
];

// Every variant's number is its row.
const _: () = {
    let mut i = 0;
    while i < TC_OBJECTS.len() {
        assert!(TC_OBJECTS[i].key as usize == i);
        i += 1;
    }
};

impl TcObject {
    /// The object's row in [`TC_OBJECTS`].
    pub const fn row(self) -> &'static ObjectDesc<TcObject> {
        &TC_OBJECTS[self as usize]
    }

    /// The address of a device-0 object (its own index, its first
    /// subindex): `TcObject::TcPlane.address()` is `1300/0/3/0`.
    pub const fn address(self) -> ObjectAddress {
        let row = self.row();
        address_of(row, *row.index.start(), *row.sub.start())
    }

    /// The address of the object of group `group` (devices 1 and 2):
    /// `TcObject::Radius.of(1)` is `1300/1/1/6`.
    pub const fn of(self, group: u16) -> ObjectAddress {
        address_of(self.row(), group, *self.row().sub.start())
    }

    /// The `k`-th subindex of a device-0 object that spans several
    /// (AxisNr: `k` 0 X, 1 Y, 2 Z).
    pub const fn sub(self, k: u16) -> ObjectAddress {
        let row = self.row();
        address_of(row, *row.index.start(), *row.sub.start() + k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_come_from_the_rows() {
        assert_eq!(TcObject::Clean.address().to_string(), "1300/0/1/0");
        assert_eq!(TcObject::AxisNr.sub(2).to_string(), "1300/0/2/2");
        assert_eq!(TcObject::Status.of(7).to_string(), "1300/1/7/3");
        assert_eq!(TcObject::TransitionMode.of(1).to_string(), "1300/2/1/1");
        for row in &TC_OBJECTS {
            assert!(row.matches(row.key.of(*row.index.start())), "{}", row.name);
        }
    }
}
