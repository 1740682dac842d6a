//! # tc-module — the ADDIPOS tool radius correction module (bus 1300)
//!
//! The objects of devices 0, 1 and 2 of the TC object map on top of the
//! [`uoi`] dispatcher, the one-profile correction buffer, coordinate
//! rotation, the spooler and the executor; an extension (OTC) plugs in
//! through [`TcExtension`]: its objects are appended to the one map, its
//! state lives in the groups and tool entries, and it may act on every
//! interpolation cycle ([`cycle`]).
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

pub mod bits;
pub mod correction;
pub mod cycle;
pub mod element;
pub mod executor;
pub mod extension;
pub mod geometry;
pub mod group;
pub mod limits;
pub mod module;
pub mod object_map;
pub mod plane;
pub mod rotation;
pub mod spooler;
pub mod tool_table;

pub use tc_request::motion;

pub use bits::{ErrorBits, StatusBits};
pub use cycle::{Cycle, CycleModel, NoModel, PathPart};
pub use element::{ContourNormal, NormalRule, Origin, Path, SpoolElement};
pub use extension::{Group, GroupAccess, Groups, NoExtension, TcExtension};
pub use group::{CorrGroup, Side, TransitionMode};
pub use limits::{CycleTime, MAX_COORD};
pub use module::{ExecLeft, TcModule, EXEC_SLICE_CYCLES};
pub use motion::{ArcDir, Motion};
pub use object_map::{TcKey, TcObject, GROUPS, GROUP_COUNT, TC_BUS, TC_OBJECTS};
pub use plane::{AxisPos, MainAxes, PlaneAxes, TcPlane, AXES, AXIS_NAMES};
pub use spooler::Spooler;
pub use tc_request::AxisWords;
pub use tool_table::{ToolEntry, ToolTable, WkzIndex};
