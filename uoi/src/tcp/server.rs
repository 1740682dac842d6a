//! The tokio object server: one task per connection, all connections share
//! one handler (behind a lock, or owned by one task), pipelined requests
//! answered in order. Each connection also keeps a [`Session`] of its own,
//! which may answer its requests before the shared handler sees them.

use std::collections::VecDeque;
use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, TryLockError};
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::{mpsc, oneshot};
use tokio::time::MissedTickBehavior;
use tracing::{info, warn};

use super::access::AccessPolicy;
use super::gate::Gate;
use super::idle::Activity;
use crate::wire::{Answer, ProtocolError, Request};

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
}

/// What one slice of a request left.
#[derive(Debug, Clone, PartialEq)]
pub enum Slice {
    /// The request is complete: its answer.
    Done(Answer),
    /// The rest of the request, to serve as a further slice.
    More(Request),
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

type Job = (Request, oneshot::Sender<Answer>);

/// Most times a request with more slices to go yields to requests
/// waiting for the lock before it takes the next slice.
const YIELDS_TO_WAITING: usize = 1000;

/// New jobs the owner task serves in a row before it gives the next slice
/// to a job with more to go (so a steady stream of requests cannot starve a
/// long one).
const FRESH_BEFORE_REST: usize = 64;

/// The handler behind a lock, with a count of the requests waiting for it.
pub(crate) struct Locked<H> {
    handler: Mutex<H>,
    /// Requests blocked on the lock right now (a request with more slices
    /// to go lets them in first; the mutex itself is not fair).
    waiting: AtomicUsize,
}

impl<H: Handler> Locked<H> {
    /// One slice under the lock.
    fn slice(&self, req: Request) -> Slice {
        // The count of waiters is touched only when the lock is taken:
        // two shared atomic updates per request cost pipelined traffic
        // about a fifth of its rate.
        let mut h = match self.handler.try_lock() {
            Ok(h) => h,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            Err(TryLockError::WouldBlock) => {
                self.waiting.fetch_add(1, Ordering::AcqRel);
                let h = self.handler.lock().unwrap_or_else(|p| p.into_inner());
                self.waiting.fetch_sub(1, Ordering::AcqRel);
                h
            }
        };
        h.handle_slice(req)
    }

    /// Between two slices: lets the requests waiting for the lock in
    /// (a bounded number of yields, so a steady stream cannot starve the
    /// long request).
    async fn let_others_in(&self) {
        tokio::task::yield_now().await;
        for _ in 0..YIELDS_TO_WAITING {
            if self.waiting.load(Ordering::Acquire) == 0 {
                return;
            }
            tokio::task::yield_now().await;
        }
    }
}

/// The shared handler.
pub(crate) enum Shared<H> {
    Lock(Arc<Locked<H>>),
    Owner(mpsc::Sender<Job>),
}

impl<H> Clone for Shared<H> {
    fn clone(&self) -> Self {
        match self {
            Shared::Lock(m) => Shared::Lock(Arc::clone(m)),
            Shared::Owner(tx) => Shared::Owner(tx.clone()),
        }
    }
}

impl<H: Handler> Shared<H> {
    /// Answers one request with the shared handler, slice by slice; the
    /// lock is released and other tasks run between slices. When the
    /// connection is closed meanwhile (`closed`: idle, evicted, stopping)
    /// the rest of the request is dropped and `Busy` comes back (nobody
    /// reads it), so a closed connection never keeps the handler busy.
    pub(crate) async fn handle(&self, req: Request, closed: &Activity) -> Answer {
        match self {
            Shared::Lock(m) => {
                let mut req = req;
                loop {
                    // No await while locked: one slice is a plain call.
                    match m.slice(req) {
                        Slice::Done(answer) => return answer,
                        Slice::More(rest) => req = rest,
                    }
                    m.let_others_in().await;
                    if closed.closed().is_some() {
                        return Answer::Protocol(ProtocolError::Busy);
                    }
                }
            }
            // Boxed: its state (a channel and a race with the close) would
            // otherwise enlarge every request's future, lock core too.
            Shared::Owner(tx) => Box::pin(ask(tx, req, closed)).await,
        }
    }
}

/// The owner task: serves the jobs of every connection; a job with more
/// slices to go waits behind the jobs that arrived meanwhile.
async fn own<H: Handler>(mut h: H, mut rx: mpsc::Receiver<Job>) {
    let mut later: VecDeque<Job> = VecDeque::new();
    let mut fresh = 0;
    loop {
        let turn = if fresh >= FRESH_BEFORE_REST {
            fresh = 0;
            later.pop_front()
        } else {
            None
        };
        let job = match turn.map_or_else(|| rx.try_recv().map(|j| (j, true)), |j| Ok((j, false))) {
            Ok((job, new)) => {
                fresh += usize::from(new);
                job
            }
            Err(_) => match later.pop_front() {
                Some(job) => job,
                None => match rx.recv().await {
                    Some(job) => job,
                    None => return,
                },
            },
        };
        let (req, answer) = job;
        match h.handle_slice(req) {
            Slice::Done(a) => {
                let _ = answer.send(a);
            }
            // The rest waits its turn, unless its connection is gone.
            Slice::More(rest) if !answer.is_closed() => {
                later.push_back((rest, answer));
                tokio::task::yield_now().await;
            }
            Slice::More(_) => {}
        }
    }
}

/// Hands a request to the owner task and waits for its answer, or until
/// the connection is closed (the owner task then drops the rest of it).
async fn ask(tx: &mpsc::Sender<Job>, req: Request, closed: &Activity) -> Answer {
    let (atx, arx) = oneshot::channel();
    if tx.send((req, atx)).await.is_err() {
        return Answer::Protocol(ProtocolError::Busy);
    }
    let gone = std::future::poll_fn(|cx| closed.poll_closed(cx));
    tokio::select! {
        answer = arx => answer.unwrap_or(Answer::Protocol(ProtocolError::Busy)),
        _ = gone => Answer::Protocol(ProtocolError::Busy),
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
        let shared = match cfg.core {
            Core::Lock => Shared::Lock(Arc::new(Locked {
                handler: Mutex::new(handler),
                waiting: AtomicUsize::new(0),
            })),
            Core::Owner => {
                let (tx, rx) = mpsc::channel::<Job>(1024);
                tokio::spawn(own(handler, rx));
                Shared::Owner(tx)
            }
        };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ObjectAddress, Value, ValueType};
    use std::sync::atomic::AtomicU64;

    /// READ of index 0 never ends (counted per slice); any other READ is
    /// answered at once.
    struct Endless(Arc<AtomicU64>);

    impl Handler for Endless {
        type Session = ();
        fn handle(&mut self, _req: Request) -> Answer {
            Answer::Ok
        }
        fn handle_slice(&mut self, req: Request) -> Slice {
            match req {
                Request::Read(a, _) if a.index == 0 => {
                    self.0.fetch_add(1, Ordering::Relaxed);
                    Slice::More(req)
                }
                _ => Slice::Done(Answer::Value(Value::I32(1))),
            }
        }
    }

    fn read(index: u16) -> Request {
        Request::Read(ObjectAddress::new(1, 0, index, 0), ValueType::I32)
    }

    #[tokio::test]
    async fn a_stream_of_new_jobs_cannot_starve_a_long_one() {
        let slices = Arc::new(AtomicU64::new(0));
        let (tx, rx) = mpsc::channel::<Job>(2048);
        let owner = tokio::spawn(own(Endless(Arc::clone(&slices)), rx));
        let (long_tx, _long_rx) = oneshot::channel();
        tx.try_send((read(0), long_tx)).expect("queued");
        let answers: Vec<_> = (0..1000)
            .map(|_| {
                let (atx, arx) = oneshot::channel();
                tx.try_send((read(5), atx)).expect("queued");
                arx
            })
            .collect();
        for a in answers {
            assert_eq!(a.await.expect("answered"), Answer::Value(Value::I32(1)));
        }
        // The long job had a slice after every 64 new ones at least.
        assert!(slices.load(Ordering::Relaxed) >= 1000 / 64, "{slices:?}");
        drop(tx);
        drop(_long_rx);
        owner.await.expect("the owner task ends once nobody waits");
    }
}
