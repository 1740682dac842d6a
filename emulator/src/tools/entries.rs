//! The emulator's tool entries as the tool store sees them: which object
//! writes set a tool field directly, the value of a field in an entry, and
//! the whole tool data as store tables (to load, compare and save).

use otc_ext::{OtcExtension, OtcTool, TenthMicrons, TiltAngle, WearRate};
use tc_module::{TcModule, ToolChange, ToolEntry, WkzIndex};
use tc_objects::ToolEffect;
use tool_store::{FileField, GroupTable, Record, ToolField, ToolKey, ToolValue, TOOL_ENTRIES};
use uoi::{ObjectAddress, Value};

/// The tool field a write to `addr` sets directly, if any (RADIUS,
/// WkzLen and the OTC tool fields of the entry at the group's WKZINDEX).
pub fn direct_field(addr: ObjectAddress) -> Option<ToolField> {
    ToolField::of_address(addr)
}

/// The object of `group` that writes `field` (the inverse of
/// [`direct_field`]).
pub fn field_object(group: u8, field: ToolField) -> ObjectAddress {
    field.address(u16::from(group))
}

/// Whether writing `value` to `addr` may change tool data other than
/// through one field: Clean, Reset, a group RESET and OTC switched off
/// (the wear booked on the tool).
pub fn may_change_tools(addr: ObjectAddress, value: Value) -> bool {
    ToolEffect::of_write(addr, value) == ToolEffect::Many
}

/// The value of `field` in entry `e`.
pub fn value_of(e: &ToolEntry<OtcTool>, field: ToolField) -> ToolValue {
    match field {
        ToolField::ToolType => ToolValue::I32(e.ext.tool_type),
        ToolField::Radius => ToolValue::F64(e.radius),
        ToolField::Length => ToolValue::F64(e.length),
        ToolField::WearConst => ToolValue::F64(e.ext.wear_const.0),
        ToolField::MaxInfeed => ToolValue::F64(e.ext.max_infeed.0),
        ToolField::TiltAngle => ToolValue::F64(e.ext.tilt.0),
    }
}

/// Sets `field` of entry `e` (a value of the other kind is taken as its
/// number): tool data loaded from the tool files at start, before the
/// emulator serves (a write goes through the module's plan and apply).
fn set_value(e: &mut ToolEntry<OtcTool>, field: ToolField, value: ToolValue) {
    let f = match value {
        ToolValue::F64(v) => v,
        ToolValue::I32(v) => f64::from(v),
    };
    match field {
        ToolField::ToolType => {
            e.ext.tool_type = match value {
                ToolValue::I32(v) => v,
                // Within the field's range 0..=3 once checked by the store.
                ToolValue::F64(v) => v as i32,
            }
        }
        ToolField::Radius => e.radius = f,
        ToolField::Length => e.length = f,
        ToolField::WearConst => e.ext.wear_const = WearRate(f),
        ToolField::MaxInfeed => e.ext.max_infeed = TenthMicrons(f),
        ToolField::TiltAngle => e.ext.tilt = TiltAngle(f),
    }
}

/// The tool entry at (`group`, `index`), created with its group.
pub fn entry_mut(
    tc: &mut TcModule<OtcExtension>,
    group: u8,
    index: WkzIndex,
) -> Option<&mut ToolEntry<OtcTool>> {
    Some(tc.tools_mut(u16::from(group))?.entry_mut(index))
}

/// The tool data of group `group` as a store table (only values that
/// differ from the defaults).
pub fn table_of(tc: &TcModule<OtcExtension>, group: u8) -> GroupTable {
    let mut t = GroupTable::new();
    let Some(g) = tc.group_at(u16::from(group)) else {
        return t;
    };
    let default = ToolEntry::<OtcTool>::default();
    for i in 0..TOOL_ENTRIES {
        let Some(w) = WkzIndex::new(i32::from(i)) else {
            continue;
        };
        let e = g.tools.entry(w);
        if *e == default {
            continue;
        }
        for field in ToolField::ALL {
            if let Some(key) = ToolKey::new(i, field) {
                t.set(key, value_of(e, field));
            }
        }
    }
    t
}

/// The records that turn tables `before` into tables `after` (index =
/// group − 1): every value that differs, bit for bit.
pub fn changes(after: &[GroupTable], before: &[GroupTable]) -> Vec<Record> {
    let mut out = Vec::new();
    for (slot, (old, new)) in before.iter().zip(after).enumerate() {
        // At most 32 tables.
        let group = slot as u8 + 1;
        for (key, value) in new.iter() {
            if old.get(key) != value {
                out.push(Record::Set { group, key, value });
            }
        }
        // Keys gone from the new table are back at their default.
        for (key, value) in old.iter() {
            let now = new.get(key);
            if now != value && now == key.field.default_value() {
                out.push(Record::Set {
                    group,
                    key,
                    value: now,
                });
            }
        }
    }
    out
}

/// The tool data of every group as store tables (index = group − 1) as
/// a planned write leaves it: the emulator's now, with `change`.
pub fn tables_after(tc: &TcModule<OtcExtension>, change: &ToolChange<OtcTool>) -> Vec<GroupTable> {
    let mut tables = all_tables(tc);
    let slot = |g: u16| usize::from(g).wrapping_sub(1);
    match *change {
        ToolChange::None => {}
        ToolChange::AllCleared => tables.iter_mut().for_each(GroupTable::clear),
        ToolChange::GroupCleared(g) => {
            if let Some(t) = tables.get_mut(slot(g)) {
                t.clear();
            }
        }
        ToolChange::Field {
            group,
            index,
            ref entry,
        }
        | ToolChange::Entry {
            group,
            index,
            ref entry,
        } => {
            let Some(t) = tables.get_mut(slot(group)) else {
                return tables;
            };
            for field in ToolField::ALL {
                // A WkzIndex is below TOOL_ENTRIES.
                if let Some(key) = ToolKey::new(index.get() as u16, field) {
                    t.set(key, value_of(entry, field));
                }
            }
        }
    }
    tables
}

/// The tool data of every group as store tables (index = group − 1) as
/// a planned write with side effects leaves it, over `expected` (the
/// emulator's now plus the changes still on their way to the disk): a
/// Clean or a group RESET clears those too, as it clears memory; an entry
/// the write changes on the side (OTC OFF booking its wear) takes only
/// the fields the write changes, so a change on its way to another
/// field, entry or group stays as it is (decision 489).
pub fn tables_planned(
    expected: &[GroupTable],
    tc: &TcModule<OtcExtension>,
    change: &ToolChange<OtcTool>,
) -> Vec<GroupTable> {
    let mut tables = expected.to_vec();
    match *change {
        ToolChange::None => {}
        ToolChange::AllCleared => tables.iter_mut().for_each(GroupTable::clear),
        ToolChange::GroupCleared(g) => {
            if let Some(t) = tables.get_mut(usize::from(g).wrapping_sub(1)) {
                t.clear();
            }
        }
        ToolChange::Field { .. } | ToolChange::Entry { .. } => {
            let written = changes(&tables_after(tc, change), &all_tables(tc));
            for r in written {
                if let Record::Set { group, key, value } = r {
                    if let Some(t) = tables.get_mut(usize::from(group).wrapping_sub(1)) {
                        t.set(key, value);
                    }
                }
            }
        }
    }
    tables
}

/// The tool data of every group as store tables (index = group − 1).
pub fn all_tables(tc: &TcModule<OtcExtension>) -> Vec<GroupTable> {
    tool_store::GROUPS.map(|g| table_of(tc, g)).collect()
}

/// Loads tool values `(group, entry and field, value)` into the emulator;
/// fields not named keep their values.
pub fn load(
    tc: &mut TcModule<OtcExtension>,
    values: impl Iterator<Item = (u8, ToolKey, ToolValue)>,
) {
    for (group, key, value) in values {
        let Some(w) = WkzIndex::new(i32::from(key.index)) else {
            continue;
        };
        if let Some(e) = entry_mut(tc, group, w) {
            set_value(e, key.field, value);
        }
    }
}
