//! The commands of `addipos`, one module each, and the one way a command
//! ends: [`Outcome`], which `main` turns into the exit status and the
//! `error:` line on standard error.

pub mod call;
pub mod junit;
pub mod objects;
pub mod plot;
pub mod progress;
pub mod record_file;
pub mod remote_args;
pub mod replay;
pub mod run;
pub mod serve;
pub mod shard;
pub mod token;
pub mod tools;

use std::fmt::Display;
use std::process::ExitCode;

/// Exit status when the command ran and found a failure: a trace that
/// differs, an error answer to `call`, a server that failed while serving.
const EXIT_FAILED: u8 = 1;

/// Exit status when the command could not do its job at all: bad
/// arguments or settings, no traces, an address it cannot listen on or
/// connect to (clap's usage errors exit with 2 as well).
const EXIT_TROUBLE: u8 = 2;

/// Exit statuses of the whole program, for the top-level `--help` (each
/// command's `--help` says its own).
pub const EXIT_HELP: &str = "Exit status: 0 success; 1 ran and found a failure (a trace differs, \
an error answer, the server failed while serving); 2 could not start (bad arguments or \
settings, no traces found, a path that does not exist, an address that cannot be listened \
on or connected to). Each command's --help gives its own.";

/// Exit statuses of `serve`.
pub const SERVE_EXIT: &str = "Exit status: 0 stopped by Ctrl-C or SIGTERM after a clean \
shutdown; 1 the server failed while serving; 2 could not start (bad arguments or settings, \
an address that cannot be listened on, the tool data locked by another server or unreadable).";

/// Exit statuses of `call`.
pub const CALL_EXIT: &str = "Exit status: 0 the server answered ok or a value; 1 it answered \
an error (err NAME: meaning, or a protocol error) or the connection failed during the request; \
2 could not start (bad arguments, a request that does not parse, a server that cannot be \
reached or gives no UOI answer).";

/// Exit statuses of `replay`.
pub const REPLAY_EXIT: &str = "Exit status: 0 every trace passed (an empty --shard part \
too); 1 a trace differs, holds no request, or could not be read or parsed; 2 nothing could \
be replayed (bad \
arguments such as --shard 4/3, a path that does not exist, a folder without *.trace files, a \
server that cannot be reached, gives no UOI answer or cannot set up a fresh emulator, a \
--junit file that cannot be written).";

/// Exit statuses of `run`.
pub const RUN_EXIT: &str = "Exit status: 0 the program ran to its end; 1 a parse error, a \
run error or an OTC error (reported on stderr with line and block); 2 could not start (the \
program or the tool file cannot be read, a tool file with bad lines, bad arguments).";

/// Exit statuses of `plot`.
pub const PLOT_EXIT: &str = "Exit status: 0 the picture is written; 1 the program or trace \
does not parse (nothing is drawn; `run` and `replay` exit 1 for it too) or failed (the \
picture is still written, up to the failure); 2 could not start (the input cannot be read, \
the output cannot be written, bad arguments).";

/// Exit statuses of `objects`.
pub const OBJECTS_EXIT: &str = "Exit status: 0 the reference is printed; 2 bad arguments.";

/// Why a command did not succeed: its exit status and what it says.
#[derive(Debug)]
pub struct Failure {
    status: u8,
    /// Said on standard error after `error: `; empty when the command has
    /// reported the failure itself (mismatches, errors of a program).
    message: String,
}

impl Failure {
    /// The command could not do its job (exit 2).
    pub fn trouble(message: impl Display) -> Self {
        Self {
            status: EXIT_TROUBLE,
            message: message.to_string(),
        }
    }

    /// The command ran and failed (exit 1), for the reason given.
    pub fn failed(message: impl Display) -> Self {
        Self {
            status: EXIT_FAILED,
            message: message.to_string(),
        }
    }

    /// The command ran and found a failure it has reported already
    /// (exit 1).
    pub fn reported() -> Self {
        Self::failed("")
    }
}

/// How a command ended.
pub type Outcome = Result<(), Failure>;

/// The exit status of `outcome`, saying its failure on standard error.
pub fn exit(outcome: Outcome) -> ExitCode {
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            if !f.message.is_empty() {
                eprintln!("error: {}", f.message);
            }
            ExitCode::from(f.status)
        }
    }
}
