//! The lines of a program, read ahead a chunk at a time: each chunk of
//! whole lines is checked as UTF-8 text once, not line by line, and its
//! lines are handed out where they lie.

use std::io::{self, BufRead};

/// One line, without its line end.
pub enum Line<'a> {
    /// A line of a chunk that is UTF-8 text, and whether the chunk is
    /// ASCII.
    Text(&'a str, bool),
    /// A line of a chunk that is not: the line itself may still be.
    Bytes(&'a [u8]),
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
            eof: false,
        }
    }

    /// The next line; `None` at the end, an error when reading fails.
    pub fn next_line(&mut self) -> Option<io::Result<Line<'_>>> {
        while self.pos >= self.chunk.bytes().len() {
            match self.refill() {
                Ok(true) => {}
                Ok(false) => return None,
                Err(e) => return Some(Err(e)),
            }
        }
        let start = self.pos;
        let end = match self.ends.get(self.next_end) {
            Some(&end) => end,
            None => self.chunk.bytes().len(),
        };
        self.next_end += 1;
        self.pos = end + 1;
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
