//! Helpers the integration tests share: a server of a handler on its own
//! thread and runtime, and the `addipos serve` binary started and read for
//! the address it bound.

// Each test file uses only some of these; setups may stop loudly.
#![allow(dead_code, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{BufRead, BufReader, Read};
use std::net::SocketAddr;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use emulator::EmulatorService;
use uoi::tcp::{Handler, Server, ServerConfig};

/// A server on its own thread and runtime (two workers), stopped on drop.
pub struct TestServer {
    /// The address it bound.
    pub addr: SocketAddr,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl TestServer {
    /// A server of `handler` with `cfg`.
    pub fn with<H: Handler>(cfg: ServerConfig, handler: H) -> Self {
        let (addr_tx, addr_rx) = std::sync::mpsc::channel();
        let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
        let thread = std::thread::spawn(move || {
            let rt = tokio::runtime::Builder::new_multi_thread()
                .worker_threads(2)
                .enable_all()
                .build()
                .expect("runtime");
            rt.block_on(async move {
                let server = Server::bind(cfg, handler).await.expect("bind");
                addr_tx
                    .send(server.local_addr().expect("addr"))
                    .expect("send addr");
                server
                    .run(async {
                        let _ = stop_rx.await;
                    })
                    .await
                    .expect("run");
            });
        });
        let addr = addr_rx
            .recv_timeout(Duration::from_secs(10))
            .expect("server started");
        Self {
            addr,
            stop: Some(stop_tx),
            thread: Some(thread),
        }
    }

    /// A server of a fresh emulator with `cfg`.
    pub fn start(cfg: ServerConfig) -> Self {
        Self::with(
            cfg,
            EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT),
        )
    }

    /// A server of a fresh emulator on 127.0.0.1.
    pub fn local() -> Self {
        Self::start(loopback())
    }
}

/// Default settings on 127.0.0.1, any port.
pub fn loopback() -> ServerConfig {
    ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        ..ServerConfig::default()
    }
}

impl Drop for TestServer {
    fn drop(&mut self) {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The `addipos` binary.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
}

/// A running `addipos serve`, killed when dropped; its log is drained from
/// stderr by a thread so that it never blocks on it.
pub struct ServeProcess {
    child: Child,
    /// The address it bound, as its start line names it.
    pub addr: String,
    log: Arc<Mutex<String>>,
    drain: Option<JoinHandle<()>>,
}

impl ServeProcess {
    /// Starts `addipos serve` with `args` and `env` (with `--no-persist`
    /// unless `args` name a `--data-dir`), and waits for its start line.
    pub fn start(args: &[&str], env: &[(&str, &str)]) -> Self {
        // Tool data in memory unless the test gives a data directory.
        let persist = args.contains(&"--data-dir");
        let mut child = bin()
            .arg("serve")
            .args((!persist).then_some("--no-persist"))
            .args(args)
            .envs(env.iter().copied())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start serve");
        // The start line is the server's log line on stderr naming the address.
        let mut err = BufReader::new(child.stderr.take().expect("stderr"));
        let mut log = String::new();
        let mut line = String::new();
        while !line.contains("serving") {
            line.clear();
            let n = err.read_line(&mut line).expect("start line");
            assert!(n > 0, "serve ended without a start line: {log}");
            log.push_str(&line);
        }
        let addr = line
            .split_whitespace()
            .find_map(|w| w.strip_prefix("listen="))
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_string();
        let log = Arc::new(Mutex::new(log));
        let sink = Arc::clone(&log);
        let drain = std::thread::spawn(move || {
            let mut rest = String::new();
            let _ = err.read_to_string(&mut rest);
            sink.lock().expect("log").push_str(&rest);
        });
        Self {
            child,
            addr,
            log,
            drain: Some(drain),
        }
    }

    /// The server's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Stops the server gracefully (SIGTERM) and waits for its end, at most
    /// `guard`; returns its exit status and log.
    pub fn terminate(mut self, guard: Duration) -> (std::process::ExitStatus, String) {
        let term = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .expect("kill");
        assert!(term.success(), "kill -TERM failed");
        let t0 = std::time::Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                break status;
            }
            assert!(t0.elapsed() < guard, "serve did not stop on SIGTERM");
            std::thread::sleep(Duration::from_millis(20));
        };
        if let Some(d) = self.drain.take() {
            let _ = d.join();
        }
        let log = self.log.lock().expect("log").clone();
        (status, log)
    }

    /// Stops the server and returns its log.
    pub fn stop(mut self) -> String {
        let _ = self.child.kill();
        let _ = self.child.wait();
        if let Some(d) = self.drain.take() {
            let _ = d.join();
        }
        let log = self.log.lock().expect("log").clone();
        log
    }
}

/// A failed test does not leave the server running.
impl Drop for ServeProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Replays `t` on a fresh conformance session of the server.
pub fn replay_remote(
    t: &trace::Trace,
    session: &mut addipos_host::RemoteSession,
) -> Vec<trace::Mismatch> {
    let h = &t.header;
    let capacity = h.spool_capacity as u64;
    session
        .set_up(h.start, h.cycle.secs(), capacity)
        .expect("setup");
    trace::replay_on(t, session)
}

/// A conformance session on the server at `addr`.
pub fn session(addr: &str) -> addipos_host::RemoteSession {
    let wire = addipos_host::WireClient::connect(addr, Default::default()).expect("connect");
    addipos_host::RemoteSession::new(wire)
}
