//! Switching OTC on and off (docs/otc.md, "Switching a legacy TC program
//! to OTC": the wear booked at switch-off, position requests, tool
//! changes), and the NotAllowed check of the PLC units ("The error bits").

use tc_module::{GroupAccess, Groups, AXES};
use uoi::AccessError;

use crate::plc::PlcUnit;
use crate::setting::ProcType;
use crate::state::{OtcErrorBits, GRINDING};
use crate::wear::units::TakenUnits;
use crate::wear::{TakenMut, WearState};
use crate::OtcExtension;

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

/// `#OTC OFF`: the wear since ON is booked on the tool and read back
/// through the V.G. values; every unit gives its offset back. A booking
/// the tool entry refuses (a radius or length beyond ±1e9) changes
/// nothing.
fn switch_off(g: &mut Access<'_>, axes: &mut [PlcUnit; AXES]) -> Result<(), AccessError> {
    let t = taken(g);
    let s = g.state_mut();
    let units = TakenMut::lend(t, &mut s.radius_unit, axes);
    let w_disc = units.w_disc();
    let s = g.state();
    let w_cont = booked(s.wear.w_cont);
    let w = booked(w_cont + w_disc);
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
            if g.state().proc_type == ProcType::Radius && g.running() {
                g.state_mut().error |= OtcErrorBits::SEQUENCE;
            } else {
                switch_off(&mut g, &mut self.axes)?;
                self.on_group = None;
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
