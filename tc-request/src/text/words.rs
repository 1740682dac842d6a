//! The words of the trace syntax: numbers, addresses, type letters and
//! the axis words of a motion line.

use uoi::{ObjectAddress, ValueType};

use super::error::TextError;
use crate::axes::{axis_index, AxisWords};

/// A text error kept as its message: the integer and number readers'
/// results ([`parse_int`], [`parse_f64`]), which the trace reader returns
/// as its own; every other reader here returns a [`TextError`].
pub type TextResult<T> = Result<T, String>;

/// Parses an integer: decimal or `0x` hex digits, with at most one sign,
/// before the digits or before `0x` (`-5`, `+0x1f`, `-0x10`). Hex values
/// up to `0xffffffff` without `-` are read as the i32 with that bit
/// pattern; anything else outside the i32 range is an error.
pub fn parse_int(s: &str) -> TextResult<i32> {
    Ok(integer(s)?)
}

/// An integer, as [`parse_int`] reads it.
pub(super) fn integer(s: &str) -> Result<i32, TextError> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let (digits, radix) = match body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        Some(h) => (h, 16),
        None => (body, 10),
    };
    // Digits only: `from_str_radix` would take one more sign after `0x`.
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return Err(TextError::BadInteger(s.into()));
    }
    let out_of_range = || TextError::IntegerOutOfRange(s.into());
    let mag = u64::from_str_radix(digits, radix).map_err(|_| out_of_range())?;
    if !neg && radix == 16 {
        if let Ok(bits) = u32::try_from(mag) {
            return Ok(i32::from_ne_bytes(bits.to_ne_bytes()));
        }
    }
    let v = if neg {
        -i128::from(mag)
    } else {
        i128::from(mag)
    };
    i32::try_from(v).map_err(|_| out_of_range())
}

/// Parses a double (`inf`, `-inf`, `nan` allowed, to test rejection).
pub fn parse_f64(s: &str) -> TextResult<f64> {
    Ok(number(s)?)
}

/// A double, as [`parse_f64`] reads it.
pub(super) fn number(s: &str) -> Result<f64, TextError> {
    let ok_chars = s
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E'));
    let special = matches!(
        s.to_ascii_lowercase().as_str(),
        "inf" | "-inf" | "+inf" | "nan" | "-nan" | "+nan" | "infinity" | "-infinity"
    );
    if !(ok_chars || special) {
        return Err(TextError::BadNumber(s.into()));
    }
    s.parse::<f64>().map_err(|_| TextError::BadNumber(s.into()))
}

/// Parses an object address `1300/1/2/8`.
pub fn parse_addr(s: &str) -> Result<ObjectAddress, TextError> {
    Ok(s.parse()?)
}

/// Parses a type letter `i` or `d`.
pub fn parse_type(s: &str) -> Result<ValueType, TextError> {
    ValueType::from_letter(s).ok_or_else(|| TextError::BadType(s.into()))
}

/// Parses a lone axis letter (`X`, as in `JS X` or `SSF X 2001`).
pub fn parse_axis(s: &str) -> Result<usize, TextError> {
    let mut c = s.chars();
    match (c.next(), c.next()) {
        (Some(l), None) => axis_index(l),
        _ => None,
    }
    .ok_or_else(|| TextError::BadAxis(s.into()))
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
pub fn parse_words(tokens: &[&str], allow: Allow) -> Result<Words, TextError> {
    let mut w = Words::default();
    for tok in tokens {
        let mut chars = tok.chars();
        let letter = chars.next().ok_or(TextError::EmptyWord)?;
        let num = chars.as_str();
        let up = letter.to_ascii_uppercase();
        let slot: &mut Option<f64> = match (axis_index(letter), up) {
            (Some(i), _) => &mut w.axes[i],
            (None, 'I' | 'J' | 'K') if allow.centre => &mut w.centre[usize::from(up as u8 - b'I')],
            (None, 'F') if allow.feed => &mut w.feed,
            _ => return Err(TextError::UnexpectedWord((*tok).into())),
        };
        if slot.is_some() {
            return Err(TextError::WordTwice(letter));
        }
        if num.is_empty() {
            return Err(TextError::NoNumber((*tok).into()));
        }
        *slot = Some(number(num)?);
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
    fn integer_edges_and_signs() {
        for (text, want) in [
            ("2147483647", Some(i32::MAX)),
            ("-2147483648", Some(i32::MIN)),
            ("+2147483647", Some(i32::MAX)),
            ("2147483648", None),
            ("-2147483649", None),
            ("0x7fffffff", Some(i32::MAX)),
            ("0x80000000", Some(i32::MIN)),
            ("-0x80000000", Some(i32::MIN)),
            ("-0x80000001", None),
            ("-0xffffffff", None),
            ("+0xffffffff", Some(-1)),
            ("0X1F", Some(31)),
            ("-0x1f", Some(-31)),
            ("0x100000000", None),
            ("9223372036854775807", None),
            ("-9223372036854775808", None),
            ("-9223372036854775809", None),
            ("0x7fffffffffffffff", None),
            ("-0x8000000000000000", None),
            ("0xffffffffffffffff", None),
            ("0x10000000000000000", None),
            ("-0x-8000000000000000", None),
            ("-0x-1", None),
            ("0x-1", None),
            ("0x+1f", None),
            ("+0x+1", None),
            ("--5", None),
            ("+-5", None),
            ("-+5", None),
            ("5-", None),
            ("0x", None),
            ("-", None),
            ("-0x", None),
            ("0x 1", None),
            ("١٢", None),
        ] {
            assert_eq!(parse_int(text).ok(), want, "{text:?}");
        }
        assert!(parse_int("0x-1").unwrap_err().contains("bad integer"));
        assert!(parse_int("-0x80000001")
            .unwrap_err()
            .contains("out of range"));
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
