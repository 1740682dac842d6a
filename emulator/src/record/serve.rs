//! `addipos serve --record FILE`: the shared emulator's request log
//! ([`RequestLog`]) written as one conformance trace, in the same form as
//! a connection's recording ([`Recorder`]).
//!
//! The service formats each line under its lock (a few hundred
//! nanoseconds); the bytes go in chunks of at most 64 KiB through a
//! bounded queue to a thread of their own that writes them, so a slow
//! disk never holds the emulator. When the queue is full (the disk has
//! not kept up with [`QUEUE_CHUNKS`](super::QUEUE_CHUNKS) chunks, 4 MiB) or the destination
//! cannot be written, the recording stops with a message and the server
//! goes on: a trace with a hole in it would not replay, so none is
//! pretended.
//!
//! Nothing ever waits for the writer thread while it is blocked: a
//! recording that stopped is left to its thread, and the end of a
//! recording waits only while the writer makes progress (a FIFO whose
//! reader stopped is given up after [`STALL_LIMIT`]). The destination is
//! opened by the writer thread, with the opener its caller hands over
//! (the command line, which alone touches files): a FIFO without a reader
//! does not hold the start (docs/decisions.md, decisions 410 and 510).

use std::io::{self, Write};

use tc_request::{Reply, Request, SpoolRecord};

use super::stream::{spawn, WriterEnd, WriterStop, STALL_LIMIT};
use super::writer::{RecordHeader, Recorder};
use crate::request_log::{LogError, RequestLog};

/// Why a `serve --record` recording stopped: the destination's name and
/// what happened.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The recording has ended (finished, or stopped earlier).
    #[error("{dest}: the recording has ended")]
    Ended {
        /// The destination, as named to [`ServeRecorder::start`].
        dest: String,
    },
    /// A line could not be handed on.
    #[error("{dest}: {source}")]
    Io {
        /// The destination.
        dest: String,
        /// What the hand-over answered.
        source: io::Error,
    },
    /// The writer thread stopped.
    #[error("{dest}: {stop}")]
    Stopped {
        /// The destination.
        dest: String,
        /// Why.
        stop: WriterStop,
    },
    /// The trace's reader took nothing for [`STALL_LIMIT`].
    #[error(
        "{dest}: the trace's reader took nothing for {} s; the rest of the recording is given up",
        STALL_LIMIT.as_secs()
    )]
    Stalled {
        /// The destination.
        dest: String,
    },
}

/// The shared emulator's recording, streamed to its destination.
pub struct ServeRecorder {
    rec: Option<Recorder>,
    /// Idle cycles of the real-time clock not written yet: one `EXEC n`
    /// before the next entry or at the end.
    idle: u64,
    writer: WriterEnd,
    dest: String,
}

impl std::fmt::Debug for ServeRecorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ServeRecorder({})", self.dest)
    }
}

impl ServeRecorder {
    /// Starts the trace with `header`, written to what `open` opens:
    /// `open` runs on the writer thread, so a FIFO nobody reads yet does
    /// not hold the caller. `dest` names the destination in messages.
    /// The destination is flushed once, at the end.
    pub fn start<W, F>(dest: impl Into<String>, open: F, header: &RecordHeader) -> io::Result<Self>
    where
        W: Write,
        F: FnOnce() -> io::Result<W> + Send + 'static,
    {
        let (out, writer) = spawn(open)?;
        let rec = Recorder::start(Box::new(out), header)?;
        Ok(Self {
            rec: Some(rec),
            idle: 0,
            writer,
            dest: dest.into(),
        })
    }

    /// Runs `f` on the recorder after the idle cycles merged so far; an
    /// error names the destination.
    fn with(&mut self, f: impl FnOnce(&mut Recorder) -> io::Result<()>) -> Result<(), RecordError> {
        let Some(rec) = self.rec.as_mut() else {
            return Err(RecordError::Ended {
                dest: self.dest.clone(),
            });
        };
        let idle = std::mem::take(&mut self.idle);
        let r = if idle > 0 {
            rec.exchange(&Request::Exec(Some(idle)), &Reply::Ok, &[], [0, 1, 2])
        } else {
            Ok(())
        };
        r.and_then(|()| f(rec)).map_err(|source| RecordError::Io {
            dest: self.dest.clone(),
            source,
        })
    }

    /// Hands everything to the writer thread and waits until it is
    /// written, as long as the writer makes progress: a recording that
    /// already failed is left at once, and a writer that writes nothing
    /// for [`STALL_LIMIT`] is given up.
    fn close(&mut self) -> Result<(), RecordError> {
        let idle = if self.idle > 0 && self.rec.is_some() {
            self.with(|_| Ok(()))
        } else {
            Ok(())
        };
        let flushed = match self.rec.take() {
            Some(mut r) => r.flush().map_err(|source| RecordError::Io {
                dest: self.dest.clone(),
                source,
            }),
            None => Ok(()),
        };
        if self.writer.wait().is_err() {
            return Err(RecordError::Stalled {
                dest: self.dest.clone(),
            });
        }
        idle?;
        flushed?;
        match self.writer.failed() {
            Some(stop) => Err(RecordError::Stopped {
                dest: self.dest.clone(),
                stop,
            }),
            None => Ok(()),
        }
    }
}

impl RequestLog for ServeRecorder {
    fn exchange(
        &mut self,
        req: &Request,
        reply: &Reply,
        spooled: &[SpoolRecord],
        axis_nr: [u8; 3],
    ) -> Result<(), LogError> {
        Ok(self.with(|r| r.exchange(req, reply, spooled, axis_nr))?)
    }

    fn idle(&mut self, cycles: u64) -> Result<(), LogError> {
        if self.rec.is_none() {
            return Err(RecordError::Ended {
                dest: self.dest.clone(),
            }
            .into());
        }
        self.idle = self.idle.saturating_add(cycles);
        Ok(())
    }

    fn note(&mut self, text: &str) -> Result<(), LogError> {
        Ok(self.with(|r| r.comment(text))?)
    }

    fn finish(&mut self) -> Result<(), LogError> {
        Ok(self.close()?)
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
    use std::path::Path;

    /// A recording into `path`, opened on the writer thread as the
    /// command line opens a FIFO.
    fn create(path: &Path, header: &RecordHeader) -> io::Result<ServeRecorder> {
        let p = path.to_path_buf();
        let open = move || {
            std::fs::OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(true)
                .open(p)
        };
        ServeRecorder::start(path.display().to_string(), open, header)
    }

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
        let mut r = create(&path, &header()).unwrap();
        r.exchange(&Request::Queue, &Reply::Queue(0), &[], [0, 1, 2])
            .unwrap();
        r.note("hello").unwrap();
        r.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "@name serve\nQUEUE => 0\n# hello\n");
        assert!(r.note("late").is_err(), "an ended recording takes nothing");
    }

    #[test]
    fn idle_cycles_are_one_exec_before_the_next_entry_and_at_the_end() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("idle.trace");
        let mut r = create(&path, &header()).unwrap();
        for _ in 0..300 {
            r.idle(3).unwrap();
        }
        r.exchange(&Request::Queue, &Reply::Queue(0), &[], [0, 1, 2])
            .unwrap();
        r.idle(2).unwrap();
        r.idle(5).unwrap();
        r.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "@name serve\nEXEC 900 => ok\nQUEUE => 0\nEXEC 7 => ok\n"
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_disk_that_refuses_the_trace_stops_the_recording_with_a_message() {
        let mut r = create(Path::new("/dev/full"), &header()).unwrap();
        // /dev/full refuses every write: the first chunk fails in the
        // writer thread, and a later write says so.
        let e = first_refusal(&mut r);
        assert!(e.contains("/dev/full"), "{e}");
        assert!(r.finish().is_err());
    }

    /// Writes `EXEC 1` lines until the recorder refuses one (at most
    /// 2,000,000): the refusal's message.
    fn first_refusal(r: &mut ServeRecorder) -> String {
        let line = Request::Exec(Some(1));
        for _ in 0..2_000_000 {
            if let Err(e) = r.exchange(&line, &Reply::Ok, &[], [0, 1, 2]) {
                return e.to_string();
            }
        }
        panic!("the recording never stopped");
    }

    /// Runs `f` on a thread of its own and waits for it at most 20 s (a
    /// hang is a failure, not a frozen test run).
    #[cfg(unix)]
    fn within_20s<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> Option<T> {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = tx.send(f());
        });
        rx.recv_timeout(std::time::Duration::from_secs(20)).ok()
    }

    /// A FIFO at `dir/name`.
    #[cfg(unix)]
    fn fifo(dir: &Path, name: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        let made = std::process::Command::new("mkfifo")
            .arg(&path)
            .status()
            .unwrap();
        assert!(made.success());
        path
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_without_a_reader_does_not_hold_the_start() {
        let dir = tempfile::tempdir().unwrap();
        let path = fifo(dir.path(), "no-reader");
        let made = within_20s(move || {
            let mut r = create(&path, &header()).map_err(|e| e.to_string())?;
            r.exchange(&Request::Queue, &Reply::Queue(0), &[], [0, 1, 2])
                .map_err(|e| e.to_string())?;
            drop(r);
            Ok::<(), String>(())
        });
        assert_eq!(made, Some(Ok(())), "create and end returned");
    }

    #[cfg(unix)]
    #[test]
    fn a_reader_that_stops_never_holds_the_end_of_the_recording() {
        use std::os::unix::fs::OpenOptionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = fifo(dir.path(), "stalled");
        // A reader that opens the FIFO and never reads (O_NONBLOCK: the
        // open does not wait for the writer).
        let reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(0o4000)
            .open(&path)
            .unwrap();
        let mut r = create(&path, &header()).unwrap();
        // The pipe takes 64 KiB, the queue 4 MiB: the recording stops
        // within a few hundred thousand lines.
        let e = first_refusal(&mut r);
        assert!(e.contains("did not keep up"), "{e}");
        // The service drops a recording that failed: that must not wait
        // for the writer blocked in write().
        assert!(within_20s(move || drop(r)).is_some(), "the drop returned");
        // A recording ended at shutdown while its reader stalls ends too.
        let path2 = fifo(dir.path(), "stalled2");
        let reader2 = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(0o4000)
            .open(&path2)
            .unwrap();
        let ended = within_20s(move || {
            let mut r = create(&path2, &header()).unwrap();
            for _ in 0..40_000 {
                r.exchange(&Request::Exec(Some(1)), &Reply::Ok, &[], [0, 1, 2])
                    .unwrap();
            }
            r.finish()
        });
        let e = ended.expect("finish returned").unwrap_err().to_string();
        assert!(e.contains("took nothing"), "{e}");
        drop((reader, reader2));
    }
}
