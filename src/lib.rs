//! # addipos — emulator of the ADDIPOS TC module and its conformance traces
//!
//! Wires the [`uoi`] object server, the [`tc_module`] and the [`otc_ext`]
//! extension into one [`Emulator`], and replays conformance traces
//! (`shared/spec/trace-format.md`) against it.
//!
//! ```
//! use addipos::trace::{parse_trace, replay};
//!
//! let text = "@name demo\nR 1300/0/3/0 i => 17\nW 1300/1/1/8 i 1024 => err Range\n";
//! let trace = parse_trace("demo.trace", text).unwrap();
//! assert!(replay(&trace).is_empty());
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod config;
pub mod emulator;
pub mod remote;
pub mod trace;

pub use emulator::Emulator;
