//! The object map of bus 1300: ONE declarative table of the TC module's
//! own objects (uoi-map.md, devices 0 to 2), to which an extension appends
//! its rows (OTC: devices 3 and 4). The dispatcher in `uoi` enforces
//! address, type, access and range from it before the module sees a value.

use std::ops::RangeInclusive;

use uoi::{Access, ObjectDesc, ValueRange};

use crate::extension::TcExtension;
use crate::plane::TcPlane;
use crate::tool_table::TOOL_ENTRIES;

/// The BusNumber of the TC module.
pub const TC_BUS: u16 = 1300;

/// Number of compensation groups (uoi-map.md device 1: "Index =
/// compensation group number, 1..=32").
pub const GROUP_COUNT: usize = 32;

/// Group indexes of devices 1, 2 and of an extension's group objects.
pub const GROUPS: RangeInclusive<u16> = 1..=GROUP_COUNT as u16;

/// Machine axes as an index range (uoi-map.md device 4: "Index = machine
/// axis 0..7").
pub const MACHINE_AXES: RangeInclusive<u16> = 0..=(crate::plane::AXES as u16 - 1);

/// An axis register: a machine axis 0..7.
pub const AXIS: ValueRange = ValueRange::Int {
    min: 0,
    max: crate::plane::AXES as i32 - 1,
};

/// A switch: 0 or 1.
pub const BOOL: ValueRange = ValueRange::Int { min: 0, max: 1 };

/// TcPlane values (uoi-map.md device 0 index 3: 17, 18, 19).
pub const PLANE_CODES: [i32; 3] = [TcPlane::Xy.code(), TcPlane::Zx.code(), TcPlane::Yz.code()];

/// The TC module's own objects, named as in uoi-map.md.
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
/// Rotation centre, RADIUS and WkzLen: within the coordinate limit, so
/// what they add to a programmed point stays finite.
pub const COORD: ValueRange = ValueRange::Finite {
    min: -crate::limits::MAX_COORD,
    max: crate::limits::MAX_COORD,
};
const WKZ: ValueRange = ValueRange::Int {
    min: 0,
    max: TOOL_ENTRIES as i32 - 1,
};
use TcObject as O;

/// The table of the TC module's own objects, row for row as in uoi-map.md.
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

/// The key of a row of the whole bus-1300 map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TcKey<K> {
    /// One of the TC module's own objects.
    Tc(TcObject),
    /// An extension's object indexed by compensation group.
    Group(K),
    /// An extension's other object.
    Ext(K),
}

/// The whole map: the TC rows, then the extension's group rows (their
/// index range is always [`GROUPS`], whatever the row says), then its
/// other rows.
pub fn object_table<E: TcExtension>() -> Vec<ObjectDesc<TcKey<E::Key>>> {
    let own = TC_OBJECTS.iter().map(|r| r.with_key(TcKey::Tc(r.key)));
    let group = E::GROUP_OBJECTS.iter().map(|r| {
        let mut row = r.with_key(TcKey::Group(r.key));
        row.index = GROUPS;
        row
    });
    let other = E::OBJECTS.iter().map(|r| r.with_key(TcKey::Ext(r.key)));
    own.chain(group).chain(other).collect()
}

/// Whether two inclusive ranges share a value.
fn meet(x: &RangeInclusive<u16>, y: &RangeInclusive<u16>) -> bool {
    x.start() <= y.end() && y.start() <= x.end()
}

/// Pairs of rows of `table` that answer for the same address (an
/// extension row shadowed by a TC row, say), by name.
pub fn overlapping_rows<K>(table: &[ObjectDesc<K>]) -> Vec<(&'static str, &'static str)> {
    let mut out = Vec::new();
    for (i, a) in table.iter().enumerate() {
        for b in &table[i + 1..] {
            if a.device == b.device && meet(&a.index, &b.index) && meet(&a.sub, &b.sub) {
                out.push((a.name, b.name));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extension::NoExtension;

    #[test]
    fn tc_rows_do_not_overlap() {
        assert_eq!(overlapping_rows(&object_table::<NoExtension>()), vec![]);
    }
}
