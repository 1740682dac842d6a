//! Parts of the `addipos` command line, one concern each: how `call` and
//! `replay --server` reach a server, and how `serve` starts and stops.

pub mod plot;
pub mod remote_args;
pub mod run;
pub mod serve;
pub mod tools;

/// Exit status when the command ran and found a failure: a trace that
/// differs, an error answer to `call`, a server that failed while serving.
pub const EXIT_FAILED: u8 = 1;

/// Exit status when the command could not do its job at all: bad
/// arguments or settings, no traces, an address it cannot listen on or
/// connect to (clap's usage errors exit with 2 as well).
pub const EXIT_TROUBLE: u8 = 2;

/// Exit statuses, for `--help`.
pub const EXIT_HELP: &str = "Exit status: 0 success; 1 ran and found a failure (a trace differs, \
an error answer, the server failed while serving); 2 could not start (bad arguments or \
settings, no traces found, a path that does not exist, an address that cannot be listened \
on or connected to).";
