//! The corner between the held profile and the next one (docs/trc.md "How
//! a corner is decided"): where the held element ends, what is inserted,
//! and where the next one starts; and the spooling of what is inserted.

use super::held::Held;
use super::profile::{Profile, TransitionMode};
use super::sink::{Axes, Sink};
use crate::bits::ErrorBits;
use crate::element::{NormalRule, Origin};
use crate::geometry::V2;
use crate::geometry::{classify, inside_point, transition, CornerKind, Offset, Part, Transition};

/// How a corner joins the held element `a` to the next `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Join {
    /// Where a's corrected element ends.
    pub a_end: V2,
    /// What is inserted between them.
    pub transition: Option<Transition>,
    /// Where b's corrected element starts.
    pub b_from: V2,
    /// b continues from a's end (case 1).
    pub continued: bool,
}

/// The corner between the held `a` and the next profile's offset `b`
/// (`b_full`: a programmed full circle); `KORR_ERROR` when the tool does
/// not fit an inside corner.
#[inline]
pub(super) fn corner(
    a: &Held,
    b: &Offset,
    b_full: bool,
    mode: TransitionMode,
) -> Result<Join, ErrorBits> {
    let k = a.corner();
    let pa = a.off.end;
    let join = |a_end, transition, b_from, continued| Join {
        a_end,
        transition,
        b_from,
        continued,
    };
    match classify(a.off.t_end, b.t_start, b.d, &a.off.path, &b.path) {
        CornerKind::Smooth => Ok(join(pa, None, pa, true)),
        CornerKind::Outside => {
            let linear = mode == TransitionMode::Linear;
            let t = transition(linear, k, pa, b.start, a.off.t_end, b.t_start, b.d);
            Ok(join(pa, Some(t), b.start, false))
        }
        CornerKind::Inside => {
            let part_b = Part {
                path: b.path,
                from: Some(b.start),
                to: b.end,
                full: b_full,
            };
            let x = inside_point(&a.part(), &part_b, k).ok_or(ErrorBits::KORR_ERROR)?;
            Ok(join(x, None, x, false))
        }
    }
}

/// Spools the transition at corner `k`, at the next profile's feed.
pub(super) fn spool_transition(t: Transition, k: V2, next: &Profile, sink: &mut Sink) {
    let rule = NormalRule::FromCorner(k);
    match t {
        Transition::Arc { centre, ccw, to } => {
            let (feed, origin) = (next.feed, Origin::Transition);
            sink.arc(to, Axes::Stay, (centre, ccw), feed, origin, rule);
        }
        Transition::Lines(lines) => {
            let motion = (next.feed, next.rapid);
            for p in lines.points() {
                sink.line(*p, Axes::Stay, motion, Origin::Transition, Some(rule));
            }
        }
    }
}
