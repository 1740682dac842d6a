//! Durable before acknowledged: a write that changes tool data is on disk
//! before its answer leaves, and the emulator's memory never runs ahead of
//! the disk.
//!
//! * A direct tool write (RADIUS, WkzLen, the OTC tool fields) is checked
//!   on the emulator and undone at once, so nobody sees it yet; its change
//!   goes to the writer and the request waits (`Slice::Wait`) without
//!   holding the emulator. Once the change is on disk it is applied
//!   (`resume`); if the disk refused it, the answer is `Storage` and the
//!   value stays what it was. Changes apply in the journal's order: a
//!   change older than the one a field already holds is not applied.
//! * A write that may change tool data on the side (Clean, Reset, a group
//!   RESET, OTC switched off) is rare: it is applied, its tool changes are
//!   made durable while the emulator waits, and if the disk refused them
//!   the emulator is put back as it was before the write (answer
//!   `Storage`: nothing changed).

use std::collections::HashMap;

use otc_ext::OtcExtension;
use tc_module::{TcExtension, WkzIndex};
use tc_objects::{BusObject, OtcObject, TcObject};
use tokio::sync::oneshot;
use tool_store::{GroupTable, Record, ToolField, ToolKey, ToolValue};
use uoi::tcp::{Slice, Wait};
use uoi::wire::{Answer, ProtocolError};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

use super::entries::{all_tables, changes, direct_field, entry_mut, may_change_tools, set_value};
use crate::Emulator;
use tool_store::{Done, DurableLog, Writer};

/// What the server's handler asks of tool persistence (the shared
/// emulator's; conformance sessions keep nothing).
pub trait ToolPersistence<E: TcExtension = OtcExtension>: Send + std::fmt::Debug {
    /// Serves a write if it changes tool data; `None` for any other.
    fn serve(&mut self, emu: &mut Emulator<E>, addr: ObjectAddress, value: Value) -> Option<Slice>;
    /// A direct tool write's wait is over.
    fn resume(&mut self, emu: &mut Emulator<E>, token: u64, ok: bool) -> Slice;
    /// Every queued change written; the journal compacted into the tool
    /// files (at shutdown).
    fn close(self: Box<Self>);
}

impl<J: DurableLog + std::fmt::Debug> ToolPersistence for Durable<J> {
    fn serve(&mut self, emu: &mut Emulator, addr: ObjectAddress, value: Value) -> Option<Slice> {
        Durable::serve(self, emu, addr, value)
    }

    fn resume(&mut self, emu: &mut Emulator, token: u64, ok: bool) -> Slice {
        Durable::resume(self, emu, token, ok)
    }

    fn close(self: Box<Self>) {
        if let Some(mut j) = self.stop() {
            j.close();
        }
    }
}

/// One field of one entry of one group.
type FieldKey = (u8, u16, ToolField);

/// A direct tool write waiting for the disk.
#[derive(Debug, Clone, Copy)]
struct Pending {
    group: u8,
    index: WkzIndex,
    field: ToolField,
    value: ToolValue,
}

/// The persistence of the shared emulator's tool data.
#[derive(Debug)]
pub struct Durable<J> {
    writer: Writer<J>,
    /// Number of the last change submitted (journal order).
    last: u64,
    pending: HashMap<u64, Pending>,
    /// The number of the change each field holds now.
    holds: HashMap<FieldKey, u64>,
}

impl<J: DurableLog> Durable<J> {
    /// Persistence through `writer`.
    pub fn new(writer: Writer<J>) -> Self {
        Self {
            writer,
            last: 0,
            pending: HashMap::new(),
            holds: HashMap::new(),
        }
    }

    /// Serves `req` if it is a write that changes tool data: `None` for
    /// every other request (served as before).
    pub fn serve(
        &mut self,
        emu: &mut Emulator,
        addr: ObjectAddress,
        value: Value,
    ) -> Option<Slice> {
        if let Some(field) = direct_field(addr) {
            return Some(self.direct(emu, addr, value, field));
        }
        may_change_tools(addr, value).then(|| Slice::Done(self.indirect(emu, addr, value)))
    }

    /// A direct tool write: checked, undone, and sent to the disk.
    fn direct(
        &mut self,
        emu: &mut Emulator,
        addr: ObjectAddress,
        value: Value,
        field: ToolField,
    ) -> Slice {
        // The table refuses a group index outside 1..=32 (`NoObject`).
        let group = u8::try_from(addr.index).unwrap_or(0);
        let index = emu
            .tc()
            .group_at(addr.index)
            .map_or(WkzIndex::new(0), |g| Some(g.wkz));
        let (Some(index), Some(before)) = (index, index.and_then(|i| current(emu, group, i)))
        else {
            return Slice::Done(answer(emu.write(addr, value)));
        };
        if let Err(e) = emu.write(addr, value) {
            return Slice::Done(Answer::Access(e));
        }
        let Some(entry) = entry_mut(emu.tc_mut(), group, index) else {
            return Slice::Done(Answer::Access(AccessError::NoObject));
        };
        let new = super::entries::value_of(entry, field);
        *entry = before;
        let Some(key) = ToolKey::new(index.get() as u16, field) else {
            return Slice::Done(Answer::Access(AccessError::NoObject));
        };
        self.last += 1;
        let token = self.last;
        let change = Pending {
            group,
            index,
            field,
            value: new,
        };
        self.pending.insert(token, change);
        let (tx, rx) = oneshot::channel();
        let record = Record::Set {
            group,
            key,
            value: new,
        };
        self.writer.submit(vec![record], Done::Async(tx));
        Slice::Wait(Wait { done: rx, token })
    }

    /// A direct tool write is on disk (`ok`) or refused: applied if no
    /// newer change holds the field, answered.
    pub fn resume(&mut self, emu: &mut Emulator, token: u64, ok: bool) -> Slice {
        let Some(p) = self.pending.remove(&token) else {
            return Slice::Done(Answer::Protocol(ProtocolError::Busy));
        };
        if !ok {
            return Slice::Done(Answer::Access(AccessError::Storage));
        }
        let key = (p.group, p.index.get() as u16, p.field);
        if self.holds.get(&key).is_none_or(|&held| held < token) {
            if let Some(e) = entry_mut(emu.tc_mut(), p.group, p.index) {
                set_value(e, p.field, p.value);
            }
            self.holds.insert(key, token);
        }
        Slice::Done(Answer::Ok)
    }

    /// A write that may change tool data on the side: applied; its tool
    /// changes made durable before the answer, or the whole write undone
    /// (the emulator as it was before it: these writes are rare, a copy of
    /// the emulator is affordable).
    fn indirect(&mut self, emu: &mut Emulator, addr: ObjectAddress, value: Value) -> Answer {
        // Compared with the memory plus the changes still on their way, so
        // that the journal ends as memory does.
        let mut expected = all_tables(emu.tc());
        for p in self.pending.values() {
            if let (Some(t), Some(key)) = (
                expected.get_mut(usize::from(p.group) - 1),
                ToolKey::new(p.index.get() as u16, p.field),
            ) {
                t.set(key, p.value);
            }
        }
        if !may_touch_tools(emu, addr, &expected) {
            return answer(emu.write(addr, value));
        }
        let saved = emu.clone();
        if let Err(e) = emu.write(addr, value) {
            return Answer::Access(e);
        }
        let records = changes(emu.tc(), &expected);
        if records.is_empty() {
            return Answer::Ok;
        }
        self.last += 1;
        if !self.writer.write_blocking(records.clone()) {
            *emu = saved;
            return Answer::Access(AccessError::Storage);
        }
        warn_group_reset(addr, &expected);
        for r in &records {
            if let Record::Set { group, key, .. } = r {
                self.holds.insert((*group, key.index, key.field), self.last);
            }
        }
        Answer::Ok
    }

    /// Stops the writer once every queued change is written; gives the
    /// journal back.
    pub fn stop(self) -> Option<J> {
        self.writer.stop()
    }
}

/// Whether the side-effect write to `addr` can change tool data, given
/// the tool data `expected` (memory plus changes on their way): a RESET or
/// Clean of tables that hold nothing cannot, nor can OTC OFF of a group
/// whose OTC is off. Such writes then need no copy of the emulator.
fn may_touch_tools(emu: &mut Emulator, addr: ObjectAddress, expected: &[GroupTable]) -> bool {
    let group = |i: u16| expected.get(usize::from(i).wrapping_sub(1));
    match BusObject::at(addr) {
        Some(BusObject::Tc(TcObject::GroupReset)) => {
            group(addr.index).is_some_and(|t| !t.is_empty())
        }
        Some(BusObject::Otc(OtcObject::OtcOn)) => {
            emu.read(addr, ValueType::I32) == Ok(Value::I32(1))
        }
        _ => expected.iter().any(|t| !t.is_empty()),
    }
}

/// A group RESET rejects the programmed tool values and, as the legacy
/// module did, clears the group's tool table, persisted one included
/// (docs/tool-files.md): said in the log with the group and how many
/// entries held values (decision 321).
fn warn_group_reset(addr: ObjectAddress, before: &[GroupTable]) {
    if BusObject::at(addr) != Some(BusObject::Tc(TcObject::GroupReset)) {
        return;
    }
    let Some(table) = before.get(usize::from(addr.index).wrapping_sub(1)) else {
        return;
    };
    let mut entries: Vec<u16> = table.iter().map(|(key, _)| key.index).collect();
    entries.sort_unstable();
    entries.dedup();
    tracing::warn!(
        group = addr.index,
        entries = entries.len(),
        "group RESET: the tool table of group {} is cleared, {} entries back at their \
         defaults, on disk too",
        addr.index,
        entries.len()
    );
}

/// The entry at (`group`, `index`) as it is now (its group created).
fn current(
    emu: &mut Emulator,
    group: u8,
    index: WkzIndex,
) -> Option<tc_module::ToolEntry<otc_ext::OtcTool>> {
    entry_mut(emu.tc_mut(), group, index).map(|e| *e)
}

/// The answer to a write.
fn answer(r: Result<(), AccessError>) -> Answer {
    r.map_or_else(Answer::Access, |()| Answer::Ok)
}
