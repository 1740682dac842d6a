//! The seam through which an extension (OTC, in `otc-ext`) adds objects to
//! bus 1300, keeps its own state in the TC state it belongs to, follows
//! what the TC module does, and acts on every interpolation cycle.
//!
//! * Objects: the extension declares its rows ([`TcExtension::GROUP_OBJECTS`]
//!   indexed by compensation group, [`TcExtension::OBJECTS`] on devices of
//!   its own); the module appends them to its one map.
//! * State: [`TcExtension::Group`] lives in each compensation group,
//!   [`TcExtension::Tool`] in each tool entry. TC data is read-only to the
//!   extension except through named operations of [`GroupAccess`].
//! * Events: tool change, group reset, Clean, position requests.
//! * Cycles: [`TcExtension::cycle_model`] hands the module the per-cycle
//!   model ([`CycleModel`]).

use std::fmt::Debug;

use uoi::{AccessError, ObjectAddress, ObjectDesc, Value};

use crate::cycle::{Cycle, CycleModel, NoModel};
use crate::group::CorrGroup;
use crate::plane::{AxisPos, MainAxes, AXES};
use crate::tool_table::{ToolEntry, WkzIndex};

/// A compensation group as the module stores it for extension `E`.
pub type Group<E> = CorrGroup<<E as TcExtension>::Group, <E as TcExtension>::Tool>;

/// The module's group slots (index - 1), created on first access.
pub type GroupSlots<E> = [Option<Box<Group<E>>>];

/// One compensation group as an extension sees it.
#[derive(Debug)]
pub struct GroupAccess<'a, E: TcExtension> {
    index: u16,
    group: &'a mut Group<E>,
    running: bool,
    main: MainAxes,
}

impl<'a, E: TcExtension> GroupAccess<'a, E> {
    /// The group at `index` (1..=32), running or not, on a machine with
    /// main axes `main` (device 0).
    pub fn new(index: u16, group: &'a mut Group<E>, running: bool, main: MainAxes) -> Self {
        Self {
            index,
            group,
            running,
            main,
        }
    }

    /// The machine's main axes (device 0 AxisNr and TcPlane).
    pub fn main_axes(&self) -> MainAxes {
        self.main
    }

    /// The group number, 1..=32.
    pub fn index(&self) -> u16 {
        self.index
    }

    /// Whether its correction runs (STATUS bit Run).
    pub fn running(&self) -> bool {
        self.running
    }

    /// Its WKZINDEX.
    pub fn wkz(&self) -> WkzIndex {
        self.group.wkz
    }

    /// The tool entry at WKZINDEX (TC fields and the extension's).
    pub fn tool(&self) -> &ToolEntry<E::Tool> {
        self.group.tool()
    }

    /// The extension's fields of the tool entry at WKZINDEX.
    pub fn tool_ext(&mut self) -> &mut E::Tool {
        &mut self.group.tool_mut().ext
    }

    /// The extension's state of this group.
    pub fn state(&self) -> &E::Group {
        &self.group.ext
    }

    /// The extension's state of this group, mutable.
    pub fn state_mut(&mut self) -> &mut E::Group {
        &mut self.group.ext
    }

    /// Reduces the radius of the entry at WKZINDEX by `w` (wear booked on
    /// the tool). `Range`, and nothing changes, when the radius would
    /// leave its range (±`MAX_COORD`), as a RADIUS write would be refused. On a running group
    /// the new radius acts from the next profile like a RADIUS write
    /// (decision 21: the buffered profile is finished, the next is an
    /// approach).
    pub fn reduce_radius(&mut self, w: f64) -> Result<(), AccessError> {
        let entry = self.group.tool_mut();
        entry.radius = reduced(entry.radius, w)?;
        Ok(())
    }

    /// Reduces the length of the entry at WKZINDEX by `w`; `Range`, and
    /// nothing changes, when the length would leave its range
    /// (±`MAX_COORD`).
    pub fn reduce_length(&mut self, w: f64) -> Result<(), AccessError> {
        let entry = self.group.tool_mut();
        entry.length = reduced(entry.length, w)?;
        Ok(())
    }
}

/// `value - w`, if within the range of RADIUS and WkzLen (±`MAX_COORD`).
fn reduced(value: f64, w: f64) -> Result<f64, AccessError> {
    let v = value - w;
    if crate::limits::within_limit(v) {
        Ok(v)
    } else {
        Err(AccessError::Range)
    }
}

/// Every compensation group that exists, as an extension sees them.
#[derive(Debug)]
pub struct Groups<'a, E: TcExtension> {
    slots: &'a mut GroupSlots<E>,
    running: Option<usize>,
    main: MainAxes,
}

impl<'a, E: TcExtension> Groups<'a, E> {
    /// The groups in `slots` (slot = index - 1); `running` is the slot of
    /// the running group, `main` the machine's main axes (device 0).
    pub fn new(slots: &'a mut GroupSlots<E>, running: Option<usize>, main: MainAxes) -> Self {
        Self {
            slots,
            running,
            main,
        }
    }

    /// The same view, borrowed again.
    pub fn reborrow(&mut self) -> Groups<'_, E> {
        Groups {
            slots: &mut *self.slots,
            running: self.running,
            main: self.main,
        }
    }

    /// The group at `index` (1..=32), if it was created.
    pub fn get(&mut self, index: u16) -> Option<GroupAccess<'_, E>> {
        let slot = usize::from(index).checked_sub(1)?;
        let running = self.running == Some(slot);
        let g = self.slots.get_mut(slot)?.as_deref_mut()?;
        Some(GroupAccess::new(index, g, running, self.main))
    }

    /// Every group that was created, in index order.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = GroupAccess<'_, E>> {
        let (running, main) = (self.running, self.main);
        self.slots
            .iter_mut()
            .enumerate()
            .filter_map(move |(slot, g)| {
                let g = g.as_deref_mut()?;
                // slot < GROUP_COUNT (32) fits u16.
                let index = slot as u16 + 1;
                Some(GroupAccess::new(index, g, running == Some(slot), main))
            })
    }
}

/// An extension of the TC module.
///
/// Type, access and range of an access are checked against the declared
/// rows before `read_group`/`write_group`/`read`/`write` are called.
pub trait TcExtension: Debug + Send + Sized + 'static {
    /// The extension's own name for its objects.
    type Key: Copy + Debug + PartialEq + Send + Sync + 'static;
    /// Its state of one compensation group.
    type Group: Debug + Default + Clone + Send + 'static;
    /// Its fields of one tool entry.
    type Tool: Debug + Default + Copy + PartialEq + Send + 'static;
    /// Its per-cycle model over the groups ([`TcExtension::cycle_model`]).
    type Model<'a>: CycleModel
    where
        Self: 'a;

    /// Its objects indexed by compensation group (index range `GROUPS`);
    /// the group is created on first access like every group.
    const GROUP_OBJECTS: &'static [ObjectDesc<Self::Key>];
    /// Its other objects, on devices of its own.
    const OBJECTS: &'static [ObjectDesc<Self::Key>];

    /// Reads a group object of the group at `addr.index`, which exists
    /// (created on first access) in `groups`; the other groups are there
    /// too. (Only called for declared rows; an extension without group
    /// rows need not implement it.)
    fn read_group(
        &mut self,
        _key: Self::Key,
        _addr: ObjectAddress,
        _groups: Groups<'_, Self>,
    ) -> Result<Value, AccessError> {
        Err(AccessError::NoObject)
    }

    /// Writes a group object of the group at `addr.index` (as for
    /// [`TcExtension::read_group`]).
    fn write_group(
        &mut self,
        _key: Self::Key,
        _addr: ObjectAddress,
        _value: Value,
        _groups: Groups<'_, Self>,
    ) -> Result<(), AccessError> {
        Err(AccessError::NoObject)
    }

    /// Reads one of its other objects.
    fn read(
        &mut self,
        _key: Self::Key,
        _addr: ObjectAddress,
        _groups: Groups<'_, Self>,
    ) -> Result<Value, AccessError> {
        Err(AccessError::NoObject)
    }

    /// Writes one of its other objects.
    fn write(
        &mut self,
        _key: Self::Key,
        _addr: ObjectAddress,
        _value: Value,
        _groups: Groups<'_, Self>,
    ) -> Result<(), AccessError> {
        Err(AccessError::NoObject)
    }

    /// Sets the field of a tool entry's extension part `tool` that group
    /// object `key` writes (an object of the entry at WKZINDEX); `false`
    /// when `key` is no tool field. Such a write changes nothing else: the
    /// module plans it and sets the field on the entry planned
    /// ([`TcModule::plan_write`](crate::TcModule::plan_write)); it never
    /// reaches [`TcExtension::write_group`].
    fn write_tool(_key: Self::Key, _value: Value, _tool: &mut Self::Tool) -> bool {
        false
    }

    /// The entry at WKZINDEX of `group` as a write of `value` to group
    /// object `key` would leave it, when the write changes it on the side
    /// (OTC switched off books its wear on it); `None`: it changes no tool
    /// entry; `Err`: the write would be refused and change nothing.
    /// `running`: the group's correction runs. Changes nothing.
    fn tool_after(
        &self,
        _key: Self::Key,
        _value: Value,
        _group: &Group<Self>,
        _running: bool,
        _main: MainAxes,
    ) -> Result<Option<ToolEntry<Self::Tool>>, AccessError> {
        Ok(None)
    }

    /// The group's WKZINDEX changed from `outgoing` (the tool handed back)
    /// to the group's current one.
    fn tool_changed(&mut self, _outgoing: WkzIndex, _group: GroupAccess<'_, Self>) {}

    /// The group RESET (its tool entries, the extension's fields included,
    /// are back to default).
    fn group_reset(&mut self, _group: GroupAccess<'_, Self>) {}

    /// Device 0 Clean: every group is gone; the extension's own state
    /// goes back to defaults.
    fn clean(&mut self) {}

    /// A position request (`JA`, `JS`, ReInit) is about to happen; an error
    /// refuses it.
    fn position_request(&mut self, _groups: Groups<'_, Self>) -> Result<(), AccessError> {
        Ok(())
    }

    /// The extension's per-cycle model over the groups, for one `EXEC`
    /// slice (or one look at the offset after a direct command, or after a
    /// write: whether it still acts). The one seam of the per-cycle model
    /// ([`CycleModel`]: `active`, `cycle`, `at_rest`, `offset_now`). An
    /// extension whose model needs no groups lends itself
    /// (`type Model<'a> = &'a mut Self`).
    fn cycle_model<'a>(&'a mut self, groups: Groups<'a, Self>) -> Self::Model<'a>;
}

/// The key of an extension without objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoKey {}

/// No extension: devices 3 and 4 do not exist (`NoObject`).
#[derive(Debug, Default, Clone, Copy)]
pub struct NoExtension;

impl TcExtension for NoExtension {
    type Key = NoKey;
    type Group = ();
    type Tool = ();
    type Model<'a> = NoModel;
    const GROUP_OBJECTS: &'static [ObjectDesc<NoKey>] = &[];
    const OBJECTS: &'static [ObjectDesc<NoKey>] = &[];

    fn cycle_model<'a>(&'a mut self, _: Groups<'a, Self>) -> NoModel {
        NoModel
    }
}

/// No extension objects, and a per-cycle model that is always active and
/// adds no offset: the executor steps every cycle one by one, as it does
/// for OTC (for tests and benchmarks of stepped execution).
#[derive(Debug, Default, Clone, Copy)]
pub struct AlwaysStepped;

impl TcExtension for AlwaysStepped {
    type Key = NoKey;
    type Group = ();
    type Tool = ();
    type Model<'a> = &'a mut Self;
    const GROUP_OBJECTS: &'static [ObjectDesc<NoKey>] = &[];
    const OBJECTS: &'static [ObjectDesc<NoKey>] = &[];

    fn cycle_model<'a>(&'a mut self, _: Groups<'a, Self>) -> &'a mut Self {
        self
    }
}

impl CycleModel for AlwaysStepped {
    fn active(&self) -> bool {
        true
    }

    fn cycle(&mut self, _: &Cycle<'_>) -> AxisPos {
        [0.0; AXES]
    }
}
