//! Server addresses as users type them, for `serve --listen`, the
//! `listen` setting, `call` and `replay --server`: one reading for all.

use std::net::{Ipv4Addr, SocketAddr, ToSocketAddrs};

/// The forms accepted, for error messages.
pub const ADDRESS_FORMS: &str =
    "HOST:PORT (127.0.0.1:1300, localhost:1300, [::1]:1300) or a bare PORT (1300)";

/// Why a text is not a server address.
#[derive(Debug, thiserror::Error)]
pub enum AddressError {
    /// Not in one of the [`ADDRESS_FORMS`].
    #[error("`{0}` is not an address: use {ADDRESS_FORMS}")]
    Form(String),
    /// The host name could not be looked up (the text, the host).
    #[error("`{0}`: cannot find host `{1}`: {2}")]
    Lookup(String, String, #[source] std::io::Error),
    /// The host name has no address (the text, the host).
    #[error("`{0}`: host `{1}` has no address")]
    NoAddress(String, String),
}

/// The message, for callers that keep errors as text (the command line).
impl From<AddressError> for String {
    fn from(e: AddressError) -> Self {
        e.to_string()
    }
}

/// Reads a server address: `HOST:PORT` (an IP address, `localhost`, or a
/// host name looked up), or a bare `PORT` meaning `127.0.0.1:PORT`.
/// `localhost` is `127.0.0.1`, so that a server and its clients agree
/// whatever the resolver says.
pub fn parse_address(text: &str) -> Result<SocketAddr, AddressError> {
    let text = text.trim();
    let bad = || AddressError::Form(text.into());
    if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) {
        let port: u16 = text.parse().map_err(|_| bad())?;
        return Ok(SocketAddr::from((Ipv4Addr::LOCALHOST, port)));
    }
    if let Ok(addr) = text.parse::<SocketAddr>() {
        return Ok(addr);
    }
    let (host, port) = text.rsplit_once(':').ok_or_else(bad)?;
    let port: u16 = port.parse().map_err(|_| bad())?;
    if host.eq_ignore_ascii_case("localhost") {
        return Ok(SocketAddr::from((Ipv4Addr::LOCALHOST, port)));
    }
    if host.is_empty() || host.contains(':') {
        return Err(bad());
    }
    let mut found = (host, port)
        .to_socket_addrs()
        .map_err(|e| AddressError::Lookup(text.into(), host.into(), e))?;
    found
        .next()
        .ok_or_else(|| AddressError::NoAddress(text.into(), host.into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_form() {
        for (text, want) in [
            ("127.0.0.1:1300", "127.0.0.1:1300"),
            ("1300", "127.0.0.1:1300"),
            ("0", "127.0.0.1:0"),
            ("localhost:1301", "127.0.0.1:1301"),
            ("LOCALHOST:1301", "127.0.0.1:1301"),
            ("[::1]:1302", "[::1]:1302"),
            ("0.0.0.0:1300", "0.0.0.0:1300"),
        ] {
            assert_eq!(
                parse_address(text).map(|a| a.to_string()).ok(),
                Some(want.into())
            );
        }
        for text in [
            "",
            "nowhere",
            "65536",
            "localhost",
            "localhost:",
            "localhost:x",
            ":1300",
            "::1:1300",
            "127.0.0.1:99999",
            "-1",
        ] {
            let e = parse_address(text).unwrap_err();
            assert!(e.to_string().contains(text), "{text}: {e}");
        }
    }
}
