//! Durable before acknowledged: a write that changes tool data is on disk
//! before its answer leaves, and the emulator's memory never runs ahead of
//! the disk.
//!
//! Every write is planned first ([`Emulator::plan`]): checked, and what it
//! would change of the tool data said, nothing changed. The plan is
//! applied ([`Emulator::apply`], the route of every write) once its
//! change is on disk (docs/decisions.md, decision 480).
//!
//! * A direct tool write (RADIUS, WkzLen, the OTC tool fields): its
//!   change goes to the writer and the request waits (`Slice::Wait`)
//!   without holding the emulator. Once the change is on disk the plan is
//!   applied (`resume`); if the disk refused it, the answer is `Storage`
//!   and the value stays what it was. Changes apply in the journal's
//!   order: a change older than the one a field already holds is not
//!   applied.
//! * A write that may change tool data on the side (Clean, Reset, a group
//!   RESET, OTC switched off) is rare: its planned tool changes are made
//!   durable while the emulator waits, then it is applied; if the disk
//!   refused them, it is not applied (answer `Storage`: nothing changed).

use std::collections::HashMap;

use otc_ext::OtcExtension;
use tc_module::{Plan, TcExtension, ToolChange, WkzIndex};
use tc_objects::{BusObject, OtcObject, TcObject};
use tokio::sync::oneshot;
use tool_store::{GroupTable, Record, ToolField, ToolKey, ToolValue};
use uoi::tcp::{Slice, Wait};
use uoi::wire::{Answer, ProtocolError};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

use super::entries::{
    all_tables, changes, direct_field, may_change_tools, tables_planned, value_of,
};
use crate::serving::ExecRest;
use crate::Emulator;
use tool_store::{Done, DurableLog, Writer};

/// What the server's handler asks of tool persistence (the shared
/// emulator's; conformance sessions keep nothing).
pub trait ToolPersistence<E: TcExtension = OtcExtension>: Send + std::fmt::Debug {
    /// Serves a write if it changes tool data; `None` for any other.
    fn serve(
        &mut self,
        emu: &mut Emulator<E>,
        addr: ObjectAddress,
        value: Value,
    ) -> Option<Slice<ExecRest>>;
    /// A direct tool write's wait is over.
    fn resume(&mut self, emu: &mut Emulator<E>, token: u64, ok: bool) -> Slice<ExecRest>;
    /// Every queued change written; the journal compacted into the tool
    /// files (at shutdown).
    fn close(self: Box<Self>);
}

impl<J: DurableLog + std::fmt::Debug> ToolPersistence for Durable<J> {
    fn serve(
        &mut self,
        emu: &mut Emulator,
        addr: ObjectAddress,
        value: Value,
    ) -> Option<Slice<ExecRest>> {
        Durable::serve(self, emu, addr, value)
    }

    fn resume(&mut self, emu: &mut Emulator, token: u64, ok: bool) -> Slice<ExecRest> {
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

/// A direct tool write waiting for the disk: its plan, applied once the
/// change is on disk, and the change as journaled.
#[derive(Debug, Clone, Copy)]
struct Pending {
    plan: Plan<OtcExtension>,
    group: u8,
    key: ToolKey,
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

    /// Serves a write if it changes tool data: `None` for every other
    /// request (served as before). The write is planned first: refused,
    /// it is answered at once and changes nothing.
    pub fn serve(
        &mut self,
        emu: &mut Emulator,
        addr: ObjectAddress,
        value: Value,
    ) -> Option<Slice<ExecRest>> {
        let field = direct_field(addr);
        if field.is_none() && !may_change_tools(addr, value) {
            return None;
        }
        let plan = match emu.plan(addr, value) {
            Ok(plan) => plan,
            Err(e) => return Some(Slice::Done(Answer::Access(e))),
        };
        Some(match (plan.tools, field) {
            (
                ToolChange::Field {
                    group,
                    index,
                    entry,
                },
                Some(field),
            ) => self.direct(plan, group, index, value_of(&entry, field), field),
            _ => Slice::Done(self.indirect(emu, plan)),
        })
    }

    /// A direct tool write: its change sent to the disk, the plan kept
    /// until the change is there.
    fn direct(
        &mut self,
        plan: Plan<OtcExtension>,
        group: u16,
        index: WkzIndex,
        value: ToolValue,
        field: ToolField,
    ) -> Slice<ExecRest> {
        // The table refuses a group index outside 1..=32 (`NoObject`); a
        // WkzIndex is below TOOL_ENTRIES.
        let (Ok(group), Some(key)) = (u8::try_from(group), ToolKey::new(index.get() as u16, field))
        else {
            return Slice::Done(Answer::Access(AccessError::NoObject));
        };
        self.last += 1;
        let token = self.last;
        let change = Pending {
            plan,
            group,
            key,
            value,
        };
        self.pending.insert(token, change);
        let (tx, rx) = oneshot::channel();
        let record = Record::Set { group, key, value };
        self.writer.submit(vec![record], Done::Async(tx));
        Slice::Wait(Wait { done: rx, token })
    }

    /// A direct tool write is on disk (`ok`) or refused: its plan applied
    /// if no newer change holds the field, answered.
    pub fn resume(&mut self, emu: &mut Emulator, token: u64, ok: bool) -> Slice<ExecRest> {
        let Some(p) = self.pending.remove(&token) else {
            return Slice::Done(Answer::Protocol(ProtocolError::Busy));
        };
        if !ok {
            return Slice::Done(Answer::Access(AccessError::Storage));
        }
        // Tokens start at 1: a field no change holds yet takes any.
        let held = self
            .holds
            .entry((p.group, p.key.index, p.key.field))
            .or_insert(0);
        if *held < token {
            *held = token;
            if let Err(e) = emu.apply(p.plan) {
                return Slice::Done(Answer::Access(e));
            }
        }
        Slice::Done(Answer::Ok)
    }

    /// A write that may change tool data on the side: the tool changes
    /// of its plan made durable, then the plan applied; if the disk
    /// refused them, nothing is applied (answer `Storage`).
    fn indirect(&mut self, emu: &mut Emulator, plan: Plan<OtcExtension>) -> Answer {
        // Compared with the memory plus the changes still on their way, so
        // that the journal ends as memory does.
        let mut expected = all_tables(emu.tc());
        for p in self.pending.values() {
            if let Some(t) = expected.get_mut(usize::from(p.group) - 1) {
                t.set(p.key, p.value);
            }
        }
        if !may_touch_tools(emu, plan.address(), &expected) {
            return answer(emu.apply(plan));
        }
        let records = changes(&tables_planned(&expected, emu.tc(), &plan.tools), &expected);
        if records.is_empty() {
            return answer(emu.apply(plan));
        }
        self.last += 1;
        if !self.writer.write_blocking(records.clone()) {
            return Answer::Access(AccessError::Storage);
        }
        warn_group_reset(plan.address(), &expected);
        for r in &records {
            if let Record::Set { group, key, .. } = r {
                self.holds.insert((*group, key.index, key.field), self.last);
            }
        }
        answer(emu.apply(plan))
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
/// whose OTC is off. Such writes are applied at once.
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

/// The answer to a write.
fn answer(r: Result<(), AccessError>) -> Answer {
    r.map_or_else(Answer::Access, |()| Answer::Ok)
}
