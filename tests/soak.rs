//! Soak test: 64 clients on loopback against the real `serve`
//! binary for a bounded time, mixing valid requests, malformed frames,
//! clients that never read their answers, huge `EXEC`s and spooler floods
//! (on the shared emulator and in conformance sessions). Afterwards a fresh
//! client is answered at once, the server's peak memory stays within the
//! stated bound, and the shared emulator holds exactly what the valid
//! requests wrote.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use bytes::BytesMut;
use tc_request::text::parse_request;
use tc_request::{Reply, Request};
use uoi::tcp::BlockingClient;
use uoi::wire::{encode_request, Answer};
use uoi::{AccessError, Value};

mod common;
use common::ServeProcess;

/// How long the mixed load runs.
const SOAK: Duration = Duration::from_secs(15);
/// Clients of each kind (5 kinds → 65 connections at most at once, plus
/// reconnects).
const PER_KIND: usize = 13;
/// Spooler capacity of the server under test.
const CAPACITY: usize = 20_000;
/// Peak resident memory the server may reach (VmHWM): the shared spooler
/// and 16 sessions' spoolers full (17 × 20,000 elements × ~250 B = 85 MB),
/// 65 connections' buffers (~13 MB) and the runtime, with room to spare.
const RSS_BOUND_KB: u64 = 200 * 1024;

fn start_server(dir: &std::path::Path) -> ServeProcess {
    let cfg = dir.join("soak.toml");
    std::fs::write(
        &cfg,
        format!(
            "listen = \"127.0.0.1:0\"\nidle_timeout_s = 2\nwrite_timeout_s = 1\n\
             spool_capacity = {CAPACITY}\n"
        ),
    )
    .unwrap();
    let cfg = cfg.to_str().expect("utf-8 path");
    ServeProcess::start(&["--config", cfg], &[("RUST_LOG", "warn,uoi=info")])
}

fn wire(text: &str) -> uoi::wire::Request {
    parse_request(text).expect(text).to_wire()
}

/// A valid client: group `g` of the shared emulator is its own; it writes
/// WKZINDEX and RADIUS over and over and reads them back. Returns the last
/// values written and how many rounds it made.
fn valid(addr: &str, g: usize, stop: &AtomicBool) -> (i32, f64, usize) {
    let mut c = BlockingClient::connect(addr).expect("valid client connects");
    let mut rounds = 0;
    let (mut tool, mut radius) = (0, 0.0);
    while !stop.load(Ordering::Relaxed) {
        tool = ((g * 7 + rounds) % 1024) as i32;
        radius = g as f64 + rounds as f64 * 0.001;
        let ans = c
            .pipeline(&[
                wire(&format!("W 1300/1/{g}/8 i {tool}")),
                wire(&format!("W 1300/1/{g}/6 d {radius}")),
                wire(&format!("R 1300/1/{g}/6 d")),
                wire(&format!("R 1300/1/{g}/8 i")),
            ])
            .expect("valid client answered");
        assert_eq!(ans[0], Answer::Ok);
        assert_eq!(ans[1], Answer::Ok);
        assert_eq!(ans[2], Answer::Value(Value::F64(radius)));
        assert_eq!(ans[3], Answer::Value(Value::I32(tool)));
        rounds += 1;
        thread::sleep(Duration::from_millis(5));
    }
    (tool, radius, rounds)
}

/// Malformed frames of many kinds, reconnecting whenever the server
/// closes.
fn malformed(addr: &str, seed: u64, stop: &AtomicBool) {
    let mut x = seed | 1;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    while !stop.load(Ordering::Relaxed) {
        let Ok(mut s) = TcpStream::connect(addr) else {
            continue;
        };
        let _ = s.set_read_timeout(Some(Duration::from_millis(50)));
        for _ in 0..20 {
            let bytes: Vec<u8> = match next() % 4 {
                // Random bytes.
                0 => (0..next() % 300).map(|_| next() as u8).collect(),
                // A length prefix over the limit.
                1 => u32::MAX.to_le_bytes().to_vec(),
                // A valid prefix and header, then a wrong magic.
                2 => [&16u32.to_le_bytes()[..], b"XX\x01\x01", &[0; 12]].concat(),
                // A READ frame with one byte flipped.
                _ => {
                    let mut b = BytesMut::new();
                    encode_request(7, &wire("R 1300/0/3/0 i"), &mut b);
                    let i = (next() as usize) % b.len();
                    b[i] ^= 1 << (next() % 8);
                    b.to_vec()
                }
            };
            if s.write_all(&bytes).is_err() {
                break;
            }
            let mut sink = [0u8; 4096];
            let _ = s.read(&mut sink);
        }
    }
}

/// Sends pipelines of requests and never reads an answer; the server must
/// drop it (write timeout) while serving the others.
fn never_reads(addr: &str, stop: &AtomicBool) {
    let mut frames = BytesMut::new();
    for id in 0..4096 {
        encode_request(id, &wire("R 1300/0/20/0 d"), &mut frames);
    }
    while !stop.load(Ordering::Relaxed) {
        let Ok(mut s) = TcpStream::connect(addr) else {
            continue;
        };
        let _ = s.set_write_timeout(Some(Duration::from_millis(200)));
        while !stop.load(Ordering::Relaxed) && s.write_all(&frames).is_ok() {}
        let _ = s.shutdown(Shutdown::Both);
    }
}

/// A TC op's answer must be ok, `Full` or `Range`, nothing else.
fn ok_or_refused(a: &Answer) {
    // Every TC op checked here (MOTION, EXEC) answers an empty payload.
    let reply = Reply::from_wire(Request::Exec(None).wire_op(), a);
    let allowed = [
        Reply::Ok,
        Reply::Access(AccessError::Full),
        Reply::Access(AccessError::Range),
    ];
    assert!(
        reply.as_ref().is_some_and(|r| allowed.contains(r)),
        "unexpected answer {a:?}"
    );
}

/// Floods a spooler with lines, `in_session` in a conformance session of
/// its own (else on the shared emulator), with a huge `EXEC` now and then.
fn flood(addr: &str, in_session: bool, stop: &AtomicBool) {
    let mut c = BlockingClient::connect(addr).expect("flooder connects");
    if in_session {
        let setup = Request::Setup {
            start: [0.0; 8],
            cycle_s: 1e-3,
            spool_capacity: CAPACITY as u64,
        };
        let ans = c.call(&setup.to_wire()).expect("setup answered");
        // Sessions are limited; a flooder without one floods the shared one.
        let reply = Reply::from_wire(setup.wire_op(), &ans).unwrap();
        assert!(matches!(
            reply,
            Reply::Ok | Reply::Access(AccessError::Full)
        ));
    }
    let lines: Vec<_> = (0..2000)
        .map(|k| wire(&format!("LIN X{} Y{} F60000", k % 7, k % 5)))
        .collect();
    let mut round = 0u64;
    while !stop.load(Ordering::Relaxed) {
        for a in c.pipeline(&lines).expect("flood answered") {
            ok_or_refused(&a);
        }
        round += 1;
        if round.is_multiple_of(8) {
            let exec = Request::Exec(Some(u64::MAX - 1)).to_wire();
            ok_or_refused(&c.call(&exec).expect("huge EXEC answered"));
        }
    }
}

/// Huge `EXEC`s and queue/position reads on the shared emulator.
fn huge_exec(addr: &str, stop: &AtomicBool) {
    let mut c = BlockingClient::connect(addr).expect("exec client connects");
    while !stop.load(Ordering::Relaxed) {
        for req in [
            Request::Exec(Some(u64::MAX - 1)),
            Request::Exec(None),
            Request::Exec(Some(4_000_000_000)),
        ] {
            ok_or_refused(&c.call(&req.to_wire()).expect("EXEC answered"));
        }
        let pos = c.call(&Request::Pos.to_wire()).expect("POS answered");
        match Reply::from_wire(Request::Pos.wire_op(), &pos).unwrap() {
            Reply::Pos(p) => assert!(p.iter().all(|v| v.is_finite() && v.abs() <= 2e9)),
            other => panic!("POS answered {other:?}"),
        }
    }
}

/// What one client thread does, given the address and the stop flag.
type Role = Box<dyn FnOnce(&str, &AtomicBool) + Send>;

/// Peak resident memory of `pid` in KiB.
fn peak_rss_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(0)
}

#[test]
fn sixty_four_clients_of_every_kind_cannot_hurt_the_server() {
    let dir = std::env::temp_dir().join(format!("addipos-soak-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let server = start_server(&dir);
    let stop = Arc::new(AtomicBool::new(false));
    let addr = server.addr.clone();
    let spawn = |f: Role| {
        let (addr, stop) = (addr.clone(), Arc::clone(&stop));
        thread::spawn(move || f(&addr, &stop))
    };
    let mut others = Vec::new();
    for k in 0..PER_KIND {
        others.push(spawn(Box::new(move |a, s| malformed(a, k as u64 + 1, s))));
        others.push(spawn(Box::new(never_reads)));
        others.push(spawn(Box::new(move |a, s| flood(a, k % 2 == 0, s))));
        others.push(spawn(Box::new(huge_exec)));
    }
    let valid: Vec<_> = (1..=PER_KIND)
        .map(|g| {
            let (addr, stop) = (addr.clone(), Arc::clone(&stop));
            thread::spawn(move || valid(&addr, g, &stop))
        })
        .collect();
    thread::sleep(SOAK);
    stop.store(true, Ordering::Relaxed);
    let written: Vec<_> = valid.into_iter().map(|h| h.join().unwrap()).collect();
    for h in others {
        h.join().unwrap();
    }

    // A fresh client is answered at once (best of five round trips, so a
    // single scheduling hiccup of the machine does not count).
    let mut fresh = BlockingClient::connect(&server.addr).expect("fresh client connects");
    let best = (0..5)
        .map(|_| {
            let t = Instant::now();
            let ans = fresh.call(&wire("R 1300/0/3/0 i")).expect("answered");
            assert_eq!(ans, Answer::Value(Value::I32(17)));
            t.elapsed()
        })
        .min()
        .unwrap();
    println!("fresh client round trip after the soak: {best:?}");
    assert!(
        best < Duration::from_millis(100),
        "fresh client waited {best:?}"
    );

    // The shared emulator holds what the valid requests made it.
    for (g, (tool, radius, rounds)) in (1..).zip(&written) {
        assert!(*rounds >= 10, "valid client {g} made only {rounds} rounds");
        let ans = fresh
            .pipeline(&[
                wire(&format!("R 1300/1/{g}/8 i")),
                wire(&format!("R 1300/1/{g}/6 d")),
            ])
            .unwrap();
        assert_eq!(ans[0], Answer::Value(Value::I32(*tool)), "group {g}");
        assert_eq!(ans[1], Answer::Value(Value::F64(*radius)), "group {g}");
    }
    let rounds: usize = written.iter().map(|w| w.2).sum();
    let peak = peak_rss_kb(server.id());
    println!(
        "valid rounds: {rounds}; server peak RSS: {} MB",
        peak / 1024
    );
    assert!(peak > 0 && peak < RSS_BOUND_KB, "server peak RSS {peak} kB");
    let _ = std::fs::remove_dir_all(&dir);
}
