//! The words of the trace syntax: numbers, addresses, type letters and
//! the axis words of a motion line.

use uoi::{ObjectAddress, ValueType};

use crate::axes::{axis_index, AxisWords};

/// What is wrong with a piece of text (a message for the user).
pub type TextResult<T> = Result<T, String>;

/// Parses an integer: decimal or `0x` hex, optionally signed. Hex values
/// up to `0xffffffff` are read as the i32 with that bit pattern.
pub fn parse_int(s: &str) -> TextResult<i32> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let hex = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X"));
    let mag: i64 = match hex {
        Some(h) => i64::from_str_radix(h, 16).map_err(|_| format!("bad integer `{s}`"))?,
        None if !body.is_empty() && body.bytes().all(|b| b.is_ascii_digit()) => body
            .parse()
            .map_err(|_| format!("integer `{s}` out of range"))?,
        None => return Err(format!("bad integer `{s}`")),
    };
    if !neg && hex.is_some() && (0..=0xffff_ffff).contains(&mag) {
        return Ok(mag as u32 as i32);
    }
    let v = if neg { -mag } else { mag };
    i32::try_from(v).map_err(|_| format!("integer `{s}` out of range"))
}

/// Parses a double (`inf`, `-inf`, `nan` allowed, to test rejection).
pub fn parse_f64(s: &str) -> TextResult<f64> {
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

/// Parses an object address `1300/1/2/8`.
pub fn parse_addr(s: &str) -> TextResult<ObjectAddress> {
    s.parse().map_err(|e: uoi::AddressParseError| e.to_string())
}

/// Parses a type letter `i` or `d`.
pub fn parse_type(s: &str) -> TextResult<ValueType> {
    ValueType::from_letter(s).ok_or_else(|| format!("bad type `{s}` (want i or d)"))
}

/// Parses a lone axis letter (`X`, as in `JS X` or `SSF X 2001`).
pub fn parse_axis(s: &str) -> TextResult<usize> {
    let mut c = s.chars();
    match (c.next(), c.next()) {
        (Some(l), None) => axis_index(l),
        _ => None,
    }
    .ok_or_else(|| format!("bad axis `{s}`"))
}

/// The words of a motion line: axis letters, `I J K`, `F`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Words {
    /// Axis words.
    pub axes: AxisWords,
    /// `I J K`.
    pub centre: [Option<f64>; 3],
    /// `F`.
    pub feed: Option<f64>,
}

/// Which words besides the axes a line may carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Allow {
    /// `I J K`.
    pub centre: bool,
    /// `F`.
    pub feed: bool,
}

impl Allow {
    /// Axis words only.
    pub const AXES: Allow = Allow {
        centre: false,
        feed: false,
    };
}

/// Parses axis words (`X10 Y-2.5`), and `I J K` / `F` where allowed. A
/// word given twice, or one without a number, is an error.
pub fn parse_words(tokens: &[&str], allow: Allow) -> TextResult<Words> {
    let mut w = Words::default();
    for tok in tokens {
        let mut chars = tok.chars();
        let letter = chars.next().ok_or("empty word")?;
        let num = chars.as_str();
        let up = letter.to_ascii_uppercase();
        let slot: &mut Option<f64> = match (axis_index(letter), up) {
            (Some(i), _) => &mut w.axes[i],
            (None, 'I' | 'J' | 'K') if allow.centre => &mut w.centre[usize::from(up as u8 - b'I')],
            (None, 'F') if allow.feed => &mut w.feed,
            _ => return Err(format!("unexpected word `{tok}`")),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_int("0x1f"), Ok(31));
        assert_eq!(parse_int("-5"), Ok(-5));
        assert_eq!(parse_int("+5"), Ok(5));
        assert_eq!(parse_int("0xffffffff"), Ok(-1));
        assert!(parse_int("99999999999").is_err());
        assert!(parse_int("0x1ffffffff").is_err());
        assert!(parse_int("").is_err());
        assert!(parse_f64("nan").is_ok_and(f64::is_nan));
        assert_eq!(parse_f64("-inf"), Ok(f64::NEG_INFINITY));
        assert!(parse_f64("1.2.3").is_err());
        assert!(parse_f64("1x").is_err());
    }

    #[test]
    fn words() {
        let w = parse_words(
            &["X1", "i2", "F3"],
            Allow {
                centre: true,
                feed: true,
            },
        );
        let w = w.unwrap_or_default();
        assert_eq!(
            (w.axes[0], w.centre[0], w.feed),
            (Some(1.0), Some(2.0), Some(3.0))
        );
        assert!(parse_words(&["X1", "X2"], Allow::AXES).is_err());
        assert!(parse_words(&["I1"], Allow::AXES).is_err());
        assert!(parse_words(&["X"], Allow::AXES).is_err());
        assert_eq!(parse_axis("v"), Ok(7));
        assert!(parse_axis("XY").is_err());
    }
}
