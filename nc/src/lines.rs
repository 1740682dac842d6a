//! The lines of a program, read ahead a chunk at a time: each chunk of
//! whole lines is checked as UTF-8 text once, not line by line, and its
//! lines are handed out where they lie. A line longer than
//! [`MAX_LINE_BYTES`] is not held: it is read past, and handed out as
//! [`Line::TooLong`].

use std::io::{self, BufRead};

/// Longest line of a program, in bytes before its line end (`\n`):
/// 1 MiB (decision 241). A longer line is an error on its line, read past
/// without being held, so that memory stays bounded by this and the
/// reader's buffer whatever the input.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Bytes of a line too long that are kept: enough for its block number.
const HEAD_BYTES: usize = 64;

/// One line, without its line end.
pub enum Line<'a> {
    /// A line of a chunk that is UTF-8 text, and whether the chunk is
    /// ASCII.
    Text(&'a str, bool),
    /// A line of a chunk that is not: the line itself may still be.
    Bytes(&'a [u8]),
    /// A line longer than [`MAX_LINE_BYTES`]: its first bytes (at most
    /// 64), the rest unread.
    TooLong(&'a [u8]),
}

/// Whole lines read ahead.
enum Chunk {
    /// UTF-8 text, and whether it is ASCII.
    Text(String, bool),
    Bytes(Vec<u8>),
}

impl Chunk {
    fn bytes(&self) -> &[u8] {
        match self {
            Chunk::Text(s, _) => s.as_bytes(),
            Chunk::Bytes(b) => b,
        }
    }

    fn into_bytes(self) -> Vec<u8> {
        match self {
            Chunk::Text(s, _) => s.into_bytes(),
            Chunk::Bytes(b) => b,
        }
    }
}

/// The lines `reader` delivers, in memory bounded by the reader's buffer
/// and the longest line.
pub struct Lines<R> {
    reader: R,
    chunk: Chunk,
    /// Where the next line of `chunk` starts.
    pos: usize,
    /// The line ends of `chunk` (found in one sweep), and the next one.
    ends: Vec<usize>,
    next_end: usize,
    /// The start of a line whose end was not read yet.
    tail: Vec<u8>,
    /// Whether the next line is one too long, read past; its first bytes.
    overlong: bool,
    head: Vec<u8>,
    eof: bool,
}

impl<R: BufRead> Lines<R> {
    /// Lines of `reader`.
    pub fn new(reader: R) -> Self {
        Lines {
            reader,
            chunk: Chunk::Bytes(Vec::new()),
            pos: 0,
            ends: Vec::new(),
            next_end: 0,
            tail: Vec::new(),
            overlong: false,
            head: Vec::new(),
            eof: false,
        }
    }

    /// The next line; `None` at the end, an error when reading fails.
    pub fn next_line(&mut self) -> Option<io::Result<Line<'_>>> {
        while !self.overlong && self.pos >= self.chunk.bytes().len() {
            match self.refill() {
                Ok(true) => {}
                Ok(false) => return None,
                Err(e) => return Some(Err(e)),
            }
        }
        if self.overlong {
            self.overlong = false;
            return Some(Ok(Line::TooLong(&self.head)));
        }
        let start = self.pos;
        let end = match self.ends.get(self.next_end) {
            Some(&end) => end,
            None => self.chunk.bytes().len(),
        };
        self.next_end += 1;
        self.pos = end + 1;
        if end - start > MAX_LINE_BYTES {
            let head = &self.chunk.bytes()[start..start + HEAD_BYTES];
            return Some(Ok(Line::TooLong(head)));
        }
        Some(Ok(match &self.chunk {
            Chunk::Text(s, ascii) => Line::Text(&s[start..end], *ascii),
            Chunk::Bytes(b) => Line::Bytes(&b[start..end]),
        }))
    }

    /// Reads the next whole lines (at least one, unless the file ends);
    /// false when nothing is left.
    fn refill(&mut self) -> io::Result<bool> {
        if self.eof {
            return Ok(false);
        }
        let mut bytes = std::mem::replace(&mut self.chunk, Chunk::Bytes(Vec::new())).into_bytes();
        bytes.clear();
        bytes.append(&mut self.tail);
        let mut searched = 0;
        loop {
            let buf = match self.reader.fill_buf() {
                Ok(buf) => buf,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    self.tail = bytes;
                    return Err(e);
                }
            };
            if buf.is_empty() {
                self.eof = true;
                break;
            }
            let n = buf.len();
            bytes.extend_from_slice(buf);
            self.reader.consume(n);
            if memchr::memchr(b'\n', &bytes[searched..]).is_some() {
                break;
            }
            searched = bytes.len();
            if searched > MAX_LINE_BYTES {
                // All of `bytes` is the start of one line, too long.
                self.read_past_line(bytes)?;
                return Ok(true);
            }
        }
        let end = if self.eof {
            bytes.len()
        } else {
            memchr::memrchr(b'\n', &bytes).map_or(0, |k| k + 1)
        };
        self.tail = bytes.split_off(end);
        self.pos = 0;
        self.ends.clear();
        self.ends.extend(memchr::memchr_iter(b'\n', &bytes));
        self.next_end = 0;
        self.chunk = match String::from_utf8(bytes) {
            Ok(s) => {
                let ascii = s.is_ascii();
                Chunk::Text(s, ascii)
            }
            Err(e) => Chunk::Bytes(e.into_bytes()),
        };
        Ok(!self.chunk.bytes().is_empty())
    }

    /// Reads past the rest of a line too long, `start` its start, without
    /// holding it: the next line handed out is [`Line::TooLong`].
    fn read_past_line(&mut self, mut start: Vec<u8>) -> io::Result<()> {
        start.truncate(HEAD_BYTES);
        self.head = start;
        self.overlong = true;
        self.chunk = Chunk::Bytes(Vec::new());
        self.pos = 0;
        self.ends.clear();
        self.next_end = 0;
        loop {
            let buf = match self.reader.fill_buf() {
                Ok(buf) => buf,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if buf.is_empty() {
                self.eof = true;
                return Ok(());
            }
            if let Some(k) = memchr::memchr(b'\n', buf) {
                self.reader.consume(k + 1);
                return Ok(());
            }
            let n = buf.len();
            self.reader.consume(n);
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use super::*;

    /// Every line of `bytes` read through a reader buffer of `capacity`
    /// bytes, as text or as raw bytes.
    fn lines(bytes: &[u8], capacity: usize) -> Vec<Result<String, Vec<u8>>> {
        let mut lines = Lines::new(io::BufReader::with_capacity(capacity, bytes));
        let mut out = Vec::new();
        while let Some(line) = lines.next_line() {
            out.push(match line.unwrap() {
                Line::Text(t, ascii) => {
                    // The chunk's flag: an ASCII chunk has ASCII lines.
                    assert!(!ascii || t.is_ascii());
                    Ok(t.to_string())
                }
                Line::Bytes(b) => Err(b.to_vec()),
                Line::TooLong(_) => panic!("no line here is too long"),
            });
        }
        out
    }

    #[test]
    fn lines_come_whole_whatever_the_buffer() {
        let text = "N1 X1\r\n\nN2 Y2 (ä)\nN3 a long line of words X1 Y2 Z3\nlast";
        let expected: Vec<Result<String, Vec<u8>>> =
            text.split('\n').map(|l| Ok(l.to_string())).collect();
        for capacity in [1, 2, 3, 7, 64, 4096] {
            assert_eq!(lines(text.as_bytes(), capacity), expected, "{capacity}");
        }
        assert!(lines(b"", 4).is_empty());
        assert_eq!(lines(b"\n", 4), vec![Ok(String::new())]);
    }

    #[test]
    fn a_line_too_long_is_read_past_and_handed_out_as_its_start() {
        let long = format!("N12 {}", "X".repeat(MAX_LINE_BYTES));
        let just = "Y".repeat(MAX_LINE_BYTES);
        let text = format!("N1\n{long}\nN3\n{just}\n{long}");
        for capacity in [1000, 8192, text.len()] {
            let reader = io::BufReader::with_capacity(capacity, text.as_bytes());
            let mut lines = Lines::new(reader);
            let mut got = Vec::new();
            while let Some(line) = lines.next_line() {
                got.push(match line.unwrap() {
                    Line::Text(t, _) => format!("text {}", t.len()),
                    Line::Bytes(b) => format!("bytes {}", b.len()),
                    Line::TooLong(head) => {
                        assert_eq!(head, &long.as_bytes()[..HEAD_BYTES]);
                        "too long".to_string()
                    }
                });
            }
            let just = format!("text {MAX_LINE_BYTES}");
            let expected = ["text 2", "too long", "text 2", &just, "too long"];
            assert_eq!(got, expected, "{capacity}");
        }
    }

    #[test]
    fn a_chunk_with_bad_text_hands_out_bytes() {
        let bytes = b"N1 X1\nN2 \xff\nN3 X3\n";
        let got = lines(bytes, 64);
        assert_eq!(got.len(), 3);
        assert_eq!(got[1], Err(b"N2 \xff".to_vec()));
        assert_eq!(got[0], Err(b"N1 X1".to_vec()));
        // With a small buffer the good lines come in chunks of their own.
        let got = lines(bytes, 4);
        assert_eq!(got[0], Ok("N1 X1".to_string()));
        assert_eq!(got[1], Err(b"N2 \xff".to_vec()));
    }
}
