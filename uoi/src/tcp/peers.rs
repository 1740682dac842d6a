//! Connections open per peer address: one host may hold at most
//! `max_connections_per_peer` of the server's places, so it cannot take
//! them all from the others.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::{Arc, Mutex};

/// How many connections each peer address has open.
#[derive(Debug)]
pub(crate) struct Peers {
    open: Mutex<HashMap<IpAddr, usize>>,
    /// Most connections one address may have open.
    max_per_peer: usize,
}

impl Peers {
    /// At most `max_per_peer` connections per address.
    pub(crate) fn new(max_per_peer: usize) -> Arc<Self> {
        Arc::new(Self {
            open: Mutex::new(HashMap::new()),
            max_per_peer,
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<IpAddr, usize>> {
        self.open.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// A place for one more connection from `ip`, or `None` when it has
    /// its maximum open. An IPv4 peer seen through a dual-stack listener
    /// counts as its IPv4 address.
    pub(crate) fn take(self: &Arc<Self>, ip: IpAddr) -> Option<PeerPlace> {
        let ip = ip.to_canonical();
        let mut open = self.lock();
        let n = open.entry(ip).or_insert(0);
        if *n >= self.max_per_peer {
            return None;
        }
        *n += 1;
        Some(PeerPlace {
            peers: Arc::clone(self),
            ip,
        })
    }
}

/// One connection's place among its peer's; given back when dropped.
#[derive(Debug)]
pub(crate) struct PeerPlace {
    peers: Arc<Peers>,
    ip: IpAddr,
}

impl Drop for PeerPlace {
    fn drop(&mut self) {
        let mut open = self.peers.lock();
        if let Some(n) = open.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                open.remove(&self.ip);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(s: &str) -> IpAddr {
        s.parse().expect("ip")
    }

    #[test]
    fn each_address_has_its_own_places_given_back_on_drop() {
        let peers = Peers::new(2);
        let a1 = peers.take(ip("10.0.0.1")).expect("first");
        let _a2 = peers
            .take(ip("::ffff:10.0.0.1"))
            .expect("second, same host");
        assert!(peers.take(ip("10.0.0.1")).is_none());
        let _b = peers.take(ip("10.0.0.2")).expect("another host");
        drop(a1);
        assert!(peers.take(ip("10.0.0.1")).is_some());
    }

    #[test]
    fn addresses_without_connections_are_forgotten() {
        let peers = Peers::new(1);
        for k in 0..100u8 {
            drop(peers.take(IpAddr::from([10, 0, 0, k])).expect("place"));
        }
        assert!(peers.lock().is_empty());
    }
}
