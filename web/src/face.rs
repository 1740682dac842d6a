//! The web face bound and served: where it listens (loopback unless
//! allowed, and then only with the access token, as the UOI face), how
//! many connections and pages it takes, and each connection served to
//! its one answer or its event stream.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::task::JoinSet;
use uoi::tcp::{AccessPolicy, CoreHandle, Places};

use crate::events;
use crate::http::{read_head, write_within, Answer};
use crate::hub::Hub;
use crate::routes::{route, Route};
use crate::sampler;

/// Most pages open at once (event streams); more get `503`.
pub const MAX_VIEWERS: usize = 16;

/// Most connections open at once (pages and their files, `/state`); more
/// get `503`.
pub const MAX_CONNECTIONS: usize = 64;

/// The settings of the web face.
#[derive(Debug, Clone)]
pub struct WebConfig {
    /// Where it listens.
    pub listen: SocketAddr,
    /// Allow a non-loopback address (it then also needs `access.token`).
    pub allow_remote: bool,
    /// Which peers must present the access token (the UOI face's rule).
    pub access: AccessPolicy,
    /// Most pages open at once.
    pub max_viewers: usize,
    /// Most connections open at once.
    pub max_connections: usize,
    /// A write a client does not take within this is its end.
    pub slow_client: Duration,
    /// A request head not complete within this is the connection's end.
    pub request_timeout: Duration,
    /// The OPC UA face's count of client connections
    /// (`opcua_face::Face::connections`), shown beside the others; `None`
    /// without the OPC UA face.
    pub opcua_connections: Option<Arc<Places>>,
}

impl WebConfig {
    /// The face at `listen`, with the limits of this module.
    pub fn new(listen: SocketAddr) -> Self {
        Self {
            listen,
            allow_remote: false,
            access: AccessPolicy::default(),
            max_viewers: MAX_VIEWERS,
            max_connections: MAX_CONNECTIONS,
            slow_client: Duration::from_secs(5),
            request_timeout: Duration::from_secs(5),
            opcua_connections: None,
        }
    }
}

/// Why the web face could not start.
#[derive(Debug, thiserror::Error)]
pub enum WebError {
    /// A non-loopback address without `--allow-remote`.
    #[error("{0} is not a loopback address: serving the web view there needs --allow-remote")]
    NotAllowed(SocketAddr),
    /// A non-loopback address without an access token.
    #[error("{0} is not a loopback address: serving the web view there needs an access token")]
    NoToken(SocketAddr),
    /// The address could not be bound.
    #[error("web view: cannot listen on {0}: {1}")]
    Bind(SocketAddr, std::io::Error),
}

/// The web face, bound.
#[derive(Debug)]
pub struct WebFace {
    listener: TcpListener,
    cfg: Arc<WebConfig>,
    core: CoreHandle,
    hub: Arc<Hub>,
}

impl WebFace {
    /// Binds `cfg.listen`, to show the emulator served behind `core`.
    pub async fn bind(cfg: WebConfig, core: CoreHandle) -> Result<Self, WebError> {
        let at = cfg.listen;
        if !at.ip().is_loopback() {
            if !cfg.allow_remote {
                return Err(WebError::NotAllowed(at));
            }
            if cfg.access.token.is_none() {
                return Err(WebError::NoToken(at));
            }
        }
        let listener = TcpListener::bind(at)
            .await
            .map_err(|e| WebError::Bind(at, e))?;
        Ok(Self {
            listener,
            hub: Hub::with_opcua(cfg.opcua_connections.clone()),
            cfg: Arc::new(cfg),
            core,
        })
    }

    /// The address it listens on.
    pub fn local_addr(&self) -> std::io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// Serves until `shutdown` completes; then every connection is closed.
    pub async fn run(self, shutdown: impl Future<Output = ()>) -> std::io::Result<()> {
        let addr = self.local_addr()?;
        tracing::info!("web view on http://{addr}/");
        let sampling = tokio::spawn(sampler::run(self.core.clone(), Arc::clone(&self.hub)));
        let open = Arc::new(AtomicUsize::new(0));
        let mut connections = JoinSet::new();
        tokio::pin!(shutdown);
        loop {
            tokio::select! {
                () = &mut shutdown => break,
                accepted = self.listener.accept() => match accepted {
                    Ok((socket, peer)) => self.admit(socket, peer, &open, &mut connections),
                    Err(e) => {
                        tracing::warn!("web view: accept failed: {e}");
                        tokio::time::sleep(Duration::from_millis(10)).await;
                    }
                },
                Some(_) = connections.join_next(), if !connections.is_empty() => {}
            }
        }
        connections.shutdown().await;
        sampling.abort();
        Ok(())
    }

    /// Serves one connection in a task of its own, or answers `503` when
    /// the face is full.
    fn admit(
        &self,
        mut socket: TcpStream,
        peer: SocketAddr,
        open: &Arc<AtomicUsize>,
        tasks: &mut JoinSet<()>,
    ) {
        let seat = open.fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
            (n < self.cfg.max_connections).then_some(n + 1)
        });
        let cfg = Arc::clone(&self.cfg);
        if seat.is_err() {
            tasks.spawn(async move {
                let busy = Answer::error("503 Service Unavailable", "too many connections");
                finish(&mut socket, &busy, cfg.slow_client).await;
            });
            return;
        }
        let (hub, core, open) = (Arc::clone(&self.hub), self.core.clone(), Arc::clone(open));
        tasks.spawn(async move {
            serve(socket, peer, &cfg, &hub, &core).await;
            open.fetch_sub(1, Ordering::AcqRel);
        });
    }
}

/// One connection: its request, and its answer or event stream.
async fn serve(
    mut socket: TcpStream,
    peer: SocketAddr,
    cfg: &WebConfig,
    hub: &Arc<Hub>,
    core: &CoreHandle,
) {
    let head = match read_head(&mut socket, cfg.request_timeout).await {
        Ok(h) => h,
        Err(e) => {
            tracing::debug!("web view: {peer}: {e}");
            let bad = Answer::error("400 Bad Request", "not an HTTP request");
            return finish(&mut socket, &bad, cfg.slow_client).await;
        }
    };
    let token_ok = |t: &str| {
        cfg.access
            .token
            .as_ref()
            .is_some_and(|k| k.matches(t.as_bytes()))
    };
    let answer = match route(&head, token_ok, cfg.access.needs_token(peer.ip())) {
        Route::Fixed(a) => a,
        Route::State => state(hub, core).await,
        Route::Events => {
            let Some(_seat) = hub.seat(cfg.max_viewers) else {
                let full = Answer::error("503 Service Unavailable", "too many pages open");
                return finish(&mut socket, &full, cfg.slow_client).await;
            };
            let end = events::stream(&mut socket, hub, cfg.slow_client).await;
            tracing::debug!("web view: {peer}: page gone ({end:?})");
            return;
        }
    };
    finish(&mut socket, &answer, cfg.slow_client).await;
}

/// `/state`: the state now as JSON.
async fn state(hub: &Hub, core: &CoreHandle) -> Answer {
    match sampler::snapshot_now(core, hub.viewers())
        .await
        .map(|s| hub.with_others(s))
    {
        Some(s) => match serde_json::to_string_pretty(&s) {
            Ok(json) => Answer::ok("application/json", json),
            Err(e) => Answer::error("500 Internal Server Error", &e.to_string()),
        },
        None => Answer::error("503 Service Unavailable", "the emulator has stopped"),
    }
}

/// Writes `answer`, then closes: the write side first, and what the
/// client still sends (a request body) is read and dropped for a moment,
/// so that it gets the answer rather than a reset.
async fn finish(socket: &mut TcpStream, answer: &Answer, slow: Duration) {
    if write_within(socket, &answer.to_bytes(), slow)
        .await
        .is_err()
    {
        return;
    }
    let _ = socket.shutdown().await;
    let drain = async {
        let mut sink = [0u8; 4096];
        let mut left: usize = 1 << 20;
        while left > 0 {
            match socket.read(&mut sink).await {
                Ok(0) | Err(_) => break,
                Ok(n) => left = left.saturating_sub(n),
            }
        }
    };
    let _ = tokio::time::timeout(Duration::from_secs(1), drain).await;
}
