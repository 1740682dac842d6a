//! Streaming: one block at a time from a reader, with the check that
//! `$FOR/$IF/$WHILE` and their ends pair up.

use std::io::BufRead;

use crate::block::parse_line_into;
use crate::error::NcError;
use crate::lines::{Line, Lines, MAX_LINE_BYTES};
use crate::model::{Block, Item};

/// A control structure still open, with where it was opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Open {
    For,
    If,
    Else,
    While,
}

/// The blocks of a program read from `reader`, one at a time, in bounded
/// memory: only the lines of the reader's buffer are held.
///
/// Yields `Ok(block)` for each block and `Err` for each line in error (the
/// reader then moves on to the next line); at the end, one `Err` per
/// control structure left open.
pub struct Blocks<R> {
    lines: Lines<R>,
    line: usize,
    open: Vec<(Open, NcError)>,
    done: bool,
    /// Whether blocks keep their plain words (`X10`, `G1`).
    keep: bool,
}

impl<R: BufRead> Blocks<R> {
    /// Blocks of the program that `reader` delivers.
    pub fn new(reader: R) -> Self {
        Blocks {
            lines: Lines::new(reader),
            line: 0,
            open: Vec::new(),
            done: false,
            keep: true,
        }
    }

    /// As [`Blocks::new`], for a check pass: every error is found the
    /// same, but the blocks keep only their words that are not plain
    /// address words with a number (`X10`, `G1`): `$` statements, `#`
    /// commands, assignments, words with expressions.
    pub fn checking(reader: R) -> Self {
        Blocks {
            keep: false,
            ..Blocks::new(reader)
        }
    }

    /// Lines read so far (the line of the last block or error yielded).
    pub fn line(&self) -> usize {
        self.line
    }

    /// Reads the next block into `block`, reusing its storage (no
    /// allocation per block): `Ok` when `block` holds it, `Err` for a line
    /// in error or a structure left open (then `block` holds nothing
    /// useful), `None` at the end.
    pub fn next_into(&mut self, block: &mut Block) -> Option<Result<(), NcError>> {
        if !self.done {
            match self.next_line(block) {
                Some(Ok(())) => return Some(self.check_nesting(block)),
                Some(Err(e)) => return Some(Err(e)),
                None => self.done = true,
            }
        }
        if self.open.is_empty() {
            return None;
        }
        Some(Err(self.open.remove(0).1))
    }

    fn next_line(&mut self, block: &mut Block) -> Option<Result<(), NcError>> {
        loop {
            let result = match self.lines.next_line()? {
                Ok(Line::Text(text, ascii)) => {
                    parse_line_into(text, self.line + 1, block, self.keep, ascii)
                }
                Ok(Line::Bytes(raw)) => parse_raw(raw, self.line + 1, block, self.keep),
                Ok(Line::TooLong(head)) => Some(Err(too_long(head, self.line + 1))),
                Err(e) => return Some(Err(self.read_error(&e))),
            };
            self.line += 1;
            if result.is_some() {
                return result;
            }
        }
    }

    /// A read error ends the program.
    fn read_error(&mut self, e: &std::io::Error) -> NcError {
        self.done = true;
        plain_error(self.line + 1, None, format!("read error: {e}"))
    }

    /// An error at item `k` of `block`.
    fn error_at(block: &Block, k: usize, message: String) -> NcError {
        NcError {
            line: block.line,
            block_number: block.number,
            column: block.column(k),
            message,
        }
    }

    /// Follows `$FOR/$IF/$WHILE` nesting; an end without its start is an error.
    fn check_nesting(&mut self, block: &Block) -> Result<(), NcError> {
        // A control statement stands alone in its block (the parser
        // checks that).
        let [item] = block.items.as_slice() else {
            return Ok(());
        };
        let (closes, opens): (&[Open], Option<Open>) = match item {
            Item::For { .. } => (&[], Some(Open::For)),
            Item::If(_) => (&[], Some(Open::If)),
            Item::While(_) => (&[], Some(Open::While)),
            Item::Else => (&[Open::If], Some(Open::Else)),
            Item::EndFor => (&[Open::For], None),
            Item::EndIf => (&[Open::If, Open::Else], None),
            Item::EndWhile => (&[Open::While], None),
            _ => return Ok(()),
        };
        if !closes.is_empty() {
            match self.open.last() {
                Some((kind, _)) if closes.contains(kind) => {
                    self.open.pop();
                }
                _ => {
                    let msg = format!("{} without its opening statement", end_name(item));
                    return Err(Self::error_at(block, 0, msg));
                }
            }
        }
        if let Some(kind) = opens {
            if closes.is_empty() && self.open.len() >= MAX_CONTROL_NESTING {
                let msg =
                    format!("control structures nest deeper than {MAX_CONTROL_NESTING} levels");
                return Err(Self::error_at(block, 0, msg));
            }
            let msg = open_name(kind).to_string();
            self.open.push((kind, Self::error_at(block, 0, msg)));
        }
        Ok(())
    }
}

/// Deepest nesting of `$FOR/$IF/$WHILE` a program may have: deeper is an
/// error, so that the structures still open stay few (a controller's
/// interpreter has such a limit too).
pub const MAX_CONTROL_NESTING: usize = 256;

/// One line's bytes (without its line end) into `block`; `None` for a
/// line without a block.
fn parse_raw(
    raw: &[u8],
    line: usize,
    block: &mut Block,
    keep: bool,
) -> Option<Result<(), NcError>> {
    match std::str::from_utf8(raw) {
        Ok(text) => parse_line_into(text, line, block, keep, text.is_ascii()),
        Err(_) => {
            let msg = "line is not valid UTF-8 text".to_string();
            Some(Err(plain_error(line, None, msg)))
        }
    }
}

/// The error of a line longer than [`MAX_LINE_BYTES`], `head` its first
/// bytes (for the block number written at its start).
fn too_long(head: &[u8], line: usize) -> NcError {
    let msg = format!("line longer than {MAX_LINE_BYTES} bytes, the limit of an NC line");
    plain_error(line, written_number(head), msg)
}

/// The block number `N<digits>` at the start of `head` (after blanks),
/// when its digits end inside `head` and fit in `u32`.
fn written_number(head: &[u8]) -> Option<u32> {
    let blanks = head
        .iter()
        .take_while(|b| matches!(b, b' ' | b'\t'))
        .count();
    let rest = head[blanks..]
        .strip_prefix(b"N")
        .or_else(|| head[blanks..].strip_prefix(b"n"))?;
    let digits = rest.iter().take_while(|b| b.is_ascii_digit()).count();
    if digits == 0 || digits == rest.len() {
        return None;
    }
    std::str::from_utf8(&rest[..digits]).ok()?.parse().ok()
}

/// An error of a whole line (column 1).
fn plain_error(line: usize, block_number: Option<u32>, message: String) -> NcError {
    NcError {
        line,
        block_number,
        column: 1,
        message,
    }
}

fn end_name(item: &Item) -> &'static str {
    match item {
        Item::Else => "$ELSE",
        Item::EndFor => "$ENDFOR",
        Item::EndIf => "$ENDIF",
        _ => "$ENDWHILE",
    }
}

fn open_name(kind: Open) -> &'static str {
    match kind {
        Open::For => "$FOR without $ENDFOR",
        Open::If | Open::Else => "$IF without $ENDIF",
        Open::While => "$WHILE without $ENDWHILE",
    }
}

impl<R: BufRead> Iterator for Blocks<R> {
    type Item = Result<Block, NcError>;

    fn next(&mut self) -> Option<Self::Item> {
        let mut block = Block::default();
        self.next_into(&mut block).map(|r| r.map(|()| block))
    }
}
