//! The NC front end: a parser of NC programs in the ISG / DIN 66025 subset
//! that the manuals' examples use, into a typed block model, and an
//! interpreter that runs them as requests to a controller.
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
//! `#TANGFEED [RMIN=..]` and `#SET TANGFEED RMIN [..]`;
//! `#set ToolParam(l; c; v)#` and `#get ToolParam(l; c; R)#`; `#KIN ID[n]`,
//! `#TRAFO ON|OFF`, `#HSC ON[..]|OFF`.
//!
//! Words and expressions are parsed with winnow; the line/block split is
//! plain code, and so is a fast path for the plain address words that make
//! up most of a long program (`X10`, `G1`: a letter and a number), checked
//! by a property test to read exactly what the winnow parser reads. Every
//! unknown or malformed word is an [`NcError`] with line, block number and
//! column; parsing goes on with the next line, so a program reports all its
//! errors. Nothing panics on any input.
//!
//! **Running.** [`run::run_blocks`] interprets a program into the requests
//! of `tc-request` (object writes, motion commands, a final `EXEC`) sent to
//! a [`run::Controller`]: modal state, parameters and variables, loops and
//! conditions, the D table, `#OTC`, the selection modes and the feed
//! adaptation. The correction is the controller's; the interpreter's own
//! plane geometry only places what ISG's selection modes insert and finds
//! the centre of an arc given by its radius. Its errors are typed ([`run::RunError`]: a
//! [`run::RunErrorKind`] a caller can match, and the [`Location`] (line,
//! block, column) of the word that caused it), and so are its warnings.
//!
//! **Limits.** A line holds at most [`MAX_LINE_BYTES`] (1 MiB; a longer
//! one is an error on its line and is read past, not held). A chain of
//! operators of any length is one expression node, evaluated in a loop;
//! brackets, signs, calls and indices nest at most [`MAX_EXPR_NESTING`]
//! (64) deep, and `$FOR/$IF/$WHILE` at most [`MAX_CONTROL_NESTING`]: no
//! input overflows the stack.
//!
//! **Streaming.** A program of any length runs in bounded memory: a first
//! pass over the text ([`check_program`]) collects every error, and only a
//! program without one runs, in a second pass ([`run::run_reader`]) that
//! pulls its blocks from a [`Blocks`] reader as they are needed, into
//! reused storage. The interpreter holds only the blocks of the outermost
//! open `$FOR`/`$WHILE` (for jumping back) and works off a full spooler
//! with `EXEC`, as a controller's interpreter waits for its interpolator.
//! [`parse_program`] and [`run::run_program`] do the same on a program
//! held whole (tests, small programs).
//!
//! **Running on a target.** [`nc_run`] runs a checked program on any
//! [`tc_request::Runner`] (the CLI and the plot pass a fresh emulator),
//! hands each request on with its answer and spooled elements, and
//! writes the run as an equivalent conformance trace as it goes
//! (`addipos run`).

mod block;
mod commands;
mod control;
mod error;
mod expr;
mod lines;
mod model;
pub mod nc_run;
mod plain;
mod refusal;
pub mod run;
mod stream;
mod words;

pub use error::{Location, NcError};
pub use expr::{BinOp, Expr, Func, Segment, Var, MAX_EXPR_NESTING};
pub use lines::MAX_LINE_BYTES;
pub use model::{Axis, Block, CentreAxis, GCode, Item, OtcCommand, OtcKind, OtcMode, OtcOption};
pub use stream::{Blocks, MAX_CONTROL_NESTING};

/// Reads a whole program from `reader` and keeps only its errors: the
/// first pass of a streamed run (nothing runs when there is one). Memory
/// stays bounded by the longest line and [`MAX_KEPT_ERRORS`].
pub fn check_program<R: std::io::BufRead>(reader: R) -> Vec<NcError> {
    check_program_counted(reader).0
}

/// Most errors, warnings or faults of one program kept for the report; the
/// rest are only counted, so a program of a million bad lines cannot
/// exhaust memory.
pub const MAX_KEPT_ERRORS: usize = 1000;

/// The check pass: the first [`MAX_KEPT_ERRORS`] errors of the program
/// `reader` delivers, and how many more there were.
pub fn check_program_counted<R: std::io::BufRead>(reader: R) -> (Vec<NcError>, u64) {
    let mut blocks = Blocks::checking(reader);
    let mut scratch = Block::default();
    let mut errors = Vec::new();
    let mut more = 0u64;
    while let Some(result) = blocks.next_into(&mut scratch) {
        if let Err(e) = result {
            if errors.len() < MAX_KEPT_ERRORS {
                errors.push(e);
            } else {
                more += 1;
            }
        }
    }
    (errors, more)
}

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
