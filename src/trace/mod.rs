//! Conformance traces (`*.trace`, trace-format.md v1): the parser and the
//! replayer.

mod parse;
mod replay;

pub use parse::{
    parse_request, parse_trace, Expect, Request, SpoolExpect, SpoolKind, Step, Trace, TraceError,
};
pub use replay::{format_element, replay, replay_on, Mismatch, Target, TargetAnswer};
