//! The axis words of the motion calls, from Python keywords: `X=50, Y=0`
//! (the 8 axes `X Y Z A B C U V`), `F=6000` (the feed) and, for arcs,
//! `I J K` (the centre seen from the start), as in traces and NC programs.

use addipos_host::{ArcDir, AxisWords, AXES, AXIS_NAMES};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors;

/// The centre offsets of an arc, `I J K`.
const CENTRE_NAMES: [char; 3] = ['I', 'J', 'K'];

/// What a motion call was given.
#[derive(Debug, Default)]
pub struct Words {
    /// The axes named (others keep their programmed value).
    pub axes: AxisWords,
    /// `I J K`.
    pub centre: [Option<f64>; 3],
    /// `F`.
    pub feed: Option<f64>,
}

/// Which words a call takes besides the axes.
#[derive(Debug, Clone, Copy)]
pub struct Allowed {
    /// `F`.
    pub feed: bool,
    /// `I J K`.
    pub centre: bool,
}

/// Reads the keywords of `call`; a keyword that is not a word it takes,
/// or a value that is not a number, is `addipos.Argument`. `None` as a
/// value leaves the word out.
pub fn read(
    py: Python<'_>,
    call: &str,
    kwargs: Option<&Bound<'_, PyDict>>,
    allowed: Allowed,
) -> PyResult<Words> {
    let mut w = Words::default();
    let Some(kwargs) = kwargs else {
        return Ok(w);
    };
    for (key, value) in kwargs.iter() {
        let name: String = key.extract()?;
        if value.is_none() {
            continue;
        }
        let number: f64 = value
            .extract()
            .map_err(|_| errors::argument(py, format!("{call}: {name}={value} is not a number")))?;
        let slot = word_slot(&mut w, &name, allowed).ok_or_else(|| {
            errors::argument(
                py,
                format!("{call}: no word {name}; it takes {}", takes(allowed)),
            )
        })?;
        *slot = Some(number);
    }
    // One rule with the C library: F=0 is the modal feed (as leaving F
    // out); a negative feed is refused by the emulator with Range.
    if w.feed == Some(0.0) {
        w.feed = None;
    }
    Ok(w)
}

/// Where the word `name` goes, if the call takes it.
fn word_slot<'w>(w: &'w mut Words, name: &str, allowed: Allowed) -> Option<&'w mut Option<f64>> {
    let mut chars = name.chars();
    let (Some(c), None) = (chars.next(), chars.next()) else {
        return None;
    };
    if let Some(i) = AXIS_NAMES.iter().position(|&a| a == c) {
        return w.axes.get_mut(i);
    }
    if allowed.centre {
        if let Some(i) = CENTRE_NAMES.iter().position(|&a| a == c) {
            return w.centre.get_mut(i);
        }
    }
    (allowed.feed && c == 'F').then_some(&mut w.feed)
}

/// The words a call takes, for a message.
fn takes(allowed: Allowed) -> String {
    let mut s: String = AXIS_NAMES.iter().map(|c| format!("{c} ")).collect();
    if allowed.centre {
        s.push_str("I J K ");
    }
    if allowed.feed {
        s.push_str("F ");
    }
    s.trim_end().to_string()
}

/// The machine axis of a name (`"X"` .. `"V"`) or a number 0..7.
pub fn axis(py: Python<'_>, call: &str, axis: &Bound<'_, PyAny>) -> PyResult<usize> {
    let found = if let Ok(n) = axis.extract::<i64>() {
        usize::try_from(n).ok().filter(|&n| n < AXES)
    } else if let Ok(name) = axis.extract::<String>() {
        let mut chars = name.chars();
        match (chars.next(), chars.next()) {
            (Some(c), None) => AXIS_NAMES.iter().position(|&a| a == c),
            _ => None,
        }
    } else {
        None
    };
    found.ok_or_else(|| {
        errors::argument(
            py,
            format!("{call}: axis {axis} is not one of X Y Z A B C U V or 0..7"),
        )
    })
}

/// The direction of an arc: `"CW"` or `"CCW"` (also `"G2"`, `"G3"`),
/// in any case.
pub fn arc_dir(py: Python<'_>, dir: &str) -> PyResult<ArcDir> {
    match dir.to_ascii_uppercase().as_str() {
        "CW" | "G2" | "G02" => Ok(ArcDir::Cw),
        "CCW" | "G3" | "G03" => Ok(ArcDir::Ccw),
        _ => Err(errors::argument(
            py,
            format!("cir: direction {dir:?} is not \"CW\" or \"CCW\""),
        )),
    }
}
