//! # trace — conformance traces of the TC emulator
//!
//! Traces (`*.trace`, trace format v1, docs/trace-format.md): the reader,
//! which parses headers, requests, expectations and spool lines line by
//! line, and the replayer, which runs each step as it is read, so a trace
//! of any length replays in bounded memory, on an in-process emulator or
//! on any other [`tc_request::Runner`] (a server's conformance session,
//! which the host library's wire client opens).
//!
//! ```
//! use trace::{parse_trace, replay};
//!
//! let text = "@name demo\nR 1300/0/3/0 i => 17\nW 1300/1/1/8 i 1024 => err Range\n";
//! let trace = parse_trace("demo.trace", text).unwrap();
//! assert!(replay(&trace).is_empty());
//! ```

mod echo;
mod expect;
mod files;
mod model;
mod parse;
mod replay;

pub use echo::{printable, shorten, MAX_ECHO_CHARS};
pub use files::{load_corpus, load_trace, open_trace, trace_files, TraceFileError};
pub use model::{Expect, Header, SpoolExpect, SpoolKind, Step, Trace, TraceError, DEFAULT_TOL};
pub use parse::{parse_trace, TraceReader, MAX_LINE_BYTES};
pub use replay::{fresh_emulator, replay, replay_on, replay_stream, Mismatch, Replayed};
