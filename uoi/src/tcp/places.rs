//! The server's places: how many connections are open, in all and per
//! peer address, against `max_connections` and `max_connections_per_peer`.
//! One host may hold at most its share, so it cannot take every place from
//! the others; programs on the server's own machine (loopback) count only
//! against the total, unless told otherwise.

use std::collections::HashMap;
use std::fmt;
use std::net::IpAddr;
use std::sync::{Arc, Mutex};

use super::access::is_loopback_peer;

/// Which limit a connection found reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Full {
    /// `max_connections` are open.
    All,
    /// Its address has `max_connections_per_peer` open.
    Peer(IpAddr),
}

impl fmt::Display for Full {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Full::All => f.write_str("max_connections"),
            Full::Peer(ip) => write!(f, "max_connections_per_peer of {ip}"),
        }
    }
}

/// The limits on open connections.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Most connections open at once.
    pub all: usize,
    /// Most connections open at once from one peer address.
    pub per_peer: usize,
    /// Whether loopback peers count against `per_peer` too.
    pub per_peer_on_loopback: bool,
}

/// Connections open now.
#[derive(Debug, Default)]
struct Open {
    all: usize,
    per_peer: HashMap<IpAddr, usize>,
}

/// How many connections are open, in all and per address.
#[derive(Debug)]
pub struct Places {
    open: Mutex<Open>,
    limits: Limits,
}

impl Places {
    /// Places within `limits`.
    pub fn new(limits: Limits) -> Arc<Self> {
        Arc::new(Self {
            open: Mutex::new(Open::default()),
            limits,
        })
    }

    /// Connections open now, in all.
    pub fn open(&self) -> usize {
        self.lock().all
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Open> {
        self.open.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// A place for one more connection from `ip`, or which limit stands in
    /// the way (its address's first). An IPv4 peer seen through a
    /// dual-stack listener counts as its IPv4 address.
    pub fn take(self: &Arc<Self>, ip: IpAddr) -> Result<Seat, Full> {
        let ip = ip.to_canonical();
        let mut open = self.lock();
        let mine = open.per_peer.get(&ip).copied().unwrap_or(0);
        let limited = self.limits.per_peer_on_loopback || !is_loopback_peer(ip);
        if limited && mine >= self.limits.per_peer {
            return Err(Full::Peer(ip));
        }
        if open.all >= self.limits.all {
            return Err(Full::All);
        }
        open.all += 1;
        *open.per_peer.entry(ip).or_insert(0) += 1;
        Ok(Seat {
            places: Arc::clone(self),
            ip,
        })
    }
}

/// One connection's place; given back when dropped.
#[derive(Debug)]
pub struct Seat {
    places: Arc<Places>,
    ip: IpAddr,
}

impl Seat {
    /// The peer address it counts against.
    pub fn ip(&self) -> IpAddr {
        self.ip
    }
}

impl Drop for Seat {
    fn drop(&mut self) {
        let mut open = self.places.lock();
        open.all = open.all.saturating_sub(1);
        if let Some(n) = open.per_peer.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                open.per_peer.remove(&self.ip);
            }
        }
    }
}

/// A place from `ip` among many, for tests of what holds one.
#[cfg(test)]
pub(crate) fn test_seat(ip: IpAddr) -> Seat {
    let places = Places::new(Limits {
        all: usize::MAX,
        per_peer: usize::MAX,
        per_peer_on_loopback: true,
    });
    match places.take(ip) {
        Ok(seat) => seat,
        Err(full) => panic!("no place: {full}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(s: &str) -> IpAddr {
        s.parse().expect("ip")
    }

    fn places(all: usize, per_peer: usize, per_peer_on_loopback: bool) -> Arc<Places> {
        Places::new(Limits {
            all,
            per_peer,
            per_peer_on_loopback,
        })
    }

    #[test]
    fn each_address_has_its_own_places_given_back_on_drop() {
        let p = places(8, 2, false);
        let a1 = p.take(ip("10.0.0.1")).expect("first");
        let _a2 = p.take(ip("::ffff:10.0.0.1")).expect("second, same host");
        assert_eq!(
            p.take(ip("10.0.0.1")).err(),
            Some(Full::Peer(ip("10.0.0.1")))
        );
        let _b = p.take(ip("10.0.0.2")).expect("another host");
        drop(a1);
        assert!(p.take(ip("10.0.0.1")).is_ok());
    }

    #[test]
    fn the_total_holds_for_every_address() {
        let p = places(2, 2, false);
        let _a = p.take(ip("10.0.0.1")).expect("a");
        let _b = p.take(ip("10.0.0.2")).expect("b");
        assert_eq!(p.take(ip("10.0.0.3")).err(), Some(Full::All));
        assert_eq!(p.take(ip("127.0.0.1")).err(), Some(Full::All));
    }

    #[test]
    fn loopback_counts_per_peer_only_when_told() {
        let p = places(8, 2, false);
        let held: Vec<Seat> = (0..8)
            .map(|_| p.take(ip("127.0.0.1")).expect("loopback"))
            .collect();
        assert_eq!(p.take(ip("127.0.0.1")).err(), Some(Full::All));
        drop(held);
        let p = places(8, 2, true);
        let _held: Vec<Seat> = (0..2)
            .map(|_| p.take(ip("::1")).expect("loopback"))
            .collect();
        assert_eq!(p.take(ip("::1")).err(), Some(Full::Peer(ip("::1"))));
    }

    #[test]
    fn addresses_without_connections_are_forgotten() {
        let p = places(8, 1, false);
        for k in 0..100u8 {
            drop(p.take(IpAddr::from([10, 0, 0, k])).expect("place"));
        }
        let open = p.lock();
        assert!(open.per_peer.is_empty());
        assert_eq!(open.all, 0);
    }
}
