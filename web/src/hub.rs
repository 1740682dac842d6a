//! What the pages share: the last state taken, the path, and the version
//! each page waits on. The sampler ([`crate::sampler`]) writes here and
//! bumps the version when something changed; each page's stream
//! ([`crate::events`]) reads what it has not seen. Nobody here ever waits
//! for a page: a page that falls behind only gets a larger update later.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use tokio::sync::watch;
use uoi::tcp::Places;

use crate::path::{Cursor, PathLog, PathUpdate};
use crate::snapshot::Snapshot;

/// The shared state of the view.
#[derive(Debug)]
pub struct Hub {
    shown: Mutex<Shown>,
    /// Bumped whenever the state or the path changed.
    version: watch::Sender<u64>,
    /// Pages open (event streams).
    viewers: AtomicUsize,
    /// Wakes the sampler when the first page opens.
    opened: tokio::sync::Notify,
    /// The OPC UA face's count of client connections, when it runs.
    opcua: Option<Arc<Places>>,
}

/// The state and the path as the pages get them.
#[derive(Debug, Default)]
struct Shown {
    snapshot: Option<Snapshot>,
    path: PathLog,
}

/// One update for a page.
#[derive(Debug, Clone)]
pub struct Update {
    /// The state, when it changed since the page's last update.
    pub snapshot: Option<Snapshot>,
    /// The path entries it has not had.
    pub path: PathUpdate,
}

impl Default for Hub {
    fn default() -> Self {
        Self {
            shown: Mutex::default(),
            version: watch::Sender::new(0),
            viewers: AtomicUsize::new(0),
            opened: tokio::sync::Notify::new(),
            opcua: None,
        }
    }
}

impl Hub {
    /// A hub, shared.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// A hub that shows `opcua`'s count of OPC UA connections, shared.
    pub fn with_opcua(opcua: Option<Arc<Places>>) -> Arc<Self> {
        Arc::new(Self {
            opcua,
            ..Self::default()
        })
    }

    /// `snapshot` with the OPC UA connections open now (`None` without
    /// the OPC UA face).
    pub fn with_others(&self, mut snapshot: Snapshot) -> Snapshot {
        snapshot.clients.opcua = self.opcua.as_ref().map(|p| p.open());
        snapshot
    }

    fn lock(&self) -> MutexGuard<'_, Shown> {
        self.shown.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Pages open now.
    pub fn viewers(&self) -> usize {
        self.viewers.load(Ordering::Acquire)
    }

    /// Counts a page open, up to `max`; `None` when `max` are open. The
    /// seat counts until dropped.
    pub fn seat(self: &Arc<Self>, max: usize) -> Option<ViewerSeat> {
        self.viewers
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
                (n < max).then_some(n + 1)
            })
            .ok()?;
        self.opened.notify_one();
        Some(ViewerSeat(Arc::clone(self)))
    }

    /// Waits until a page is open.
    pub async fn until_viewed(&self) {
        while self.viewers() == 0 {
            self.opened.notified().await;
        }
    }

    /// A receiver of the version.
    pub fn subscribe(&self) -> watch::Receiver<u64> {
        self.version.subscribe()
    }

    /// Takes in what the sampler saw: a new state (`None`: not taken this
    /// time) and the path appended by `add`; the version is bumped when
    /// anything changed.
    pub fn publish(&self, snapshot: Option<Snapshot>, add: impl FnOnce(&mut PathLog)) {
        let changed = {
            let mut shown = self.lock();
            let before = shown.path.end();
            add(&mut shown.path);
            let mut changed = shown.path.end() != before;
            if let Some(s) = snapshot {
                if shown.snapshot.as_ref() != Some(&s) {
                    shown.snapshot = Some(s);
                    changed = true;
                }
            }
            changed
        };
        if changed {
            self.version.send_modify(|v| *v += 1);
        }
    }

    /// The last state taken.
    pub fn snapshot(&self) -> Option<Snapshot> {
        self.lock().snapshot.clone()
    }

    /// What a page at `cursor` that last saw `seen` has not had.
    pub fn update(&self, seen: Option<&Snapshot>, cursor: Cursor) -> (Update, Cursor) {
        let shown = self.lock();
        let snapshot = shown
            .snapshot
            .as_ref()
            .filter(|s| Some(*s) != seen)
            .cloned();
        let (path, next) = shown.path.since(cursor);
        (Update { snapshot, path }, next)
    }

    /// Elements kept of the path (spooled, executed points) and those
    /// not kept.
    pub fn path_len(&self) -> ((usize, usize), u64) {
        let shown = self.lock();
        (shown.path.len(), shown.path.missed)
    }
}

/// A page counted as open; dropped when it closes.
#[derive(Debug)]
pub struct ViewerSeat(Arc<Hub>);

impl Drop for ViewerSeat {
    fn drop(&mut self) {
        self.0.viewers.fetch_sub(1, Ordering::AcqRel);
    }
}
