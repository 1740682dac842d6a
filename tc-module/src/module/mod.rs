//! The TC module on bus 1300: global registers, up to 32 compensation
//! groups, the machine's spooler and executor, and an extension.
//!
//! * `dispatch`: the `Bus` face, routing each object to its owner;
//! * `registers`: devices 0..2 and their init rules (STATUS, RESET,
//!   Clean, changes while running);
//! * `intake`: the programmed frame: limits, modal feed, rotation;
//! * `commands`: motion commands, the correction, faults, direct
//!   commands.

mod commands;
mod dispatch;
mod intake;
mod registers;

use crate::cycle::{Cycle, CycleModel};
use crate::element::{ContourNormal, Origin, SpoolElement};
use crate::executor::{Executor, DEFAULT_CYCLE_S};
use crate::extension::{Group, Groups, NoExtension, TcExtension};
use crate::object_map::{object_table, TcKey, GROUP_COUNT};
use crate::plane::{AxisPos, PlaneAxes, TcPlane, AXES};
use crate::rotation::Rotation;
use crate::spooler::Spooler;
use uoi::ObjectDesc;

pub use intake::{DEFAULT_FEED, MAX_COORD, RAPID_FEED};

/// Default AxisNr X/Y/Z (uoi-map.md device 0 index 2: "default 0,1,2").
pub const DEFAULT_AXIS_NR: [u8; 3] = [0, 1, 2];

/// The TC module with extension `E`.
#[derive(Debug)]
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
    /// Set at STATUS=0: the next uncorrected element is the departure.
    departure: Option<Departure>,
    spooler: Spooler,
    executor: Executor,
    ext: E,
    table: Vec<ObjectDesc<TcKey<E::Key>>>,
}

impl Default for TcModule<NoExtension> {
    fn default() -> Self {
        Self::new([0.0; AXES], DEFAULT_CYCLE_S, NoExtension)
    }
}

impl<E: TcExtension> TcModule<E> {
    /// A module whose machine stands at `start`, with an interpolation
    /// cycle of `cycle_s` seconds and extension `ext`.
    pub fn new(start: AxisPos, cycle_s: f64, ext: E) -> Self {
        Self {
            axis_nr: DEFAULT_AXIS_NR,
            plane: TcPlane::default(),
            rotation: Rotation::default(),
            groups: Box::new(std::array::from_fn(|_| None)),
            running: None,
            programmed: start,
            contour_end: start,
            feed: DEFAULT_FEED,
            departure: None,
            spooler: Spooler::default(),
            executor: Executor::new(start, cycle_s),
            ext,
            table: object_table::<E>(),
        }
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

    /// The spooler (to switch the log on, or take it).
    pub fn spooler_mut(&mut self) -> &mut Spooler {
        &mut self.spooler
    }

    /// Elements waiting in the spooler.
    pub fn queue_len(&self) -> usize {
        self.spooler.len()
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
    /// with the extension's per-cycle model.
    pub fn exec(&mut self, cycles: Option<u64>) {
        let mut model = ExtModel::new(&mut self.ext, &mut self.groups[..], self.running);
        match cycles {
            Some(n) => self.executor.run(&mut self.spooler, n, &mut model),
            None => self.executor.run_until_empty(&mut self.spooler, &mut model),
        }
    }

    /// Drops the executor's offset when the extension's model stopped
    /// acting (after a write to its objects: OTC switched off).
    fn sync_offset(&mut self) {
        let mut groups = Groups::new(&mut self.groups[..], self.running);
        if !self.ext.cycle_active(groups.reborrow()) {
            self.executor.clear_offset();
        }
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
            Some(Departure(normal)) => SpoolElement {
                origin: Origin::Departure,
                ..e
            }
            .with_normal(normal),
        }
    }
}

/// A pending departure: the contour normal the last corrected element
/// ended with (otc.md rule 4), if it had one.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Departure(Option<ContourNormal>);

/// The extension's per-cycle model, with the groups it reads and writes.
struct ExtModel<'a, E: TcExtension> {
    ext: &'a mut E,
    groups: Groups<'a, E>,
    active: bool,
}

impl<'a, E: TcExtension> ExtModel<'a, E> {
    fn new(
        ext: &'a mut E,
        slots: &'a mut crate::extension::GroupSlots<E>,
        running: Option<usize>,
    ) -> Self {
        let mut groups = Groups::new(slots, running);
        let active = ext.cycle_active(groups.reborrow());
        Self {
            ext,
            groups,
            active,
        }
    }
}

impl<E: TcExtension> CycleModel for ExtModel<'_, E> {
    fn active(&self) -> bool {
        self.active
    }

    fn cycle(&mut self, cycle: &Cycle<'_>) -> AxisPos {
        self.ext.cycle(cycle, self.groups.reborrow())
    }
}
