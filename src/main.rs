//! The `addipos` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use addipos::config::{Config, DEFAULT_CONFIG};
use addipos::remote::{replay_remote, RemoteTarget};
use addipos::trace::{load_trace, replay, trace_files, Mismatch};
use tc_request::text::parse_request;
use tc_request::Reply;
use uoi::tcp::Server;

/// Emulator of the ADDIPOS TC module (UOI bus 1300) with OTC wear compensation.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Serve the emulator over TCP (UOI wire protocol, docs/protocol.md).
    /// Without --config the built-in settings apply (127.0.0.1:1300).
    Serve {
        /// Settings file (TOML, keys as in config/default.toml).
        #[arg(long, value_name = "FILE")]
        config: Option<PathBuf>,
        /// Listen address, overriding the settings.
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
    Call {
        /// Server address.
        addr: String,
        /// The request in trace syntax (R, W, LIN, CIR, JA, JS, SSF, RS, EXEC, POS, QUEUE).
        #[arg(required = true, num_args = 1.., allow_hyphen_values = true)]
        request: Vec<String>,
    },
    /// Replay conformance traces (*.trace) against a fresh emulator each and
    /// report every mismatch; exits non-zero if any trace fails.
    Replay {
        /// Trace files, or folders whose *.trace files are replayed.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Replay over the wire against this server instead of in-process.
        #[arg(long, value_name = "ADDR")]
        server: Option<String>,
        /// Print a line for every trace, not only failing ones.
        #[arg(short, long)]
        verbose: bool,
    },
}

fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            out.extend(trace_files(p).map_err(|e| format!("{}: {e}", p.display()))?);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

fn cmd_replay(files: &[PathBuf], server: Option<&str>, verbose: bool) -> ExitCode {
    let files = match expand(files) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut remote = match server.map(RemoteTarget::connect) {
        None => None,
        Some(Ok(r)) => Some(r),
        Some(Err(e)) => {
            eprintln!(
                "error: cannot connect to {}: {e}",
                server.unwrap_or_default()
            );
            return ExitCode::from(2);
        }
    };
    let (mut passed, mut failed) = (0usize, 0usize);
    for f in &files {
        let trace = match load_trace(f) {
            Ok(t) => t,
            Err(e) => {
                println!("{e}");
                failed += 1;
                continue;
            }
        };
        let mismatches: Vec<Mismatch> = match remote.as_mut() {
            Some(r) => replay_remote(&trace, r),
            None => replay(&trace),
        };
        if mismatches.is_empty() {
            passed += 1;
            if verbose {
                println!("{}: ok ({} requests)", trace.file, trace.steps.len());
            }
        } else {
            failed += 1;
            for m in &mismatches {
                println!("{m}");
            }
        }
    }
    println!("{passed} passed, {failed} failed");
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn cmd_call(addr: &str, words: &[String]) -> ExitCode {
    let text = words.join(" ");
    let req = match parse_request(&text) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: `{text}`: {e}");
            return ExitCode::from(2);
        }
    };
    let mut client = match RemoteTarget::connect(addr) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: cannot connect to {addr}: {e}");
            return ExitCode::from(2);
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
        Ok(other) => {
            eprintln!("error: unexpected answer {other:?}");
            return ExitCode::FAILURE;
        }
        Err(e) => {
            eprintln!("error: {e}");
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

fn cmd_serve(config: Option<&Path>, listen: Option<String>, allow_remote: bool) -> ExitCode {
    let text = match config {
        None => DEFAULT_CONFIG.to_string(),
        Some(p) => match std::fs::read_to_string(p) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: cannot read {}: {e}", p.display());
                return ExitCode::from(2);
            }
        },
    };
    let mut cfg = match Config::parse(&text) {
        Ok(c) => c,
        Err(e) => {
            eprintln!(
                "error: {}: {e}",
                config.map_or("built-in settings".into(), |p| p.display().to_string())
            );
            return ExitCode::from(2);
        }
    };
    if let Some(l) = listen {
        cfg.listen = l;
    }
    cfg.allow_remote |= allow_remote;
    let (server_cfg, service) = match (cfg.server(), cfg.service()) {
        (Ok(s), Ok(h)) => (s, h),
        (Err(e), _) | (_, Err(e)) => {
            let file = config.map_or("built-in settings".into(), |p| p.display().to_string());
            eprintln!("error: {file}: {e}");
            return ExitCode::from(2);
        }
    };
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("error: cannot start the runtime: {e}");
            return ExitCode::FAILURE;
        }
    };
    let result = rt.block_on(async move {
        let server = Server::bind(server_cfg, service).await?;
        println!(
            "addipos: serving UOI on {} (Ctrl-C to stop)",
            server.local_addr()?
        );
        server.run(shutdown_signal()).await
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
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
            cmd_serve(config.as_deref(), listen, allow_remote)
        }
        Command::Call { addr, request } => cmd_call(&addr, &request),
        Command::Replay {
            files,
            server,
            verbose,
        } => cmd_replay(&files, server.as_deref(), verbose),
    }
}
