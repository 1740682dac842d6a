//! A full server makes room: a new connection takes the place of the
//! connection quiet longest (for the eviction grace at least), from its own
//! address when that address holds its limit; only when every connection
//! is in use is it answered `Busy`. Clients from one machine (loopback)
//! count against the total only, by default.
//!
//! No timed assertions: every wait is bounded by a hang guard (the 60 s
//! read timeout of each client).

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use common::{connect, connect_from, flood_until_blocked, local, read_frame, serve, try_read_head};
use uoi::tcp::{AcceptRate, AccessPolicy, AccessToken, ServerConfig};

const BUSY: u32 = 0xE000_0007;
const HOUR: Duration = Duration::from_secs(3600);

/// `max` places, eviction after `grace_ms` of quiet; the idle and write
/// timeouts far away, so only eviction frees a place.
fn full_at(max: usize, grace_ms: u64) -> ServerConfig {
    ServerConfig {
        max_connections: max,
        idle_timeout: HOUR,
        write_timeout: HOUR,
        evict_after: Some(Duration::from_millis(grace_ms)),
        ..local()
    }
}

/// Sends READ `k` and returns the answer's status; `None` if the server
/// has closed the connection.
fn ask(s: &mut TcpStream, k: u16) -> Option<u32> {
    s.write_all(&read_frame(k)).ok()?;
    let (id, _, status) = try_read_head(s)?;
    assert!(status != 0 || id == u32::from(k), "answer {id} to {k}");
    Some(status)
}

/// Reads (and drops) whatever is left until the server closes `s`: end
/// of stream or a reset, not the guard timeout.
fn closed_by_server(s: &mut TcpStream) -> bool {
    let mut b = [0u8; 4096];
    loop {
        match s.read(&mut b) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(e) => {
                return !matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                )
            }
        }
    }
}

/// A client in use: asks, reads the answer, asks again, until stopped.
struct InUse {
    stop: Arc<AtomicBool>,
    thread: JoinHandle<Result<usize, String>>,
}

impl InUse {
    fn start(mut s: TcpStream) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let mut answered = 0;
            while !stopped.load(Ordering::Relaxed) {
                match ask(&mut s, (answered % 1000) as u16) {
                    Some(0) => answered += 1,
                    other => return Err(format!("after {answered} answers: {other:?}")),
                }
            }
            Ok(answered)
        });
        Self { stop, thread }
    }

    /// Stops it; how many answers it had, or how it lost its connection.
    fn stop(self) -> Result<usize, String> {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().expect("client thread")
    }
}

/// 8 places held by clients that never read their
/// answers (one flooding until the server's writes block), never complete
/// a request (half a frame) or stay silent; fresh clients from the same
/// address are served each in the place of one of them, and every one of
/// them is closed (the close wakes a blocked read or write).
#[test]
fn clients_that_never_read_or_stay_silent_make_room_for_fresh_ones() {
    let (addr, _stop) = serve(full_at(8, 200));
    let mut hogs = Vec::new();
    let mut flooder = connect(addr);
    flood_until_blocked(&mut flooder);
    hogs.push(flooder);
    for k in 0..4 {
        let mut s = connect(addr);
        s.write_all(&read_frame(k)[..10]).expect("write");
        hogs.push(s);
    }
    hogs.extend((0..3).map(|_| connect(addr)));
    let mut fresh = Vec::new();
    for k in 0..8 {
        let mut c = connect(addr);
        assert_eq!(ask(&mut c, 100 + k), Some(0), "fresh client {k}");
        fresh.push(c);
    }
    for (k, hog) in hogs.iter_mut().enumerate() {
        assert!(closed_by_server(hog), "hog {k} still open");
    }
    for (k, c) in fresh.iter_mut().enumerate() {
        assert_eq!(ask(c, 200 + k as u16), Some(0), "fresh client {k} again");
    }
}

/// The connection quiet longest makes room, not one in use.
#[test]
fn the_connection_quiet_longest_goes_not_one_in_use() {
    let (addr, _stop) = serve(full_at(2, 200));
    let mut silent = connect(addr);
    let in_use = InUse::start(connect(addr));
    let mut fresh = connect(addr);
    assert_eq!(ask(&mut fresh, 7), Some(0));
    assert!(closed_by_server(&mut silent));
    let answered = in_use.stop().expect("the client in use kept its place");
    assert!(answered > 0);
}

/// When every connection has made progress within the grace, a newcomer
/// waits a moment and is then answered `Busy`; the others keep going.
#[test]
fn a_newcomer_is_refused_while_every_connection_is_in_use() {
    // A grace of 1 s: a client in use answers thousands of times in it.
    let (addr, _stop) = serve(full_at(2, 1000));
    let a = InUse::start(connect(addr));
    let b = InUse::start(connect(addr));
    let mut fresh = connect(addr);
    assert_eq!(try_read_head(&mut fresh), Some((0, 0, BUSY)));
    assert!(closed_by_server(&mut fresh));
    a.stop().expect("a kept its place");
    b.stop().expect("b kept its place");
}

/// When an address holds its `max_connections_per_peer`, a newcomer from
/// it takes the place of that address's connection quiet longest, even
/// if another host's has been quiet longer; the other host keeps its own.
#[test]
fn at_its_own_limit_an_address_makes_room_among_its_own() {
    let (addr, _stop) = serve(ServerConfig {
        max_connections_per_peer: 3,
        per_peer_limit_on_loopback: true,
        ..full_at(6, 200)
    });
    // 127.0.0.2 plays another host; its first connection is the oldest.
    let mut other = connect_from([127, 0, 0, 2], addr);
    let mut hogs: Vec<TcpStream> = (0..3).map(|_| connect(addr)).collect();
    let mut other2 = connect_from([127, 0, 0, 2], addr);
    assert_eq!(ask(&mut other2, 1), Some(0));
    let mut fresh = connect(addr);
    assert_eq!(ask(&mut fresh, 2), Some(0));
    assert_eq!(ask(&mut other, 3), Some(0), "the other host lost its place");
    let open = hogs
        .iter_mut()
        .enumerate()
        .map(|(k, h)| ask(h, 10 + k as u16))
        .filter(Option::is_some)
        .count();
    assert_eq!(open, 2, "one of 127.0.0.1's own made room");
}

/// With the default limits, 64 clients on this machine
/// (a load test on loopback) are all served, and keep their places.
#[test]
fn sixty_four_local_clients_with_default_limits_are_all_served() {
    let (addr, _stop) = serve(local());
    let mut clients: Vec<TcpStream> = (0..64).map(|_| connect(addr)).collect();
    for round in 0..2u16 {
        for (k, c) in clients.iter_mut().enumerate() {
            let k = k as u16;
            assert_eq!(
                ask(c, 100 * round + k),
                Some(0),
                "client {k}, round {round}"
            );
        }
    }
}

/// A client polling slower than the eviction grace,
/// which has presented the token (`token`) or only completed requests, is
/// never closed to make room for the connections a flood from its own
/// address opens and holds: it loses no request while the flood runs.
fn a_polling_client_loses_nothing_to_a_flood(token: bool) {
    const TOKEN: &str = "0123456789abcdef0123";
    let access = if token {
        AccessPolicy {
            token: Some(AccessToken::new(TOKEN).expect("token")),
            on_loopback: true,
        }
    } else {
        AccessPolicy::default()
    };
    let (addr, _stop) = serve(ServerConfig {
        access,
        accept_rate_per_peer: None,
        ..full_at(4, 20)
    });
    let mut poller = connect(addr);
    if token {
        let mut f = bytes::BytesMut::new();
        let hello = uoi::wire::Request::Hello(bytes::Bytes::from_static(TOKEN.as_bytes()));
        uoi::wire::encode_request(9, &hello, &mut f);
        poller.write_all(&f).expect("hello");
        assert_eq!(try_read_head(&mut poller), Some((9, 3, 0)));
    } else {
        assert_eq!(ask(&mut poller, 1), Some(0));
    }
    let stop = Arc::new(AtomicBool::new(false));
    let flooding = Arc::clone(&stop);
    let flood = std::thread::spawn(move || {
        let mut opened = 0usize;
        let mut held = std::collections::VecDeque::new();
        while !flooding.load(Ordering::Relaxed) {
            if let Ok(s) = TcpStream::connect(addr) {
                opened += 1;
                held.push_back(s);
                if held.len() > 8 {
                    held.pop_front();
                }
            }
        }
        opened
    });
    // Each poll comes after several graces of quiet.
    for k in 0..20 {
        std::thread::sleep(Duration::from_millis(60));
        assert_eq!(ask(&mut poller, 10 + k), Some(0), "poll {k} lost");
    }
    stop.store(true, Ordering::Relaxed);
    let opened = flood.join().expect("flood");
    assert!(opened > 20, "the flood opened {opened} connections");
}

#[test]
fn a_client_that_showed_the_token_is_not_evicted_by_a_flood() {
    a_polling_client_loses_nothing_to_a_flood(true);
}

#[test]
fn a_client_that_completed_requests_is_not_evicted_by_a_flood() {
    a_polling_client_loses_nothing_to_a_flood(false);
}

/// Connections from one address beyond its burst of
/// new connections are answered `Busy` at once and closed, though places
/// are free; those within it are served.
#[test]
fn new_connections_beyond_the_rate_of_their_address_are_refused() {
    let (addr, _stop) = serve(ServerConfig {
        accept_rate_per_peer: Some(AcceptRate {
            per_second: 0.001,
            burst: 3,
        }),
        ..local()
    });
    let mut served: Vec<TcpStream> = (0..3).map(|_| connect(addr)).collect();
    let mut over = connect(addr);
    assert_eq!(try_read_head(&mut over), Some((0, 0, BUSY)));
    assert!(closed_by_server(&mut over));
    for (k, s) in served.iter_mut().enumerate() {
        assert_eq!(ask(s, k as u16), Some(0), "connection {k}");
    }
    // Another address has a burst of its own.
    let mut other = connect_from([127, 0, 0, 2], addr);
    assert_eq!(ask(&mut other, 5), Some(0));
}
