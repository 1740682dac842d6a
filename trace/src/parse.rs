//! The trace parser: text to [`Step`]s, read line by line from any
//! [`BufRead`] so that a trace of any length replays in bounded memory,
//! with a `file:line` error for any malformed line (invalid UTF-8 too)
//! and no panic on any input. Requests are read by `tc_request::text`, one
//! function per verb.

use std::io::{BufRead, Read};

use tc_module::check_capacity;
use tc_module::{CycleTime, AXES};
use tc_request::text::{parse_f64, parse_request, parse_words, Allow};

use super::echo::shorten;
use super::expect::{parse_expect, parse_spool, TextResult};
use super::model::{Expect, Header, Step, Trace, TraceError};

/// Longest line read (a guard against a file without line breaks).
pub const MAX_LINE_BYTES: usize = 1 << 20;

fn parse_cycle(s: &str) -> TextResult<CycleTime> {
    let lower: String = s
        .split_whitespace()
        .collect::<String>()
        .to_ascii_lowercase();
    let (num, scale) = if let Some(n) = lower.strip_suffix("ms") {
        (n, 1e-3)
    } else if let Some(n) = lower.strip_suffix("us") {
        (n, 1e-6)
    } else {
        return Err(format!("bad cycle `{s}` (want e.g. `1ms` or `500us`)"));
    };
    let v = parse_f64(num)?;
    CycleTime::from_secs(v * scale).map_err(|e| format!("bad cycle `{s}`: {e}"))
}

fn parse_spool_capacity(s: &str) -> TextResult<usize> {
    let n: u64 = s
        .trim()
        .parse()
        .map_err(|_| format!("bad spooler capacity `{s}` (want a count of elements)"))?;
    check_capacity(n).map_err(|e| e.to_string())
}

fn parse_tol(value: &str) -> TextResult<f64> {
    let t = parse_f64(value)?;
    if t.is_finite() && t >= 0.0 {
        Ok(t)
    } else {
        Err(format!(
            "tolerance must be finite and >= 0, found `{value}`"
        ))
    }
}

fn parse_start(value: &str, start: &mut [f64; AXES]) -> TextResult<()> {
    let tokens: Vec<&str> = value.split_whitespace().collect();
    let w = parse_words(&tokens, Allow::AXES)?;
    for (p, v) in start.iter_mut().zip(w.axes) {
        if let Some(v) = v {
            if !v.is_finite() {
                return Err("start position must be finite".into());
            }
            *p = v;
        }
    }
    Ok(())
}

/// A header line (after `@`).
fn parse_header(header: &str, h: &mut Header) -> TextResult<()> {
    let (key, value) = header
        .split_once(char::is_whitespace)
        .unwrap_or((header, ""));
    let value = value.trim();
    match key.to_ascii_lowercase().as_str() {
        "name" => h.name = Some(value.to_string()),
        "tol" => h.tol = parse_tol(value)?,
        "start" => parse_start(value, &mut h.start)?,
        "cycle" => h.cycle = parse_cycle(value)?,
        "spool" => h.spool_capacity = parse_spool_capacity(value)?,
        other => return Err(format!("unknown header `@{other}`")),
    }
    Ok(())
}

/// A request line `REQUEST [=> EXPECT]`.
fn parse_step(line: usize, code: &str) -> TextResult<Step> {
    let (req_text, expect_text) = match code.split_once("=>") {
        Some((r, e)) => (r.trim(), Some(e.trim())),
        None => (code, None),
    };
    let request = parse_request(req_text)?;
    let expect = match expect_text {
        None => Expect::Success,
        Some(e) => parse_expect(&request, e)?,
    };
    Ok(Step {
        line,
        text: req_text.to_string(),
        request,
        expect,
        spool: Vec::new(),
    })
}

/// Reads a trace step by step: the header lines when opened, then one
/// [`Step`] (a request with its `<` spool lines) per item. Only the step
/// being read is held in memory. After an error it yields nothing more.
pub struct TraceReader<R> {
    input: R,
    header: Header,
    /// Number of the last line read.
    line: usize,
    /// The line being read (its buffer reused).
    buf: Vec<u8>,
    /// The request read last; complete once the next request line (or the
    /// end) shows that no more `<` lines follow.
    pending: Option<Step>,
    /// An error found on the line after a complete step, given out after
    /// that step.
    deferred: Option<TraceError>,
    finished: bool,
}

impl<R: BufRead> TraceReader<R> {
    /// Reads the header lines and the first request of `input`; `file`
    /// names the trace in errors.
    pub fn open(file: &str, input: R) -> Result<Self, TraceError> {
        let mut reader = Self {
            input,
            header: Header::new(file),
            line: 0,
            buf: Vec::new(),
            pending: None,
            deferred: None,
            finished: false,
        };
        while reader.pending.is_none() {
            let Some(code) = reader.next_code()? else {
                break;
            };
            let result = match code.strip_prefix('@') {
                Some(header) => parse_header(header, &mut reader.header),
                None if code.starts_with('<') => {
                    Err("a spool line `<` must follow a request".into())
                }
                None => parse_step(reader.line, &code).map(|s| reader.pending = Some(s)),
            };
            result.map_err(|m| reader.error(m))?;
        }
        Ok(reader)
    }

    /// What the header lines set.
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// A [`TraceError`] at the line last read.
    fn error(&self, message: String) -> TraceError {
        TraceError {
            file: self.header.file.clone(),
            line: self.line,
            message: shorten(&message).into_owned(),
        }
    }

    /// The next line with code (comment stripped, trimmed, not empty), or
    /// `None` at the end.
    fn next_code(&mut self) -> Result<Option<String>, TraceError> {
        loop {
            self.buf.clear();
            self.line += 1;
            let limit = u64::try_from(MAX_LINE_BYTES).unwrap_or(u64::MAX);
            let read = (&mut self.input)
                .take(limit + 1)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| self.error(format!("cannot read: {e}")))?;
            if read == 0 {
                return Ok(None);
            }
            if self.buf.len() > MAX_LINE_BYTES {
                let m = format!("line longer than {MAX_LINE_BYTES} bytes");
                return Err(self.error(m));
            }
            let text = std::str::from_utf8(&self.buf).map_err(|e| {
                self.error(format!(
                    "not UTF-8 text (invalid byte at column {})",
                    e.valid_up_to() + 1
                ))
            })?;
            let code = text.split('#').next().unwrap_or("").trim();
            if !code.is_empty() {
                return Ok(Some(code.to_string()));
            }
        }
    }

    /// The next complete step, `None` at the end.
    fn next_step(&mut self) -> Result<Option<Step>, TraceError> {
        if let Some(e) = self.deferred.take() {
            return Err(e);
        }
        while let Some(code) = self.next_code()? {
            if code.starts_with('@') {
                let e = self.error("header lines must come before the first request".into());
                return self.complete_then(e);
            }
            if let Some(spool) = code.strip_prefix('<') {
                let expect = parse_spool(self.line, spool).map_err(|m| self.error(m))?;
                match self.pending.as_mut() {
                    Some(step) => step.spool.push(expect),
                    None => {
                        let m = "a spool line `<` must follow a request".to_string();
                        return Err(self.error(m));
                    }
                }
                continue;
            }
            return match parse_step(self.line, &code) {
                Ok(next) => Ok(self.pending.replace(next)),
                Err(m) => {
                    let e = self.error(m);
                    self.complete_then(e)
                }
            };
        }
        Ok(self.pending.take())
    }

    /// A line that is not a `<` line completes the step before it: that
    /// step first, the error of the line after it.
    fn complete_then(&mut self, e: TraceError) -> Result<Option<Step>, TraceError> {
        match self.pending.take() {
            Some(step) => {
                self.deferred = Some(e);
                Ok(Some(step))
            }
            None => Err(e),
        }
    }
}

impl<R: BufRead> Iterator for TraceReader<R> {
    type Item = Result<Step, TraceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.finished {
            return None;
        }
        let item = self.next_step().transpose();
        self.finished = !matches!(item, Some(Ok(_)));
        item
    }
}

/// Parses the text of a trace as a whole. `file` names it in errors.
pub fn parse_trace(file: &str, text: &str) -> Result<Trace, TraceError> {
    let mut reader = TraceReader::open(file, text.as_bytes())?;
    let steps = reader.by_ref().collect::<Result<Vec<Step>, TraceError>>()?;
    Ok(Trace {
        header: reader.header,
        steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use uoi::AccessError;

    #[test]
    fn spec_example_parses() {
        let text = "@name left-square-corner\nW 1300/1/1/2 i 0            # RESET group 1\nR 1300/1/1/3 i => 1\nLIN X10 Y10\n< LIN X8 Y2\nR 1300/0/20/0 d => 0.5\nPOS => X1 Y2\nQUEUE => 3\nEXEC 25\nCIR ccw X1 Y2 I3 J4 F100 => err State\nR 1300/1/1/1 i => 0x1f\n";
        let t = parse_trace("ex.trace", text).unwrap();
        assert_eq!(t.header.name.as_deref(), Some("left-square-corner"));
        assert_eq!(t.steps.len(), 9);
        assert_eq!(t.steps[2].spool.len(), 1);
        assert_eq!(t.steps[8].expect, Expect::Int(31));
        assert_eq!(t.steps[7].expect, Expect::Err(AccessError::State));
    }

    #[test]
    fn errors_name_the_line() {
        for (text, line) in [
            ("R 1300/0/3/0 i\nFOO\n", 2),
            ("R 1300/0/3 i\n", 1),
            ("\n\nW 1300/0/3/0 i 1x\n", 3),
            ("W 1300/0/3/0 q 1\n", 1),
            ("< LIN X1\n", 1),
            ("R 1300/0/3/0 i => abc\n", 1),
            ("LIN X1 X2\n", 1),
            ("R 1300/0/3/0 i\n@tol 1\n", 2),
            ("@cycle 1s\n", 1),
            ("W 1300/0/3/0 i 5 => err Nope\n", 1),
        ] {
            let e = parse_trace("bad.trace", text).unwrap_err();
            assert_eq!(e.line, line, "{text:?}: {e}");
            assert!(e.to_string().starts_with(&format!("bad.trace:{line}: ")));
        }
    }

    #[test]
    fn invalid_utf8_names_its_line() {
        let text = b"R 1300/0/3/0 i => 17\r\n# caf\xe9\nR 1300/0/3/0 i\n";
        let e = TraceReader::open("bytes.trace", &text[..])
            .unwrap()
            .collect::<Result<Vec<Step>, TraceError>>()
            .unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        assert!(e.to_string().starts_with("bytes.trace:2: not UTF-8"), "{e}");
    }

    #[test]
    fn spool_lines_join_the_step_before_them() {
        let text = "LIN X1\n< LIN X1\n\n# between\n< LIN X2\nLIN X3\n";
        let steps: Vec<Step> = TraceReader::open("s.trace", text.as_bytes())
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        let lines: Vec<Vec<usize>> = steps
            .iter()
            .map(|s| s.spool.iter().map(|e| e.line).collect())
            .collect();
        assert_eq!(lines, [vec![2, 5], vec![]]);
    }

    #[test]
    fn the_step_before_a_malformed_line_comes_first() {
        for (bad, line) in [("FROB", 3), ("@tol 1", 3), ("< FROB", 3)] {
            let text = format!("R 1300/0/3/0 i\nR 1300/0/3/0 i => 17\n{bad}\nR 1300/0/3/0 i\n");
            let items: Vec<Result<Step, TraceError>> =
                TraceReader::open("m.trace", text.as_bytes())
                    .unwrap()
                    .collect();
            let complete = if bad.starts_with('<') { 1 } else { 2 };
            assert_eq!(items.len(), complete + 1, "{bad}: {items:?}");
            assert!(items[..complete].iter().all(Result::is_ok), "{bad}");
            let e = items[complete].as_ref().unwrap_err();
            assert_eq!(e.line, line, "{bad}: {e}");
        }
    }

    #[test]
    fn a_line_without_end_is_refused() {
        let text = "R 1300/0/3/0 i => 17\n".to_string() + &"#".repeat(MAX_LINE_BYTES + 1);
        let e = parse_trace("endless.trace", &text).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("longer than"), "{e}");
    }

    #[test]
    fn long_messages_are_cut() {
        let word = "Q".repeat(10_000);
        let e = parse_trace("w.trace", &format!("R 1300/0/3/0 i => {word}\n")).unwrap_err();
        assert!(e.to_string().len() < 300, "{e}");
        assert!(e.message.ends_with('…'), "{e}");
    }

    #[test]
    fn cycles_and_tolerances() {
        let secs = |s| parse_cycle(s).map(CycleTime::secs);
        assert_eq!(secs("250us"), Ok(250e-6));
        assert_eq!(secs("2 ms"), Ok(2e-3));
        assert!(parse_cycle("0ms").is_err());
        // A cycle that would make every step vanish is refused.
        assert!(parse_cycle("1e-320us").is_err());
        assert!(parse_cycle("0.5us").is_err());
        assert!(parse_cycle("1001ms").is_err());
        assert_eq!(parse_spool_capacity(" 8 "), Ok(8));
        assert!(parse_spool_capacity("7").is_err());
        assert!(parse_spool_capacity("lots").is_err());
        assert!(parse_tol("-1").is_err());
    }
}
