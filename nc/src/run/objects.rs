//! The bus 1300 objects the interpreter writes and reads, all of
//! correction group 1, named through the object vocabulary (`tc-objects`,
//! docs/objects.md): no address is written here by hand.

use tc_objects::{ErrorBits, OtcErrorBits, OtcObject, TcObject};
use uoi::ObjectAddress;

/// The correction group NC programs run on.
const GROUP: u16 = 1;

/// Main plane (G17/G18/G19).
pub const TC_PLANE: ObjectAddress = TcObject::TcPlane.address();
/// ReInit: every group's held profile dropped, nothing spooled.
pub const RE_INIT: ObjectAddress = TcObject::ReInit.address();
/// Error bits of correction group 1.
pub const ERROR: ObjectAddress = TcObject::Error.of(GROUP);
/// Start (1) / end (0) of the correction.
pub const STATUS: ObjectAddress = TcObject::Status.of(GROUP);
/// Radius of the current tool entry.
pub const RADIUS: ObjectAddress = TcObject::Radius.of(GROUP);
/// Current tool entry.
pub const WKZINDEX: ObjectAddress = TcObject::WkzIndex.of(GROUP);
/// Correction left of the contour.
pub const LEFT: ObjectAddress = TcObject::Left.of(GROUP);
/// Correction right of the contour.
pub const RIGHT: ObjectAddress = TcObject::Right.of(GROUP);
/// Length of the current tool entry.
pub const WKZ_LEN: ObjectAddress = TcObject::WkzLen.of(GROUP);
/// Transition at outside corners: 0 circular (G26), 1 linear (G25).
pub const TRANSITION_MODE: ObjectAddress = TcObject::TransitionMode.of(GROUP);
/// `#OTC ON/OFF`; read = `V.G.OTC_ACTIVE`.
pub const OTC_ON: ObjectAddress = OtcObject::OtcOn.of(GROUP);
/// OTC processing type.
pub const OTC_PROC_TYPE: ObjectAddress = OtcObject::ProcType.of(GROUP);
/// OTC mode.
pub const OTC_MODE: ObjectAddress = OtcObject::Mode.of(GROUP);
/// `WEAR_CONST=..`.
pub const OTC_WEAR_CONST: ObjectAddress = OtcObject::WearConst.of(GROUP);
/// `WEAR_CONST_TOOL`.
pub const OTC_WEAR_CONST_TOOL: ObjectAddress = OtcObject::WearConstTool.of(GROUP);
/// `ACC_WEIGHT=..`.
pub const OTC_ACC_WEIGHT: ObjectAddress = OtcObject::AccWeight.of(GROUP);
/// OTC error bits.
pub const OTC_ERROR: ObjectAddress = OtcObject::OtcError.of(GROUP);
/// `V.G.WZ_AKT.WEAR_RADIUS`.
pub const WEAR_RADIUS: ObjectAddress = OtcObject::WearRadius.of(GROUP);
/// `V.G.WZ_AKT.WEAR_RADIUS_CONT`.
pub const WEAR_RADIUS_CONT: ObjectAddress = OtcObject::WearRadiusCont.of(GROUP);

/// `V.G.WZ_AKT.WEAR[axis]`, axis 0..7.
pub const fn wear_axis(axis: u16) -> ObjectAddress {
    OtcObject::WearAxis.sub_of(GROUP, axis)
}

/// The names of the ERROR bits set in `bits` (`CalcError` ...).
pub fn error_bit_names(bits: i32) -> Vec<String> {
    ErrorBits::from_bits_truncate(bits)
        .iter_names()
        .map(|(name, _)| tc_objects::camel_name(name))
        .collect()
}

/// What each OtcError bit means to the NC programmer, with its ISG error
/// id.
pub const OTC_ERROR_BITS: [(i32, &str); 4] = [
    (
        OtcErrorBits::TOOL_TYPE.bits(),
        "ToolType (P-ERR-21391): #OTC ON needs a grinding tool",
    ),
    (
        OtcErrorBits::SEQUENCE.bits(),
        "Sequence (ISG 90050): G40 must come before #OTC OFF",
    ),
    (OtcErrorBits::POS_REQUEST.bits(), "PosRequest (ISG 21572)"),
    (
        OtcErrorBits::NOT_ALLOWED.bits(),
        "NotAllowed: a PLC unit the OTC type and mode ignore",
    ),
];
