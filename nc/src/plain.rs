//! The fast path of plain numbers: the value of `10`, `-5.5`, `.5` read
//! by a byte scan, exactly as the number parser reads it (property tests
//! in `expr.rs` and `words.rs` check both agree). Everything else goes
//! through winnow.

/// Powers of ten that are exact doubles.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// A plain number as read: its digits as an integer, how many of them
/// follow the `.`, its sign and its length in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlainNumber {
    /// The digits as an integer (at most 15 digits: below 2^53).
    pub mantissa: u64,
    /// Digits after the `.`.
    pub fraction: usize,
    /// A leading `-`.
    pub negative: bool,
    /// Bytes read.
    pub len: usize,
}

impl PlainNumber {
    /// The value: the digits and the power of ten are exact doubles, so
    /// their quotient is the correctly rounded value, as `str::parse`
    /// gives it.
    pub fn value(&self) -> f64 {
        let m = self.mantissa as f64;
        let v = match self.fraction {
            0 => m,
            f => m / POW10[f],
        };
        if self.negative {
            -v
        } else {
            v
        }
    }

    /// The value of a whole number (read with `whole`: at most 9 digits,
    /// so within u32).
    pub fn whole(&self) -> u32 {
        u32::try_from(self.mantissa).unwrap_or(u32::MAX)
    }
}

/// A plain number at the start of `b`: digits (at most 9 and unsigned
/// when `whole`), or a sign, digits, `.`, digits, at most 15 digits in
/// all; `None` for anything else (the number parser reads it).
pub fn plain_number(b: &[u8], whole: bool) -> Option<PlainNumber> {
    let signed = !whole && matches!(b.first(), Some(b'-' | b'+'));
    let mut k = usize::from(signed);
    let mut mantissa = 0u64;
    let mut digits = 0usize;
    let mut fraction: Option<usize> = None;
    while let Some(&c) = b.get(k) {
        match c {
            b'0'..=b'9' => {
                mantissa = mantissa * 10 + u64::from(c - b'0');
                digits += 1;
                if let Some(f) = fraction.as_mut() {
                    *f += 1;
                }
            }
            b'.' if fraction.is_none() && !whole => fraction = Some(0),
            _ => break,
        }
        k += 1;
        if digits > if whole { 9 } else { 15 } {
            return None;
        }
    }
    (digits > 0).then_some(PlainNumber {
        mantissa,
        fraction: fraction.unwrap_or(0),
        negative: b.first() == Some(&b'-'),
        len: k,
    })
}
