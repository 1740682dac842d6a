//! Corner classification (docs/trc.md "How a corner is decided", cases
//! 1-4).

use super::angle::{turn_at_least_reversal, turn_at_most};
use super::offset::OffsetPath;
use super::tolerance::TANGENT;
use super::vector::{cross, V2};

/// What a corner needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CornerKind {
    /// Case 1: nothing inserted, the next element continues from `pa`.
    Smooth,
    /// The tool goes around the corner: a transition is inserted.
    Outside,
    /// The offsets cross: both are cut at their intersection.
    Inside,
}

/// Classifies the corner between element `a` (end tangent `ta`) and the
/// next `b` (start tangent `tb`) for offset `d`. The turn angle θ is
/// compared by sign tests ([`super::angle`]).
pub fn classify(ta: V2, tb: V2, d: f64, a: &OffsetPath, b: &OffsetPath) -> CornerKind {
    if d == 0.0 || turn_at_most(ta, tb, TANGENT) {
        return CornerKind::Smooth;
    }
    let s_eff = d.signum();
    if turn_at_least_reversal(ta, tb, TANGENT) {
        return near_reversal(s_eff, a, b);
    }
    if s_eff * cross(ta, tb) < 0.0 {
        CornerKind::Outside
    } else {
        CornerKind::Inside
    }
}

/// Case 2: an inside corner when b is an arc and the tool is outside it,
/// or b is a line and a is an arc with the tool outside it.
fn near_reversal(s_eff: f64, a: &OffsetPath, b: &OffsetPath) -> CornerKind {
    let outside_arc =
        |p: &OffsetPath| matches!(*p, OffsetPath::Arc { sigma, .. } if s_eff * sigma < 0.0);
    let inside = match b {
        OffsetPath::Arc { .. } => outside_arc(b),
        OffsetPath::Line { .. } => outside_arc(a),
    };
    if inside {
        CornerKind::Inside
    } else {
        CornerKind::Outside
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::angle::turn_angle;
    use crate::geometry::tolerance::TANGENT;
    const TANGENT_TOL: f64 = TANGENT.rad();
    use std::f64::consts::PI;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    const LINE: OffsetPath = OffsetPath::Line {
        dir: V2::new(1.0, 0.0),
    };

    #[test]
    fn sides_and_turns() {
        // left side, left turn: inside; right turn: outside
        let k = |ta, tb, d| classify(ta, tb, d, &LINE, &LINE);
        assert_eq!(k(v(1.0, 0.0), v(0.0, 1.0), 2.0), CornerKind::Inside);
        assert_eq!(k(v(1.0, 0.0), v(0.0, -1.0), 2.0), CornerKind::Outside);
        assert_eq!(k(v(1.0, 0.0), v(0.0, -1.0), -2.0), CornerKind::Inside);
        assert_eq!(k(v(1.0, 0.0), v(0.0, 1.0), 0.0), CornerKind::Smooth);
    }

    #[test]
    fn tangent_tolerance_is_inclusive() {
        let k = |theta: f64| classify(v(1.0, 0.0), v(theta.cos(), theta.sin()), 1.0, &LINE, &LINE);
        assert_eq!(k(0.01), CornerKind::Smooth);
        assert_eq!(k(TANGENT_TOL * 0.999), CornerKind::Smooth);
        assert_eq!(k(TANGENT_TOL * 1.001), CornerKind::Inside);
        assert_eq!(k(-TANGENT_TOL * 1.001), CornerKind::Outside);
    }

    #[test]
    fn boundaries_decided_as_the_turn_angle_decides() {
        let ta = v(1.0, 0.0);
        for edge in [TANGENT_TOL, PI - TANGENT_TOL] {
            for k in -3..=3 {
                let theta = edge + f64::from(k) * f64::EPSILON;
                let tb = v(theta.cos(), theta.sin());
                let angle = turn_angle(ta, tb);
                let want = if angle <= TANGENT_TOL {
                    CornerKind::Smooth
                } else if angle >= PI - TANGENT_TOL {
                    CornerKind::Outside // lines: a near-reversal is outside
                } else {
                    CornerKind::Inside
                };
                assert_eq!(classify(ta, tb, 1.0, &LINE, &LINE), want, "θ = {theta}");
            }
        }
    }

    #[test]
    fn near_reversal_depends_on_arcs() {
        let (ta, tb) = (v(1.0, 0.0), v(-1.0, 0.0));
        assert_eq!(classify(ta, tb, 2.0, &LINE, &LINE), CornerKind::Outside);
        let ccw = OffsetPath::Arc {
            centre: v(0.0, 0.0),
            radius: 1.0,
            sigma: 1.0,
        };
        let cw = OffsetPath::Arc {
            centre: v(0.0, 0.0),
            radius: 1.0,
            sigma: -1.0,
        };
        // Left side (s_eff +1): outside a CW arc.
        assert_eq!(classify(ta, tb, 2.0, &LINE, &cw), CornerKind::Inside);
        assert_eq!(classify(ta, tb, 2.0, &LINE, &ccw), CornerKind::Outside);
        assert_eq!(classify(ta, tb, 2.0, &cw, &LINE), CornerKind::Inside);
        assert_eq!(classify(ta, tb, -2.0, &cw, &LINE), CornerKind::Outside);
    }
}
