//! How fast one address may open connections: a token bucket per peer
//! address (`burst` new connections at once, then `per_second`). A flood
//! of new connections from one address is slowed to that rate, whatever
//! the places; those over it are answered `Busy` and closed at once.
//!
//! Memory stays bounded: the buckets of addresses that have opened none
//! lately (a full bucket) are forgotten once more than [`TRACKED`] are
//! kept, and if an attacker with that many addresses keeps them all busy,
//! all are forgotten (each address then starts with a full burst again).

use std::collections::HashMap;
use std::net::IpAddr;
use std::time::Instant;

/// Addresses whose buckets are kept before idle ones are forgotten.
const TRACKED: usize = 4096;

/// The rate at which one address may open connections.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AcceptRate {
    /// New connections per second, in the long run.
    pub per_second: f64,
    /// New connections at once, after a pause.
    pub burst: u32,
}

impl Default for AcceptRate {
    /// 100 a second, 200 at once: far above what scripts and load tests
    /// on one machine open, far below a flood (hundreds a second).
    fn default() -> Self {
        Self {
            per_second: 100.0,
            burst: 200,
        }
    }
}

/// The buckets of the addresses seen lately.
#[derive(Debug)]
pub(crate) struct Arrivals {
    rate: Option<AcceptRate>,
    buckets: HashMap<IpAddr, Bucket>,
}

/// New connections an address may still open, as of `at`.
#[derive(Debug, Clone, Copy)]
struct Bucket {
    tokens: f64,
    at: Instant,
}

impl Arrivals {
    /// Arrivals at `rate` per address; `None`: no limit.
    pub(crate) fn new(rate: Option<AcceptRate>) -> Self {
        Self {
            rate,
            buckets: HashMap::new(),
        }
    }

    /// Whether a new connection from `ip` at `now` is within its
    /// address's rate (and counts it).
    pub(crate) fn admit(&mut self, ip: IpAddr, now: Instant) -> bool {
        let Some(rate) = self.rate else {
            return true;
        };
        let burst = f64::from(rate.burst);
        if self.buckets.len() >= TRACKED {
            self.forget_idle(rate, now);
        }
        let b = self.buckets.entry(ip.to_canonical()).or_insert(Bucket {
            tokens: burst,
            at: now,
        });
        let since = now.saturating_duration_since(b.at).as_secs_f64();
        b.tokens = (b.tokens + since * rate.per_second.max(0.0)).min(burst);
        b.at = now;
        if b.tokens >= 1.0 {
            b.tokens -= 1.0;
            true
        } else {
            false
        }
    }

    /// Forgets the buckets that are full again by `now`; all of them if
    /// that leaves too many.
    fn forget_idle(&mut self, rate: AcceptRate, now: Instant) {
        let burst = f64::from(rate.burst);
        self.buckets.retain(|_, b| {
            let since = now.saturating_duration_since(b.at).as_secs_f64();
            b.tokens + since * rate.per_second < burst
        });
        if self.buckets.len() >= TRACKED {
            self.buckets.clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn ip(s: &str) -> IpAddr {
        s.parse().expect("ip")
    }

    #[test]
    fn a_burst_then_the_rate_per_address() {
        let mut a = Arrivals::new(Some(AcceptRate {
            per_second: 10.0,
            burst: 3,
        }));
        let t0 = Instant::now();
        let ms = |n| t0 + Duration::from_millis(n);
        let first: Vec<bool> = (0..5).map(|_| a.admit(ip("10.0.0.1"), t0)).collect();
        assert_eq!(first, [true, true, true, false, false]);
        // Another address has its own bucket; the IPv4-mapped form is the
        // same address.
        assert!(a.admit(ip("10.0.0.2"), t0));
        assert!(!a.admit(ip("::ffff:10.0.0.1"), t0));
        // One more every 100 ms.
        assert!(!a.admit(ip("10.0.0.1"), ms(50)));
        assert!(a.admit(ip("10.0.0.1"), ms(150)));
        assert!(!a.admit(ip("10.0.0.1"), ms(160)));
        // After a pause, the whole burst again, not more.
        let later: Vec<bool> = (0..4)
            .map(|_| a.admit(ip("10.0.0.1"), ms(10_000)))
            .collect();
        assert_eq!(later, [true, true, true, false]);
    }

    #[test]
    fn without_a_rate_every_connection_is_admitted() {
        let mut a = Arrivals::new(None);
        let t0 = Instant::now();
        assert!((0..10_000).all(|_| a.admit(ip("127.0.0.1"), t0)));
    }

    #[test]
    fn the_buckets_kept_stay_bounded() {
        let mut a = Arrivals::new(Some(AcceptRate {
            per_second: 1.0,
            burst: 2,
        }));
        let t0 = Instant::now();
        for k in 0..3 * TRACKED as u32 {
            assert!(a.admit(IpAddr::from(k.to_be_bytes()), t0));
        }
        assert!(a.buckets.len() <= TRACKED);
    }
}
