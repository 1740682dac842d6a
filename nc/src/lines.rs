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
        let bytes = self.chunk.bytes();
        let end = memchr::memchr(b'\n', &bytes[start..]).map_or(bytes.len(), |n| start + n);
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
