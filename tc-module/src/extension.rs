//! The hook through which an extension (OTC, in `otc-ext`) serves the
//! objects of devices 3 and 4 and follows what the TC module does.

use std::fmt::Debug;

use uoi::{AccessError, ObjectAddress, Value};

use crate::group::CorrGroup;
use crate::object_map::OtcObject;
use crate::tool_table::WkzIndex;

/// The compensation group an access to device 3 addresses.
#[derive(Debug)]
pub struct GroupContext<'a> {
    /// Group number 1..=32.
    pub index: u16,
    /// The group (created on first access, like every group).
    pub group: &'a mut CorrGroup,
    /// Whether its correction runs (STATUS bit Run).
    pub running: bool,
}

/// An extension of the TC module. The table in `object_map` declares its
/// objects; type, access and range are checked before these calls.
pub trait TcExtension: Send + Debug + 'static {
    /// Reads an object of device 3 (`group` is `Some`) or 4 (`None`).
    fn read(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        group: Option<GroupContext<'_>>,
    ) -> Result<Value, AccessError>;

    /// Writes an object of device 3 (`group` is `Some`) or 4 (`None`).
    fn write(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        value: Value,
        group: Option<GroupContext<'_>>,
    ) -> Result<(), AccessError>;

    /// WKZINDEX of `group` changed from `outgoing` (the tool handed back)
    /// to `incoming`.
    fn tool_changed(&mut self, _group: u16, _outgoing: WkzIndex, _incoming: WkzIndex) {}

    /// The group RESET of `group` (its tool table entries go back to default).
    fn group_reset(&mut self, _group: u16) {}

    /// Device 0 Clean: everything back to defaults.
    fn clean(&mut self) {}

    /// A position request (`JA`, `JS`, ReInit) is about to happen; an error
    /// refuses it.
    fn position_request(&mut self) -> Result<(), AccessError> {
        Ok(())
    }
}

/// No extension: devices 3 and 4 do not exist (`NoObject`).
#[derive(Debug, Default, Clone, Copy)]
pub struct NoExtension;

impl TcExtension for NoExtension {
    fn read(
        &mut self,
        _: OtcObject,
        _: ObjectAddress,
        _: Option<GroupContext<'_>>,
    ) -> Result<Value, AccessError> {
        Err(AccessError::NoObject)
    }

    fn write(
        &mut self,
        _: OtcObject,
        _: ObjectAddress,
        _: Value,
        _: Option<GroupContext<'_>>,
    ) -> Result<(), AccessError> {
        Err(AccessError::NoObject)
    }
}
