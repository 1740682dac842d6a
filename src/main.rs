//! The `addipos` command line.

use std::io::IsTerminal;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Parser, Subcommand};

use addipos::access;
use addipos::address::parse_address;
use addipos::config::{Config, DEFAULT_CONFIG};
use addipos::remote::{setup_failed, RemoteTarget};
use addipos::service::EmulatorService;
use addipos::trace::{fresh_emulator, open_trace, replay_stream, trace_files, Target};
use tc_request::text::parse_request;
use tc_request::Reply;
use uoi::tcp::{AccessToken, ClientError, ClientOptions, Server};
use uoi::wire::ProtocolError;

/// Exit status when the command ran and found a failure: a trace that
/// differs, an error answer to `call`, a server that failed while serving.
const EXIT_FAILED: u8 = 1;

/// Exit status when the command could not do its job at all: bad
/// arguments or settings, no traces, an address it cannot listen on or
/// connect to (clap's usage errors exit with 2 as well).
const EXIT_TROUBLE: u8 = 2;

/// Exit statuses, for `--help`.
const EXIT_HELP: &str = "Exit status: 0 success; 1 ran and found a failure (a trace differs, \
an error answer, the server failed while serving); 2 could not start (bad arguments or \
settings, no traces found, a path that does not exist, an address that cannot be listened \
on or connected to).";

/// Emulator of the ADDIPOS TC module (UOI bus 1300) with OTC wear compensation.
#[derive(Parser)]
#[command(version, about, long_about = None, after_help = EXIT_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Serve the emulator over TCP (UOI wire protocol, docs/protocol.md).
    /// Without --config the built-in settings apply (127.0.0.1:1300).
    #[command(after_help = EXIT_HELP)]
    Serve {
        /// Settings file (TOML, keys as in config/default.toml).
        #[arg(long, value_name = "FILE")]
        config: Option<PathBuf>,
        /// Listen address, overriding the settings: HOST:PORT,
        /// localhost:PORT, or a bare PORT (on 127.0.0.1).
        #[arg(long, value_name = "ADDR")]
        listen: Option<String>,
        /// Allow listening on a non-loopback address.
        #[arg(long)]
        allow_remote: bool,
        /// Print the built-in settings and exit.
        #[arg(long)]
        print_default_config: bool,
    },
    /// Send one request to a server and print the answer, e.g.
    /// `addipos call 127.0.0.1:1300 R 1300/0/3/0 i`.
    #[command(after_help = EXIT_HELP)]
    Call {
        /// Server address: HOST:PORT, localhost:PORT, or a bare PORT (on
        /// 127.0.0.1).
        addr: String,
        /// The request in trace syntax (R, W, LIN, CIR, JA, JS, SSF, RS, EXEC, POS, QUEUE).
        #[arg(required = true, num_args = 1.., allow_hyphen_values = true)]
        request: Vec<String>,
        #[command(flatten)]
        remote: RemoteArgs,
    },
    /// Replay conformance traces (*.trace) against a fresh emulator each and
    /// report every mismatch; exits non-zero if any trace fails.
    #[command(after_help = EXIT_HELP)]
    Replay {
        /// Trace files, or folders whose *.trace files are replayed.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Replay over the wire against this server instead of in-process
        /// (HOST:PORT, localhost:PORT, or a bare PORT).
        #[arg(long, value_name = "ADDR")]
        server: Option<String>,
        /// Print a line for every trace, not only failing ones.
        #[arg(short, long)]
        verbose: bool,
        #[command(flatten)]
        remote: RemoteArgs,
    },
    /// Print the object reference of bus 1300 (Markdown): every object with
    /// its address, type, access, range and meaning, the access errors and
    /// the register bits. `docs/objects.md` is this output.
    Objects,
}

/// How `call` and `replay --server` reach the server.
#[derive(Args)]
struct RemoteArgs {
    /// Longest wait, in seconds, for the connection and for each answer
    /// [default: 5 for the connection, 30 for an answer].
    #[arg(long, value_name = "SECS", value_parser = parse_secs)]
    timeout: Option<Duration>,
    /// Access token to present (a server with allow_remote asks remote
    /// clients for it).
    #[arg(
        long,
        value_name = "TOKEN",
        env = "ADDIPOS_TOKEN",
        hide_env_values = true
    )]
    token: Option<String>,
    /// File holding the access token (the server's <data_dir>/access-token);
    /// takes precedence over --token and ADDIPOS_TOKEN.
    #[arg(long, value_name = "FILE")]
    token_file: Option<PathBuf>,
}

fn parse_secs(s: &str) -> Result<Duration, String> {
    s.parse::<f64>()
        .ok()
        .filter(|v| *v > 0.0)
        .and_then(|v| Duration::try_from_secs_f64(v).ok())
        .ok_or_else(|| format!("`{s}` is not a number of seconds above 0"))
}

impl RemoteArgs {
    /// The client options these arguments give.
    fn options(&self) -> Result<ClientOptions, String> {
        let mut opts = ClientOptions::default();
        if let Some(t) = self.timeout {
            opts.connect_timeout = t;
            opts.request_timeout = t;
        }
        opts.token = match (&self.token_file, &self.token) {
            (Some(f), _) => Some(access::read_token_file(f).map_err(|e| e.to_string())?),
            (None, Some(t)) => Some(AccessToken::new(t).map_err(|e| format!("--token: {e}"))?),
            (None, None) => None,
        };
        Ok(opts)
    }
}

/// A hint for an `Unauthorized` answer.
fn token_hint(e: &ClientError) -> &'static str {
    match e {
        ClientError::Protocol(p) => protocol_hint(*p),
        _ => "",
    }
}

/// What to do about a protocol error, if the user can do something.
fn protocol_hint(e: ProtocolError) -> &'static str {
    match e {
        ProtocolError::Unauthorized => {
            " (pass the server's access token with --token-file FILE, --token or ADDIPOS_TOKEN)"
        }
        _ => "",
    }
}

/// The trace files the arguments name: files as given, folders as their
/// `*.trace` files. A path that does not exist, or a folder without
/// traces, is an error.
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => format!("{}: no such file or folder", p.display()),
            _ => format!("{}: {e}", p.display()),
        })?;
        if !meta.is_dir() {
            out.push(p.clone());
            continue;
        }
        let files = trace_files(p).map_err(|e| format!("{}: {e}", p.display()))?;
        if files.is_empty() {
            return Err(format!(
                "no traces found: {} holds no *.trace file",
                p.display()
            ));
        }
        out.extend(files);
    }
    Ok(out)
}

/// Connects `call` or `replay --server` to a server given as the user
/// typed its address, or says why not.
fn connect(addr: &str, args: &RemoteArgs) -> Result<RemoteTarget, String> {
    let resolved = parse_address(addr)?;
    let opts = args.options()?;
    RemoteTarget::connect_with(&resolved.to_string(), &opts).map_err(|e| match e {
        ClientError::TimedOut { .. } => e.to_string(),
        e => format!(
            "cannot connect to {addr} ({resolved}): {e}{}",
            token_hint(&e)
        ),
    })
}

/// Replays one trace file as it is read, printing every mismatch; true
/// when it passed.
fn replay_file(path: &Path, remote: Option<&mut RemoteTarget>, verbose: bool) -> bool {
    let mut reader = match open_trace(path) {
        Ok(r) => r,
        Err(e) => {
            println!("{e}");
            return false;
        }
    };
    let header = reader.header().clone();
    let mut emulator;
    let target: &mut dyn Target = match remote {
        Some(r) => match r.prepare(&header) {
            Ok(()) => r,
            Err(e) => {
                println!("{}", setup_failed(&header, e));
                return false;
            }
        },
        None => {
            emulator = fresh_emulator(&header);
            &mut emulator
        }
    };
    match replay_stream(&mut reader, target, &mut |m| println!("{m}")) {
        Ok(done) if done.mismatches == 0 => {
            if verbose {
                println!("{}: ok ({} requests)", header.file, done.steps);
            }
            true
        }
        Ok(_) => false,
        Err(e) => {
            println!("{e}");
            false
        }
    }
}

fn cmd_replay(
    files: &[PathBuf],
    server: Option<&str>,
    verbose: bool,
    remote_args: &RemoteArgs,
) -> ExitCode {
    let files = match expand(files) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let mut remote = match server.map(|s| connect(s, remote_args)) {
        None => None,
        Some(Ok(r)) => Some(r),
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let (mut passed, mut failed) = (0usize, 0usize);
    for f in &files {
        if replay_file(f, remote.as_mut(), verbose) {
            passed += 1;
        } else {
            failed += 1;
        }
    }
    println!("{passed} passed, {failed} failed");
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(EXIT_FAILED)
    }
}

fn cmd_call(addr: &str, words: &[String], remote_args: &RemoteArgs) -> ExitCode {
    let text = words.join(" ");
    let req = match parse_request(&text) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: `{text}`: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let mut client = match connect(addr, remote_args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    match client.call(&req) {
        Ok(Reply::Ok) => println!("ok"),
        Ok(Reply::Value(v)) => println!("{v}"),
        Ok(Reply::Queue(n)) => println!("{n}"),
        Ok(Reply::Pos(p)) => {
            let words: Vec<String> = tc_module::AXIS_NAMES
                .iter()
                .zip(p)
                .map(|(n, v)| format!("{n}{v}"))
                .collect();
            println!("{}", words.join(" "));
        }
        Ok(Reply::Access(e)) => {
            println!("err {}", e.name());
            return ExitCode::FAILURE;
        }
        Ok(Reply::Protocol(e)) => {
            eprintln!("error: {e}{}", protocol_hint(e));
            return ExitCode::FAILURE;
        }
        Ok(other) => {
            eprintln!("error: unexpected answer {other:?}");
            return ExitCode::FAILURE;
        }
        Err(e) => {
            eprintln!("error: {e}{}", token_hint(&e));
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {},
        () = term => {},
    }
    tracing::info!("stop requested");
}

/// What `serve` runs with.
struct ServeSettings {
    server: uoi::tcp::ServerConfig,
    service: EmulatorService,
}

/// The settings file (or the built-in settings) with `--listen` and
/// `--allow-remote` applied, checked; every error names where the bad
/// value came from.
fn serve_settings(
    config: Option<&Path>,
    listen: Option<&str>,
    allow_remote: bool,
) -> Result<ServeSettings, String> {
    let source = config.map_or_else(|| "built-in settings".into(), |p| p.display().to_string());
    let text = match config {
        None => DEFAULT_CONFIG.to_string(),
        Some(p) => std::fs::read_to_string(p).map_err(|e| format!("cannot read {source}: {e}"))?,
    };
    let in_source = |e: addipos::config::ConfigError| format!("{source}: {e}");
    let mut cfg = Config::parse(&text).map_err(in_source)?;
    if let Some(l) = listen {
        cfg.listen = parse_address(l)
            .map_err(|e| format!("--listen: {e}"))?
            .to_string();
    }
    cfg.allow_remote |= allow_remote;
    let mut server = cfg.server().map_err(in_source)?;
    let service = cfg.service().map_err(in_source)?;
    if cfg.wants_token() {
        let token = server_token(&cfg.data_dir).map_err(|e| format!("access token: {e}"))?;
        server.access.token = Some(token);
    }
    Ok(ServeSettings { server, service })
}

/// The server's access token, read or generated; the log names its file
/// (not the token itself: logs are often read more widely than the file).
fn server_token(data_dir: &Path) -> std::io::Result<AccessToken> {
    let t = access::load_or_create(data_dir)?;
    let path = std::path::absolute(&t.path).unwrap_or_else(|_| t.path.clone());
    let file = path.display();
    if t.created {
        tracing::info!("generated a new access token in {file}");
    }
    tracing::info!(
        "clients must present the access token in {file} (call/replay: --token-file FILE)"
    );
    Ok(t.token)
}

/// Why the server could not listen on `addr`, and what to do about it.
fn listen_error(addr: SocketAddr, e: &std::io::Error) -> String {
    const HINT: &str = "choose another with --listen ADDR or `listen` in the settings file";
    match e.kind() {
        std::io::ErrorKind::AddrInUse => {
            format!("cannot listen on {addr}: address already in use ({HINT})")
        }
        // The server's own refusal (a non-loopback address) says what to do.
        _ if e.raw_os_error().is_none() => e.to_string(),
        _ => format!("cannot listen on {addr}: {e} ({HINT})"),
    }
}

fn cmd_serve(config: Option<&Path>, listen: Option<&str>, allow_remote: bool) -> ExitCode {
    let settings = match serve_settings(config, listen, allow_remote) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("error: cannot start the runtime: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let addr = settings.server.listen;
    // The server logs its one start line (address, limits) once bound.
    let server = match rt.block_on(Server::bind(settings.server, settings.service)) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {}", listen_error(addr, &e));
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    match rt.block_on(server.run(shutdown_signal())) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_FAILED)
        }
    }
}

/// Log lines on stderr; colour only on a terminal, and not with `NO_COLOR`
/// set.
fn init_log() {
    let colour = std::io::stderr().is_terminal()
        && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty());
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(colour)
        .init();
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    init_log();
    match cli.command {
        Command::Serve {
            config,
            listen,
            allow_remote,
            print_default_config,
        } => {
            if print_default_config {
                print!("{DEFAULT_CONFIG}");
                return ExitCode::SUCCESS;
            }
            cmd_serve(config.as_deref(), listen.as_deref(), allow_remote)
        }
        Command::Call {
            addr,
            request,
            remote,
        } => cmd_call(&addr, &request, &remote),
        Command::Replay {
            files,
            server,
            verbose,
            remote,
        } => cmd_replay(&files, server.as_deref(), verbose, &remote),
        Command::Objects => {
            print!("{}", addipos::reference::object_reference());
            ExitCode::SUCCESS
        }
    }
}
