//! Reading the journal batch by batch, by the rules of [`crate::journal`]:
//! records before the first `batch` line one by one (the older form), then
//! every batch checked against its `batch` line; an unacknowledged last
//! batch cut by a crash is dropped as the torn tail.

use crate::journal::{
    decode_line, format_line, JournalError, Line, RecordError, Replay, TornTail, Trailer,
};

/// One line of the journal as read.
#[derive(Debug)]
struct Scanned {
    /// Line number, from 1.
    no: usize,
    /// Offset of its first byte.
    start: usize,
    /// Offset after its newline (or the end of the journal).
    end: usize,
    /// Whether it ends in a newline.
    complete: bool,
    /// What it holds.
    decoded: Result<Line, RecordError>,
    /// Whether it holds a NUL byte (what a power cut leaves where data
    /// was not written yet).
    nul: bool,
}

impl Scanned {
    /// Damage that a crash cannot explain: a complete line, without NUL
    /// bytes, that does not decode (a flipped bit, an edit).
    fn corrupt(&self) -> bool {
        self.complete && !self.nul && self.decoded.is_err()
    }
}

/// The journal's lines.
fn scan(bytes: &[u8]) -> Vec<Scanned> {
    let mut lines = Vec::new();
    let mut start = 0;
    while start < bytes.len() {
        let rest = &bytes[start..];
        let (text, len, complete) = match rest.iter().position(|&b| b == b'\n') {
            Some(nl) => (&rest[..nl], nl + 1, true),
            None => (rest, rest.len(), false),
        };
        let decoded = if complete {
            decode_line(text)
        } else {
            Err(RecordError::Incomplete)
        };
        lines.push(Scanned {
            no: lines.len() + 1,
            start,
            end: start + len,
            complete,
            decoded,
            nul: text.contains(&0),
        });
        start += len;
    }
    lines
}

/// The state of a read.
struct Reader<'a> {
    bytes: &'a [u8],
    lines: &'a [Scanned],
    lenient: bool,
    out: Replay,
    /// Index of the first line after the last batch closed.
    next: usize,
    /// Whether a `batch` line was seen (the journal is of the batch form).
    batched: bool,
    /// Index of the first line of a damaged batch that looks torn by a
    /// crash: dropped, unless an intact batch follows.
    torn: Option<usize>,
}

/// Reads a journal: a torn tail (a last line without its newline, or an
/// unacknowledged last batch cut by a crash) is dropped; any other bad
/// line or batch is the error.
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

/// Reads a journal (`lenient`: bad lines skipped instead of refused).
fn read(bytes: &[u8], lenient: bool) -> Result<Replay, JournalError> {
    let lines = scan(bytes);
    let mut r = Reader {
        bytes,
        lines: &lines,
        lenient,
        out: Replay::default(),
        next: 0,
        batched: false,
        torn: None,
    };
    // A journal of batches says so in its first line (or said so: a
    // power cut during the first batch can leave NUL bytes in its place).
    let format =
        |l: &&Scanned| matches!(l.decoded, Ok(Line::Format)) || torn_format(&bytes[l.start..l.end]);
    if let Some(first) = lines.first().filter(format) {
        r.batched = true;
        r.next = 1;
        r.out.valid_len = first.end as u64;
    }
    for (i, line) in lines.iter().enumerate() {
        if let Ok(Line::Trailer(t)) = line.decoded {
            r.close_batch(i, t)?;
        }
    }
    r.finish()?;
    Ok(r.out)
}

/// Whether `line` is the first line of a journal of batches with some of
/// its bytes never written (NUL): each byte NUL or the line's own.
fn torn_format(line: &[u8]) -> bool {
    let format = format_line();
    line.len() == format.len()
        && line.contains(&0)
        && line
            .iter()
            .zip(format.as_bytes())
            .all(|(&b, &f)| b == 0 || b == f)
}

impl Reader<'_> {
    /// A bad line: the error, or skipped when lenient.
    fn bad(&mut self, line: &Scanned, error: RecordError) -> Result<(), JournalError> {
        let error = JournalError {
            line: line.no,
            error,
        };
        if !self.lenient {
            return Err(error);
        }
        self.out.skipped.push(error);
        self.out.valid_len = line.end as u64;
        Ok(())
    }

    /// Takes the records of `lines` one by one (bad ones refused or
    /// skipped).
    fn take_lines(&mut self, from: usize, to: usize) -> Result<(), JournalError> {
        let lines = self.lines;
        for line in &lines[from..to] {
            match &line.decoded {
                Ok(Line::Record(r)) => {
                    self.out.records.push(*r);
                    self.out.valid_len = line.end as u64;
                }
                Ok(Line::Trailer(_)) => {}
                Ok(Line::Format) => self.bad(
                    line,
                    RecordError::Malformed("a journal's first line in the middle of it".into()),
                )?,
                Err(e) => self.bad(line, e.clone())?,
            }
        }
        Ok(())
    }

    /// Where the batch closed by line `i` starts (the index of its first
    /// line), if its length leads to a line start after the last batch.
    fn batch_start(&self, i: usize, t: Trailer) -> Option<usize> {
        let end = self.lines[i].start;
        let start = end.checked_sub(usize::try_from(t.bytes).ok()?)?;
        let first = self.lines.get(self.next)?.start;
        if start < first {
            return None;
        }
        (self.next..=i).find(|&k| self.lines[k].start == start)
    }

    /// Whether lines `from..i` are the batch line `i` closes.
    fn intact(&self, from: usize, i: usize, t: Trailer) -> bool {
        let lines = &self.lines[from..i];
        let (start, end) = (self.lines[from].start, self.lines[i].start);
        lines.len() == t.records
            && lines
                .iter()
                .all(|l| matches!(l.decoded, Ok(Line::Record(_))))
            && crc32fast::hash(&self.bytes[start..end]) == t.crc
    }

    /// Line `i` closes a batch: the lines before the batch (older form)
    /// are taken one by one, the batch whole if intact. A damaged batch
    /// that looks torn is held back (dropped unless an intact batch
    /// follows); one damaged otherwise is corruption.
    fn close_batch(&mut self, i: usize, t: Trailer) -> Result<(), JournalError> {
        let from = self.batch_start(i, t);
        let ok = from.is_some_and(|f| self.intact(f, i, t));
        let first = self.next;
        self.next = i + 1;
        if let Some(torn) = self.torn {
            return self.after_torn(torn, ok.then_some((from.unwrap_or(first), i)));
        }
        let start = from.unwrap_or(first);
        if !self.batched {
            self.take_lines(first, start)?;
        } else if start > first {
            // Lines outside any batch in a journal of batches.
            return self.damaged(first, i, t);
        }
        self.batched = true;
        if ok {
            self.take_lines(start, i)?;
            self.out.valid_len = self.lines[i].end as u64;
            return Ok(());
        }
        self.damaged(start, i, t)
    }

    /// A batch closes after the torn one that starts at line index `torn`:
    /// if it is intact (`intact`: its lines), the torn batch was
    /// acknowledged data after all, damaged: refused (or skipped).
    fn after_torn(
        &mut self,
        torn: usize,
        intact: Option<(usize, usize)>,
    ) -> Result<(), JournalError> {
        let Some((from, i)) = intact else {
            return Ok(());
        };
        let line = &self.lines[torn];
        let why = format!(
            "damaged, and followed by the intact batch ending at line {}: acknowledged data \
             is damaged",
            self.lines[i].no
        );
        self.bad(line, RecordError::Batch(why))?;
        self.torn = None;
        self.take_lines(from, i)?;
        self.out.valid_len = self.lines[i].end as u64;
        Ok(())
    }

    /// The batch of lines `from..=i` does not match its `batch` line.
    fn damaged(&mut self, from: usize, i: usize, t: Trailer) -> Result<(), JournalError> {
        let lines = &self.lines[from..=i];
        if !lines.iter().any(|l| l.nul) {
            // A bad line says what is wrong with it (refused or skipped
            // as its records are taken); else the batch does.
            if lines.iter().all(|l| l.decoded.is_ok()) {
                let why = format!(
                    "its lines do not match the batch line {} ({} records, {} bytes, \
                     checksum {:08x})",
                    self.lines[i].no, t.records, t.bytes, t.crc
                );
                self.bad(&lines[0], RecordError::Batch(why))?;
            }
            self.take_lines(from, i)?;
            self.out.valid_len = self.lines[i].end as u64;
            return Ok(());
        }
        self.torn = Some(from);
        Ok(())
    }

    /// The end of the journal: a torn batch, or the lines after the last
    /// batch (an unfinished batch, or the older form's records).
    fn finish(&mut self) -> Result<(), JournalError> {
        let lines = self.lines;
        let tail = &lines[self.next..];
        if let Some(torn) = self.torn {
            return self.drop_from(torn, RecordError::TornBatch);
        }
        if !self.batched {
            // A first batch torn with its first line lost: NUL bytes to
            // the end, nothing intact after them.
            let first_bad = tail.iter().position(|l| l.decoded.is_err());
            if let Some(k) = first_bad.filter(|&k| tail[k].nul) {
                if tail[k..].iter().all(|l| l.decoded.is_err()) {
                    self.take_lines(self.next, self.next + k)?;
                    return self.drop_from(self.next + k, RecordError::TornBatch);
                }
            }
            let whole = tail.iter().take_while(|l| l.complete).count();
            self.take_lines(self.next, self.next + whole)?;
            if whole < tail.len() {
                self.drop_from(self.next + whole, RecordError::Incomplete)?;
            }
            return Ok(());
        }
        if let Some(line) = tail.iter().find(|l| l.corrupt()) {
            let error = line.decoded.clone().err().unwrap_or(RecordError::TornBatch);
            self.bad(line, error)?;
        }
        match tail {
            [] => Ok(()),
            [only] if !only.complete => self.drop_from(self.next, RecordError::Incomplete),
            _ => self.drop_from(self.next, RecordError::TornBatch),
        }
    }

    /// Drops every line from index `from` on as the torn tail.
    fn drop_from(&mut self, from: usize, reason: RecordError) -> Result<(), JournalError> {
        let Some(line) = self.lines.get(from) else {
            return Ok(());
        };
        let offset = line.start as u64;
        self.out.torn_tail = Some(TornTail {
            line: line.no,
            offset,
            bytes: self.bytes.len() as u64 - offset,
            reason,
        });
        self.out.valid_len = offset;
        Ok(())
    }
}
