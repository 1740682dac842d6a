//! The emulator's tool entries as the tool store sees them: which object
//! writes set a tool field directly, the value of a field in an entry, and
//! the whole tool data as store tables (to load, compare and save).

use otc_ext::{OtcExtension, OtcTool};
use tc_module::{TcModule, ToolEntry, WkzIndex};
use tool_store::{GroupTable, Record, ToolField, ToolKey, ToolValue, TOOL_ENTRIES};
use uoi::{ObjectAddress, Value};

/// Each tool field and the (device, sub) of the group object that sets it
/// in the entry at the group's WKZINDEX: RADIUS, WkzLen and the OTC tool
/// fields 30..33.
const FIELD_OBJECTS: [(ToolField, u16, u16); 6] = [
    (ToolField::Radius, 1, 6),
    (ToolField::Laenge, 1, 12),
    (ToolField::Typ, 3, 30),
    (ToolField::GrindingWearConst, 3, 31),
    (ToolField::GrindingMaxInfeed, 3, 32),
    (ToolField::GrindingDiscTiltAngle, 3, 33),
];

/// The tool field a write to `addr` sets directly, if any.
pub fn direct_field(addr: ObjectAddress) -> Option<ToolField> {
    if addr.bus != tc_module::TC_BUS {
        return None;
    }
    FIELD_OBJECTS
        .iter()
        .find(|(_, d, s)| (*d, *s) == (addr.device, addr.sub))
        .map(|(f, _, _)| *f)
}

/// The object of `group` that writes `field` (the inverse of
/// [`direct_field`]).
pub fn field_object(group: u8, field: ToolField) -> ObjectAddress {
    let (_, device, sub) = FIELD_OBJECTS
        .iter()
        .copied()
        .find(|(f, _, _)| *f == field)
        .unwrap_or(FIELD_OBJECTS[0]);
    ObjectAddress::new(tc_module::TC_BUS, device, u16::from(group), sub)
}

/// Whether writing `value` to `addr` may change tool data other than
/// through one field: Clean (0/1), Reset (0/12), a group RESET (1/g/2)
/// and OTC switched off (3/g/1 = 0, the wear booked on the tool).
pub fn may_change_tools(addr: ObjectAddress, value: Value) -> bool {
    addr.bus == tc_module::TC_BUS
        && match (addr.device, addr.index, addr.sub) {
            (0, 1, 0) | (0, 12, 0) | (1, _, 2) => true,
            (3, _, 1) => value != Value::I32(1),
            _ => false,
        }
}

/// The value of `field` in entry `e`.
pub fn value_of(e: &ToolEntry<OtcTool>, field: ToolField) -> ToolValue {
    match field {
        ToolField::Typ => ToolValue::I32(e.ext.tool_type),
        ToolField::Radius => ToolValue::F64(e.radius),
        ToolField::Laenge => ToolValue::F64(e.length),
        ToolField::GrindingWearConst => ToolValue::F64(e.ext.wear_const),
        ToolField::GrindingMaxInfeed => ToolValue::F64(e.ext.max_infeed),
        ToolField::GrindingDiscTiltAngle => ToolValue::F64(e.ext.tilt),
    }
}

/// Sets `field` of entry `e` (a value of the other kind is taken as its
/// number).
pub fn set_value(e: &mut ToolEntry<OtcTool>, field: ToolField, value: ToolValue) {
    let f = match value {
        ToolValue::F64(v) => v,
        ToolValue::I32(v) => f64::from(v),
    };
    match field {
        ToolField::Typ => {
            e.ext.tool_type = match value {
                ToolValue::I32(v) => v,
                // Within the field's range 0..=3 once checked by the store.
                ToolValue::F64(v) => v as i32,
            }
        }
        ToolField::Radius => e.radius = f,
        ToolField::Laenge => e.length = f,
        ToolField::GrindingWearConst => e.ext.wear_const = f,
        ToolField::GrindingMaxInfeed => e.ext.max_infeed = f,
        ToolField::GrindingDiscTiltAngle => e.ext.tilt = f,
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

/// The records that turn tables `before` (index = group − 1) into the
/// emulator's tool data now: every value that differs, bit for bit.
pub fn changes(tc: &TcModule<OtcExtension>, before: &[GroupTable]) -> Vec<Record> {
    let mut out = Vec::new();
    for (slot, old) in before.iter().enumerate() {
        // At most 32 tables.
        let group = slot as u8 + 1;
        let new = table_of(tc, group);
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
