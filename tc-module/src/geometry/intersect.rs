//! Intersections of the carriers of offset elements: lines and circles.
//! Typed results, one function per pair of primitives.

use super::tolerance::{ON_PART, PARALLEL};
use super::vector::{cross, left_normal, V2};

/// Points where two carriers meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Intersections {
    /// They do not meet (parallel lines, circles apart, a line passing by).
    None,
    /// They meet once (crossing lines).
    One(V2),
    /// They meet twice (a line or circle touching a circle gives the
    /// touching point twice).
    Two(V2, V2),
}

#[cfg(test)]
impl Intersections {
    /// The points, in order.
    pub fn points(self) -> impl Iterator<Item = V2> {
        let (a, b) = match self {
            Intersections::None => (None, None),
            Intersections::One(p) => (Some(p), None),
            Intersections::Two(p, q) => (Some(p), Some(q)),
        };
        a.into_iter().chain(b)
    }
}

/// The point where the line through `p` along `dp` meets the line through
/// `q` along `dq` (unit directions); `None` when they are parallel.
pub fn line_line(p: V2, dp: V2, q: V2, dq: V2) -> Option<V2> {
    let den = cross(dp, dq);
    if den.abs() <= PARALLEL {
        return None;
    }
    Some(p + dp * (cross(q - p, dq) / den))
}

/// The points of the line `p + u dir` (unit `dir`) on the circle `(c, r)`.
pub fn line_circle(p: V2, dir: V2, c: V2, r: f64) -> Intersections {
    let f = p - c;
    let b = f.dot(&dir);
    let disc = b * b - (f.norm_squared() - r * r);
    if disc < 0.0 {
        return Intersections::None;
    }
    let s = disc.sqrt();
    Intersections::Two(p + dir * (-b - s), p + dir * (-b + s))
}

/// The points of two circles; circles that miss each other by at most
/// [`ON_PART`] still touch.
pub fn circle_circle(c1: V2, r1: f64, c2: V2, r2: f64) -> Intersections {
    let dvec = c2 - c1;
    let dist = dvec.norm();
    if dist <= PARALLEL || dist > r1 + r2 + ON_PART || dist < (r1 - r2).abs() - ON_PART {
        return Intersections::None;
    }
    let a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let m = c1 + dvec * (a / dist);
    let n = left_normal(dvec / dist) * h;
    Intersections::Two(m + n, m - n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    fn near(a: V2, b: V2) -> bool {
        (a - b).norm() < 1e-12
    }

    #[test]
    fn lines_cross_or_are_parallel() {
        let x = line_line(v(0.0, 2.0), v(1.0, 0.0), v(8.0, 0.0), v(0.0, 1.0));
        assert_eq!(x, Some(v(8.0, 2.0)));
        assert_eq!(
            line_line(v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0), v(-1.0, 0.0)),
            None
        );
    }

    #[test]
    fn line_meets_circle_twice_or_not() {
        let pts: Vec<V2> = line_circle(v(-5.0, 0.0), v(1.0, 0.0), v(0.0, 0.0), 2.0)
            .points()
            .collect();
        assert!(near(pts[0], v(-2.0, 0.0)) && near(pts[1], v(2.0, 0.0)));
        assert_eq!(
            line_circle(v(-5.0, 3.0), v(1.0, 0.0), v(0.0, 0.0), 2.0),
            Intersections::None
        );
    }

    #[test]
    fn circles_meet_touch_or_miss() {
        let pts: Vec<V2> = circle_circle(v(0.0, 0.0), 5.0, v(8.0, 0.0), 5.0)
            .points()
            .collect();
        assert!(near(pts[0], v(4.0, 3.0)) && near(pts[1], v(4.0, -3.0)));
        // Apart by less than ON_PART: they touch.
        let touch = circle_circle(v(0.0, 0.0), 1.0, v(2.0 + 0.5 * ON_PART, 0.0), 1.0);
        assert!(touch.points().all(|p| (p - v(1.0, 0.0)).norm() < 1e-3));
        assert_eq!(
            circle_circle(v(0.0, 0.0), 1.0, v(3.0, 0.0), 1.0),
            Intersections::None
        );
        assert_eq!(
            circle_circle(v(0.0, 0.0), 1.0, v(0.0, 0.0), 1.0),
            Intersections::None
        );
    }
}
