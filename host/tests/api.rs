//! The Rust API on an embedded emulator: handles and Clean, recording
//! (streamed, replayable, stopped by a write error), and the whole trace
//! corpus sent through the library, recorded and replayed.

// Helpers of the tests may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};

use addipos_host::{Descriptor, EmbeddedOptions, ErrorCode, Handle, Machine, ObjectAddress};
use tc_objects::TcObject;
use tc_request::{Motion, Reply, Request, Runner, SpoolRecord};
use trace::{load_trace, replay, replay_on, Header};
use uoi::{Value, ValueType};

fn d(device: i32, index: i32, sub: i32) -> Descriptor {
    Descriptor {
        bus_number: 1300,
        device_number: device,
        index,
        sub_index: sub,
    }
}

#[test]
fn a_clean_voids_earlier_handles_and_later_ones_work() {
    let m = Machine::open("embedded").unwrap();
    let wkz = m.handle(&d(1, 1, 8)).unwrap();
    let clean = m.handle(&d(0, 1, 0)).unwrap();
    m.write_int(wkz, 7).unwrap();
    assert_eq!(m.read_int(wkz).unwrap(), 7);
    m.write_int(clean, 1).unwrap();
    let e = m.read_int(wkz).unwrap_err();
    assert_eq!(e.code(), ErrorCode::StaleHandle);
    assert!(e.message().contains("Clean"), "{e}");
    assert_eq!(m.last_failure(), e.message());
    let again = m.handle(&d(1, 1, 8)).unwrap();
    assert_eq!(m.read_int(again).unwrap(), 0, "Clean put WKZINDEX back");
    let e = m.handle(&d(1, 1, 7)).unwrap_err();
    assert_eq!(e.code(), ErrorCode::NoSubindex);
    assert_eq!(e.code().code(), 0x0609_0011);
}

/// A writer shared with the test, failing once it holds `limit` bytes.
#[derive(Clone)]
struct Shared {
    bytes: Arc<Mutex<Vec<u8>>>,
    limit: usize,
}

impl Shared {
    fn new(limit: usize) -> Self {
        Self {
            bytes: Arc::default(),
            limit,
        }
    }

    fn text(&self) -> String {
        String::from_utf8(self.bytes.lock().unwrap().clone()).unwrap()
    }
}

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut b = self.bytes.lock().unwrap();
        if b.len() + buf.len() > self.limit {
            return Err(io::Error::other("disk full"));
        }
        b.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn words(x: f64, y: f64) -> addipos_host::AxisWords {
    [Some(x), Some(y), None, None, None, None, None, None]
}

#[test]
fn a_write_error_stops_the_recording_not_the_program() {
    let m = Machine::open("embedded").unwrap();
    let out = Shared::new(300);
    m.record_to(Box::new(out.clone())).unwrap();
    let plane = m.handle(&d(0, 3, 0)).unwrap();
    // Each exec flushes; the buffer fills the writer past its limit.
    for i in 0..200 {
        m.lin(words(f64::from(i), 0.0), Some(600.0)).unwrap();
        m.exec(None).unwrap();
    }
    assert!(!m.recording());
    let why = m.record_failure().unwrap();
    assert!(why.contains("disk full"), "{why}");
    assert!(m.last_failure().contains("recording stopped"));
    assert_eq!(m.read_int(plane).unwrap(), 17);
    assert_eq!(m.position().unwrap()[0], 199.0);
    assert!(out.text().len() <= 300);
}

#[test]
fn recording_starts_only_on_a_fresh_connection() {
    let m = Machine::open("embedded").unwrap();
    m.queue().unwrap();
    let e = m.record_to(Box::new(io::sink())).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Record);
    let dir = tempfile::tempdir().unwrap();
    let fresh = Machine::open("embedded").unwrap();
    let e = fresh
        .record(&dir.path().join("no/such/dir/x.trace"))
        .unwrap_err();
    assert_eq!(e.code(), ErrorCode::Record);
    assert!(e.message().contains("cannot create"), "{e}");
}

/// The library as a trace target: every request of a trace through the
/// API calls a PCAP program makes (a handle per object, initialised
/// again after a Clean).
struct Library {
    m: Machine,
    handles: HashMap<ObjectAddress, Handle>,
}

fn reply<T>(r: addipos_host::Result<T>, ok: impl FnOnce(T) -> Reply) -> Reply {
    match r {
        Ok(v) => ok(v),
        Err(e) => match e.code().access_error() {
            Some(a) => Reply::Access(a),
            None => Reply::Protocol(uoi::wire::ProtocolError::BadPayload),
        },
    }
}

impl Library {
    /// The handle of `addr`: the one kept, or a new one.
    fn handle(&mut self, addr: ObjectAddress) -> addipos_host::Result<Handle> {
        if let Some(h) = self.handles.get(&addr) {
            return Ok(*h);
        }
        let h = self.m.handle(&Descriptor::of(addr))?;
        self.handles.insert(addr, h);
        Ok(h)
    }

    /// A read or write through the object's handle.
    fn through(&mut self, req: &Request, h: Handle) -> addipos_host::Result<Reply> {
        Ok(match *req {
            Request::Read(_, ValueType::I32) => Reply::Value(Value::I32(self.m.read_int(h)?)),
            Request::Read(_, ValueType::F64) => Reply::Value(Value::F64(self.m.read_double(h)?)),
            Request::Write(_, Value::I32(v)) => self.m.write_int(h, v).map(|()| Reply::Ok)?,
            Request::Write(_, Value::F64(v)) => self.m.write_double(h, v).map(|()| Reply::Ok)?,
            _ => unreachable!(),
        })
    }

    /// An object access; a handle made stale by a Clean is initialised
    /// again, as a PCAP program must.
    fn access(&mut self, req: &Request, addr: ObjectAddress) -> Reply {
        let first = self.handle(addr).and_then(|h| self.through(req, h));
        let result = match first {
            Err(e) if e.code() == ErrorCode::StaleHandle => {
                self.handles.remove(&addr);
                self.handle(addr).and_then(|h| self.through(req, h))
            }
            other => other,
        };
        reply(result, |r| r)
    }

    fn motion(&mut self, m: &Motion) -> Reply {
        let ok = |()| Reply::Ok;
        match *m {
            Motion::Lin { words, feed } => reply(self.m.lin(words, feed), ok),
            Motion::Rap { words, feed } => reply(self.m.rap(words, feed), ok),
            Motion::Cir {
                dir,
                words,
                centre,
                feed,
            } => reply(self.m.cir(dir, words, centre, feed), ok),
            Motion::Ja { words } => reply(self.m.ja(words), ok),
            Motion::Js { axes } => reply(self.m.js(axes), ok),
            Motion::Ssf { axis, function } => reply(self.m.ssf(axis.into(), function), ok),
            Motion::Rs => reply(self.m.rs(), ok),
        }
    }
}

/// Why the library could not carry a trace's request out.
#[derive(Debug, thiserror::Error)]
enum LibraryError {
    /// A request no trace holds.
    #[error("not in traces: {0:?}")]
    NotInTraces(Request),
    /// The library's error.
    #[error(transparent)]
    Library(#[from] addipos_host::Error),
}

impl Runner for Library {
    type Error = LibraryError;

    fn run(&mut self, req: &Request) -> Result<Reply, LibraryError> {
        Ok(match req {
            Request::Read(a, _) | Request::Write(a, _) => self.access(req, *a),
            Request::Motion(m) => self.motion(m),
            Request::Exec(n) => reply(self.m.exec(*n), |()| Reply::Ok),
            Request::Pos => reply(self.m.position(), Reply::Pos),
            Request::Queue => reply(self.m.queue(), Reply::Queue),
            other => return Err(LibraryError::NotInTraces(other.clone())),
        })
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, LibraryError> {
        Ok(self.m.take_spooled())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], LibraryError> {
        let mut out = [0u8; 3];
        for (sub, o) in (0..3).zip(out.iter_mut()) {
            let h = self.handle(TcObject::AxisNr.sub(sub))?;
            *o = self.m.read_int(h)? as u8;
        }
        Ok(out)
    }
}

fn options(h: &Header) -> EmbeddedOptions {
    EmbeddedOptions {
        realtime: None,
        start: h.start,
        cycle: h.cycle,
        cycle_ms: h.cycle.secs() * 1e3,
        spool_capacity: h.spool_capacity,
    }
}

#[test]
fn the_corpus_through_the_library_answers_as_traced_and_its_recordings_replay() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../traces");
    let dir = tempfile::tempdir().unwrap();
    let files = trace::trace_files(&corpus).unwrap();
    assert!(files.len() > 50, "the corpus: {}", files.len());
    for file in files {
        let t = load_trace(&file).unwrap();
        // FEED_ADAPT is an NC program's request (docs/trace-format.md): a
        // legacy host program has no call for it.
        let nc_only = t
            .steps
            .iter()
            .any(|s| matches!(s.request, tc_request::Request::FeedAdaption { .. }));
        if nc_only {
            continue;
        }
        let m = Machine::embedded(options(&t.header));
        let rec = dir.path().join(file.file_name().unwrap());
        m.record(&rec).unwrap();
        m.set_spool_log(true);
        let mut lib = Library {
            m,
            handles: HashMap::new(),
        };
        let through = replay_on(&t, &mut lib);
        assert!(through.is_empty(), "{}: {:?}", file.display(), through);
        lib.m.stop_recording();
        assert!(lib.m.record_failure().is_none());
        let recorded = load_trace(&rec).unwrap();
        let again = replay(&recorded);
        assert!(again.is_empty(), "{}: {:?}", rec.display(), again);
    }
}
