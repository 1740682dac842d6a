//! The `addipos` command line.

mod cli;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use addipos::config::DEFAULT_CONFIG;
use addipos::remote::{setup_failed, RemoteTarget};
use addipos::trace::{fresh_emulator, open_trace, replay_stream, trace_files, Target};
use cli::plot::{cmd_plot, PlotArgs};
use cli::remote_args::{connect, protocol_hint, token_hint, RemoteArgs};
use cli::run::{cmd_run, RunArgs};
use cli::serve::{cmd_serve, ServeArgs};
use cli::{EXIT_FAILED, EXIT_HELP, EXIT_TROUBLE};
use tc_request::text::parse_request;
use tc_request::Reply;

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
        #[command(flatten)]
        args: ServeArgs,
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
    /// Run an NC program (ISG / DIN 66025 subset) on a fresh emulator: print
    /// the spooled elements in trace `<` syntax, the final position and the
    /// V.G. wear values; warnings and errors (with line and block) go to
    /// stderr. Exits 1 on a parse error, a run error or an OTC error.
    #[command(after_help = EXIT_HELP)]
    Run {
        #[command(flatten)]
        args: RunArgs,
    },
    /// Draw an NC program (*.nc) or a trace (*.trace) as SVG in its plane
    /// (that of its arcs, else X-Y, or X-Z or Y-Z for a path that moves
    /// in those only): the programmed contour, the corrected tool-centre
    /// path and the executed path cycle by cycle (OTC offset included);
    /// rapids dashed, the block of each piece on hover. Exits 1 when the
    /// program failed (the picture is still written).
    #[command(after_help = EXIT_HELP)]
    Plot {
        #[command(flatten)]
        args: PlotArgs,
    },
    /// Print the object reference of bus 1300 (Markdown): every object with
    /// its address, type, access, range and meaning, the access errors and
    /// the register bits. `docs/objects.md` is this output.
    Objects,
    /// Show, export or import the tool data a server keeps in its data
    /// directory (offline, on the tool files themselves).
    Tools {
        #[command(subcommand)]
        command: cli::tools::ToolsCommand,
    },
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

/// What is logged unless `RUST_LOG` says otherwise: our lines from `info`
/// on; of the OPC UA library only warnings (its `info` lines describe every
/// connection).
// The OPC UA library's address space warns at every start of NodeSet
// declarations it meets twice (the Machine Tools NodeSet shares some
// between types, as the standard allows).
const DEFAULT_LOG: &str =
    "info,opcua_server=warn,opcua_server::address_space=error,opcua_crypto=warn,opcua_core=warn";

/// Log lines on stderr; colour only on a terminal, and not with `NO_COLOR`
/// set.
fn init_log() {
    let colour = std::io::stderr().is_terminal()
        && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty());
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(DEFAULT_LOG)),
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
            args,
            print_default_config,
        } => {
            if print_default_config {
                print!("{DEFAULT_CONFIG}");
                return ExitCode::SUCCESS;
            }
            cmd_serve(&args)
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
        Command::Run { args } => cmd_run(&args),
        Command::Plot { args } => cmd_plot(&args),
        Command::Objects => {
            print!("{}", addipos::reference::object_reference());
            ExitCode::SUCCESS
        }
        Command::Tools { command } => cli::tools::cmd_tools(command),
    }
}
