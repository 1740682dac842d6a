//! The server's settings: where it listens, its limits and every time
//! limit it keeps, and why it may refuse to listen.

use std::fmt;
use std::net::SocketAddr;
use std::time::Duration;

use super::access::AccessPolicy;
use super::arrivals::AcceptRate;

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
    /// one and a half times this for a place — unless it has presented
    /// the access token or completed a request (and takes its answers):
    /// such a connection is never closed to make room. `None`: no
    /// eviction, a new connection finding the server full is refused at
    /// once.
    pub evict_after: Option<Duration>,
    /// How fast one peer address (loopback too) may open new connections;
    /// those over the rate are answered `Busy` and closed at once.
    /// `None`: no limit.
    pub accept_rate_per_peer: Option<AcceptRate>,
    /// A connection with no complete request read and no batch of answers
    /// written for this long is closed.
    pub idle_timeout: Duration,
    /// A connection whose answers wait on a full socket (the client does
    /// not read them) and do not all leave within this time is closed.
    pub write_timeout: Duration,
    /// Pause after a failed accept (no file descriptor left, for one)
    /// before the next: a failure that lasts does not spin the server.
    pub accept_pause: Duration,
    /// On shutdown, how long the open connections may take to finish the
    /// request each is on; those still open after it are dropped.
    pub shutdown_grace: Duration,
    /// Which peers must present an access token in a HELLO frame first.
    pub access: AccessPolicy,
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
            accept_rate_per_peer: Some(AcceptRate::default()),
            idle_timeout: Duration::from_secs(300),
            write_timeout: Duration::from_secs(30),
            accept_pause: Duration::from_millis(10),
            shutdown_grace: Duration::from_secs(5),
            access: AccessPolicy::default(),
        }
    }
}

impl ServerConfig {
    /// Why the server may not listen where these settings say: a
    /// non-loopback address without `allow_remote`, or without a token.
    pub fn refusal(&self) -> Option<Refused> {
        if self.listen.ip().is_loopback() {
            None
        } else if !self.allow_remote {
            Some(Refused::NotAllowed(self.listen))
        } else if self.access.token.is_none() {
            Some(Refused::NoToken(self.listen))
        } else {
            None
        }
    }
}

/// Why the server refuses to listen on an address (the inner error of the
/// `PermissionDenied` that [`Server::bind`](super::Server::bind) returns).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refused {
    /// A non-loopback address while `allow_remote` is off.
    NotAllowed(SocketAddr),
    /// A non-loopback address without an access token.
    NoToken(SocketAddr),
}

impl fmt::Display for Refused {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refused::NotAllowed(a) => write!(
                f,
                "{a} is not a loopback address: listening there is not allowed"
            ),
            Refused::NoToken(a) => write!(
                f,
                "{a} is not a loopback address: listening there needs an access token"
            ),
        }
    }
}

impl std::error::Error for Refused {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tcp::AccessToken;

    #[test]
    fn only_loopback_is_served_without_leave_and_token() {
        let at = |listen: &str| ServerConfig {
            listen: listen.parse().expect("addr"),
            ..ServerConfig::default()
        };
        assert_eq!(at("127.0.0.1:1").refusal(), None);
        assert_eq!(at("[::1]:1").refusal(), None);
        let remote = at("0.0.0.0:1");
        assert_eq!(remote.refusal(), Some(Refused::NotAllowed(remote.listen)));
        let allowed = ServerConfig {
            allow_remote: true,
            ..remote
        };
        assert_eq!(allowed.refusal(), Some(Refused::NoToken(allowed.listen)));
        let mut with_token = allowed;
        with_token.access.token = Some(AccessToken::new("0123456789abcdef").expect("token"));
        assert_eq!(with_token.refusal(), None);
    }
}
