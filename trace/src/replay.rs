//! The replayer: runs a trace on a fresh [`Emulator`], or on any other
//! [`Runner`] (a server's conformance session), and reports every line
//! whose answer differs from the expectation, step by step as the trace
//! is read.

use std::fmt::Display;
use std::io::BufRead;

use tc_request::text::{centre_offset, format_record, write_axis_words};
use tc_request::{Reply, Runner, SpoolRecord, AXES};
use uoi::Value;

use super::echo::shorten;
use super::model::{Expect, Header, SpoolExpect, SpoolKind, Step, Trace, TraceError};
use super::parse::TraceReader;
use emulator::Emulator;

/// One line whose answer differs from the trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Mismatch {
    /// The trace file.
    pub file: String,
    /// The line number (the request's, or the `<` line's).
    pub line: usize,
    /// The request text (whole; shortened when displayed).
    pub request: String,
    /// What the trace expected.
    pub expected: String,
    /// What the emulator answered.
    pub got: String,
}

impl std::fmt::Display for Mismatch {
    /// `file:line: `request`: expected .., got ..`; a long request is cut
    /// short with `…` and its length given.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: ", self.file, self.line)?;
        let request = shorten(&self.request);
        if request.len() == self.request.len() {
            write!(f, "`{request}`")?;
        } else {
            let chars = self.request.chars().count();
            write!(f, "`{request}` ({chars} characters)")?;
        }
        write!(f, ": expected {}, got {}", self.expected, self.got)
    }
}

/// `X1 Y2 ...` for the given axes.
fn axis_words(words: [Option<f64>; AXES]) -> String {
    let mut s = String::new();
    let _ = write_axis_words(&mut s, &words);
    s.trim_start().to_string()
}

fn describe(a: &Result<Reply, impl Display>) -> String {
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

fn matches<E>(expect: &Expect, got: &Result<Reply, E>, tol: f64) -> bool {
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

fn element_matches(exp: &SpoolExpect, got: &SpoolRecord, axis_nr: [u8; 3], tol: f64) -> bool {
    let kind_ok = match (&exp.kind, &got.arc) {
        (SpoolKind::Line, None) => true,
        (SpoolKind::Arc(d), Some(a)) => (*d == tc_request::ArcDir::Ccw) == a.ccw,
        _ => false,
    };
    let end_ok = (0..AXES).all(|i| close(exp.words[i].unwrap_or(got.start[i]), got.end[i], tol));
    let centre_ok = axis_nr.iter().zip(exp.centre).all(|(&m, c)| {
        centre_offset(got, m)
            .is_none_or(|off| close(c.unwrap_or(0.0), off, tol))
    });
    let feed_ok = exp.feed.is_none_or(|f| close(f, got.feed, tol));
    kind_ok && end_ok && centre_ok && feed_ok
}

fn check_spool(
    step: &Step,
    got: &[SpoolRecord],
    axis_nr: [u8; 3],
    tol: f64,
    file: &str,
    report: &mut dyn FnMut(Mismatch),
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
            report(Mismatch {
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

/// A fresh emulator for a trace: its start position and cycle, spool log
/// on.
pub fn fresh_emulator(header: &Header) -> Emulator {
    let mut emu =
        Emulator::new(header.start, header.cycle).with_spool_capacity(header.spool_capacity);
    emu.set_spool_log(true);
    emu
}

/// Replays `trace` on a fresh emulator; returns every mismatch (empty when
/// the trace passes).
pub fn replay(trace: &Trace) -> Vec<Mismatch> {
    let mut emu = fresh_emulator(&trace.header);
    replay_on(trace, &mut emu)
}

/// Replays `trace` against a target already set up for it (fresh state at
/// the trace's start, spool log on): the emulator of [`fresh_emulator`],
/// or a server's conformance session.
pub fn replay_on<T: Runner + ?Sized>(trace: &Trace, target: &mut T) -> Vec<Mismatch> {
    let mut out = Vec::new();
    for step in &trace.steps {
        if !replay_step(step, &trace.header, target, &mut |m| out.push(m)) {
            break;
        }
    }
    out
}

/// How a streamed replay went.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Replayed {
    /// Requests replayed.
    pub steps: usize,
    /// Mismatches reported.
    pub mismatches: usize,
}

/// Replays a trace while reading it, against a target already set up for
/// its header; hands each mismatch to `report` as it is found. Only the
/// step being replayed is in memory. A malformed line ends the replay with
/// its error (the steps before it have been replayed and reported).
pub fn replay_stream<R: BufRead, T: Runner + ?Sized>(
    reader: &mut TraceReader<R>,
    target: &mut T,
    report: &mut dyn FnMut(Mismatch),
) -> Result<Replayed, TraceError> {
    let header = reader.header().clone();
    let mut done = Replayed::default();
    let mut count = |m: Mismatch| {
        done.mismatches += 1;
        report(m);
    };
    let mut steps = 0;
    for step in reader {
        let step = step?;
        steps += 1;
        if !replay_step(&step, &header, target, &mut count) {
            break;
        }
    }
    done.steps = steps;
    Ok(done)
}

/// Replays one step; `false` when the target broke and the rest of the
/// trace cannot run.
fn replay_step<T: Runner + ?Sized>(
    step: &Step,
    header: &Header,
    target: &mut T,
    report: &mut dyn FnMut(Mismatch),
) -> bool {
    let mismatch = |expected: String, got: String| Mismatch {
        file: header.file.clone(),
        line: step.line,
        request: step.text.clone(),
        expected,
        got,
    };
    let got = target.run(&step.request);
    if !matches(&step.expect, &got, header.tol) {
        report(mismatch(describe_expect(&step.expect), describe(&got)));
    }
    let spooled = match target.take_spooled() {
        Ok(s) => s,
        Err(e) => {
            report(mismatch("a spool log".into(), e.to_string()));
            return false;
        }
    };
    if spooled.is_empty() && step.spool.is_empty() {
        return true;
    }
    match target.axis_nr() {
        Ok(axis_nr) => {
            check_spool(step, &spooled, axis_nr, header.tol, &header.file, report);
            true
        }
        Err(e) => {
            report(mismatch("a spool log".into(), e.to_string()));
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{BufReader, Read};

    /// `lines` copies of one trace line, then a read error: input that
    /// cannot be read whole before replaying.
    struct FailsAfter {
        lines: usize,
        text: &'static [u8],
        at: usize,
    }

    impl Read for FailsAfter {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            if self.lines == 0 {
                return Err(std::io::Error::other("cable pulled"));
            }
            let rest = &self.text[self.at..];
            let n = rest.len().min(buf.len());
            buf[..n].copy_from_slice(&rest[..n]);
            self.at += n;
            if self.at == self.text.len() {
                self.at = 0;
                self.lines -= 1;
            }
            Ok(n)
        }
    }

    #[test]
    fn steps_replay_as_they_are_read() {
        let input = FailsAfter {
            lines: 1000,
            text: b"R 1300/0/3/0 i => 18\n",
            at: 0,
        };
        let mut reader = TraceReader::open("stream.trace", BufReader::new(input)).unwrap();
        let mut emu = fresh_emulator(reader.header());
        let mut lines = Vec::new();
        let e = replay_stream(&mut reader, &mut emu, &mut |m| lines.push(m.line)).unwrap_err();
        // Every step before the failing read was replayed and reported;
        // the last line read stays unreplayed, as `<` lines might follow.
        assert_eq!(lines.len(), 999);
        assert!(lines.iter().copied().eq(1..=999));
        assert_eq!(e.line, 1001);
        assert!(e.message.contains("cable pulled"), "{e}");
        assert_eq!(reader.next(), None);
    }

    #[test]
    fn counts_steps_and_mismatches() {
        let text = "@tol 0.1\nR 1300/0/3/0 i => 17\nR 1300/0/3/0 i => 1\nPOS => X0\n";
        let mut reader = TraceReader::open("count.trace", text.as_bytes()).unwrap();
        let mut emu = fresh_emulator(reader.header());
        let done = replay_stream(&mut reader, &mut emu, &mut |_| {}).unwrap();
        assert_eq!(
            done,
            Replayed {
                steps: 3,
                mismatches: 1
            }
        );
    }

    #[test]
    fn long_requests_are_echoed_short() {
        let request = format!("LIN X1.{}", "0".repeat(300));
        let m = Mismatch {
            file: "long.trace".into(),
            line: 7,
            request: request.clone(),
            expected: "err State".into(),
            got: "ok".into(),
        };
        let shown = m.to_string();
        assert!(!shown.contains(&request), "{shown}");
        let cut = format!("`{}…` (307 characters)", &request[..120]);
        assert!(shown.contains(&cut), "{shown}");
        assert!(shown.starts_with("long.trace:7: "), "{shown}");
        assert!(shown.ends_with(": expected err State, got ok"), "{shown}");
        let short = Mismatch {
            request: "LIN X1".into(),
            ..m
        };
        assert_eq!(
            short.to_string(),
            "long.trace:7: `LIN X1`: expected err State, got ok"
        );
    }
}
