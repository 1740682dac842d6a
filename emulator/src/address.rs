//! Server addresses as users type them, for `serve --listen`, the
//! `listen` setting, `call` and `replay --server`: one reading for all.

use std::net::{Ipv4Addr, SocketAddr, ToSocketAddrs};

/// The forms accepted, for error messages.
pub const ADDRESS_FORMS: &str =
    "HOST:PORT (127.0.0.1:1300, localhost:1300, [::1]:1300) or a bare PORT (1300)";

/// Reads a server address: `HOST:PORT` (an IP address, `localhost`, or a
/// host name looked up), or a bare `PORT` meaning `127.0.0.1:PORT`.
/// `localhost` is `127.0.0.1`, so that a server and its clients agree
/// whatever the resolver says.
pub fn parse_address(text: &str) -> Result<SocketAddr, String> {
    let text = text.trim();
    let bad = || format!("`{text}` is not an address: use {ADDRESS_FORMS}");
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
        .map_err(|e| format!("`{text}`: cannot find host `{host}`: {e}"))?;
    found
        .next()
        .ok_or_else(|| format!("`{text}`: host `{host}` has no address"))
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
            assert_eq!(parse_address(text).map(|a| a.to_string()), Ok(want.into()));
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
            assert!(e.contains(text), "{text}: {e}");
        }
    }
}
