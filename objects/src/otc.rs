//! The objects of OTC online wear compensation, devices 3 and 4
//! (docs/objects.md): the per-group objects and the PLC control units of
//! the machine axes. The TC module appends them to its own rows.

use std::ops::RangeInclusive;

use tc_request::AXES;
use uoi::{Access, ObjectAddress, ObjectDesc, ValueRange};

use crate::bus::{address_of, AXIS, BOOL, GROUPS, MACHINE_AXES};

/// Device of the per-group OTC objects.
pub const OTC_GROUP_DEVICE: u16 = 3;
/// Device of the per-axis PLC control units.
pub const OTC_AXIS_DEVICE: u16 = 4;
/// Subindexes of WearAxis0..7 (device 3 sub 20..27).
pub const WEAR_AXIS_SUBS: RangeInclusive<u16> = 20..=27;

// One WearAxis subindex per machine axis: the table checks the subindex,
// so `sub - 20` always indexes the axes.
const _: () = assert!((*WEAR_AXIS_SUBS.end() - *WEAR_AXIS_SUBS.start() + 1) as usize == AXES);

/// The OTC objects, named as in docs/objects.md. The variants stand in the
/// order of [`OTC_GROUP_OBJECTS`] then [`OTC_AXIS_OBJECTS`]: a variant's
/// number is its row.
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
const G: u16 = OTC_GROUP_DEVICE;
use OtcObject as O;

/// Device 3: OTC per compensation group, row for row as in docs/objects.md.
#[rustfmt::skip]
pub static OTC_GROUP_OBJECTS: [ObjectDesc<OtcObject>; 24] = [
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
pub static OTC_AXIS_OBJECTS: [ObjectDesc<OtcObject>; 4] = [
    ObjectDesc::int(O::AxisOffsetCommand, "OffsetCommand", OTC_AXIS_DEVICE, MACHINE_AXES, 1, RW, ANY),
    ObjectDesc::int(O::AxisOffsetEnable, "OffsetEnable", OTC_AXIS_DEVICE, MACHINE_AXES, 2, RW, BOOL),
    ObjectDesc::int(O::AxisOffsetRequest, "OffsetRequest", OTC_AXIS_DEVICE, MACHINE_AXES, 3, R, ANY),
    ObjectDesc::int(O::AxisOffsetState, "OffsetState", OTC_AXIS_DEVICE, MACHINE_AXES, 4, R, ANY),
];

// Every variant's number is its row: the group rows, then the axis rows.
const _: () = {
    let mut i = 0;
    while i < OTC_GROUP_OBJECTS.len() {
        assert!(OTC_GROUP_OBJECTS[i].key as usize == i);
        i += 1;
    }
    let mut j = 0;
    while j < OTC_AXIS_OBJECTS.len() {
        assert!(OTC_AXIS_OBJECTS[j].key as usize == OTC_GROUP_OBJECTS.len() + j);
        j += 1;
    }
};

impl OtcObject {
    /// The object's row in [`OTC_GROUP_OBJECTS`] or [`OTC_AXIS_OBJECTS`].
    pub const fn row(self) -> &'static ObjectDesc<OtcObject> {
        let n = self as usize;
        if n < OTC_GROUP_OBJECTS.len() {
            &OTC_GROUP_OBJECTS[n]
        } else {
            &OTC_AXIS_OBJECTS[n - OTC_GROUP_OBJECTS.len()]
        }
    }

    /// The address of the object of group (device 3) or machine axis
    /// (device 4) `index`, at its first subindex:
    /// `OtcObject::OtcOn.of(1)` is `1300/3/1/1`.
    pub const fn of(self, index: u16) -> ObjectAddress {
        address_of(self.row(), index, *self.row().sub.start())
    }

    /// The `k`-th subindex of an object that spans several (WearAxis: `k`
    /// is the machine axis).
    pub const fn sub_of(self, index: u16, k: u16) -> ObjectAddress {
        address_of(self.row(), index, *self.row().sub.start() + k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_come_from_the_rows() {
        assert_eq!(OtcObject::WearRadius.of(2).to_string(), "1300/3/2/10");
        assert_eq!(OtcObject::WearAxis.sub_of(1, 7).to_string(), "1300/3/1/27");
        assert_eq!(OtcObject::AxisOffsetState.of(0).to_string(), "1300/4/0/4");
        for row in OTC_GROUP_OBJECTS.iter().chain(&OTC_AXIS_OBJECTS) {
            assert!(row.matches(row.key.of(*row.index.start())), "{}", row.name);
        }
    }
}
