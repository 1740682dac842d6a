//! # tc-module — the ADDIPOS tool radius correction module (bus 1300)
//!
//! Implements the objects of devices 0, 1 and 2 of `shared/spec/uoi-map.md`
//! on top of the [`uoi`] dispatcher, the one-profile correction buffer of
//! `trc-geometry.md`, coordinate rotation, the spooler and the executor.
//!
//! ```
//! use tc_module::TcModule;
//! use uoi::{ObjectServer, Value, ValueType};
//!
//! let mut server = ObjectServer::new();
//! server.register(TcModule::default()).unwrap();
//! let plane = "1300/0/3/0".parse().unwrap();
//! assert_eq!(server.read(plane, ValueType::I32), Ok(Value::I32(17)));
//! // WKZINDEX of group 1 only takes 0..=1023.
//! let wkz = "1300/1/1/8".parse().unwrap();
//! assert_eq!(server.write(wkz, Value::I32(1024)), Err(uoi::AccessError::Range));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod bits;
pub mod correction;
pub mod executor;
pub mod extension;
pub mod geometry;
pub mod group;
pub mod module;
pub mod motion;
pub mod object_map;
pub mod plane;
pub mod rotation;
pub mod spooler;
pub mod tool_table;

pub use bits::{ErrorBits, StatusBits};
pub use extension::{GroupContext, NoExtension, TcExtension};
pub use group::{CorrGroup, Side, TransitionMode};
pub use module::TcModule;
pub use motion::{ArcDir, AxisWords, Motion};
pub use object_map::{OtcObject, TcObject, TC_BUS, TC_OBJECTS};
pub use plane::{AxisPos, PlaneAxes, TcPlane, AXES, AXIS_NAMES};
pub use spooler::{Origin, Path, SpoolElement, Spooler};
pub use tool_table::{ToolEntry, ToolTable, WkzIndex};
