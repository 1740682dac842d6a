//! The one writer of the tool journal, with group commit: changes that
//! arrive while a sync runs are written together and made durable by the
//! next single sync; each submitter learns whether its change is on disk.

use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::thread::JoinHandle;

use crate::journal::Record;
use crate::store::StoreError;
use tokio::sync::oneshot;
use tracing::warn;
use uoi::LogLimit;

/// Changes waiting for the writer at most; a submitter finding it full
/// waits (back-pressure), its change is never dropped.
pub const QUEUE: usize = 4096;

/// Most changes of different submitters written with one sync.
pub const MAX_BATCH: usize = 1024;

/// Where the writer puts changes: appended and synced in one call, so one
/// call is one durable batch (docs/decisions.md, decision 502).
pub trait DurableLog: Send + 'static {
    /// Appends `records` and syncs them; an error leaves nothing of them.
    fn append(&mut self, records: &[Record]) -> Result<(), StoreError>;
    /// After a batch: housekeeping such as compaction (its failure is
    /// logged, the journal stays valid).
    fn maintain(&mut self) {}
    /// At shutdown, after the last batch (compaction).
    fn close(&mut self) {}
}

/// How a submitter hears of its batch: from async code, or by blocking.
#[derive(Debug)]
pub enum Done {
    /// A request that waits in the server (`Slice::Wait`).
    Async(oneshot::Sender<bool>),
    /// A caller that blocks until the batch is durable.
    Blocking(SyncSender<bool>),
}

impl Done {
    fn send(self, ok: bool) {
        match self {
            Done::Async(tx) => {
                let _ = tx.send(ok);
            }
            Done::Blocking(tx) => {
                let _ = tx.send(ok);
            }
        }
    }
}

/// One submitted change set.
#[derive(Debug)]
struct Job {
    records: Vec<Record>,
    done: Done,
}

/// The writer thread and the queue to it.
#[derive(Debug)]
pub struct Writer<J> {
    tx: Option<SyncSender<Job>>,
    thread: Option<JoinHandle<J>>,
}

impl<J: DurableLog> Writer<J> {
    /// Starts the writer thread on `journal`.
    pub fn start(journal: J) -> std::io::Result<Self> {
        let (tx, rx) = mpsc::sync_channel(QUEUE);
        let thread = std::thread::Builder::new()
            .name("tool-journal".into())
            .spawn(move || run(journal, rx))?;
        Ok(Self {
            tx: Some(tx),
            thread: Some(thread),
        })
    }

    /// Queues `records`; `done` hears whether they are on disk. A writer
    /// that is gone answers `false` at once.
    pub fn submit(&self, records: Vec<Record>, done: Done) {
        let Some(tx) = &self.tx else {
            return done.send(false);
        };
        let job = Job { records, done };
        let job = match tx.try_send(job) {
            Ok(()) => return,
            Err(TrySendError::Full(job)) => job,
            Err(TrySendError::Disconnected(job)) => return job.done.send(false),
        };
        if let Err(mpsc::SendError(job)) = tx.send(job) {
            job.done.send(false);
        }
    }

    /// Queues `records` and blocks until they are on disk (or not).
    pub fn write_blocking(&self, records: Vec<Record>) -> bool {
        let (tx, rx) = mpsc::sync_channel(1);
        self.submit(records, Done::Blocking(tx));
        rx.recv().unwrap_or(false)
    }

    /// Stops the writer once every queued change is written; gives the
    /// journal back (to compact it).
    pub fn stop(mut self) -> Option<J> {
        self.tx = None;
        self.thread.take()?.join().ok()
    }
}

/// The writer loop: takes every job waiting (up to [`MAX_BATCH`]), writes
/// them with one sync, tells each submitter. A refused batch is logged at
/// most once a second, with the count of refusals left out.
fn run<J: DurableLog>(mut journal: J, rx: Receiver<Job>) -> J {
    let mut jobs = Vec::new();
    let mut records = Vec::new();
    let refusals = LogLimit::per_second();
    while let Ok(first) = rx.recv() {
        jobs.push(first);
        while jobs.len() < MAX_BATCH {
            match rx.try_recv() {
                Ok(job) => jobs.push(job),
                Err(_) => break,
            }
        }
        records.clear();
        records.extend(jobs.iter().flat_map(|j| j.records.iter().copied()));
        let ok = match journal.append(&records) {
            Ok(()) => true,
            Err(e) => {
                if let Some(suppressed) = refusals.allow() {
                    warn!(error = %e, changes = records.len(), suppressed, "tool data not stored");
                }
                false
            }
        };
        for job in jobs.drain(..) {
            job.done.send(ok);
        }
        journal.maintain();
    }
    journal
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ToolField, ToolKey, ToolValue};
    use std::sync::{Arc, Mutex};

    /// Records every batch; fails the batches whose number is listed.
    #[derive(Default, Clone)]
    struct Batches(Arc<Mutex<(Vec<usize>, Vec<usize>)>>);

    impl DurableLog for Batches {
        fn append(&mut self, records: &[Record]) -> Result<(), StoreError> {
            let mut b = self.0.lock().unwrap();
            let n = b.0.len();
            b.0.push(records.len());
            if b.1.contains(&n) {
                Err(StoreError::Poisoned)
            } else {
                Ok(())
            }
        }
    }

    fn record(i: u16) -> Record {
        Record::Set {
            group: 1,
            key: ToolKey::new(i, ToolField::Radius).unwrap(),
            value: ToolValue::F64(f64::from(i)),
        }
    }

    #[test]
    fn waiting_changes_share_one_batch_and_each_hears_the_outcome() {
        let log = Batches::default();
        log.0.lock().unwrap().1.push(1);
        let w = Writer::start(log.clone()).unwrap();
        assert!(w.write_blocking(vec![record(0)]));
        // Block the writer on its journal, queue three, release it.
        let guard = log.0.lock().unwrap();
        let rxs: Vec<_> = (1..4)
            .map(|i| {
                let (otx, orx) = oneshot::channel();
                w.submit(vec![record(i)], Done::Async(otx));
                orx
            })
            .collect();
        drop(guard);
        let outcomes: Vec<bool> = rxs
            .into_iter()
            .map(|r| r.blocking_recv().unwrap())
            .collect();
        let batches = log.0.lock().unwrap().0.clone();
        // Batch 1 failed: whoever was in it hears false, later ones true.
        assert_eq!(batches.iter().sum::<usize>(), 4);
        assert!(batches.len() < 4, "no group commit: {batches:?}");
        assert_eq!(outcomes.iter().filter(|o| !**o).count(), batches[1]);
        assert!(w.stop().is_some());
    }
}
