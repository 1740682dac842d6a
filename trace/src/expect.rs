//! The expectation after `=>` and the `<` spool lines of a trace.

use tc_request::text::{parse_dir, parse_f64, parse_int, parse_words, Allow};

/// A line's fault as its message, inside the crate: the reader puts it
/// into a typed [`crate::TraceError`] with the file and line.
pub(crate) type TextResult<T> = Result<T, String>;
use tc_request::Request;
use uoi::{AccessError, ValueType};

use super::model::{Expect, SpoolExpect, SpoolKind};

/// `err NAME`, if the text is one.
fn parse_err(tokens: &[&str]) -> Option<TextResult<Expect>> {
    let (first, rest) = tokens.split_first()?;
    if !first.eq_ignore_ascii_case("err") {
        return None;
    }
    let [name] = rest else {
        return Some(Err("`err` needs one error name".into()));
    };
    Some(
        AccessError::from_name(name)
            .map(Expect::Err)
            .ok_or_else(|| format!("unknown error name `{name}`")),
    )
}

/// Parses what follows `=>` for `req`.
pub(crate) fn parse_expect(req: &Request, text: &str) -> TextResult<Expect> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    if let Some(e) = parse_err(&tokens) {
        return e;
    }
    let single = match tokens.as_slice() {
        [one] => Some(*one),
        _ => None,
    };
    match req {
        Request::Read(_, ty) => {
            let v = single
                .ok_or_else(|| format!("expected one value or `err NAME`, found `{text}`"))?;
            match ty {
                ValueType::I32 => Ok(Expect::Int(parse_int(v)?)),
                ValueType::F64 => Ok(Expect::Double(parse_f64(v)?)),
            }
        }
        Request::Queue => {
            let v = single.ok_or_else(|| format!("expected a count, found `{text}`"))?;
            v.parse::<usize>()
                .map(Expect::Queue)
                .map_err(|_| format!("bad count `{v}`"))
        }
        Request::Pos => {
            let w = parse_words(&tokens, Allow::AXES)?;
            if w.axes.iter().all(Option::is_none) {
                return Err("POS expectation needs axis words like `X10 Y5`".into());
            }
            Ok(Expect::Pos(w.axes))
        }
        _ if single.is_some_and(|t| t.eq_ignore_ascii_case("ok")) => Ok(Expect::Ok),
        _ => Err(format!("expected `ok` or `err NAME`, found `{text}`")),
    }
}

/// Parses a spool line (after `<`): `LIN X.. Y.. [F..]` or
/// `CIR CW|CCW X.. I.. [F..]`.
pub(crate) fn parse_spool(line: usize, text: &str) -> TextResult<SpoolExpect> {
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
    let allow = Allow {
        centre: kind != SpoolKind::Line,
        feed: true,
    };
    let w = parse_words(rest, allow)?;
    Ok(SpoolExpect {
        line,
        kind,
        words: w.axes,
        centre: w.centre,
        feed: w.feed,
    })
}
