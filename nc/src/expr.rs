//! Values and arithmetic expressions: numbers, R/P parameters, `V.` variables,
//! operators, functions. Parsed with winnow.

use winnow::ascii::{digit0, digit1, space0, Caseless};
use winnow::combinator::{alt, cut_err, delimited, not, opt, preceded, repeat, terminated};
use winnow::error::{ContextError, ErrMode, StrContext, StrContextValue};
use winnow::stream::Stream;
use winnow::token::{one_of, take_while};
use winnow::{ModalResult, Parser};

/// An arithmetic or logical expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A literal number.
    Number(f64),
    /// A parameter or variable.
    Var(Var),
    /// Unary minus.
    Neg(Box<Expr>),
    /// Operands of one precedence group joined left to right:
    /// `first op1 e1 op2 e2 ..` is `((first op1 e1) op2 e2) ..`. A flat
    /// chain of any length is one node, so an expression is as deep as
    /// its nesting of brackets, signs and calls (at most
    /// [`MAX_EXPR_NESTING`]), not as long as it is: evaluating, copying or
    /// dropping it needs no deeper stack for a longer chain.
    Chain(Box<Expr>, Box<[(BinOp, Expr)]>),
    /// A function applied to one argument.
    Call(Func, Box<Expr>),
}

/// A parameter or variable that can be read or assigned.
#[derive(Debug, Clone, PartialEq)]
pub enum Var {
    /// `R<n>`: arithmetic parameter.
    R(u32),
    /// `P<n>`: local parameter (the `$FOR P1=...` counter of the seeds).
    P(u32),
    /// `V.<scope>.<path>`: `V.P.NAME`, `V.G.WZ_AKT.R`, `V.G.WZ_AKT.WEAR[0]`.
    V {
        /// The scope letter after `V.`: P (program), G (global), L (local), S, E.
        scope: char,
        /// The dotted path after the scope.
        path: Box<[Segment]>,
    },
}

/// One dotted part of a `V.` variable, with an optional `[index]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// The name as written.
    pub name: String,
    /// The index expression of `NAME[expr]`.
    pub index: Option<Box<Expr>>,
}

/// Binary operators, by rising precedence group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `OR`.
    Or,
    /// `AND`.
    And,
    /// `==`.
    Eq,
    /// `!=`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
}

/// Functions of one argument (angles in degrees, as on the controller).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    /// SIN.
    Sin,
    /// COS.
    Cos,
    /// TAN.
    Tan,
    /// ASIN.
    Asin,
    /// ACOS.
    Acos,
    /// ATAN.
    Atan,
    /// ABS.
    Abs,
    /// SQRT.
    Sqrt,
    /// INT: integer part.
    Int,
    /// ROUND.
    Round,
    /// EXP.
    Exp,
    /// LN.
    Ln,
}

fn label(text: &'static str) -> StrContext {
    StrContext::Label(text)
}

fn expected(text: &'static str) -> StrContext {
    StrContext::Expected(StrContextValue::Description(text))
}

/// A full expression; spaces may stand around operators.
pub fn expr(i: &mut &str) -> ModalResult<Expr> {
    level(i, and_level, |i| {
        terminated(Caseless("OR"), not(ident_char))
            .value(BinOp::Or)
            .parse_next(i)
    })
}

fn and_level(i: &mut &str) -> ModalResult<Expr> {
    level(i, comparison, |i| {
        terminated(Caseless("AND"), not(ident_char))
            .value(BinOp::And)
            .parse_next(i)
    })
}

fn comparison(i: &mut &str) -> ModalResult<Expr> {
    level(i, additive, |i| {
        alt((
            "==".value(BinOp::Eq),
            "!=".value(BinOp::Ne),
            "<=".value(BinOp::Le),
            ">=".value(BinOp::Ge),
            "<".value(BinOp::Lt),
            ">".value(BinOp::Gt),
        ))
        .parse_next(i)
    })
}

fn additive(i: &mut &str) -> ModalResult<Expr> {
    level(i, multiplicative, |i| {
        if i.starts_with(TYPOGRAPHIC_DASHES) {
            return cut_err(winnow::combinator::fail)
                .context(label("operator: a typographic dash, write '-'"))
                .parse_next(i);
        }
        alt(('+'.value(BinOp::Add), '-'.value(BinOp::Sub))).parse_next(i)
    })
}

fn multiplicative(i: &mut &str) -> ModalResult<Expr> {
    level(i, unary, |i| {
        alt(('*'.value(BinOp::Mul), '/'.value(BinOp::Div))).parse_next(i)
    })
}

const TYPOGRAPHIC_DASHES: [char; 3] = ['\u{2013}', '\u{2014}', '\u{2212}'];

/// One precedence level: `next (op next)*`, left-associative, read in a
/// loop into one [`Expr::Chain`] (a lone operand stays as it is).
fn level(
    i: &mut &str,
    mut next: impl FnMut(&mut &str) -> ModalResult<Expr>,
    mut op: impl FnMut(&mut &str) -> ModalResult<BinOp>,
) -> ModalResult<Expr> {
    let first = next(i)?;
    let mut rest = Vec::new();
    loop {
        let before = i.checkpoint();
        space0.parse_next(i)?;
        match op(i) {
            Ok(op) => {
                space0.parse_next(i)?;
                let rhs = cut_err(&mut next)
                    .context(expected("an operand after the operator"))
                    .parse_next(i)?;
                rest.push((op, rhs));
            }
            Err(ErrMode::Backtrack(_)) => {
                i.reset(&before);
                break;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(if rest.is_empty() {
        first
    } else {
        Expr::Chain(Box::new(first), rest.into_boxed_slice())
    })
}

/// Deepest nesting of signs, brackets and calls one expression may have
/// (decision 240); deeper input is a parse error, so that parsing and
/// evaluating need a stack bounded by this, whatever the input.
pub const MAX_EXPR_NESTING: usize = 64;

thread_local! {
    static DEPTH: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Counts one level of nesting while alive.
struct DepthGuard;

impl DepthGuard {
    fn enter() -> Option<DepthGuard> {
        DEPTH.with(|d| {
            if d.get() >= MAX_EXPR_NESTING {
                return None;
            }
            d.set(d.get() + 1);
            Some(DepthGuard)
        })
    }
}

impl Drop for DepthGuard {
    fn drop(&mut self) {
        DEPTH.with(|d| d.set(d.get().saturating_sub(1)));
    }
}

fn unary(i: &mut &str) -> ModalResult<Expr> {
    let Some(_guard) = DepthGuard::enter() else {
        return cut_err(winnow::combinator::fail)
            .context(label("expression: nested deeper than 64 levels"))
            .parse_next(i);
    };
    if i.starts_with(TYPOGRAPHIC_DASHES) {
        return cut_err(winnow::combinator::fail)
            .context(label("sign: a typographic dash, write '-'"))
            .parse_next(i);
    }
    alt((
        preceded(('-', space0), cut_err(unary)).map(|e| Expr::Neg(Box::new(e))),
        preceded(('+', space0), cut_err(unary)),
        primary,
    ))
    .parse_next(i)
}

fn primary(i: &mut &str) -> ModalResult<Expr> {
    alt((
        number.map(Expr::Number),
        bracketed('(', ')'),
        bracketed('[', ']'),
        call,
        var.map(Expr::Var),
    ))
    .context(expected(
        "a number, a parameter, a variable or a bracketed expression",
    ))
    .parse_next(i)
}

fn bracketed(open: char, close: char) -> impl FnMut(&mut &str) -> ModalResult<Expr> {
    move |i: &mut &str| {
        delimited(
            (open, space0),
            cut_err(expr),
            cut_err((space0, close)).context(expected("a closing bracket")),
        )
        .parse_next(i)
    }
}

fn call(i: &mut &str) -> ModalResult<Expr> {
    let start = *i;
    let name = take_while(2..=5, |c: char| c.is_ascii_alphabetic()).parse_next(i)?;
    let Some(func) = func_of(name) else {
        *i = start;
        return Err(ErrMode::Backtrack(ContextError::new()));
    };
    if i.starts_with('[') {
        // Square brackets group; a new user wrote `SIN[30]`.
        return crate::refusal::refuse(
            "function call: the argument is in round brackets, SIN(30), not SIN[30]",
        );
    }
    let Some(rest) = i.strip_prefix('(') else {
        *i = start;
        return Err(ErrMode::Backtrack(ContextError::new()));
    };
    *i = rest;
    let arg = cut_err(terminated(
        delimited(space0, expr, space0),
        cut_err(')').context(expected("')' after the function argument")),
    ))
    .parse_next(i)?;
    Ok(Expr::Call(func, Box::new(arg)))
}

fn func_of(name: &str) -> Option<Func> {
    const FUNCS: [(&str, Func); 12] = [
        ("SIN", Func::Sin),
        ("COS", Func::Cos),
        ("TAN", Func::Tan),
        ("ASIN", Func::Asin),
        ("ACOS", Func::Acos),
        ("ATAN", Func::Atan),
        ("ABS", Func::Abs),
        ("SQRT", Func::Sqrt),
        ("INT", Func::Int),
        ("ROUND", Func::Round),
        ("EXP", Func::Exp),
        ("LN", Func::Ln),
    ];
    FUNCS
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, f)| *f)
}

/// An unsigned decimal number: `10`, `20.3`, `.5`, `5.`.
#[inline]
pub fn number(i: &mut &str) -> ModalResult<f64> {
    (digit0, opt((one_of(|c: char| c == '.'), digit0)))
        .take()
        .verify(|t: &str| t.bytes().any(|b| b.is_ascii_digit()))
        .try_map(str::parse::<f64>)
        .parse_next(i)
}

/// An unsigned integer that fits in `u32`.
#[inline]
pub fn integer(i: &mut &str) -> ModalResult<u32> {
    digit1.try_map(str::parse::<u32>).parse_next(i)
}

fn ident_char(i: &mut &str) -> ModalResult<char> {
    one_of(|c: char| c.is_ascii_alphanumeric() || c == '_').parse_next(i)
}

/// A parameter or variable: `R1`, `P1`, `V.P.NAME`, `V.G.WZ_AKT.WEAR[0]`.
pub fn var(i: &mut &str) -> ModalResult<Var> {
    alt((
        preceded(one_of(['R', 'r']), integer).map(Var::R),
        preceded(one_of(['P', 'p']), integer).map(Var::P),
        v_var,
    ))
    .parse_next(i)
}

fn v_var(i: &mut &str) -> ModalResult<Var> {
    (one_of(['V', 'v']), '.').parse_next(i)?;
    let scope = cut_err(terminated(one_of(['P', 'G', 'L', 'S', 'E']), '.'))
        .context(expected("a scope V.P., V.G., V.L., V.S. or V.E."))
        .parse_next(i)?;
    let first = cut_err(segment).parse_next(i)?;
    let rest: Vec<Segment> = repeat(0.., preceded('.', cut_err(segment))).parse_next(i)?;
    let mut path = vec![first];
    path.extend(rest);
    Ok(Var::V {
        scope,
        path: path.into_boxed_slice(),
    })
}

fn segment(i: &mut &str) -> ModalResult<Segment> {
    let name = take_while(1.., |c: char| c.is_ascii_alphanumeric() || c == '_')
        .context(expected("a variable name"))
        .parse_next(i)?;
    let index = opt(bracketed('[', ']')).parse_next(i)?;
    Ok(Segment {
        name: name.to_string(),
        index: index.map(Box::new),
    })
}

/// The value of an address word: a signed number or variable, or `[expr]`.
/// No spaces inside, so `X10 Y-5` stays two words.
#[inline]
pub fn word_value(i: &mut &str) -> ModalResult<Expr> {
    let minus = match i.as_bytes().first() {
        Some(b'-') => Some('-'),
        Some(b'+') => Some('+'),
        _ => None,
    };
    if minus.is_some() {
        *i = &i[1..];
    }
    // What may follow is told by its first character.
    let value = (|i: &mut &str| match i.as_bytes().first() {
        Some(b'0'..=b'9' | b'.') => number.map(Expr::Number).parse_next(i),
        Some(b'[') => bracketed('[', ']').parse_next(i),
        _ => var.map(Expr::Var).parse_next(i),
    })
    .context(expected_value())
    .parse_next(i)?;
    Ok(match minus {
        Some('-') => match value {
            Expr::Number(n) => Expr::Number(-n),
            other => Expr::Neg(Box::new(other)),
        },
        _ => value,
    })
}

fn expected_value() -> StrContext {
    expected("a number, a parameter or [expression]")
}

/// The message of a failed parse, from its innermost context.
pub fn describe(e: &ErrMode<ContextError>) -> Option<String> {
    let ctx = match e {
        ErrMode::Backtrack(c) | ErrMode::Cut(c) => c,
        ErrMode::Incomplete(_) => return None,
    };
    ctx.context().next().map(|c| match c {
        StrContext::Label(l) => format!("invalid {l}"),
        StrContext::Expected(v) => format!("expected {v}"),
        _ => c.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plain::plain_number;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5000))]

        /// The exact short path gives what the number parser (and so
        /// `str::parse`) gives, or leaves the number to it.
        #[test]
        fn plain_numbers_are_those_of_the_number_parser(
            sign in "[-+]?", int in "[0-9]{0,18}", frac in proptest::option::of("[0-9]{0,18}")
        ) {
            let digits = match &frac {
                Some(f) => format!("{int}.{f}"),
                None => int.clone(),
            };
            let text = format!("{sign}{digits}");
            if let Some(p) = plain_number(text.as_bytes(), false) {
                let mut rest = digits.as_str();
                let n = number.parse_next(&mut rest).unwrap_or(f64::NAN);
                prop_assert_eq!(p.value(), if sign == "-" { -n } else { n });
                prop_assert_eq!(p.len, text.len());
            }
        }
    }
}
