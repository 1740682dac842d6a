//! Recording: a connection's session written as a conformance trace
//! (docs/trace-format.md) while it happens, so that `addipos replay`
//! runs it again and compares every answer.
//!
//! Every request goes out as its trace line with the answer as the
//! expectation (`R 1300/1/1/3 i => 1`), followed by the elements it
//! spooled as `<` lines; the cycles a real-time clock ran between
//! requests as `EXEC n => ok`; what has no trace form (a handle
//! initialised, a call refused by the library before it reached the
//! emulator) as a `#` comment. The trace streams through a buffer to its
//! file: memory stays flat for a session of any length.

use std::fmt::Write as _;
use std::io::{self, BufWriter, Write};

use tc_module::{AxisPos, AXIS_NAMES};
use tc_request::text::format_record;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::{ObjectAddress, Value, ValueType};

/// Size of the buffer between the recorder and its file.
const BUFFER_BYTES: usize = 64 * 1024;

/// What the header of a recorded trace says: where the machine started,
/// its cycle and its spooler, each only when it is not the default.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordHeader {
    /// `@name`.
    pub name: String,
    /// `@start`, when not all 0.
    pub start: AxisPos,
    /// `@cycle` in ms, when not 1 ms.
    pub cycle_ms: f64,
    /// `@spool`, when not the default capacity.
    pub spool_capacity: usize,
    /// A comment under the header (what kind of session it is).
    pub note: String,
}

/// A trace being written.
pub struct Recorder {
    out: BufWriter<Box<dyn Write + Send>>,
    /// One line, reused.
    line: String,
    /// The `R ADDR i => ` of recently read objects, by [`prefix_slot`].
    prefixes: Vec<(Option<ObjectAddress>, String)>,
}

/// Places of the read-prefix cache.
const PREFIX_SLOTS: usize = 64;

/// The place of `addr` in the read-prefix cache.
fn prefix_slot(addr: ObjectAddress) -> usize {
    let mix = usize::from(addr.device) * 7 + usize::from(addr.index) * 31 + usize::from(addr.sub);
    mix % PREFIX_SLOTS
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Recorder")
    }
}

/// `X.. Y.. ..` of all axes.
fn axis_text(out: &mut String, p: &AxisPos) {
    for (i, (name, v)) in AXIS_NAMES.iter().zip(p).enumerate() {
        let sep = if i == 0 { "" } else { " " };
        let _ = write!(out, "{sep}{name}{v}");
    }
}

/// One line of comment text: line breaks become spaces.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

impl Recorder {
    /// Starts a trace on `out` with its header.
    pub fn start(out: Box<dyn Write + Send>, header: &RecordHeader) -> io::Result<Self> {
        let mut r = Self {
            out: BufWriter::with_capacity(BUFFER_BYTES, out),
            line: String::new(),
            prefixes: vec![(None, String::new()); PREFIX_SLOTS],
        };
        let mut h = format!("@name {}\n", one_line(&header.name));
        if header.start.iter().any(|&v| v != 0.0) {
            h.push_str("@start ");
            axis_text(&mut h, &header.start);
            h.push('\n');
        }
        if header.cycle_ms != 1.0 {
            let _ = writeln!(h, "@cycle {}ms", header.cycle_ms);
        }
        if header.spool_capacity != tc_module::DEFAULT_SPOOL_CAPACITY {
            let _ = writeln!(h, "@spool {}", header.spool_capacity);
        }
        if !header.note.is_empty() {
            let _ = writeln!(h, "# {}", one_line(&header.note));
        }
        r.out.write_all(h.as_bytes())?;
        Ok(r)
    }

    /// A request with its answer as the expectation, then the elements
    /// it spooled (`axis_nr`: the machine axes allocated as X, Y, Z, for
    /// the `I J K` of arcs).
    pub fn exchange(
        &mut self,
        req: &Request,
        reply: &Reply,
        spooled: &[SpoolRecord],
        axis_nr: [u8; 3],
    ) -> io::Result<()> {
        let l = &mut self.line;
        l.clear();
        let _ = write!(l, "{req} => ");
        match reply {
            Reply::Ok => l.push_str("ok"),
            Reply::Value(v) => {
                let _ = write!(l, "{v}");
            }
            Reply::Pos(p) => axis_text(l, p),
            Reply::Queue(n) => {
                let _ = write!(l, "{n}");
            }
            Reply::Access(e) => {
                let _ = write!(l, "err {}", e.name());
            }
            Reply::Spool(..) | Reply::Protocol(_) => {
                l.clear();
                let _ = write!(l, "# {req}: answered {reply:?}");
            }
        }
        l.push('\n');
        for e in spooled {
            let _ = writeln!(l, "< {}", format_record(e, axis_nr));
        }
        self.out.write_all(l.as_bytes())
    }

    /// A read with its answer: the commonest request, written without
    /// the formatting machinery (a read spools nothing).
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType, reply: &Reply) -> io::Result<()> {
        let (Reply::Value(Value::I32(v)), ValueType::I32) = (reply, ty) else {
            return self.exchange(&Request::Read(addr, ty), reply, &[], [0, 1, 2]);
        };
        let slot = prefix_slot(addr);
        let prefix = &mut self.prefixes[slot];
        if prefix.0 != Some(addr) {
            *prefix = (Some(addr), format!("R {addr} i => "));
        }
        let l = &mut self.line;
        l.clear();
        l.push_str(&prefix.1);
        l.push_str(itoa::Buffer::new().format(*v));
        l.push('\n');
        self.out.write_all(l.as_bytes())
    }

    /// A request that was carried out and succeeded (the cycles a clock
    /// ran, an `EXEC` cut short): `REQ => ok`.
    pub fn ran(&mut self, req: &Request) -> io::Result<()> {
        writeln!(self.out, "{req} => ok")
    }

    /// A comment line.
    pub fn comment(&mut self, text: &str) -> io::Result<()> {
        writeln!(self.out, "# {}", one_line(text))
    }

    /// Everything written so far handed to the file.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    /// A writer whose bytes a test can read.
    #[derive(Clone, Default)]
    struct Shared(Arc<Mutex<Vec<u8>>>);

    impl Write for Shared {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_header_names_only_what_is_not_the_default_and_reads_are_written_whole() {
        let buf = Shared::default();
        let header = RecordHeader {
            name: "t\nx".into(),
            start: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5],
            cycle_ms: 0.5,
            spool_capacity: 8,
            note: "stepped".into(),
        };
        let mut r = Recorder::start(Box::new(buf.clone()), &header).unwrap();
        let plane = tc_objects::TcObject::TcPlane.address();
        r.read(plane, ValueType::I32, &Reply::Value(Value::I32(-17)))
            .unwrap();
        let radius = tc_objects::TcObject::Radius.of(12);
        r.read(radius, ValueType::F64, &Reply::Value(Value::F64(2.5)))
            .unwrap();
        let err = Reply::Access(uoi::AccessError::WriteOnly);
        r.read(plane, ValueType::F64, &err).unwrap();
        r.flush().unwrap();
        let text = String::from_utf8(buf.0.lock().unwrap().clone()).unwrap();
        assert_eq!(
            text,
            "@name t x\n@start X1 Y0 Z0 A0 B0 C0 U0 V0.5\n@cycle 0.5ms\n@spool 8\n# stepped\n\
             R 1300/0/3/0 i => -17\nR 1300/1/12/6 d => 2.5\nR 1300/0/3/0 d => err WriteOnly\n"
        );
    }
}
