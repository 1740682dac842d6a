//! # tc-objects — the vocabulary of bus 1300
//!
//! Every object of the TC module (devices 0 to 2) and of its OTC extension
//! (devices 3 and 4) in ONE declarative table: address, value type,
//! access, range (`uoi::ObjectDesc` rows), the meaning a user reads in
//! `docs/objects.md`, the bits of the ERROR, STATUS and OtcError
//! registers, and which objects carry a field of a tool entry. The engine
//! dispatches on these rows, the NC front end and tool persistence name
//! objects through their keys, and the object reference is generated from
//! them, so a renumbered row changes every user at once.
//!
//! ```
//! use tc_objects::{OtcObject, TcObject, ToolField};
//!
//! assert_eq!(TcObject::Radius.of(1).to_string(), "1300/1/1/6");
//! assert_eq!(TcObject::TcPlane.address().to_string(), "1300/0/3/0");
//! assert_eq!(OtcObject::WearAxis.sub_of(2, 3).to_string(), "1300/3/2/23");
//! assert_eq!(ToolField::of_address(TcObject::WkzLen.of(5)), Some(ToolField::Length));
//! ```

mod bits;
mod bus;
mod device;
mod meaning;
mod object;
mod otc;
mod otc_setting;
mod tc;
mod tool;

pub use bits::{bit_meaning, camel_name, ErrorBits, OtcErrorBits, StatusBits};
pub use bus::{
    AXIS, BOOL, COORD, GROUPS, GROUP_COUNT, MACHINE_AXES, MAX_COORD, PLANE_CODES, PLANE_XY,
    PLANE_YZ, PLANE_ZX, TC_BUS, TOOL_ENTRIES,
};
pub use device::{DeviceDesc, DEVICES};
pub use object::BusObject;
pub use otc::{
    OtcObject, OTC_AXIS_DEVICE, OTC_AXIS_OBJECTS, OTC_GROUP_DEVICE, OTC_GROUP_OBJECTS,
    WEAR_AXIS_SUBS,
};
pub use otc_setting::{OtcMode, ProcType};
pub use tc::{TcObject, TC_OBJECTS};
pub use tool::{ToolEffect, ToolField};
