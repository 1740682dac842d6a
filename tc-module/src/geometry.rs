//! Plane geometry of the tool radius correction (trc-geometry.md "Offset
//! geometry" and "Corner"): offsets of lines and arcs, corner
//! classification, transitions at outside corners and intersections at
//! inside corners. Pure functions on plane points `(h, v)`.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::Vector2;

/// A plane point or vector `(h, v)`.
pub type V2 = Vector2<f64>;

/// Tangent angle below which a corner is treated as smooth (LinuxCNC's
/// tolerance), and margin to π for a near-reversal.
pub const TANGENT_TOL: f64 = 0.05;

/// Start and end radius of an arc may differ by this much (rounding).
pub const CENTER_TOL: f64 = 0.002;

/// An offset radius at or below this is a `CalcError`.
pub const MIN_RADIUS: f64 = 1e-9;

/// Distance tolerance when testing whether a point lies on a part.
const ON_TOL: f64 = 1e-7;

/// Left normal of a unit tangent: `nL(t) = (-tv, th)`.
pub fn left_normal(t: V2) -> V2 {
    V2::new(-t.y, t.x)
}

/// 2-D cross product `a × b`.
pub fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// A programmed plane contour element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Contour {
    /// Straight line.
    Line {
        /// Start.
        from: V2,
        /// End.
        to: V2,
    },
    /// Arc about `centre`, `sigma` +1 CCW / -1 CW; `from == to` is a full circle.
    Arc {
        /// Start.
        from: V2,
        /// End.
        to: V2,
        /// Centre.
        centre: V2,
        /// Direction σ.
        sigma: f64,
    },
}

/// Why an element cannot be offset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OffsetError {
    /// The offset radius vanishes (or the arc itself has no radius).
    Calc,
    /// Start and end radius differ by more than [`CENTER_TOL`].
    Center,
}

/// The offset path of a contour element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OffsetPath {
    /// Offset line with unit direction `dir`.
    Line {
        /// Unit direction.
        dir: V2,
    },
    /// Offset circle.
    Arc {
        /// Centre.
        centre: V2,
        /// Offset radius `R - σ d`.
        radius: f64,
        /// Direction σ.
        sigma: f64,
    },
}

/// A contour element moved by `d` to the left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Offset {
    /// Line or circle.
    pub path: OffsetPath,
    /// Offset start point.
    pub start: V2,
    /// Offset end point.
    pub end: V2,
    /// Unit tangent at the start.
    pub t_start: V2,
    /// Unit tangent at the end.
    pub t_end: V2,
}

impl Contour {
    /// Whether the element has no extent in the plane (a pure third-axis move).
    pub fn is_plane_null(&self) -> bool {
        match *self {
            Contour::Line { from, to } => (to - from).norm() <= MIN_RADIUS,
            Contour::Arc { .. } => false,
        }
    }

    /// Offsets the element by `d` (positive: left of the direction of travel).
    pub fn offset(&self, d: f64) -> Result<Offset, OffsetError> {
        match *self {
            Contour::Line { from, to } => {
                let len = (to - from).norm();
                if len <= MIN_RADIUS || !len.is_finite() {
                    return Err(OffsetError::Calc);
                }
                let dir = (to - from) / len;
                let n = left_normal(dir) * d;
                Ok(Offset {
                    path: OffsetPath::Line { dir },
                    start: from + n,
                    end: to + n,
                    t_start: dir,
                    t_end: dir,
                })
            }
            Contour::Arc {
                from,
                to,
                centre,
                sigma,
            } => {
                let (rs, re) = ((from - centre).norm(), (to - centre).norm());
                if !(rs.is_finite() && re.is_finite()) || rs <= MIN_RADIUS {
                    return Err(OffsetError::Calc);
                }
                if (rs - re).abs() > CENTER_TOL {
                    return Err(OffsetError::Center);
                }
                if re <= MIN_RADIUS {
                    return Err(OffsetError::Calc);
                }
                let radius = rs - sigma * d;
                if radius <= MIN_RADIUS {
                    return Err(OffsetError::Calc);
                }
                let us = (from - centre) / rs;
                let ue = (to - centre) / re;
                Ok(Offset {
                    path: OffsetPath::Arc {
                        centre,
                        radius,
                        sigma,
                    },
                    start: centre + us * radius,
                    end: centre + ue * radius,
                    t_start: left_normal(us) * sigma,
                    t_end: left_normal(ue) * sigma,
                })
            }
        }
    }
}

/// What a corner needs (trc-geometry.md "Corner", cases 1-4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CornerKind {
    /// Case 1: nothing inserted, the next element continues from `pa`.
    Smooth,
    /// The tool goes around the corner: a transition is inserted.
    Outside,
    /// The offsets cross: both are cut at their intersection.
    Inside,
}

/// Turn angle θ in [0, π] between two unit tangents.
pub fn turn_angle(ta: V2, tb: V2) -> f64 {
    cross(ta, tb).abs().atan2(ta.dot(&tb))
}

/// Classifies the corner between element `a` (end tangent `ta`) and the
/// next `b` (start tangent `tb`) for offset `d`.
pub fn classify(ta: V2, tb: V2, d: f64, a: &OffsetPath, b: &OffsetPath) -> CornerKind {
    let theta = turn_angle(ta, tb);
    if d == 0.0 || theta <= TANGENT_TOL {
        return CornerKind::Smooth;
    }
    let s_eff = d.signum();
    let outside_arc =
        |p: &OffsetPath| matches!(*p, OffsetPath::Arc { sigma, .. } if s_eff * sigma < 0.0);
    if theta >= PI - TANGENT_TOL {
        let inside = match b {
            OffsetPath::Arc { .. } => outside_arc(b),
            OffsetPath::Line { .. } => outside_arc(a),
        };
        return if inside {
            CornerKind::Inside
        } else {
            CornerKind::Outside
        };
    }
    if s_eff * cross(ta, tb) < 0.0 {
        CornerKind::Outside
    } else {
        CornerKind::Inside
    }
}

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
    /// Up to three straight lines (TransitionMode 1): the first `count`
    /// points of `points` are the successive end points.
    Lines {
        /// End points.
        points: [V2; 3],
        /// How many are used (2 or 3).
        count: usize,
    },
}

/// The transition at an outside corner K from `pa` (tangent `ta`) to `pb`
/// (tangent `tb`).
pub fn transition(linear: bool, k: V2, pa: V2, pb: V2, ta: V2, tb: V2, d: f64) -> Transition {
    if !linear {
        return Transition::Arc {
            centre: k,
            ccw: d < 0.0,
            to: pb,
        };
    }
    let theta = turn_angle(ta, tb);
    if theta <= FRAC_PI_2 {
        // Intersection of pa + u ta and pb + w tb.
        let den = cross(ta, tb);
        if den.abs() > 1e-12 {
            let u = cross(pb - pa, tb) / den;
            let p = pa + ta * u;
            return Transition::Lines {
                points: [p, pb, pb],
                count: 2,
            };
        }
    }
    let r = d.abs();
    Transition::Lines {
        points: [pa + ta * r, pb - tb * r, pb],
        count: 3,
    }
}

/// Points of the line `p + u dir` (unit `dir`) and the circle `(c, r)`.
fn line_circle(p: V2, dir: V2, c: V2, r: f64) -> ([V2; 2], usize) {
    let f = p - c;
    let b = f.dot(&dir);
    let disc = b * b - (f.norm_squared() - r * r);
    if disc < 0.0 {
        return ([p; 2], 0);
    }
    let s = disc.sqrt();
    ([p + dir * (-b - s), p + dir * (-b + s)], 2)
}

fn circle_circle(c1: V2, r1: f64, c2: V2, r2: f64) -> ([V2; 2], usize) {
    let dvec = c2 - c1;
    let dist = dvec.norm();
    if dist <= 1e-12 || dist > r1 + r2 + ON_TOL || dist < (r1 - r2).abs() - ON_TOL {
        return ([c1; 2], 0);
    }
    let a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let m = c1 + dvec * (a / dist);
    let n = left_normal(dvec / dist) * h;
    ([m + n, m - n], 2)
}

/// The part of an offset element on which an inside-corner point may lie.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    /// Offset line or circle.
    pub path: OffsetPath,
    /// Where the part starts, or `None` for an unbounded start (an
    /// approach line).
    pub from: Option<V2>,
    /// Where it ends.
    pub to: V2,
    /// For an arc part whose `from` equals `to`: the whole circle.
    pub full: bool,
}

impl Part {
    fn contains(&self, x: V2) -> bool {
        match self.path {
            OffsetPath::Line { dir } => {
                let Some(from) = self.from else { return true };
                let len = (self.to - from).dot(&dir);
                let u = (x - from).dot(&dir);
                u >= -ON_TOL && u <= len + ON_TOL
            }
            OffsetPath::Arc { centre, sigma, .. } => {
                if self.full {
                    return true;
                }
                let Some(from) = self.from else { return true };
                let ang = |p: V2| (p.y - centre.y).atan2(p.x - centre.x);
                let sweep = (sigma * (ang(self.to) - ang(from))).rem_euclid(TAU);
                let at = (sigma * (ang(x) - ang(from))).rem_euclid(TAU);
                let tol = 1e-9;
                at <= sweep + tol || at >= TAU - tol
            }
        }
    }
}

/// The inside-corner point: the intersection of the offsets of `a` and `b`
/// lying on both parts that is nearest to the programmed corner `k`.
/// `None` means the tool does not fit (KorrError).
pub fn inside_point(a: &Part, b: &Part, k: V2) -> Option<V2> {
    // `to` is a point on each carrier line or circle.
    let (pa, path_a) = (a.to, a.path);
    let (pb_any, path_b) = (b.to, b.path);
    let (pts, n) = match (path_a, path_b) {
        (OffsetPath::Line { dir: da }, OffsetPath::Line { dir: db }) => {
            let den = cross(da, db);
            if den.abs() <= 1e-12 {
                ([pa; 2], 0)
            } else {
                let u = cross(pb_any - pa, db) / den;
                ([pa + da * u; 2], 1)
            }
        }
        (OffsetPath::Line { dir }, OffsetPath::Arc { centre, radius, .. }) => {
            line_circle(pa, dir, centre, radius)
        }
        (OffsetPath::Arc { centre, radius, .. }, OffsetPath::Line { dir }) => {
            line_circle(pb_any, dir, centre, radius)
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
    };
    pts[..n]
        .iter()
        .copied()
        .filter(|&x| x.x.is_finite() && x.y.is_finite() && a.contains(x) && b.contains(x))
        .min_by(|x, y| (x - k).norm().total_cmp(&(y - k).norm()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    #[test]
    fn line_offsets_left_and_right() {
        let l = Contour::Line {
            from: v(0.0, 0.0),
            to: v(10.0, 0.0),
        };
        let o = l.offset(2.0).unwrap();
        assert_eq!((o.start, o.end), (v(0.0, 2.0), v(10.0, 2.0)));
        let o = l.offset(-2.0).unwrap();
        assert_eq!((o.start, o.end), (v(0.0, -2.0), v(10.0, -2.0)));
    }

    #[test]
    fn arc_offset_radius_and_errors() {
        let ccw = Contour::Arc {
            from: v(5.0, 0.0),
            to: v(0.0, 5.0),
            centre: v(0.0, 0.0),
            sigma: 1.0,
        };
        let o = ccw.offset(1.0).unwrap(); // left of CCW = inside
        assert!((o.start - v(4.0, 0.0)).norm() < 1e-12);
        assert!((o.t_start - v(0.0, 1.0)).norm() < 1e-12);
        assert_eq!(ccw.offset(5.0), Err(OffsetError::Calc));
        let bad = Contour::Arc {
            from: v(5.0, 0.0),
            to: v(0.0, 5.01),
            centre: v(0.0, 0.0),
            sigma: 1.0,
        };
        assert_eq!(bad.offset(1.0), Err(OffsetError::Center));
    }

    #[test]
    fn corner_classes() {
        let line = OffsetPath::Line { dir: v(1.0, 0.0) };
        // left side, left turn: inside; right turn: outside
        assert_eq!(
            classify(v(1.0, 0.0), v(0.0, 1.0), 2.0, &line, &line),
            CornerKind::Inside
        );
        assert_eq!(
            classify(v(1.0, 0.0), v(0.0, -1.0), 2.0, &line, &line),
            CornerKind::Outside
        );
        assert_eq!(
            classify(v(1.0, 0.0), v(0.0, -1.0), -2.0, &line, &line),
            CornerKind::Inside
        );
        assert_eq!(
            classify(v(1.0, 0.0), v(1.0, 0.01), 2.0, &line, &line),
            CornerKind::Smooth
        );
        assert_eq!(
            classify(v(1.0, 0.0), v(0.0, 1.0), 0.0, &line, &line),
            CornerKind::Smooth
        );
        assert_eq!(
            classify(v(1.0, 0.0), v(-1.0, 0.0), 2.0, &line, &line),
            CornerKind::Outside
        );
    }

    #[test]
    fn linear_transitions() {
        let t = transition(
            true,
            v(10.0, 0.0),
            v(10.0, 2.0),
            v(12.0, 0.0),
            v(1.0, 0.0),
            v(0.0, -1.0),
            2.0,
        );
        assert_eq!(
            t,
            Transition::Lines {
                points: [v(12.0, 2.0), v(12.0, 0.0), v(12.0, 0.0)],
                count: 2
            }
        );
        // 135° turn: three lines
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
        match t {
            Transition::Lines { points, count: 3 } => {
                assert!((points[0] - v(1.0, 1.0)).norm() < 1e-12);
                assert!((points[1] - v(2.0 * s, 2.0 * s)).norm() < 1e-12);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn inside_point_of_two_lines() {
        let a = Part {
            path: OffsetPath::Line { dir: v(1.0, 0.0) },
            from: None,
            to: v(10.0, 2.0),
            full: false,
        };
        let b = Part {
            path: OffsetPath::Line { dir: v(0.0, 1.0) },
            from: Some(v(8.0, 0.0)),
            to: v(8.0, 10.0),
            full: false,
        };
        assert_eq!(inside_point(&a, &b, v(10.0, 0.0)), Some(v(8.0, 2.0)));
        let short = Part {
            to: v(8.0, 1.0),
            ..b
        };
        assert_eq!(inside_point(&a, &short, v(10.0, 0.0)), None);
    }
}
