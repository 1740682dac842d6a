//! The replayer: runs a [`Trace`] on a fresh [`Emulator`] and lists every
//! line whose answer differs from the expectation.

use std::fmt::Write as _;

use tc_module::{AXES, AXIS_NAMES};
use tc_request::text::write_axis_words;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::Value;

use super::model::{Expect, SpoolExpect, SpoolKind, Step, Trace};
use crate::Emulator;

/// One line whose answer differs from the trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Mismatch {
    /// The trace file.
    pub file: String,
    /// The line number (the request's, or the `<` line's).
    pub line: usize,
    /// The request text.
    pub request: String,
    /// What the trace expected.
    pub expected: String,
    /// What the emulator answered.
    pub got: String,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}: `{}`: expected {}, got {}",
            self.file, self.line, self.request, self.expected, self.got
        )
    }
}

/// `X1 Y2 ...` for the given axes.
fn axis_words(words: [Option<f64>; AXES]) -> String {
    let mut s = String::new();
    let _ = write_axis_words(&mut s, &words);
    s.trim_start().to_string()
}

fn describe(a: &Result<Reply, String>) -> String {
    match a {
        Ok(Reply::Ok) => "ok".into(),
        Ok(Reply::Access(e)) => format!("err {}", e.name()),
        Ok(Reply::Value(v)) => v.to_string(),
        Ok(Reply::Pos(p)) => axis_words(p.map(Some)),
        Ok(Reply::Queue(n)) => n.to_string(),
        Ok(other) => format!("err (unexpected answer {other:?})"),
        Err(e) => format!("err {e}"),
    }
}

fn describe_expect(e: &Expect) -> String {
    match e {
        Expect::Success => "success".into(),
        Expect::Ok => "ok".into(),
        Expect::Err(e) => format!("err {}", e.name()),
        Expect::Int(v) => v.to_string(),
        Expect::Double(v) => v.to_string(),
        Expect::Pos(w) => axis_words(*w),
        Expect::Queue(n) => n.to_string(),
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol || (a.is_nan() && b.is_nan()) || (a.is_infinite() && a == b)
}

fn matches(expect: &Expect, got: &Result<Reply, String>, tol: f64) -> bool {
    let Ok(got) = got else { return false };
    match (expect, got) {
        (Expect::Success, Reply::Access(_) | Reply::Protocol(_)) => false,
        (Expect::Success, _) => true,
        (Expect::Ok, Reply::Ok) => true,
        (Expect::Err(e), Reply::Access(g)) => e == g,
        (Expect::Int(e), Reply::Value(Value::I32(g))) => e == g,
        (Expect::Double(e), Reply::Value(Value::F64(g))) => close(*e, *g, tol),
        (Expect::Pos(w), Reply::Pos(p)) => w
            .iter()
            .zip(p)
            .all(|(e, g)| e.is_none_or(|e| close(e, *g, tol))),
        (Expect::Queue(e), Reply::Queue(g)) => u64::try_from(*e) == Ok(*g),
        _ => false,
    }
}

/// What a trace is replayed against: the emulator in this process, or a
/// server over the wire.
pub trait Target {
    /// Carries out one request; `Err` when it could not be carried to the
    /// target (a broken connection).
    fn run(&mut self, req: &Request) -> Result<Reply, String>;
    /// The elements spooled since the last call.
    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, String>;
    /// Device 0 AxisNr X/Y/Z (to read `I J K` of spooled arcs).
    fn axis_nr(&mut self) -> Result<[u8; 3], String>;
}

impl Target for Emulator {
    fn run(&mut self, req: &Request) -> Result<Reply, String> {
        Ok(Emulator::run(self, req))
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, String> {
        Ok(self.take_spool_log())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], String> {
        Ok(self.tc().axis_nr())
    }
}

/// The offset of an arc's centre from its start along machine axis `m`,
/// if `m` is one of its plane axes.
fn centre_offset(e: &SpoolRecord, m: u8) -> Option<f64> {
    let a = e.arc?;
    let start = *e.start.get(usize::from(m))?;
    if m == a.plane[0] {
        Some(a.centre[0] - start)
    } else if m == a.plane[1] {
        Some(a.centre[1] - start)
    } else {
        None
    }
}

/// Writes a spooled element in trace syntax: changed axes, and `I J K` of
/// an arc along the axes allocated as X, Y, Z (`axis_nr`).
pub fn format_record(e: &SpoolRecord, axis_nr: [u8; 3]) -> String {
    let mut s = String::new();
    match &e.arc {
        None => s.push_str("LIN"),
        Some(a) => s.push_str(if a.ccw { "CIR CCW" } else { "CIR CW" }),
    }
    for (i, name) in AXIS_NAMES.iter().enumerate() {
        if e.end[i] != e.start[i] || i < 2 {
            let _ = write!(s, " {}{}", name, e.end[i]);
        }
    }
    for (letter, &m) in ['I', 'J', 'K'].iter().zip(&axis_nr) {
        if let Some(o) = centre_offset(e, m) {
            let _ = write!(s, " {letter}{o}");
        }
    }
    s
}

fn element_matches(exp: &SpoolExpect, got: &SpoolRecord, axis_nr: [u8; 3], tol: f64) -> bool {
    let kind_ok = match (&exp.kind, &got.arc) {
        (SpoolKind::Line, None) => true,
        (SpoolKind::Arc(d), Some(a)) => (*d == tc_module::ArcDir::Ccw) == a.ccw,
        _ => false,
    };
    let end_ok = (0..AXES).all(|i| close(exp.words[i].unwrap_or(got.start[i]), got.end[i], tol));
    let centre_ok = axis_nr
        .iter()
        .zip(exp.centre)
        .all(|(&m, c)| centre_offset(got, m).is_none_or(|off| close(c.unwrap_or(0.0), off, tol)));
    kind_ok && end_ok && centre_ok
}

fn check_spool(
    step: &Step,
    got: &[SpoolRecord],
    axis_nr: [u8; 3],
    tol: f64,
    file: &str,
    out: &mut Vec<Mismatch>,
) {
    let n = step.spool.len().max(got.len());
    for k in 0..n {
        let exp = step.spool.get(k);
        let g = got.get(k);
        let ok = match (exp, g) {
            (Some(e), Some(g)) => element_matches(e, g, axis_nr, tol),
            _ => false,
        };
        if !ok {
            out.push(Mismatch {
                file: file.to_string(),
                line: exp.map_or(step.line, |e| e.line),
                request: step.text.clone(),
                expected: exp.map_or("nothing more spooled".into(), |e| format!("spooled `{e}`")),
                got: g.map_or("nothing".into(), |g| {
                    format!("`{}`", format_record(g, axis_nr))
                }),
            });
        }
    }
}

/// Replays `trace` on a fresh emulator; returns every mismatch (empty when
/// the trace passes).
pub fn replay(trace: &Trace) -> Vec<Mismatch> {
    let mut emu = Emulator::new(trace.start, trace.cycle).with_spool_capacity(trace.spool_capacity);
    emu.set_spool_log(true);
    replay_on(trace, &mut emu)
}

/// Replays `trace` against a target already set up for it (fresh state at
/// the trace's start, spool log on).
pub fn replay_on(trace: &Trace, target: &mut dyn Target) -> Vec<Mismatch> {
    let mut out = Vec::new();
    for step in &trace.steps {
        let got = target.run(&step.request);
        if !matches(&step.expect, &got, trace.tol) {
            out.push(Mismatch {
                file: trace.file.clone(),
                line: step.line,
                request: step.text.clone(),
                expected: describe_expect(&step.expect),
                got: describe(&got),
            });
        }
        let fail = |out: &mut Vec<Mismatch>, e: String| {
            out.push(Mismatch {
                file: trace.file.clone(),
                line: step.line,
                request: step.text.clone(),
                expected: "a spool log".into(),
                got: e,
            })
        };
        let spooled = match target.take_spooled() {
            Ok(s) => s,
            Err(e) => {
                fail(&mut out, e);
                break;
            }
        };
        if spooled.is_empty() && step.spool.is_empty() {
            continue;
        }
        let axis_nr = match target.axis_nr() {
            Ok(a) => a,
            Err(e) => {
                fail(&mut out, e);
                break;
            }
        };
        check_spool(step, &spooled, axis_nr, trace.tol, &trace.file, &mut out);
    }
    out
}
