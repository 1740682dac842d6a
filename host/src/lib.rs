//! # addipos_host — the host library of the ADDIPOS TC emulator
//!
//! A legacy PCAP host program initialises object descriptors (BusNumber,
//! DeviceNumber, Index, SubIndex), gets handles, reads and writes
//! through them, spools interpolation commands and waits for the machine
//! to move. This crate lets such a program run on the emulator:
//!
//! * the Rust API: a [`Machine`] is one connection (to an emulator inside
//!   the process, stepped or in real time); [`Handle`]s name objects and
//!   are void after a Clean; every call answers a typed [`Error`] with its
//!   [`ErrorCode`] (the CANopen code of an access error, or a code of the
//!   library's own); motion calls, `exec`, `position`, `queue`; a session
//!   recorded as a conformance trace;
//! * the one wire client of `addipos serve` ([`WireClient`]: timeouts,
//!   connecting again after a failure, `INFO`), which the command line's
//!   `call` and `replay --server` (on a conformance session,
//!   [`RemoteSession`], a `tc_request::Runner`) use too;
//! * the C ABI (`libaddipos`, header `libaddipos/include/addipos.h`), a
//!   thin layer over it in a crate of its own (`libaddipos/`, decision
//!   511): `addipos_open`, `uoi_init`, `uoi_read_int`, `tc_lin`,
//!   `tc_exec`, ... (docs/host-api.md); the Python package `addipos`
//!   wraps it too (docs/python.md).
//!
//! ```
//! use addipos_host::{Descriptor, Machine};
//!
//! let m = Machine::open("embedded").unwrap();
//! let plane = m.handle(&Descriptor { bus_number: 1300, device_number: 0, index: 3, sub_index: 0 }).unwrap();
//! assert_eq!(m.read_int(plane).unwrap(), 17);
//! m.lin([Some(10.0), None, None, None, None, None, None, None], Some(600.0)).unwrap();
//! m.exec(None).unwrap();
//! assert_eq!(m.position().unwrap()[0], 10.0);
//! ```

mod error;
mod explain;
mod handles;
mod link;
mod machine;
mod objects;
mod remote_session;
mod served;
mod served_target;
pub mod target;
mod wire_client;

pub use error::{Error, ErrorCode, Result};
pub use handles::{Epoch, Handle, MAX_HANDLES};
pub use machine::{Machine, DEFAULT_TIMEOUT, RECORD_ENV};
pub use objects::{find_object, Descriptor};
pub use record::RecordHeader;
pub use remote_session::{RemoteSession, SessionError};
pub use served::CONNECT_TIMEOUT;
pub use served_target::{ServedTarget, TOKEN_ENV, TOKEN_FILE_ENV};
pub use target::{EmbeddedOptions, Target};
pub use wire_client::{WireClient, WireError};

pub use emulator::RealTimeFactor;
pub use tc_request::{ArcDir, AxisPos, AxisWords, SpoolRecord, AXES, AXIS_NAMES};
pub use uoi::{AccessError, ObjectAddress};

/// A session recorded as a conformance trace: the emulator's trace
/// writer (`emulator::record`), which `serve --record` writes with too.
mod record {
    pub use emulator::record::{RecordHeader, Recorder};
}
