//! `addipos serve --record FILE`: the shared emulator's journal
//! ([`emulator::Journal`]) written as one conformance trace, in the same
//! form as a connection's recording ([`crate::record`]).
//!
//! The service formats each line under its lock (a few hundred
//! nanoseconds); the bytes go in chunks of at most 64 KiB through a
//! bounded queue to a thread of their own that writes the file, so a slow
//! disk never holds the emulator. When the queue is full (the disk has
//! not kept up with [`QUEUE_CHUNKS`] chunks, 4 MiB) or the file cannot be
//! written, the recording stops with a message and the server goes on:
//! a trace with a hole in it would not replay, so none is pretended.

use std::fs::File;
use std::io::{self, Write};
use std::path::Path;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use emulator::Journal;
use tc_request::{Reply, Request, SpoolRecord};

use crate::record::{RecordHeader, Recorder};

/// Chunks that may wait for the writer thread.
pub const QUEUE_CHUNKS: usize = 64;

/// Why the writer thread stopped, if it did.
type Failure = Arc<Mutex<Option<String>>>;

/// The bytes of a recording on their way to the writer thread.
struct ToWriter {
    tx: Option<SyncSender<Vec<u8>>>,
    failure: Failure,
}

impl Write for ToWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let gone = || io::Error::other("the writer thread stopped");
        let tx = self.tx.as_ref().ok_or_else(gone)?;
        match tx.try_send(buf.to_vec()) {
            Ok(()) => Ok(buf.len()),
            Err(TrySendError::Full(_)) => Err(io::Error::other(format!(
                "the disk did not keep up ({QUEUE_CHUNKS} chunks of the trace waited)"
            ))),
            Err(TrySendError::Disconnected(_)) => {
                let why = self.failure.lock().ok().and_then(|f| f.clone());
                Err(io::Error::other(
                    why.unwrap_or_else(|| "the writer thread stopped".into()),
                ))
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// Writes what comes through `rx` to `file`; the first error is kept in
/// `failure` and ends the thread.
fn write_all(mut file: File, rx: Receiver<Vec<u8>>, failure: Failure) {
    let result = (|| -> io::Result<()> {
        for chunk in rx {
            file.write_all(&chunk)?;
        }
        file.flush()?;
        file.sync_data()
    })();
    if let Err(e) = result {
        if let Ok(mut f) = failure.lock() {
            *f = Some(format!("cannot write the trace: {e}"));
        }
    }
}

/// The shared emulator's recording, streamed to a file.
pub struct ServeRecorder {
    rec: Option<Recorder>,
    writer: Option<JoinHandle<()>>,
    failure: Failure,
    path: String,
}

impl std::fmt::Debug for ServeRecorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ServeRecorder({})", self.path)
    }
}

impl ServeRecorder {
    /// Creates `path` and starts the trace with `header`.
    pub fn create(path: &Path, header: &RecordHeader) -> io::Result<Self> {
        let file = File::create(path)?;
        let (tx, rx) = sync_channel(QUEUE_CHUNKS);
        let failure = Failure::default();
        let f = failure.clone();
        let writer = std::thread::Builder::new()
            .name("serve-record".into())
            .spawn(move || write_all(file, rx, f))?;
        let out = ToWriter {
            tx: Some(tx),
            failure: failure.clone(),
        };
        let rec = Recorder::start(Box::new(out), header)?;
        Ok(Self {
            rec: Some(rec),
            writer: Some(writer),
            failure,
            path: path.display().to_string(),
        })
    }

    /// Runs `f` on the recorder; an error names the file.
    fn with(&mut self, f: impl FnOnce(&mut Recorder) -> io::Result<()>) -> Result<(), String> {
        let rec = self
            .rec
            .as_mut()
            .ok_or_else(|| format!("{}: the recording has ended", self.path))?;
        f(rec).map_err(|e| format!("{}: {e}", self.path))
    }

    /// Hands everything to the writer thread and waits until it is
    /// written.
    fn close(&mut self) -> Result<(), String> {
        let flushed = match self.rec.take() {
            Some(mut r) => r.flush().map_err(|e| format!("{}: {e}", self.path)),
            None => Ok(()),
        };
        if let Some(w) = self.writer.take() {
            let _ = w.join();
        }
        let failed = self.failure.lock().ok().and_then(|f| f.clone());
        flushed?;
        match failed {
            Some(why) => Err(format!("{}: {why}", self.path)),
            None => Ok(()),
        }
    }
}

impl Journal for ServeRecorder {
    fn exchange(
        &mut self,
        req: &Request,
        reply: &Reply,
        spooled: &[SpoolRecord],
        axis_nr: [u8; 3],
    ) -> Result<(), String> {
        self.with(|r| r.exchange(req, reply, spooled, axis_nr))
    }

    fn note(&mut self, text: &str) -> Result<(), String> {
        self.with(|r| r.comment(text))
    }

    fn finish(&mut self) -> Result<(), String> {
        self.close()
    }
}

impl Drop for ServeRecorder {
    fn drop(&mut self) {
        if let Err(e) = self.close() {
            eprintln!("addipos serve --record: {e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> RecordHeader {
        RecordHeader {
            name: "serve".into(),
            start: [0.0; 8],
            cycle_ms: 1.0,
            spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY,
            note: String::new(),
        }
    }

    #[test]
    fn a_recording_reaches_its_file_when_it_ends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.trace");
        let mut r = ServeRecorder::create(&path, &header()).unwrap();
        r.exchange(&Request::Queue, &Reply::Queue(0), &[], [0, 1, 2])
            .unwrap();
        r.note("hello").unwrap();
        r.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "@name serve\nQUEUE => 0\n# hello\n");
        assert!(r.note("late").is_err(), "an ended recording takes nothing");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_disk_that_refuses_the_trace_stops_the_recording_with_a_message() {
        let mut r = ServeRecorder::create(Path::new("/dev/full"), &header()).unwrap();
        let line = Request::Exec(Some(1));
        let mut failed = None;
        // /dev/full refuses every write: the first chunk fails in the
        // writer thread, and a later write says so.
        for _ in 0..2_000_000 {
            if let Err(e) = r.exchange(&line, &Reply::Ok, &[], [0, 1, 2]) {
                failed = Some(e);
                break;
            }
        }
        let e = failed.expect("the recording stops");
        assert!(e.contains("/dev/full"), "{e}");
        assert!(r.finish().is_err());
    }
}
