//! Which PLC units a processing type and mode take (docs/otc.md, "Processing types and
//! their directions" and "The error bits"): RADIUS and TOOL_DIR the group's channel unit,
//! LENGTH the axis unit of the third main axis, TOOL_DIR also and
//! SURF_NORM_DIR only the axis unit of axis 2; CONT none.

use crate::plc::PlcUnit;
use tc_objects::{OtcMode, ProcType};

/// The machine axis whose unit TOOL_DIR adds and SURF_NORM_DIR takes.
pub const TOOL_DIR_AXIS: usize = 2;

/// The units one type and mode take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TakenUnits {
    /// The group's channel unit (`otc_radius_offset`).
    pub channel: bool,
    /// The machine axis whose device-4 unit is taken.
    pub axis: Option<usize>,
}

impl TakenUnits {
    /// The units `proc` takes in `mode`; `third` is the third main axis
    /// (LENGTH).
    pub fn of(proc: ProcType, mode: OtcMode, third: u8) -> Self {
        if mode == OtcMode::Cont {
            return Self {
                channel: false,
                axis: None,
            };
        }
        let (channel, axis) = match proc {
            ProcType::Radius => (true, None),
            ProcType::Length => (false, Some(usize::from(third))),
            ProcType::ToolDir => (true, Some(TOOL_DIR_AXIS)),
            ProcType::SurfNormDir => (false, Some(TOOL_DIR_AXIS)),
        };
        Self { channel, axis }
    }

    /// Whether an enabled unit is one these ignore: the channel unit, or
    /// an axis unit other than the taken one (NotAllowed, docs/otc.md "The error bits").
    pub fn ignore_an_enabled(&self, channel: &PlcUnit, axes: &[PlcUnit]) -> bool {
        (channel.enable && !self.channel)
            || axes
                .iter()
                .enumerate()
                .any(|(i, u)| u.enable && self.axis != Some(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn enabled() -> PlcUnit {
        PlcUnit {
            enable: true,
            ..PlcUnit::default()
        }
    }

    #[test]
    fn each_type_takes_its_units() {
        let t = |p| TakenUnits::of(p, OtcMode::Auto, 2);
        assert_eq!(t(ProcType::Radius).axis, None);
        assert!(t(ProcType::Radius).channel);
        assert_eq!(t(ProcType::Length).axis, Some(2));
        assert!(!t(ProcType::Length).channel);
        assert_eq!(t(ProcType::ToolDir).axis, Some(2));
        assert!(t(ProcType::ToolDir).channel);
        assert_eq!(t(ProcType::SurfNormDir).axis, Some(2));
        assert!(!t(ProcType::SurfNormDir).channel);
        assert_eq!(
            TakenUnits::of(ProcType::Length, OtcMode::Disc, 1).axis,
            Some(1)
        );
        let cont = TakenUnits::of(ProcType::ToolDir, OtcMode::Cont, 2);
        assert!(!cont.channel && cont.axis.is_none());
    }

    #[test]
    fn an_enabled_unit_that_is_not_taken_is_ignored() {
        let off = PlcUnit::default();
        let mut axes = [PlcUnit::default(); 8];
        let length = TakenUnits::of(ProcType::Length, OtcMode::Auto, 2);
        assert!(!length.ignore_an_enabled(&off, &axes));
        assert!(length.ignore_an_enabled(&enabled(), &axes));
        axes[2] = enabled();
        assert!(!length.ignore_an_enabled(&off, &axes));
        axes[5] = enabled();
        assert!(length.ignore_an_enabled(&off, &axes));
        let cont = TakenUnits::of(ProcType::Radius, OtcMode::Cont, 2);
        assert!(cont.ignore_an_enabled(&enabled(), &[]));
    }
}
