//! The bytes of a recording on their way to a writer thread of its own
//! (decision 410): a bounded queue of chunks, the thread that opens the
//! destination and writes them, and the end, which waits only while the
//! writer makes progress.

use std::io::{self, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Chunks that may wait for the writer thread.
pub const QUEUE_CHUNKS: usize = 64;

/// How long the end of a recording waits for a writer that writes
/// nothing (a reader of the FIFO that stopped): the rest is then given
/// up, never the server's stop.
pub const STALL_LIMIT: Duration = Duration::from_secs(2);

/// Why the writer thread stopped taking the trace.
#[derive(Debug, Clone, thiserror::Error)]
pub enum WriterStop {
    /// The queue to the writer thread was full.
    #[error("the disk did not keep up ({QUEUE_CHUNKS} chunks of the trace waited)")]
    Behind,
    /// The destination could not be opened or written.
    #[error("cannot write the trace: {0}")]
    Write(Arc<io::Error>),
    /// The writer thread ended for a reason it did not leave.
    #[error("the writer thread stopped")]
    Gone,
}

/// Why the recording stopped, if it did (the writer thread's error, or
/// a queue the writer did not empty in time).
type Failure = Arc<Mutex<Option<WriterStop>>>;

/// Keeps the first reason in `failure`.
fn fail(failure: &Failure, why: WriterStop) {
    if let Ok(mut f) = failure.lock() {
        f.get_or_insert(why);
    }
}

/// The bytes of a recording on their way to the writer thread.
pub(super) struct ToWriter {
    tx: Option<SyncSender<Vec<u8>>>,
    failure: Failure,
}

impl Write for ToWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let tx = self
            .tx
            .as_ref()
            .ok_or_else(|| io::Error::other(WriterStop::Gone))?;
        match tx.try_send(buf.to_vec()) {
            Ok(()) => Ok(buf.len()),
            Err(TrySendError::Full(_)) => {
                fail(&self.failure, WriterStop::Behind);
                // Nothing more goes to the writer: it may stay blocked.
                self.tx = None;
                Err(io::Error::other(WriterStop::Behind))
            }
            Err(TrySendError::Disconnected(_)) => {
                let why = self.failure.lock().ok().and_then(|f| f.clone());
                Err(io::Error::other(why.unwrap_or(WriterStop::Gone)))
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// What the writer thread shares: its failure, and the chunks written
/// (how the end of a recording tells a slow writer from a stalled one).
#[derive(Clone, Default)]
struct Shared {
    failure: Failure,
    written: Arc<AtomicU64>,
}

/// Opens the destination with `open` and writes what comes through `rx`
/// to it, flushed at the end; the first error is kept in `failure` and
/// ends the thread.
fn write_all<W: Write>(
    open: impl FnOnce() -> io::Result<W>,
    rx: Receiver<Vec<u8>>,
    shared: &Shared,
) {
    let result = (|| -> io::Result<()> {
        let mut out = open()?;
        shared.written.fetch_add(1, Ordering::Relaxed);
        for chunk in rx {
            out.write_all(&chunk)?;
            shared.written.fetch_add(1, Ordering::Relaxed);
        }
        out.flush()
    })();
    if let Err(e) = result {
        fail(&shared.failure, WriterStop::Write(Arc::new(e)));
    }
}

/// The writer thread as whoever ends the recording sees it: whether it
/// failed, and when it is done.
pub(super) struct WriterEnd {
    /// Says (by closing) that the writer thread has ended.
    ended: Option<Receiver<()>>,
    shared: Shared,
}

/// The writer thread has written nothing for [`STALL_LIMIT`].
#[derive(Debug)]
pub(super) struct Stalled;

/// Starts the writer thread, which opens the destination with `open`;
/// what to write goes to the [`ToWriter`], and the [`WriterEnd`] tells
/// how the thread fares. The thread is never joined: a writer blocked in
/// write() must not hold whoever ends the recording.
pub(super) fn spawn<W, F>(open: F) -> io::Result<(ToWriter, WriterEnd)>
where
    W: Write,
    F: FnOnce() -> io::Result<W> + Send + 'static,
{
    let (tx, rx) = sync_channel(QUEUE_CHUNKS);
    let (end_tx, end_rx) = sync_channel::<()>(0);
    let shared = Shared::default();
    let s = shared.clone();
    std::thread::Builder::new()
        .name("serve-record".into())
        .spawn(move || {
            write_all(open, rx, &s);
            drop(end_tx);
        })?;
    let out = ToWriter {
        tx: Some(tx),
        failure: shared.failure.clone(),
    };
    let end = WriterEnd {
        ended: Some(end_rx),
        shared,
    };
    Ok((out, end))
}

impl WriterEnd {
    /// Why the writer stopped, if it did.
    pub(super) fn failed(&self) -> Option<WriterStop> {
        self.shared.failure.lock().ok().and_then(|f| f.clone())
    }

    /// Waits until the writer thread ends, or has written nothing for
    /// [`STALL_LIMIT`]; a writer that failed, or was waited for once, is
    /// not waited for.
    pub(super) fn wait(&mut self) -> Result<(), Stalled> {
        const LOOK: Duration = Duration::from_millis(100);
        let Some(ended) = self.ended.take() else {
            return Ok(());
        };
        if self.failed().is_some() {
            return Ok(());
        }
        let mut seen = self.shared.written.load(Ordering::Relaxed);
        let mut quiet = Duration::ZERO;
        loop {
            match ended.recv_timeout(LOOK) {
                Ok(()) | Err(RecvTimeoutError::Disconnected) => return Ok(()),
                Err(RecvTimeoutError::Timeout) => {}
            }
            let now = self.shared.written.load(Ordering::Relaxed);
            quiet = if now == seen {
                quiet + LOOK
            } else {
                Duration::ZERO
            };
            seen = now;
            if quiet >= STALL_LIMIT {
                return Err(Stalled);
            }
        }
    }
}
