//! The log lines a client can make the server repeat
//! (a wrong token, a connection refused) are written at most once a second
//! per kind, with the count of lines left out; and a
//! HELLO to a server without a token answers `BadPayload` for a malformed
//! payload, `Ok` for an empty one or one shaped like a token.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::Write;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use bytes::{Bytes, BytesMut};
use common::{connect, is_closed, local, read_answer, read_frame, read_head, Index};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use uoi::tcp::{AccessPolicy, AccessToken, Server, ServerConfig};
use uoi::wire::{encode_request, ProtocolError, Request};

fn hello_frame(id: u32, token: &[u8]) -> Vec<u8> {
    let mut f = BytesMut::new();
    encode_request(id, &Request::Hello(Bytes::copy_from_slice(token)), &mut f);
    f.to_vec()
}

/// The log, as the server writes it.
#[derive(Clone, Default)]
struct Log(Arc<Mutex<Vec<u8>>>);

impl Write for Log {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Log {
    fn lines_with(&self, text: &str) -> Vec<String> {
        let all = String::from_utf8_lossy(&self.0.lock().unwrap()).into_owned();
        all.lines()
            .filter(|l| l.contains(text))
            .map(str::to_owned)
            .collect()
    }
}

#[test]
fn a_flood_of_wrong_tokens_writes_a_line_a_second_with_the_count() {
    const TRIES: usize = 300;
    let log = Log::default();
    let writer = log.clone();
    let subscriber = tracing_subscriber::fmt()
        .with_writer(move || writer.clone())
        .with_ansi(false)
        .finish();
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let cfg = ServerConfig {
        access: AccessPolicy {
            token: Some(AccessToken::new("0123456789abcdef0123").expect("token")),
            on_loopback: true,
        },
        // Every try reaches the token check.
        accept_rate_per_peer: None,
        ..local()
    };
    let took = tracing::subscriber::with_default(subscriber, || {
        rt.block_on(async {
            let server = Server::bind(cfg, Index).await.expect("bind");
            let addr = server.local_addr().expect("addr");
            let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
            let serving = tokio::spawn(server.run(async {
                let _ = stopped.await;
            }));
            let t0 = Instant::now();
            for k in 0..TRIES {
                let mut s = tokio::net::TcpStream::connect(addr).await.expect("connect");
                s.write_all(&hello_frame(k as u32, b"wrong-token-wrong-token"))
                    .await
                    .expect("hello");
                let mut rest = Vec::new();
                let _ = s.read_to_end(&mut rest).await;
                let status = u32::from_le_bytes([rest[12], rest[13], rest[14], rest[15]]);
                assert_eq!(status, ProtocolError::Unauthorized.code());
            }
            let took = t0.elapsed();
            drop(stop);
            serving.await.expect("server").expect("run");
            took
        })
    });
    let lines = log.lines_with("wrong access token");
    assert!(!lines.is_empty());
    // One line a second at most (plus the first).
    let most = 1 + took.as_secs() as usize + 1;
    assert!(lines.len() <= most, "{} lines in {took:?}", lines.len());
    // The first line counts nothing left out; later ones what they left out.
    assert!(lines[0].contains("suppressed=0"), "{}", lines[0]);
}

#[test]
fn a_hello_without_a_configured_token_is_checked_for_its_form() {
    let (addr, _stop) = common::serve(local());
    let mut s = connect(addr);
    let bad = ProtocolError::BadPayload.code();
    for (id, payload) in [
        (1, b"short".to_vec()),
        (2, vec![0xFF; 20]),
        (3, vec![b'a'; 60_000]),
        (4, b"0123456789 abcdef".to_vec()),
    ] {
        s.write_all(&hello_frame(id, &payload)).expect("write");
        assert_eq!(read_head(&mut s), (id, 0x03, bad), "payload {id}");
    }
    // The connection stays open; an empty payload and a token's shape are
    // well formed.
    s.write_all(&hello_frame(5, b"")).expect("write");
    assert_eq!(read_head(&mut s), (5, 0x03, 0));
    s.write_all(&hello_frame(6, b"0123456789abcdef"))
        .expect("write");
    assert_eq!(read_head(&mut s), (6, 0x03, 0));
    s.write_all(&read_frame(7)).expect("write");
    assert_eq!(read_answer(&mut s), (7, 7));
    drop(s);
    let mut s = connect(addr);
    s.write_all(&hello_frame(1, b"short")).expect("write");
    assert_eq!(read_head(&mut s), (1, 0x03, bad));
    s.shutdown(std::net::Shutdown::Write).expect("shutdown");
    assert!(is_closed(&mut s));
}
