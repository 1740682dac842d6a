//! One line of a program into one block: block number, header, comments,
//! and the words between them.

use winnow::error::{ContextError, ErrMode};
use winnow::Parser;

use crate::commands::command;
use crate::control::statement;
use crate::error::NcError;
use crate::expr::{describe, integer};
use crate::model::{Block, Item};
use crate::plain::plain_number;
use crate::words::{plain_word, word};

/// Where a line is being read: for the column and the error's block number.
struct Cursor<'a> {
    line_text: &'a str,
    ascii: bool,
    /// Whether plain words are kept (else only checked: a check pass).
    keep: bool,
    line: usize,
    number: Option<u32>,
    /// The last column asked for on a line that is not ASCII: its byte
    /// offset and the characters before it, so that columns asked for from
    /// left to right cost the characters in between, not the whole line.
    counted: std::cell::Cell<(usize, usize)>,
}

impl Cursor<'_> {
    /// The column (from 1, in characters) where `rest` starts.
    fn column(&self, rest: &str) -> usize {
        let offset = self.line_text.len() - rest.len();
        if self.ascii {
            return offset + 1;
        }
        let (mut from, mut chars) = self.counted.get();
        if offset < from {
            (from, chars) = (0, 0);
        }
        chars += self.line_text[from..offset].chars().count();
        self.counted.set((offset, chars));
        chars + 1
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

/// Spaces and tabs at the start of `text` skipped.
fn skip_blanks(text: &str) -> &str {
    let n = text
        .as_bytes()
        .iter()
        .take_while(|b| matches!(b, b' ' | b'\t'))
        .count();
    &text[n..]
}

/// Parses one line into `block` (its storage reused; on an error its
/// content is unspecified); `None` for a line with nothing but spaces and
/// comments. With `keep` false the plain words (`X10`, `G1`) are checked
/// but not kept: the block then holds only the other words (a check pass).
/// `ascii` tells whether `text` is ASCII (columns are then byte offsets).
pub fn parse_line_into(
    text: &str,
    line: usize,
    block: &mut Block,
    keep: bool,
    ascii: bool,
) -> Option<Result<(), NcError>> {
    let text = text.strip_suffix('\r').unwrap_or(text);
    let mut cur = Cursor {
        line_text: text,
        ascii,
        keep,
        line,
        number: None,
        counted: std::cell::Cell::new((0, 0)),
    };
    block.line = line;
    block.number = None;
    block.items.clear();
    block.columns.clear();
    let mut rest = skip_blanks(text);
    if let Some(name) = rest.strip_prefix('%') {
        return Some(header(&cur, name, block));
    }
    if let Some(after) = rest.strip_prefix(['N', 'n']) {
        let mut after = after;
        // A plain number of up to 9 digits read by a byte scan, else by
        // the parser (which also refuses what does not fit in u32).
        let plain = plain_number(after.as_bytes(), true).map(|n| {
            after = &after[n.len..];
            n.whole()
        });
        match plain.map_or_else(|| integer.parse_next(&mut after), Ok) {
            Ok(n) => {
                cur.number = Some(n);
                block.number = Some(n);
                rest = after;
            }
            Err(_) => {
                let msg = "malformed block number: N needs a number (0..4294967295)";
                return Some(Err(cur.error(rest, msg.to_string())));
            }
        }
    }
    match items(&cur, rest, block) {
        Ok(0) if cur.number.is_none() => None,
        Ok(_) => Some(Ok(())),
        Err(e) => Some(Err(e)),
    }
}

fn header(cur: &Cursor<'_>, after_percent: &str, block: &mut Block) -> Result<(), NcError> {
    let end = after_percent
        .find(|c: char| c.is_whitespace() || c == '(' || c == ';')
        .unwrap_or(after_percent.len());
    let (name, rest) = after_percent.split_at(end);
    if name.is_empty() {
        let msg = "malformed program header: '%' needs a program name".to_string();
        return Err(cur.error(after_percent, msg));
    }
    block.items.push(Item::ProgramName(name.to_string()));
    block.columns.push(cur.column(after_percent) - 1);
    items(cur, rest, block).map(|_| ())
}

/// Whether a word may end before `c`: a blank, a comment, the next word.
fn ends_word(c: char) -> bool {
    c.is_whitespace() || matches!(c, '(' | ';' | '#' | '$') || c.is_ascii_alphabetic()
}

/// The words of a block up to its end, skipping comments, appended to
/// `block` (plain words only when the cursor keeps them); a `$` control
/// statement must stand alone in its block. The number of words.
fn items(cur: &Cursor<'_>, mut rest: &str, block: &mut Block) -> Result<usize, NcError> {
    let mut words = Words {
        count: block.items.len(),
        second: 1,
    };
    loop {
        rest = skip_blanks(rest);
        let Some(&first) = rest.as_bytes().first() else {
            return alone(cur, block, &words);
        };
        match first {
            b';' => return alone(cur, block, &words),
            b'(' => {
                match rest.find(')') {
                    Some(end) => rest = &rest[end + 1..],
                    None => return Err(cur.error(rest, "unclosed comment: ')' missing".into())),
                }
                continue;
            }
            _ => {}
        }
        let start = rest;
        let kept = cur.keep.then_some(&mut block.items);
        if plain_word(&mut rest, kept) {
            if cur.keep {
                block.columns.push(cur.column(start));
            }
        } else {
            let parsed: Result<Item, ErrMode<ContextError>> = match first {
                b'#' => command.parse_next(&mut rest),
                b'$' => statement.parse_next(&mut rest),
                _ => word.parse_next(&mut rest),
            };
            match parsed {
                Ok(item) => {
                    block.items.push(item);
                    block.columns.push(cur.column(start));
                }
                Err(e) => return Err(cur.error(start, word_message(start, &e))),
            }
        }
        words.count += 1;
        if words.count == 2 {
            words.second = cur.column(start);
        }
        let next = match rest.as_bytes().first() {
            Some(&b) if b.is_ascii() => Some(char::from(b)),
            Some(_) => rest.chars().next(),
            None => None,
        };
        if let Some(c) = next.filter(|c| !ends_word(*c)) {
            let msg = format!("unexpected '{c}' after a word");
            return Err(cur.error(rest, msg));
        }
    }
}

/// The words of a block read so far (plain ones included) and the column
/// of the second.
struct Words {
    count: usize,
    second: usize,
}

/// Refuses a `$` control statement that stands beside other words (at the
/// column of the second word); the number of words.
fn alone(cur: &Cursor<'_>, block: &Block, words: &Words) -> Result<usize, NcError> {
    if words.count > 1 && block.items.iter().any(Item::is_control) {
        return Err(NcError {
            line: cur.line,
            block_number: cur.number,
            column: words.second,
            message: "a $ control statement must stand alone in its block".into(),
        });
    }
    Ok(words.count)
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
