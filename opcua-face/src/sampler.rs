//! Sampling of the monitored variables: one task reads each watched
//! variable through the object server when one of its monitored items is
//! due, and hands each item a change of its own. So a change made by any
//! face, or by the emulator itself (the executor moving, an ERROR bit set
//! by the correction), reaches a subscriber within one sampling interval;
//! a refused write changes no value and notifies no one.
//!
//! Each item gets its samples at its own interval, stamped at least that
//! far apart: the library holds back a value that comes sooner than the
//! interval after the last one and, when no further change follows, never
//! sends it.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use opcua::server::{MonitoredItemHandle, SubscriptionCache};
use opcua::types::{AttributeId, DataValue, DateTime, MonitoringMode, NodeId};
use tokio::sync::Notify;
use tokio::time::{Instant, MissedTickBehavior};
use tokio_util::sync::{CancellationToken, DropGuard};

use crate::points::Points;
use crate::space::Source;

/// How often the sampler looks for items due: the shortest sampling
/// interval the face offers.
pub const TICK: Duration = Duration::from_millis(10);

/// A monitored item: its wishes and what it was sent last.
#[derive(Debug, Clone)]
struct Item {
    mode: MonitoringMode,
    every: Duration,
    /// Its next sample.
    due: Instant,
    /// The value (and status) it was sent last, with its stamp.
    last: DataValue,
}

/// A variable with monitored items.
struct Watched {
    source: Source,
    items: HashMap<MonitoredItemHandle, Item>,
}

/// One variable read for the items due.
struct Sample {
    id: NodeId,
    value: DataValue,
    items: Vec<MonitoredItemHandle>,
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

    /// Watches `id` for the monitored item `handle`, which was given
    /// `initial` when it was made.
    pub fn add(
        &self,
        id: NodeId,
        source: Source,
        handle: MonitoredItemHandle,
        (mode, every): (MonitoringMode, Duration),
        initial: DataValue,
    ) {
        let item = Item {
            mode,
            every,
            due: Instant::now() + every,
            last: initial,
        };
        let mut watched = self.lock();
        let w = watched.entry(id).or_insert_with(|| Watched {
            source,
            items: HashMap::new(),
        });
        w.items.insert(handle, item);
        drop(watched);
        self.wake.notify_one();
    }

    /// A monitored item's new sampling interval.
    pub fn set_every(&self, id: &NodeId, handle: MonitoredItemHandle, every: Duration) {
        self.change(id, handle, |item| item.every = every);
    }

    /// A monitored item's new monitoring mode.
    pub fn set_mode(&self, id: &NodeId, handle: MonitoredItemHandle, mode: MonitoringMode) {
        self.change(id, handle, |item| item.mode = mode);
    }

    /// Changes the monitored item `handle` of variable `id`, if it is
    /// watched.
    fn change(&self, id: &NodeId, handle: MonitoredItemHandle, f: impl FnOnce(&mut Item)) {
        if let Some(item) = self
            .lock()
            .get_mut(id)
            .and_then(|w| w.items.get_mut(&handle))
        {
            f(item);
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

    /// The variables with items due at `at` (a tick), and those items;
    /// each item's next sample planned.
    fn due(&self, at: Instant) -> Vec<(NodeId, Source, Vec<MonitoredItemHandle>)> {
        let mut watched = self.lock();
        let mut out = Vec::new();
        for (id, w) in watched.iter_mut() {
            let items: Vec<_> = w
                .items
                .iter_mut()
                .filter(|(_, i)| i.mode != MonitoringMode::Disabled && i.due <= at)
                .map(|(h, i)| {
                    i.due = at + i.every;
                    *h
                })
                .collect();
            if !items.is_empty() {
                out.push((id.clone(), w.source, items));
            }
        }
        out
    }

    /// The items a sample changes, each with the value to send it (stamped
    /// at least its interval after the last), which it is then sent.
    fn changes(&self, samples: Vec<Sample>) -> Vec<(NodeId, MonitoredItemHandle, DataValue)> {
        let mut watched = self.lock();
        let mut out = Vec::new();
        for sample in samples {
            let Some(w) = watched.get_mut(&sample.id) else {
                continue;
            };
            for handle in sample.items {
                let Some(item) = w.items.get_mut(&handle) else {
                    continue;
                };
                let last = &item.last;
                if last.value == sample.value.value && last.status == sample.value.status {
                    continue;
                }
                let value = spaced(sample.value.clone(), last, item.every);
                item.last = value.clone();
                out.push((sample.id.clone(), handle, value));
            }
        }
        out
    }
}

/// `value` with its stamps no sooner than `every` after those of `last`.
fn spaced(mut value: DataValue, last: &DataValue, every: Duration) -> DataValue {
    let step = i64::try_from(every.as_nanos() / 100).unwrap_or(i64::MAX);
    let soonest =
        |t: Option<DateTime>| t.map(|t| DateTime::from(i64::from(t).saturating_add(step)));
    if let (Some(now), Some(min)) = (value.source_timestamp, soonest(last.source_timestamp)) {
        value.source_timestamp = Some(now.max(min));
    }
    if let (Some(now), Some(min)) = (value.server_timestamp, soonest(last.server_timestamp)) {
        value.server_timestamp = Some(now.max(min));
    }
    value
}

/// The sampling loop: every [`TICK`], the variables with items due are
/// read and their changes handed to those items; with nothing watched it
/// sleeps until something is.
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
        let mut samples = Vec::new();
        for (id, source, items) in me.due(at) {
            let value = points.sample(source).await;
            samples.push(Sample { id, value, items });
        }
        let changes = me.changes(samples);
        if !changes.is_empty() {
            let mut notifier = subscriptions.data_notifier();
            for (id, handle, value) in changes {
                if let Some(mut batch) = notifier.notify_for(&id, AttributeId::Value) {
                    batch.data_value_to_item(value, &handle);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(ticks: i64) -> DataValue {
        DataValue {
            value: Some(opcua::types::Variant::Int32(1)),
            source_timestamp: Some(DateTime::from(ticks)),
            server_timestamp: Some(DateTime::from(ticks)),
            ..Default::default()
        }
    }

    #[test]
    fn a_sample_is_stamped_no_sooner_than_its_interval_after_the_last() {
        let every = Duration::from_millis(10);
        // 10 ms are 100,000 ticks of 100 ns.
        let early = spaced(at(1_050_000), &at(1_000_000), every);
        assert_eq!(early.source_timestamp, Some(DateTime::from(1_100_000)));
        assert_eq!(early.server_timestamp, Some(DateTime::from(1_100_000)));
        let late = spaced(at(1_300_000), &at(1_000_000), every);
        assert_eq!(late.source_timestamp, Some(DateTime::from(1_300_000)));
    }
}
