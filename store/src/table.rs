//! The tool values of one compensation group, keyed by entry and field.

use crate::field::{FileField, ToolField, ToolValue};
use std::collections::BTreeMap;
use std::ops::RangeInclusive;

/// Compensation group numbers: one tool file each (the groups of bus
/// 1300, 1..=32).
pub const GROUPS: RangeInclusive<u8> = 1..=tc_objects::GROUP_COUNT as u8;

/// Entries of a tool table (WKZINDEX 0..=1023).
pub const TOOL_ENTRIES: u16 = tc_objects::TOOL_ENTRIES as u16;

/// One field of one tool entry of a group: `wz[index].field`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ToolKey {
    /// The entry, WKZINDEX 0..=1023.
    pub index: u16,
    /// The field.
    pub field: ToolField,
}

impl ToolKey {
    /// The key `wz[index].field`; `None` if `index` is 1024 or more.
    pub fn new(index: u16, field: ToolField) -> Option<Self> {
        (index < TOOL_ENTRIES).then_some(Self { index, field })
    }
}

impl std::fmt::Display for ToolKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "wz[{}].{}", self.index, self.field.name())
    }
}

/// The tool table of one group. Only values that differ from the field's
/// default (bit for bit, so `-0.0` is kept) are held; a missing key reads
/// as the default.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GroupTable {
    values: BTreeMap<ToolKey, ToolValue>,
}

impl GroupTable {
    /// An empty table: every field at its default.
    pub fn new() -> Self {
        Self::default()
    }

    /// The value of `key` (the default if never set).
    pub fn get(&self, key: ToolKey) -> ToolValue {
        self.values
            .get(&key)
            .copied()
            .unwrap_or(key.field.default_value())
    }

    /// Sets `key` to `value` (setting the default removes the key).
    pub fn set(&mut self, key: ToolKey, value: ToolValue) {
        if value == key.field.default_value() {
            self.values.remove(&key);
        } else {
            self.values.insert(key, value);
        }
    }

    /// Every entry back to its defaults (group RESET).
    pub fn clear(&mut self) {
        self.values.clear();
    }

    /// True if every field is at its default.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Number of fields that differ from their default.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// The values that differ from their default, sorted by index, then
    /// field.
    pub fn iter(&self) -> impl Iterator<Item = (ToolKey, ToolValue)> + '_ {
        self.values.iter().map(|(k, v)| (*k, *v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(i: u16, f: ToolField) -> ToolKey {
        ToolKey::new(i, f).unwrap()
    }

    #[test]
    fn key_bounds() {
        assert!(ToolKey::new(1023, ToolField::ToolType).is_some());
        assert!(ToolKey::new(1024, ToolField::ToolType).is_none());
        assert_eq!(key(5, ToolField::Radius).to_string(), "wz[5].radius");
    }

    #[test]
    fn default_values_are_not_kept_but_negative_zero_is() {
        let mut t = GroupTable::new();
        t.set(key(1, ToolField::Radius), ToolValue::F64(3.0));
        t.set(key(1, ToolField::Radius), ToolValue::F64(0.0));
        assert!(t.is_empty());
        t.set(key(2, ToolField::Length), ToolValue::F64(-0.0));
        assert_eq!(t.len(), 1);
        assert_eq!(t.get(key(2, ToolField::Length)), ToolValue::F64(-0.0));
        assert_eq!(t.get(key(3, ToolField::ToolType)), ToolValue::I32(0));
        t.clear();
        assert!(t.is_empty());
    }

    #[test]
    fn iteration_is_sorted_by_index_then_field() {
        let mut t = GroupTable::new();
        t.set(key(7, ToolField::ToolType), ToolValue::I32(2));
        t.set(key(1, ToolField::Length), ToolValue::F64(1.0));
        t.set(key(1, ToolField::ToolType), ToolValue::I32(1));
        let keys: Vec<_> = t.iter().map(|(k, _)| k.to_string()).collect();
        assert_eq!(keys, ["wz[1].typ", "wz[1].laenge", "wz[7].typ"]);
    }
}
