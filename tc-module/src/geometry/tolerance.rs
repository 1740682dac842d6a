//! Every tolerance of the correction geometry, named once with the rule it
//! comes from (docs/trc.md and the decisions named; the numerical ones say
//! so).

use std::f64::consts::FRAC_PI_2;

/// An angle tolerance (radians, in [0, π/2)) with its tangent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleTol {
    rad: f64,
    tan: f64,
}

impl AngleTol {
    /// The tolerance `rad` with `tan = tan(rad)` (written out, as `tan` is
    /// not a const fn; the tests below check that they belong together).
    /// Refused at compile time outside [0, π/2), where the sign tests do
    /// not hold.
    pub const fn new(rad: f64, tan: f64) -> Self {
        assert!(rad >= 0.0 && rad < FRAC_PI_2 && tan >= 0.0);
        Self { rad, tan }
    }

    /// The tolerance in radians.
    pub const fn rad(self) -> f64 {
        self.rad
    }

    /// Its tangent.
    pub const fn tan(self) -> f64 {
        self.tan
    }
}

/// "Corner", case 1: a turn of at most 0.05 rad is treated as smooth
/// (LinuxCNC's tolerance, so programs with 4-decimal coordinates keep
/// their tangencies); case 2: within 0.05 rad of π is a near-reversal.
/// With its tangent, for the sign tests of [`super::angle`].
pub const TANGENT: AngleTol = AngleTol::new(0.05, 0.050_041_708_375_538_79);

/// "Offset geometry", arcs: start and end radius may differ by this much
/// (rounding); more is a `CenterError`.
pub const CENTER_TOL: f64 = 0.002;

/// "Offset geometry", arcs: an offset radius at or below this is a
/// `CalcError`; so is a programmed arc whose own radius is (decision 15:
/// refused with `Range` when no group runs).
pub const MIN_RADIUS: f64 = 1e-9;

/// "Offset geometry", plane-null profiles: a line whose plane part is at
/// most this long has none (decision 22), and cannot be offset.
pub const PLANE_NULL: f64 = 1e-9;

/// "Inside corner", full circles: a corrected start within 1e-7 rad of
/// the offset start keeps the whole turn of a programmed full circle.
/// With its tangent.
pub const FULL_CIRCLE: AngleTol = AngleTol::new(1e-7, 1.000_000_000_000_003_3e-7);

/// Inside corners: a candidate point may lie this far (units) outside a
/// line part, and two circles this far apart still touch. Absorbs the
/// rounding of the intersection itself, not a rule of the spec.
pub const ON_PART: f64 = 1e-7;

/// Inside corners: a candidate point may lie this far (radians) outside
/// an arc part, for the same reason.
pub const ON_ARC: f64 = 1e-9;

/// Below this, a cross product of unit vectors counts as parallel (no
/// line/line intersection) and two centres as one (no circle/circle
/// intersection): numerical, not a rule of the spec.
pub const PARALLEL: f64 = 1e-12;

/// An arc element whose sweep is within this of 0 (radians) is a full
/// circle (start = end): numerical.
pub const ZERO_SWEEP: f64 = 1e-12;

/// "Inside corner": an arc whose corrected part is at most this long
/// (units, chord) has zero length and is not spooled: numerical.
pub const ZERO_ARC: f64 = 1e-12;

/// A sign test standing in for an angle comparison decides only when its
/// margin exceeds this fraction of the vectors' size (about this many
/// radians); nearer the boundary the angle itself (atan2) decides, so no
/// decision differs from the angle's: numerical, not a rule of the spec.
pub const SIGN_BAND: f64 = 1e-12;

/// An arc part whose end lies within about this angle (radians) of its
/// start, either way, is decided by its angles: a sign test cannot tell a
/// part that nearly closes the circle from one that nearly vanishes.
/// Numerical (where the fast test stops), not a rule of the spec.
pub const NEARLY_CLOSED: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangents_belong_to_their_angles() {
        for tol in [TANGENT, FULL_CIRCLE] {
            assert!((tol.rad().tan() - tol.tan()).abs() <= f64::EPSILON * tol.tan());
        }
        // Turning by ON_ARC: sine and cosine are exact in f64.
        assert_eq!(ON_ARC.sin_cos(), (ON_ARC, 1.0));
    }
}
