//! Soak test: a connection flood from one address and
//! abandoned `EXEC`s against a server that asks every peer, loopback too,
//! for the access token. A client that has presented the token and polls
//! the position loses no request while the flood runs; once the
//! abandoning clients have left, their requests stop at the next slice
//! boundary, so the server's CPU returns to idle within a second.
//!
//! The server runs in this process (an emulator whose per-cycle model is
//! always active, so every `EXEC` steps every cycle and never ends by
//! itself); its CPU is read from `/proc/self/stat` (the client threads
//! sleep or have ended while it is measured). Bounded: about 10 s.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use bytes::{Bytes, BytesMut};
use emulator::{Emulator, EmulatorService};
use tc_module::{AlwaysStepped, CycleTime, AXES};
use tc_request::{Reply, Request};
use uoi::tcp::{AccessPolicy, AccessToken, BlockingClient, ClientOptions, ServerConfig};
use uoi::wire::encode_request;

mod common;
use common::{loopback, TestServer};

/// How long the flood and the abandoned `EXEC`s run.
const SOAK: Duration = Duration::from_secs(6);
/// Clients that start an endless `EXEC` and leave, again and again.
const ABANDONERS: usize = 8;
/// Connections the flood holds open at once (more than the places).
const FLOOD_HELD: usize = 64;
/// The token every peer must present.
const TOKEN: &str = "soak-token-0123456789abcdef";
/// Most CPU the idle server may take, in seconds per second: the poller's
/// request every 100 ms and the watchdog, far below one busy core.
const IDLE_CPU: f64 = 0.25;

fn token() -> AccessToken {
    AccessToken::new(TOKEN).expect("token")
}

/// CPU time this process has used (user and system).
fn cpu_time() -> Duration {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("stat");
    // The fields after the command name (which is in parentheses).
    let rest = &stat[stat.rfind(')').expect("comm") + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15, here 11 and 12.
    let ticks: u64 = f[11].parse::<u64>().unwrap() + f[12].parse::<u64>().unwrap();
    // Linux reports them in USER_HZ, 100 per second.
    Duration::from_millis(ticks * 10)
}

/// Polls the position every 100 ms until `stop`: (answered, lost).
fn poller(addr: SocketAddr, stop: &AtomicBool) -> (usize, Vec<String>) {
    let opts = ClientOptions {
        token: Some(token()),
        ..ClientOptions::default()
    };
    let mut c = BlockingClient::connect_with(&addr.to_string(), &opts).expect("poller connects");
    let (mut answered, mut lost) = (0, Vec::new());
    while !stop.load(Ordering::Relaxed) {
        match c.call(&Request::Pos.to_wire()) {
            Ok(a) => match Reply::from_wire(Request::Pos.wire_op(), &a) {
                Some(Reply::Pos(_)) => answered += 1,
                other => lost.push(format!("{other:?}")),
            },
            Err(e) => {
                lost.push(e.to_string());
                match BlockingClient::connect_with(&addr.to_string(), &opts) {
                    Ok(again) => c = again,
                    Err(e) => lost.push(format!("reconnect: {e}")),
                }
            }
        }
        thread::sleep(Duration::from_millis(100));
    }
    (answered, lost)
}

/// Opens connections from 127.0.0.2 as fast as it can, holding the last
/// [`FLOOD_HELD`] silent, until `stop`; how many it opened.
fn flood(addr: SocketAddr, stop: &AtomicBool) -> usize {
    let mut held = std::collections::VecDeque::new();
    let mut opened = 0;
    while !stop.load(Ordering::Relaxed) {
        let Ok(sock) = tokio::net::TcpSocket::new_v4() else {
            continue;
        };
        if sock.bind(SocketAddr::from(([127, 0, 0, 2], 0))).is_err() {
            continue;
        }
        let std_sock = match socket_connect(sock, addr) {
            Some(s) => s,
            None => continue,
        };
        opened += 1;
        held.push_back(std_sock);
        if held.len() > FLOOD_HELD {
            held.pop_front();
        }
    }
    opened
}

/// Connects a bound socket, blocking.
fn socket_connect(sock: tokio::net::TcpSocket, addr: SocketAddr) -> Option<TcpStream> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()
        .ok()?;
    let s = rt.block_on(sock.connect(addr)).ok()?;
    s.into_std().ok()
}

/// A frame of `req` with id `id`.
fn frame(id: u32, req: &uoi::wire::Request) -> Vec<u8> {
    let mut f = BytesMut::new();
    encode_request(id, req, &mut f);
    f.to_vec()
}

/// Presents the token, starts an endless `EXEC`, waits a moment and
/// leaves without its answer; again and again until `stop`. How many it
/// abandoned.
fn abandoner(addr: SocketAddr, stop: &AtomicBool) -> usize {
    let hello = frame(
        1,
        &uoi::wire::Request::Hello(Bytes::from_static(TOKEN.as_bytes())),
    );
    let exec = frame(2, &Request::Exec(Some(u64::MAX - 1)).to_wire());
    let mut abandoned = 0;
    while !stop.load(Ordering::Relaxed) {
        let Ok(mut s) = TcpStream::connect(addr) else {
            continue;
        };
        s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        let mut answer = [0u8; 16];
        if s.write_all(&hello).is_err() || s.read_exact(&mut answer).is_err() {
            continue;
        }
        if answer[12..16] != [0; 4] {
            // Refused (no place now): try again.
            thread::sleep(Duration::from_millis(50));
            continue;
        }
        s.write_all(&exec).expect("EXEC sent");
        thread::sleep(Duration::from_millis(400));
        abandoned += 1;
        drop(s);
    }
    abandoned
}

#[test]
fn a_flood_and_abandoned_execs_cost_the_polling_client_nothing() {
    let emu = Emulator::with_extension([0.0; AXES], CycleTime::DEFAULT, AlwaysStepped);
    let cfg = ServerConfig {
        max_connections: 48,
        evict_after: Some(Duration::from_millis(100)),
        access: AccessPolicy {
            token: Some(token()),
            on_loopback: true,
        },
        ..loopback()
    };
    let server = TestServer::with(cfg, EmulatorService::with_emulator(emu));
    let addr = server.addr;

    let stop_poll = Arc::new(AtomicBool::new(false));
    let stop_load = Arc::new(AtomicBool::new(false));
    let polling = {
        let stop = Arc::clone(&stop_poll);
        thread::spawn(move || poller(addr, &stop))
    };
    let flooding = {
        let stop = Arc::clone(&stop_load);
        thread::spawn(move || flood(addr, &stop))
    };
    let abandoning: Vec<_> = (0..ABANDONERS)
        .map(|_| {
            let stop = Arc::clone(&stop_load);
            thread::spawn(move || abandoner(addr, &stop))
        })
        .collect();

    let t0 = Instant::now();
    let cpu0 = cpu_time();
    thread::sleep(SOAK);
    let busy = (cpu_time() - cpu0).as_secs_f64() / t0.elapsed().as_secs_f64();

    // The abandoning clients and the flood leave.
    stop_load.store(true, Ordering::Relaxed);
    let abandoned: usize = abandoning.into_iter().map(|t| t.join().unwrap()).sum();
    let opened = flooding.join().unwrap();
    // Within a second of their leaving, the server is idle: over the next
    // second it takes a small part of one core.
    thread::sleep(Duration::from_secs(1));
    let (t1, cpu1) = (Instant::now(), cpu_time());
    thread::sleep(Duration::from_secs(1));
    let idle = (cpu_time() - cpu1).as_secs_f64() / t1.elapsed().as_secs_f64();

    stop_poll.store(true, Ordering::Relaxed);
    let (answered, lost) = polling.join().unwrap();
    eprintln!(
        "soak: {opened} flood connections, {abandoned} abandoned EXECs, \
         {answered} polls answered, CPU {busy:.2} under load, {idle:.2} after"
    );
    assert!(
        lost.is_empty(),
        "the polling client lost requests: {lost:?}"
    );
    assert!(answered > 0);
    assert!(abandoned >= ABANDONERS, "only {abandoned} EXECs abandoned");
    assert!(opened > FLOOD_HELD, "the flood opened only {opened}");
    assert!(
        idle < IDLE_CPU,
        "CPU {idle:.2} s/s a second after the abandoning clients left (under load {busy:.2})"
    );
}
