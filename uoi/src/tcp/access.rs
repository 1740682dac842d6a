//! Who may use a connection: the access token a peer presents in its
//! HELLO frame, and which peers must present it.
//!
//! The token is a shared secret, compared in constant time. It travels in
//! clear: it keeps out whoever does not know it, not whoever can read the
//! network path.

use std::fmt;
use std::net::IpAddr;

use subtle::ConstantTimeEq;

/// Shortest token accepted, in characters.
pub const MIN_TOKEN_LEN: usize = 16;
/// Longest token accepted, in characters.
pub const MAX_TOKEN_LEN: usize = 256;

/// Why a text is not a usable token.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "an access token is {MIN_TOKEN_LEN} to {MAX_TOKEN_LEN} printable ASCII characters \
     without spaces; this one {0}"
)]
pub struct BadToken(String);

/// A shared secret that grants a connection access. Its `Debug` form does
/// not show it.
#[derive(Clone, PartialEq, Eq)]
pub struct AccessToken(Box<[u8]>);

impl AccessToken {
    /// The token `text` stands for, surrounding white space (a file's
    /// final newline) removed.
    pub fn new(text: &str) -> Result<Self, BadToken> {
        let t = text.trim();
        if !t.bytes().all(|b| b.is_ascii_graphic()) {
            return Err(BadToken("has spaces or other characters".into()));
        }
        if !(MIN_TOKEN_LEN..=MAX_TOKEN_LEN).contains(&t.len()) {
            return Err(BadToken(format!("has {} characters", t.len())));
        }
        Ok(Self(t.as_bytes().into()))
    }

    /// The token's bytes, as a HELLO frame carries them.
    pub fn as_bytes(&self) -> &[u8] {
        &self.0
    }

    /// Whether `presented` is this token. The time taken does not depend
    /// on where the two differ (only on their lengths).
    pub fn matches(&self, presented: &[u8]) -> bool {
        self.0.ct_eq(presented).into()
    }
}

/// Whether `payload` is a well-formed HELLO payload: empty (a client
/// with no token to show), or shaped like a token — [`MIN_TOKEN_LEN`] to
/// [`MAX_TOKEN_LEN`] printable ASCII characters without spaces.
pub fn is_hello_payload(payload: &[u8]) -> bool {
    payload.is_empty()
        || ((MIN_TOKEN_LEN..=MAX_TOKEN_LEN).contains(&payload.len())
            && payload.iter().all(u8::is_ascii_graphic))
}

impl fmt::Debug for AccessToken {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("AccessToken(..)")
    }
}

/// Whether `ip` is this machine's loopback: `127.0.0.0/8`, `::1`, or a
/// loopback IPv4 address mapped into IPv6 (as a dual-stack listener on
/// `[::]` sees an IPv4 peer).
pub fn is_loopback_peer(ip: IpAddr) -> bool {
    ip.to_canonical().is_loopback()
}

/// Which peers must present the token before their first request.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AccessPolicy {
    /// The token; `None` lets every peer in without one.
    pub token: Option<AccessToken>,
    /// Ask loopback peers (programs on this machine) for the token too.
    pub on_loopback: bool,
}

impl AccessPolicy {
    /// Whether a connection from `peer` must present the token first.
    pub fn needs_token(&self, peer: IpAddr) -> bool {
        self.token.is_some() && (self.on_loopback || !is_loopback_peer(peer))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(s: &str) -> IpAddr {
        s.parse().expect("ip")
    }

    #[test]
    fn loopback_peers_in_every_form_and_nothing_else() {
        for local in [
            "127.0.0.1",
            "127.0.0.2",
            "127.255.0.9",
            "::1",
            "::ffff:127.0.0.1",
        ] {
            assert!(is_loopback_peer(ip(local)), "{local}");
        }
        for remote in [
            "192.168.1.5",
            "10.0.0.1",
            "0.0.0.0",
            "::ffff:10.0.0.1",
            "fe80::1",
        ] {
            assert!(!is_loopback_peer(ip(remote)), "{remote}");
        }
    }

    #[test]
    fn the_token_is_asked_of_remote_peers_and_of_loopback_only_if_configured() {
        let token = AccessToken::new("0123456789abcdef0123").expect("token");
        let open = AccessPolicy::default();
        assert!(!open.needs_token(ip("192.168.1.5")));
        let remote_only = AccessPolicy {
            token: Some(token.clone()),
            on_loopback: false,
        };
        assert!(remote_only.needs_token(ip("192.168.1.5")));
        assert!(remote_only.needs_token(ip("::ffff:10.1.2.3")));
        assert!(!remote_only.needs_token(ip("127.0.0.1")));
        assert!(!remote_only.needs_token(ip("::ffff:127.0.0.1")));
        let everyone = AccessPolicy {
            token: Some(token),
            on_loopback: true,
        };
        assert!(everyone.needs_token(ip("127.0.0.1")));
    }

    #[test]
    fn a_hello_payload_is_empty_or_shaped_like_a_token() {
        assert!(is_hello_payload(b""));
        assert!(is_hello_payload(b"0123456789abcdef"));
        assert!(is_hello_payload("x".repeat(MAX_TOKEN_LEN).as_bytes()));
        assert!(!is_hello_payload(b"short"));
        assert!(!is_hello_payload(b"0123456789 abcdef"));
        assert!(!is_hello_payload(&[0xFF; 20]));
        assert!(!is_hello_payload("x".repeat(MAX_TOKEN_LEN + 1).as_bytes()));
        assert!(!is_hello_payload(&vec![b'a'; 60_000]));
    }

    #[test]
    fn tokens_match_exactly_and_weak_ones_are_refused() {
        let t = AccessToken::new("  0123456789abcdef\n").expect("token");
        assert!(t.matches(b"0123456789abcdef"));
        assert!(!t.matches(b"0123456789abcdeF"));
        assert!(!t.matches(b"0123456789abcde"));
        assert!(!t.matches(b""));
        assert!(AccessToken::new("short").is_err());
        assert!(AccessToken::new("0123456789 abcdef").is_err());
        assert!(AccessToken::new(&"x".repeat(MAX_TOKEN_LEN + 1)).is_err());
        assert_eq!(format!("{t:?}"), "AccessToken(..)");
    }
}
