//! Angle comparisons as sign tests. The rules compare angles (θ ≤ 0.05
//! rad, θ ≤ 90°, a point within 1e-9 rad of an arc part); comparing
//! cross and dot products with the tangent of the tolerance decides the
//! same without trigonometry. Within [`SIGN_BAND`] of a boundary the
//! angle itself (atan2, as the rule is written) decides, so every
//! decision is the one the angle gives.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::tolerance::{AngleTol, NEARLY_CLOSED, ON_ARC, SIGN_BAND};
use super::vector::{cross, V2};

/// Turn angle θ in [0, π] between two vectors: the reference the sign
/// tests fall back to.
pub fn turn_angle(ta: V2, tb: V2) -> f64 {
    cross(ta, tb).abs().atan2(ta.dot(&tb))
}

/// Whether `atan2(y, x)` (y ≥ 0) is at most `tol`: the sign of
/// `y - tan·x`; `None` within the band around the boundary (and for NaN).
fn at_most(y: f64, x: f64, tol: AngleTol) -> Option<bool> {
    let margin = y - tol.tan() * x;
    (margin.abs() > SIGN_BAND * (x.abs() + y)).then_some(margin < 0.0)
}

/// θ between `a` and `b` is at most `tol`.
pub fn turn_at_most(a: V2, b: V2, tol: AngleTol) -> bool {
    let (y, x) = (cross(a, b).abs(), a.dot(&b));
    at_most(y, x, tol).unwrap_or_else(|| turn_angle(a, b) <= tol.rad())
}

/// θ between `a` and `b` is at least `π - tol` (a near-reversal).
pub fn turn_at_least_reversal(a: V2, b: V2, tol: AngleTol) -> bool {
    let (y, x) = (cross(a, b).abs(), a.dot(&b));
    at_most(y, -x, tol).unwrap_or_else(|| turn_angle(a, b) >= PI - tol.rad())
}

/// θ between `a` and `b` is at most 90°: `a · b ≥ 0`.
pub fn turn_at_most_right_angle(a: V2, b: V2) -> bool {
    let (y, x) = (cross(a, b).abs(), a.dot(&b));
    if x.abs() > SIGN_BAND * (x.abs() + y) {
        x > 0.0
    } else {
        turn_angle(a, b) <= FRAC_PI_2
    }
}

fn l1(v: V2) -> f64 {
    v.x.abs() + v.y.abs()
}

/// `σ (u × v)`, or `None` when u and v are within the band of one line
/// (or NaN).
fn side(u: V2, v: V2, sigma: f64) -> Option<f64> {
    let c = sigma * cross(u, v);
    (c.abs() > SIGN_BAND * l1(u) * l1(v)).then_some(c)
}

/// Whether `p` lies within the sweep from `a` to `b` in direction σ
/// (angles about the origin, from `a`, in [0, 2π)); `None` when two of
/// the three are within the band of one line.
fn in_sweep(a: V2, b: V2, p: V2, sigma: f64) -> Option<bool> {
    let (ab, ap, pb) = (side(a, b, sigma)?, side(a, p, sigma)?, side(p, b, sigma)?);
    // Half turns from a: [0, π) where the cross is positive.
    Some(match (ap > 0.0, ab > 0.0) {
        (true, false) => true,
        (false, true) => false,
        _ => pb > 0.0,
    })
}

/// `v` turned by the small angle `phi` (|phi| ≤ [`ON_ARC`]: its sine is
/// itself and its cosine 1 in f64).
fn turned(v: V2, phi: f64) -> V2 {
    V2::new(v.x - phi * v.y, v.y + phi * v.x)
}

/// Whether `x` lies on the arc part from `from` to `to` about `centre` in
/// direction σ, [`ON_ARC`] radians beyond either end included: the angle
/// `at` of x from `from` (in direction σ, in [0, 2π)) is at most the
/// part's sweep + ON_ARC, or at least 2π - ON_ARC.
pub fn on_arc_part(centre: V2, sigma: f64, from: V2, to: V2, x: V2) -> bool {
    let (f, t, p) = (from - centre, to - centre, x - centre);
    // The part widened by ON_ARC at both ends; a sweep that nearly closes
    // the circle (or nearly vanishes) is left to the angles.
    let nearly_closed = f.dot(&t) > 0.0 && cross(f, t).abs() <= NEARLY_CLOSED * l1(f) * l1(t);
    let fast = if nearly_closed {
        None
    } else {
        in_sweep(
            turned(f, -sigma * ON_ARC),
            turned(t, sigma * ON_ARC),
            p,
            sigma,
        )
    };
    fast.unwrap_or_else(|| on_arc_part_by_angles(centre, sigma, from, to, x))
}

/// [`on_arc_part`] with atan2 angles, as the rule is written.
pub fn on_arc_part_by_angles(centre: V2, sigma: f64, from: V2, to: V2, x: V2) -> bool {
    let ang = |p: V2| (p.y - centre.y).atan2(p.x - centre.x);
    let sweep = (sigma * (ang(to) - ang(from))).rem_euclid(TAU);
    let at = (sigma * (ang(x) - ang(from))).rem_euclid(TAU);
    at <= sweep + ON_ARC || at >= TAU - ON_ARC
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tolerance::{FULL_CIRCLE, TANGENT};
    use proptest::prelude::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    fn at(angle: f64) -> V2 {
        v(angle.cos(), angle.sin())
    }

    /// Angles around `edge`: the edge itself, a few ulps and a few band
    /// widths either side, and clear of it.
    fn around(edge: f64) -> Vec<f64> {
        let mut out = vec![edge, edge * 0.5, edge * 1.5];
        for k in 1..=4 {
            let ulps = f64::EPSILON * edge.abs().max(1.0) * k as f64;
            out.extend([edge - ulps, edge + ulps]);
            let band = SIGN_BAND * 4.0f64.powi(k);
            out.extend([edge - band, edge + band]);
        }
        out
    }

    #[test]
    fn turn_tests_agree_with_the_angle_at_the_boundaries() {
        for tol in [TANGENT, FULL_CIRCLE] {
            for base in [0.0, 1.0, -2.5, 3.0] {
                for theta in around(tol.rad()).into_iter().chain(around(PI - tol.rad())) {
                    for sign in [1.0, -1.0] {
                        let (a, b) = (at(base), at(base + sign * theta));
                        let angle = turn_angle(a, b);
                        assert_eq!(turn_at_most(a, b, tol), angle <= tol.rad(), "{theta}");
                        let rev = angle >= PI - tol.rad();
                        assert_eq!(turn_at_least_reversal(a, b, tol), rev, "{theta}");
                    }
                }
            }
        }
    }

    #[test]
    fn right_angle_test_agrees_with_the_angle() {
        for base in [0.0, 0.3, -2.0] {
            for theta in around(FRAC_PI_2) {
                let (a, b) = (at(base), at(base + theta));
                let want = turn_angle(a, b) <= FRAC_PI_2;
                assert_eq!(turn_at_most_right_angle(a, b), want, "{theta}");
            }
        }
        // Exactly perpendicular, either sign of zero: 90° is at most 90°.
        assert!(turn_at_most_right_angle(v(1.0, 0.0), v(0.0, 1.0)));
        assert!(turn_at_most_right_angle(v(1.0, 0.0), v(-0.0, -1.0)));
        assert!(!turn_at_most_right_angle(v(1.0, 0.0), v(-1e-3, 1.0)));
    }

    #[test]
    fn tangent_tolerance_is_inclusive_and_scale_free() {
        let a = v(3.0, 0.0);
        assert!(turn_at_most(a, at(0.0499) * 7.0, TANGENT));
        assert!(!turn_at_most(a, at(0.0501) * 7.0, TANGENT));
        assert!(turn_at_most(a, a, TANGENT));
        assert!(!turn_at_most(a, -a, TANGENT));
        assert!(turn_at_least_reversal(a, -a, TANGENT));
        // A zero vector: the angle decides (atan2(0, 0) = 0).
        assert!(turn_at_most(v(0.0, 0.0), a, TANGENT));
    }

    #[test]
    fn arc_part_ends_with_on_arc_either_side() {
        let (c, from, to) = (v(1.0, 2.0), 0.3, 1.2);
        for sigma in [1.0, -1.0] {
            let p = |a: f64| c + at(a) * 5.0;
            let (f, t) = (p(from), p(sigma * to + (1.0 - sigma) * from));
            let end = if sigma > 0.0 { to } else { from - (to - from) };
            for (x, want) in [
                (from + sigma * 0.5 * (to - from), true),
                (from - sigma * 0.5 * ON_ARC, true),
                (from - sigma * 2.0 * ON_ARC, false),
                (end + sigma * 0.5 * ON_ARC, true),
                (end + sigma * 2.0 * ON_ARC, false),
                (from + PI + 1.0, false),
            ] {
                assert_eq!(on_arc_part(c, sigma, f, t, p(x)), want, "σ {sigma} at {x}");
                assert_eq!(on_arc_part_by_angles(c, sigma, f, t, p(x)), want);
            }
        }
    }

    #[test]
    fn sweep_sign_test_decides_clear_cases_itself() {
        let (a, b) = (v(1.0, 0.0), v(0.0, 1.0));
        assert_eq!(in_sweep(a, b, v(1.0, 1.0), 1.0), Some(true));
        assert_eq!(in_sweep(a, b, v(1.0, 1.0), -1.0), Some(false));
        assert_eq!(in_sweep(a, b, v(-1.0, -1.0), -1.0), Some(true));
        assert_eq!(in_sweep(a, -a, v(1.0, 1.0), 1.0), None);
        assert_eq!(in_sweep(a, b, v(2.0, 0.0), 1.0), None);
    }

    #[test]
    fn arc_part_nearly_closed_or_empty_uses_the_angles() {
        let c = v(0.0, 0.0);
        let f = at(1.0) * 2.0;
        for gap in [0.0, 1e-12, 1e-9, 3e-9, 1e-7, -1e-9, -3e-9, -1e-7] {
            let t = at(1.0 + gap) * 2.0;
            for x in around(1.0).into_iter().chain([1.0 + PI, 1.0 - 1e-8]) {
                for sigma in [1.0, -1.0] {
                    let want = on_arc_part_by_angles(c, sigma, f, t, at(x) * 2.0);
                    assert_eq!(on_arc_part(c, sigma, f, t, at(x) * 2.0), want, "{gap} {x}");
                }
            }
        }
    }

    proptest! {
        /// The sign tests decide as the angles do, also next to every end.
        #[test]
        fn arc_part_sign_test_equals_angles(
            cx in -1e3..1e3f64, cy in -1e3..1e3f64, r in 1e-6..1e4f64,
            a0 in -7.0..7.0f64, sweep in -7.0..7.0f64,
            pick in 0..4usize, off in -1e-8..1e-8f64, free in -7.0..7.0f64,
            ccw in any::<bool>(),
        ) {
            let (c, sigma) = (v(cx, cy), if ccw { 1.0 } else { -1.0 });
            let x = match pick {
                0 => a0 + off,
                1 => a0 + sweep + off,
                2 => a0 + sweep * 0.5,
                _ => free,
            };
            let (f, t, p) = (c + at(a0) * r, c + at(a0 + sweep) * r, c + at(x) * r);
            prop_assert_eq!(on_arc_part(c, sigma, f, t, p), on_arc_part_by_angles(c, sigma, f, t, p));
        }

        /// The turn tests decide as the turn angle does.
        #[test]
        fn turn_sign_tests_equal_the_angle(
            a0 in -7.0..7.0f64, la in 1e-3..1e3f64, lb in 1e-3..1e3f64,
            pick in 0..5usize, off in -1e-9..1e-9f64, free in -4.0..4.0f64,
        ) {
            let theta = [TANGENT.rad(), PI - TANGENT.rad(), FRAC_PI_2, FULL_CIRCLE.rad(), 0.0][pick];
            for th in [theta + off, -theta - off, free] {
                let (a, b) = (at(a0) * la, at(a0 + th) * lb);
                let angle = turn_angle(a, b);
                prop_assert_eq!(turn_at_most(a, b, TANGENT), angle <= TANGENT.rad());
                prop_assert_eq!(turn_at_most(a, b, FULL_CIRCLE), angle <= FULL_CIRCLE.rad());
                prop_assert_eq!(turn_at_least_reversal(a, b, TANGENT), angle >= PI - TANGENT.rad());
                prop_assert_eq!(turn_at_most_right_angle(a, b), angle <= FRAC_PI_2);
            }
        }
    }
}
