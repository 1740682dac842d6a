//! Requests written back in trace syntax: what `parse_request` reads.

use std::fmt;

use crate::axes::{AxisWords, AXIS_NAMES};
use crate::motion::Motion;
use crate::request::Request;

/// Writes ` X1 Y2` for the named axes.
pub fn write_axis_words(f: &mut impl fmt::Write, words: &AxisWords) -> fmt::Result {
    for (name, w) in AXIS_NAMES.iter().zip(words) {
        if let Some(v) = w {
            write!(f, " {name}{v}")?;
        }
    }
    Ok(())
}

/// Writes ` I1 J2` for the given letters' values that are present.
pub fn write_letters(
    f: &mut impl fmt::Write,
    letters: &[char],
    values: &[Option<f64>],
) -> fmt::Result {
    for (l, v) in letters.iter().zip(values) {
        if let Some(v) = v {
            write!(f, " {l}{v}")?;
        }
    }
    Ok(())
}

fn axis_name(axis: u8) -> String {
    AXIS_NAMES
        .get(usize::from(axis))
        .map_or_else(|| format!("#{axis}"), char::to_string)
}

impl fmt::Display for Motion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Motion::Lin { words, feed } | Motion::Rap { words, feed } => {
                f.write_str(if matches!(self, Motion::Lin { .. }) {
                    "LIN"
                } else {
                    "RAP"
                })?;
                write_axis_words(f, words)?;
                write_letters(f, &['F'], &[*feed])
            }
            Motion::Cir {
                dir,
                words,
                centre,
                feed,
            } => {
                write!(f, "CIR {}", dir.keyword())?;
                write_axis_words(f, words)?;
                write_letters(f, &['I', 'J', 'K'], centre)?;
                write_letters(f, &['F'], &[*feed])
            }
            Motion::Ja { words } => {
                f.write_str("JA")?;
                write_axis_words(f, words)
            }
            Motion::Js { axes } => {
                f.write_str("JS")?;
                for (name, _) in AXIS_NAMES.iter().zip(axes).filter(|(_, on)| **on) {
                    write!(f, " {name}")?;
                }
                Ok(())
            }
            Motion::Ssf { axis, function } => write!(f, "SSF {} {function}", axis_name(*axis)),
            Motion::Rs => f.write_str("RS"),
        }
    }
}

impl fmt::Display for Request {
    /// Trace syntax; the emulator-control ops, which traces do not hold,
    /// are written as their wire names.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Request::Read(a, ty) => write!(f, "R {a} {ty}"),
            Request::Write(a, v) => write!(f, "W {a} {} {v}", v.value_type()),
            Request::Motion(m) => m.fmt(f),
            Request::Exec(None) => f.write_str("EXEC"),
            Request::Exec(Some(n)) => write!(f, "EXEC {n}"),
            Request::Pos => f.write_str("POS"),
            Request::Queue => f.write_str("QUEUE"),
            Request::FeedAdaption { on, rmin } => {
                write!(f, "FEED_ADAPT {} {rmin}", u8::from(*on))
            }
            Request::Setup { .. } => f.write_str("SETUP"),
            Request::SpoolLog { logging } => write!(f, "SPOOL_LOG {}", u8::from(*logging)),
        }
    }
}
