//! Address words: G, axes, I J K, F D T M, and assignments.

use winnow::ascii::space0;
use winnow::combinator::{cut_err, preceded};
use winnow::error::{StrContext, StrContextValue};
use winnow::token::any;
use winnow::{ModalResult, Parser};

use crate::expr::{expr, integer, var, word_value, Expr, Var};
use crate::model::{Axis, CentreAxis, GCode, Item};
use crate::plain::{plain_number, PlainNumber};
use crate::refusal::refuse;

fn expected(text: &'static str) -> StrContext {
    StrContext::Expected(StrContextValue::Description(text))
}

/// One address word or assignment at the input's start.
#[inline]
pub fn word(i: &mut &str) -> ModalResult<Item> {
    let bytes = i.as_bytes();
    let Some(letter) = bytes.first().map(u8::to_ascii_uppercase) else {
        return refuse("address: a word is missing");
    };
    let second = bytes.get(1).copied();
    match letter {
        b'R' if !is_assignment(bytes) => valued(i, Item::ArcRadius),
        b'R' | b'P' if second.is_some_and(|c| c.is_ascii_digit()) => assignment(i),
        b'V' if second == Some(b'.') => assignment(i),
        b'G' => g_word(i),
        b'M' => preceded(any, cut_err(integer).context(expected("an M number")))
            .map(Item::M)
            .parse_next(i),
        b'F' => valued(i, Item::Feed),
        b'D' => valued(i, Item::ToolData),
        b'T' => valued(i, Item::Tool),
        b'I' => valued(i, |v| Item::Centre(CentreAxis::I, v)),
        b'J' => valued(i, |v| Item::Centre(CentreAxis::J, v)),
        b'K' => valued(i, |v| Item::Centre(CentreAxis::K, v)),
        b'N' => refuse("block number: N is allowed only at the start of a block"),
        _ => match Axis::from_letter(char::from(letter)) {
            Some(axis) => valued(i, |v| Item::Axis(axis, v)),
            None => refuse("address: not an address of this controller"),
        },
    }
}

/// Whether the `R` word at the start of `bytes` is a parameter
/// assignment (`R1 = 5`, `R12=R1*2`): digits, spaces, then `=`. Any
/// other `R` is the radius of an arc (`R10`, `R-5`, `R[R1*2]`).
fn is_assignment(bytes: &[u8]) -> bool {
    let digits = bytes[1..].iter().take_while(|c| c.is_ascii_digit()).count();
    if digits == 0 {
        return false;
    }
    let rest = &bytes[1 + digits..];
    let spaces = rest
        .iter()
        .take_while(|c| **c == b' ' || **c == b'\t')
        .count();
    rest.get(spaces) == Some(&b'=')
}

/// The common words `X10`, `Y-5.5`, `G1`, `M30`: an address letter and a
/// plain number of at most 15 digits, recognised by a byte scan and pushed
/// onto `items` (the hot path of long programs; a property test checks it
/// reads exactly what [`word`] reads), or only recognised when `items` is
/// `None` (a check pass). False, with `i` unchanged, for anything else:
/// the general [`word`] reads it and reports what is wrong.
#[inline]
pub fn plain_word(i: &mut &str, items: Option<&mut Vec<Item>>) -> bool {
    let b = i.as_bytes();
    let Some(letter) = b.first().map(u8::to_ascii_uppercase) else {
        return false;
    };
    if !letter.is_ascii_alphabetic() || matches!(letter, b'R' | b'P' | b'N') {
        return false;
    }
    let whole = matches!(letter, b'G' | b'M');
    let Some(n) = plain_number(&b[1..], whole) else {
        return false;
    };
    let g = if letter == b'G' {
        GCode::from_number(n.whole())
    } else {
        None
    };
    let axis = if whole {
        None
    } else {
        Axis::from_letter(char::from(letter))
    };
    let known = match letter {
        b'G' => g.is_some(),
        b'M' | b'F' | b'D' | b'T' | b'I' | b'J' | b'K' => true,
        b'V' if b.get(1) == Some(&b'.') => false,
        _ => axis.is_some(),
    };
    if !known {
        return false;
    }
    if let Some(items) = items {
        push_plain(items, letter, &n, g, axis);
    }
    *i = &i[1 + n.len..];
    true
}

/// Pushes a plain word known to be one: each kind where it is made, so the
/// item is written into the block's storage directly, not built aside and
/// copied.
#[inline]
fn push_plain(
    items: &mut Vec<Item>,
    letter: u8,
    n: &PlainNumber,
    g: Option<GCode>,
    axis: Option<Axis>,
) {
    let num = || Expr::Number(n.value());
    match (letter, g, axis) {
        (b'G', Some(g), _) => items.push(Item::G(g)),
        (b'M', ..) => items.push(Item::M(n.whole())),
        (b'F', ..) => items.push(Item::Feed(num())),
        (b'D', ..) => items.push(Item::ToolData(num())),
        (b'T', ..) => items.push(Item::Tool(num())),
        (b'I', ..) => items.push(Item::Centre(CentreAxis::I, num())),
        (b'J', ..) => items.push(Item::Centre(CentreAxis::J, num())),
        (b'K', ..) => items.push(Item::Centre(CentreAxis::K, num())),
        (_, _, Some(axis)) => items.push(Item::Axis(axis, num())),
        _ => {}
    }
}

/// The value after the address letter (ASCII, one byte) at the start.
#[inline]
fn valued(i: &mut &str, make: impl Fn(crate::expr::Expr) -> Item) -> ModalResult<Item> {
    *i = &i[1..];
    cut_err(word_value).map(make).parse_next(i)
}

#[inline]
fn g_word(i: &mut &str) -> ModalResult<Item> {
    let n = preceded(any, cut_err(integer).context(expected("a G number"))).parse_next(i)?;
    match GCode::from_number(n) {
        Some(g) => Ok(Item::G(g)),
        None => refuse("G function: not supported by this controller"),
    }
}

/// `target = expr`, spaces allowed around `=`.
pub fn assignment(i: &mut &str) -> ModalResult<Item> {
    let target: Var = var.parse_next(i)?;
    cut_err((space0, '=', space0))
        .context(expected("'=' after the parameter"))
        .parse_next(i)?;
    let value = cut_err(expr).parse_next(i)?;
    Ok(Item::Assign(target, value))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// The plain-word path reads exactly what the general parser reads.
        #[test]
        fn plain_words_read_as_the_general_parser_does(
            text in "[GMXYZABCUVIJKFDTRPNgxv][-+.]?[0-9.]{0,18}[ .\\[A-Z]?[0-9]?"
        ) {
            let mut fast = text.as_str();
            let mut items = Vec::new();
            let plain = plain_word(&mut fast, Some(&mut items));
            let mut only_recognised = text.as_str();
            prop_assert_eq!(plain, plain_word(&mut only_recognised, None));
            prop_assert_eq!(fast, only_recognised);
            if plain {
                let mut general = text.as_str();
                prop_assert_eq!(Ok(items), word.parse_next(&mut general).map(|w| vec![w]).map_err(|_| ()));
                prop_assert_eq!(fast, general);
            }
        }
    }
}
