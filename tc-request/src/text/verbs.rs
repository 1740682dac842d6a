//! Requests in trace syntax, one function per verb
//! (docs/trace-format.md, "Requests").

use uoi::{Value, ValueType};

use super::error::TextError;
use super::words::{integer, number, parse_addr, parse_axis, parse_type, parse_words, Allow};
use crate::axes::AXES;
use crate::motion::{ArcDir, Motion};
use crate::request::{Request, MAX_EXEC_CYCLES};

/// Parses one request in trace syntax (`R 1300/0/3/0 i`, `LIN X10`, ...).
pub fn parse_request(text: &str) -> Result<Request, TextError> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    let (verb, rest) = tokens.split_first().ok_or(TextError::EmptyRequest)?;
    let parse = match verb.to_ascii_uppercase().as_str() {
        "W" => write,
        "R" => read,
        "LIN" => lin,
        "RAP" => rap,
        "CIR" => cir,
        "JA" => ja,
        "JS" => js,
        "SSF" => ssf,
        "RS" => rs,
        "EXEC" => exec,
        "POS" => pos,
        "QUEUE" => queue,
        "FEED_ADAPT" => feed_adapt,
        other => return Err(TextError::UnknownRequest(other.into())),
    };
    parse(rest)
}

fn no_more(tokens: &[&str], verb: &str) -> Result<(), TextError> {
    match tokens.first() {
        None => Ok(()),
        Some(t) => Err(TextError::Trailing((*t).into(), verb.into())),
    }
}

/// `W 1300/1/1/8 i 5`.
fn write(rest: &[&str]) -> Result<Request, TextError> {
    let [addr, ty, val] = rest else {
        return Err(TextError::Usage(
            "W needs an address, a type and a value: `W BUS/DEVICE/INDEX/SUB i 5` \
             (`addipos objects` lists the addresses)",
        ));
    };
    let addr = parse_addr(addr)?;
    let value = match parse_type(ty)? {
        ValueType::I32 => Value::I32(integer(val)?),
        ValueType::F64 => Value::F64(number(val)?),
    };
    Ok(Request::Write(addr, value))
}

/// `R 1300/1/1/3 i`.
fn read(rest: &[&str]) -> Result<Request, TextError> {
    let [addr, ty] = rest else {
        return Err(TextError::Usage(
            "R needs an address and a type: `R BUS/DEVICE/INDEX/SUB i` \
             (`addipos objects` lists the addresses)",
        ));
    };
    Ok(Request::Read(parse_addr(addr)?, parse_type(ty)?))
}

const FEED: Allow = Allow {
    centre: false,
    feed: true,
};

/// `LIN X20 Y5 [F600]`.
fn lin(rest: &[&str]) -> Result<Request, TextError> {
    let w = parse_words(rest, FEED)?;
    Ok(Request::Motion(Motion::Lin {
        words: w.axes,
        feed: w.feed,
    }))
}

/// `RAP X20 Y5`.
fn rap(rest: &[&str]) -> Result<Request, TextError> {
    let w = parse_words(rest, FEED)?;
    Ok(Request::Motion(Motion::Rap {
        words: w.axes,
        feed: w.feed,
    }))
}

/// The direction word of `CIR`.
pub fn parse_dir(s: Option<&&str>) -> Result<ArcDir, TextError> {
    match s.map(|s| s.to_ascii_uppercase()).as_deref() {
        Some("CW") => Ok(ArcDir::Cw),
        Some("CCW") => Ok(ArcDir::Ccw),
        _ => Err(TextError::Usage("CIR needs a direction CW or CCW")),
    }
}

/// `CIR CW X30 Y5 I5 J0 [F..]`.
fn cir(rest: &[&str]) -> Result<Request, TextError> {
    let dir = parse_dir(rest.first())?;
    let w = parse_words(
        &rest[1..],
        Allow {
            centre: true,
            feed: true,
        },
    )?;
    Ok(Request::Motion(Motion::Cir {
        dir,
        words: w.axes,
        centre: w.centre,
        feed: w.feed,
    }))
}

/// `JA X10`.
fn ja(rest: &[&str]) -> Result<Request, TextError> {
    let w = parse_words(rest, Allow::AXES)?;
    if w.axes.iter().all(Option::is_none) {
        return Err(TextError::Usage("JA needs at least one axis word"));
    }
    Ok(Request::Motion(Motion::Ja { words: w.axes }))
}

/// `JS X [Y ...]`.
fn js(rest: &[&str]) -> Result<Request, TextError> {
    if rest.is_empty() {
        return Err(TextError::Usage("JS needs at least one axis"));
    }
    let mut axes = [false; AXES];
    for t in rest {
        axes[parse_axis(t)?] = true;
    }
    Ok(Request::Motion(Motion::Js { axes }))
}

/// `SSF X 2001`.
fn ssf(rest: &[&str]) -> Result<Request, TextError> {
    let [axis, func] = rest else {
        return Err(TextError::SsfUsage);
    };
    let axis = parse_axis(axis)?;
    Ok(Request::Motion(Motion::Ssf {
        // An axis index is below AXES (8).
        axis: axis as u8,
        function: integer(func)?,
    }))
}

/// `RS`.
fn rs(rest: &[&str]) -> Result<Request, TextError> {
    no_more(rest, "RS")?;
    Ok(Request::Motion(Motion::Rs))
}

/// `EXEC` / `EXEC 25`; a count up to [`MAX_EXEC_CYCLES`].
fn exec(rest: &[&str]) -> Result<Request, TextError> {
    match rest {
        [] => Ok(Request::Exec(None)),
        [n] => match n.parse::<u64>() {
            Ok(c) if c <= MAX_EXEC_CYCLES => Ok(Request::Exec(Some(c))),
            Ok(_) => Err(TextError::CyclesTooMany((*n).into())),
            Err(_) => Err(TextError::BadCycles((*n).into())),
        },
        _ => Err(TextError::Usage("EXEC takes at most one cycle count")),
    }
}

/// `POS`.
fn pos(rest: &[&str]) -> Result<Request, TextError> {
    no_more(rest, "POS")?;
    Ok(Request::Pos)
}

/// `QUEUE`.
fn queue(rest: &[&str]) -> Result<Request, TextError> {
    no_more(rest, "QUEUE")?;
    Ok(Request::Queue)
}

/// `FEED_ADAPT 1 3`: G11 with RMIN 3; `FEED_ADAPT 0 0`: G10.
fn feed_adapt(rest: &[&str]) -> Result<Request, TextError> {
    let [on, rmin] = rest else {
        return Err(TextError::Usage(
            "FEED_ADAPT needs 0 or 1 and the smallest radius: `FEED_ADAPT 1 0`",
        ));
    };
    let on = match *on {
        "0" => false,
        "1" => true,
        other => return Err(TextError::NotOnOff((*other).into())),
    };
    let rmin = number(rmin)?;
    Ok(Request::FeedAdaption { on, rmin })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_verb() {
        for (text, ok) in [
            ("W 1300/1/1/8 i 5", true),
            ("w 1300/1/1/6 d nan", true),
            ("R 1300/1/1/3 i", true),
            ("LIN X1 Y2 F600", true),
            ("RAP X1", true),
            ("RAP X1 F5", true),
            ("RAP X1 I5", false),
            ("CIR ccw X1 I1 J0", true),
            ("CIR X1", false),
            ("JA X1", true),
            ("JA", false),
            ("JS X Y", true),
            ("JS", false),
            ("SSF Z 2001", true),
            ("SSF Z", false),
            ("RS", true),
            ("RS 1", false),
            ("EXEC", true),
            ("EXEC 5", true),
            ("EXEC -1", false),
            ("EXEC 18446744073709551614", true),
            ("EXEC 18446744073709551615", false),
            ("POS", true),
            ("QUEUE 1", false),
            ("FROB", false),
            ("", false),
        ] {
            assert_eq!(parse_request(text).is_ok(), ok, "{text}");
        }
    }
}
