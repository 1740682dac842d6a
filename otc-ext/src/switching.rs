//! Switching OTC on and off (docs/otc.md, "Switching a legacy TC program
//! to OTC": the wear booked at switch-off, position requests, tool
//! changes), and the NotAllowed check of the PLC units ("The error bits").

use tc_module::limits::within_limit;
use tc_module::{GroupAccess, Groups, MainAxes, ToolEntry, AXES};
use uoi::AccessError;

use crate::plc::{PlcUnit, APPLIED_UNIT_MM};
use crate::state::{OtcErrorBits, OtcGroup, OtcTool, GRINDING};
use crate::wear::units::TakenUnits;
use crate::wear::WearState;
use crate::OtcExtension;
use tc_objects::ProcType;

type Access<'a> = GroupAccess<'a, OtcExtension>;

/// The units the group's type and mode take.
pub(crate) fn taken(g: &Access<'_>) -> TakenUnits {
    let s = g.state();
    TakenUnits::of(s.proc_type, s.mode, g.main_axes().plane.third)
}

/// Rule 8: NotAllowed when an enabled unit is one the group's type and
/// mode ignore (the unit stays ignored, OTC keeps running).
pub(crate) fn check_units(g: &mut Access<'_>, axes: &[PlcUnit; AXES]) {
    let ignored = taken(g).ignore_an_enabled(&g.state().radius_unit, axes);
    if ignored {
        g.state_mut().error |= OtcErrorBits::NOT_ALLOWED;
    }
}

/// Steps of booked wear per mm: wear is booked to 1e-10 mm. The sum of
/// millions of per-cycle increments carries floating-point noise far
/// below that (9.5 mm of wear read 9.500000000001434), and no controller
/// or measurement resolves anything near it (docs/decisions.md, decision
/// 444).
const WEAR_STEPS_PER_MM: f64 = 1e10;

/// `w` to the resolution of booked wear: the nearest step, as the double
/// nearest to that decimal (a division by a power of ten).
fn booked(w: f64) -> f64 {
    let steps = (w * WEAR_STEPS_PER_MM).round();
    // Far beyond any wear a tool entry takes (1e9 mm): left as it is.
    if steps.abs() < 1e20 {
        steps / WEAR_STEPS_PER_MM
    } else {
        w
    }
}

/// The wear `#OTC OFF` books on the tool, `(w, w_cont)`: since ON, the
/// continuous part and the applied values of the taken units.
fn booking(s: &OtcGroup, axes: &[PlcUnit; AXES], main: MainAxes) -> (f64, f64) {
    let t = TakenUnits::of(s.proc_type, s.mode, main.plane.third);
    let channel = if t.channel {
        s.radius_unit.applied
    } else {
        0.0
    };
    let axis = t.axis.and_then(|a| axes.get(a)).map_or(0.0, |u| u.applied);
    let w_disc = (channel + axis) * APPLIED_UNIT_MM;
    let w_cont = booked(s.wear.w_cont);
    (booked(w_cont + w_disc), w_cont)
}

/// Whether OTC of a group in state `s` goes off when written 0: it is on,
/// and no RADIUS correction of it runs (that is out of sequence).
pub(crate) fn switches_off(s: &OtcGroup, running: bool) -> bool {
    s.on && !(s.proc_type == ProcType::Radius && running)
}

/// The tool entry `tool` with the wear of `#OTC OFF` booked on its radius
/// or length; `Range` when the entry refuses it (beyond ±1e9).
pub(crate) fn booked_entry(
    s: &OtcGroup,
    tool: &ToolEntry<OtcTool>,
    axes: &[PlcUnit; AXES],
    main: MainAxes,
) -> Result<ToolEntry<OtcTool>, AccessError> {
    let (w, _) = booking(s, axes, main);
    let mut entry = *tool;
    let field = match s.proc_type {
        ProcType::Radius => &mut entry.radius,
        _ => &mut entry.length,
    };
    *field -= w;
    if within_limit(*field) {
        Ok(entry)
    } else {
        Err(AccessError::Range)
    }
}

/// `#OTC OFF`: the wear since ON is booked on the tool and read back
/// through the V.G. values; every unit gives its offset back. A booking
/// the tool entry refuses (a radius or length beyond ±1e9) changes
/// nothing.
fn switch_off(g: &mut Access<'_>, axes: &mut [PlcUnit; AXES]) -> Result<(), AccessError> {
    let (w, w_cont) = booking(g.state(), axes, g.main_axes());
    let s = g.state();
    let dir = s.wear.last_dir.unwrap_or([0.0; AXES]);
    if s.proc_type == ProcType::Radius {
        g.reduce_radius(w)?;
        let s = g.state_mut();
        s.wear_radius += w;
        s.wear_radius_cont += w_cont;
    } else {
        g.reduce_length(w)?;
        let s = g.state_mut();
        for (acc, u) in s.wear_axis.iter_mut().zip(dir) {
            *acc += w * u;
        }
    }
    let s = g.state_mut();
    s.wear = WearState::default();
    s.radius_unit.applied = 0.0;
    s.on = false;
    axes.iter_mut().for_each(|u| u.applied = 0.0);
    Ok(())
}

/// `#OTC ON` of the group at `index`: needs a grinding tool (else
/// ToolType) and no other group with OTC on (else Sequence); fixes the
/// wear constant and checks the units. Whether OTC went on.
fn switch_on(index: u16, groups: &mut Groups<'_, OtcExtension>, axes: &[PlcUnit; AXES]) -> bool {
    let other_on = groups
        .iter_mut()
        .any(|g| g.index() != index && g.state().on);
    let Some(mut g) = groups.get(index) else {
        return false;
    };
    let tool = g.tool().ext;
    let s = g.state_mut();
    if tool.tool_type != GRINDING {
        s.error |= OtcErrorBits::TOOL_TYPE;
    } else if other_on {
        s.error |= OtcErrorBits::SEQUENCE;
    } else {
        s.const_in_force = s.wear_const_override.unwrap_or(tool.wear_const);
        s.wear = WearState::default();
        s.on = true;
        check_units(&mut g, axes);
        return true;
    }
    false
}

impl OtcExtension {
    /// `OtcOn` of the group at `index` written. ON twice or OFF while off
    /// changes nothing; OFF while a RADIUS correction runs is out of
    /// sequence.
    pub(crate) fn write_on(
        &mut self,
        index: u16,
        on: bool,
        mut groups: Groups<'_, Self>,
    ) -> Result<(), AccessError> {
        let is_on = groups.get(index).is_some_and(|g| g.state().on);
        if on && !is_on {
            if switch_on(index, &mut groups, &self.axes) {
                self.on_group = Some(index);
            }
        } else if !on && is_on {
            let Some(mut g) = groups.get(index) else {
                return Ok(());
            };
            if switches_off(g.state(), g.running()) {
                switch_off(&mut g, &mut self.axes)?;
                self.on_group = None;
            } else {
                g.state_mut().error |= OtcErrorBits::SEQUENCE;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod booking_tests {
    use super::booked;

    #[test]
    fn booked_wear_has_no_floating_point_noise() {
        assert_eq!(booked(9.500000000001434), 9.5);
        assert_eq!(30.0 - booked(9.500000000001434), 20.5);
        assert_eq!(booked(2.42356194490001), 2.4235619449);
        assert_eq!(booked(-0.145), -0.145);
        assert_eq!(booked(0.0), 0.0);
        assert!(booked(f64::NAN).is_nan());
        assert_eq!(booked(1e300), 1e300);
    }
}
