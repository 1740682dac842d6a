//! # otc-ext — OTC online wear compensation for the TC module
//!
//! Serves devices 3 and 4 of bus 1300 as a [`TcExtension`] of the TC
//! module: it declares its objects (appended to the module's one map),
//! keeps the OTC state of each group in the group and the OTC fields of
//! each tool entry in the entry, and implements the switching rules
//! (`ToolType`, `Sequence`, `PosRequest`) and the read-back of wear at
//! switch-off and tool change.
//!
//! The per-cycle wear model (`wear`: continuous wear along the path, the
//! ramped discrete offsets of the PLC units, the direction of each
//! processing type) is pure and testable alone; `per_cycle` plugs it into
//! the executor through `TcExtension::cycle`, so the offset shows in the
//! executed position (`POS`), never in the spool log.
//!
//! ```
//! use otc_ext::OtcExtension;
//! use tc_module::{CycleTime, TcModule};
//! use uoi::{AccessError, ObjectServer, Value, ValueType};
//!
//! let mut server = ObjectServer::new();
//! server.register(TcModule::new([0.0; 8], CycleTime::DEFAULT, OtcExtension::default())).unwrap();
//! let wear = "1300/3/1/10".parse().unwrap();
//! assert_eq!(server.read(wear, ValueType::F64), Ok(Value::F64(0.0)));
//! assert_eq!(server.write(wear, Value::F64(1.0)), Err(AccessError::ReadOnly));
//! ```

mod extension;
mod objects;
mod per_cycle;
mod plc;
mod quantity;
mod registers;
mod running;
mod state;
mod switching;
pub mod wear;

pub use extension::OtcExtension;
pub use objects::{
    OtcObject, AXIS_DEVICE, AXIS_OBJECTS, GROUP_DEVICE, GROUP_OBJECTS, WEAR_AXIS_SUBS,
};
pub use per_cycle::WearModel;
pub use plc::{clamp_command, PlcUnit};
pub use quantity::{TenthMicrons, TiltAngle, WearRate};
pub use running::running_wear;
pub use state::{OtcErrorBits, OtcGroup, OtcTool, GRINDING};
pub use tc_module::TcExtension;
