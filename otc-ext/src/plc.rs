//! A PLC control unit (the channel unit of a group, device 3 sub 50..53;
//! the units of the machine axes, device 4): command, enable, the value
//! applied now, and the bound of its request register.

use crate::quantity::TenthMicrons;

/// A PLC control unit: command, enable, the value applied now.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlcUnit {
    /// `command_w`.
    pub command: i32,
    /// `enable_w`.
    pub enable: bool,
    /// The value applied now, in `APPLIED_UNIT_MM` (0.01 µm): always a
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
}
