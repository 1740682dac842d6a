//! The OTC objects of bus 1300 (uoi-map.md devices 3 and 4), declared by
//! the extension and appended to the TC module's one map.

use std::ops::RangeInclusive;

use tc_module::object_map::{AXIS, BOOL, GROUPS, MACHINE_AXES};
use uoi::{Access, ObjectDesc, ValueRange};

/// Device of the per-group OTC objects (uoi-map.md "Device 3").
pub const GROUP_DEVICE: u16 = 3;
/// Device of the per-axis PLC control units (uoi-map.md "Device 4").
pub const AXIS_DEVICE: u16 = 4;
/// Subindexes of WearAxis0..7 (uoi-map.md device 3 sub 20..27).
pub const WEAR_AXIS_SUBS: RangeInclusive<u16> = 20..=27;

// One WearAxis subindex per machine axis: the table checks the subindex,
// so `sub - 20` always indexes the axes.
const _: () =
    assert!((*WEAR_AXIS_SUBS.end() - *WEAR_AXIS_SUBS.start() + 1) as usize == tc_module::AXES);

/// The OTC objects.
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

const RW: Access = Access::ReadWrite;
const W: Access = Access::WriteOnly;
const R: Access = Access::ReadOnly;
const ANY: ValueRange = ValueRange::AnyInt;
const FINITE: ValueRange = ValueRange::AnyFinite;
const NONNEG: ValueRange = ValueRange::Finite {
    min: 0.0,
    max: f64::MAX,
};
const G: u16 = GROUP_DEVICE;
use OtcObject as O;

/// Device 3: OTC per compensation group, row for row as in uoi-map.md.
#[rustfmt::skip]
pub static GROUP_OBJECTS: [ObjectDesc<OtcObject>; 24] = [
    ObjectDesc::int(O::OtcOn, "OtcOn", G, GROUPS, 1, RW, BOOL),
    ObjectDesc::int(O::ProcType, "ProcType", G, GROUPS, 2, RW, ValueRange::Int { min: 0, max: 3 }),
    ObjectDesc::int(O::Mode, "Mode", G, GROUPS, 3, RW, ValueRange::Int { min: 0, max: 2 }),
    ObjectDesc::double(O::WearConst, "WearConst", G, GROUPS, 4, RW, NONNEG),
    ObjectDesc::int(O::WearConstTool, "WearConstTool", G, GROUPS, 5, W, ANY),
    ObjectDesc::int(O::AccWeight, "AccWeight", G, GROUPS, 6, RW, ValueRange::Int { min: 1, max: 100 }),
    ObjectDesc::int(O::OtcError, "OtcError", G, GROUPS, 7, RW, ANY),
    ObjectDesc::double(O::WearRadius, "WearRadius", G, GROUPS, 10, R, FINITE),
    ObjectDesc::double(O::WearRadiusCont, "WearRadiusCont", G, GROUPS, 11, R, FINITE),
    ObjectDesc::double(O::WearAxis, "WearAxis", G, GROUPS, 0, R, FINITE)
        .subs(*WEAR_AXIS_SUBS.start(), *WEAR_AXIS_SUBS.end()),
    ObjectDesc::int(O::ToolType, "ToolType", G, GROUPS, 30, RW, ValueRange::Int { min: 0, max: 3 }),
    ObjectDesc::double(O::ToolWearConst, "ToolWearConst", G, GROUPS, 31, RW, NONNEG),
    ObjectDesc::double(O::ToolMaxInfeed, "ToolMaxInfeed", G, GROUPS, 32, RW, FINITE),
    ObjectDesc::double(O::ToolTiltAngle, "ToolTiltAngle", G, GROUPS, 33, RW, ValueRange::Finite { min: -450_000.0, max: 450_000.0 }),
    ObjectDesc::int(O::AllowPosReq, "AllowPosReq", G, GROUPS, 40, RW, BOOL),
    ObjectDesc::int(O::OriAxis, "OriAxis", G, GROUPS, 41, RW, AXIS),
    ObjectDesc::int(O::RadiusOffsetCommand, "RadiusOffsetCommand", G, GROUPS, 50, RW, ANY),
    ObjectDesc::int(O::RadiusOffsetEnable, "RadiusOffsetEnable", G, GROUPS, 51, RW, BOOL),
    ObjectDesc::int(O::RadiusOffsetRequest, "RadiusOffsetRequest", G, GROUPS, 52, R, ANY),
    ObjectDesc::int(O::RadiusOffsetState, "RadiusOffsetState", G, GROUPS, 53, R, ANY),
    ObjectDesc::int(O::HandoffCount, "HandoffCount", G, GROUPS, 60, R, ANY),
    ObjectDesc::int(O::HandoffToolIndex, "HandoffToolIndex", G, GROUPS, 61, R, ANY),
    ObjectDesc::double(O::HandoffWearRadius, "HandoffWearRadius", G, GROUPS, 62, R, FINITE),
    ObjectDesc::double(O::HandoffWearRadiusCont, "HandoffWearRadiusCont", G, GROUPS, 63, R, FINITE),
];

/// Device 4: the PLC control units of the machine axes.
#[rustfmt::skip]
pub static AXIS_OBJECTS: [ObjectDesc<OtcObject>; 4] = [
    ObjectDesc::int(O::AxisOffsetCommand, "OffsetCommand", AXIS_DEVICE, MACHINE_AXES, 1, RW, ANY),
    ObjectDesc::int(O::AxisOffsetEnable, "OffsetEnable", AXIS_DEVICE, MACHINE_AXES, 2, RW, BOOL),
    ObjectDesc::int(O::AxisOffsetRequest, "OffsetRequest", AXIS_DEVICE, MACHINE_AXES, 3, R, ANY),
    ObjectDesc::int(O::AxisOffsetState, "OffsetState", AXIS_DEVICE, MACHINE_AXES, 4, R, ANY),
];

#[cfg(test)]
mod tests {
    use tc_module::object_map::{object_table, overlapping_rows};

    use crate::OtcExtension;

    #[test]
    fn otc_rows_extend_the_map_without_overlap() {
        let table = object_table::<OtcExtension>();
        assert_eq!(overlapping_rows(&table), vec![]);
        assert_eq!(
            table.len(),
            tc_module::TC_OBJECTS.len() + super::GROUP_OBJECTS.len() + super::AXIS_OBJECTS.len()
        );
    }
}
