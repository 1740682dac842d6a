//! The PLC control units' discrete offsets (docs/otc.md, "What happens in
//! each interpolation cycle", step 3): the target a unit asks for and the ramp toward it.
//! Values are in the unit of [`PlcUnit::applied`] (0.01 µm), where
//! targets and steps are whole numbers.

use crate::plc::{PlcUnit, APPLIED_PER_PLC};
use crate::quantity::TenthMicrons;

/// The ramp step per cycle: `1e-3 · AccWeight / 100` mm, which is
/// AccWeight × 0.01 µm.
pub fn step_per_cycle(acc_weight: i32) -> f64 {
    f64::from(acc_weight)
}

/// The value a unit moves toward: its command (0.1 µm) clamped to
/// ±`max_infeed` when enabled (the bound as it is, fractions included;
/// only the integer request register rounds it), 0 when not (a disabled
/// unit gives its offset back).
pub fn target(unit: &PlcUnit, max_infeed: TenthMicrons) -> f64 {
    if unit.enable {
        let bound = max_infeed.magnitude();
        f64::from(unit.command).clamp(-bound, bound) * APPLIED_PER_PLC
    } else {
        0.0
    }
}

/// One cycle of the ramp: `applied` moves toward `target` by at most
/// `step`, and lands on it when within one step.
pub fn ramp(applied: f64, target: f64, step: f64) -> f64 {
    let gap = target - applied;
    if gap.abs() <= step {
        target
    } else {
        applied + step.copysign(gap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(command: i32, enable: bool) -> PlcUnit {
        PlcUnit {
            command,
            enable,
            ..PlcUnit::default()
        }
    }

    /// Runs the ramp from 0 toward `target` (0.1 µm) for `cycles` cycles;
    /// the applied value in 0.1 µm.
    fn after(cycles: u32, target: f64, acc_weight: i32) -> f64 {
        let step = step_per_cycle(acc_weight);
        let t = target * APPLIED_PER_PLC;
        (0..cycles).fold(0.0, |a, _| ramp(a, t, step)) / APPLIED_PER_PLC
    }

    #[test]
    fn two_millimetres_take_2000_cycles_at_100_percent_and_4000_at_50() {
        // 2 mm = 20000 × 0.1 µm; 1 µm per cycle at 100 %, 0.5 µm at 50 %.
        assert_eq!(after(1999, 20000.0, 100), 19990.0);
        assert_eq!(after(2000, 20000.0, 100), 20000.0);
        assert_eq!(after(3999, 20000.0, 50), 19995.0);
        assert_eq!(after(4000, 20000.0, 50), 20000.0);
        assert_eq!(after(5000, 20000.0, 50), 20000.0);
    }

    #[test]
    fn one_percent_moves_a_hundredth_of_a_micrometre_and_lands_exactly() {
        // AccWeight 1: 1e-5 mm = 0.1 × 0.1 µm per cycle; 10 µm take 1000.
        assert_eq!(after(999, 100.0, 1), 99.9);
        assert_eq!(after(1000, 100.0, 1), 100.0);
    }

    #[test]
    fn negative_targets_ramp_down_and_disabled_units_give_back() {
        assert_eq!(after(5, -30.0, 100), -30.0);
        assert_eq!(ramp(-300.0, 0.0, 100.0), -200.0);
        assert_eq!(target(&unit(-500, true), TenthMicrons(200.0)), -2000.0);
        assert_eq!(target(&unit(500, false), TenthMicrons(200.0)), 0.0);
        assert_eq!(target(&unit(500, true), TenthMicrons(0.0)), 0.0);
        // A fractional bound limits the applied value as it is.
        assert_eq!(target(&unit(1000, true), TenthMicrons(150.5)), 1505.0);
        assert_eq!(target(&unit(-1000, true), TenthMicrons(-150.5)), -1505.0);
    }
}
