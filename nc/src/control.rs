//! `$` control statements: `$FOR`, `$IF`, `$ELSE`, `$WHILE` and their ends.

use winnow::ascii::{space0, space1, Caseless};
use winnow::combinator::{alt, cut_err, not, preceded, terminated};
use winnow::error::{StrContext, StrContextValue};
use winnow::token::one_of;
use winnow::{ModalResult, Parser};

use crate::expr::{expr, var};
use crate::model::Item;
use crate::refusal::refuse;

fn expected(text: &'static str) -> StrContext {
    StrContext::Expected(StrContextValue::Description(text))
}

fn keyword<'a>(
    word: &'static str,
) -> impl Parser<&'a str, &'a str, winnow::error::ErrMode<winnow::error::ContextError>> {
    terminated(
        Caseless(word),
        not(one_of(|c: char| c.is_ascii_alphanumeric() || c == '_')),
    )
}

/// One `$` statement at the input's start.
pub fn statement(i: &mut &str) -> ModalResult<Item> {
    '$'.parse_next(i)?;
    alt((
        preceded(keyword("FOR"), cut_err(for_head)),
        keyword("ENDFOR").value(Item::EndFor),
        preceded(keyword("IF"), cut_err(condition)).map(Item::If),
        keyword("ELSE").value(Item::Else),
        keyword("ENDIF").value(Item::EndIf),
        preceded(keyword("WHILE"), cut_err(condition)).map(Item::While),
        keyword("ENDWHILE").value(Item::EndWhile),
    ))
    .parse_next(i)
    .or_else(|e| match e {
        winnow::error::ErrMode::Backtrack(_) => {
            refuse("statement: not a $ statement of this controller")
        }
        other => Err(other),
    })
}

fn condition(i: &mut &str) -> ModalResult<crate::expr::Expr> {
    preceded(space1, expr)
        .context(expected("a condition"))
        .parse_next(i)
}

fn comma(i: &mut &str) -> ModalResult<()> {
    cut_err((space0, ',', space0))
        .void()
        .context(expected("',' between start, end and step"))
        .parse_next(i)
}

fn for_head(i: &mut &str) -> ModalResult<Item> {
    let var = preceded(space1, var)
        .context(expected("the loop counter"))
        .parse_next(i)?;
    cut_err((space0, '=', space0))
        .context(expected("'=' after the loop counter"))
        .parse_next(i)?;
    let start = expr.parse_next(i)?;
    comma(i)?;
    let end = expr.parse_next(i)?;
    comma(i)?;
    let step = expr.parse_next(i)?;
    Ok(Item::For {
        var,
        start: Box::new(start),
        end: Box::new(end),
        step: Box::new(step),
    })
}
