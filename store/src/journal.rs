//! The journal: one line per change, appended and synced before the change
//! is acknowledged, each line ending in a CRC-32 of its text.
//!
//! ```text
//! g3 wz[5].radius 300000 *26a0b7f4
//! g3 reset *b7948462
//! clean *f1b0ad49
//! ```
//!
//! A record counts only with its newline and a matching checksum. A last
//! line without its newline is a torn tail (a write cut short by a crash):
//! it is dropped and reported. Any complete line that is bad, the last one
//! included, is corruption: a write cut short cannot leave a newline after
//! a wrong byte, but a flipped bit can.

use crate::field::{FileField, ToolValue};
use crate::file::{format_assignment, parse_assignment, LineError};
use crate::table::{ToolKey, GROUPS};

/// One change of tool data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Record {
    /// `g<group> wz[i].field value`: one field of one entry set.
    Set {
        /// Compensation group, 1..=32.
        group: u8,
        /// The entry and field.
        key: ToolKey,
        /// The new value, bus unit.
        value: ToolValue,
    },
    /// `g<group> reset`: group RESET, every entry of the group back to
    /// its defaults.
    ResetGroup {
        /// Compensation group, 1..=32.
        group: u8,
    },
    /// `clean`: module Clean, every entry of every group back to its
    /// defaults.
    Clean,
}

/// What is wrong with a journal record.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RecordError {
    /// The line has no ` *<8 hex digits>` checksum at its end.
    #[error("no checksum at the end of the record")]
    NoChecksum,
    /// The checksum does not match the record's text.
    #[error("checksum mismatch")]
    Checksum,
    /// The line does not end in a newline (cut short).
    #[error("record cut short (no newline)")]
    Incomplete,
    /// The record is not `clean`, `g<n> reset` or `g<n> wz[i].field value`.
    #[error("{0}")]
    Malformed(String),
    /// The group is not in 1..=32.
    #[error("group {0} is out of range (1..=32)")]
    GroupOutOfRange(String),
    /// The assignment is bad.
    #[error(transparent)]
    Line(#[from] LineError),
}

/// A bad journal line: its number (from 1) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {error}")]
pub struct JournalError {
    /// Line number, counting from 1.
    pub line: usize,
    /// What is wrong.
    pub error: RecordError,
}

/// A dropped torn tail: the last line of the journal, cut short before its
/// newline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TornTail {
    /// Its line number, counting from 1.
    pub line: usize,
    /// Byte offset where it starts (the journal's valid length).
    pub offset: u64,
    /// Its length in bytes, newline included if there is one.
    pub bytes: u64,
    /// Why it was dropped (always [`RecordError::Incomplete`]).
    pub reason: RecordError,
}

/// The result of reading a journal.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Replay {
    /// The good records in order.
    pub records: Vec<Record>,
    /// The dropped torn tail, if any.
    pub torn_tail: Option<TornTail>,
    /// Bad complete lines that were skipped (lenient reading only).
    pub skipped: Vec<JournalError>,
    /// Bytes up to the end of the last good line (or skipped bad line):
    /// the length to truncate the journal to before appending again.
    pub valid_len: u64,
}

impl Record {
    /// The record's group, if it has one.
    pub fn group(&self) -> Option<u8> {
        match *self {
            Self::Set { group, .. } | Self::ResetGroup { group } => Some(group),
            Self::Clean => None,
        }
    }

    /// Checks the group number and the value's kind and range.
    pub fn check(&self) -> Result<(), RecordError> {
        if let Some(g) = self.group() {
            if !GROUPS.contains(&g) {
                return Err(RecordError::GroupOutOfRange(g.to_string()));
            }
        }
        if let Self::Set { key, value, .. } = *self {
            key.field.check(value).map_err(LineError::from)?;
        }
        Ok(())
    }

    /// The record's journal line, checksum and newline included.
    pub fn encode(&self) -> String {
        let body = match *self {
            Self::Set { group, key, value } => {
                format!("g{group} {}", format_assignment(key, value))
            }
            Self::ResetGroup { group } => format!("g{group} reset"),
            Self::Clean => "clean".to_owned(),
        };
        format!("{body} *{:08x}\n", crc32fast::hash(body.as_bytes()))
    }

    /// Decodes one journal line (without its newline).
    pub fn decode(line: &[u8]) -> Result<Self, RecordError> {
        let text = std::str::from_utf8(line)
            .map_err(|_| RecordError::Malformed("not UTF-8 text".into()))?;
        let (body, crc) = text.rsplit_once(" *").ok_or(RecordError::NoChecksum)?;
        let is_hex = |b: u8| b.is_ascii_digit() || (b'a'..=b'f').contains(&b);
        if crc.len() != 8 || !crc.bytes().all(is_hex) {
            return Err(RecordError::NoChecksum);
        }
        if u32::from_str_radix(crc, 16).ok() != Some(crc32fast::hash(body.as_bytes())) {
            return Err(RecordError::Checksum);
        }
        Self::decode_body(body)
    }

    fn decode_body(body: &str) -> Result<Self, RecordError> {
        if body == "clean" {
            return Ok(Self::Clean);
        }
        let malformed = || RecordError::Malformed(format!("unknown record `{body}`"));
        let (group_text, rest) = body.split_once(' ').ok_or_else(malformed)?;
        let digits = group_text.strip_prefix('g').ok_or_else(malformed)?;
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(malformed());
        }
        let group = digits
            .parse::<u8>()
            .ok()
            .filter(|g| GROUPS.contains(g))
            .ok_or_else(|| RecordError::GroupOutOfRange(digits.into()))?;
        if rest == "reset" {
            return Ok(Self::ResetGroup { group });
        }
        let (key, value) = parse_assignment(rest)?;
        Ok(Self::Set { group, key, value })
    }
}

/// Encodes records into the bytes to append.
pub fn encode_batch(records: &[Record]) -> Vec<u8> {
    records
        .iter()
        .flat_map(|r| r.encode().into_bytes())
        .collect()
}

/// Reads a journal: a last line without its newline is dropped as a torn
/// tail; any other bad line is the error.
pub fn replay(bytes: &[u8]) -> Result<Replay, JournalError> {
    read(bytes, false)
}

/// Reads a journal, skipping bad complete lines (reported in
/// [`Replay::skipped`]) instead of failing; a torn tail is dropped as by
/// [`replay`].
pub fn replay_lenient(bytes: &[u8]) -> Replay {
    // Lenient reading never fails: every bad line is skipped.
    read(bytes, true).unwrap_or_default()
}

fn read(bytes: &[u8], lenient: bool) -> Result<Replay, JournalError> {
    let mut out = Replay::default();
    let mut offset = 0usize;
    let mut line = 0usize;
    while offset < bytes.len() {
        line += 1;
        let rest = &bytes[offset..];
        let (len, result) = match rest.iter().position(|&b| b == b'\n') {
            Some(nl) => (nl + 1, Record::decode(&rest[..nl])),
            None => (rest.len(), Err(RecordError::Incomplete)),
        };
        match result {
            Ok(record) => out.records.push(record),
            // Only a line without its newline is the last one.
            Err(reason @ RecordError::Incomplete) => {
                out.torn_tail = Some(TornTail {
                    line,
                    offset: offset as u64,
                    bytes: len as u64,
                    reason,
                });
                break;
            }
            Err(error) if lenient => out.skipped.push(JournalError { line, error }),
            Err(error) => return Err(JournalError { line, error }),
        }
        offset += len;
        out.valid_len = offset as u64;
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
