//! The OTC extension of the TC module: what it keeps of its own. Its
//! registers are served in `registers`, switching in `switching`, the
//! per-cycle model in `per_cycle`.

use tc_module::AXES;

use crate::plc::PlcUnit;

/// The OTC extension: its own state is the PLC units of the machine axes
/// (device 4); the state of each group and tool entry lives in them.
#[derive(Debug, Default, Clone)]
pub struct OtcExtension {
    pub(crate) axes: [PlcUnit; AXES],
    /// The group whose OTC is on (kept by switching, so that a cycle need
    /// not look through the groups).
    pub(crate) on_group: Option<u16>,
}
