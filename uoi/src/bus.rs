//! The bus a module implements, and the checked access every bus gets.

use std::any::Any;

use crate::{lookup, AccessError, ObjectAddress, ObjectDesc, Value, ValueType};

/// A module on the UOI, registered under one BusNumber.
///
/// The module declares its objects in [`Bus::objects`]; its `read` and
/// `write` are only called through [`ObjectBus`], after the address, access,
/// type and range have been checked against that table.
pub trait Bus: Send + 'static {
    /// The module's own name for an object (the `key` of its table rows).
    type Key: Copy + 'static;

    /// The BusNumber.
    fn number(&self) -> u16;

    /// The module's object table.
    fn objects(&self) -> &[ObjectDesc<Self::Key>];

    /// Reads an object that exists and is readable. The returned value must
    /// have the object's type.
    fn read(&mut self, key: Self::Key, addr: ObjectAddress) -> Result<Value, AccessError>;

    /// Writes a value that has already passed type and range checks.
    fn write(
        &mut self,
        key: Self::Key,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<(), AccessError>;
}

/// The checked, object-safe face of a [`Bus`]: what the [`crate::ObjectServer`]
/// talks to. Implemented for every `Bus`.
pub trait ObjectBus: Send + 'static {
    /// The BusNumber.
    fn bus_number(&self) -> u16;

    /// Reads `addr` asking for type `ty`: `NoObject`/`NoSubindex` for an
    /// unknown address, `WriteOnly` for a `w` object, `TypeMismatch` for the
    /// wrong type letter.
    fn read_checked(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError>;

    /// Writes `value` to `addr`: address, then access (`ReadOnly`), then
    /// type (`TypeMismatch`), then range (`Range`) are checked first.
    fn write_checked(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError>;

    /// The bus as `Any`, to reach the concrete module.
    fn as_any(&self) -> &dyn Any;

    /// The bus as mutable `Any`, to reach the concrete module.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<B: Bus> ObjectBus for B {
    fn bus_number(&self) -> u16 {
        self.number()
    }

    fn read_checked(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError> {
        if addr.bus != self.number() {
            return Err(AccessError::NoObject);
        }
        let row = lookup(self.objects(), addr)?;
        if !row.access.readable() {
            return Err(AccessError::WriteOnly);
        }
        if row.ty != ty {
            return Err(AccessError::TypeMismatch);
        }
        let key = row.key;
        self.read(key, addr)
    }

    fn write_checked(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError> {
        let key = check_write(self, addr, value)?;
        self.write(key, addr, value)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// The key of the object a write of `value` to `addr` goes to, once
/// address, then access (`ReadOnly`), then type (`TypeMismatch`), then
/// range (`Range`) are checked: the checks of
/// [`ObjectBus::write_checked`], changing nothing (for a module that plans
/// a write before it carries it out).
pub fn check_write<B: Bus + ?Sized>(
    bus: &B,
    addr: ObjectAddress,
    value: Value,
) -> Result<B::Key, AccessError> {
    if addr.bus != bus.number() {
        return Err(AccessError::NoObject);
    }
    let row = lookup(bus.objects(), addr)?;
    if !row.access.writable() {
        return Err(AccessError::ReadOnly);
    }
    if row.ty != value.value_type() {
        return Err(AccessError::TypeMismatch);
    }
    if !row.range.contains(value) {
        return Err(AccessError::Range);
    }
    Ok(row.key)
}
