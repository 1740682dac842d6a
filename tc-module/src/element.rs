//! A spooled element: its end in its plane, the plane geometry of an arc
//! with what the executor needs derived once (start direction, sweep,
//! radii, path length), feed, origin tag and the contour normal a wear
//! model needs (decisions 24, 26, 42 and 43; docs/otc.md "Processing
//! types and their directions").
//!
//! An element keeps neither its start nor its end on every axis: the
//! spooler is a chain, each element starting where the one before it
//! ended (or, the first, where the executor stands), and the axes outside
//! its plane end where they start unless the element moves them; only
//! then does the spooler keep its whole end. Whoever runs or reports an
//! element hands its start and end in.

use std::f64::consts::TAU;

use crate::geometry::tolerance::ZERO_SWEEP;
use crate::geometry::V2;
use crate::plane::{AxisPos, PlaneAxes, AXES};
pub use tc_request::Origin;
use tc_request::{ArcRecord, SpoolRecord};

/// The arc of an element as it is reported: plane, centre, direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPath {
    /// The plane axes.
    pub plane: PlaneAxes,
    /// Centre `(h, v)`.
    pub centre: V2,
    /// Counter-clockwise?
    pub ccw: bool,
}

/// Path of an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path {
    /// Straight line from start to end in all axes.
    Line,
    /// Arc in a plane, helical where other axes move.
    Arc(ArcPath),
}

/// How the unit vector from the programmed contour to the tool centre is
/// found along an element the correction spooled (decision 43; docs/otc.md
/// "Processing types and their directions", RADIUS' n).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalRule {
    /// One vector all along: the side normal of a corrected line, and the
    /// normal an approach leads onto or a departure leaves.
    Fixed(V2),
    /// Radial about the arc centre: outward when the tool runs outside the
    /// programmed arc, inward when inside.
    Radial {
        /// The arc centre.
        centre: V2,
        /// Whether the tool centre lies outside the programmed arc.
        outward: bool,
    },
    /// From the programmed corner K to the tool centre (a transition).
    FromCorner(V2),
}

/// The contour normal of an element, in its group's plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContourNormal {
    /// The group's plane axes.
    pub plane: PlaneAxes,
    /// How the normal is found.
    pub rule: NormalRule,
}

/// The kind of contour normal an element carries, its vector (or point)
/// kept beside it in the element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NormalKind {
    None,
    Fixed,
    Outward,
    Inward,
    FromCorner,
}

/// The plane geometry of an arc element and what the executor needs of
/// it, derived once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ArcGeometry {
    /// Centre `(h, v)`.
    centre: V2,
    /// Unit vector from the centre to the start point.
    start_dir: V2,
    /// Signed sweep (positive CCW); a full circle sweeps ±2π.
    sweep: f64,
    /// Radius at the start.
    r0: f64,
    /// Radius at the end (equal to `r0` up to rounding).
    r1: f64,
}

impl ArcGeometry {
    /// The arc from `from` to `to` about `centre` in the direction given
    /// (start = end is a whole turn), and its length in the plane.
    #[inline]
    pub(crate) fn of(from: V2, to: V2, centre: V2, ccw: bool) -> (Self, f64) {
        let (s, e) = (from - centre, to - centre);
        let sweep = sweep_of(s, e, ccw);
        // Coordinates stay within ±1e9: the squares cannot overflow, and a
        // square root is several times cheaper than `hypot`.
        let (r0, r1) = (s.norm(), e.norm());
        // On the centre, the start direction is that of angle 0.
        let start_dir = if r0 > 0.0 { s / r0 } else { V2::x() };
        let plane_len = sweep.abs() * 0.5 * (r0 + r1);
        let arc = Self {
            centre,
            start_dir,
            sweep,
            r0,
            r1,
        };
        (arc, plane_len)
    }

    /// The unit vector from the centre at fraction `f` of the sweep, the
    /// start direction turned by `sweep · f`.
    fn dir_at(&self, f: f64) -> V2 {
        let (sin, cos) = (self.sweep * f).sin_cos();
        let (c0, s0) = (self.start_dir.x, self.start_dir.y);
        V2::new(c0 * cos - s0 * sin, s0 * cos + c0 * sin)
    }

    /// The tangent in the plane, per unit of a path `length` long, where
    /// the direction from the centre is `(cos, sin)` at radius `r`: along
    /// the circle (r dθ/ds) plus the radius' own drift (dr/ds).
    fn tangent(&self, cos: f64, sin: f64, r: f64, length: f64) -> V2 {
        let k = self.sweep * r / length;
        let dr = (self.r1 - self.r0) / length;
        V2::new(-k * sin + dr * cos, k * cos + dr * sin)
    }
}

/// One element of the spooler (see the module documentation: its start
/// is the end of the element before it, and its end outside its plane is
/// its start there unless it moves those axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpoolElement {
    /// The end in the plane `(h, v)`.
    to: V2,
    /// Path length (arc length, helical where other axes move).
    length: f64,
    /// Feed, units/min.
    feed: f64,
    /// The arc, or `None` for a line.
    arc: Option<ArcGeometry>,
    /// The normal's vector, corner or centre (see [`NormalKind`]).
    normal_at: V2,
    /// The plane of `to` (an arc's plane).
    plane: PlaneAxes,
    /// The normal's plane.
    normal_plane: PlaneAxes,
    normal: NormalKind,
    /// Whether an axis outside the plane moves: then the spooler keeps
    /// the end of every axis.
    moves_off_plane: bool,
    rapid: bool,
    origin: Origin,
}

/// Whether `end` differs from `start` on an axis outside `plane`, to the
/// bit (a −0 that was 0 is kept too).
#[inline]
fn moves_off_plane(start: &AxisPos, end: &AxisPos, plane: PlaneAxes) -> bool {
    // The end with the start's plane coordinates, compared to the bit.
    let mut e = *end;
    e[usize::from(plane.h)] = start[usize::from(plane.h)];
    e[usize::from(plane.v)] = start[usize::from(plane.v)];
    (0..AXES).fold(0, |acc, i| acc | (e[i].to_bits() ^ start[i].to_bits())) != 0
}

/// `Σ (end − start)²` over the axes outside `plane`: zero where none moves.
/// Straight-line code: the plane's axes add an exact zero.
#[inline]
fn off_plane_squared(start: &AxisPos, end: &AxisPos, plane: PlaneAxes) -> f64 {
    let (h, v) = (usize::from(plane.h), usize::from(plane.v));
    let mut sum = 0.0;
    for i in 0..AXES {
        let d = if i == h || i == v {
            0.0
        } else {
            end[i] - start[i]
        };
        sum += d * d;
    }
    sum
}

fn line_length(start: &AxisPos, end: &AxisPos) -> f64 {
    start
        .iter()
        .zip(end)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

/// The signed sweep from `s` to `e` (vectors from the centre) in the
/// direction given; start = end is a whole turn.
fn sweep_of(s: V2, e: V2, ccw: bool) -> f64 {
    let sweep = (s.x * e.y - s.y * e.x).atan2(s.x * e.x + s.y * e.y); // (-π, π]
    if ccw {
        if sweep <= ZERO_SWEEP {
            return sweep + TAU;
        }
    } else if sweep >= -ZERO_SWEEP {
        return sweep - TAU;
    }
    sweep
}

impl SpoolElement {
    /// An element to `end` of `length` from `start`, plane point in
    /// `plane`, without arc geometry or normal.
    #[inline]
    fn bare(start: &AxisPos, end: &AxisPos, plane: PlaneAxes, length: f64) -> Self {
        Self {
            to: plane.point(end),
            length,
            feed: 0.0,
            arc: None,
            normal_at: V2::zeros(),
            plane,
            normal_plane: plane,
            normal: NormalKind::None,
            moves_off_plane: moves_off_plane(start, end, plane),
            rapid: false,
            origin: Origin::Uncorrected,
        }
    }

    /// An element in `plane` to `to`, `length` long, that moves no other
    /// axis (the sink knows as much without comparing them).
    #[inline]
    pub(crate) fn in_plane(
        plane: PlaneAxes,
        to: V2,
        length: f64,
        arc: Option<ArcGeometry>,
    ) -> Self {
        Self {
            to,
            length,
            feed: 0.0,
            arc,
            normal_at: V2::zeros(),
            plane,
            normal_plane: plane,
            normal: NormalKind::None,
            moves_off_plane: false,
            rapid: false,
            origin: Origin::Uncorrected,
        }
    }

    /// The same element with its feed, rapid flag and origin.
    #[inline]
    pub(crate) fn moving(self, feed: f64, rapid: bool, origin: Origin) -> Self {
        Self {
            feed,
            rapid,
            origin,
            ..self
        }
    }

    /// A straight element from `start` to `end`; `plane` names the two
    /// axes the element keeps the end of (any other axis that moves makes
    /// the spooler keep its whole end).
    #[inline]
    pub fn line(
        start: &AxisPos,
        end: &AxisPos,
        plane: PlaneAxes,
        feed: f64,
        rapid: bool,
        origin: Origin,
    ) -> Self {
        Self {
            feed,
            rapid,
            origin,
            ..Self::bare(start, end, plane, line_length(start, end))
        }
    }

    /// An arc element from `start` to `end` about `centre` in `plane`;
    /// start = end in the plane is a full circle.
    #[inline]
    pub fn arc(
        start: &AxisPos,
        end: &AxisPos,
        plane: PlaneAxes,
        centre: V2,
        ccw: bool,
        feed: f64,
        origin: Origin,
    ) -> Self {
        let (arc, plane_len) = ArcGeometry::of(plane.point(start), plane.point(end), centre, ccw);
        let other = off_plane_squared(start, end, plane);
        let length = (plane_len * plane_len + other).sqrt();
        Self {
            feed,
            origin,
            arc: Some(arc),
            ..Self::bare(start, end, plane, length)
        }
    }

    /// The same element with its contour normal.
    #[inline]
    pub fn with_normal(mut self, normal: Option<ContourNormal>) -> Self {
        let Some(n) = normal else {
            self.normal = NormalKind::None;
            return self;
        };
        self.normal_plane = n.plane;
        (self.normal, self.normal_at) = match n.rule {
            NormalRule::Fixed(v) => (NormalKind::Fixed, v),
            NormalRule::Radial { centre, outward } if outward => (NormalKind::Outward, centre),
            NormalRule::Radial { centre, .. } => (NormalKind::Inward, centre),
            NormalRule::FromCorner(k) => (NormalKind::FromCorner, k),
        };
        self
    }

    /// The end in the plane `(h, v)` of [`SpoolElement::plane`].
    #[inline]
    pub fn to(&self) -> V2 {
        self.to
    }

    /// The two axes of [`SpoolElement::to`] (an arc's plane).
    #[inline]
    pub fn plane(&self) -> PlaneAxes {
        self.plane
    }

    /// Whether an axis outside the plane moves (the spooler then keeps
    /// the element's end on every axis).
    #[inline]
    pub fn moves_off_plane(&self) -> bool {
        self.moves_off_plane
    }

    /// Path length (arc length, helical where other axes move).
    #[inline]
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Feed in units/min.
    #[inline]
    pub fn feed(&self) -> f64 {
        self.feed
    }

    /// A rapid move (`RAP`).
    #[inline]
    pub fn rapid(&self) -> bool {
        self.rapid
    }

    /// Who spooled it.
    #[inline]
    pub fn origin(&self) -> Origin {
        self.origin
    }

    /// The same element with another origin tag (the departure).
    pub fn with_origin(self, origin: Origin) -> Self {
        Self { origin, ..self }
    }

    /// Line or arc.
    pub fn path(&self) -> Path {
        match &self.arc {
            None => Path::Line,
            Some(a) => Path::Arc(ArcPath {
                plane: self.plane,
                centre: a.centre,
                ccw: a.sweep > 0.0,
            }),
        }
    }

    /// The contour normal, for elements the correction spooled.
    pub fn normal(&self) -> Option<ContourNormal> {
        let v = self.normal_at;
        let rule = match self.normal {
            NormalKind::None => return None,
            NormalKind::Fixed => NormalRule::Fixed(v),
            NormalKind::Outward => NormalRule::Radial {
                centre: v,
                outward: true,
            },
            NormalKind::Inward => NormalRule::Radial {
                centre: v,
                outward: false,
            },
            NormalKind::FromCorner => NormalRule::FromCorner(v),
        };
        Some(ContourNormal {
            plane: self.normal_plane,
            rule,
        })
    }

    /// The element from `start` to `end` as it is reported (spool log,
    /// wire).
    pub fn record(&self, start: &AxisPos, end: &AxisPos) -> SpoolRecord {
        SpoolRecord {
            arc: self.arc.map(|a| ArcRecord {
                plane: [self.plane.h, self.plane.v, self.plane.third],
                centre: [a.centre.x, a.centre.y],
                ccw: a.sweep > 0.0,
            }),
            start: *start,
            end: *end,
            feed: self.feed,
            rapid: self.rapid,
            origin: self.origin,
        }
    }
}

mod run;

#[cfg(test)]
mod tests;
