//! `#` commands: `#OTC`, `#set/#get ToolParam`, `#KIN`, `#TRAFO`, `#HSC`.

use winnow::ascii::{space0, space1, Caseless};
use winnow::combinator::{alt, cut_err, delimited, opt, preceded, terminated};
use winnow::error::{ContextError, ErrMode, StrContext, StrContextValue};
use winnow::token::{take_till, take_while};
use winnow::{ModalResult, Parser};

use crate::expr::{integer, var, word_value, Expr};
use crate::model::{Item, OtcCommand, OtcKind, OtcMode, OtcOption};
use crate::refusal::refuse;

fn expected(text: &'static str) -> StrContext {
    StrContext::Expected(StrContextValue::Description(text))
}

/// One `#` command at the input's start.
pub fn command(i: &mut &str) -> ModalResult<Item> {
    '#'.parse_next(i)?;
    alt((
        preceded(Caseless("OTC"), cut_err(otc)),
        preceded(Caseless("TANGFEED"), cut_err(tangfeed)),
        preceded(Caseless("TRC"), cut_err(trc_options)),
        preceded(
            (Caseless("SET"), space1, Caseless("TANGFEED")),
            cut_err(set_tangfeed),
        ),
        preceded(Caseless("set"), cut_err(set_tool_param)),
        preceded(Caseless("get"), cut_err(get_tool_param)),
        preceded(Caseless("KIN"), cut_err(kin)),
        preceded(Caseless("TRAFO"), cut_err(on_off)).map(Item::Trafo),
        preceded(Caseless("HSC"), cut_err(hsc)),
    ))
    .parse_next(i)
    .or_else(|e| match e {
        winnow::error::ErrMode::Backtrack(_) => {
            refuse("command: not a # command of this controller")
        }
        other => Err(other),
    })
}

/// `#TANGFEED`, `#TANGFEED [RMIN=<v>]`: the smallest arc radius G11
/// adapts the feed of.
fn tangfeed(i: &mut &str) -> ModalResult<Item> {
    let rmin = opt(preceded(
        space0,
        delimited(
            ('[', space0),
            opt(preceded(assigned("RMIN"), cut_err(word_value))),
            cut_err((space0, ']')).context(expected("RMIN=<v> and ']' closing #TANGFEED")),
        ),
    ))
    .parse_next(i)?;
    Ok(Item::TangFeed(rmin.flatten()))
}

/// `#TRC [NAME ...]`: the first option's name is kept for the run's error.
fn trc_options(i: &mut &str) -> ModalResult<Item> {
    let name = delimited(
        (space0, '[', space0),
        take_while(1.., |c: char| c.is_ascii_alphanumeric() || c == '_'),
        take_till(0.., |c| c == ']'),
    )
    .context(expected("[OPTION ..] after #TRC"))
    .parse_next(i)?;
    cut_err(']')
        .context(expected("']' closing the #TRC options"))
        .parse_next(i)?;
    Ok(Item::TrcOption(name.to_ascii_uppercase()))
}

/// `#SET TANGFEED RMIN [<v>]`, the older form of `#TANGFEED [RMIN=<v>]`.
fn set_tangfeed(i: &mut &str) -> ModalResult<Item> {
    let value = preceded(
        (space1, Caseless("RMIN"), space0, '[', space0),
        cut_err(terminated(crate::expr::expr, (space0, ']'))),
    )
    .context(expected("RMIN [<v>]"))
    .parse_next(i)?;
    Ok(Item::TangFeed(Some(value)))
}

fn on_off(i: &mut &str) -> ModalResult<bool> {
    preceded(
        space1,
        alt((Caseless("ON").value(true), Caseless("OFF").value(false))),
    )
    .context(expected("ON or OFF"))
    .parse_next(i)
}

fn otc(i: &mut &str) -> ModalResult<Item> {
    let switch = opt(on_off).parse_next(i)?;
    let options = opt(preceded(space0, otc_options)).parse_next(i)?;
    if switch.is_none() && options.is_none() {
        return refuse("#OTC: needs ON, OFF or [options]");
    }
    Ok(Item::Otc(OtcCommand {
        switch,
        options: options.unwrap_or_default(),
    }))
}

/// What an `#OTC` option may be, for the error of an unknown one.
const OTC_OPTIONS: &str = "an #OTC option (RADIUS, LENGTH, TOOL_DIR, SURF_NORM_DIR, DISC, \
                           CONT, AUTO, WEAR_CONST=<v>, WEAR_CONST_TOOL, ACC_WEIGHT=<n>)";

/// `[option, option ...]`: after a separator another option must follow,
/// so an unknown one is named as such, not as a missing `]`.
fn otc_options(i: &mut &str) -> ModalResult<Vec<OtcOption>> {
    ('[', space0).parse_next(i)?;
    let mut options = vec![cut_err(otc_option).parse_next(i)?];
    let mut separator = alt(((space0, ',', space0).void(), space1.void()));
    while opt(separator.by_ref()).parse_next(i)?.is_some() {
        if i.starts_with(']') {
            break;
        }
        options.push(cut_err(otc_option).parse_next(i)?);
    }
    cut_err((space0, ']'))
        .context(expected("']' closing the #OTC options"))
        .parse_next(i)?;
    Ok(options)
}

fn otc_option(i: &mut &str) -> ModalResult<OtcOption> {
    alt((otc_valued, otc_keyword))
        .context(expected(OTC_OPTIONS))
        .parse_next(i)
}

fn assigned<'a>(name: &'static str) -> impl Parser<&'a str, (), ErrMode<ContextError>> {
    (Caseless(name), space0, '=', space0).void()
}

fn otc_valued(i: &mut &str) -> ModalResult<OtcOption> {
    alt((
        preceded(assigned("WEAR_CONST"), cut_err(word_value)).map(OtcOption::WearConst),
        preceded(assigned("ACC_WEIGHT"), cut_err(acc_weight)).map(OtcOption::AccWeight),
    ))
    .parse_next(i)
}

fn otc_keyword(i: &mut &str) -> ModalResult<OtcOption> {
    alt((
        Caseless("WEAR_CONST_TOOL").value(OtcOption::WearConstTool),
        Caseless("RADIUS").value(OtcOption::Kind(OtcKind::Radius)),
        Caseless("LENGTH").value(OtcOption::Kind(OtcKind::Length)),
        Caseless("TOOL_DIR").value(OtcOption::Kind(OtcKind::ToolDir)),
        Caseless("SURF_NORM_DIR").value(OtcOption::Kind(OtcKind::SurfNormDir)),
        Caseless("DISC").value(OtcOption::Mode(OtcMode::Disc)),
        Caseless("CONT").value(OtcOption::Mode(OtcMode::Cont)),
        Caseless("AUTO").value(OtcOption::Mode(OtcMode::Auto)),
    ))
    .parse_next(i)
}

fn acc_weight(i: &mut &str) -> ModalResult<Expr> {
    let value = word_value.parse_next(i)?;
    match value {
        Expr::Number(n) if !(1.0..=100.0).contains(&n) => {
            refuse("ACC_WEIGHT: the weighting is a percentage in [1, 100]")
        }
        other => Ok(other),
    }
}

/// `<line>; <column>;` of ToolParam: numbers or parameters, no formulas.
fn line_and_column(i: &mut &str) -> ModalResult<(Expr, Expr)> {
    (space0, Caseless("ToolParam"), space0, '(', space0).parse_next(i)?;
    let line = terminated(word_value, (space0, ';', space0)).parse_next(i)?;
    let column = terminated(word_value, (space0, ';', space0)).parse_next(i)?;
    Ok((line, column))
}

fn closing(i: &mut &str) -> ModalResult<()> {
    cut_err((space0, ')', space0, '#'))
        .void()
        .context(expected("')#' closing the ToolParam command"))
        .parse_next(i)
}

fn set_tool_param(i: &mut &str) -> ModalResult<Item> {
    let (line, column) = line_and_column
        .context(expected("ToolParam(<line>; <column>; <value>)#"))
        .parse_next(i)?;
    let value = word_value.parse_next(i)?;
    closing(i)?;
    Ok(Item::SetToolParam {
        line: Box::new(line),
        column: Box::new(column),
        value: Box::new(value),
    })
}

fn get_tool_param(i: &mut &str) -> ModalResult<Item> {
    let (line, column) = line_and_column
        .context(expected("ToolParam(<line>; <column>; <parameter>)#"))
        .parse_next(i)?;
    let target = var
        .context(expected("the parameter that receives the value"))
        .parse_next(i)?;
    closing(i)?;
    Ok(Item::GetToolParam {
        line: Box::new(line),
        column: Box::new(column),
        target,
    })
}

fn kin(i: &mut &str) -> ModalResult<Item> {
    delimited((space1, Caseless("ID"), space0, '['), integer, ']')
        .map(Item::Kinematic)
        .context(expected("ID[<kinematic number>]"))
        .parse_next(i)
}

fn hsc(i: &mut &str) -> ModalResult<Item> {
    let on = on_off.parse_next(i)?;
    let options = opt(preceded(
        space0,
        delimited('[', take_till(0.., [']']), cut_err(']')),
    ))
    .context(expected("']' closing the #HSC options"))
    .parse_next(i)?;
    Ok(Item::Hsc {
        on,
        options: options.unwrap_or("").trim().to_string(),
    })
}
