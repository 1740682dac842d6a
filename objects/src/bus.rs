//! The shape of bus 1300: its number, how many groups, tool entries and
//! machine axes it has, the coordinate limit, and the value ranges the
//! rows share (docs/objects.md).

use std::ops::RangeInclusive;

use tc_request::AXES;
use uoi::{ObjectAddress, ObjectDesc, ValueRange};

/// The BusNumber of the TC module.
pub const TC_BUS: u16 = 1300;

/// Number of compensation groups: the index of devices 1 to 3 is the
/// group, `1..=32` (docs/objects.md, device 1).
pub const GROUP_COUNT: usize = 32;

/// Group indexes of devices 1, 2 and 3.
pub const GROUPS: RangeInclusive<u16> = 1..=GROUP_COUNT as u16;

/// Entries of a group's tool table, WKZINDEX `0..=1023`.
pub const TOOL_ENTRIES: usize = 1024;

/// Machine axes as an index range: the index of device 4, and the value of
/// every axis register.
pub const MACHINE_AXES: RangeInclusive<u16> = 0..=(AXES as u16 - 1);

/// The coordinate limit: every word of a motion command, every point that
/// enters the spooler, and the registers that add to a programmed point
/// (RADIUS, WkzLen, the rotation centre) lie within ±1e9 units
/// (decisions 14 and 78). Beyond it a value is refused with `Range`.
pub const MAX_COORD: f64 = 1e9;

/// TcPlane 17: the X-Y plane (NC G17).
pub const PLANE_XY: i32 = 17;
/// TcPlane 18: the Z-X plane (NC G18).
pub const PLANE_ZX: i32 = 18;
/// TcPlane 19: the Y-Z plane (NC G19).
pub const PLANE_YZ: i32 = 19;
/// The values TcPlane takes.
pub const PLANE_CODES: [i32; 3] = [PLANE_XY, PLANE_ZX, PLANE_YZ];

/// An axis register: a machine axis 0..7.
pub const AXIS: ValueRange = ValueRange::Int {
    min: 0,
    max: AXES as i32 - 1,
};

/// A switch: 0 or 1.
pub const BOOL: ValueRange = ValueRange::Int { min: 0, max: 1 };

/// Rotation centre, RADIUS and WkzLen: within the coordinate limit, so
/// what they add to a programmed point stays finite.
pub const COORD: ValueRange = ValueRange::Finite {
    min: -MAX_COORD,
    max: MAX_COORD,
};

/// The address of row `row`'s object at `index`, subindex `sub`.
pub(crate) const fn address_of<K>(row: &ObjectDesc<K>, index: u16, sub: u16) -> ObjectAddress {
    ObjectAddress::new(TC_BUS, row.device, index, sub)
}
