//! The OTC state: of each compensation group (kept in the group) and of
//! each tool entry (kept in the entry).

use tc_module::AXES;

use crate::plc::PlcUnit;
use crate::quantity::{TenthMicrons, TiltAngle, WearRate};
use crate::wear::WearState;
use tc_objects::{OtcMode, ProcType};

pub use tc_objects::OtcErrorBits;

/// Tool type of a grinding tool (P-TOOL-00001; docs/otc.md, "Switching a legacy TC program to OTC": `OtcOn=1`
/// needs ToolType 2).
pub const GRINDING: i32 = 2;

/// Default AccWeight in percent (docs/objects.md, device 3 sub 6).
pub const DEFAULT_ACC_WEIGHT: i32 = 100;

/// Default OriAxis: B (docs/objects.md, device 3 sub 41).
pub const DEFAULT_ORI_AXIS: usize = 4;

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
