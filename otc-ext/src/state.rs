//! The OTC state: of each compensation group (kept in the group), of each
//! tool entry (kept in the entry), and of the machine axes' PLC units.

use tc_module::AXES;

use crate::quantity::{TenthMicrons, TiltAngle, WearRate};
use crate::wear::WearState;

pub use tc_objects::OtcErrorBits;

/// Tool type of a grinding tool (P-TOOL-00001; docs/otc.md, "Switching a legacy TC program to OTC": `OtcOn=1`
/// needs ToolType 2).
pub const GRINDING: i32 = 2;

/// Default AccWeight in percent (docs/objects.md, device 3 sub 6).
pub const DEFAULT_ACC_WEIGHT: i32 = 100;

/// Default OriAxis: B (docs/objects.md, device 3 sub 41).
pub const DEFAULT_ORI_AXIS: usize = 4;

/// Processing type (device 3 sub 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ProcType {
    /// 0: wear as a radius change.
    Radius,
    /// 1: wear along the tool length (default).
    #[default]
    Length,
    /// 2: wear along the tool direction.
    ToolDir,
    /// 3: wear along the surface normal.
    SurfNormDir,
}

impl ProcType {
    /// The type for a register value (the table allows 0..=3).
    pub fn from_code(v: i32) -> Self {
        match v {
            0 => ProcType::Radius,
            2 => ProcType::ToolDir,
            3 => ProcType::SurfNormDir,
            _ => ProcType::Length,
        }
    }

    /// The register value.
    pub fn code(self) -> i32 {
        match self {
            ProcType::Radius => 0,
            ProcType::Length => 1,
            ProcType::ToolDir => 2,
            ProcType::SurfNormDir => 3,
        }
    }
}

/// OTC mode (device 3 sub 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OtcMode {
    /// 0: discrete offsets from the PLC only.
    Disc,
    /// 1: continuous wear only.
    Cont,
    /// 2: both (default).
    #[default]
    Auto,
}

impl OtcMode {
    /// The mode for a register value (the table allows 0..=2).
    pub fn from_code(v: i32) -> Self {
        match v {
            0 => OtcMode::Disc,
            1 => OtcMode::Cont,
            _ => OtcMode::Auto,
        }
    }

    /// The register value.
    pub fn code(self) -> i32 {
        match self {
            OtcMode::Disc => 0,
            OtcMode::Cont => 1,
            OtcMode::Auto => 2,
        }
    }
}

/// The OTC fields of one tool entry (P-TOOL parameters), kept in the
/// entry itself.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OtcTool {
    /// P-TOOL-00001: 0 milling, 1 turning, 2 grinding, 3 wire.
    pub tool_type: i32,
    /// P-TOOL-00030, 0.1 µm/m.
    pub wear_const: WearRate,
    /// P-TOOL-00031, 0.1 µm.
    pub max_infeed: TenthMicrons,
    /// P-TOOL-00138, 0.0001°.
    pub tilt: TiltAngle,
}

/// A PLC control unit: command, enable, the value applied now.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlcUnit {
    /// `command_w`.
    pub command: i32,
    /// `enable_w`.
    pub enable: bool,
    /// The value applied now, in [`APPLIED_UNIT_MM`] (0.01 µm): always a
    /// whole number, since the targets and the ramp step are, so ramps
    /// are exact.
    pub applied: f64,
}

/// The unit of [`PlcUnit::applied`] in mm: 0.01 µm, a tenth of the PLC's
/// 0.1 µm. The ramp step `1e-3 · AccWeight / 100` mm is AccWeight of them.
pub const APPLIED_UNIT_MM: f64 = 1e-5;

/// Applied units per PLC unit (0.1 µm).
pub const APPLIED_PER_PLC: f64 = 10.0;

impl PlcUnit {
    /// `state_r`: the applied value rounded to the nearest 0.1 µm (docs/objects.md),
    /// halves away from zero.
    pub fn state(&self) -> i32 {
        // Within ±i32::MAX: the applied value moves between 0 and clamped
        // commands; `as` saturates anyway.
        (self.applied / APPLIED_PER_PLC).round() as i32
    }
}

/// Clamps a PLC command to ± the tool's maximum infeed (0: no discrete
/// offset).
pub fn clamp_command(command: i32, max_infeed: TenthMicrons) -> i32 {
    let bound = max_infeed.magnitude().min(f64::from(i32::MAX)).floor();
    // Within ±i32::MAX after the clamp.
    f64::from(command).clamp(-bound, bound) as i32
}

/// OTC state of one compensation group, kept in the group itself.
#[derive(Debug, Clone)]
pub struct OtcGroup {
    /// `#OTC ON`.
    pub on: bool,
    /// ProcType.
    pub proc_type: ProcType,
    /// Mode.
    pub mode: OtcMode,
    /// WearConst written since the last WearConstTool.
    pub wear_const_override: Option<WearRate>,
    /// The constant fixed at OTC ON.
    pub const_in_force: WearRate,
    /// AccWeight, percent.
    pub acc_weight: i32,
    /// OtcError.
    pub error: OtcErrorBits,
    /// `V.G.WZ_AKT.WEAR_RADIUS`.
    pub wear_radius: f64,
    /// `V.G.WZ_AKT.WEAR_RADIUS_CONT`.
    pub wear_radius_cont: f64,
    /// `V.G.WZ_AKT.WEAR[idx]`.
    pub wear_axis: [f64; AXES],
    /// AllowPosReq.
    pub allow_pos_req: bool,
    /// OriAxis: the machine axis of the orientation angle B.
    pub ori_axis: usize,
    /// The channel unit `otc_radius_offset`.
    pub radius_unit: PlcUnit,
    /// The wear model's state since OTC ON (continuous wear, direction).
    pub wear: WearState,
    /// Tool changes reported to external tool management.
    pub handoff_count: i32,
    /// WKZINDEX of the tool last handed back.
    pub handoff_tool: i32,
    /// Its wear radius.
    pub handoff_wear_radius: f64,
    /// Its continuous wear radius.
    pub handoff_wear_radius_cont: f64,
}

impl Default for OtcGroup {
    fn default() -> Self {
        Self {
            on: false,
            proc_type: ProcType::default(),
            mode: OtcMode::default(),
            wear_const_override: None,
            const_in_force: WearRate::default(),
            acc_weight: DEFAULT_ACC_WEIGHT,
            error: OtcErrorBits::empty(),
            wear_radius: 0.0,
            wear_radius_cont: 0.0,
            wear_axis: [0.0; AXES],
            allow_pos_req: false,
            ori_axis: DEFAULT_ORI_AXIS,
            radius_unit: PlcUnit::default(),
            wear: WearState::default(),
            handoff_count: 0,
            handoff_tool: 0,
            handoff_wear_radius: 0.0,
            handoff_wear_radius_cont: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp() {
        let c = |command, bound| clamp_command(command, TenthMicrons(bound));
        assert_eq!(c(500, 100.0), 100);
        assert_eq!(c(-500, 100.0), -100);
        assert_eq!(c(50, 100.0), 50);
        assert_eq!(c(50, 0.0), 0);
        assert_eq!(c(i32::MIN, 1e300), i32::MIN + 1);
    }

    #[test]
    fn codes_round_trip() {
        for c in 0..=3 {
            assert_eq!(ProcType::from_code(c).code(), c);
        }
        for c in 0..=2 {
            assert_eq!(OtcMode::from_code(c).code(), c);
        }
    }
}
