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
    line: usize,
    number: Option<u32>,
}

impl Cursor<'_> {
    fn error(&self, rest: &str, message: String) -> NcError {
        let offset = self.line_text.len() - rest.len();
        NcError {
            line: self.line,
            block_number: self.number,
            column: self.line_text[..offset].chars().count() + 1,
            message,
        }
    }
}

/// Parses one line; `None` for a line with nothing but spaces and comments.
pub fn parse_line(text: &str, line: usize) -> Option<Result<Block, NcError>> {
    let text = text.strip_suffix('\r').unwrap_or(text);
    let mut cur = Cursor {
        line_text: text,
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
        Ok(items) if items.is_empty() && cur.number.is_none() => None,
        Ok(items) => Some(Ok(Block {
            line,
            number: cur.number,
            items,
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
        Ok(items) => Block {
            line: cur.line,
            number: None,
            items,
        },
        Err(e) => return Some(Err(e)),
    };
    block.items.insert(0, Item::ProgramName(name.to_string()));
    Some(Ok(block))
}

/// The words of a block up to its end, skipping comments.
fn items(cur: &Cursor<'_>, mut rest: &str) -> Result<Vec<Item>, NcError> {
    let mut items = Vec::new();
    loop {
        rest = rest.trim_start_matches([' ', '\t']);
        if rest.is_empty() || rest.starts_with(';') {
            return Ok(items);
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
            Ok(item) => items.push(item),
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
