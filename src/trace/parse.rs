//! The trace parser: text to [`Trace`], with a `file:line` error for any
//! malformed line and no panic on any input. Requests are read by
//! `tc_request::text`, one function per verb.

use tc_module::spooler::{check_capacity, DEFAULT_SPOOL_CAPACITY};
use tc_module::{CycleTime, AXES};
use tc_request::text::{parse_f64, parse_request, parse_words, Allow, TextResult};

use super::expect::{parse_expect, parse_spool};
use super::model::{Expect, Step, Trace, TraceError};

/// Default `@tol`.
pub const DEFAULT_TOL: f64 = 1e-6;

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
fn parse_header(header: &str, trace: &mut Trace) -> TextResult<()> {
    if !trace.steps.is_empty() {
        return Err("header lines must come before the first request".into());
    }
    let (key, value) = header
        .split_once(char::is_whitespace)
        .unwrap_or((header, ""));
    let value = value.trim();
    match key.to_ascii_lowercase().as_str() {
        "name" => trace.name = Some(value.to_string()),
        "tol" => trace.tol = parse_tol(value)?,
        "start" => parse_start(value, &mut trace.start)?,
        "cycle" => trace.cycle = parse_cycle(value)?,
        "spool" => trace.spool_capacity = parse_spool_capacity(value)?,
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

/// One line of code (comment stripped, not empty).
fn parse_line(line: usize, code: &str, trace: &mut Trace) -> TextResult<()> {
    if let Some(header) = code.strip_prefix('@') {
        return parse_header(header, trace);
    }
    if let Some(spool) = code.strip_prefix('<') {
        let step = trace
            .steps
            .last_mut()
            .ok_or("a spool line `<` must follow a request")?;
        step.spool.push(parse_spool(line, spool)?);
        return Ok(());
    }
    trace.steps.push(parse_step(line, code)?);
    Ok(())
}

/// Parses the text of a trace. `file` names it in errors.
pub fn parse_trace(file: &str, text: &str) -> Result<Trace, TraceError> {
    let mut trace = Trace {
        file: file.to_string(),
        name: None,
        tol: DEFAULT_TOL,
        start: [0.0; AXES],
        cycle: CycleTime::DEFAULT,
        spool_capacity: DEFAULT_SPOOL_CAPACITY,
        steps: Vec::new(),
    };
    for (n, raw) in text.lines().enumerate() {
        let code = raw.split('#').next().unwrap_or("").trim();
        if code.is_empty() {
            continue;
        }
        parse_line(n + 1, code, &mut trace).map_err(|message| TraceError {
            file: file.to_string(),
            line: n + 1,
            message,
        })?;
    }
    Ok(trace)
}

#[cfg(test)]
mod tests {
    use super::*;
    use uoi::AccessError;

    #[test]
    fn spec_example_parses() {
        let text = "@name left-square-corner\nW 1300/1/1/2 i 0            # RESET group 1\nR 1300/1/1/3 i => 1\nLIN X10 Y10\n< LIN X8 Y2\nR 1300/0/20/0 d => 0.5\nPOS => X1 Y2\nQUEUE => 3\nEXEC 25\nCIR ccw X1 Y2 I3 J4 F100 => err State\nR 1300/1/1/1 i => 0x1f\n";
        let t = parse_trace("ex.trace", text).unwrap();
        assert_eq!(t.name.as_deref(), Some("left-square-corner"));
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
