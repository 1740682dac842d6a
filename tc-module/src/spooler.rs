//! The spooler: a FIFO of LIN/CIR elements waiting for the executor, plus
//! the spool log that traces check (trc-geometry.md "Spooler and execution").

use std::collections::VecDeque;
use std::f64::consts::TAU;

use crate::plane::{AxisPos, PlaneAxes, AXES};

/// Who put an element into the spooler: OTC's continuous wear only counts
/// on elements the running correction spooled (otc.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Origin {
    /// No correction running (including the departure move).
    Plain,
    /// The approach element of a correction.
    Approach,
    /// A corrected profile element.
    Corrected,
    /// A transition inserted by the correction at an outside corner.
    Transition,
}

/// Geometry of an arc element in its plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPath {
    /// The plane axes.
    pub plane: PlaneAxes,
    /// Centre `(h, v)`.
    pub centre: [f64; 2],
    /// Counter-clockwise?
    pub ccw: bool,
    /// Angle of the start point about the centre.
    start_angle: f64,
    /// Signed sweep (positive CCW); a full circle sweeps ±2π.
    sweep: f64,
    /// Radius at the start.
    r0: f64,
    /// Radius at the end (equal to `r0` up to rounding).
    r1: f64,
}

/// Path of an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path {
    /// Straight line from start to end in all axes.
    Line,
    /// Arc in a plane, helical where other axes move.
    Arc(ArcPath),
}

/// One element of the spooler.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpoolElement {
    /// Start position (all axes).
    pub start: AxisPos,
    /// End position (all axes).
    pub end: AxisPos,
    /// Line or arc.
    pub path: Path,
    /// Feed in units/min.
    pub feed: f64,
    /// A rapid move (`RAP`).
    pub rapid: bool,
    /// Who spooled it.
    pub origin: Origin,
    /// Path length (arc length, helical where other axes move).
    pub length: f64,
}

fn line_length(start: &AxisPos, end: &AxisPos) -> f64 {
    start
        .iter()
        .zip(end)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

impl SpoolElement {
    /// A straight element.
    pub fn line(start: AxisPos, end: AxisPos, feed: f64, rapid: bool, origin: Origin) -> Self {
        Self {
            start,
            end,
            path: Path::Line,
            feed,
            rapid,
            origin,
            length: line_length(&start, &end),
        }
    }

    /// An arc element about `centre` in `plane`; start = end in the plane
    /// is a full circle.
    pub fn arc(
        start: AxisPos,
        end: AxisPos,
        plane: PlaneAxes,
        centre: [f64; 2],
        ccw: bool,
        feed: f64,
        origin: Origin,
    ) -> Self {
        let s = plane.point(&start);
        let e = plane.point(&end);
        let (sh, sv) = (s[0] - centre[0], s[1] - centre[1]);
        let (eh, ev) = (e[0] - centre[0], e[1] - centre[1]);
        let start_angle = sv.atan2(sh);
        let mut sweep = (sh * ev - sv * eh).atan2(sh * eh + sv * ev); // (-π, π]
        if ccw {
            if sweep <= 1e-12 {
                sweep += TAU;
            }
        } else if sweep >= -1e-12 {
            sweep -= TAU;
        }
        let r0 = sh.hypot(sv);
        let r1 = eh.hypot(ev);
        let plane_len = sweep.abs() * 0.5 * (r0 + r1);
        let other: f64 = (0..AXES)
            .filter(|&i| i != plane.h as usize && i != plane.v as usize)
            .map(|i| (end[i] - start[i]) * (end[i] - start[i]))
            .sum();
        Self {
            start,
            end,
            path: Path::Arc(ArcPath {
                plane,
                centre,
                ccw,
                start_angle,
                sweep,
                r0,
                r1,
            }),
            feed,
            rapid: false,
            origin,
            length: (plane_len * plane_len + other).sqrt(),
        }
    }

    /// The position at path distance `s` (0 ≤ s ≤ length).
    pub fn point_at(&self, s: f64) -> AxisPos {
        let f = if self.length > 0.0 {
            (s / self.length).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let mut p = self.start;
        for (i, q) in p.iter_mut().enumerate() {
            *q += (self.end[i] - self.start[i]) * f;
        }
        if let Path::Arc(a) = &self.path {
            let ang = a.start_angle + a.sweep * f;
            let r = a.r0 + (a.r1 - a.r0) * f;
            a.plane.set_point(
                &mut p,
                [a.centre[0] + r * ang.cos(), a.centre[1] + r * ang.sin()],
            );
        }
        p
    }
}

/// The spooler queue and its log.
#[derive(Debug, Default)]
pub struct Spooler {
    queue: VecDeque<SpoolElement>,
    log: Vec<SpoolElement>,
    logging: bool,
}

impl Spooler {
    /// Whether every spooled element is also kept in the log.
    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Appends an element.
    pub fn push(&mut self, e: SpoolElement) {
        if self.logging {
            self.log.push(e);
        }
        self.queue.push_back(e);
    }

    /// Elements waiting (the one under way included).
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether nothing waits.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// The end of the last waiting element.
    pub fn last_end(&self) -> Option<AxisPos> {
        self.queue.back().map(|e| e.end)
    }

    /// The element under way.
    pub fn front(&self) -> Option<&SpoolElement> {
        self.queue.front()
    }

    /// Removes the element under way.
    pub fn pop_front(&mut self) -> Option<SpoolElement> {
        self.queue.pop_front()
    }

    /// Discards every waiting element (direct commands).
    pub fn discard(&mut self) {
        self.queue.clear();
    }

    /// Takes the log collected so far.
    pub fn take_log(&mut self) -> Vec<SpoolElement> {
        std::mem::take(&mut self.log)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pos(x: f64, y: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p[1] = y;
        p
    }

    const XY: PlaneAxes = PlaneAxes {
        h: 0,
        v: 1,
        third: 2,
    };

    #[test]
    fn quarter_arc_length_and_midpoint() {
        let e = SpoolElement::arc(
            pos(1.0, 0.0),
            pos(0.0, 1.0),
            XY,
            [0.0, 0.0],
            true,
            1000.0,
            Origin::Plain,
        );
        assert!((e.length - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let m = e.point_at(e.length / 2.0);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((m[0] - h).abs() < 1e-12 && (m[1] - h).abs() < 1e-12);
        let cw = SpoolElement::arc(
            pos(1.0, 0.0),
            pos(0.0, 1.0),
            XY,
            [0.0, 0.0],
            false,
            1000.0,
            Origin::Plain,
        );
        assert!((cw.length - 3.0 * std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn full_circle() {
        let e = SpoolElement::arc(
            pos(1.0, 0.0),
            pos(1.0, 0.0),
            XY,
            [0.0, 0.0],
            false,
            1000.0,
            Origin::Plain,
        );
        assert!((e.length - TAU).abs() < 1e-12);
        let q = e.point_at(e.length / 4.0);
        assert!((q[0]).abs() < 1e-12 && (q[1] + 1.0).abs() < 1e-12);
    }
}
