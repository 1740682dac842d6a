//! Plane geometry of the ISG selection modes (docs/nc.md, "Selection and
//! deselection"): the programmed elements of the main plane as lines and
//! arcs, their tangents and offset points, the centre of an arc given by
//! its radius, and the cut of two offset geometries. The correction itself
//! (corners, transitions, gouging) stays the controller's; this is only
//! what the interpreter must know to place the elements the selection
//! modes insert.

use std::f64::consts::PI;

/// A point or vector of the main plane `(h, v)`.
pub(super) type P2 = [f64; 2];

/// Chord tolerance of an arc given by its radius: a radius up to this much
/// below half the chord is taken as half the chord (a half circle).
pub(super) const RADIUS_SLACK: f64 = 1e-9;

/// How far the last contour element of a `G238` contour may end from the
/// selection point P2 (units).
pub(super) const CLOSURE_TOL: f64 = 1e-6;

/// Angle tolerance of the corner cases (rad), as the correction's case 1
/// and 2 (docs/trc.md, "Corner").
const CORNER_TOL: f64 = 0.05;

/// The two main-plane axes `(h, v)` of plane code 17, 18 or 19 (docs/trc.md,
/// "Coordinates"); any other code is the module's default X-Y.
pub(super) fn plane_axes(plane: Option<i32>) -> (usize, usize) {
    match plane {
        Some(18) => (2, 0),
        Some(19) => (1, 2),
        _ => (0, 1),
    }
}

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: P2, b: P2) -> P2 {
    [a[0] + b[0], a[1] + b[1]]
}

fn scale(a: P2, k: f64) -> P2 {
    [a[0] * k, a[1] * k]
}

fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Length of a vector.
pub(super) fn norm(a: P2) -> f64 {
    a[0].hypot(a[1])
}

/// Distance of two points.
pub(super) fn dist(a: P2, b: P2) -> f64 {
    norm(sub(a, b))
}

fn unit(a: P2) -> P2 {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0, 0.0]
    }
}

/// Left normal `nL(t) = (-tv, th)`.
pub(super) fn left_normal(t: P2) -> P2 {
    [-t[1], t[0]]
}

/// A programmed element of the main plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Seg {
    /// A line from `s` to `e`.
    Line { s: P2, e: P2 },
    /// An arc from `s` to `e` about `c`, counter-clockwise when `ccw`.
    Arc { s: P2, e: P2, c: P2, ccw: bool },
}

impl Seg {
    /// Its programmed start.
    pub(super) fn start(&self) -> P2 {
        match *self {
            Seg::Line { s, .. } | Seg::Arc { s, .. } => s,
        }
    }

    /// Its programmed end.
    pub(super) fn end(&self) -> P2 {
        match *self {
            Seg::Line { e, .. } | Seg::Arc { e, .. } => e,
        }
    }

    /// Whether it moves in the plane at all.
    pub(super) fn has_length(&self) -> bool {
        match *self {
            Seg::Line { s, e } => dist(s, e) > 0.0,
            Seg::Arc { .. } => true,
        }
    }

    /// Unit tangent at point `p` of the element (`p` on an arc: the
    /// tangent of the circle there).
    fn tangent_at(&self, p: P2) -> P2 {
        match *self {
            Seg::Line { s, e } => unit(sub(e, s)),
            Seg::Arc { c, ccw, .. } => {
                let t = left_normal(unit(sub(p, c)));
                if ccw {
                    t
                } else {
                    scale(t, -1.0)
                }
            }
        }
    }

    /// Unit tangent at the start.
    pub(super) fn start_tangent(&self) -> P2 {
        self.tangent_at(self.start())
    }

    /// Unit tangent at the end.
    pub(super) fn end_tangent(&self) -> P2 {
        self.tangent_at(self.end())
    }

    /// Offset start `S + d nL(t)` for the signed offset `d`.
    #[cfg(test)]
    pub(super) fn offset_start(&self, d: f64) -> P2 {
        add(self.start(), scale(left_normal(self.start_tangent()), d))
    }

    /// Offset end `E + d nL(t)` for the signed offset `d`.
    pub(super) fn offset_end(&self, d: f64) -> P2 {
        add(self.end(), scale(left_normal(self.end_tangent()), d))
    }

    /// A full circle (start = end).
    pub(super) fn is_full_circle(&self) -> bool {
        matches!(self, Seg::Arc { s, e, .. } if dist(*s, *e) <= 1e-9)
    }

    /// The offset geometry for the signed offset `d`: the offset line or
    /// circle, whole.
    fn offset_geometry(&self, d: f64) -> Geometry {
        match *self {
            Seg::Line { s, e } => {
                let t = unit(sub(e, s));
                Geometry::Line {
                    p: add(s, scale(left_normal(t), d)),
                    t,
                }
            }
            Seg::Arc { s, c, ccw, .. } => {
                let sigma = if ccw { 1.0 } else { -1.0 };
                Geometry::Circle {
                    c,
                    r: dist(s, c) - sigma * d,
                }
            }
        }
    }

    /// Angle (rad, in the arc's direction, from its start) of the point
    /// `p` seen from the centre; 0 for a line.
    fn sweep_to(&self, p: P2) -> f64 {
        let Seg::Arc { s, c, ccw, .. } = *self else {
            return 0.0;
        };
        let a = sub(s, c);
        let b = sub(p, c);
        let mut ang = cross(a, b).atan2(dot(a, b));
        if !ccw {
            ang = -ang;
        }
        if ang < 0.0 {
            ang += 2.0 * PI;
        }
        ang
    }

    /// The whole sweep of an arc (2π for a full circle).
    fn sweep(&self) -> f64 {
        if self.is_full_circle() {
            2.0 * PI
        } else {
            self.sweep_to(self.end())
        }
    }

    /// Distance of point `p` from the element.
    pub(super) fn distance_to(&self, p: P2) -> f64 {
        match *self {
            Seg::Line { s, e } => {
                let v = sub(e, s);
                let l2 = dot(v, v);
                let k = if l2 > 0.0 {
                    (dot(sub(p, s), v) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                dist(p, add(s, scale(v, k)))
            }
            Seg::Arc { s, e, c, .. } => {
                if dist(p, c) > 0.0 && self.sweep_to(p) <= self.sweep() {
                    (dist(p, c) - dist(s, c)).abs()
                } else {
                    dist(p, s).min(dist(p, e))
                }
            }
        }
    }

    /// The points where the line from `a` to `b` meets the element.
    pub(super) fn meets_line(&self, a: P2, b: P2) -> Vec<P2> {
        let chord = Seg::Line { s: a, e: b };
        let on_chord = |p: &P2| chord.distance_to(*p) <= 1e-9;
        match *self {
            Seg::Line { s, e } => {
                let (r, q) = (sub(b, a), sub(e, s));
                let den = cross(r, q);
                if den.abs() <= 1e-12 {
                    // Parallel: they meet where an end lies on the other.
                    return [s, e, a, b]
                        .into_iter()
                        .filter(|p| on_chord(p) && self.distance_to(*p) <= 1e-9)
                        .collect();
                }
                let k = cross(sub(s, a), q) / den;
                let p = add(a, scale(r, k));
                vec![p]
                    .into_iter()
                    .filter(|p| on_chord(p) && self.distance_to(*p) <= 1e-9)
                    .collect()
            }
            Seg::Arc { s, c, .. } => {
                let circle = Geometry::Circle { c, r: dist(s, c) };
                let line = Geometry::Line {
                    p: a,
                    t: unit(sub(b, a)),
                };
                line.cut(&circle)
                    .into_iter()
                    .filter(|p| on_chord(p) && self.distance_to(*p) <= 1e-9)
                    .collect()
            }
        }
    }
}

/// A whole offset geometry: a line through `p` along the unit `t`, or a
/// circle.
#[derive(Debug, Clone, Copy)]
enum Geometry {
    Line { p: P2, t: P2 },
    Circle { c: P2, r: f64 },
}

impl Geometry {
    /// Their intersections (none for parallel lines or circles apart).
    fn cut(&self, other: &Geometry) -> Vec<P2> {
        match (*self, *other) {
            (Geometry::Line { p, t }, Geometry::Line { p: q, t: u }) => {
                let den = cross(t, u);
                if den.abs() <= 1e-12 {
                    return Vec::new();
                }
                vec![add(p, scale(t, cross(sub(q, p), u) / den))]
            }
            (Geometry::Line { p, t }, Geometry::Circle { c, r })
            | (Geometry::Circle { c, r }, Geometry::Line { p, t }) => {
                let foot = add(p, scale(t, dot(sub(c, p), t)));
                let h2 = r * r - dist(foot, c).powi(2);
                if h2 < -1e-12 {
                    return Vec::new();
                }
                let h = h2.max(0.0).sqrt();
                vec![add(foot, scale(t, -h)), add(foot, scale(t, h))]
            }
            (Geometry::Circle { c, r }, Geometry::Circle { c: k, r: q }) => {
                let l = dist(c, k);
                if l <= 1e-12 {
                    return Vec::new();
                }
                let a = (r * r - q * q + l * l) / (2.0 * l);
                let h2 = r * r - a * a;
                if h2 < -1e-12 {
                    return Vec::new();
                }
                let u = unit(sub(k, c));
                let m = add(c, scale(u, a));
                let h = h2.max(0.0).sqrt();
                let n = left_normal(u);
                vec![add(m, scale(n, h)), add(m, scale(n, -h))]
            }
        }
    }
}

/// The cut point of a `G238` contour: the intersection of the whole
/// offset geometries of the last element `last` and the first `first`
/// nearest their common point `k`, for the signed offset `d`.
pub(super) fn cut_point(last: &Seg, first: &Seg, d: f64, k: P2) -> Option<P2> {
    let a = last.offset_geometry(d);
    let b = first.offset_geometry(d);
    a.cut(&b)
        .into_iter()
        .min_by(|p, q| dist(*p, k).total_cmp(&dist(*q, k)))
}

/// Whether the corner from `a` into `b` is an inside corner for the signed
/// offset `d` (docs/trc.md, "Corner": cases 2 and 4) on side `side` (+1
/// left, -1 right; what counts when the radius is 0).
pub(super) fn is_inside_corner(a: &Seg, b: &Seg, d: f64, side: f64) -> bool {
    let (ta, tb) = (a.end_tangent(), b.start_tangent());
    let c = cross(ta, tb);
    let theta = c.abs().atan2(dot(ta, tb));
    if theta <= CORNER_TOL {
        return false;
    }
    let s_eff = if d == 0.0 { side } else { d.signum() };
    let outside_of = |seg: &Seg| match seg {
        Seg::Arc { ccw, .. } => s_eff * if *ccw { 1.0 } else { -1.0 } < 0.0,
        Seg::Line { .. } => false,
    };
    if theta >= PI - CORNER_TOL {
        return match b {
            Seg::Arc { .. } => outside_of(b),
            Seg::Line { .. } => matches!(a, Seg::Arc { .. }) && outside_of(a),
        };
    }
    s_eff * c >= 0.0
}

/// Why an arc given by its radius has no centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum RadiusArc {
    /// Start and end are the same point (a full circle needs I J K).
    FullCircle,
    /// The radius is shorter than half the chord.
    TooShort {
        /// Half the chord, the smallest radius.
        half_chord: f64,
    },
}

/// The centre of the arc from `s` to `e` with radius `r` (negative: more
/// than 180°), counter-clockwise when `ccw` (docs/nc.md, "Arcs by radius").
pub(super) fn centre_from_radius(s: P2, e: P2, r: f64, ccw: bool) -> Result<P2, RadiusArc> {
    let chord = dist(s, e);
    if chord <= 0.0 {
        return Err(RadiusArc::FullCircle);
    }
    let half = chord / 2.0;
    if r.abs() < half - RADIUS_SLACK {
        return Err(RadiusArc::TooShort { half_chord: half });
    }
    let h = (r * r - half * half).max(0.0).sqrt();
    let mid = scale(add(s, e), 0.5);
    let n = left_normal(unit(sub(e, s)));
    // Left of the chord for G3 with r > 0, right for G2; the other side
    // for r < 0.
    let left = ccw == (r > 0.0);
    Ok(add(mid, scale(n, if left { h } else { -h })))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn close(a: P2, b: P2) -> bool {
        dist(a, b) < 1e-9
    }

    #[test]
    fn radius_centre_left_for_g3_and_right_for_g2() {
        let (s, e) = ([0.0, 0.0], [10.0, 0.0]);
        let g3 = centre_from_radius(s, e, 5.0, true).unwrap();
        assert!(close(g3, [5.0, 0.0]));
        let g3 = centre_from_radius(s, e, 13.0, true).unwrap();
        assert!(close(g3, [5.0, 12.0]));
        let g2 = centre_from_radius(s, e, 13.0, false).unwrap();
        assert!(close(g2, [5.0, -12.0]));
        let g3_big = centre_from_radius(s, e, -13.0, true).unwrap();
        assert!(close(g3_big, [5.0, -12.0]));
    }

    #[test]
    fn radius_shorter_than_half_chord_is_refused_within_slack_taken() {
        let (s, e) = ([0.0, 0.0], [10.0, 0.0]);
        assert_eq!(
            centre_from_radius(s, e, 4.9, true),
            Err(RadiusArc::TooShort { half_chord: 5.0 })
        );
        let c = centre_from_radius(s, e, 5.0 - 1e-10, true).unwrap();
        assert!(close(c, [5.0, 0.0]));
        assert_eq!(
            centre_from_radius(s, s, 5.0, true),
            Err(RadiusArc::FullCircle)
        );
    }

    #[test]
    fn offset_points_of_an_arc_lie_on_the_offset_circle() {
        let arc = Seg::Arc {
            s: [10.0, 10.0],
            e: [60.0, 60.0],
            c: [10.0, 60.0],
            ccw: true,
        };
        assert!(close(arc.offset_start(-5.0), [10.0, 5.0]));
        assert!(close(arc.offset_end(-5.0), [65.0, 60.0]));
    }

    #[test]
    fn star_corner_is_inside_and_cut_on_both_offset_lines() {
        let last = Seg::Line {
            s: [20.0, 20.0],
            e: [0.0, 100.0],
        };
        let first = Seg::Line {
            s: [0.0, 100.0],
            e: [-20.0, 20.0],
        };
        assert!(is_inside_corner(&last, &first, 10.0, 1.0));
        assert!(!is_inside_corner(&last, &first, -10.0, -1.0));
        assert!(is_inside_corner(&last, &first, 0.0, 1.0));
        let c = cut_point(&last, &first, 10.0, [0.0, 100.0]).unwrap();
        // On the axis of symmetry, below the tip.
        assert!(c[0].abs() < 1e-9 && c[1] < 100.0);
        assert!((last.distance_to(c) - 10.0).abs() < 1e-9);
        assert!((first.distance_to(c) - 10.0).abs() < 1e-9);
    }

    #[test]
    fn line_meets_arc_only_within_its_sweep() {
        let arc = Seg::Arc {
            s: [10.0, 0.0],
            e: [0.0, 10.0],
            c: [0.0, 0.0],
            ccw: true,
        };
        assert_eq!(arc.meets_line([-20.0, -5.0], [20.0, -5.0]).len(), 0);
        assert_eq!(arc.meets_line([0.0, 0.0], [20.0, 20.0]).len(), 1);
    }
}
