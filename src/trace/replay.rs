//! The replayer: runs a [`Trace`] on a fresh [`Emulator`] and lists every
//! line whose answer differs from the expectation.

use std::fmt::Write as _;

use tc_module::{AxisPos, Path, SpoolElement, AXES, AXIS_NAMES};
use uoi::Value;

use super::parse::{Expect, Request, SpoolExpect, SpoolKind, Step, Trace};
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
    for (name, v) in AXIS_NAMES.iter().zip(words) {
        if let Some(v) = v {
            let _ = write!(s, "{name}{v} ");
        }
    }
    s.trim_end().to_string()
}

fn describe(a: &Answer) -> String {
    match a {
        Answer::Ok => "ok".into(),
        Answer::Err(e) => format!("err {e}"),
        Answer::Value(v) => v.to_string(),
        Answer::Pos(p) => axis_words(p.map(Some)),
        Answer::Queue(n) => n.to_string(),
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

fn matches(expect: &Expect, got: &Answer, tol: f64) -> bool {
    match (expect, got) {
        (Expect::Success, Answer::Err(_)) => false,
        (Expect::Success, _) => true,
        (Expect::Ok, Answer::Ok) => true,
        (Expect::Err(e), Answer::Err(g)) => e.name() == g,
        (Expect::Int(e), Answer::Value(Value::I32(g))) => e == g,
        (Expect::Double(e), Answer::Value(Value::F64(g))) => close(*e, *g, tol),
        (Expect::Pos(w), Answer::Pos(p)) => w
            .iter()
            .zip(p)
            .all(|(e, g)| e.is_none_or(|e| close(e, *g, tol))),
        (Expect::Queue(e), Answer::Queue(g)) => e == g,
        _ => false,
    }
}

/// What a trace is replayed against: the emulator in this process, or a
/// server over the wire.
pub trait Target {
    /// Carries out one request.
    fn run(&mut self, req: &Request) -> TargetAnswer;
    /// The elements spooled since the last call.
    fn take_spooled(&mut self) -> Result<Vec<SpoolElement>, String>;
    /// Device 0 AxisNr X/Y/Z (to read `I J K` of spooled arcs).
    fn axis_nr(&mut self) -> Result<[u8; 3], String>;
}

/// The answer to one request, as the replayer compares it.
#[derive(Debug, Clone, PartialEq)]
pub enum TargetAnswer {
    /// Done.
    Ok,
    /// Refused: the access error's name (or a transport failure in brackets).
    Err(String),
    /// A value read.
    Value(Value),
    /// The executed position.
    Pos(AxisPos),
    /// The spooler length.
    Queue(usize),
}

use TargetAnswer as Answer;

impl Target for Emulator {
    fn run(&mut self, req: &Request) -> Answer {
        match req {
            Request::Write(addr, v) => match self.write(*addr, *v) {
                Ok(()) => Answer::Ok,
                Err(e) => Answer::Err(e.name().to_string()),
            },
            Request::Read(addr, ty) => match self.read(*addr, *ty) {
                Ok(v) => Answer::Value(v),
                Err(e) => Answer::Err(e.name().to_string()),
            },
            Request::Motion(m) => match self.command(m) {
                Ok(()) => Answer::Ok,
                Err(e) => Answer::Err(e.name().to_string()),
            },
            Request::Exec(n) => {
                self.exec(*n);
                Answer::Ok
            }
            Request::Pos => Answer::Pos(self.position()),
            Request::Queue => Answer::Queue(self.queue_len()),
        }
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolElement>, String> {
        Ok(self.take_spool_log())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], String> {
        Ok(self.tc().axis_nr())
    }
}

/// Writes an element in trace syntax: changed axes, and `I J K` of an arc
/// along the axes allocated as X, Y, Z (`axis_nr`).
pub fn format_element(e: &SpoolElement, axis_nr: [u8; 3]) -> String {
    let mut s = String::new();
    match &e.path {
        Path::Line => s.push_str("LIN"),
        Path::Arc(a) => s.push_str(if a.ccw { "CIR CCW" } else { "CIR CW" }),
    }
    for (i, name) in AXIS_NAMES.iter().enumerate() {
        if e.end[i] != e.start[i] || i < 2 {
            let _ = write!(s, " {}{}", name, e.end[i]);
        }
    }
    if let Path::Arc(a) = &e.path {
        for (letter, &m) in ['I', 'J', 'K'].iter().zip(&axis_nr) {
            let off = if m == a.plane.h {
                Some(a.centre[0] - e.start[m as usize])
            } else if m == a.plane.v {
                Some(a.centre[1] - e.start[m as usize])
            } else {
                None
            };
            if let Some(o) = off {
                let _ = write!(s, " {letter}{o}");
            }
        }
    }
    s
}

fn element_matches(exp: &SpoolExpect, got: &SpoolElement, axis_nr: [u8; 3], tol: f64) -> bool {
    let arc = match (&exp.kind, &got.path) {
        (SpoolKind::Line, Path::Line) => None,
        (SpoolKind::Arc(d), Path::Arc(a)) if (*d == tc_module::ArcDir::Ccw) == a.ccw => Some(a),
        _ => return false,
    };
    let end_ok = (0..AXES).all(|i| close(exp.words[i].unwrap_or(got.start[i]), got.end[i], tol));
    let centre_ok = arc.is_none_or(|a| {
        axis_nr.iter().zip(exp.centre).all(|(&m, c)| {
            let got_off = if m == a.plane.h {
                a.centre[0] - got.start[m as usize]
            } else if m == a.plane.v {
                a.centre[1] - got.start[m as usize]
            } else {
                return true;
            };
            close(c.unwrap_or(0.0), got_off, tol)
        })
    });
    end_ok && centre_ok
}

fn check_spool(
    step: &Step,
    got: &[SpoolElement],
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
                    format!("`{}`", format_element(g, axis_nr))
                }),
            });
        }
    }
}

/// Replays `trace` on a fresh emulator; returns every mismatch (empty when
/// the trace passes).
pub fn replay(trace: &Trace) -> Vec<Mismatch> {
    let mut emu = Emulator::new(trace.start, trace.cycle_s);
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
