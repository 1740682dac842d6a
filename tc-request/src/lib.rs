//! # tc-request — what a host program asks of the TC module
//!
//! ONE model of a request to the ADDIPOS TC module on bus 1300: object
//! accesses, motion commands ([`Motion`], the only list of motion kinds),
//! the executor, and the emulator-control ops of conformance replay. Three
//! front ends produce it and one engine consumes it:
//!
//! * [`text`]: the trace syntax (`W 1300/1/1/8 i 5`, `LIN X10 Y0 F600`),
//!   one parser function per verb, and writing a request back;
//! * [`wire`]: the payloads of the TC ops on the UOI wire (the object
//!   layer `uoi` carries them without knowing what they mean);
//! * the NC front end (`nc`) turns program blocks into [`Request`]s.
//!
//! Whatever runs requests — the emulator in the process, a server over
//! the wire — is a [`Runner`]: trace replay, the NC runner and the host
//! library drive it through that one trait.
//!
//! The model's own modules are private: every type is named at the root;
//! [`text`] and [`wire`] are namespaces of their own.
//!
//! It lives in its own small crate so that a client, the trace tools and
//! the NC front end can speak to the TC module without depending on its
//! correction engine, and so that the engine (`tc-module`) consumes the
//! very type the front ends produce.
//!
//! ```
//! use tc_request::{text::parse_request, Motion, Request};
//!
//! let req = parse_request("LIN X20 Y5 F600").unwrap();
//! assert!(matches!(req, Request::Motion(Motion::Lin { feed: Some(600.0), .. })));
//! assert_eq!(req.to_string(), "LIN X20 Y5 F600");
//! let wire = req.to_wire();
//! assert_eq!(Request::from_wire(&wire), Ok(req));
//! ```

mod axes;
mod element;
mod motion;
mod request;
mod runner;
pub mod text;
pub mod wire;

pub use axes::{axis_index, AxisPos, AxisWords, AXES, AXIS_NAMES};
pub use element::{ArcRecord, Origin, SpoolRecord};
pub use motion::{ArcDir, Motion, SSF_FLUSH};
pub use request::{Reply, Request, MAX_EXEC_CYCLES};
pub use runner::Runner;
