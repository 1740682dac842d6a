//! The server's connection handling with a trivial handler: answers in
//! order, batches only over complete requests, idle, write-timeout and
//! shutdown closes, limits per peer, the access token, client timeouts.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use bytes::{Bytes, BytesMut};
use common::{
    connect, connect_from, flood_until_blocked, is_closed, local, read_answer, read_frame,
    read_head, serve, Index,
};
use uoi::tcp::{
    AccessPolicy, AccessToken, Client, ClientError, ClientOptions, Server, ServerConfig, Waited,
};
use uoi::wire::{encode_request, ProtocolError, Request};
use uoi::{ObjectAddress, Value, ValueType};

#[test]
fn pipelined_requests_are_answered_in_order() {
    let (addr, _stop) = serve(local());
    let mut s = connect(addr);
    let burst: Vec<u8> = (1..=200).flat_map(read_frame).collect();
    s.write_all(&burst).expect("write");
    for k in 1..=200 {
        assert_eq!(read_answer(&mut s), (k, k as i32));
    }
}

/// The answer to a complete request is not held back for a request of
/// which only a part has arrived.
#[test]
fn a_partial_next_request_does_not_hold_back_the_answer() {
    let (addr, _stop) = serve(local());
    let mut s = connect(addr);
    let second = read_frame(2);
    let mut first = read_frame(1);
    first.extend_from_slice(&second[..10]);
    s.write_all(&first).expect("write");
    assert_eq!(read_answer(&mut s), (1, 1));
    s.write_all(&second[10..]).expect("write");
    assert_eq!(read_answer(&mut s), (2, 2));
}

#[test]
fn a_silent_connection_is_closed_an_active_one_answered() {
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_millis(200),
        ..local()
    });
    let mut silent = connect(addr);
    // Blocks until the server closes the connection.
    assert!(is_closed(&mut silent));
    let mut s = connect(addr);
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_answer(&mut s), (3, 3));
}

#[test]
fn shutdown_closes_a_waiting_connection() {
    let (addr, stop) = serve(local());
    let mut s = connect(addr);
    s.write_all(&read_frame(4)).expect("write");
    assert_eq!(read_answer(&mut s), (4, 4));
    drop(stop);
    assert!(is_closed(&mut s));
}

#[test]
fn a_client_that_never_reads_is_closed_when_idle_and_frees_its_place() {
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_millis(300),
        max_connections: 1,
        // Only the idle timeout may free the place.
        evict_after: None,
        ..local()
    });
    // Pipeline requests and never read an answer: the server's writes
    // block once the socket buffers are full.
    let mut hog = connect(addr);
    flood_until_blocked(&mut hog);
    // The blocked connection is closed by the idle timeout: a new client
    // gets in (a guard of 60 s, not a timed assertion).
    let deadline = std::time::Instant::now() + Duration::from_secs(60);
    loop {
        let mut c = connect(addr);
        c.write_all(&read_frame(5)).expect("write");
        let mut head = [0u8; 16];
        c.read_exact(&mut head).expect("an answer");
        let status = u32::from_le_bytes([head[12], head[13], head[14], head[15]]);
        if status == 0 {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the blocked client kept its place"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// A frame whose first two bytes arrive before a look
/// of the watchdog and the rest after it is answered (the read is not
/// cancelled halfway through the length prefix).
#[test]
fn a_frame_split_across_a_watchdog_look_is_answered() {
    // Looks every 250 ms; the pause below spans two of them and stays
    // well under the idle timeout.
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_secs(2),
        ..local()
    });
    let mut s = connect(addr);
    let f = read_frame(6);
    s.write_all(&f[..2]).expect("write");
    std::thread::sleep(Duration::from_millis(600));
    s.write_all(&f[2..]).expect("write");
    assert_eq!(read_answer(&mut s), (6, 6));
}

/// A READ followed by two bytes of the next frame is
/// answered at once, not when the next frame is complete.
#[test]
fn a_read_and_two_bytes_of_the_next_frame_get_the_answer_at_once() {
    let (addr, _stop) = serve(local());
    let mut s = connect(addr);
    let mut bytes = read_frame(1);
    bytes.extend_from_slice(&read_frame(2)[..2]);
    s.write_all(&bytes).expect("write");
    // The 60 s read timeout of `connect` is only the hang guard.
    assert_eq!(read_answer(&mut s), (1, 1));
}

/// A client that floods requests and then takes its
/// answers a few bytes at a time cannot keep its place: the answers
/// waiting for it must leave within the write timeout. The idle timeout
/// is far away, so only the write timeout can free the place.
#[test]
fn a_client_that_takes_its_answers_a_trickle_at_a_time_loses_its_place() {
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_secs(3600),
        write_timeout: Duration::from_millis(500),
        max_connections: 1,
        evict_after: None,
        ..local()
    });
    let mut hog = connect(addr);
    flood_until_blocked(&mut hog);
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let stopped = std::sync::Arc::clone(&stop);
    let trickle = std::thread::spawn(move || {
        let mut b = [0u8; 64];
        while !stopped.load(std::sync::atomic::Ordering::Relaxed) {
            if matches!(hog.read(&mut b), Ok(0) | Err(_)) {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    });
    // A guard of 60 s, not a timed assertion.
    let deadline = std::time::Instant::now() + Duration::from_secs(60);
    loop {
        let mut c = connect(addr);
        c.write_all(&read_frame(5)).expect("write");
        if read_head(&mut c).2 == 0 {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the trickling client kept its place"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    trickle.join().expect("trickle");
}

/// Clients from one address that hold connections
/// without using them cannot lock out another host. 127.0.0.1 plays the
/// greedy host, 127.0.0.2 the other one (loopback counted per address as
/// a remote host would be; eviction off, so the limit alone acts).
#[test]
fn one_peer_address_cannot_take_every_place() {
    let (addr, _stop) = serve(ServerConfig {
        max_connections: 6,
        max_connections_per_peer: 3,
        per_peer_limit_on_loopback: true,
        evict_after: None,
        ..local()
    });
    // Accepted in order: the first three are served, the rest refused.
    let mut hogs: Vec<TcpStream> = (0..6).map(|_| connect(addr)).collect();
    for (k, hog) in hogs.iter_mut().enumerate().skip(3) {
        assert_eq!(read_head(hog), (0, 0, 0xE000_0007), "connection {k}");
        assert!(is_closed(hog));
    }
    for (k, hog) in hogs.iter_mut().enumerate().take(3) {
        hog.write_all(&read_frame(k as u16)).expect("write");
        assert_eq!(read_answer(hog), (k as u32, k as i32));
    }
    let mut other = connect_from([127, 0, 0, 2], addr);
    other.write_all(&read_frame(9)).expect("write");
    assert_eq!(read_answer(&mut other), (9, 9));
}

fn token() -> AccessToken {
    AccessToken::new("0123456789abcdef0123456789abcdef").expect("token")
}

fn hello_frame(id: u32, token: &[u8]) -> Vec<u8> {
    let mut f = BytesMut::new();
    encode_request(id, &Request::Hello(Bytes::copy_from_slice(token)), &mut f);
    f.to_vec()
}

/// A server that asks every peer, loopback too, for the token.
fn guarded() -> ServerConfig {
    ServerConfig {
        access: AccessPolicy {
            token: Some(token()),
            on_loopback: true,
        },
        ..local()
    }
}

const UNAUTHORIZED: u32 = 0xE000_0008;
const HELLO: u8 = 0x03;

/// Before a valid HELLO, every frame is answered
/// `Unauthorized` and the connection closed.
#[test]
fn a_peer_that_must_present_the_token_gets_nothing_else_before_it() {
    let (addr, _stop) = serve(guarded());
    let mut s = connect(addr);
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_head(&mut s), (3, 0x01, UNAUTHORIZED));
    assert!(is_closed(&mut s));

    let mut s = connect(addr);
    s.write_all(&hello_frame(1, b"0123456789abcdef0123456789abcdeX"))
        .expect("write");
    assert_eq!(read_head(&mut s), (1, HELLO, UNAUTHORIZED));
    assert!(is_closed(&mut s));

    let mut s = connect(addr);
    s.write_all(&hello_frame(1, token().as_bytes()))
        .expect("write");
    assert_eq!(read_head(&mut s), (1, HELLO, 0));
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_answer(&mut s), (3, 3));
}

/// The client presents its token on connecting; without one its first
/// call is refused.
#[test]
fn the_client_presents_its_token() {
    let (addr, _stop) = serve(guarded());
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let obj = ObjectAddress::new(7, 0, 4, 0);
    rt.block_on(async {
        let opts = ClientOptions {
            token: Some(token()),
            ..ClientOptions::default()
        };
        let mut c = Client::connect_with(addr, &opts).await.expect("connect");
        assert_eq!(
            c.read(obj, ValueType::I32).await.expect("read"),
            Value::I32(4)
        );
        let mut c = Client::connect(addr).await.expect("connect");
        let err = c.read(obj, ValueType::I32).await.expect_err("refused");
        assert!(
            matches!(err, ClientError::Protocol(ProtocolError::Unauthorized)),
            "{err}"
        );
    });
}

/// Loopback peers need no token unless configured; one that presents a
/// wrong token anyway is told so.
#[test]
fn loopback_peers_need_no_token_unless_asked() {
    let (addr, _stop) = serve(ServerConfig {
        access: AccessPolicy {
            token: Some(token()),
            on_loopback: false,
        },
        ..local()
    });
    let mut s = connect(addr);
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_answer(&mut s), (3, 3));
    s.write_all(&hello_frame(2, token().as_bytes()))
        .expect("write");
    assert_eq!(read_head(&mut s), (2, HELLO, 0));
    s.write_all(&hello_frame(3, b"0123456789abcdef0123456789abcdeX"))
        .expect("write");
    assert_eq!(read_head(&mut s), (3, HELLO, UNAUTHORIZED));
    assert!(is_closed(&mut s));
}

#[test]
fn a_remote_listener_needs_a_token() {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let cfg = ServerConfig {
        listen: "0.0.0.0:0".parse().expect("addr"),
        allow_remote: true,
        ..ServerConfig::default()
    };
    let err = rt
        .block_on(Server::bind(cfg, Index))
        .err()
        .expect("refused");
    assert_eq!(err.kind(), std::io::ErrorKind::PermissionDenied);
    assert!(err.to_string().contains("access token"), "{err}");
}

/// A server that accepts but never answers, and one
/// whose backlog is full, make the client give up with an error that
/// names the address and the time waited.
#[test]
fn the_client_gives_up_on_a_silent_or_full_server() {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let opts = ClientOptions {
        connect_timeout: Duration::from_millis(300),
        request_timeout: Duration::from_millis(300),
        token: None,
    };
    rt.block_on(async {
        // Never accepts: the kernel completes the connection, nobody reads.
        let silent = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
        let addr = silent.local_addr().expect("addr");
        let mut c = Client::connect_with(addr, &opts).await.expect("connect");
        let err = c
            .read(ObjectAddress::new(7, 0, 1, 0), ValueType::I32)
            .await
            .expect_err("no answer");
        assert!(
            matches!(
                err,
                ClientError::TimedOut {
                    waited: Waited::Answer,
                    ..
                }
            ),
            "{err}"
        );
        assert_eq!(
            err.to_string(),
            format!("no answer from {addr} within 0.3 s")
        );
        // Later calls on the connection fail at once.
        assert!(c
            .read(ObjectAddress::new(7, 0, 1, 0), ValueType::I32)
            .await
            .is_err());

        // A backlog of 0 holds one connection; the next handshake waits.
        let sock = tokio::net::TcpSocket::new_v4().expect("socket");
        sock.bind("127.0.0.1:0".parse().expect("addr"))
            .expect("bind");
        let full = sock.listen(0).expect("listen");
        let addr = full.local_addr().expect("addr");
        let _first = std::net::TcpStream::connect(addr).expect("first");
        let err = Client::connect_with(addr, &opts)
            .await
            .err()
            .expect("no connection");
        assert!(
            matches!(
                err,
                ClientError::TimedOut {
                    waited: Waited::Connect,
                    ..
                }
            ),
            "{err}"
        );
        assert_eq!(
            err.to_string(),
            format!("no connection to {addr} within 0.3 s")
        );
    });
}

/// This machine's address on its first non-loopback interface, if it
/// has one (a UDP socket "connected" to a documentation address sends
/// nothing, but picks the source address a route would use).
fn non_loopback_address() -> Option<std::net::IpAddr> {
    let s = std::net::UdpSocket::bind("0.0.0.0:0").ok()?;
    s.connect("192.0.2.1:9").ok()?;
    let ip = s.local_addr().ok()?.ip();
    (!ip.is_loopback() && !ip.is_unspecified()).then_some(ip)
}

/// With a real non-loopback peer where the machine
/// has a network interface: a server on 0.0.0.0 asks a connection to its
/// network address for the token, not one over loopback.
#[test]
fn a_peer_on_the_network_must_present_the_token() {
    let Some(ip) = non_loopback_address() else {
        eprintln!("no non-loopback interface: skipped");
        return;
    };
    let (addr, _stop) = serve(ServerConfig {
        listen: "0.0.0.0:0".parse().expect("addr"),
        allow_remote: true,
        access: AccessPolicy {
            token: Some(token()),
            on_loopback: false,
        },
        ..ServerConfig::default()
    });
    let remote = SocketAddr::new(ip, addr.port());
    let mut s = connect(remote);
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_head(&mut s), (3, 0x01, UNAUTHORIZED));
    let mut s = connect(remote);
    s.write_all(&hello_frame(1, token().as_bytes()))
        .expect("write");
    assert_eq!(read_head(&mut s), (1, HELLO, 0));
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_answer(&mut s), (3, 3));
    let mut s = connect(SocketAddr::from(([127, 0, 0, 1], addr.port())));
    s.write_all(&read_frame(4)).expect("write");
    assert_eq!(read_answer(&mut s), (4, 4));
}
