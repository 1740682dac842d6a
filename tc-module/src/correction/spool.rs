//! Spooling of the held profile, of the plane-null profiles waiting with
//! it and of the transitions at outside corners, with the check of the
//! held profile's corrected points.

use uoi::AccessError;

use super::sink::{rule_of, Sink};
use super::{Held, NullMove, Profile};
use crate::element::{NormalRule, Origin};
use crate::geometry::tolerance::ZERO_ARC;
use crate::geometry::{Contour, Offset, Transition, V2};
use crate::limits::check_point;

/// `Range` unless the held profile's corrected end (and, for an approach
/// arc, its corrected start), tool length included, are within the limit.
pub(super) fn check_held(
    prof: &Profile,
    off: &Offset,
    arc_approach: bool,
    sink: &Sink,
) -> Result<(), AccessError> {
    check_point(&sink.end_point(off.end, &prof.end))?;
    if arc_approach {
        check_point(&sink.end_point(off.start, &prof.start))?;
    }
    Ok(())
}

/// Spools the held profile's corrected element(s) up to `x`, then the
/// plane-null profiles waiting with it; returns the contour normal where
/// it ends (the caller forgets the plane-null profiles once all is
/// admitted).
pub(super) fn spool_held(a: &Held, x: V2, nulls: &[NullMove], sink: &mut Sink) -> V2 {
    let n_end = match a.contour {
        Contour::Line { .. } => {
            let origin = if a.approach {
                Origin::Approach
            } else {
                Origin::Corrected
            };
            let end = sink.end_point(x, &a.end);
            let n_end = a.off.normal_at(x);
            sink.line(end, a.feed, a.rapid, origin, Some(rule_of(n_end)));
            n_end
        }
        Contour::Arc { centre, sigma, .. } => {
            a.off.normal_at(spool_held_arc(a, centre, sigma, x, sink))
        }
    };
    for n in nulls {
        spool_null(n, Some(n_end), sink);
    }
    n_end
}

/// Spools the held arc (after its approach line, for an approach) up to
/// `x`, or where its whole turn ends; an arc cut to zero length is not
/// spooled, a full circle always is. Returns where it ends.
fn spool_held_arc(a: &Held, centre: V2, sigma: f64, x: V2, sink: &mut Sink) -> V2 {
    if a.approach {
        let end = sink.end_point(a.off.start, &a.start);
        let n = rule_of(a.off.normal_at(a.off.start));
        sink.line(end, a.feed, a.rapid, Origin::Approach, Some(n));
    }
    let here = sink.here();
    let x = a.end_at(here, x);
    let zero = (here - x).norm() <= ZERO_ARC;
    if !zero || a.contour.is_full_circle() {
        let end = sink.end_point(x, &a.end);
        let rule = NormalRule::Radial {
            centre: [centre.x, centre.y],
            outward: a.off.tool_outside_arc(sigma),
        };
        sink.arc(end, centre, sigma > 0.0, a.feed, Origin::Corrected, rule);
    }
    x
}

/// Spools a plane-null profile at the current tool position; it keeps the
/// normal the tool has there.
pub(super) fn spool_null(n: &NullMove, normal: Option<V2>, sink: &mut Sink) {
    let end = sink.end_point(sink.here(), &n.end);
    sink.line(end, n.feed, n.rapid, Origin::Corrected, normal.map(rule_of));
}

/// Spools the transition at corner `k`, at the next profile's feed.
pub(super) fn spool_transition(t: Transition, k: V2, next: &Profile, sink: &mut Sink) {
    let rule = NormalRule::FromCorner([k.x, k.y]);
    match t {
        Transition::Arc { centre, ccw, to } => {
            let end = sink.in_plane(to);
            sink.arc(end, centre, ccw, next.feed, Origin::Transition, rule);
        }
        Transition::Lines(lines) => {
            for p in lines.points() {
                let end = sink.in_plane(*p);
                sink.line(end, next.feed, next.rapid, Origin::Transition, Some(rule));
            }
        }
    }
}
