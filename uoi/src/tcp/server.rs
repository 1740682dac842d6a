//! The tokio object server: one task per connection, all connections share
//! one handler (behind a lock, or owned by one task), pipelined requests
//! answered in order. Each connection also keeps a [`Session`] of its own,
//! which may answer its requests before the shared handler sees them.

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::time::MissedTickBehavior;
use tracing::{info, warn};

use super::access::AccessPolicy;
use super::core_handle::CoreHandle;
use super::gate::Gate;
use super::shared::Shared;
use crate::wire::{Answer, Request};

/// What serves the requests: the emulator, in `addipos`. HELLO frames
/// are answered by the connection itself and never reach it.
pub trait Handler: Send + 'static {
    /// What each connection keeps for itself (`()` for nothing).
    type Session: Session;
    /// Answers one request.
    fn handle(&mut self, req: Request) -> Answer;

    /// Serves one slice of a request: its answer, or the rest of it to
    /// serve later. The server releases the handler between slices, so
    /// requests of other connections are served in between and shutdown
    /// is not held up by a long request. Default: the whole request at
    /// once.
    fn handle_slice(&mut self, req: Request) -> Slice {
        Slice::Done(self.handle(req))
    }

    /// Continues a request that waited ([`Slice::Wait`]) once its wait is
    /// over; `ok` says whether what it waited for succeeded. Always called,
    /// even when the request's connection has closed meanwhile. Default
    /// (a handler that never waits is never asked): `Busy`.
    fn resume(&mut self, _token: u64, _ok: bool) -> Slice {
        Slice::Done(Answer::Protocol(crate::wire::ProtocolError::Busy))
    }
}

/// What one slice of a request left.
#[derive(Debug)]
pub enum Slice {
    /// The request is complete: its answer.
    Done(Answer),
    /// The rest of the request, to serve as a further slice.
    More(Request),
    /// The request waits for something outside the handler (a durable
    /// write): the server awaits it without holding the handler, so other
    /// requests are served meanwhile, then calls
    /// [`Handler::resume`] with the wait's token.
    Wait(Wait),
}

/// What a request waits for (see [`Slice::Wait`]).
#[derive(Debug)]
pub struct Wait {
    /// Says whether it succeeded; a sender dropped unsent counts as a
    /// failure.
    pub done: tokio::sync::oneshot::Receiver<bool>,
    /// The handler's own number for the request, given back to
    /// [`Handler::resume`].
    pub token: u64,
}

/// The state one connection keeps for itself: made (`Default`) when the
/// connection is accepted, dropped when it ends, seen by no other
/// connection. It sees each of its connection's requests first, in order.
pub trait Session: Default + Send + 'static {
    /// Answers `req` from the connection's own state, or hands it on to
    /// the shared handler.
    fn handle(&mut self, req: Request) -> Served;
}

/// Who answers a request: the connection's session or the shared handler.
#[derive(Debug, Clone, PartialEq)]
pub enum Served {
    /// Answered by the session.
    Here(Answer),
    /// Served in part by the session: the rest, for the session to serve
    /// as a further slice (the connection lets other tasks run, and stops
    /// if it is closed, in between).
    More(Request),
    /// For the shared handler.
    Shared(Request),
}

/// No state of its own: every request goes to the shared handler.
impl Session for () {
    fn handle(&mut self, req: Request) -> Served {
        Served::Shared(req)
    }
}

/// How connections share the handler.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Core {
    /// A mutex around the handler; each request locks it briefly.
    #[default]
    Lock,
    /// One task owns the handler; connections send it requests over a channel.
    Owner,
}

/// Server settings.
#[derive(Debug, Clone)]
pub struct ServerConfig {
    /// Address to listen on (default `127.0.0.1:1300`).
    pub listen: SocketAddr,
    /// Allow a non-loopback listen address (it also needs an access token).
    pub allow_remote: bool,
    /// Connections served at once. A further one takes the place of the
    /// connection quiet longest (for `evict_after` at least), or else is
    /// answered `Busy` and closed.
    pub max_connections: usize,
    /// Connections served at once from one peer address on another
    /// machine. A further one from it takes the place of its connection
    /// quiet longest, or else is answered `Busy` and closed.
    pub max_connections_per_peer: usize,
    /// Count loopback peers (every program on this machine shares one
    /// address) against `max_connections_per_peer` too; off, they count
    /// against `max_connections` only.
    pub per_peer_limit_on_loopback: bool,
    /// When the server is full, a connection without progress for this
    /// long may be closed to make room for a new one, which waits at most
    /// one and a half times this for a place. `None`: no eviction, a new
    /// connection finding the server full is refused at once.
    pub evict_after: Option<Duration>,
    /// A connection with no complete request read and no batch of answers
    /// written for this long is closed.
    pub idle_timeout: Duration,
    /// A connection whose answers wait on a full socket (the client does
    /// not read them) and do not all leave within this time is closed.
    pub write_timeout: Duration,
    /// Which peers must present an access token in a HELLO frame first.
    pub access: AccessPolicy,
    /// Lock or owner task.
    pub core: Core,
}

impl Default for ServerConfig {
    fn default() -> Self {
        Self {
            listen: SocketAddr::from(([127, 0, 0, 1], 1300)),
            allow_remote: false,
            max_connections: 256,
            max_connections_per_peer: 16,
            per_peer_limit_on_loopback: false,
            evict_after: Some(Duration::from_secs(1)),
            idle_timeout: Duration::from_secs(300),
            write_timeout: Duration::from_secs(30),
            access: AccessPolicy::default(),
            core: Core::Lock,
        }
    }
}

/// A bound server, ready to run.
pub struct Server<H> {
    listener: TcpListener,
    cfg: ServerConfig,
    shared: Shared<H>,
}

impl<H: Handler> Server<H> {
    /// Binds the listen address. A non-loopback address is refused unless
    /// `allow_remote` is set and an access token is given.
    pub async fn bind(cfg: ServerConfig, handler: H) -> io::Result<Self> {
        if !cfg.listen.ip().is_loopback() && !cfg.allow_remote {
            return Err(io::Error::new(
                io::ErrorKind::PermissionDenied,
                format!(
                    "{} is not a loopback address: listening there needs --allow-remote",
                    cfg.listen
                ),
            ));
        }
        if !cfg.listen.ip().is_loopback() && cfg.access.token.is_none() {
            return Err(io::Error::new(
                io::ErrorKind::PermissionDenied,
                format!(
                    "{} is not a loopback address: listening there needs an access token",
                    cfg.listen
                ),
            ));
        }
        let listener = TcpListener::bind(cfg.listen).await?;
        let shared = Shared::new(cfg.core, handler);
        Ok(Self {
            listener,
            cfg,
            shared,
        })
    }

    /// The address actually bound (port 0 picks a free port).
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// A handle through which another face of the same object table
    /// submits requests to the handler the connections share.
    pub fn core(&self) -> CoreHandle {
        CoreHandle::new(self.shared.clone())
    }

    /// Serves until `shutdown` completes, then stops accepting, lets every
    /// connection finish the request it is on, and returns.
    pub async fn run(self, shutdown: impl Future<Output = ()>) -> io::Result<()> {
        let Server {
            listener,
            cfg,
            shared,
        } = self;
        info!(
            listen = %listener.local_addr()?,
            max_connections = cfg.max_connections,
            max_connections_per_peer = cfg.max_connections_per_peer,
            per_peer_limit_on_loopback = cfg.per_peer_limit_on_loopback,
            evict_after_ms = cfg
                .evict_after
                .map(|d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX)),
            token_from_remote = cfg.access.token.is_some(),
            token_from_loopback = cfg.access.token.is_some() && cfg.access.on_loopback,
            core = ?cfg.core,
            "serving UOI"
        );
        let mut gate = Gate::new(&cfg, shared)?;
        let mut retry = tokio::time::interval(gate.retry_every());
        retry.set_missed_tick_behavior(MissedTickBehavior::Delay);
        tokio::pin!(shutdown);
        loop {
            tokio::select! {
                () = &mut shutdown => break,
                accepted = listener.accept() => match accepted {
                    Ok((stream, peer)) => gate.arrive(stream, peer),
                    Err(e) => {
                        warn!(error = %e, "accept failed");
                        tokio::time::sleep(Duration::from_millis(10)).await;
                    }
                },
                // A connection ended: its place may serve a waiting one.
                Some(_) = gate.tasks.join_next(), if !gate.tasks.is_empty() => {
                    if gate.has_waiting() {
                        gate.retry_waiting();
                    }
                }
                _ = retry.tick(), if gate.has_waiting() => gate.retry_waiting(),
            }
        }
        info!("shutting down: finishing open connections");
        gate.close_all();
        let drain = async { while gate.tasks.join_next().await.is_some() {} };
        if tokio::time::timeout(Duration::from_secs(5), drain)
            .await
            .is_err()
        {
            warn!("connections still open after 5 s; closing them");
        }
        Ok(())
    }
}
