//! The one task that looks at the emulator for the view, and only while
//! a page is open: every [`SAMPLE`] it takes the executed position and the
//! elements spooled since its last look; every [`PUBLISH`] the whole
//! state too. With no page open it sleeps on the hub and the emulator
//! keeps no spooled element for it: the view then costs nothing.

use std::sync::Arc;
use std::time::Duration;

use emulator::{EmulatorService, WatchedSpool};
use uoi::tcp::CoreHandle;

use crate::hub::Hub;
use crate::path::Element;
use crate::snapshot::{self, Plane, Snapshot};

/// How often the position and the spooled elements are taken.
pub const SAMPLE: Duration = Duration::from_millis(10);

/// How often the whole state is taken: at most 20 updates a second.
pub const PUBLISH: Duration = Duration::from_millis(50);

/// What one look at the emulator gives.
struct Look {
    spooled: WatchedSpool,
    plane: Plane,
    at: [f64; 2],
    snapshot: Option<Snapshot>,
}

/// Runs until the server stops (the handle's looks come back `None`).
pub async fn run(core: CoreHandle, hub: Arc<Hub>) {
    let every = (PUBLISH.as_millis() / SAMPLE.as_millis()).max(1) as u32;
    loop {
        hub.until_viewed().await;
        let mut tick = tokio::time::interval(SAMPLE);
        tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        let mut n: u32 = 0;
        while hub.viewers() > 0 {
            tick.tick().await;
            let whole = n.is_multiple_of(every);
            n = n.wrapping_add(1);
            let web = hub.viewers();
            let Some(look) = core.inspect(move |h| look_at(h, whole, web)).await else {
                return;
            };
            let Some(look) = look else { return };
            let snapshot = look.snapshot.map(|s| hub.with_others(s));
            hub.publish(snapshot, |path| {
                for r in &look.spooled.records {
                    path.spooled(Element::of(r, look.plane));
                }
                path.missed += look.spooled.missed;
                path.executed(look.at);
            });
        }
        if core.inspect(|h| watch(h, false)).await.is_none() {
            return;
        }
    }
}

/// Starts or stops keeping spooled elements for the view.
fn watch(h: &mut dyn std::any::Any, on: bool) {
    if let Some(s) = h.downcast_mut::<EmulatorService>() {
        s.watch_spool(on);
    }
}

/// One look: `whole` takes the state too; `web`: pages open. `None`
/// when the handler is not an emulator service.
fn look_at(h: &mut dyn std::any::Any, whole: bool, web: usize) -> Option<Look> {
    let s = h.downcast_mut::<EmulatorService>()?;
    s.watch_spool(true);
    let spooled = s.take_watched_spool();
    let main = s.emulator_mut().tc().main_axes().plane;
    let plane = Plane {
        h: main.h,
        v: main.v,
    };
    let pos = s.emulator_mut().position();
    let at = [pos[usize::from(plane.h)], pos[usize::from(plane.v)]];
    let snapshot = whole.then(|| snapshot::take(s, web));
    Some(Look {
        spooled,
        plane,
        at,
        snapshot,
    })
}

/// The state now, looked at once (`/state` with no page open).
pub async fn snapshot_now(core: &CoreHandle, web: usize) -> Option<Snapshot> {
    core.inspect(move |h| {
        h.downcast_mut::<EmulatorService>()
            .map(|s| snapshot::take(s, web))
    })
    .await
    .flatten()
}
