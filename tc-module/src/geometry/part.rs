//! Inside corners (docs/trc.md "Inside corner of two lines", "... of a
//! line and an arc"): the part of each
//! offset element a cut point may lie on, and the cut point itself.

use super::angle::on_arc_part;
use super::intersect::{circle_circle, line_circle, line_line, Intersections};
use super::offset::OffsetPath;
use super::tolerance::ON_PART;
use super::vector::V2;

/// The part of an offset element on which an inside-corner point may lie.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Offset line or circle.
    pub path: OffsetPath,
    /// Where the part starts, or `None` for an unbounded start (an
    /// approach line).
    pub from: Option<V2>,
    /// Where it ends (a point on the carrier).
    pub to: V2,
    /// For an arc part: the whole circle (a programmed full circle whose
    /// corrected start lies on its offset start).
    pub full: bool,
}

impl Part {
    /// Whether `x` (a point on the carrier) lies on the part.
    #[inline]
    pub fn contains(&self, x: V2) -> bool {
        let Some(from) = self.from else { return true };
        match self.path {
            OffsetPath::Line { dir } => {
                let len = (self.to - from).dot(&dir);
                let u = (x - from).dot(&dir);
                u >= -ON_PART && u <= len + ON_PART
            }
            OffsetPath::Arc { .. } if self.full => true,
            OffsetPath::Arc { centre, sigma, .. } => on_arc_part(centre, sigma, from, self.to, x),
        }
    }
}

/// Where the carriers of two parts meet.
#[inline]
fn carriers_meet(a: &Part, b: &Part) -> Intersections {
    match (a.path, b.path) {
        (OffsetPath::Line { dir: da }, OffsetPath::Line { dir: db }) => {
            line_line(a.to, da, b.to, db).map_or(Intersections::None, Intersections::One)
        }
        (OffsetPath::Line { dir }, OffsetPath::Arc { centre, radius, .. }) => {
            line_circle(a.to, dir, centre, radius)
        }
        (OffsetPath::Arc { centre, radius, .. }, OffsetPath::Line { dir }) => {
            line_circle(b.to, dir, centre, radius)
        }
        (
            OffsetPath::Arc {
                centre: c1,
                radius: r1,
                ..
            },
            OffsetPath::Arc {
                centre: c2,
                radius: r2,
                ..
            },
        ) => circle_circle(c1, r1, c2, r2),
    }
}

/// The inside-corner point: the intersection of the offsets of `a` and `b`
/// lying on both parts that is nearest to the programmed corner `k`.
/// `None` means the tool does not fit (`KorrError`).
#[inline]
pub fn inside_point(a: &Part, b: &Part, k: V2) -> Option<V2> {
    let (p, q) = match carriers_meet(a, b) {
        Intersections::None => return None,
        Intersections::One(p) => (p, None),
        Intersections::Two(p, q) => (p, Some(q)),
    };
    let on_both = |x: V2| x.x.is_finite() && x.y.is_finite() && a.contains(x) && b.contains(x);
    let first = on_both(p).then_some(p);
    match q.filter(|&q| on_both(q)) {
        // On a tie the first point wins.
        Some(q) if first.is_none_or(|p| (q - k).norm() < (p - k).norm()) => Some(q),
        _ => first,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    fn line(dir: V2, from: Option<V2>, to: V2) -> Part {
        Part {
            path: OffsetPath::Line { dir },
            from,
            to,
            full: false,
        }
    }

    #[test]
    fn line_part_bounds() {
        let p = line(v(1.0, 0.0), Some(v(0.0, 0.0)), v(10.0, 0.0));
        assert!(p.contains(v(0.0, 0.0)) && p.contains(v(10.0, 0.0)));
        assert!(!p.contains(v(10.0 + 10.0 * ON_PART, 0.0)));
        assert!(!p.contains(v(-1.0, 0.0)));
        assert!(line(v(1.0, 0.0), None, v(10.0, 0.0)).contains(v(-100.0, 0.0)));
    }

    /// An arc part about the origin.
    fn arc(radius: f64, sigma: f64, from: V2, to: V2, full: bool) -> Part {
        Part {
            path: OffsetPath::Arc {
                centre: v(0.0, 0.0),
                radius,
                sigma,
            },
            from: Some(from),
            to,
            full,
        }
    }

    #[test]
    fn arc_part_bounds_follow_direction() {
        let ccw = arc(1.0, 1.0, v(1.0, 0.0), v(0.0, 1.0), false);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        assert!(ccw.contains(v(s, s)));
        assert!(!ccw.contains(v(-s, -s)));
        let cw = arc(1.0, -1.0, v(1.0, 0.0), v(0.0, 1.0), false);
        assert!(!cw.contains(v(s, s)));
        assert!(cw.contains(v(-s, -s)));
        assert!(Part { full: true, ..cw }.contains(v(s, s)));
    }

    #[test]
    fn inside_point_of_two_lines() {
        let a = line(v(1.0, 0.0), None, v(10.0, 2.0));
        let b = line(v(0.0, 1.0), Some(v(8.0, 0.0)), v(8.0, 10.0));
        assert_eq!(inside_point(&a, &b, v(10.0, 0.0)), Some(v(8.0, 2.0)));
        let short = Part {
            to: v(8.0, 1.0),
            ..b
        };
        assert_eq!(inside_point(&a, &short, v(10.0, 0.0)), None);
    }

    #[test]
    fn inside_point_nearest_the_corner() {
        // A line through a circle: two candidates, the one nearer K wins.
        let a = line(v(1.0, 0.0), None, v(0.0, 0.0));
        let b = arc(2.0, 1.0, v(2.0, 0.0), v(2.0, 0.0), true);
        assert_eq!(inside_point(&a, &b, v(3.0, 0.0)), Some(v(2.0, 0.0)));
        assert_eq!(inside_point(&a, &b, v(-3.0, 0.0)), Some(v(-2.0, 0.0)));
        // Equally near: the first intersection wins.
        assert_eq!(inside_point(&a, &b, v(0.0, 5.0)), Some(v(-2.0, 0.0)));
        // Only the second lies on the part.
        let half = Part {
            from: Some(v(0.0, -2.0)),
            to: v(0.0, 2.0),
            full: false,
            ..b
        };
        assert_eq!(inside_point(&a, &half, v(-3.0, 0.0)), Some(v(2.0, 0.0)));
    }
}
