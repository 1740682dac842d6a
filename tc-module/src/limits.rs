//! The engine's numeric limits: how large a coordinate may be, how small a
//! step per interpolation cycle, and which cycle times are allowed. They
//! keep every number the executor works with finite and every step along
//! a path larger than the rounding of the positions it is added to.
//!
//! Why [`MIN_STEP`] is 1e-5 units: every end point and arc centre that
//! enters the spooler lies within ±[`MAX_COORD`], so a line is at most
//! √8 · 4e9 ≈ 1.2e10 long (8 axes, a start up to 2e9 out after a tool
//! length change) and an arc (radius at most 2√2 · 1e9, one turn, helical
//! on the other axes) at most ≈ 1.9e10: every path length is below 2^35,
//! where one f64 step (ulp) is 2^-18 ≈ 3.8e-6. A step of 1e-5 is more
//! than 2.6 of those ulps, so the distance run on an element always grows;
//! at a coordinate of 1e9 (ulp ≈ 1.2e-7) it is more than 80 ulps.

use std::fmt;

use uoi::AccessError;

/// Largest coordinate, offset or feed magnitude accepted (interpolation
/// units), for what a client programs and for every end point and arc
/// centre that enters the spooler (after rotation, correction and tool
/// length): beyond it a command is refused with `Range`. The registers
/// that add to a point (RADIUS, WkzLen, the rotation centre) take the same
/// range in the object table.
pub use tc_objects::MAX_COORD;

/// Smallest path step per interpolation cycle (units): a feed `F` is
/// refused with `Range` when `F · cycle / 60` is smaller (0.6 units/min at
/// the default 1 ms cycle). See the module documentation for the reason.
pub const MIN_STEP: f64 = 1e-5;

/// Shortest interpolation cycle, seconds (1 µs): the default feed (1000
/// units/min) still steps more than [`MIN_STEP`] per cycle.
pub const MIN_CYCLE_S: f64 = 1e-6;

/// Default interpolation cycle, seconds: 1 ms.
pub const DEFAULT_CYCLE_S: f64 = 1e-3;

/// Longest interpolation cycle, seconds.
pub const MAX_CYCLE_S: f64 = 1.0;

/// Default feed in units/min, until a program gives an `F` word.
pub const DEFAULT_FEED: f64 = 1000.0;

/// The feed of a rapid move (`RAP`), units/min (decision 49).
pub const RAPID_FEED: f64 = 10000.0;

// A coordinate at the limit resolves the step in many ulps.
const _: () = assert!((MAX_COORD + MIN_STEP) - MAX_COORD > 0.5 * MIN_STEP);
// The default feed is valid at the shortest cycle.
const _: () = assert!(DEFAULT_FEED * MIN_CYCLE_S / 60.0 >= MIN_STEP);

/// Whether `v` is finite and within ±[`MAX_COORD`] (NaN and the
/// infinities compare false).
#[inline]
pub fn within_limit(v: f64) -> bool {
    v.abs() <= MAX_COORD
}

/// `Range` unless every coordinate is within ±[`MAX_COORD`].
pub fn check_point(p: &[f64]) -> Result<(), AccessError> {
    if p.iter().all(|&v| within_limit(v)) {
        Ok(())
    } else {
        Err(AccessError::Range)
    }
}

/// A cycle time outside [`MIN_CYCLE_S`]..=[`MAX_CYCLE_S`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CycleError(pub f64);

impl fmt::Display for CycleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "interpolation cycle {} s: it must lie in {MIN_CYCLE_S} s ..= {MAX_CYCLE_S} s",
            self.0
        )
    }
}

impl std::error::Error for CycleError {}

/// An interpolation cycle time, checked: within
/// [`MIN_CYCLE_S`]..=[`MAX_CYCLE_S`].
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct CycleTime(f64);

impl CycleTime {
    /// The default cycle: 1 ms.
    pub const DEFAULT: CycleTime = CycleTime(DEFAULT_CYCLE_S);

    /// The one check of a cycle time, wherever it is set (module,
    /// settings, `SETUP`, trace header).
    pub fn from_secs(s: f64) -> Result<Self, CycleError> {
        if (MIN_CYCLE_S..=MAX_CYCLE_S).contains(&s) {
            Ok(Self(s))
        } else {
            Err(CycleError(s))
        }
    }

    /// The cycle in seconds.
    pub fn secs(self) -> f64 {
        self.0
    }

    /// The cycle in minutes (feeds are units/min).
    pub fn minutes(self) -> f64 {
        self.0 / 60.0
    }
}

impl Default for CycleTime {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_times_are_checked() {
        for bad in [
            0.0,
            5e-324,
            1e-320,
            9.9e-7,
            1.01,
            f64::INFINITY,
            f64::NAN,
            -1e-3,
        ] {
            assert_eq!(
                CycleTime::from_secs(bad).map(CycleTime::secs).ok(),
                None,
                "{bad}"
            );
        }
        for good in [MIN_CYCLE_S, 5e-4, 1e-3, MAX_CYCLE_S] {
            assert_eq!(CycleTime::from_secs(good).map(CycleTime::secs), Ok(good));
        }
        assert!(CycleError(0.0).to_string().contains("1 s"));
    }

    #[test]
    fn min_step_never_vanishes_on_the_longest_path() {
        // The longest path stays below 2^35; a step of MIN_STEP added to
        // any distance run below it moves it.
        let longest = 2f64.powi(35) * (1.0 - f64::EPSILON);
        assert!(longest + MIN_STEP > longest);
        assert!(1.9e10 < longest);
    }
}
