//! # addipos — emulator of the ADDIPOS TC module and its conformance traces
//!
//! Wires the TC module ([`tc_module`]) with the OTC extension ([`otc_ext`])
//! into one [`Emulator`] driven by the one request model ([`tc_request`]),
//! serves it over TCP ([`service`], with a private emulator per
//! conformance session: [`session`]) and, beside it, over OPC UA
//! ([`opcua`]: what the `opcua-face` crate shows), and replays conformance traces
//! (docs/trace-format.md) in-process or over the wire ([`trace`],
//! [`remote`]). [`picture`] draws paths in a plane as SVG for the docs.
//!
//! ```
//! use addipos::trace::{parse_trace, replay};
//!
//! let text = "@name demo\nR 1300/0/3/0 i => 17\nW 1300/1/1/8 i 1024 => err Range\n";
//! let trace = parse_trace("demo.trace", text).unwrap();
//! assert!(replay(&trace).is_empty());
//! ```

pub mod access;
pub mod address;
pub mod config;
pub mod emulator;
pub mod fuzz_checks;
pub mod nc_run;
pub mod opcua;
pub mod path_plot;
pub mod picture;
pub mod reference;
pub mod remote;
pub mod service;
mod serving;
pub mod session;
pub mod tools;
pub mod trace;

pub use emulator::Emulator;
