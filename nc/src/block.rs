//! One line of a program into one block: block number, header, comments,
//! and the words between them.

use winnow::ascii::space0;
use winnow::error::{ContextError, ErrMode};
use winnow::Parser;

use crate::commands::command;
use crate::control::statement;
use crate::error::NcError;
use crate::expr::{describe, integer};
use crate::model::{Block, Item};
use crate::words::word;

/// Where a line is being read: for the column and the error's block number.
struct Cursor<'a> {
    line_text: &'a str,
    ascii: bool,
    line: usize,
    number: Option<u32>,
}

impl Cursor<'_> {
    /// The column (from 1, in characters) where `rest` starts.
    fn column(&self, rest: &str) -> usize {
        let offset = self.line_text.len() - rest.len();
        if self.ascii {
            offset + 1
        } else {
            self.line_text[..offset].chars().count() + 1
        }
    }

    fn error(&self, rest: &str, message: String) -> NcError {
        NcError {
            line: self.line,
            block_number: self.number,
            column: self.column(rest),
            message,
        }
    }
}

/// The words of a block and the column where each starts.
type Words = (Vec<Item>, Vec<usize>);

/// Parses one line; `None` for a line with nothing but spaces and comments.
pub fn parse_line(text: &str, line: usize) -> Option<Result<Block, NcError>> {
    let text = text.strip_suffix('\r').unwrap_or(text);
    let mut cur = Cursor {
        line_text: text,
        ascii: text.is_ascii(),
        line,
        number: None,
    };
    let mut rest = text.trim_start_matches([' ', '\t']);
    if let Some(name) = rest.strip_prefix('%') {
        return header(&cur, name);
    }
    if rest.starts_with(['N', 'n']) {
        let mut after = &rest[1..];
        match integer.parse_next(&mut after) {
            Ok(n) => {
                cur.number = Some(n);
                rest = after;
            }
            Err(_) => {
                let msg = "malformed block number: N needs a number (0..4294967295)";
                return Some(Err(cur.error(rest, msg.to_string())));
            }
        }
    }
    match items(&cur, rest) {
        Ok((items, _)) if items.is_empty() && cur.number.is_none() => None,
        Ok((items, columns)) => Some(Ok(Block {
            line,
            number: cur.number,
            items,
            columns,
        })),
        Err(e) => Some(Err(e)),
    }
}

fn header(cur: &Cursor<'_>, after_percent: &str) -> Option<Result<Block, NcError>> {
    let end = after_percent
        .find(|c: char| c.is_whitespace() || c == '(' || c == ';')
        .unwrap_or(after_percent.len());
    let (name, rest) = after_percent.split_at(end);
    if name.is_empty() {
        let msg = "malformed program header: '%' needs a program name".to_string();
        return Some(Err(cur.error(after_percent, msg)));
    }
    let mut block = match items(cur, rest) {
        Ok((items, columns)) => Block {
            line: cur.line,
            number: None,
            items,
            columns,
        },
        Err(e) => return Some(Err(e)),
    };
    block.items.insert(0, Item::ProgramName(name.to_string()));
    block.columns.insert(0, cur.column(after_percent) - 1);
    Some(Ok(block))
}

/// The words of a block up to its end, skipping comments; a `$` control
/// statement must stand alone in its block.
fn items(cur: &Cursor<'_>, mut rest: &str) -> Result<Words, NcError> {
    let mut items = Vec::new();
    let mut columns = Vec::new();
    loop {
        rest = rest.trim_start_matches([' ', '\t']);
        if rest.is_empty() || rest.starts_with(';') {
            return alone(cur, items, columns);
        }
        if rest.starts_with('(') {
            match rest.find(')') {
                Some(end) => rest = &rest[end + 1..],
                None => return Err(cur.error(rest, "unclosed comment: ')' missing".into())),
            }
            continue;
        }
        let start = rest;
        let parsed: Result<Item, ErrMode<ContextError>> = match rest.chars().next() {
            Some('#') => command.parse_next(&mut rest),
            Some('$') => statement.parse_next(&mut rest),
            _ => word.parse_next(&mut rest),
        };
        match parsed {
            Ok(item) => {
                items.push(item);
                columns.push(cur.column(start));
            }
            Err(e) => return Err(cur.error(start, word_message(start, &e))),
        }
        if let Some(c) = rest.chars().next() {
            if !(c.is_whitespace()
                || matches!(c, '(' | ';')
                || c.is_ascii_alphabetic()
                || matches!(c, '#' | '$'))
            {
                let msg = format!("unexpected '{c}' after a word");
                return Err(cur.error(rest, msg));
            }
        }
        let _ = space0::<&str, ContextError>.parse_next(&mut rest);
    }
}

/// The words of a block, refused when a `$` control statement stands
/// beside other words (at the column of the second word).
fn alone(cur: &Cursor<'_>, items: Vec<Item>, columns: Vec<usize>) -> Result<Words, NcError> {
    if items.len() > 1 && items.iter().any(Item::is_control) {
        return Err(NcError {
            line: cur.line,
            block_number: cur.number,
            column: columns[1],
            message: "a $ control statement must stand alone in its block".into(),
        });
    }
    Ok((items, columns))
}

/// The message of a failed word: the word as written and what was wrong.
fn word_message(start: &str, e: &ErrMode<ContextError>) -> String {
    let text: String = start
        .split(|c: char| c.is_whitespace() || c == '(' || c == ';')
        .next()
        .unwrap_or(start)
        .chars()
        .take(40)
        .collect();
    match describe(e) {
        Some(why) => format!("malformed or unknown word `{text}`: {why}"),
        None => format!("malformed or unknown word `{text}`"),
    }
}
