//! Admission of accepted connections. A new connection gets a free place;
//! when the server is full (`max_connections` open, or
//! `max_connections_per_peer` from its address), the place of the
//! connection quiet longest — for the eviction grace at least, from the
//! same address when that address's limit is reached — which is closed to
//! make room. When every connection has made progress within the grace,
//! the newcomer waits (one and a half graces at most) for one to go quiet
//! or to end; only then is it answered `Busy` and closed.
//!
//! Open sockets stay bounded: the places (`max_connections`), plus
//! connections closed and still finishing (a close wakes their blocked
//! read or write, so they end at once), plus at most `max_connections`
//! newcomers waiting.

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures_util::SinkExt;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::task::JoinSet;
use tokio_util::codec::FramedWrite;
use tracing::{debug, info, warn};

use super::access::AccessPolicy;
use super::arrivals::Arrivals;
use super::config::ServerConfig;
use super::connection::{reply, serve_connection, Gatekeeper};
use super::floods::FloodLogs;
use super::handler::Handler;
use super::idle::Watchdog;
use super::places::{Full, Limits, Places, Seat};
use super::shared::Shared;
use crate::wire::{Answer, ProtocolError, ServerCodec};

/// Looks for a place per grace while newcomers wait.
const RETRIES_PER_GRACE: u32 = 8;

/// Shortest time between two looks for a place.
const MIN_RETRY: Duration = Duration::from_millis(1);

/// A newcomer waiting for a place.
struct Waiting {
    stream: TcpStream,
    peer: SocketAddr,
    since: Instant,
}

/// What admits accepted connections and keeps them.
pub(crate) struct Gate<H> {
    /// Connections open, in all and per peer address.
    places: Arc<Places>,
    /// Closes idle connections, those it is told to evict, and all of
    /// them on shutdown.
    watchdog: Watchdog,
    /// Quiet a connection must have been before it is evicted; `None`:
    /// no eviction, and a newcomer finding the server full is refused at
    /// once.
    grace: Option<Duration>,
    /// Newcomers waiting for a place, oldest first.
    waiting: VecDeque<Waiting>,
    /// Most newcomers waiting at once.
    max_waiting: usize,
    /// Who must present the access token.
    access: AccessPolicy,
    /// How fast each address opens connections.
    arrivals: Arrivals,
    /// The limits on log lines a client can make the server repeat.
    pub(crate) logs: Arc<FloodLogs>,
    shared: Shared<H>,
    /// The connections' tasks, and those answering `Busy`.
    pub(crate) tasks: JoinSet<()>,
}

impl<H: Handler> Gate<H> {
    /// A gate for `cfg`, its connections served by `shared`.
    pub(crate) fn new(cfg: &ServerConfig, shared: Shared<H>) -> std::io::Result<Self> {
        let watchdog = Watchdog::start(
            cfg.idle_timeout,
            cfg.write_timeout,
            cfg.evict_after.unwrap_or(Duration::MAX),
            cfg.max_connections,
        )?;
        Ok(Self {
            places: Places::new(Limits {
                all: cfg.max_connections,
                per_peer: cfg.max_connections_per_peer,
                per_peer_on_loopback: cfg.per_peer_limit_on_loopback,
            }),
            watchdog,
            grace: cfg.evict_after,
            waiting: VecDeque::new(),
            max_waiting: cfg.max_connections,
            access: cfg.access.clone(),
            arrivals: Arrivals::new(cfg.accept_rate_per_peer),
            logs: Arc::new(FloodLogs::default()),
            shared,
            tasks: JoinSet::new(),
        })
    }

    /// How often to look for places while newcomers wait; `None` without
    /// eviction (then nobody waits).
    pub(crate) fn retry_every(&self) -> Option<Duration> {
        self.grace
            .map(|grace| (grace / RETRIES_PER_GRACE).max(MIN_RETRY))
    }

    /// Whether newcomers wait for a place.
    pub(crate) fn has_waiting(&self) -> bool {
        !self.waiting.is_empty()
    }

    /// Serves an accepted connection, or lets it wait for a place; one
    /// over its address's rate of new connections is refused at once.
    pub(crate) fn arrive(&mut self, stream: TcpStream, peer: SocketAddr) {
        let _ = stream.set_nodelay(true);
        if !self.arrivals.admit(peer.ip(), Instant::now()) {
            if let Some(suppressed) = self.logs.too_fast.allow() {
                warn!(%peer, suppressed, "new connections from this address too fast, refusing");
            }
            self.tasks.spawn(refuse(stream));
        } else if let Some(seat) = self.place_for(peer) {
            self.serve(stream, peer, seat);
        } else if self.grace.is_some() && self.waiting.len() < self.max_waiting {
            debug!(%peer, "server full, waiting for a place");
            let since = Instant::now();
            self.waiting.push_back(Waiting {
                stream,
                peer,
                since,
            });
        } else {
            if let Some(suppressed) = self.logs.refused.allow() {
                warn!(%peer, suppressed, "connection limit reached, refusing");
            }
            self.tasks.spawn(refuse(stream));
        }
    }

    /// Serves the waiting newcomers that find a place now, oldest first;
    /// answers `Busy` to those that have waited in vain.
    pub(crate) fn retry_waiting(&mut self) {
        let now = Instant::now();
        let grace = self.grace.unwrap_or_default();
        let patience = grace + grace / 2;
        for _ in 0..self.waiting.len() {
            let Some(w) = self.waiting.pop_front() else {
                break;
            };
            if let Some(seat) = self.place_for(w.peer) {
                self.serve(w.stream, w.peer, seat);
            } else if now.saturating_duration_since(w.since) >= patience {
                if let Some(suppressed) = self.logs.refused.allow() {
                    warn!(peer = %w.peer, suppressed, "connection limit reached and no connection quiet, refusing");
                }
                self.tasks.spawn(refuse(w.stream));
            } else {
                self.waiting.push_back(w);
            }
        }
    }

    /// A place for a connection from `peer`: a free one, or the one of the
    /// connection quiet longest (for the grace at least), closed to make
    /// room.
    fn place_for(&self, peer: SocketAddr) -> Option<Seat> {
        let full = match self.places.take(peer.ip()) {
            Ok(seat) => return Some(seat),
            Err(full) => full,
        };
        let within = match full {
            Full::Peer(ip) => Some(ip),
            Full::All => None,
        };
        let evicted = self.watchdog.evict(within, self.grace?)?;
        if let Some(suppressed) = self.logs.evicted.allow() {
            info!(
                %peer,
                evicted = %evicted.peer,
                quiet_ms = u64::try_from(evicted.quiet.as_millis()).unwrap_or(u64::MAX),
                limit = %full,
                suppressed,
                "connection limit reached: closed the connection quiet longest to make room"
            );
        }
        self.places.take(peer.ip()).ok()
    }

    /// Serves a connection that holds `seat`.
    fn serve(&mut self, stream: TcpStream, peer: SocketAddr, seat: Seat) {
        let shared = self.shared.clone();
        let activity = self.watchdog.watch(seat);
        let token = self.access.token.clone();
        let authorized = !self.access.needs_token(peer.ip());
        let logs = Arc::clone(&self.logs);
        self.tasks.spawn(async move {
            debug!(%peer, authorized, "connected");
            serve_connection(
                stream,
                shared,
                activity,
                Gatekeeper::new(token, authorized, peer, logs),
            )
            .await;
            debug!(%peer, "disconnected");
        });
    }

    /// Closes every connection (the server is stopping); newcomers still
    /// waiting are dropped.
    pub(crate) fn close_all(&mut self) {
        self.waiting.clear();
        self.watchdog.close_all();
    }
}

/// Answers `Busy` and closes.
async fn refuse(stream: TcpStream) {
    let mut w = FramedWrite::new(stream, ServerCodec);
    let _ = w
        .send(reply(0, 0, Answer::Protocol(ProtocolError::Busy)))
        .await;
    let _ = w.into_inner().shutdown().await;
}
