//! The `Bus` face of the TC module: each row of the map goes to its owner,
//! the module's registers or the extension.

use uoi::{AccessError, Bus, ObjectAddress, ObjectDesc, Value};

use super::registers::slot_of;
use super::TcModule;
use crate::extension::{Groups, TcExtension};
use crate::object_map::TcKey;
use tc_objects::TC_BUS;

impl<E: TcExtension> Bus for TcModule<E> {
    type Key = TcKey<E::Key>;

    fn number(&self) -> u16 {
        TC_BUS
    }

    fn objects(&self) -> &[ObjectDesc<Self::Key>] {
        &self.table
    }

    fn read(&mut self, key: Self::Key, addr: ObjectAddress) -> Result<Value, AccessError> {
        match key {
            TcKey::Tc(obj) => self.read_register(obj, addr),
            TcKey::Group(k) => {
                self.group_mut(slot_of(addr));
                let main = self.main_axes();
                let groups = Groups::new(&mut self.groups[..], self.running, main);
                self.ext.read_group(k, addr, groups)
            }
            TcKey::Ext(k) => {
                let main = self.main_axes();
                let groups = Groups::new(&mut self.groups[..], self.running, main);
                self.ext.read(k, addr, groups)
            }
        }
    }

    /// A write planned and applied at once ([`TcModule::apply`]): the
    /// one route of every write.
    fn write(
        &mut self,
        key: Self::Key,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<(), AccessError> {
        let plan = self.plan_key(key, addr, value)?;
        self.apply(plan)
    }
}
