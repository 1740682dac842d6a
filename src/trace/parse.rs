//! The trace parser: text to [`Trace`], with a `file:line` error for any
//! malformed line and no panic on any input.

use std::fmt;

use tc_module::motion::SSF_FLUSH;
use tc_module::plane::axis_index;
use tc_module::{ArcDir, AxisPos, AxisWords, Motion, AXES};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

/// A malformed trace line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct TraceError {
    /// The trace file.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// One request of a trace.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// `W addr type value`.
    Write(ObjectAddress, Value),
    /// `R addr type`.
    Read(ObjectAddress, ValueType),
    /// `LIN`, `RAP`, `CIR`, `JA`, `JS`, `SSF`, `RS`.
    Motion(Motion),
    /// `EXEC` (until empty) or `EXEC n` (n cycles).
    Exec(Option<u64>),
    /// `POS`.
    Pos,
    /// `QUEUE`.
    Queue,
}

/// What the controller must answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Expect {
    /// No `=>`: the request must succeed; the answer is not checked.
    Success,
    /// `=> ok`.
    Ok,
    /// `=> err NAME`.
    Err(AccessError),
    /// `=> 5` / `=> 0x1f` for an `i` read.
    Int(i32),
    /// `=> 2.5` for a `d` read, within `@tol`.
    Double(f64),
    /// `=> X.. Y..` for `POS`: named axes within `@tol`.
    Pos(AxisWords),
    /// `=> n` for `QUEUE`.
    Queue(usize),
}

/// Line or arc in a spool expectation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpoolKind {
    /// `< LIN` (or `< RAP`).
    Line,
    /// `< CIR CW|CCW`.
    Arc(ArcDir),
}

/// One `<` line: an element the request must have spooled.
#[derive(Debug, Clone, PartialEq)]
pub struct SpoolExpect {
    /// Line number.
    pub line: usize,
    /// Line or arc.
    pub kind: SpoolKind,
    /// End point words; unnamed axes keep the element's start value.
    pub words: AxisWords,
    /// Centre offsets I J K from the element's start.
    pub centre: [Option<f64>; 3],
}

/// One request with its expectations.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Line number of the request.
    pub line: usize,
    /// The request text (comment stripped).
    pub text: String,
    /// The request.
    pub request: Request,
    /// The answer expected.
    pub expect: Expect,
    /// The complete list of elements it must spool.
    pub spool: Vec<SpoolExpect>,
}

/// A parsed trace.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// The file it came from.
    pub file: String,
    /// `@name`.
    pub name: Option<String>,
    /// `@tol`: absolute tolerance for doubles.
    pub tol: f64,
    /// `@start`: initial machine position.
    pub start: AxisPos,
    /// `@cycle` in seconds.
    pub cycle_s: f64,
    /// The requests.
    pub steps: Vec<Step>,
}

impl fmt::Display for SpoolExpect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            SpoolKind::Line => write!(f, "LIN")?,
            SpoolKind::Arc(d) => write!(f, "CIR {}", d.keyword())?,
        }
        for (i, w) in self.words.iter().enumerate() {
            if let Some(v) = w {
                write!(f, " {}{}", tc_module::AXIS_NAMES[i], v)?;
            }
        }
        for (l, c) in ['I', 'J', 'K'].iter().zip(self.centre) {
            if let Some(v) = c {
                write!(f, " {l}{v}")?;
            }
        }
        Ok(())
    }
}

type Res<T> = Result<T, String>;

/// Parses an integer: decimal or `0x` hex, optionally negative.
fn parse_int(s: &str) -> Res<i32> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let mag: i64 = if let Some(hex) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        i64::from_str_radix(hex, 16).map_err(|_| format!("bad integer `{s}`"))?
    } else if !body.is_empty() && body.bytes().all(|b| b.is_ascii_digit()) {
        body.parse()
            .map_err(|_| format!("integer `{s}` out of range"))?
    } else {
        return Err(format!("bad integer `{s}`"));
    };
    let v = if neg { -mag } else { mag };
    // Hex values up to 0xffffffff are read as the i32 with that bit pattern.
    if !neg
        && body.len() > 2
        && (body.starts_with("0x") || body.starts_with("0X"))
        && (0..=0xffff_ffff).contains(&v)
    {
        return Ok(v as u32 as i32);
    }
    i32::try_from(v).map_err(|_| format!("integer `{s}` out of range"))
}

/// Parses a double (`inf`, `-inf`, `nan` allowed).
fn parse_f64(s: &str) -> Res<f64> {
    let ok_chars = s
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E'));
    let special = matches!(
        s.to_ascii_lowercase().as_str(),
        "inf" | "-inf" | "+inf" | "nan" | "-nan" | "+nan" | "infinity" | "-infinity"
    );
    if !(ok_chars || special) {
        return Err(format!("bad number `{s}`"));
    }
    s.parse::<f64>().map_err(|_| format!("bad number `{s}`"))
}

fn parse_addr(s: &str) -> Res<ObjectAddress> {
    s.parse().map_err(|e: uoi::AddressParseError| e.to_string())
}

fn parse_type(s: &str) -> Res<ValueType> {
    ValueType::from_letter(s).ok_or_else(|| format!("bad type `{s}` (want i or d)"))
}

/// Words of a motion line: axis letters, I J K, F.
#[derive(Default)]
struct Words {
    axes: AxisWords,
    centre: [Option<f64>; 3],
    feed: Option<f64>,
}

fn parse_words(tokens: &[&str], allow_centre: bool, allow_feed: bool) -> Res<Words> {
    let mut w = Words::default();
    for tok in tokens {
        let mut chars = tok.chars();
        let letter = chars.next().ok_or("empty word")?;
        let num = chars.as_str();
        let slot: &mut Option<f64> = if let Some(i) = axis_index(letter) {
            &mut w.axes[i]
        } else {
            match letter.to_ascii_uppercase() {
                'I' | 'J' | 'K' if allow_centre => {
                    let k = (letter.to_ascii_uppercase() as u8 - b'I') as usize;
                    &mut w.centre[k]
                }
                'F' if allow_feed => &mut w.feed,
                _ => return Err(format!("unexpected word `{tok}`")),
            }
        };
        if slot.is_some() {
            return Err(format!("word `{letter}` given twice"));
        }
        if num.is_empty() {
            return Err(format!("word `{tok}` has no number"));
        }
        *slot = Some(parse_f64(num)?);
    }
    Ok(w)
}

fn parse_dir(s: Option<&&str>) -> Res<ArcDir> {
    match s.map(|s| s.to_ascii_uppercase()) {
        Some(d) if d == "CW" => Ok(ArcDir::Cw),
        Some(d) if d == "CCW" => Ok(ArcDir::Ccw),
        _ => Err("CIR needs a direction CW or CCW".into()),
    }
}

fn no_more(tokens: &[&str], verb: &str) -> Res<()> {
    match tokens.first() {
        None => Ok(()),
        Some(t) => Err(format!("unexpected `{t}` after {verb}")),
    }
}

/// Parses one request in trace syntax (`R 1300/0/3/0 i`, `LIN X10`, ...).
pub fn parse_request(text: &str) -> Result<Request, String> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    let (verb, rest) = tokens.split_first().ok_or("empty request")?;
    let verb = verb.to_ascii_uppercase();
    Ok(match verb.as_str() {
        "W" => {
            let [addr, ty, val] = rest else {
                return Err("W needs an address, a type and a value: `W 1300/1/1/8 i 5`".into());
            };
            let addr = parse_addr(addr)?;
            let value = match parse_type(ty)? {
                ValueType::I32 => Value::I32(parse_int(val)?),
                ValueType::F64 => Value::F64(parse_f64(val)?),
            };
            Request::Write(addr, value)
        }
        "R" => {
            let [addr, ty] = rest else {
                return Err("R needs an address and a type: `R 1300/1/1/3 i`".into());
            };
            Request::Read(parse_addr(addr)?, parse_type(ty)?)
        }
        "LIN" | "RAP" => {
            let w = parse_words(rest, false, true)?;
            Request::Motion(Motion::Lin {
                words: w.axes,
                feed: w.feed,
                rapid: verb == "RAP",
            })
        }
        "CIR" => {
            let dir = parse_dir(rest.first())?;
            let w = parse_words(&rest[1..], true, true)?;
            Request::Motion(Motion::Cir {
                dir,
                words: w.axes,
                centre: w.centre,
                feed: w.feed,
            })
        }
        "JA" => {
            let w = parse_words(rest, false, false)?;
            if w.axes.iter().all(Option::is_none) {
                return Err("JA needs at least one axis word".into());
            }
            Request::Motion(Motion::Ja { words: w.axes })
        }
        "JS" => {
            let mut axes = [false; AXES];
            if rest.is_empty() {
                return Err("JS needs at least one axis".into());
            }
            for t in rest {
                let mut c = t.chars();
                let i = match (c.next(), c.next()) {
                    (Some(l), None) => axis_index(l),
                    _ => None,
                }
                .ok_or_else(|| format!("bad axis `{t}`"))?;
                axes[i] = true;
            }
            Request::Motion(Motion::Js { axes })
        }
        "SSF" => {
            let [axis, func] = rest else {
                return Err(format!(
                    "SSF needs an axis and a function: `SSF X {SSF_FLUSH}`"
                ));
            };
            let mut c = axis.chars();
            let axis = match (c.next(), c.next()) {
                (Some(l), None) => axis_index(l),
                _ => None,
            }
            .ok_or_else(|| format!("bad axis `{axis}`"))?;
            Request::Motion(Motion::Ssf {
                axis: axis as u8,
                function: parse_int(func)?,
            })
        }
        "RS" => {
            no_more(rest, "RS")?;
            Request::Motion(Motion::Rs)
        }
        "EXEC" => match rest {
            [] => Request::Exec(None),
            [n] => Request::Exec(Some(
                n.parse::<u64>()
                    .map_err(|_| format!("bad cycle count `{n}`"))?,
            )),
            _ => return Err("EXEC takes at most one cycle count".into()),
        },
        "POS" => {
            no_more(rest, "POS")?;
            Request::Pos
        }
        "QUEUE" => {
            no_more(rest, "QUEUE")?;
            Request::Queue
        }
        _ => return Err(format!("unknown request `{verb}`")),
    })
}

fn parse_expect(req: &Request, text: &str) -> Res<Expect> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    if let [first, rest @ ..] = tokens.as_slice() {
        if first.eq_ignore_ascii_case("err") {
            let [name] = rest else {
                return Err("`err` needs one error name".into());
            };
            return AccessError::from_name(name)
                .map(Expect::Err)
                .ok_or_else(|| format!("unknown error name `{name}`"));
        }
    }
    let single = match tokens.as_slice() {
        [one] => Some(*one),
        _ => None,
    };
    let is_ok = single.is_some_and(|t| t.eq_ignore_ascii_case("ok"));
    match req {
        Request::Write(..) | Request::Motion(_) | Request::Exec(_) => {
            if is_ok {
                Ok(Expect::Ok)
            } else {
                Err(format!("expected `ok` or `err NAME`, found `{text}`"))
            }
        }
        Request::Read(_, ty) => {
            let v = single
                .ok_or_else(|| format!("expected one value or `err NAME`, found `{text}`"))?;
            match ty {
                ValueType::I32 => parse_int(v).map(Expect::Int),
                ValueType::F64 => parse_f64(v).map(Expect::Double),
            }
        }
        Request::Queue => {
            let v = single.ok_or_else(|| format!("expected a count, found `{text}`"))?;
            v.parse::<usize>()
                .map(Expect::Queue)
                .map_err(|_| format!("bad count `{v}`"))
        }
        Request::Pos => {
            let w = parse_words(&tokens, false, false)?;
            if w.axes.iter().all(Option::is_none) {
                return Err("POS expectation needs axis words like `X10 Y5`".into());
            }
            Ok(Expect::Pos(w.axes))
        }
    }
}

fn parse_spool(line: usize, text: &str) -> Res<SpoolExpect> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    let (verb, rest) = tokens
        .split_first()
        .ok_or("empty spool line (want `< LIN ...` or `< CIR ...`)")?;
    let verb = verb.to_ascii_uppercase();
    let (kind, rest) = match verb.as_str() {
        "LIN" | "RAP" => (SpoolKind::Line, rest),
        "CIR" => (SpoolKind::Arc(parse_dir(rest.first())?), &rest[1..]),
        _ => return Err(format!("a spool line holds LIN or CIR, found `{verb}`")),
    };
    let w = parse_words(rest, kind != SpoolKind::Line, false)?;
    Ok(SpoolExpect {
        line,
        kind,
        words: w.axes,
        centre: w.centre,
    })
}

fn parse_cycle(s: &str) -> Res<f64> {
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
    if v.is_finite() && v > 0.0 {
        Ok(v * scale)
    } else {
        Err(format!("cycle must be positive, found `{s}`"))
    }
}

/// Parses the text of a trace. `file` names it in errors.
pub fn parse_trace(file: &str, text: &str) -> Result<Trace, TraceError> {
    let mut trace = Trace {
        file: file.to_string(),
        name: None,
        tol: 1e-6,
        start: [0.0; AXES],
        cycle_s: 1e-3,
        steps: Vec::new(),
    };
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let err = |message: String| TraceError {
            file: file.to_string(),
            line,
            message,
        };
        let code = raw.split('#').next().unwrap_or("").trim();
        if code.is_empty() {
            continue;
        }
        if let Some(header) = code.strip_prefix('@') {
            if !trace.steps.is_empty() {
                return Err(err("header lines must come before the first request".into()));
            }
            let (key, value) = header
                .split_once(char::is_whitespace)
                .unwrap_or((header, ""));
            let value = value.trim();
            match key.to_ascii_lowercase().as_str() {
                "name" => trace.name = Some(value.to_string()),
                "tol" => {
                    let t = parse_f64(value).map_err(err)?;
                    if !(t.is_finite() && t >= 0.0) {
                        return Err(err(format!(
                            "tolerance must be finite and >= 0, found `{value}`"
                        )));
                    }
                    trace.tol = t;
                }
                "start" => {
                    let tokens: Vec<&str> = value.split_whitespace().collect();
                    let w = parse_words(&tokens, false, false).map_err(err)?;
                    for (p, v) in trace.start.iter_mut().zip(w.axes) {
                        if let Some(v) = v {
                            if !v.is_finite() {
                                return Err(err("start position must be finite".into()));
                            }
                            *p = v;
                        }
                    }
                }
                "cycle" => trace.cycle_s = parse_cycle(value).map_err(err)?,
                other => return Err(err(format!("unknown header `@{other}`"))),
            }
            continue;
        }
        if let Some(spool) = code.strip_prefix('<') {
            let step = trace
                .steps
                .last_mut()
                .ok_or_else(|| err("a spool line `<` must follow a request".into()))?;
            step.spool.push(parse_spool(line, spool).map_err(err)?);
            continue;
        }
        let (req_text, expect_text) = match code.split_once("=>") {
            Some((r, e)) => (r.trim(), Some(e.trim())),
            None => (code, None),
        };
        let request = parse_request(req_text).map_err(err)?;
        let expect = match expect_text {
            None => Expect::Success,
            Some(e) => parse_expect(&request, e).map_err(err)?,
        };
        trace.steps.push(Step {
            line,
            text: req_text.to_string(),
            request,
            expect,
            spool: Vec::new(),
        });
    }
    Ok(trace)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn numbers() {
        assert_eq!(parse_int("0x1f"), Ok(31));
        assert_eq!(parse_int("-5"), Ok(-5));
        assert_eq!(parse_int("0xffffffff"), Ok(-1));
        assert!(parse_int("99999999999").is_err());
        assert!(parse_f64("nan").unwrap().is_nan());
        assert_eq!(parse_f64("-inf"), Ok(f64::NEG_INFINITY));
        assert!(parse_f64("1.2.3").is_err());
        assert_eq!(parse_cycle("250us"), Ok(250e-6));
        assert_eq!(parse_cycle("2 ms"), Ok(2e-3));
    }
}
