//! A spooled element written in trace `<` syntax (docs/trace-format.md):
//! what trace replay reports, the NC runner writes and the host library
//! records.

use std::fmt::Write as _;

use crate::axes::AXIS_NAMES;
use crate::element::SpoolRecord;

/// The offset of an arc's centre from its start along machine axis `m`,
/// if `m` is one of its plane axes.
pub fn centre_offset(e: &SpoolRecord, m: u8) -> Option<f64> {
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
    let mut s = String::with_capacity(64);
    match &e.arc {
        None => s.push_str("LIN"),
        Some(a) => s.push_str(if a.ccw { "CIR CCW" } else { "CIR CW" }),
    }
    for (i, name) in AXIS_NAMES.iter().enumerate() {
        if e.end[i] != e.start[i] || i < 2 {
            push_word(&mut s, name, e.end[i]);
        }
    }
    for (letter, &m) in ['I', 'J', 'K'].iter().zip(&axis_nr) {
        if let Some(o) = centre_offset(e, m) {
            push_word(&mut s, letter, o);
        }
    }
    s
}

/// [`format_record`] with the element's feed (`F..`), as `addipos run`
/// prints and writes it.
pub fn format_record_fed(e: &SpoolRecord, axis_nr: [u8; 3]) -> String {
    let mut s = format_record(e, axis_nr);
    push_word(&mut s, 'F', e.feed);
    s
}

/// ` X10`: a word with its value as `f64`'s `Display` writes it; a whole
/// number by the integer path, which writes the same digits faster (the
/// spool lines of a long NC run are mostly such numbers).
fn push_word(s: &mut String, letter: impl std::fmt::Display, v: f64) {
    let _ = write!(s, " {letter}");
    let whole = v.fract() == 0.0 && v.abs() < 1e15 && (v != 0.0 || v.is_sign_positive());
    if whole {
        // Exact: |v| < 1e15 is an integer below 2^53.
        let _ = write!(s, "{}", v as i64);
    } else {
        let _ = write!(s, "{v}");
    }
}

#[cfg(test)]
mod tests {
    use super::push_word;

    /// The integer path writes exactly what `f64`'s `Display` writes.
    #[test]
    fn whole_numbers_are_written_as_display_writes_them() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            6000.0,
            1e14,
            -1e14,
            999999999999999.0,
            1e15,
            0.5,
            -2.25,
        ] {
            let mut s = String::new();
            push_word(&mut s, 'X', v);
            assert_eq!(s, format!(" X{v}"), "{v}");
        }
    }
}
