//! Sampling of the monitored variables: one task reads each watched
//! variable through the object server at its monitored items' fastest
//! sampling interval and hands a change to the subscriptions. So a change
//! made by any face, or by the emulator itself (the executor moving, an
//! ERROR bit set by the correction), reaches a subscriber within one
//! sampling interval; a refused write changes no value and notifies no one.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use opcua::server::{MonitoredItemHandle, SubscriptionCache};
use opcua::types::{AttributeId, DataValue, MonitoringMode, NodeId};
use tokio::sync::Notify;
use tokio::time::{Instant, MissedTickBehavior};
use tokio_util::sync::{CancellationToken, DropGuard};

use crate::points::Points;
use crate::space::Source;

/// How often the sampler looks for variables due: the shortest sampling
/// interval the face offers.
pub const TICK: Duration = Duration::from_millis(10);

/// A monitored item's wishes.
#[derive(Debug, Clone, Copy)]
struct Item {
    mode: MonitoringMode,
    every: Duration,
}

/// A variable with monitored items.
struct Watched {
    source: Source,
    items: HashMap<MonitoredItemHandle, Item>,
    /// Its next sample.
    due: Instant,
    /// The value and status sampled last (`None`: tell every item the next
    /// sample).
    last: Option<DataValue>,
}

impl Watched {
    /// The fastest interval of its sampling items, if any samples.
    fn every(&self) -> Option<Duration> {
        self.items
            .values()
            .filter(|i| i.mode != MonitoringMode::Disabled)
            .map(|i| i.every)
            .min()
    }
}

/// The variables watched, and the task that samples them.
pub(crate) struct Sampler {
    watched: Mutex<HashMap<NodeId, Watched>>,
    /// Wakes the task when the first variable is watched.
    wake: Arc<Notify>,
    stop: CancellationToken,
    _stop_on_drop: DropGuard,
}

impl Sampler {
    /// A sampler watching nothing yet; [`start`](Self::start) runs it.
    pub fn new() -> Self {
        let stop = CancellationToken::new();
        Self {
            watched: Mutex::new(HashMap::new()),
            wake: Arc::new(Notify::new()),
            _stop_on_drop: stop.clone().drop_guard(),
            stop,
        }
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<NodeId, Watched>> {
        self.watched.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Runs the sampling task (until the sampler is dropped): samples
    /// through `points`, changes to `subscriptions`.
    pub fn start(self: &Arc<Self>, points: Arc<Points>, subscriptions: Arc<SubscriptionCache>) {
        let me = Arc::downgrade(self);
        let (stop, wake) = (self.stop.clone(), Arc::clone(&self.wake));
        tokio::spawn(async move {
            tokio::select! {
                () = stop.cancelled() => {}
                () = run(me, wake, points, subscriptions) => {}
            }
        });
    }

    /// Watches `id` for the monitored item `handle`; the next sample goes
    /// to every item of it.
    pub fn add(
        &self,
        id: NodeId,
        source: Source,
        handle: MonitoredItemHandle,
        mode: MonitoringMode,
        every: Duration,
    ) {
        let mut watched = self.lock();
        let w = watched.entry(id).or_insert_with(|| Watched {
            source,
            items: HashMap::new(),
            due: Instant::now() + every,
            last: None,
        });
        w.items.insert(handle, Item { mode, every });
        w.last = None;
        drop(watched);
        self.wake.notify_one();
    }

    /// A monitored item's new sampling interval.
    pub fn set_every(&self, id: &NodeId, handle: MonitoredItemHandle, every: Duration) {
        if let Some(item) = self
            .lock()
            .get_mut(id)
            .and_then(|w| w.items.get_mut(&handle))
        {
            item.every = every;
        }
    }

    /// A monitored item's new monitoring mode.
    pub fn set_mode(&self, id: &NodeId, handle: MonitoredItemHandle, mode: MonitoringMode) {
        let mut watched = self.lock();
        if let Some(w) = watched.get_mut(id) {
            if let Some(item) = w.items.get_mut(&handle) {
                item.mode = mode;
                w.last = None;
            }
        }
    }

    /// Forgets a monitored item (and the variable with its last item).
    pub fn remove(&self, id: &NodeId, handle: MonitoredItemHandle) {
        let mut watched = self.lock();
        if let Some(w) = watched.get_mut(id) {
            w.items.remove(&handle);
            if w.items.is_empty() {
                watched.remove(id);
            }
        }
    }

    /// The variables due now, their next sample planned.
    fn due(&self, now: Instant) -> Vec<(NodeId, Source)> {
        let mut watched = self.lock();
        watched
            .iter_mut()
            .filter_map(|(id, w)| {
                let every = w.every()?;
                (w.due <= now).then(|| {
                    w.due = now + every;
                    (id.clone(), w.source)
                })
            })
            .collect()
    }

    /// Of `samples`, those that differ from the variable's last sample
    /// (which they become).
    fn changed(&self, samples: Vec<(NodeId, DataValue)>) -> Vec<(NodeId, DataValue)> {
        let mut watched = self.lock();
        samples
            .into_iter()
            .filter(|(id, sample)| {
                let Some(w) = watched.get_mut(id) else {
                    return false;
                };
                let same = w
                    .last
                    .as_ref()
                    .is_some_and(|l| l.value == sample.value && l.status == sample.status);
                w.last = Some(sample.clone());
                !same
            })
            .collect()
    }
}

/// The sampling loop: every [`TICK`], the variables due are read and their
/// changes notified; with nothing watched it sleeps until something is.
async fn run(
    sampler: std::sync::Weak<Sampler>,
    wake: Arc<Notify>,
    points: Arc<Points>,
    subscriptions: Arc<SubscriptionCache>,
) {
    let mut tick = tokio::time::interval(TICK);
    tick.set_missed_tick_behavior(MissedTickBehavior::Skip);
    loop {
        let idle = wake.notified();
        let Some(me) = sampler.upgrade() else { return };
        let empty = me.lock().is_empty();
        drop(me);
        if empty {
            idle.await;
            continue;
        }
        // The tick's own moment, not the time it is handled: an item due
        // every tick is sampled every tick.
        let at = tick.tick().await;
        let Some(me) = sampler.upgrade() else { return };
        let due = me.due(at);
        let mut samples = Vec::with_capacity(due.len());
        for (id, source) in due {
            samples.push((id, points.sample(source).await));
        }
        let changed = me.changed(samples);
        if !changed.is_empty() {
            subscriptions.notify_data_change(
                changed
                    .iter()
                    .map(|(id, dv)| (dv.clone(), id, AttributeId::Value)),
            );
        }
    }
}
