//! Offsets of lines and arcs: a line moved by `d` along its left normal,
//! an arc's radius changed by `σ d` (docs/trc.md; decisions 15 and 22 for
//! the elements that cannot be offset).

use super::tolerance::{CENTER_TOL, MIN_RADIUS, PLANE_NULL};
use super::vector::{left_normal, V2};

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
    /// The offset radius vanishes (or the arc itself has no radius):
    /// `CalcError`.
    Calc,
    /// Start and end radius differ by more than [`CENTER_TOL`]:
    /// `CenterError`.
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
    /// The offset `d` (side × radius) it was made with.
    pub d: f64,
}

impl Contour {
    /// Start and end point.
    pub fn ends(&self) -> (V2, V2) {
        match *self {
            Contour::Line { from, to } | Contour::Arc { from, to, .. } => (from, to),
        }
    }

    /// Whether the element has no extent in the plane (a pure third-axis move).
    pub fn is_plane_null(&self) -> bool {
        match *self {
            Contour::Line { from, to } => (to - from).norm() <= PLANE_NULL,
            Contour::Arc { .. } => false,
        }
    }

    /// Whether it is a programmed full circle (start = end).
    pub fn is_full_circle(&self) -> bool {
        matches!(*self, Contour::Arc { from, to, .. } if from == to)
    }

    /// Offsets the element by `d` (positive: left of the direction of travel).
    #[inline]
    pub fn offset(&self, d: f64) -> Result<Offset, OffsetError> {
        match *self {
            Contour::Line { from, to } => offset_line(from, to, d),
            Contour::Arc {
                from,
                to,
                centre,
                sigma,
            } => offset_arc(from, to, centre, sigma, d),
        }
    }
}

#[inline]
fn offset_line(from: V2, to: V2, d: f64) -> Result<Offset, OffsetError> {
    let len = (to - from).norm();
    if len <= PLANE_NULL || !len.is_finite() {
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
        d,
    })
}

#[inline]
fn offset_arc(from: V2, to: V2, centre: V2, sigma: f64, d: f64) -> Result<Offset, OffsetError> {
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
        d,
    })
}

impl Offset {
    /// The unit vector from the programmed contour to the tool centre at
    /// the offset point `p` (docs/otc.md "Processing types and their
    /// directions", RADIUS' n; decision 43): the side normal of a line,
    /// radial for an arc (outward when the tool runs outside it).
    pub fn normal_at(&self, p: V2) -> V2 {
        match self.path {
            OffsetPath::Line { dir } => left_normal(dir) * self.d.signum(),
            OffsetPath::Arc { centre, sigma, .. } => {
                let u = (p - centre).normalize();
                if self.tool_outside_arc(sigma) {
                    u
                } else {
                    -u
                }
            }
        }
    }

    /// Whether the tool runs outside an arc of direction `sigma`:
    /// `s_eff * σ < 0`, `s_eff` the sign of d ("Corner", case 2).
    pub fn tool_outside_arc(&self, sigma: f64) -> bool {
        self.d.signum() * sigma < 0.0
    }
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
        assert_eq!(o.normal_at(o.end), v(0.0, 1.0));
        let o = l.offset(-2.0).unwrap();
        assert_eq!((o.start, o.end), (v(0.0, -2.0), v(10.0, -2.0)));
        assert_eq!(o.normal_at(o.end), v(0.0, -1.0));
        let dot = Contour::Line {
            from: v(1.0, 1.0),
            to: v(1.0, 1.0 + 1e-10),
        };
        assert!(dot.is_plane_null());
        assert_eq!(dot.offset(1.0), Err(OffsetError::Calc));
    }

    #[test]
    fn arc_offset_radius_normal_and_errors() {
        let ccw = Contour::Arc {
            from: v(5.0, 0.0),
            to: v(0.0, 5.0),
            centre: v(0.0, 0.0),
            sigma: 1.0,
        };
        let o = ccw.offset(1.0).unwrap(); // left of CCW = inside
        assert!((o.start - v(4.0, 0.0)).norm() < 1e-12);
        assert!((o.t_start - v(0.0, 1.0)).norm() < 1e-12);
        assert!((o.normal_at(o.start) - v(-1.0, 0.0)).norm() < 1e-12);
        let outside = ccw.offset(-1.0).unwrap();
        assert!((outside.normal_at(outside.end) - v(0.0, 1.0)).norm() < 1e-12);
        assert_eq!(ccw.offset(5.0), Err(OffsetError::Calc));
        let bad = Contour::Arc {
            from: v(5.0, 0.0),
            to: v(0.0, 5.01),
            centre: v(0.0, 0.0),
            sigma: 1.0,
        };
        assert_eq!(bad.offset(1.0), Err(OffsetError::Center));
        let within = Contour::Arc {
            from: v(5.0, 0.0),
            to: v(0.0, 5.0015),
            centre: v(0.0, 0.0),
            sigma: 1.0,
        };
        assert!(within.offset(1.0).is_ok());
    }
}
