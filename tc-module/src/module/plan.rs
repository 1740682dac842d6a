//! A write planned, then applied: [`TcModule::plan_write`] checks a write
//! (the table's address, access, type and range, then the module's rules
//! for tool data: the entry at WKZINDEX, the field written) and says what
//! it would change of the tool data, changing nothing; [`TcModule::apply`]
//! carries a plan out. Every write takes this one route: the bus's
//! `write` is a plan applied at once, and durable tool data plans a
//! write, makes its change durable, then applies the plan
//! (docs/tool-files.md; docs/decisions.md, decision 480).

use uoi::{check_write, AccessError, ObjectAddress, Value};

use super::registers::slot_of;
use super::TcModule;
use crate::extension::{Groups, TcExtension};
use crate::object_map::TcKey;
use crate::tool_table::{ToolEntry, WkzIndex};
use tc_objects::TcObject;

/// What a write would change of the tool data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ToolChange<T> {
    /// Nothing.
    None,
    /// One field of entry `index` of group `group` (RADIUS, WkzLen, an
    /// extension's tool field): the entry as the write leaves it. The
    /// field is set on that entry when the plan is applied, whatever the
    /// group's WKZINDEX is by then.
    Field {
        /// The group (1..=32).
        group: u16,
        /// The entry (the group's WKZINDEX when planned).
        index: WkzIndex,
        /// The entry after the write.
        entry: ToolEntry<T>,
    },
    /// Entry `index` of group `group` changed on the side (OTC switched
    /// off books the wear on it): the entry as the write leaves it.
    Entry {
        /// The group (1..=32).
        group: u16,
        /// The group's WKZINDEX.
        index: WkzIndex,
        /// The entry after the write.
        entry: ToolEntry<T>,
    },
    /// Every entry of group `group` back at its default (group RESET).
    GroupCleared(u16),
    /// Every entry of every group back at its default (Clean, Reset).
    AllCleared,
}

/// A write checked and planned; nothing has changed yet
/// ([`TcModule::apply`] carries it out).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WritePlan<K, T> {
    key: TcKey<K>,
    addr: ObjectAddress,
    value: Value,
    /// What the write changes of the tool data.
    pub tools: ToolChange<T>,
}

impl<K, T> WritePlan<K, T> {
    /// The object written.
    pub fn address(&self) -> ObjectAddress {
        self.addr
    }

    /// The value written.
    pub fn value(&self) -> Value {
        self.value
    }
}

/// The plan of a write to the module with extension `E`.
pub type Plan<E> = WritePlan<<E as TcExtension>::Key, <E as TcExtension>::Tool>;

/// Sets the tool field object `key` writes in `entry`; `false` when `key`
/// is no tool field.
fn set_field<E: TcExtension>(
    key: TcKey<E::Key>,
    value: Value,
    entry: &mut ToolEntry<E::Tool>,
) -> bool {
    let d = || value.as_f64().unwrap_or(0.0);
    match key {
        TcKey::Tc(TcObject::Radius) => entry.radius = d(),
        TcKey::Tc(TcObject::WkzLen) => entry.length = d(),
        TcKey::Group(k) => return E::write_tool(k, value, &mut entry.ext),
        _ => return false,
    }
    true
}

impl<E: TcExtension> TcModule<E> {
    /// Checks a write of `value` to `addr` and plans it, changing nothing:
    /// the refusals of the object table (`NoObject`, `NoSubindex`,
    /// `ReadOnly`, `TypeMismatch`, `Range`, in this order), then those of
    /// the tool data (a wear booking the entry refuses: `Range`). Rules
    /// that leave a trace when they refuse (InitError, a position request
    /// refused) act when the plan is applied.
    pub fn plan_write(&self, addr: ObjectAddress, value: Value) -> Result<Plan<E>, AccessError> {
        let key = check_write(self, addr, value)?;
        self.plan_key(key, addr, value)
    }

    /// The plan of a checked write to the object of `key`.
    pub(super) fn plan_key(
        &self,
        key: TcKey<E::Key>,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<Plan<E>, AccessError> {
        let tools = match key {
            TcKey::Tc(TcObject::Clean | TcObject::Reset) => ToolChange::AllCleared,
            TcKey::Tc(TcObject::GroupReset) => ToolChange::GroupCleared(addr.index),
            TcKey::Tc(_) | TcKey::Group(_) => self.entry_change(key, addr, value)?,
            TcKey::Ext(_) => ToolChange::None,
        };
        Ok(WritePlan {
            key,
            addr,
            value,
            tools,
        })
    }

    /// What a write to a register of the group at `addr.index` changes of
    /// the entry at its WKZINDEX.
    fn entry_change(
        &self,
        key: TcKey<E::Key>,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<ToolChange<E::Tool>, AccessError> {
        let slot = slot_of(addr);
        let group = self.groups.get(slot).and_then(|g| g.as_deref());
        let index = group.map_or(WkzIndex::default(), |g| g.wkz);
        let mut entry = group.map_or(ToolEntry::default(), |g| *g.tool());
        if set_field::<E>(key, value, &mut entry) {
            return Ok(ToolChange::Field {
                group: addr.index,
                index,
                entry,
            });
        }
        let (TcKey::Group(k), Some(g)) = (key, group) else {
            return Ok(ToolChange::None);
        };
        let running = self.running == Some(slot);
        Ok(
            match self
                .ext
                .tool_after(k, value, g, running, self.main_axes())?
            {
                Some(entry) => ToolChange::Entry {
                    group: addr.index,
                    index,
                    entry,
                },
                None => ToolChange::None,
            },
        )
    }

    /// Carries out a write planned by [`TcModule::plan_write`]: a tool
    /// field is set on the entry planned; every other write acts with all
    /// its rules. Any write may stop the extension's model (OTC OFF,
    /// Clean).
    pub fn apply(&mut self, plan: Plan<E>) -> Result<(), AccessError> {
        let result = match plan.tools {
            ToolChange::Field { group, index, .. } => {
                if let Some(t) = self.tools_mut(group) {
                    set_field::<E>(plan.key, plan.value, t.entry_mut(index));
                }
                Ok(())
            }
            _ => self.carry_out(plan.key, plan.addr, plan.value),
        };
        self.sync_offset();
        result
    }

    /// A write other than a tool field's, to its owner.
    fn carry_out(
        &mut self,
        key: TcKey<E::Key>,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<(), AccessError> {
        match key {
            TcKey::Tc(obj) => self.write_global(obj, addr, value),
            TcKey::Group(k) => {
                self.group_mut(slot_of(addr));
                let main = self.main_axes();
                let groups = Groups::new(&mut self.groups[..], self.running, main);
                self.ext.write_group(k, addr, value, groups)
            }
            TcKey::Ext(k) => {
                let main = self.main_axes();
                let groups = Groups::new(&mut self.groups[..], self.running, main);
                self.ext.write(k, addr, value, groups)
            }
        }
    }
}
