//! The tokio object server: one task per connection, all connections share
//! one handler behind a lock, pipelined requests answered in order. Each
//! connection also keeps a [`Session`](super::Session) of its own, which
//! may take its requests before the shared handler sees them.

use std::future::Future;
use std::io;
use std::net::SocketAddr;

use tokio::net::TcpListener;
use tokio::time::MissedTickBehavior;
use tracing::{info, warn};

use super::config::ServerConfig;
use super::core_handle::CoreHandle;
use super::gate::Gate;
use super::handler::Handler;
use super::shared::Shared;

/// A bound server, ready to run.
pub struct Server<H> {
    listener: TcpListener,
    cfg: ServerConfig,
    shared: Shared<H>,
}

impl<H: Handler> Server<H> {
    /// Binds the listen address. A non-loopback address is refused
    /// (`PermissionDenied`, its inner error a [`Refused`](super::Refused))
    /// unless `allow_remote` is set and an access token is given.
    pub async fn bind(cfg: ServerConfig, handler: H) -> io::Result<Self> {
        if let Some(refused) = cfg.refusal() {
            return Err(io::Error::new(io::ErrorKind::PermissionDenied, refused));
        }
        let listener = TcpListener::bind(cfg.listen).await?;
        let shared = Shared::new(handler);
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
        log_start(listener.local_addr()?, &cfg);
        let mut gate = Gate::new(&cfg, shared)?;
        // Newcomers wait for a place only where connections may be evicted.
        let mut retry = gate.retry_every().map(|every| {
            let mut retry = tokio::time::interval(every);
            retry.set_missed_tick_behavior(MissedTickBehavior::Delay);
            retry
        });
        tokio::pin!(shutdown);
        loop {
            tokio::select! {
                () = &mut shutdown => break,
                accepted = listener.accept() => match accepted {
                    Ok((stream, peer)) => gate.arrive(stream, peer),
                    Err(e) => {
                        if let Some(suppressed) = gate.logs.accept_failed.allow() {
                            warn!(error = %e, suppressed, "accept failed");
                        }
                        tokio::time::sleep(cfg.accept_pause).await;
                    }
                },
                // A connection ended: its place may serve a waiting one.
                Some(_) = gate.tasks.join_next(), if !gate.tasks.is_empty() => {
                    if gate.has_waiting() {
                        gate.retry_waiting();
                    }
                }
                Some(_) = tick(retry.as_mut()), if gate.has_waiting() => gate.retry_waiting(),
            }
        }
        finish(gate, &cfg).await;
        Ok(())
    }
}

/// The one start line: the address and the limits in force.
fn log_start(listen: SocketAddr, cfg: &ServerConfig) {
    info!(
        listen = %listen,
        max_connections = cfg.max_connections,
        max_connections_per_peer = cfg.max_connections_per_peer,
        per_peer_limit_on_loopback = cfg.per_peer_limit_on_loopback,
        evict_after_ms = cfg
            .evict_after
            .map(|d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX)),
        token_from_remote = cfg.access.token.is_some(),
        token_from_loopback = cfg.access.token.is_some() && cfg.access.on_loopback,
        "serving UOI"
    );
}

/// Shutdown: every connection is told to finish the request it is on;
/// those still open after the grace are dropped with the gate.
async fn finish<H: Handler>(mut gate: Gate<H>, cfg: &ServerConfig) {
    info!("shutting down: finishing open connections");
    gate.close_all();
    let drain = async { while gate.tasks.join_next().await.is_some() {} };
    if tokio::time::timeout(cfg.shutdown_grace, drain)
        .await
        .is_err()
    {
        warn!(
            grace_ms = u64::try_from(cfg.shutdown_grace.as_millis()).unwrap_or(u64::MAX),
            "connections still open after the shutdown grace; closing them"
        );
    }
}

/// The next tick of `retry`, if there is one.
async fn tick(retry: Option<&mut tokio::time::Interval>) -> Option<tokio::time::Instant> {
    Some(retry?.tick().await)
}
