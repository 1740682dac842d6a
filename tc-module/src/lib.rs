//! # tc-module — the ADDIPOS tool radius correction module (bus 1300)
//!
//! The objects of devices 0, 1 and 2 of the TC object map on top of the
//! [`uoi`] dispatcher, the one-profile correction buffer, coordinate
//! rotation, the spooler and the executor; an extension (OTC) plugs in
//! through [`TcExtension`]: its objects are appended to the one map, its
//! state lives in the groups and tool entries, and it may act on every
//! interpolation cycle ([`CycleModel`], [`Cycle`]).
//!
//! The modules are private; what a user of the crate needs is named here.
//! Three are public as namespaces of their own: [`limits`] (the engine's
//! numeric limits and defaults), [`correction`] (the one-profile buffer on
//! its own, for a caller with profiles in machine axes) and the object
//! table ([`object_map`]; the object names and meanings are `tc_objects`').
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

mod bits;
pub mod correction;
mod cycle;
mod element;
mod executor;
mod extension;
mod geometry;
mod group;
pub mod limits;
mod module;
pub mod object_map;
mod plane;
mod rotation;
mod spooler;
mod tool_table;

pub use bits::{ErrorBits, StatusBits};
pub use correction::{FeedAdaption, TransitionMode};
pub use cycle::{Cycle, CycleModel, NoModel, PathPart, MAX_PARTS};
pub use element::{ArcPath, ContourNormal, NormalRule, Origin, Path, SpoolElement};
pub use executor::Executor;
pub use extension::{AlwaysStepped, Group, GroupAccess, Groups, NoExtension, NoKey, TcExtension};
pub use geometry::V2;
pub use group::{CorrGroup, Side};
pub use limits::{CycleTime, MAX_COORD};
pub use module::plan::{Plan, ToolChange, WritePlan};
pub use module::{ExecLeft, TcModule, EXEC_SLICE_CYCLES};
pub use object_map::TcKey;
pub use plane::{AxisPos, MainAxes, PlaneAxes, TcPlane, AXES, AXIS_NAMES};
pub use spooler::{
    check_capacity, CapacityError, Logged, Spooler, DEFAULT_SPOOL_CAPACITY, KEEP_WHEN_EMPTY,
    MAX_SPOOL_CAPACITY, MIN_SPOOL_CAPACITY,
};
pub use tc_request::AxisWords;
pub use tc_request::{ArcDir, Motion};
pub use tool_table::{ToolEntry, ToolTable, WkzIndex, TOOL_ENTRIES};
