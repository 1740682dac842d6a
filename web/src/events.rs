//! One page's event stream (server-sent events): the whole state and the
//! whole path kept first, then, at most every
//! [`PUBLISH`](crate::sampler::PUBLISH), what changed, nothing while
//! nothing changes. A comment line every [`KEEP_ALIVE`] tells a page the
//! stream still lives and finds a page that went away. Each write must
//! leave within the slow-client limit, or the page is dropped: a page
//! that does not read never holds anything up.

use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;
use tokio::io::AsyncWrite;

use crate::http::{event_stream_head, write_within};
use crate::hub::{Hub, Update};
use crate::path::{Cursor, PathUpdate};
use crate::sampler::PUBLISH;
use crate::snapshot::Snapshot;

/// How often a quiet stream sends a comment line.
pub const KEEP_ALIVE: Duration = Duration::from_secs(15);

/// How a page's stream ended.
#[derive(Debug, PartialEq, Eq)]
pub enum Ended {
    /// The page went away (or the socket failed).
    Closed,
    /// The page did not take an update within the slow-client limit.
    TooSlow,
    /// The server stops.
    Stopped,
}

/// The data of one `update` event.
#[derive(Debug, Serialize)]
struct Event<'a> {
    /// The state, when it changed.
    state: Option<&'a Snapshot>,
    /// The path entries new to this page.
    path: &'a PathUpdate,
}

/// Streams updates to one page until it goes, is too slow, or the hub
/// stops (its version sender dropped).
pub async fn stream<W: AsyncWrite + Unpin>(w: &mut W, hub: &Arc<Hub>, slow: Duration) -> Ended {
    let mut version = hub.subscribe();
    if let Err(e) = write_within(w, &event_stream_head(), slow).await {
        return ended(&e);
    }
    let mut seen: Option<Snapshot> = None;
    let mut cursor = Cursor::default();
    loop {
        version.mark_unchanged();
        // Everything new; a page that is behind gets it in several events.
        loop {
            let (update, next) = hub.update(seen.as_ref(), cursor);
            if update.snapshot.is_none() && update.path.is_empty() {
                break;
            }
            cursor = next;
            if let Err(e) = send(w, &update, slow).await {
                return ended(&e);
            }
            if update.snapshot.is_some() {
                seen = update.snapshot;
            }
        }
        tokio::select! {
            changed = version.changed() => {
                if changed.is_err() {
                    return Ended::Stopped;
                }
            }
            () = tokio::time::sleep(KEEP_ALIVE) => {
                if let Err(e) = write_within(w, b": alive\n\n", slow).await {
                    return ended(&e);
                }
            }
        }
        // Coalesced: at most one update per PUBLISH.
        tokio::time::sleep(PUBLISH).await;
    }
}

/// One `update` event.
async fn send<W: AsyncWrite + Unpin>(w: &mut W, u: &Update, slow: Duration) -> std::io::Result<()> {
    let event = Event {
        state: u.snapshot.as_ref(),
        path: &u.path,
    };
    let json = serde_json::to_string(&event).map_err(std::io::Error::other)?;
    let frame = format!("event: update\ndata: {json}\n\n");
    write_within(w, frame.as_bytes(), slow).await
}

fn ended(e: &std::io::Error) -> Ended {
    if e.kind() == std::io::ErrorKind::TimedOut {
        Ended::TooSlow
    } else {
        Ended::Closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::Element;

    #[tokio::test]
    async fn a_page_that_does_not_read_is_dropped_and_holds_nothing_up() {
        let hub = Hub::new();
        // Far more than the pipe holds: 4 KiB that nobody reads.
        hub.publish(None, |p| {
            for i in 0..10_000 {
                p.executed([f64::from(i), 0.0]);
            }
        });
        let (mut server_end, _page) = tokio::io::duplex(4096);
        let slow = Duration::from_millis(200);
        let end =
            tokio::time::timeout(Duration::from_secs(10), stream(&mut server_end, &hub, slow))
                .await
                .expect("the stream gives up on its own");
        assert_eq!(end, Ended::TooSlow);
        // The hub took more meanwhile without waiting for anybody.
        hub.publish(None, |p| {
            p.spooled(Element {
                from: [0.0; 2],
                to: [1.0, 0.0],
                arc: None,
                rapid: false,
            })
        });
        assert_eq!(hub.path_len().0, (1, 10_000));
    }
}
