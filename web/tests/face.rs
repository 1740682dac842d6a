//! The web face over loopback TCP, with an emulator served behind it:
//! its bounds (16 pages, then 503), its refusals (methods, addresses),
//! the headers of every answer, nothing sent while nothing changes, and
//! no cost once no page is open.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::net::SocketAddr;
use std::time::Duration;

use emulator::EmulatorService;
use tc_module::CycleTime;
use tc_request::text::parse_request;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use uoi::tcp::{AccessPolicy, AccessToken, CoreHandle, Server, ServerConfig};
use web_view::{WebConfig, WebError, WebFace, MAX_VIEWERS};

/// A served emulator (stepped) with the web face in front; dropping the
/// sender stops both.
struct Served {
    web: SocketAddr,
    core: CoreHandle,
    _stop: tokio::sync::watch::Sender<()>,
}

async fn served() -> Served {
    served_with(WebConfig::new("127.0.0.1:0".parse().unwrap())).await
}

/// As [`served`], with the web face's settings `web`.
async fn served_with(web: WebConfig) -> Served {
    let cfg = ServerConfig {
        listen: "127.0.0.1:0".parse().unwrap(),
        ..ServerConfig::default()
    };
    let service = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    let server = Server::bind(cfg, service).await.unwrap();
    let core = server.core();
    let face = WebFace::bind(web, core.clone()).await.unwrap();
    let web = face.local_addr().unwrap();
    // Dropping the sender ends both runs.
    let (stop, rx) = tokio::sync::watch::channel(());
    let (mut rx1, mut rx2) = (rx.clone(), rx);
    tokio::spawn(async move {
        server
            .run(async move {
                let _ = rx1.changed().await;
            })
            .await
    });
    tokio::spawn(async move {
        face.run(async move {
            let _ = rx2.changed().await;
        })
        .await
    });
    Served {
        web,
        core,
        _stop: stop,
    }
}

/// Sends `request` and reads up to `limit` bytes or the end, within 5 s.
async fn exchange(at: SocketAddr, request: &str, limit: usize) -> String {
    let mut s = TcpStream::connect(at).await.unwrap();
    s.write_all(request.as_bytes()).await.unwrap();
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    let read = async {
        while got.len() < limit {
            match s.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => got.extend_from_slice(&buf[..n]),
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(5), read)
        .await
        .expect("an answer within 5 s");
    String::from_utf8_lossy(&got).into_owned()
}

/// An open event stream, its answer's head read.
async fn open_page(at: SocketAddr) -> (TcpStream, String) {
    let mut s = TcpStream::connect(at).await.unwrap();
    s.write_all(b"GET /events HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    let read = async {
        while !head.ends_with(b"\r\n\r\n") {
            if s.read(&mut byte).await.unwrap_or(0) == 0 {
                break;
            }
            head.push(byte[0]);
        }
    };
    tokio::time::timeout(Duration::from_secs(5), read)
        .await
        .expect("a head within 5 s");
    (s, String::from_utf8_lossy(&head).into_owned())
}

/// Reads from an event stream until `want` has come, within 5 s.
async fn read_until(s: &mut TcpStream, want: &str) -> String {
    let mut got = Vec::new();
    let mut buf = [0u8; 65536];
    let read = async {
        while !String::from_utf8_lossy(&got).contains(want) {
            match s.read(&mut buf).await {
                Ok(0) | Err(_) => break,
                Ok(n) => got.extend_from_slice(&buf[..n]),
            }
        }
    };
    let _ = tokio::time::timeout(Duration::from_secs(5), read).await;
    String::from_utf8_lossy(&got).into_owned()
}

async fn call(core: &CoreHandle, text: &str) {
    let answer = core.call(parse_request(text).unwrap().to_wire()).await;
    assert_eq!(answer, uoi::wire::Answer::Ok, "{text}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn only_get_is_served_and_every_answer_carries_the_policy() {
    let s = served().await;
    for method in ["POST", "PUT", "DELETE", "PATCH"] {
        let req = format!("{method} /state HTTP/1.1\r\nContent-Length: 2\r\n\r\n{{}}");
        let answer = exchange(s.web, &req, 1 << 16).await;
        assert!(answer.starts_with("HTTP/1.1 405"), "{method}: {answer}");
        assert!(answer.contains("Content-Security-Policy: default-src 'self'"));
    }
    for path in [
        "/",
        "/state",
        "/app.js",
        "/draw.js",
        "/style.css",
        "/nothing",
    ] {
        let answer = exchange(s.web, &format!("GET {path} HTTP/1.1\r\n\r\n"), 1 << 20).await;
        assert!(
            answer.contains("Content-Security-Policy: default-src 'self'"),
            "{path}"
        );
        let ok = answer.starts_with("HTTP/1.1 200");
        assert_eq!(ok, path != "/nothing", "{path}: {answer}");
    }
    let page = exchange(s.web, "GET / HTTP/1.1\r\n\r\n", 1 << 20).await;
    assert!(
        !page.contains("http://") && !page.contains("https://"),
        "nothing from elsewhere"
    );
    let (_, head) = open_page(s.web).await;
    assert!(head.contains("Content-Security-Policy: default-src 'self'"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sixteen_pages_at_most_and_a_closed_one_frees_its_place() {
    let s = served().await;
    let mut pages = Vec::new();
    for _ in 0..MAX_VIEWERS {
        let (stream, head) = open_page(s.web).await;
        assert!(head.starts_with("HTTP/1.1 200"), "{head}");
        pages.push(stream);
    }
    let refused = exchange(s.web, "GET /events HTTP/1.1\r\n\r\n", 1 << 16).await;
    assert!(refused.starts_with("HTTP/1.1 503"), "{refused}");
    // The state stays readable while the pages are full.
    let state = exchange(s.web, "GET /state HTTP/1.1\r\n\r\n", 1 << 20).await;
    assert!(state.contains("\"web\": 16"), "{state}");
    drop(pages.pop());
    let mut tries = 0;
    loop {
        let (_again, head) = open_page(s.web).await;
        if head.starts_with("HTTP/1.1 200") {
            break;
        }
        tries += 1;
        assert!(tries < 100, "the closed page's place never came back");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_page_gets_what_changes_and_nothing_while_nothing_changes() {
    let s = served().await;
    let (mut page, _) = open_page(s.web).await;
    let first = read_until(&mut page, "\n\n").await;
    assert!(
        first.contains("event: update") && first.contains("\"queue\""),
        "{first}"
    );
    call(&s.core, "LIN X10 Y5 F600").await;
    let spooled = read_until(&mut page, "\"to\":[10.0,5.0]").await;
    assert!(spooled.contains("\"waiting\":1"), "{spooled}");
    call(&s.core, "EXEC").await;
    let moved = read_until(&mut page, "\"waiting\":0").await;
    assert!(
        moved.contains("[10.0,5.0]"),
        "the executed trail reached the end: {moved}"
    );
    // Stepped and idle: nothing changes, nothing is sent.
    let mut buf = [0u8; 1024];
    let quiet = tokio::time::timeout(Duration::from_millis(500), page.read(&mut buf)).await;
    assert!(quiet.is_err(), "sent while nothing changed");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_no_page_open_the_emulator_keeps_nothing_for_the_view() {
    let s = served().await;
    let take = |core: &CoreHandle| {
        let core = core.clone();
        async move {
            core.inspect(|h| {
                let svc = h.downcast_mut::<EmulatorService>().unwrap();
                svc.take_watched_spool().records.len()
            })
            .await
            .unwrap()
        }
    };
    call(&s.core, "LIN X1 F600").await;
    assert_eq!(take(&s.core).await, 0, "nobody watched");
    let (mut page, _) = open_page(s.web).await;
    read_until(&mut page, "\n\n").await;
    drop(page);
    // Once the sampler has seen the page go, it stops watching.
    let mut tries = 0;
    loop {
        call(&s.core, "LIN X2 F600").await;
        tokio::time::sleep(Duration::from_millis(30)).await;
        if take(&s.core).await == 0 {
            call(&s.core, "LIN X3 F600").await;
            if take(&s.core).await == 0 {
                break;
            }
        }
        tries += 1;
        assert!(tries < 200, "still watching with no page open");
    }
}

#[tokio::test]
async fn another_address_than_loopback_needs_leave_and_a_token() {
    let core = {
        let cfg = ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        };
        let service = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        Server::bind(cfg, service).await.unwrap().core()
    };
    let remote: SocketAddr = "0.0.0.0:0".parse().unwrap();
    let mut cfg = WebConfig::new(remote);
    let refused = WebFace::bind(cfg.clone(), core.clone()).await.unwrap_err();
    assert!(matches!(refused, WebError::NotAllowed(_)), "{refused}");
    cfg.allow_remote = true;
    let refused = WebFace::bind(cfg.clone(), core.clone()).await.unwrap_err();
    assert!(matches!(refused, WebError::NoToken(_)), "{refused}");
    cfg.access = AccessPolicy {
        token: Some(AccessToken::new("a-long-enough-token-1234").unwrap()),
        on_loopback: false,
    };
    // Allowed now; bound on loopback here, as tests use no other network.
    cfg.listen = "127.0.0.1:0".parse().unwrap();
    assert!(WebFace::bind(cfg, core).await.is_ok());
}

/// The OPC UA face's count of connections shows in `/state` (and `null`
/// without it).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_opcua_connections_are_shown_when_the_face_counts_them() {
    let s = served().await;
    let state = exchange(s.web, "GET /state HTTP/1.1\r\n\r\n", 1 << 20).await;
    assert!(state.contains("\"opcua\": null"), "{state}");
    let places = uoi::tcp::Places::new(uoi::tcp::PlaceLimits {
        all: 8,
        per_peer: 8,
        per_peer_on_loopback: true,
    });
    let mut web = WebConfig::new("127.0.0.1:0".parse().unwrap());
    web.opcua_connections = Some(std::sync::Arc::clone(&places));
    let s = served_with(web).await;
    let ip = "127.0.0.1".parse().unwrap();
    let seats = (places.take(ip).unwrap(), places.take(ip).unwrap());
    let state = exchange(s.web, "GET /state HTTP/1.1\r\n\r\n", 1 << 20).await;
    assert!(state.contains("\"opcua\": 2"), "{state}");
    drop(seats);
    let state = exchange(s.web, "GET /state HTTP/1.1\r\n\r\n", 1 << 20).await;
    assert!(state.contains("\"opcua\": 0"), "{state}");
}
