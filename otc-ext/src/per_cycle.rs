//! The wear model plugged into the executor ([`WearModel`], OTC's
//! `CycleModel`): for the group whose OTC is on, the settings in force are
//! read from the group, its current tool entry and the axes, and the taken
//! PLC units are lent to the model for one cycle; the model is at rest
//! when those units stand on their targets.

use tc_module::{AxisPos, Cycle, CycleModel, GroupAccess, Groups, AXES};

use crate::plc::PlcUnit;
use crate::switching::taken;
use crate::wear::{offset_at, run_cycle, TakenMut, WearSettings};
use crate::OtcExtension;

type Access<'a> = GroupAccess<'a, OtcExtension>;

/// The settings in force for the group (read every cycle, docs/otc.md "Switching a legacy TC program to OTC", so
/// AccWeight, ToolMaxInfeed and ToolTiltAngle act from the next one).
fn settings(g: &Access<'_>) -> WearSettings {
    let (s, tool) = (g.state(), g.tool().ext);
    WearSettings {
        proc_type: s.proc_type,
        mode: s.mode,
        wear_const: s.const_in_force,
        acc_weight: s.acc_weight,
        max_infeed: tool.max_infeed,
        tilt: tool.tilt,
        axes: g.main_axes().plane,
        xyz: g.main_axes().xyz,
        // The table limits OriAxis to 0..7.
        ori_axis: s.ori_axis.min(AXES - 1),
    }
}

/// Runs `f` on the group whose OTC is on (`on`) with its settings and the
/// units it takes; `None` when no group's OTC is on.
fn with_on_group<T>(
    axes: &mut [PlcUnit; AXES],
    on: Option<u16>,
    mut groups: Groups<'_, OtcExtension>,
    f: impl FnOnce(&mut crate::wear::WearState, &mut TakenMut<'_>, &WearSettings) -> T,
) -> Option<T> {
    let mut g = groups.get(on?)?;
    let (set, t) = (settings(&g), taken(&g));
    let s = g.state_mut();
    let mut units = TakenMut::lend(t, &mut s.radius_unit, axes);
    Some(f(&mut s.wear, &mut units, &set))
}

/// OTC's per-cycle model over the groups: the wear model of the group
/// whose OTC is on ([`TcExtension::cycle_model`](tc_module::TcExtension::cycle_model)).
#[derive(Debug)]
pub struct WearModel<'a> {
    axes: &'a mut [PlcUnit; AXES],
    on: Option<u16>,
    groups: Groups<'a, OtcExtension>,
}

impl<'a> WearModel<'a> {
    /// The model of `ext` over `groups`.
    pub(crate) fn new(ext: &'a mut OtcExtension, groups: Groups<'a, OtcExtension>) -> Self {
        Self {
            axes: &mut ext.axes,
            on: ext.on_group,
            groups,
        }
    }
}

impl CycleModel for WearModel<'_> {
    /// Acts while a group's OTC is on.
    fn active(&self) -> bool {
        self.on.is_some()
    }

    /// One interpolation cycle of the wear model: the offset of the group
    /// whose OTC is on (none while no OTC is on).
    fn cycle(&mut self, c: &Cycle<'_>) -> AxisPos {
        with_on_group(
            self.axes,
            self.on,
            self.groups.reborrow(),
            |state, units, set| run_cycle(state, units, set, c),
        )
        .unwrap_or([0.0; AXES])
    }

    /// At rest when a cycle in which nothing moves would change nothing:
    /// the units the group whose OTC is on takes stand on their targets.
    fn at_rest(&mut self) -> bool {
        with_on_group(
            self.axes,
            self.on,
            self.groups.reborrow(),
            |_, units, set| units.at_rest(set.max_infeed),
        )
        .unwrap_or(true)
    }

    /// The offset for the wear so far where the executor stands, no cycle
    /// passing (after a direct command).
    fn offset_now(&mut self, c: &Cycle<'_>) -> AxisPos {
        with_on_group(
            self.axes,
            self.on,
            self.groups.reborrow(),
            |state, units, set| offset_at(state, units, set, c),
        )
        .unwrap_or([0.0; AXES])
    }
}
