//! The TC module on bus 1300: registers of devices 0..2, motion commands,
//! spooler and executor.

use uoi::{AccessError, Bus, ObjectAddress, ObjectDesc, Value};

use crate::bits::{ErrorBits, StatusBits};
use crate::correction::{Profile, Sink};
use crate::executor::{Executor, DEFAULT_CYCLE_S};
use crate::extension::{GroupContext, NoExtension, TcExtension};
use crate::geometry::{Contour, V2};
use crate::group::{CorrGroup, Side, TransitionMode};
use crate::motion::{ArcDir, AxisWords, Motion, SSF_FLUSH};
use crate::object_map::{TcObject, TC_BUS, TC_OBJECTS};
use crate::plane::{AxisPos, PlaneAxes, TcPlane, AXES};
use crate::rotation::Rotation;
use crate::spooler::{Origin, SpoolElement, Spooler};
use crate::tool_table::WkzIndex;

/// Number of compensation groups.
pub const GROUP_COUNT: usize = 32;

/// Default feed in units/min (trc-geometry.md).
pub const DEFAULT_FEED: f64 = 1000.0;

/// Default rapid feed in units/min.
pub const RAPID_FEED: f64 = 10000.0;

/// The TC module: global registers, up to 32 compensation groups, the
/// machine's spooler and executor.
#[derive(Debug)]
pub struct TcModule {
    axis_nr: [u8; 3],
    plane: TcPlane,
    rotation: Rotation,
    groups: [Option<Box<CorrGroup>>; GROUP_COUNT],
    running: Option<usize>,
    /// Programmed position before rotation: unnamed axes keep these values.
    programmed: AxisPos,
    /// End of the last programmed profile in machine coordinates.
    contour_end: AxisPos,
    feed: f64,
    spooler: Spooler,
    executor: Executor,
    ext: Box<dyn TcExtension>,
}

impl Default for TcModule {
    fn default() -> Self {
        Self::new([0.0; AXES], DEFAULT_CYCLE_S)
    }
}

impl TcModule {
    /// A module whose machine stands at `start`, with an interpolation cycle
    /// of `cycle_s` seconds.
    pub fn new(start: AxisPos, cycle_s: f64) -> Self {
        Self {
            axis_nr: [0, 1, 2],
            plane: TcPlane::default(),
            rotation: Rotation::default(),
            groups: Default::default(),
            running: None,
            programmed: start,
            contour_end: start,
            feed: DEFAULT_FEED,
            spooler: Spooler::default(),
            executor: Executor::new(start, cycle_s),
            ext: Box::new(NoExtension),
        }
    }

    /// The module with an extension serving devices 3 and 4 (OTC).
    pub fn with_extension(mut self, ext: Box<dyn TcExtension>) -> Self {
        self.ext = ext;
        self
    }

    /// Runs `f` on the extension with the group a device 3 access
    /// addresses (created on first access); device 4 has no group.
    fn with_ext<T>(
        &mut self,
        addr: ObjectAddress,
        f: impl FnOnce(&mut dyn TcExtension, Option<GroupContext<'_>>) -> T,
    ) -> T {
        if addr.device == 4 {
            return f(self.ext.as_mut(), None);
        }
        let running = self.is_running(Self::group_slot(addr));
        let index = addr.index;
        let group = self.groups[usize::from(index) - 1].get_or_insert_with(Default::default);
        f(
            self.ext.as_mut(),
            Some(GroupContext {
                index,
                group,
                running,
            }),
        )
    }

    fn group(&mut self, index: u16) -> &mut CorrGroup {
        self.groups[usize::from(index) - 1].get_or_insert_with(Default::default)
    }

    fn group_slot(addr: ObjectAddress) -> usize {
        usize::from(addr.index) - 1
    }

    fn is_running(&self, slot: usize) -> bool {
        self.running == Some(slot)
    }

    /// The main plane axes from device 0 (AxisNr and TcPlane).
    pub fn main_plane(&self) -> PlaneAxes {
        self.plane.pick(self.axis_nr)
    }

    /// The spooler (to switch the log on, or take it).
    pub fn spooler_mut(&mut self) -> &mut Spooler {
        &mut self.spooler
    }

    /// Elements waiting in the spooler.
    pub fn queue_len(&self) -> usize {
        self.spooler.len()
    }

    /// The executed position.
    pub fn position(&self) -> &AxisPos {
        self.executor.position()
    }

    /// Runs the executor for `cycles` cycles, or until the spooler is empty.
    pub fn exec(&mut self, cycles: Option<u64>) {
        match cycles {
            Some(n) => self.executor.run(&mut self.spooler, n),
            None => self.executor.run_until_empty(&mut self.spooler),
        }
    }

    /// The current tool position: the end of the last spooled element, or
    /// the executed position when nothing is spooled.
    pub fn tool_position(&self) -> AxisPos {
        self.spooler.last_end().unwrap_or(*self.executor.position())
    }

    /// Executes a motion command.
    pub fn command(&mut self, m: &Motion) -> Result<(), AccessError> {
        match *m {
            Motion::Lin { words, feed, rapid } => self.interpolate(&words, None, feed, rapid),
            Motion::Cir {
                dir,
                words,
                centre,
                feed,
            } => self.interpolate(&words, Some((dir, centre)), feed, false),
            Motion::Ja { words } => {
                check_words(&words)?;
                self.ext.position_request()?;
                self.direct_command();
                for (i, w) in words.iter().enumerate() {
                    if let Some(v) = *w {
                        self.executor.set_axis(i, v);
                    }
                }
                self.resync_programmed();
                Ok(())
            }
            Motion::Js { .. } => {
                self.ext.position_request()?;
                self.direct_command();
                self.resync_programmed();
                Ok(())
            }
            Motion::Ssf { axis, function } => {
                if usize::from(axis) >= AXES {
                    return Err(AccessError::Range);
                }
                if function == SSF_FLUSH {
                    if let Some(slot) = self.running {
                        let in_group = self.groups[slot]
                            .as_ref()
                            .is_some_and(|g| g.axes.contains(&axis));
                        if in_group {
                            self.flush(slot);
                        }
                    }
                }
                Ok(())
            }
            Motion::Rs => {
                self.rotation = Rotation::default();
                Ok(())
            }
        }
    }

    /// The feed a command runs at: its `F` word (checked) or the modal one.
    fn feed_for(&self, feed: Option<f64>) -> Result<f64, AccessError> {
        match feed {
            Some(f) if !(f.is_finite() && f > 0.0 && f <= MAX_COORD) => Err(AccessError::Range),
            Some(f) => Ok(f),
            None => Ok(self.feed),
        }
    }

    /// Takes over an accepted interpolation command's modal feed and end point.
    fn accept(&mut self, feed: f64, programmed: AxisPos, target: AxisPos) {
        self.feed = feed;
        self.programmed = programmed;
        self.contour_end = target;
    }

    /// The machine target and the new programmed position for axis words.
    fn target(&self, words: &AxisWords) -> (AxisPos, AxisPos) {
        let mut programmed = self.programmed;
        for (p, w) in programmed.iter_mut().zip(words) {
            if let Some(v) = *w {
                *p = v;
            }
        }
        let mut target = programmed;
        let plane = self.main_plane();
        plane.set_point(&mut target, self.rotation.apply(plane.point(&programmed)));
        (target, programmed)
    }

    /// The arc centre in machine coordinates from I J K (along the axes
    /// allocated as X, Y, Z), rotated with the command.
    fn centre(&self, start: &AxisPos, ijk: [Option<f64>; 3]) -> [f64; 2] {
        let off = ijk.map(|v| v.unwrap_or(0.0));
        let plane_off = match self.plane {
            TcPlane::Xy => [off[0], off[1]],
            TcPlane::Zx => [off[2], off[0]],
            TcPlane::Yz => [off[1], off[2]],
        };
        let plane = self.main_plane();
        let s = plane.point(start);
        let rot = Rotation {
            angle_deg: self.rotation.angle_deg,
            center: [0.0, 0.0],
        };
        let o = rot.apply(plane_off);
        [s[0] + o[0], s[1] + o[1]]
    }

    /// After a direct command the programmed position follows the machine.
    fn resync_programmed(&mut self) {
        let q = *self.executor.position();
        self.contour_end = q;
        let plane = self.main_plane();
        let mut p = q;
        plane.set_point(&mut p, self.rotation.invert(plane.point(&q)));
        self.programmed = p;
    }

    /// `JA`/`JS`: the spooler queue and the running group's buffer are
    /// discarded; the correction keeps running, next profile is an approach.
    fn direct_command(&mut self) {
        self.spooler.discard();
        self.executor.abandon_element();
        if let Some(slot) = self.running {
            if let Some(g) = self.groups[slot].as_mut() {
                g.buffer.clear();
            }
        }
    }

    /// Spools the buffered profile of a running group (STATUS=0, SSF 2001).
    fn flush(&mut self, slot: usize) {
        let q = self.tool_position();
        let plane = self.plane;
        let Some(g) = self.groups[slot].as_mut() else {
            return;
        };
        let mut sink = Sink {
            spooler: &mut self.spooler,
            q,
            plane: g.plane_axes(plane),
            len: g.tool().length,
        };
        g.buffer.flush(&mut sink);
    }

    /// `LIN`/`RAP`/`CIR`: rotated as it enters, then corrected by the
    /// running group or spooled as it is.
    fn interpolate(
        &mut self,
        words: &AxisWords,
        arc: Option<(ArcDir, [Option<f64>; 3])>,
        feed: Option<f64>,
        rapid: bool,
    ) -> Result<(), AccessError> {
        if self.groups.iter().flatten().any(|g| g.faulted) {
            return Err(AccessError::State);
        }
        check_words(words)?;
        if let Some((_, ijk)) = arc {
            check_words(&ijk)?;
        }
        let modal_feed = self.feed_for(feed)?;
        let feed = if rapid { RAPID_FEED } else { modal_feed };
        let (target, programmed) = self.target(words);
        let start = self.contour_end;
        let main = self.main_plane();
        let centre = arc.map(|(dir, ijk)| (dir, self.centre(&start, ijk)));
        let q = self.tool_position();

        let Some(slot) = self.running else {
            let element = match centre {
                None => SpoolElement::line(q, target, feed, rapid, Origin::Plain),
                Some((dir, c)) => {
                    let r = distance(main.point(&start), c);
                    if r <= crate::geometry::MIN_RADIUS {
                        // Refused: nothing changes, not even the modal feed.
                        return Err(AccessError::Range);
                    }
                    SpoolElement::arc(q, target, main, c, dir == ArcDir::Ccw, feed, Origin::Plain)
                }
            };
            self.accept(modal_feed, programmed, target);
            self.spooler.push(element);
            return Ok(());
        };
        // The command is accepted; geometry problems from here on are
        // TC-level errors (ERROR bits), answered ok (decisions.md 12).
        self.accept(modal_feed, programmed, target);

        let plane = self.plane;
        let Some(g) = self.groups[slot].as_mut() else {
            return Ok(());
        };
        let gp = g.plane_axes(plane);
        let v2 = |p: [f64; 2]| V2::new(p[0], p[1]);
        let result = match centre {
            Some(_) if !gp.same_plane(main) => Err(ErrorBits::PLANE_ERROR),
            _ => {
                let from = v2(gp.point(&start));
                let to = v2(gp.point(&target));
                let contour = match centre {
                    None => Contour::Line { from, to },
                    Some((dir, c)) => Contour::Arc {
                        from,
                        to,
                        centre: v2(c),
                        sigma: dir.sigma(),
                    },
                };
                let side = g.side.map_or(1.0, Side::sign);
                let d = side * g.tool().radius;
                let mut sink = Sink {
                    spooler: &mut self.spooler,
                    q,
                    plane: gp,
                    len: g.tool().length,
                };
                let prof = Profile {
                    contour,
                    start,
                    end: target,
                    feed,
                    rapid,
                };
                g.buffer.push(prof, d, g.transition, &mut sink)
            }
        };
        if let Err(bits) = result {
            g.error |= bits;
            g.faulted = true;
            g.buffer.clear();
            self.running = None;
        }
        Ok(())
    }

    /// Device 0 Clean: every group, table and rotation back to defaults.
    fn clean(&mut self) {
        self.ext.clean();
        self.groups = Default::default();
        self.running = None;
        self.axis_nr = [0, 1, 2];
        self.plane = TcPlane::default();
        self.rotation = Rotation::default();
    }

    fn reset_group(&mut self, slot: usize) {
        if let Some(g) = self.groups[slot].as_mut() {
            g.reset();
            self.ext.group_reset(slot as u16 + 1);
        }
        if self.running == Some(slot) {
            self.running = None;
        }
    }

    /// STATUS=1: InitError when no side was selected since the last RESET,
    /// the plane axes are not distinct, another group runs, or the group is
    /// faulted.
    fn start(&mut self, slot: usize) {
        if self.running == Some(slot) {
            return;
        }
        let other_running = self.running.is_some();
        let plane = self.plane;
        let Some(g) = self.groups[slot].as_mut() else {
            return;
        };
        let ready =
            g.side.is_some() && g.plane_axes(plane).distinct() && !other_running && !g.faulted;
        if ready {
            g.buffer.clear();
            self.running = Some(slot);
        } else {
            g.error |= ErrorBits::INIT_ERROR;
        }
    }

    /// STATUS=0: spool the buffered profile, then clear Run.
    fn stop(&mut self, slot: usize) {
        if self.running == Some(slot) {
            self.flush(slot);
            self.running = None;
        }
    }

    fn write_group(&mut self, key: TcObject, addr: ObjectAddress, v: Value) {
        let slot = Self::group_slot(addr);
        let running = self.is_running(slot);
        let i = v.as_i32().unwrap_or(0);
        let d = v.as_f64().unwrap_or(0.0);
        let g = self.group(addr.index);
        match key {
            TcObject::Error => {
                g.error = ErrorBits::empty();
                g.faulted = false;
            }
            TcObject::GroupReset => self.reset_group(slot),
            TcObject::Status => {
                if i == 1 {
                    self.start(slot)
                } else {
                    self.stop(slot)
                }
            }
            TcObject::XAxis | TcObject::YAxis | TcObject::ZAxis => {
                if running {
                    g.error |= ErrorBits::INIT_ERROR;
                } else {
                    let n = match key {
                        TcObject::XAxis => 0,
                        TcObject::YAxis => 1,
                        _ => 2,
                    };
                    g.axes[n] = axis_u8(i);
                }
            }
            TcObject::Radius => g.tool_mut().radius = d,
            TcObject::WkzLen => g.tool_mut().length = d,
            TcObject::WkzIndex => {
                if running {
                    g.error |= ErrorBits::INIT_ERROR;
                } else if let Some(w) = WkzIndex::new(i) {
                    let outgoing = std::mem::replace(&mut g.wkz, w);
                    if outgoing != w {
                        self.ext.tool_changed(addr.index, outgoing, w);
                    }
                }
            }
            TcObject::Left | TcObject::Right => {
                if running {
                    g.error |= ErrorBits::INIT_ERROR;
                } else {
                    g.side = Some(if key == TcObject::Left {
                        Side::Left
                    } else {
                        Side::Right
                    });
                }
            }
            TcObject::TransitionMode => {
                g.transition = if i == 1 {
                    TransitionMode::Linear
                } else {
                    TransitionMode::Circular
                }
            }
            _ => {}
        }
    }
}

fn axis_u8(v: i32) -> u8 {
    // The table limits axis registers to 0..7.
    u8::try_from(v).unwrap_or(0)
}

/// Largest coordinate, offset or feed magnitude accepted (interpolation
/// units): beyond it a command is refused with `Range` (decisions.md).
pub const MAX_COORD: f64 = 1e9;

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn check_words<const N: usize>(words: &[Option<f64>; N]) -> Result<(), AccessError> {
    if words
        .iter()
        .flatten()
        .all(|v| v.is_finite() && v.abs() <= MAX_COORD)
    {
        Ok(())
    } else {
        Err(AccessError::Range)
    }
}

impl Bus for TcModule {
    type Key = TcObject;

    fn number(&self) -> u16 {
        TC_BUS
    }

    fn objects(&self) -> &'static [ObjectDesc<TcObject>] {
        &TC_OBJECTS
    }

    fn read(&mut self, key: TcObject, addr: ObjectAddress) -> Result<Value, AccessError> {
        let slot = usize::from(addr.index).saturating_sub(1);
        Ok(match key {
            TcObject::AxisNr => Value::I32(i32::from(self.axis_nr[usize::from(addr.sub)])),
            TcObject::TcPlane => Value::I32(self.plane.code()),
            TcObject::RotAngle => Value::F64(self.rotation.angle_deg),
            TcObject::RotCenterX => Value::F64(self.rotation.center[0]),
            TcObject::RotCenterY => Value::F64(self.rotation.center[1]),
            TcObject::Otc(obj) => return self.with_ext(addr, |ext, g| ext.read(obj, addr, g)),
            TcObject::Status => {
                let running = self.is_running(slot);
                let g = self.group(addr.index);
                let mut s = StatusBits::empty();
                s.set(StatusBits::RUN, running);
                s.set(StatusBits::PROF_MARKED, g.buffer.is_marked());
                Value::I32(s.bits())
            }
            other => {
                let g = self.group(addr.index);
                match other {
                    TcObject::Error => Value::I32(g.error.bits()),
                    TcObject::XAxis => Value::I32(i32::from(g.axes[0])),
                    TcObject::YAxis => Value::I32(i32::from(g.axes[1])),
                    TcObject::ZAxis => Value::I32(i32::from(g.axes[2])),
                    TcObject::Radius => Value::F64(g.tool().radius),
                    TcObject::WkzLen => Value::F64(g.tool().length),
                    TcObject::WkzIndex => Value::I32(g.wkz.get() as i32),
                    TcObject::TransitionMode => Value::I32(g.transition.code()),
                    // Write-only objects never reach read (checked by the table).
                    _ => return Err(AccessError::WriteOnly),
                }
            }
        })
    }

    fn write(
        &mut self,
        key: TcObject,
        addr: ObjectAddress,
        value: Value,
    ) -> Result<(), AccessError> {
        let i = value.as_i32().unwrap_or(0);
        let d = value.as_f64().unwrap_or(0.0);
        match key {
            TcObject::Clean => self.clean(),
            TcObject::AxisNr => self.axis_nr[usize::from(addr.sub)] = axis_u8(i),
            TcObject::TcPlane => self.plane = TcPlane::from_code(i).unwrap_or_default(),
            TcObject::ReInit => {
                self.ext.position_request()?;
                for g in self.groups.iter_mut().flatten() {
                    g.buffer.clear();
                }
            }
            TcObject::Reset => {
                for slot in 0..GROUP_COUNT {
                    self.reset_group(slot);
                }
            }
            TcObject::RotAngle => self.rotation.angle_deg = d,
            TcObject::RotCenterX => self.rotation.center[0] = d,
            TcObject::RotCenterY => self.rotation.center[1] = d,
            TcObject::Otc(obj) => {
                return self.with_ext(addr, |ext, g| ext.write(obj, addr, value, g))
            }
            group_key => self.write_group(group_key, addr, value),
        }
        Ok(())
    }
}

impl TcModule {
    /// TcPlane (device 0 index 3).
    pub fn plane(&self) -> TcPlane {
        self.plane
    }

    /// AxisNr X/Y/Z (device 0 index 2).
    pub fn axis_nr(&self) -> [u8; 3] {
        self.axis_nr
    }

    /// The group at `index` (1..=32), if it was created.
    pub fn group_at(&self, index: u16) -> Option<&CorrGroup> {
        let slot = usize::from(index).checked_sub(1)?;
        self.groups.get(slot)?.as_deref()
    }
}
