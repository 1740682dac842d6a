//! Address words: G, axes, I J K, F D T M, and assignments.

use winnow::ascii::space0;
use winnow::combinator::{cut_err, peek, preceded};
use winnow::error::{ContextError, ErrMode, StrContext, StrContextValue};
use winnow::token::any;
use winnow::{ModalResult, Parser};

use crate::expr::{expr, integer, var, word_value, Var};
use crate::model::{Axis, CentreAxis, GCode, Item};

fn expected(text: &'static str) -> StrContext {
    StrContext::Expected(StrContextValue::Description(text))
}

/// A failure with one message, cut so no alternative hides it.
pub fn refuse<T>(message: &'static str) -> ModalResult<T> {
    let mut e = ContextError::new();
    e.push(StrContext::Label(message));
    Err(ErrMode::Cut(e))
}

/// One address word or assignment at the input's start.
pub fn word(i: &mut &str) -> ModalResult<Item> {
    let letter = peek(any).parse_next(i)?.to_ascii_uppercase();
    let second = i.chars().nth(1);
    match letter {
        'R' | 'P' if second.is_some_and(|c| c.is_ascii_digit()) => assignment(i),
        'V' if second == Some('.') => assignment(i),
        'G' => g_word(i),
        'M' => preceded(any, cut_err(integer).context(expected("an M number")))
            .map(Item::M)
            .parse_next(i),
        'F' => valued(i, Item::Feed),
        'D' => valued(i, Item::ToolData),
        'T' => valued(i, Item::Tool),
        'I' => valued(i, |v| Item::Centre(CentreAxis::I, v)),
        'J' => valued(i, |v| Item::Centre(CentreAxis::J, v)),
        'K' => valued(i, |v| Item::Centre(CentreAxis::K, v)),
        'N' => refuse("block number: N is allowed only at the start of a block"),
        _ => match Axis::from_letter(letter) {
            Some(axis) => valued(i, |v| Item::Axis(axis, v)),
            None => refuse("address: not an address of this controller"),
        },
    }
}

fn valued(i: &mut &str, make: impl Fn(crate::expr::Expr) -> Item) -> ModalResult<Item> {
    preceded(any, cut_err(word_value)).map(make).parse_next(i)
}

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
