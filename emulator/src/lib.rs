//! # emulator — the ADDIPOS TC emulator as a program runs it
//!
//! Wires the TC module ([`tc_module`]) with the OTC extension
//! ([`otc_ext`]) into one [`Emulator`] driven by the one request model
//! ([`tc_request`]), and gives it what a server or an embedding program
//! needs around it:
//!
//! * [`Config`]: the settings (`config/default.toml` built in, a file of
//!   the same form read by the caller), and [`parse_address`], the one
//!   reading of a server address;
//! * [`EmulatorService`]: the emulator all connections of the object
//!   server share, as its handler, with a conformance session
//!   ([`ConformanceSession`]) per connection that sends `SETUP`;
//! * [`clock`]: real time, the executor's cycles advancing with the wall
//!   clock (a [`RealTimeClock`]), and [`Emulator::clean_epoch`], the
//!   count of Cleans a host library voids its handles by;
//! * [`RequestLog`]: where the shared emulator's requests go while it is
//!   recorded, and [`record`]: a session written as a conformance trace
//!   ([`record::Recorder`]), and the shared emulator's log streamed as one
//!   by a writer thread of its own ([`record::ServeRecorder`], `addipos
//!   serve --record`);
//! * [`tools`]: tool data that survives (the emulator's tool entries as
//!   the tool store's records, written durably before a write is
//!   answered);
//! * [`object_reference`]: `docs/objects.md`, generated from the object
//!   table;
//! * with the feature `opcua`, `opcua`: what the OPC UA face shows of
//!   bus 1300.
//!
//! ```
//! use emulator::Emulator;
//! use tc_request::{text::parse_request, Reply};
//!
//! let mut emu = Emulator::default();
//! let req = parse_request("R 1300/0/3/0 i").unwrap();
//! assert_eq!(emu.run(&req), Reply::Value(uoi::Value::I32(17)));
//! ```

mod address;
pub mod clock;
mod config;
mod emulator;
mod exec_waits;
pub mod guarded_write;
pub mod info_op;
#[cfg(feature = "opcua")]
pub mod opcua;
pub mod record;
mod reference;
mod request_log;
mod runner;
mod service;
mod serving;
mod session;
pub mod tools;

pub use address::{parse_address, AddressError};
pub use clock::{RealTimeClock, RealTimeFactor};
pub use config::{
    read_settings_file, Config, ConfigError, OpcuaSettings, ServiceSettings, DEFAULT_CONFIG,
    MAX_CONNECTIONS, MAX_EVICT_AFTER_MS, MAX_SETTINGS_BYTES, OPCUA_PKI_DIR,
};
pub use emulator::{Emulator, Tc};
pub use exec_waits::MAX_EXEC_WAITS;
pub use guarded_write::{GuardedOutcome, GuardedWrite, WRITE_IF_OP};
pub use info_op::{EmulatorInfo, INFO_OP};
pub use reference::{bits_without_meaning, devices_without_section, object_reference};
pub use request_log::{LogError, RequestLog};
pub use service::{EmulatorService, WatchedSpool, MAX_WATCHED};
pub use serving::ExecRest;
pub use session::{ConformanceSession, LOG_CAPACITY, MAX_SESSIONS, MAX_SESSION_SPOOL};
