//! An NC run written as trace text (docs/trace-format.md): the head, each
//! exchange as its request with the answer as the expectation and its
//! spooled elements, and the spooled elements labelled with their blocks
//! as `addipos run` prints them.

use std::fmt::Write as _;

use tc_request::text::format_record_fed;
use tc_request::{AxisPos, Origin, Reply, Request, AXIS_NAMES};

use super::exchange::Exchange;
use crate::run::At;

/// `=> ...`: the answer as a trace expectation.
fn expectation(reply: &Reply) -> Option<String> {
    Some(match reply {
        Reply::Ok => "ok".into(),
        Reply::Value(v) => v.to_string(),
        Reply::Pos(p) => axis_text(p),
        Reply::Queue(n) => n.to_string(),
        Reply::Access(e) => format!("err {}", e.name()),
        Reply::Spool(..) | Reply::Protocol(_) => return None,
    })
}

/// `X.. Y.. ..` of all axes.
pub fn axis_text(p: &AxisPos) -> String {
    let words: Vec<String> = AXIS_NAMES
        .iter()
        .zip(p)
        .map(|(n, v)| format!("{n}{v}"))
        .collect();
    words.join(" ")
}

fn block_comment(at: At) -> String {
    format!("# {}", block_name(at))
}

/// The first line of the trace of a run of program `name`.
pub fn trace_head(name: &str) -> String {
    format!("@name NC program {name}\n")
}

/// Labels each spooled element with the block it comes from. The
/// correction holds one profile until the next block shows its corner
/// (docs/trc.md, "The one-profile buffer"): the approach and corrected
/// elements spooled at a block belong to the motion block before it, a
/// transition to the corner between the two, an uncorrected element or a
/// departure to the block that spooled it (decision 315).
#[derive(Debug, Clone, Copy, Default)]
pub struct SpoolLabels {
    /// The block of the last motion request: the profile held, if any.
    last_motion: Option<At>,
}

impl SpoolLabels {
    /// The spooled elements of an exchange in trace `<` syntax, each with
    /// its block (and the block it was spooled at where that differs), one
    /// line each (without line ends). Call it for every exchange in order.
    pub fn lines(&mut self, x: &Exchange, axis_nr: [u8; 3]) -> Vec<String> {
        let held = self.last_motion;
        let out = x
            .spooled
            .iter()
            .map(|rec| {
                let el = format_record_fed(rec, axis_nr);
                format!("< {el}    # {}", label(rec.origin, held, x.at))
            })
            .collect();
        if matches!(x.request, Request::Motion(_)) {
            self.last_motion = Some(x.at);
        }
        out
    }
}

/// `N10 (line 3)`, or `line 3` for a block without a number.
fn block_name(at: At) -> String {
    match at.number {
        Some(n) => format!("N{n} (line {})", at.line),
        None => format!("line {}", at.line),
    }
}

/// Where an element of `origin`, spooled at block `now` while the profile
/// of block `held` (if any) was held, comes from.
fn label(origin: Origin, held: Option<At>, now: At) -> String {
    match (origin, held) {
        (Origin::Approach | Origin::Corrected, Some(h)) if h != now => {
            format!("{}, spooled at {}", block_name(h), block_name(now))
        }
        (Origin::Transition, Some(h)) if h != now => {
            format!("transition {} to {}", block_name(h), block_name(now))
        }
        _ => block_name(now),
    }
}

/// An exchange as trace lines (line ends included): the request with its
/// answer as the expectation, then the elements it spooled.
pub fn trace_lines(x: &Exchange, axis_nr: [u8; 3]) -> String {
    let mut t = format!("{}", x.request);
    if let Some(e) = expectation(&x.reply) {
        let _ = write!(t, " => {e}");
    }
    let _ = writeln!(t, "    {}", block_comment(x.at));
    for rec in &x.spooled {
        let _ = writeln!(t, "< {}", format_record_fed(rec, axis_nr));
    }
    t
}
