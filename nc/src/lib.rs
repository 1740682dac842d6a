//! The NC front end's first part: a parser of NC programs in the ISG /
//! DIN 66025 subset that the manuals' examples use, into a typed block model.
//!
//! **What is parsed.** One block per line: the block number `N`, the program
//! header `%name`, comments `( ... )` and `;` to the end of the line; G
//! functions G0 G1 G2 G3, G05, G10 G11, G17 G18 G19, G25 G26, G40 G41 G42,
//! G90 G91, G138 G139, G140 G141; axis words X Y Z A B C U V, circle centres
//! I J K, F, D, T and M words, whose values are numbers, parameters or
//! `[expressions]`; assignments `R1 = ..`, `P1 = ..`, `V.P.NAME = ..`,
//! `V.G.WZ_AKT.R = ..` with arithmetic (`+ - * /`, brackets, unary minus,
//! comparisons, AND/OR, SIN COS TAN ASIN ACOS ATAN ABS SQRT INT ROUND EXP
//! LN); `$FOR/$ENDFOR`, `$IF/$ELSE/$ENDIF`, `$WHILE/$ENDWHILE` (checked to
//! pair up); `#OTC ON|OFF [..]` and `#OTC[..]` with every option;
//! `#set ToolParam(l; c; v)#` and `#get ToolParam(l; c; R)#`; `#KIN ID[n]`,
//! `#TRAFO ON|OFF`, `#HSC ON[..]|OFF`.
//!
//! Words and expressions are parsed with winnow; the line/block split is
//! plain code. Every unknown or malformed word is an [`NcError`] with line,
//! block number and column; parsing goes on with the next line, so a program
//! reports all its errors. Nothing panics on any input.
//!
//! **Running.** [`run::run_program`] interprets a parsed program into the
//! requests of `tc-request` (object writes, motion commands, a final
//! `EXEC`) sent to a [`run::Controller`]: modal state, parameters and
//! variables, loops and conditions, the D table, `#OTC`. It has no
//! geometry: the correction is the controller's.
//!
//! **Not yet.** No plot, no streaming run (the interpreter holds the block
//! list so that loops can jump back).

mod block;
mod commands;
mod control;
mod error;
mod expr;
mod model;
pub mod run;
mod stream;
mod words;

pub use error::NcError;
pub use expr::{BinOp, Expr, Func, Segment, Var};
pub use model::{Axis, Block, CentreAxis, GCode, Item, OtcCommand, OtcKind, OtcMode, OtcOption};
pub use stream::Blocks;

/// Parses a whole program text: its blocks, and all its errors.
pub fn parse_program(text: &str) -> (Vec<Block>, Vec<NcError>) {
    let mut blocks = Vec::new();
    let mut errors = Vec::new();
    for result in Blocks::new(text.as_bytes()) {
        match result {
            Ok(block) => blocks.push(block),
            Err(e) => errors.push(e),
        }
    }
    (blocks, errors)
}
