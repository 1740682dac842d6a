//! The bodies of the fuzz targets (`fuzz/`, docs/fuzzing.md): one function
//! per target, taking any bytes and checking properties of what the code
//! makes of them. A violated property panics, which is what a fuzzer (or
//! the stable harness `tests/fuzz_stable.rs`) reports:
//!
//! * [`frame_decoder`]: the server's and the client's frame decoders;
//! * [`trace_line`]: the trace reader and the request parser;
//! * [`frame_sequence`]: a byte stream of frames served the way a
//!   connection serves it, by a connection's session and the shared
//!   emulator, every answer checked;
//! * [`nc_program`]: an NC program parsed and, when it parses, run by the
//!   interpreter on the real emulator.
//!
//! Each function reads at most [`MAX_INPUT`] bytes of its input
//! ([`MAX_TRACE_INPUT`] for the trace reader, [`MAX_NC_INPUT`] for NC
//! programs).

// A violated property is meant to stop loudly: that is what is reported.
#![allow(clippy::panic)]

mod frames;
mod limits;
mod nc;
mod sequence;
mod text;

pub use frames::frame_decoder;
pub use limits::{
    EXEC_BUDGET, MAX_FRAMES, MAX_INPUT, MAX_NC_INPUT, MAX_TRACE_INPUT, NC_EXEC_SLICES,
    NC_REQUEST_BUDGET, POS_LIMIT, SPOOLED_PER_FRAME,
};
pub use nc::nc_program;
pub use sequence::{frame_sequence, request_stream, serve_stream, trace_requests, Connection};
pub use text::trace_line;
