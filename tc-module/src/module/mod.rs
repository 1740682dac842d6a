//! The TC module on bus 1300: global registers, up to 32 compensation
//! groups, the machine's spooler and executor, and an extension.
//!
//! * `dispatch`: the `Bus` face, routing each object to its owner;
//! * `registers`: devices 0..2 and their init rules (STATUS, RESET,
//!   Clean, changes while running);
//! * `intake`: the programmed frame: limits, modal feed, rotation;
//! * `commands`: motion commands, the correction, faults, direct
//!   commands;
//! * `plan`: a write planned (checked, what it changes of the tool
//!   data), then applied: the one route of every write.

mod commands;
mod dispatch;
mod intake;
pub(crate) mod plan;
mod registers;

use crate::correction::FeedAdaption;
use crate::cycle::{Cycle, CycleModel};
use crate::element::{ContourNormal, Origin, SpoolElement};
use crate::executor::Executor;
use crate::extension::{Group, Groups, NoExtension, TcExtension};
use crate::limits::{CycleTime, DEFAULT_FEED};
use crate::object_map::{object_table, TcKey};
use crate::plane::{AxisPos, MainAxes, PlaneAxes, TcPlane, AXES};
use crate::rotation::Rotation;
use crate::spooler::{Spooler, MAX_SPOOL_CAPACITY, MIN_SPOOL_CAPACITY};
use crate::tool_table::ToolTable;
use tc_objects::GROUP_COUNT;
use uoi::ObjectDesc;

/// Stepped cycles one slice of an `EXEC` may run while an extension's
/// per-cycle model is active ([`TcModule::exec_slice`]): a server runs a
/// long `EXEC` slice by slice and serves other requests in between.
pub const EXEC_SLICE_CYCLES: u64 = 10_000;

/// What is left of an `EXEC` after a slice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExecLeft {
    /// The request is complete.
    Done,
    /// Continue with `EXEC` of this argument: cycles left, or `None`
    /// until the spooler is empty.
    Rest(Option<u64>),
}

/// Default AxisNr X/Y/Z (docs/objects.md device 0 index 2: defaults 0,
/// 1, 2).
pub const DEFAULT_AXIS_NR: [u8; 3] = [0, 1, 2];

/// The TC module with extension `E`.
#[derive(Debug, Clone)]
pub struct TcModule<E: TcExtension = NoExtension> {
    axis_nr: [u8; 3],
    plane: TcPlane,
    rotation: Rotation,
    groups: Box<[Option<Box<Group<E>>>; GROUP_COUNT]>,
    running: Option<usize>,
    /// Programmed position before rotation: unnamed axes keep these values.
    programmed: AxisPos,
    /// End of the last programmed profile in machine coordinates.
    contour_end: AxisPos,
    feed: f64,
    /// Feed adaptation of corrected arcs (NC G10/G11, `#TANGFEED`): not a
    /// register of the bus, set by [`TcModule::set_feed_adaption`].
    feed_adaption: FeedAdaption,
    /// Set at STATUS=0: the next uncorrected element is the departure.
    departure: Option<Departure>,
    spooler: Spooler,
    executor: Executor,
    ext: E,
    table: Vec<ObjectDesc<TcKey<E::Key>>>,
}

impl Default for TcModule<NoExtension> {
    fn default() -> Self {
        Self::new([0.0; AXES], CycleTime::DEFAULT, NoExtension)
    }
}

impl<E: TcExtension> TcModule<E> {
    /// Sets the feed adaptation of corrected arcs (NC programs' `G10`/`G11`
    /// and `#TANGFEED RMIN`, docs/nc.md): from the next profile on, a
    /// corrected arc of programmed radius `R >= rmin` spools at `F * R'/R`.
    /// No object of the bus changes; a Clean sets it back to off.
    pub fn set_feed_adaption(&mut self, adaption: FeedAdaption) {
        self.feed_adaption = adaption;
    }
}

impl<E: TcExtension> TcModule<E> {
    /// A module whose machine stands at `start`, with interpolation cycle
    /// `cycle` and extension `ext`; the spooler has the default capacity.
    pub fn new(start: AxisPos, cycle: CycleTime, ext: E) -> Self {
        Self {
            axis_nr: DEFAULT_AXIS_NR,
            plane: TcPlane::default(),
            rotation: Rotation::default(),
            groups: Box::new(std::array::from_fn(|_| None)),
            running: None,
            programmed: start,
            contour_end: start,
            feed: DEFAULT_FEED,
            feed_adaption: FeedAdaption::default(),
            departure: None,
            spooler: Spooler::default(),
            executor: Executor::new(start, cycle),
            ext,
            table: object_table::<E>(),
        }
    }

    /// The same module with a spooler of `capacity` elements (checked by
    /// [`check_capacity`](crate::spooler::check_capacity) where it comes
    /// from outside; kept within its limits here).
    pub fn with_spool_capacity(mut self, capacity: usize) -> Self {
        let capacity = capacity.clamp(MIN_SPOOL_CAPACITY, MAX_SPOOL_CAPACITY);
        self.spooler = Spooler::with_capacity(capacity);
        self
    }

    /// The extension.
    pub fn extension(&self) -> &E {
        &self.ext
    }

    /// The extension, mutable (its own state; TC data stays behind the
    /// object map).
    pub fn extension_mut(&mut self) -> &mut E {
        &mut self.ext
    }

    /// The main plane axes from device 0 (AxisNr and TcPlane).
    pub fn main_plane(&self) -> PlaneAxes {
        self.plane.pick(self.axis_nr)
    }

    /// The main axes: AxisNr X/Y/Z and the main plane built from them.
    pub fn main_axes(&self) -> MainAxes {
        MainAxes {
            xyz: self.axis_nr,
            plane: self.main_plane(),
        }
    }

    /// TcPlane (device 0 index 3).
    pub fn plane(&self) -> TcPlane {
        self.plane
    }

    /// AxisNr X/Y/Z (device 0 index 2).
    pub fn axis_nr(&self) -> [u8; 3] {
        self.axis_nr
    }

    /// The group at `index` (1..=32), if it was created.
    pub fn group_at(&self, index: u16) -> Option<&Group<E>> {
        let slot = usize::from(index).checked_sub(1)?;
        self.groups.get(slot)?.as_deref()
    }

    /// The tool table of the group at `index` (1..=32), created on first
    /// access; `None` outside 1..=32. For tool data kept outside the
    /// module (the tool files): the module's rules do not apply to it.
    pub fn tools_mut(&mut self, index: u16) -> Option<&mut ToolTable<E::Tool>> {
        let slot = usize::from(index).checked_sub(1)?;
        let g = self.groups.get_mut(slot)?;
        Some(&mut g.get_or_insert_with(Default::default).tools)
    }

    /// The spooler (to switch the log on, or take it).
    pub fn spooler_mut(&mut self) -> &mut Spooler {
        &mut self.spooler
    }

    /// The spooler.
    pub fn spooler(&self) -> &Spooler {
        &self.spooler
    }

    /// Motion waiting (`QUEUE`): the elements in the spooler plus the
    /// plane-null profiles waiting with the running group's held profile
    /// (they enter the spooler with it and count toward its capacity).
    pub fn queue_len(&self) -> usize {
        self.spooler.len() + self.waiting_nulls()
    }

    /// Plane-null profiles waiting in the running group's buffer.
    fn waiting_nulls(&self) -> usize {
        self.running
            .and_then(|slot| self.groups[slot].as_ref())
            .map_or(0, |g| g.buffer.waiting_nulls())
    }

    /// The executed position (nominal path position plus the offset of the
    /// extension's per-cycle model).
    pub fn position(&self) -> AxisPos {
        self.executor.position()
    }

    /// The executor (nominal position, offset, cycles run).
    pub fn executor(&self) -> &Executor {
        &self.executor
    }

    /// The current tool position: the end of the last spooled element, or
    /// the nominal position when nothing is spooled.
    pub fn tool_position(&self) -> AxisPos {
        self.spooler.last_end().unwrap_or(*self.executor.nominal())
    }

    /// Runs the executor for `cycles` cycles, or until the spooler is empty,
    /// with the extension's per-cycle model: slice after slice to the end.
    pub fn exec(&mut self, cycles: Option<u64>) {
        let mut left = self.exec_slice(cycles);
        while let ExecLeft::Rest(rest) = left {
            left = self.exec_slice(rest);
        }
    }

    /// One slice of `EXEC cycles`: at most [`EXEC_SLICE_CYCLES`] cycles
    /// stepped for an active model (without one, the whole request: its
    /// work is bounded by the elements spooled). Running the slices one
    /// after the other is the same as running the whole request.
    pub fn exec_slice(&mut self, cycles: Option<u64>) -> ExecLeft {
        let main = self.main_axes();
        let groups = Groups::new(&mut self.groups[..], self.running, main);
        let mut model = SliceModel::new(self.ext.cycle_model(groups));
        let (spooler, budget) = (&mut self.spooler, EXEC_SLICE_CYCLES);
        match cycles {
            Some(n) => match self.executor.run_for(spooler, n, &mut model, budget) {
                0 => ExecLeft::Done,
                left => ExecLeft::Rest(Some(left)),
            },
            None if self
                .executor
                .run_until_empty_for(spooler, &mut model, budget) =>
            {
                ExecLeft::Done
            }
            None => ExecLeft::Rest(None),
        }
    }

    /// Drops the executor's offset when the extension's model stopped
    /// acting (after a write to its objects: OTC switched off).
    fn sync_offset(&mut self) {
        let main = self.main_axes();
        let groups = Groups::new(&mut self.groups[..], self.running, main);
        if !self.ext.cycle_model(groups).active() {
            self.executor.clear_offset();
        }
    }

    /// Re-evaluates the extension model's offset where the executor stands
    /// (after a direct command moved it at once).
    fn refresh_offset(&mut self) {
        let main = self.main_axes();
        let groups = Groups::new(&mut self.groups[..], self.running, main);
        let mut model = SliceModel::new(self.ext.cycle_model(groups));
        self.executor.refresh_offset(&self.spooler, &mut model);
    }

    /// Ends the correction of `slot`, if it runs.
    fn clear_run(&mut self, slot: usize) {
        if self.running == Some(slot) {
            self.running = None;
        }
    }

    /// An uncorrected element, tagged as the departure when it is the
    /// first after STATUS=0.
    fn uncorrected(&mut self, e: SpoolElement) -> SpoolElement {
        match self.departure.take() {
            None => e,
            Some(Departure(normal)) => e.with_origin(Origin::Departure).with_normal(normal),
        }
    }
}

/// A pending departure: the contour normal the last corrected element
/// ended with (decisions 42 and 43), if it had one.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Departure(Option<ContourNormal>);

/// The extension's per-cycle model for one slice: whether it acts is
/// asked once, when the slice begins.
struct SliceModel<M> {
    model: M,
    active: bool,
}

impl<M: CycleModel> SliceModel<M> {
    fn new(model: M) -> Self {
        let active = model.active();
        Self { model, active }
    }
}

impl<M: CycleModel> CycleModel for SliceModel<M> {
    fn active(&self) -> bool {
        self.active
    }

    fn cycle(&mut self, cycle: &Cycle<'_>) -> AxisPos {
        self.model.cycle(cycle)
    }

    fn at_rest(&mut self) -> bool {
        self.model.at_rest()
    }

    fn offset_now(&mut self, cycle: &Cycle<'_>) -> AxisPos {
        self.model.offset_now(cycle)
    }
}
