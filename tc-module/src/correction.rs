//! The correction engine: the one-profile buffer of trc-geometry.md.
//!
//! While a group runs, every profile is first held here. When the next one
//! arrives, the held one is corrected together with the corner to the new
//! one and both are spooled; the new one is held. Everything is computed
//! before anything is spooled, so an error never leaves half a corner in
//! the spooler.

use crate::bits::ErrorBits;
use crate::geometry::{
    classify, inside_point, transition, Contour, CornerKind, Offset, OffsetError, Part, Transition,
    V2,
};
use crate::group::TransitionMode;
use crate::plane::{AxisPos, PlaneAxes, AXES};
use crate::spooler::{Origin, SpoolElement, Spooler};

/// A programmed profile as it enters the correction (rotated, machine axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// The element in the group's plane.
    pub contour: Contour,
    /// Programmed start, all axes.
    pub start: AxisPos,
    /// Programmed end, all axes.
    pub end: AxisPos,
    /// Feed, units/min.
    pub feed: f64,
    /// A rapid move.
    pub rapid: bool,
}

/// Where elements go: the spooler, with the current tool position and the
/// group's plane and tool length.
#[derive(Debug)]
pub struct Sink<'a> {
    /// The spooler.
    pub spooler: &'a mut Spooler,
    /// The current tool position (end of the last spooled element).
    pub q: AxisPos,
    /// The group's plane axes.
    pub plane: PlaneAxes,
    /// Tool length added on the third main axis of every end point.
    pub len: f64,
}

impl Sink<'_> {
    /// End point: plane point `p`, other axes from `prog` with the tool
    /// length on the third axis.
    fn end_point(&self, p: V2, prog: &AxisPos) -> AxisPos {
        let mut e = *prog;
        self.plane.set_point(&mut e, [p.x, p.y]);
        let third = self.plane.third as usize;
        if third < AXES && third != self.plane.h as usize && third != self.plane.v as usize {
            e[third] += self.len;
        }
        e
    }

    /// End point that moves only the plane axes from the tool position
    /// (transitions: the other axes stay where the corner left them).
    fn in_plane(&self, p: V2) -> AxisPos {
        let mut e = self.q;
        self.plane.set_point(&mut e, [p.x, p.y]);
        e
    }

    fn line(&mut self, end: AxisPos, feed: f64, rapid: bool, origin: Origin) {
        self.spooler
            .push(SpoolElement::line(self.q, end, feed, rapid, origin));
        self.q = end;
    }

    fn arc(&mut self, end: AxisPos, centre: V2, ccw: bool, feed: f64, origin: Origin) {
        self.spooler.push(SpoolElement::arc(
            self.q,
            end,
            self.plane,
            [centre.x, centre.y],
            ccw,
            feed,
            origin,
        ));
        self.q = end;
    }

    fn here(&self) -> V2 {
        let p = self.plane.point(&self.q);
        V2::new(p[0], p[1])
    }
}

/// The held profile with its offset.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Held {
    prof: Profile,
    off: Offset,
    d: f64,
    /// First profile after start, flush or direct command.
    approach: bool,
    /// Where its corrected element starts; `None` for an approach line.
    from: Option<V2>,
}

/// A plane-null profile waiting with the held one.
#[derive(Debug, Clone, Copy, PartialEq)]
struct NullMove {
    end: AxisPos,
    feed: f64,
    rapid: bool,
}

/// The one-profile buffer of a group. Empty means the next profile is an
/// approach.
#[derive(Debug, Clone, Default)]
pub struct Buffer {
    held: Option<Held>,
    nulls: Vec<NullMove>,
}

fn offset_error(e: OffsetError) -> ErrorBits {
    match e {
        OffsetError::Calc => ErrorBits::CALC_ERROR,
        OffsetError::Center => ErrorBits::CENTER_ERROR,
    }
}

fn is_full_circle(c: &Contour) -> bool {
    matches!(*c, Contour::Arc { from, to, .. } if from == to)
}

impl Buffer {
    /// Whether a profile is held (STATUS bit ProfMarked).
    pub fn is_marked(&self) -> bool {
        self.held.is_some()
    }

    /// Drops the held profile without spooling it (ReInit, direct command,
    /// RESET, fault).
    pub fn clear(&mut self) {
        self.held = None;
        self.nulls.clear();
    }

    /// A new profile enters with offset `d` (side × radius). On error the
    /// bit to set is returned and nothing was spooled; the caller drops the
    /// buffer and faults the group.
    pub fn push(
        &mut self,
        prof: Profile,
        d: f64,
        mode: TransitionMode,
        sink: &mut Sink,
    ) -> Result<(), ErrorBits> {
        if prof.contour.is_plane_null() {
            let null = NullMove {
                end: prof.end,
                feed: prof.feed,
                rapid: prof.rapid,
            };
            if self.held.is_some() {
                self.nulls.push(null);
            } else {
                let here = sink.here();
                sink.line(
                    sink.end_point(here, &null.end),
                    null.feed,
                    null.rapid,
                    Origin::Corrected,
                );
            }
            return Ok(());
        }
        let off = prof.contour.offset(d).map_err(offset_error)?;
        let approach = |from| Held {
            prof,
            off,
            d,
            approach: true,
            from,
        };
        let approach_from = match prof.contour {
            Contour::Line { .. } => None,
            Contour::Arc { .. } => Some(off.start),
        };
        let Some(a) = self.held else {
            self.held = Some(approach(approach_from));
            return Ok(());
        };
        if a.d != d {
            // Radius changed while running: finish as at SSF 2001.
            self.flush(sink);
            self.held = Some(approach(approach_from));
            return Ok(());
        }
        let k = match a.prof.contour {
            Contour::Line { to, .. } | Contour::Arc { to, .. } => to,
        };
        let (x, trans, b_from) = match classify(a.off.t_end, off.t_start, d, &a.off.path, &off.path)
        {
            CornerKind::Smooth => (a.off.end, None, a.off.end),
            CornerKind::Outside => {
                let t = transition(
                    mode == TransitionMode::Linear,
                    k,
                    a.off.end,
                    off.start,
                    a.off.t_end,
                    off.t_start,
                    d,
                );
                (a.off.end, Some(t), off.start)
            }
            CornerKind::Inside => {
                let part_a = Part {
                    path: a.off.path,
                    from: a.from,
                    to: a.off.end,
                    full: is_full_circle(&a.prof.contour) && a.from == Some(a.off.end),
                };
                let part_b = Part {
                    path: off.path,
                    from: Some(off.start),
                    to: off.end,
                    full: is_full_circle(&prof.contour),
                };
                let x = inside_point(&part_a, &part_b, k).ok_or(ErrorBits::KORR_ERROR)?;
                (x, None, x)
            }
        };
        self.spool_held(&a, x, sink);
        if let Some(t) = trans {
            let (feed, rapid) = (prof.feed, prof.rapid);
            match t {
                Transition::Arc { centre, ccw, to } => {
                    sink.arc(sink.in_plane(to), centre, ccw, feed, Origin::Transition)
                }
                Transition::Lines { points, count } => {
                    for p in &points[..count] {
                        sink.line(sink.in_plane(*p), feed, rapid, Origin::Transition);
                    }
                }
            }
        }
        self.held = Some(Held {
            prof,
            off,
            d,
            approach: false,
            from: Some(b_from),
        });
        Ok(())
    }

    /// Spools the held profile with its own offset end, then the plane-null
    /// profiles waiting with it (STATUS=0, SSF 2001). The buffer is empty
    /// afterwards: the next profile is an approach.
    pub fn flush(&mut self, sink: &mut Sink) {
        if let Some(a) = self.held.take() {
            self.spool_held(&a, a.off.end, sink);
        }
        self.nulls.clear();
    }

    /// Spools the held profile's corrected element(s) up to `x`, then the
    /// plane-null profiles waiting with it.
    fn spool_held(&mut self, a: &Held, x: V2, sink: &mut Sink) {
        let p = &a.prof;
        match p.contour {
            Contour::Line { .. } => {
                let origin = if a.approach {
                    Origin::Approach
                } else {
                    Origin::Corrected
                };
                sink.line(sink.end_point(x, &p.end), p.feed, p.rapid, origin);
            }
            Contour::Arc { centre, sigma, .. } => {
                if a.approach {
                    sink.line(
                        sink.end_point(a.off.start, &p.start),
                        p.feed,
                        p.rapid,
                        Origin::Approach,
                    );
                }
                let zero_sweep = (sink.here() - x).norm() <= 1e-12;
                if !zero_sweep || is_full_circle(&p.contour) {
                    sink.arc(
                        sink.end_point(x, &p.end),
                        centre,
                        sigma > 0.0,
                        p.feed,
                        Origin::Corrected,
                    );
                }
            }
        }
        for n in self.nulls.drain(..) {
            let here = sink.here();
            sink.line(
                sink.end_point(here, &n.end),
                n.feed,
                n.rapid,
                Origin::Corrected,
            );
        }
    }
}
