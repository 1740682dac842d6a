//! Exact decimal numbers as text: the unit shift between bus and file
//! moves the decimal point instead of multiplying floats.
//!
//! A bus value becomes its shortest round-trip decimal (Rust's `{:e}`),
//! the shift changes only the exponent, and reading undoes the shift on
//! the text before the one correctly rounded parse. The decimal read back
//! is exactly the one written, so the f64 is bit-identical.

/// Exponents beyond this make every f64 infinite or zero; larger ones are
/// clamped so the arithmetic cannot overflow.
const EXPONENT_LIMIT: i64 = 1_000_000_000;

/// The exponent at or above which text is written in scientific form
/// (and at or below `-PLAIN_BELOW`).
const PLAIN_ABOVE: i64 = 21;
/// See [`PLAIN_ABOVE`].
const PLAIN_BELOW: i64 = 7;

/// A decimal number `±digits × 10^exponent`, digits without leading or
/// trailing zeros (zero is the digit `0` with exponent 0).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Decimal {
    negative: bool,
    digits: String,
    exponent: i64,
}

impl Decimal {
    /// The shortest decimal that reads back as `v`; `None` if not finite.
    pub(crate) fn from_f64(v: f64) -> Option<Self> {
        if v.is_finite() {
            Self::parse(&format!("{v:e}"))
        } else {
            None
        }
    }

    /// Parses `[+-]digits[.digits][(e|E)[+-]digits]` with at least one
    /// digit in the mantissa; anything else is `None`.
    pub(crate) fn parse(text: &str) -> Option<Self> {
        let (negative, rest) = match text.as_bytes().first() {
            Some(b'-') => (true, &text[1..]),
            Some(b'+') => (false, &text[1..]),
            _ => (false, text),
        };
        let (mantissa, exp_text) = match rest.find(['e', 'E']) {
            Some(at) => (&rest[..at], Some(&rest[at + 1..])),
            None => (rest, None),
        };
        let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
        if int.len() + frac.len() == 0 || !all_digits(int) || !all_digits(frac) {
            return None;
        }
        let exp = match exp_text {
            Some(t) => parse_exponent(t)?,
            None => 0,
        };
        let frac_len = i64::try_from(frac.len()).unwrap_or(EXPONENT_LIMIT);
        Some(Self::normalised(
            negative,
            format!("{int}{frac}"),
            exp - frac_len,
        ))
    }

    fn normalised(negative: bool, digits: String, exponent: i64) -> Self {
        let lead = digits.trim_start_matches('0');
        let trimmed = lead.trim_end_matches('0');
        if trimmed.is_empty() {
            return Self {
                negative,
                digits: "0".to_owned(),
                exponent: 0,
            };
        }
        let zeros = i64::try_from(lead.len() - trimmed.len()).unwrap_or(0);
        Self {
            negative,
            digits: trimmed.to_owned(),
            exponent: (exponent + zeros).clamp(-4 * EXPONENT_LIMIT, 4 * EXPONENT_LIMIT),
        }
    }

    /// The same number times `10^places`.
    pub(crate) fn shifted(mut self, places: i32) -> Self {
        if self.digits != "0" {
            self.exponent += i64::from(places);
        }
        self
    }

    /// The nearest f64 (correctly rounded; may be infinite or zero).
    pub(crate) fn to_f64(&self) -> f64 {
        let sign = if self.negative { "-" } else { "" };
        format!("{sign}{}e{}", self.digits, self.exponent)
            .parse()
            .unwrap_or(f64::NAN)
    }

    /// The number as text: plain (`300000`, `0.25`) for moderate
    /// magnitudes, scientific (`1.5e-296`) otherwise.
    pub(crate) fn to_text(&self) -> String {
        let sign = if self.negative { "-" } else { "" };
        let d = &self.digits;
        let n = i64::try_from(d.len()).unwrap_or(i64::MAX);
        // Exponent of the leading digit: value = d[0].d[1..] × 10^lead.
        let lead = self.exponent + n - 1;
        let body = if lead >= PLAIN_ABOVE || lead <= -PLAIN_BELOW {
            let (first, rest) = d.split_at(1);
            let dot = if rest.is_empty() { "" } else { "." };
            format!("{first}{dot}{rest}e{lead}")
        } else if self.exponent >= 0 {
            format!(
                "{d}{}",
                "0".repeat(usize::try_from(self.exponent).unwrap_or(0))
            )
        } else if lead >= 0 {
            let split = usize::try_from(lead + 1).unwrap_or(0);
            format!("{}.{}", &d[..split], &d[split..])
        } else {
            let zeros = usize::try_from(-lead - 1).unwrap_or(0);
            format!("0.{}{d}", "0".repeat(zeros))
        };
        format!("{sign}{body}")
    }
}

/// `[+-]digits`, clamped to ±[`EXPONENT_LIMIT`].
fn parse_exponent(text: &str) -> Option<i64> {
    let (negative, digits) = match text.as_bytes().first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let magnitude = digits.bytes().fold(0i64, |acc, b| {
        (acc * 10 + i64::from(b - b'0')).min(EXPONENT_LIMIT)
    });
    Some(if negative { -magnitude } else { magnitude })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(s: &str) -> String {
        Decimal::parse(s).map(|d| d.to_text()).unwrap_or_default()
    }

    #[test]
    fn parse_normalises() {
        assert_eq!(text("000123.4500"), "123.45");
        assert_eq!(text("1.5e3"), "1500");
        assert_eq!(text("+.5"), "0.5");
        assert_eq!(text("5."), "5");
        assert_eq!(text("-0.000"), "-0");
        assert_eq!(text("1E-8"), "1e-8");
        assert_eq!(text("123e20"), "1.23e22");
        assert_eq!(text("0.0000001"), "1e-7");
        assert_eq!(text("0.000001"), "0.000001");
        assert_eq!(text("1e99999999999999999999"), "1e1000000000");
    }

    #[test]
    fn parse_refuses_garbage() {
        for s in [
            "", "-", ".", "e5", "1e", "1e+", "1.2.3", " 1", "1 ", "inf", "NaN", "1,5",
        ] {
            assert_eq!(Decimal::parse(s), None, "{s:?}");
        }
    }

    #[test]
    fn shift_moves_the_point() {
        let d = Decimal::parse("123.456").map(|d| d.shifted(4).to_text());
        assert_eq!(d.as_deref(), Some("1234560"));
        let d = Decimal::parse("1234560").map(|d| d.shifted(-4).to_f64());
        assert_eq!(d, Some(123.456));
        let zero = Decimal::parse("0").map(|d| d.shifted(-4).to_text());
        assert_eq!(zero.as_deref(), Some("0"));
    }

    #[test]
    fn from_f64_is_shortest() {
        let t = |v: f64| Decimal::from_f64(v).map(|d| d.to_text());
        assert_eq!(t(0.1).as_deref(), Some("0.1"));
        assert_eq!(t(-0.0).as_deref(), Some("-0"));
        assert_eq!(t(f64::NAN), None);
        assert_eq!(t(f64::INFINITY), None);
    }
}
