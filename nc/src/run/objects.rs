//! The bus 1300 objects the interpreter writes and reads (uoi-map.md),
//! all of correction group 1.

use uoi::ObjectAddress;

const fn tc(device: u16, index: u16, sub: u16) -> ObjectAddress {
    ObjectAddress::new(1300, device, index, sub)
}

/// Main plane (G17/G18/G19).
pub const TC_PLANE: ObjectAddress = tc(0, 3, 0);
/// Error bits of correction group 1.
pub const ERROR: ObjectAddress = tc(1, 1, 1);
/// The ERROR bits and their names (uoi-map.md).
pub const ERROR_BITS: [(i32, &str); 5] = [
    (1, "InitError"),
    (2, "KorrError"),
    (4, "CalcError"),
    (8, "PlaneError"),
    (16, "CenterError"),
];
/// Start (1) / end (0) of the correction.
pub const STATUS: ObjectAddress = tc(1, 1, 3);
/// Radius of the current tool entry.
pub const RADIUS: ObjectAddress = tc(1, 1, 6);
/// Current tool entry.
pub const WKZINDEX: ObjectAddress = tc(1, 1, 8);
/// Correction left of the contour.
pub const LEFT: ObjectAddress = tc(1, 1, 9);
/// Correction right of the contour.
pub const RIGHT: ObjectAddress = tc(1, 1, 10);
/// Length of the current tool entry.
pub const WKZ_LEN: ObjectAddress = tc(1, 1, 12);
/// Transition at outside corners: 0 circular (G26), 1 linear (G25).
pub const TRANSITION_MODE: ObjectAddress = tc(2, 1, 1);
/// `#OTC ON/OFF`; read = `V.G.OTC_ACTIVE`.
pub const OTC_ON: ObjectAddress = tc(3, 1, 1);
/// OTC processing type.
pub const OTC_PROC_TYPE: ObjectAddress = tc(3, 1, 2);
/// OTC mode.
pub const OTC_MODE: ObjectAddress = tc(3, 1, 3);
/// `WEAR_CONST=..`.
pub const OTC_WEAR_CONST: ObjectAddress = tc(3, 1, 4);
/// `WEAR_CONST_TOOL`.
pub const OTC_WEAR_CONST_TOOL: ObjectAddress = tc(3, 1, 5);
/// `ACC_WEIGHT=..`.
pub const OTC_ACC_WEIGHT: ObjectAddress = tc(3, 1, 6);
/// OTC error bits.
pub const OTC_ERROR: ObjectAddress = tc(3, 1, 7);
/// `V.G.WZ_AKT.WEAR_RADIUS`.
pub const WEAR_RADIUS: ObjectAddress = tc(3, 1, 10);
/// `V.G.WZ_AKT.WEAR_RADIUS_CONT`.
pub const WEAR_RADIUS_CONT: ObjectAddress = tc(3, 1, 11);

/// `V.G.WZ_AKT.WEAR[axis]`, axis 0..7.
pub const fn wear_axis(axis: u16) -> ObjectAddress {
    tc(3, 1, 20 + axis)
}

/// The OtcError bits with their ISG error ids (uoi-map.md).
pub const OTC_ERROR_BITS: [(i32, &str); 4] = [
    (1, "ToolType (P-ERR-21391): #OTC ON needs a grinding tool"),
    (2, "Sequence (ISG 90050): G40 must come before #OTC OFF"),
    (4, "PosRequest (ISG 21572)"),
    (8, "NotAllowed: a PLC unit the OTC type and mode ignore"),
];
