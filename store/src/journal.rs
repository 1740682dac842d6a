//! The journal: one line per change, appended and synced before the change
//! is acknowledged, each line ending in a CRC-32 of its text; the changes
//! of one group commit (one append, one sync) are closed by a `batch`
//! line that gives their count, their length in bytes and a CRC-32 over
//! those bytes.
//!
//! ```text
//! g3 wz[5].radius 300000 *26a0b7f4
//! g3 reset *b7948462
//! batch 2 52 0c1a2b3d *5e6f7a8b
//! clean *f1b0ad49
//! batch 1 16 8a9b0c1d *2e3f4a5b
//! ```
//!
//! The batch is the unit of recovery (docs/tool-files.md): a power cut
//! can keep the later part of the last batch's write and not the earlier
//! one (NUL bytes, then complete-looking lines), or the earlier part
//! without its `batch` line; nothing of that batch was acknowledged, so
//! it is dropped at the start (reported as the journal's torn tail). A
//! batch that is damaged in another way (a flipped bit: no NUL byte), or
//! followed by an intact later batch, is corruption and refuses the
//! replay. Lines before the first `batch` line (a journal of an older
//! version, which had none) are records on their own: a last line
//! without its newline is a torn tail, any other bad line is corruption.

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
    /// A batch's bytes do not match its `batch` line (length, count or
    /// checksum).
    #[error("batch damaged: {0}")]
    Batch(String),
    /// The last batch was cut by a crash or power cut (NUL bytes where
    /// its beginning should be, or its `batch` line missing): it was
    /// never acknowledged and is dropped.
    #[error("last batch cut short by a crash (never acknowledged)")]
    TornBatch,
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
/// newline, or the last batch, cut by a crash before it was acknowledged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TornTail {
    /// Its (first) line number, counting from 1.
    pub line: usize,
    /// Byte offset where it starts (the journal's valid length).
    pub offset: u64,
    /// Its length in bytes, newline included if there is one.
    pub bytes: u64,
    /// Why it was dropped: [`RecordError::Incomplete`] (a line cut short)
    /// or [`RecordError::TornBatch`] (a batch: a copy of the journal is
    /// kept before it is cut off).
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
        Self::decode_body(checked_body(line)?)
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

/// Encodes records as journal lines, without a `batch` line (the form of
/// journals written before batches were closed).
pub fn encode_lines(records: &[Record]) -> Vec<u8> {
    records
        .iter()
        .flat_map(|r| r.encode().into_bytes())
        .collect()
}

/// Encodes records into the bytes of one batch: their lines, then the
/// `batch` line that closes them.
pub fn encode_batch(records: &[Record]) -> Vec<u8> {
    let mut bytes = encode_lines(records);
    let trailer = Trailer {
        records: records.len(),
        bytes: bytes.len() as u64,
        crc: crc32fast::hash(&bytes),
    };
    bytes.extend_from_slice(trailer.encode().as_bytes());
    bytes
}

/// The `batch <records> <bytes> <crc>` line closing a batch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Trailer {
    /// Records in the batch.
    pub records: usize,
    /// Bytes of the batch's record lines, before this line.
    pub bytes: u64,
    /// CRC-32 of those bytes.
    pub crc: u32,
}

impl Trailer {
    fn encode(&self) -> String {
        let body = format!("batch {} {} {:08x}", self.records, self.bytes, self.crc);
        format!("{body} *{:08x}\n", crc32fast::hash(body.as_bytes()))
    }
}

/// The first line of a journal of batches (its bytes go out with the
/// journal's first batch, in the same write).
const FORMAT_BODY: &str = "journal batches";

/// The first line of a journal of batches, checksum and newline included.
pub fn format_line() -> String {
    format!(
        "{FORMAT_BODY} *{:08x}\n",
        crc32fast::hash(FORMAT_BODY.as_bytes())
    )
}

/// One journal line: a record, the line closing a batch, or the first
/// line of a journal of batches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Line {
    Record(Record),
    Trailer(Trailer),
    Format,
}

/// Decodes one journal line (without its newline).
pub(crate) fn decode_line(line: &[u8]) -> Result<Line, RecordError> {
    if line.starts_with(b"journal ") {
        let body = checked_body(line)?;
        return match body {
            FORMAT_BODY => Ok(Line::Format),
            _ => Err(RecordError::Malformed(format!(
                "unknown journal form `{body}` (written by a newer version?)"
            ))),
        };
    }
    let is_trailer = line.starts_with(b"batch ");
    if !is_trailer {
        return Record::decode(line).map(Line::Record);
    }
    let body = checked_body(line)?;
    let bad = || RecordError::Malformed(format!("bad batch line `{body}`"));
    let mut words = body.split(' ').skip(1);
    let mut next = || words.next().ok_or_else(bad);
    let records = next()?.parse().map_err(|_| bad())?;
    let bytes = next()?.parse().map_err(|_| bad())?;
    let crc = next()?;
    let crc = (crc.len() == 8)
        .then(|| u32::from_str_radix(crc, 16).ok())
        .flatten()
        .ok_or_else(bad)?;
    Ok(Line::Trailer(Trailer {
        records,
        bytes,
        crc,
    }))
}

/// The text of a line before its ` *<crc>`, if the checksum matches.
fn checked_body(line: &[u8]) -> Result<&str, RecordError> {
    let text =
        std::str::from_utf8(line).map_err(|_| RecordError::Malformed("not UTF-8 text".into()))?;
    let (body, crc) = text.rsplit_once(" *").ok_or(RecordError::NoChecksum)?;
    let is_hex = |b: u8| b.is_ascii_digit() || (b'a'..=b'f').contains(&b);
    if crc.len() != 8 || !crc.bytes().all(is_hex) {
        return Err(RecordError::NoChecksum);
    }
    if u32::from_str_radix(crc, 16).ok() != Some(crc32fast::hash(body.as_bytes())) {
        return Err(RecordError::Checksum);
    }
    Ok(body)
}

#[cfg(test)]
mod tests;
