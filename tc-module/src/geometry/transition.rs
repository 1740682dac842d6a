//! Transitions inserted at outside corners (docs/trc.md "Outside corner,
//! circular transition" and the two linear ones: TransitionMode 0
//! circular, 1 linear).

use super::angle::turn_at_most_right_angle;
use super::intersect::line_line;
use super::vector::V2;

/// Elements inserted at an outside corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transition {
    /// One arc about the programmed corner (TransitionMode 0).
    Arc {
        /// The programmed corner K.
        centre: V2,
        /// Counter-clockwise?
        ccw: bool,
        /// End point `pb`.
        to: V2,
    },
    /// Two or three straight lines (TransitionMode 1): the end points of
    /// the successive lines.
    Lines(TransitionLines),
}

/// The end points of a linear transition's two or three lines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransitionLines {
    /// θ ≤ 90°: `pa → p → pb`, p where the tangent lines meet.
    Two([V2; 2]),
    /// θ > 90°: `pa → pa + |d| ta → pb - |d| tb → pb`.
    Three([V2; 3]),
}

impl TransitionLines {
    /// The end points, in order.
    pub fn points(&self) -> &[V2] {
        match self {
            TransitionLines::Two(p) => p,
            TransitionLines::Three(p) => p,
        }
    }
}

/// The transition at an outside corner K from `pa` (tangent `ta`) to `pb`
/// (tangent `tb`) for offset `d`.
pub fn transition(linear: bool, k: V2, pa: V2, pb: V2, ta: V2, tb: V2, d: f64) -> Transition {
    if !linear {
        return Transition::Arc {
            centre: k,
            ccw: d < 0.0,
            to: pb,
        };
    }
    if turn_at_most_right_angle(ta, tb) {
        if let Some(p) = line_line(pa, ta, pb, tb) {
            return Transition::Lines(TransitionLines::Two([p, pb]));
        }
    }
    let r = d.abs();
    Transition::Lines(TransitionLines::Three([pa + ta * r, pb - tb * r, pb]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    /// The right-angle outside corner at (10, 0), left side, radius 2.
    fn right_angle(linear: bool) -> Transition {
        let (k, pa, pb) = (v(10.0, 0.0), v(10.0, 2.0), v(12.0, 0.0));
        transition(linear, k, pa, pb, v(1.0, 0.0), v(0.0, -1.0), 2.0)
    }

    #[test]
    fn circular_is_one_arc_about_the_corner() {
        let t = right_angle(false);
        assert_eq!(
            t,
            Transition::Arc {
                centre: v(10.0, 0.0),
                ccw: false,
                to: v(12.0, 0.0)
            }
        );
    }

    #[test]
    fn linear_right_angle_is_two_lines() {
        let t = right_angle(true);
        assert_eq!(
            t,
            Transition::Lines(TransitionLines::Two([v(12.0, 2.0), v(12.0, 0.0)]))
        );
    }

    #[test]
    fn linear_obtuse_turn_is_three_lines() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let t = transition(
            true,
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(s, s),
            v(1.0, 0.0),
            v(-s, -s),
            1.0,
        );
        let Transition::Lines(TransitionLines::Three(p)) = t else {
            panic!("{t:?}");
        };
        assert!((p[0] - v(1.0, 1.0)).norm() < 1e-12);
        assert!((p[1] - v(2.0 * s, 2.0 * s)).norm() < 1e-12);
        assert_eq!(p[2], v(s, s));
    }
}
