//! The OTC wear model, one interpolation cycle at a time (docs/otc.md,
//! "What happens in each interpolation cycle"). Pure: the state of the group
//! whose OTC is on and the PLC units it takes go in, with the settings in
//! force and the cycle's facts; the offset to the executed position
//! comes out, and the state is updated. It allocates nothing.
//!
//! Within one cycle: the continuous wear of the path travelled is added,
//! each taken unit ramps one step, then the direction is taken where the
//! cycle ended, and the offset is `−w · direction` (RADIUS: `−w · weight
//! · n`), `w = w_cont + w_disc`.

pub mod direction;
pub mod ramp;
pub mod units;

use tc_module::{AxisPos, Cycle, Origin, PathPart, PlaneAxes, AXES};

use crate::plc::{PlcUnit, APPLIED_UNIT_MM};
use crate::quantity::{TenthMicrons, TiltAngle, WearRate};
use direction::{length_dir, radius_weight, surface_normal, tool_dir, xyz_mask};
use tc_objects::{OtcMode, ProcType};

/// What the model keeps of a group between cycles.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WearState {
    /// Continuous wear since OTC ON, interpolation units.
    pub w_cont: f64,
    /// The unit wear direction of the last cycle (RADIUS: `n`, without
    /// its weight): kept where a cycle cannot find one, and the direction
    /// a switch-off books the wear along; `None` since ON.
    pub last_dir: Option<AxisPos>,
    /// The tool direction of the last B on the last X, Y, Z.
    pub tool_dir: Memo<(f64, [u8; 3])>,
    /// The LENGTH direction of the last tilt on the last main plane.
    pub tilt_dir: Memo<(TiltAngle, PlaneAxes)>,
    /// The mask of the last X, Y, Z (SURF_NORM_DIR).
    pub xyz_mask: Memo<[u8; 3]>,
}

/// A direction kept with the key it was computed for: its sine and cosine
/// cost more than the rest of a cycle, and its angle rarely changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Memo<K> {
    kept: Option<(K, AxisPos)>,
}

impl<K> Default for Memo<K> {
    fn default() -> Self {
        Self { kept: None }
    }
}

impl<K: Copy + PartialEq> Memo<K> {
    /// The direction for `key`: the kept one if computed for the same key,
    /// else `f(key)`, kept.
    pub fn get(&mut self, key: K, f: impl FnOnce(K) -> AxisPos) -> AxisPos {
        match self.kept {
            Some((k, d)) if k == key => d,
            _ => {
                let d = f(key);
                self.kept = Some((key, d));
                d
            }
        }
    }
}

/// The settings in force for one cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearSettings {
    /// Processing type.
    pub proc_type: ProcType,
    /// Mode.
    pub mode: OtcMode,
    /// The wear constant fixed at ON.
    pub wear_const: WearRate,
    /// AccWeight, percent.
    pub acc_weight: i32,
    /// ToolMaxInfeed of the current entry.
    pub max_infeed: TenthMicrons,
    /// ToolTiltAngle of the current entry.
    pub tilt: TiltAngle,
    /// The main plane (LENGTH's first and third main axes).
    pub axes: PlaneAxes,
    /// The machine axes allocated as X, Y, Z (AxisNr).
    pub xyz: [u8; 3],
    /// The machine axis of the orientation angle B.
    pub ori_axis: usize,
}

/// The PLC units the type and mode take, mutable (their applied values
/// ramp); `None` where one is not taken.
#[derive(Debug, Default)]
pub struct TakenMut<'a> {
    /// The group's channel unit.
    pub channel: Option<&'a mut PlcUnit>,
    /// The device-4 unit of one axis.
    pub axis: Option<&'a mut PlcUnit>,
}

impl<'a> TakenMut<'a> {
    /// Lends the units `taken` names: the group's `channel` unit and one of
    /// the machine `axes`' units.
    pub fn lend(
        taken: units::TakenUnits,
        channel: &'a mut PlcUnit,
        axes: &'a mut [PlcUnit],
    ) -> Self {
        Self {
            channel: taken.channel.then_some(channel),
            axis: taken.axis.and_then(|a| axes.get_mut(a)),
        }
    }

    /// `w_disc`: the applied values of the taken units, interpolation units.
    pub fn w_disc(&self) -> f64 {
        let applied = |u: &Option<&mut PlcUnit>| u.as_ref().map_or(0.0, |u| u.applied);
        (applied(&self.channel) + applied(&self.axis)) * APPLIED_UNIT_MM
    }

    /// Whether every taken unit stands on its target.
    pub fn at_rest(&self, max_infeed: TenthMicrons) -> bool {
        let on_target = |u: &Option<&mut PlcUnit>| {
            u.as_ref()
                .is_none_or(|u| u.applied == ramp::target(u, max_infeed))
        };
        on_target(&self.channel) && on_target(&self.axis)
    }

    fn ramp(&mut self, set: &WearSettings) {
        let step = ramp::step_per_cycle(set.acc_weight);
        for u in [&mut self.channel, &mut self.axis].into_iter().flatten() {
            u.applied = ramp::ramp(u.applied, ramp::target(u, set.max_infeed), step);
        }
    }
}

/// Whether the path of `part` wears the tool: feed elements only; for
/// RADIUS only those the running correction spooled.
pub fn wears(part: &PathPart, proc: ProcType) -> bool {
    !part.rapid
        && (proc != ProcType::Radius
            || matches!(part.origin, Origin::Corrected | Origin::Transition))
}

/// The continuous wear of one cycle's path: `k · ds` over the parts that
/// wear ([`WearRate::wear_over`]).
pub fn continuous_wear(parts: &[PathPart], proc: ProcType, wear_const: WearRate) -> f64 {
    let ds: f64 = parts
        .iter()
        .filter(|p| wears(p, proc))
        .map(|p| p.length)
        .sum();
    wear_const.wear_over(ds)
}

/// The unit direction wear acts against at the cycle's end, and the
/// weight it acts with (RADIUS' weight, else 1). A direction that cannot
/// be found here (RADIUS off the elements the correction spooled, a
/// degenerate surface normal) is the last one. The tilted and tool
/// directions are remembered while their angle stays.
fn direction(state: &mut WearState, set: &WearSettings, c: &Cycle<'_>) -> (AxisPos, f64) {
    let b = c.nominal[set.ori_axis];
    let mut t = || {
        state
            .tool_dir
            .get((b, set.xyz), |(b, xyz)| tool_dir(b, xyz))
    };
    match set.proc_type {
        ProcType::Radius => {
            let n = match c.normal() {
                Some(n) => n,
                None => state.last_dir.unwrap_or([0.0; AXES]),
            };
            (n, radius_weight(c))
        }
        ProcType::Length => {
            let key = (set.tilt, set.axes);
            let u = state
                .tilt_dir
                .get(key, |(tilt, axes)| length_dir(tilt.degrees(), axes));
            (u, 1.0)
        }
        ProcType::ToolDir => (t(), 1.0),
        ProcType::SurfNormDir => {
            let t = t();
            let mask = state.xyz_mask.get(set.xyz, xyz_mask);
            let n = match surface_normal(c, &t, &mask) {
                Some(n) => n,
                None => state.last_dir.unwrap_or(t),
            };
            (n, 1.0)
        }
    }
}

/// One cycle of the model: updates `state` and the taken units, returns
/// the offset to add to the nominal position.
pub fn run_cycle(
    state: &mut WearState,
    units: &mut TakenMut<'_>,
    set: &WearSettings,
    c: &Cycle<'_>,
) -> AxisPos {
    if set.mode != OtcMode::Disc {
        state.w_cont += continuous_wear(c.parts, set.proc_type, set.wear_const);
    }
    units.ramp(set);
    offset_at(state, units, set, c)
}

/// The offset for the wear so far where cycle `c` stands, no wear added
/// and no unit ramped (also after a direct command moved the axes at
/// once); keeps the direction in `state`.
pub fn offset_at(
    state: &mut WearState,
    units: &TakenMut<'_>,
    set: &WearSettings,
    c: &Cycle<'_>,
) -> AxisPos {
    let w = state.w_cont + units.w_disc();
    let (dir, weight) = direction(state, set, c);
    state.last_dir = Some(dir);
    dir.map(|d| -w * weight * d)
}

#[cfg(test)]
mod tests;
