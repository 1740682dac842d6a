//! The object server core: routes an access to the bus registered under its
//! BusNumber.

use crate::{AccessError, ObjectAddress, ObjectBus, Value, ValueType};

/// Why a bus could not be registered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("bus {0} is already registered")]
pub struct RegisterError(pub u16);

/// Holds the registered buses and routes each access by BusNumber.
/// An access to a bus nobody registered fails with `NoObject`.
#[derive(Default)]
pub struct ObjectServer {
    buses: Vec<Box<dyn ObjectBus>>,
}

impl ObjectServer {
    /// An empty server.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers a bus under its own number.
    pub fn register<B: ObjectBus>(&mut self, bus: B) -> Result<(), RegisterError> {
        let number = bus.bus_number();
        if self.buses.iter().any(|b| b.bus_number() == number) {
            return Err(RegisterError(number));
        }
        self.buses.push(Box::new(bus));
        Ok(())
    }

    fn route(&mut self, bus: u16) -> Result<&mut dyn ObjectBus, AccessError> {
        self.buses
            .iter_mut()
            .find(|b| b.bus_number() == bus)
            .map(|b| b.as_mut())
            .ok_or(AccessError::NoObject)
    }

    /// Reads an object, asking for type `ty`.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError> {
        self.route(addr.bus)?.read_checked(addr, ty)
    }

    /// Writes an object.
    pub fn write(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError> {
        self.route(addr.bus)?.write_checked(addr, value)
    }

    /// The registered module of type `T`, if any.
    pub fn module<T: 'static>(&self) -> Option<&T> {
        self.buses
            .iter()
            .find_map(|b| b.as_any().downcast_ref::<T>())
    }

    /// The registered module of type `T`, mutable, if any.
    pub fn module_mut<T: 'static>(&mut self) -> Option<&mut T> {
        self.buses
            .iter_mut()
            .find_map(|b| b.as_any_mut().downcast_mut::<T>())
    }
}
