//! The object server over TCP: the corpus on the wire, many clients at once,
//! malformed input, limits and shutdown. Every test binds 127.0.0.1:0.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::time::Duration;

use bytes::BytesMut;
use emulator::EmulatorService;
use tc_objects::{OtcObject, TcObject};
use tc_request::{Reply, Request as TcRequest};
use uoi::tcp::{BlockingClient, Client, ClientError, Server, ServerConfig};
use uoi::wire::{encode_request, Answer, Op, ProtocolError, Request, PREFIX_LEN};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

mod common;
use common::{replay_remote, session, TestServer};

fn corpus() -> Vec<trace::Trace> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("traces");
    trace::load_corpus(&dir).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn whole_corpus_passes_over_tcp() {
    let server = TestServer::local();
    let mut target = session(&server.addr.to_string());
    let traces = corpus();
    assert!(traces.len() >= 40);
    let mut failed = Vec::new();
    for t in &traces {
        failed.extend(replay_remote(t, &mut target).iter().map(|m| m.to_string()));
    }
    assert!(failed.is_empty(), "over TCP:\n{}", failed.join("\n"));
}

/// A conformance session whose connection is lost is not carried on by a
/// new connection (which would be on the shared emulator); the next set-up
/// connects again.
#[test]
fn a_lost_session_is_not_carried_on_by_a_new_connection() {
    use tc_request::Runner;
    let server = TestServer::local();
    let mut s = session(&server.addr.to_string());
    s.set_up([0.0; tc_request::AXES], 0.001, 64).expect("setup");
    assert_eq!(s.run(&TcRequest::Queue).expect("queue"), Reply::Queue(0));
    s.wire().disconnect();
    let e = s.run(&TcRequest::Queue).unwrap_err();
    assert_eq!(
        e.to_string(),
        "(connection: the session's connection was lost)"
    );
    assert!(s.take_spooled().is_err());
    s.set_up([0.0; tc_request::AXES], 0.001, 64)
        .expect("setup again");
    assert_eq!(s.run(&TcRequest::Queue).expect("queue"), Reply::Queue(0));
    assert_eq!(s.wire().connections(), 2);
}

#[test]
fn several_clients_on_different_groups_at_once() {
    let server = TestServer::local();
    let threads: Vec<_> = (1..=8u16)
        .map(|g| {
            let a = server.addr.to_string();
            std::thread::spawn(move || {
                let mut c = BlockingClient::connect(&a).expect("connect");
                for k in 0..200 {
                    let wkz = k % 1024;
                    c.write(TcObject::WkzIndex.of(g), Value::I32(wkz))
                        .expect("WKZINDEX");
                    let r = f64::from(g) * 1000.0 + f64::from(k);
                    c.write(TcObject::Radius.of(g), Value::F64(r))
                        .expect("RADIUS");
                    assert_eq!(
                        c.read(TcObject::WkzIndex.of(g), ValueType::I32)
                            .expect("read"),
                        Value::I32(wkz)
                    );
                    assert_eq!(
                        c.read(TcObject::Radius.of(g), ValueType::F64)
                            .expect("read"),
                        Value::F64(r)
                    );
                }
            })
        })
        .collect();
    for t in threads {
        t.join().expect("client thread");
    }
}

/// A raw connection for malformed input.
fn raw(server: &TestServer) -> TcpStream {
    let s = TcpStream::connect(server.addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10)))
        .expect("timeout");
    s
}

/// Reads one answer frame: (request id, op, status).
fn read_answer(s: &mut TcpStream) -> Option<(u32, u8, u32)> {
    let mut pre = [0u8; 4];
    s.read_exact(&mut pre).ok()?;
    let mut body = vec![0u8; u32::from_le_bytes(pre) as usize];
    s.read_exact(&mut body).ok()?;
    let id = u32::from_le_bytes(body[4..8].try_into().ok()?);
    let status = u32::from_le_bytes(body[8..12].try_into().ok()?);
    Some((id, body[3], status))
}

fn frame(id: u32, req: &Request) -> Vec<u8> {
    let mut out = BytesMut::new();
    encode_request(id, req, &mut out);
    out.to_vec()
}

/// A TC request's reply over a blocking client.
fn call(c: &mut BlockingClient, req: &TcRequest) -> Result<Reply, ClientError> {
    let ans = c.call(&req.to_wire())?;
    Reply::from_wire(req.wire_op(), &ans).ok_or_else(|| ClientError::Unexpected(format!("{ans:?}")))
}

fn is_closed(s: &mut TcpStream) -> bool {
    let mut b = [0u8; 1];
    matches!(s.read(&mut b), Ok(0) | Err(_))
}

/// Everything a malformed frame could have changed, read over a good connection.
fn snapshot(c: &mut BlockingClient) -> Vec<String> {
    let mut out = Vec::new();
    for a in [
        TcObject::AxisNr.sub(0),
        TcObject::AxisNr.sub(1),
        TcObject::AxisNr.sub(2),
        TcObject::TcPlane.address(),
        TcObject::Error.of(1),
        TcObject::Status.of(1),
        TcObject::WkzIndex.of(1),
        TcObject::XAxis.of(1),
    ] {
        out.push(format!(
            "{:?}",
            c.read(a, ValueType::I32).map_err(|e| e.to_string())
        ));
    }
    for a in [
        TcObject::RotAngle.address(),
        TcObject::RotCenterX.address(),
        TcObject::Radius.of(1),
        TcObject::WkzLen.of(1),
    ] {
        out.push(format!(
            "{:?}",
            c.read(a, ValueType::F64).map_err(|e| e.to_string())
        ));
    }
    out.push(format!("{:?}", call(c, &TcRequest::Pos)));
    out.push(format!("{:?}", call(c, &TcRequest::Queue)));
    out
}

#[test]
fn malformed_input_is_answered_or_closed_and_changes_nothing() {
    let server = TestServer::local();
    let mut good = BlockingClient::connect(&server.addr.to_string()).expect("connect");
    good.write(TcObject::Radius.of(1), Value::F64(2.5))
        .expect("setup");
    let before = snapshot(&mut good);
    let pos_req = frame(
        7,
        &Request::Read(TcObject::TcPlane.address(), ValueType::I32),
    );

    // Truncated header: a 5-byte frame. Answered, connection goes on.
    let mut s = raw(&server);
    s.write_all(&[5, 0, 0, 0, b'U', b'O', 1, 1, 0])
        .expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((0, 0, ProtocolError::FrameTooShort.code()))
    );
    s.write_all(&pos_req).expect("write");
    assert_eq!(read_answer(&mut s), Some((7, Op::Read.code(), 0)));

    // Length 0.
    let mut s = raw(&server);
    s.write_all(&[0, 0, 0, 0]).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((0, 0, ProtocolError::FrameTooShort.code()))
    );

    // Length 10 MB: answered, then closed without reading 10 MB.
    let mut s = raw(&server);
    s.write_all(&(10u32 * 1024 * 1024).to_le_bytes())
        .expect("write");
    s.write_all(&[0u8; 1000]).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((0, 0, ProtocolError::FrameTooLarge.code()))
    );
    assert!(is_closed(&mut s));

    // Wrong magic: answered with the request id, connection goes on.
    let mut s = raw(&server);
    let mut f = frame(
        9,
        &Request::Write(TcObject::TcPlane.address(), Value::I32(18)),
    );
    f[PREFIX_LEN] = b'X';
    s.write_all(&f).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((9, Op::Write.code(), ProtocolError::BadMagic.code()))
    );
    // Unknown version and unknown op.
    let mut f = frame(
        10,
        &Request::Write(TcObject::TcPlane.address(), Value::I32(18)),
    );
    f[PREFIX_LEN + 2] = 2;
    s.write_all(&f).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((
            10,
            Op::Write.code(),
            ProtocolError::UnsupportedVersion.code()
        ))
    );
    let mut f = frame(
        11,
        &Request::Write(TcObject::TcPlane.address(), Value::I32(18)),
    );
    f[PREFIX_LEN + 3] = 0x7e;
    s.write_all(&f).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((11, 0x7e, ProtocolError::UnknownOp.code()))
    );
    // A payload that does not fit its op.
    let mut f = frame(
        12,
        &Request::Write(TcObject::TcPlane.address(), Value::I32(18)),
    );
    f.pop();
    let n = (f.len() - PREFIX_LEN) as u32;
    f[..4].copy_from_slice(&n.to_le_bytes());
    s.write_all(&f).expect("write");
    assert_eq!(
        read_answer(&mut s),
        Some((12, Op::Write.code(), ProtocolError::BadPayload.code()))
    );
    s.write_all(&pos_req).expect("write");
    assert_eq!(read_answer(&mut s), Some((7, Op::Read.code(), 0)));

    // Random bytes (deterministic): only error answers, or a close.
    let mut s = raw(&server);
    let mut x: u64 = 0x2545_F491_4F6C_DD1D;
    let junk: Vec<u8> = (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect();
    s.write_all(&junk).expect("write");
    let _ = s.shutdown(std::net::Shutdown::Write);
    while let Some((_, _, status)) = read_answer(&mut s) {
        assert_ne!(status, 0, "random bytes were taken as a request");
    }

    // Half a frame, then close.
    let mut s = raw(&server);
    s.write_all(&pos_req[..pos_req.len() / 2]).expect("write");
    drop(s);

    // The server still serves, and nothing changed.
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(snapshot(&mut good), before);
    let mut again = BlockingClient::connect(&server.addr.to_string()).expect("reconnect");
    assert_eq!(
        again
            .read(TcObject::TcPlane.address(), ValueType::I32)
            .expect("read"),
        Value::I32(17)
    );
}

#[test]
fn connection_limit_answers_busy() {
    let server = TestServer::start(ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        max_connections: 2,
        // Without eviction: the idle clients keep their places.
        evict_after: None,
        ..ServerConfig::default()
    });
    let mut a = BlockingClient::connect(&server.addr.to_string()).expect("a");
    let mut b = BlockingClient::connect(&server.addr.to_string()).expect("b");
    assert!(a.read(TcObject::TcPlane.address(), ValueType::I32).is_ok());
    assert!(b.read(TcObject::TcPlane.address(), ValueType::I32).is_ok());
    let mut c = raw(&server);
    assert_eq!(
        read_answer(&mut c),
        Some((0, 0, ProtocolError::Busy.code()))
    );
    assert!(is_closed(&mut c));
    drop(a);
    // The server notices the close and frees the place; a new client gets in.
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    loop {
        let mut d = BlockingClient::connect(&server.addr.to_string()).expect("d");
        if d.read(TcObject::TcPlane.address(), ValueType::I32).is_ok() {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the freed place was never reused"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn idle_connections_are_closed() {
    let server = TestServer::start(ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        idle_timeout: Duration::from_millis(300),
        ..ServerConfig::default()
    });
    let mut s = raw(&server);
    std::thread::sleep(Duration::from_millis(800));
    assert!(is_closed(&mut s));
}

#[test]
fn non_loopback_needs_allow_remote() {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("rt");
    let err = rt
        .block_on(Server::bind(
            ServerConfig {
                listen: "0.0.0.0:0".parse().expect("addr"),
                ..ServerConfig::default()
            },
            EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT),
        ))
        .err()
        .expect("refused");
    assert_eq!(err.kind(), std::io::ErrorKind::PermissionDenied);
}

#[test]
fn shutdown_closes_connections_and_returns() {
    let server = TestServer::local();
    let mut s = raw(&server);
    s.write_all(&frame(1, &TcRequest::Queue.to_wire()))
        .expect("write");
    assert_eq!(read_answer(&mut s).map(|a| a.2), Some(0));
    drop(server); // sends the stop and joins the server thread
    assert!(is_closed(&mut s));
}

/// A device number bus 1300 does not have (docs/decisions.md, decision
/// 522).
const NO_SUCH_DEVICE: u16 = 9;

/// Each client owns one object; every answer is known in advance whatever
/// the interleaving.
#[test]
fn two_hundred_clients_a_thousand_requests_each() {
    // All from 127.0.0.1: one peer address, allowed them all.
    let server = TestServer::start(ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        max_connections_per_peer: 256,
        ..ServerConfig::default()
    });
    let a = server.addr;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("rt");
    // Each object of a group, and whether it holds a double.
    type OfGroup = fn(u16) -> ObjectAddress;
    let objects: [(OfGroup, bool); 7] = [
        (|g| TcObject::Radius.of(g), true),
        (|g| TcObject::WkzLen.of(g), true),
        (|g| OtcObject::WearConst.of(g), true),
        (|g| OtcObject::ToolWearConst.of(g), true),
        (|g| OtcObject::ToolMaxInfeed.of(g), true),
        (|g| OtcObject::ToolTiltAngle.of(g), true),
        (|g| OtcObject::RadiusOffsetCommand.of(g), false),
    ];
    let work = async move {
        let mut tasks = tokio::task::JoinSet::new();
        for i in 0..200u16 {
            tasks.spawn(async move {
                let group = i / 7 + 1;
                let (of_group, is_d) = objects[usize::from(i % 7)];
                let obj = of_group(group);
                let mut c = Client::connect(a).await.expect("connect");
                let mut answered = 0usize;
                for round in 0..50u32 {
                    let v = if is_d {
                        Value::F64(f64::from(round) + f64::from(i) / 1000.0)
                    } else {
                        Value::I32(round as i32 * 1000 + i32::from(i))
                    };
                    let bad = if is_d {
                        Value::F64(f64::NAN)
                    } else {
                        Value::F64(1.0)
                    };
                    let bad_err = if is_d {
                        AccessError::Range
                    } else {
                        AccessError::TypeMismatch
                    };
                    let ty = if is_d { ValueType::F64 } else { ValueType::I32 };
                    let mut reqs = Vec::with_capacity(20);
                    let mut want = Vec::with_capacity(20);
                    for _ in 0..4 {
                        reqs.push(Request::Write(obj, v));
                        want.push(Answer::Ok);
                        reqs.push(Request::Read(obj, ty));
                        want.push(Answer::Value(v));
                        reqs.push(Request::Write(obj, bad));
                        want.push(Answer::Access(bad_err));
                        reqs.push(Request::Read(TcObject::TcPlane.address(), ValueType::I32));
                        want.push(Answer::Value(Value::I32(17)));
                        reqs.push(Request::Read(
                            ObjectAddress {
                                device: NO_SUCH_DEVICE,
                                ..TcObject::Error.of(1)
                            },
                            ValueType::I32,
                        ));
                        want.push(Answer::Access(AccessError::NoObject));
                    }
                    let got = c.pipeline(&reqs).await.expect("pipeline");
                    assert_eq!(got, want, "client {i} round {round}");
                    answered += got.len();
                }
                answered
            });
        }
        let mut total = 0;
        while let Some(r) = tasks.join_next().await {
            total += r.expect("client task");
        }
        total
    };
    let result = rt
        .block_on(async { tokio::time::timeout(Duration::from_secs(120), work).await })
        .expect("finished within 120 s");
    assert_eq!(result, 200 * 1000);
    let mut c = BlockingClient::connect(&a.to_string()).expect("connect");
    assert_eq!(call(&mut c, &TcRequest::Queue).unwrap(), Reply::Queue(0));
}
