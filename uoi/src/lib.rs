//! # uoi — the Universal Object Interface of ADDIPOS controllers
//!
//! A UOI object is addressed by `BusNumber/DeviceNumber/Index/SubIndex`
//! ([`ObjectAddress`]) and read or written as an `i32` or an `f64`
//! ([`Value`]). Every access either succeeds or fails with one of the
//! CANopen-style [`AccessError`] codes (CiA 301 SDO abort codes).
//!
//! A module implements [`Bus`] and declares
//! all of its objects in ONE table of [`ObjectDesc`]. The checked entry points
//! of [`ObjectBus`] (blanket-implemented for every [`Bus`]) enforce address,
//! access, type and range from that table before the module sees the value,
//! so no module re-checks them by hand. An [`ObjectServer`] routes an access
//! to the bus registered under its BusNumber.
//!
//! ```
//! use uoi::{AccessError, Bus, ObjectAddress, ObjectDesc, ObjectServer, Value, ValueRange, Access};
//!
//! /// A one-object bus: a counter on 7/0/1/0.
//! struct Counter(i32);
//! #[derive(Clone, Copy)]
//! struct Key;
//! static OBJECTS: [ObjectDesc<Key>; 1] = [ObjectDesc::int(Key, "Counter", 0, 1..=1, 0, Access::ReadWrite, ValueRange::Int { min: 0, max: 9 })];
//! impl Bus for Counter {
//!     type Key = Key;
//!     fn number(&self) -> u16 { 7 }
//!     fn objects(&self) -> &[ObjectDesc<Key>] { &OBJECTS }
//!     fn read(&mut self, _: Key, _: ObjectAddress) -> Result<Value, AccessError> { Ok(Value::I32(self.0)) }
//!     fn write(&mut self, _: Key, _: ObjectAddress, v: Value) -> Result<(), AccessError> {
//!         if let Value::I32(v) = v { self.0 = v }
//!         Ok(())
//!     }
//! }
//!
//! let mut server = ObjectServer::new();
//! server.register(Counter(0)).unwrap();
//! let addr: ObjectAddress = "7/0/1/0".parse().unwrap();
//! server.write(addr, Value::I32(5)).unwrap();
//! assert_eq!(server.read(addr, uoi::ValueType::I32), Ok(Value::I32(5)));
//! assert_eq!(server.write(addr, Value::I32(10)), Err(AccessError::Range));
//! assert_eq!(server.write(addr, Value::F64(1.0)), Err(AccessError::TypeMismatch));
//! assert_eq!(server.read("7/0/2/0".parse().unwrap(), uoi::ValueType::I32), Err(AccessError::NoObject));
//! ```

mod address;
mod bus;
mod dictionary;
mod error;
pub mod log_limit;
mod server;
#[cfg(feature = "tcp")]
pub mod tcp;
mod value;
pub mod wire;

pub use address::{AddressParseError, ObjectAddress};
pub use bus::{check_write, Bus, ObjectBus};
pub use dictionary::{lookup, Access, Meaning, ObjectDesc, ValueRange};
pub use error::AccessError;
pub use log_limit::LogLimit;
pub use server::{ObjectServer, RegisterError};
pub use value::{Value, ValueType};
