//! # otc-ext — OTC online wear compensation for the TC module
//!
//! Serves devices 3 and 4 of bus 1300 (`shared/spec/otc.md`, uoi-map.md) as
//! a [`TcExtension`] of the TC module: the per-group OTC registers, the OTC
//! fields of every tool entry, the PLC control units, the switching rules
//! (`ToolType`, `Sequence`, `PosRequest`) and the read-back of wear at
//! switch-off and tool change.
//!
//! Not yet here: the per-cycle wear model (continuous wear along the path,
//! the ramped discrete offset and its application to the executed
//! position). Until it lands the wear accumulators stay 0, so switch-off
//! and tool change hand back zero wear.
//!
//! ```
//! use otc_ext::OtcExtension;
//! use tc_module::TcModule;
//! use uoi::{AccessError, ObjectServer, Value, ValueType};
//!
//! let mut server = ObjectServer::new();
//! server.register(TcModule::default().with_extension(Box::new(OtcExtension::default()))).unwrap();
//! let wear = "1300/3/1/10".parse().unwrap();
//! assert_eq!(server.read(wear, ValueType::F64), Ok(Value::F64(0.0)));
//! assert_eq!(server.write(wear, Value::F64(1.0)), Err(AccessError::ReadOnly));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod registers;

pub use registers::{OtcErrorBits, OtcExtension, OtcMode, ProcType};
pub use tc_module::TcExtension;
