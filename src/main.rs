//! The `addipos` command line.

mod cli;

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use cli::plot::PlotArgs;
use cli::remote_args::RemoteArgs;
use cli::replay::ReplayArgs;
use cli::run::RunArgs;
use cli::serve::ServeArgs;
use cli::{
    exit, Outcome, CALL_EXIT, EXIT_HELP, OBJECTS_EXIT, PLOT_EXIT, REPLAY_EXIT, RUN_EXIT, SERVE_EXIT,
};

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
    #[command(after_help = SERVE_EXIT)]
    Serve {
        #[command(flatten)]
        args: ServeArgs,
        /// Print the built-in settings and exit.
        #[arg(long)]
        print_default_config: bool,
    },
    /// Send one request to a server and print the answer, e.g.
    /// `addipos call 127.0.0.1:1300 R 1300/0/3/0 i`.
    #[command(after_help = CALL_EXIT)]
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
    #[command(after_help = REPLAY_EXIT)]
    Replay {
        #[command(flatten)]
        args: ReplayArgs,
    },
    /// Run an NC program (ISG / DIN 66025 subset) on a fresh emulator: print
    /// the spooled elements in trace `<` syntax, the final position and the
    /// V.G. wear values; warnings and errors (with line and block) go to
    /// stderr. The supported NC subset, with a worked example: docs/nc.md.
    /// Exits 1 on a parse error, a run error or an OTC error.
    #[command(after_help = RUN_EXIT)]
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
    #[command(after_help = PLOT_EXIT)]
    Plot {
        #[command(flatten)]
        args: PlotArgs,
    },
    /// Print the object reference of bus 1300 (Markdown): every object with
    /// its address, type, access, range and meaning, the access errors and
    /// the register bits. `docs/objects.md` is this output.
    #[command(after_help = OBJECTS_EXIT)]
    Objects,
    /// Show, export or import the tool data a server keeps in its data
    /// directory (offline, on the tool files themselves).
    Tools {
        #[command(subcommand)]
        command: cli::tools::ToolsCommand,
    },
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
    exit(dispatch(cli.command))
}

/// Runs the command.
fn dispatch(command: Command) -> Outcome {
    match command {
        Command::Serve {
            args,
            print_default_config,
        } => cli::serve::cmd_serve(&args, print_default_config),
        Command::Call {
            addr,
            request,
            remote,
        } => cli::call::cmd_call(&addr, &request, &remote),
        Command::Replay { args } => cli::replay::cmd_replay(&args),
        Command::Run { args } => cli::run::cmd_run(&args),
        Command::Plot { args } => cli::plot::cmd_plot(&args),
        Command::Objects => cli::objects::cmd_objects(),
        Command::Tools { command } => cli::tools::cmd_tools(command),
    }
}
