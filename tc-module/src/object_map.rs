//! The object map of bus 1300: ONE declarative table of every TC object
//! (uoi-map.md, devices 0 to 4). The dispatcher in `uoi` enforces
//! address, type, access and range from it before the module sees a value.

use uoi::{Access, ObjectDesc, ValueRange};

use crate::tool_table::TOOL_ENTRIES;

/// The BusNumber of the TC module.
pub const TC_BUS: u16 = 1300;

/// Group indexes of devices 1 and 2 (uoi-map.md: "Index = compensation group
/// number, 1..=32").
pub const GROUPS: std::ops::RangeInclusive<u16> = 1..=32;

/// Every object of bus 1300, named as in uoi-map.md.
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
    /// 0/21/0 RotCenterX (rw, finite).
    RotCenterX,
    /// 0/22/0 RotCenterY (rw, finite).
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
    /// 1/g/6 RADIUS of the entry at WKZINDEX (rw, finite).
    Radius,
    /// 1/g/8 WKZINDEX (rw, 0..1023).
    WkzIndex,
    /// 1/g/9 Left (w).
    Left,
    /// 1/g/10 Right (w).
    Right,
    /// 1/g/11 ZAxis (rw, 0..7).
    ZAxis,
    /// 1/g/12 WkzLen of the entry at WKZINDEX (rw, finite).
    WkzLen,
    /// 2/g/1 TransitionMode (rw, 0 circular / 1 linear).
    TransitionMode,
    /// An OTC object of device 3 (per group) or 4 (per axis), served by the
    /// OTC extension.
    Otc(OtcObject),
}

/// OTC objects (uoi-map.md devices 3 and 4; otc.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OtcObject {
    /// 3/g/1 OtcOn (#OTC ON/OFF).
    OtcOn,
    /// 3/g/2 ProcType: 0 RADIUS, 1 LENGTH, 2 TOOL_DIR, 3 SURF_NORM_DIR.
    ProcType,
    /// 3/g/3 Mode: 0 DISC, 1 CONT, 2 AUTO.
    Mode,
    /// 3/g/4 WearConst (0.1 µm/m, modal).
    WearConst,
    /// 3/g/5 WearConstTool: use the tool's constant again.
    WearConstTool,
    /// 3/g/6 AccWeight (percent).
    AccWeight,
    /// 3/g/7 OtcError bits.
    OtcError,
    /// 3/g/10 WearRadius.
    WearRadius,
    /// 3/g/11 WearRadiusCont.
    WearRadiusCont,
    /// 3/g/20..27 WearAxis0..7.
    WearAxis,
    /// 3/g/30 ToolType of the entry at WKZINDEX.
    ToolType,
    /// 3/g/31 ToolWearConst of the entry (0.1 µm/m).
    ToolWearConst,
    /// 3/g/32 ToolMaxInfeed of the entry (0.1 µm).
    ToolMaxInfeed,
    /// 3/g/33 ToolTiltAngle of the entry (0.0001°).
    ToolTiltAngle,
    /// 3/g/40 AllowPosReq.
    AllowPosReq,
    /// 3/g/41 OriAxis.
    OriAxis,
    /// 3/g/50 RadiusOffsetCommand (0.1 µm).
    RadiusOffsetCommand,
    /// 3/g/51 RadiusOffsetEnable.
    RadiusOffsetEnable,
    /// 3/g/52 RadiusOffsetRequest.
    RadiusOffsetRequest,
    /// 3/g/53 RadiusOffsetState.
    RadiusOffsetState,
    /// 3/g/60 HandoffCount.
    HandoffCount,
    /// 3/g/61 HandoffToolIndex.
    HandoffToolIndex,
    /// 3/g/62 HandoffWearRadius.
    HandoffWearRadius,
    /// 3/g/63 HandoffWearRadiusCont.
    HandoffWearRadiusCont,
    /// 4/a/1 OffsetCommand (0.1 µm).
    AxisOffsetCommand,
    /// 4/a/2 OffsetEnable.
    AxisOffsetEnable,
    /// 4/a/3 OffsetRequest.
    AxisOffsetRequest,
    /// 4/a/4 OffsetState.
    AxisOffsetState,
}

/// Machine axes of device 4 (uoi-map.md: "Index = machine axis 0..7").
pub const MACHINE_AXES: std::ops::RangeInclusive<u16> = 0..=7;

const AXIS: ValueRange = ValueRange::Int { min: 0, max: 7 };
const BOOL: ValueRange = ValueRange::Int { min: 0, max: 1 };
const NONNEG: ValueRange = ValueRange::Finite {
    min: 0.0,
    max: f64::MAX,
};
const RW: Access = Access::ReadWrite;
const W: Access = Access::WriteOnly;
const R: Access = Access::ReadOnly;
use OtcObject as C;
use TcObject as O;

/// The table itself, row for row as in uoi-map.md.
#[rustfmt::skip]
pub static TC_OBJECTS: [ObjectDesc<TcObject>; 48] = [
    // Device 0: initialisation (global)
    ObjectDesc::int(O::Clean, "Clean", 0, 1..=1, 0, W, ValueRange::IntSet(&[1])),
    ObjectDesc::int(O::AxisNr, "AxisNr", 0, 2..=2, 0, RW, AXIS).subs(0, 2),
    ObjectDesc::int(O::TcPlane, "TcPlane", 0, 3..=3, 0, RW, ValueRange::IntSet(&[17, 18, 19])),
    ObjectDesc::int(O::ReInit, "ReInit", 0, 11..=11, 0, W, ValueRange::AnyInt),
    ObjectDesc::int(O::Reset, "Reset", 0, 12..=12, 0, W, ValueRange::AnyInt),
    ObjectDesc::double(O::RotAngle, "RotAngle", 0, 20..=20, 0, RW, ValueRange::AnyFinite),
    ObjectDesc::double(O::RotCenterX, "RotCenterX", 0, 21..=21, 0, RW, ValueRange::AnyFinite),
    ObjectDesc::double(O::RotCenterY, "RotCenterY", 0, 22..=22, 0, RW, ValueRange::AnyFinite),
    // Device 1: compensation groups and their tool tables
    ObjectDesc::int(O::Error, "ERROR", 1, GROUPS, 1, RW, ValueRange::AnyInt),
    ObjectDesc::int(O::GroupReset, "RESET", 1, GROUPS, 2, W, ValueRange::AnyInt),
    ObjectDesc::int(O::Status, "STATUS", 1, GROUPS, 3, RW, BOOL),
    ObjectDesc::int(O::XAxis, "XAxis", 1, GROUPS, 4, RW, AXIS),
    ObjectDesc::int(O::YAxis, "YAxis", 1, GROUPS, 5, RW, AXIS),
    ObjectDesc::double(O::Radius, "RADIUS", 1, GROUPS, 6, RW, ValueRange::AnyFinite),
    ObjectDesc::int(O::WkzIndex, "WKZINDEX", 1, GROUPS, 8, RW, ValueRange::Int { min: 0, max: TOOL_ENTRIES as i32 - 1 }),
    ObjectDesc::int(O::Left, "Left", 1, GROUPS, 9, W, ValueRange::AnyInt),
    ObjectDesc::int(O::Right, "Right", 1, GROUPS, 10, W, ValueRange::AnyInt),
    ObjectDesc::int(O::ZAxis, "ZAxis", 1, GROUPS, 11, RW, AXIS),
    ObjectDesc::double(O::WkzLen, "WkzLen", 1, GROUPS, 12, RW, ValueRange::AnyFinite),
    // Device 2: TC extensions
    ObjectDesc::int(O::TransitionMode, "TransitionMode", 2, GROUPS, 1, RW, BOOL),
    // Device 3: OTC online wear compensation, per group
    ObjectDesc::int(O::Otc(C::OtcOn), "OtcOn", 3, GROUPS, 1, RW, BOOL),
    ObjectDesc::int(O::Otc(C::ProcType), "ProcType", 3, GROUPS, 2, RW, ValueRange::Int { min: 0, max: 3 }),
    ObjectDesc::int(O::Otc(C::Mode), "Mode", 3, GROUPS, 3, RW, ValueRange::Int { min: 0, max: 2 }),
    ObjectDesc::double(O::Otc(C::WearConst), "WearConst", 3, GROUPS, 4, RW, NONNEG),
    ObjectDesc::int(O::Otc(C::WearConstTool), "WearConstTool", 3, GROUPS, 5, W, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::AccWeight), "AccWeight", 3, GROUPS, 6, RW, ValueRange::Int { min: 1, max: 100 }),
    ObjectDesc::int(O::Otc(C::OtcError), "OtcError", 3, GROUPS, 7, RW, ValueRange::AnyInt),
    ObjectDesc::double(O::Otc(C::WearRadius), "WearRadius", 3, GROUPS, 10, R, ValueRange::AnyFinite),
    ObjectDesc::double(O::Otc(C::WearRadiusCont), "WearRadiusCont", 3, GROUPS, 11, R, ValueRange::AnyFinite),
    ObjectDesc::double(O::Otc(C::WearAxis), "WearAxis", 3, GROUPS, 20, R, ValueRange::AnyFinite).subs(20, 27),
    ObjectDesc::int(O::Otc(C::ToolType), "ToolType", 3, GROUPS, 30, RW, ValueRange::Int { min: 0, max: 3 }),
    ObjectDesc::double(O::Otc(C::ToolWearConst), "ToolWearConst", 3, GROUPS, 31, RW, NONNEG),
    ObjectDesc::double(O::Otc(C::ToolMaxInfeed), "ToolMaxInfeed", 3, GROUPS, 32, RW, ValueRange::AnyFinite),
    ObjectDesc::double(O::Otc(C::ToolTiltAngle), "ToolTiltAngle", 3, GROUPS, 33, RW, ValueRange::Finite { min: -450_000.0, max: 450_000.0 }),
    ObjectDesc::int(O::Otc(C::AllowPosReq), "AllowPosReq", 3, GROUPS, 40, RW, BOOL),
    ObjectDesc::int(O::Otc(C::OriAxis), "OriAxis", 3, GROUPS, 41, RW, AXIS),
    ObjectDesc::int(O::Otc(C::RadiusOffsetCommand), "RadiusOffsetCommand", 3, GROUPS, 50, RW, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::RadiusOffsetEnable), "RadiusOffsetEnable", 3, GROUPS, 51, RW, BOOL),
    ObjectDesc::int(O::Otc(C::RadiusOffsetRequest), "RadiusOffsetRequest", 3, GROUPS, 52, R, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::RadiusOffsetState), "RadiusOffsetState", 3, GROUPS, 53, R, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::HandoffCount), "HandoffCount", 3, GROUPS, 60, R, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::HandoffToolIndex), "HandoffToolIndex", 3, GROUPS, 61, R, ValueRange::AnyInt),
    ObjectDesc::double(O::Otc(C::HandoffWearRadius), "HandoffWearRadius", 3, GROUPS, 62, R, ValueRange::AnyFinite),
    ObjectDesc::double(O::Otc(C::HandoffWearRadiusCont), "HandoffWearRadiusCont", 3, GROUPS, 63, R, ValueRange::AnyFinite),
    // Device 4: OTC axis control units
    ObjectDesc::int(O::Otc(C::AxisOffsetCommand), "OffsetCommand", 4, MACHINE_AXES, 1, RW, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::AxisOffsetEnable), "OffsetEnable", 4, MACHINE_AXES, 2, RW, BOOL),
    ObjectDesc::int(O::Otc(C::AxisOffsetRequest), "OffsetRequest", 4, MACHINE_AXES, 3, R, ValueRange::AnyInt),
    ObjectDesc::int(O::Otc(C::AxisOffsetState), "OffsetState", 4, MACHINE_AXES, 4, R, ValueRange::AnyInt),
];
