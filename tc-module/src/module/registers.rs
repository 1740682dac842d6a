//! The registers of devices 0..2 and their rules (docs/objects.md): STATUS
//! start/stop with its InitError conditions, RESET, Clean, ReInit, and
//! the registers that may not change while the correction runs.

use uoi::{AccessError, ObjectAddress, Value};

use super::{TcModule, DEFAULT_AXIS_NR};
use crate::bits::{ErrorBits, StatusBits};
use crate::correction::{FeedAdaption, TransitionMode};
use crate::extension::{Group, GroupAccess, TcExtension};
use crate::group::Side;
use crate::plane::TcPlane;
use crate::rotation::Rotation;
use crate::tool_table::WkzIndex;
use tc_objects::{TcObject, GROUP_COUNT};

/// The group slot (index - 1) of a device 1/2/3 address; the table limits
/// the index to 1..=32.
pub(super) fn slot_of(addr: ObjectAddress) -> usize {
    usize::from(addr.index).saturating_sub(1)
}

fn axis_u8(v: i32) -> u8 {
    // The table limits axis registers to 0..7.
    u8::try_from(v).unwrap_or(0)
}

impl<E: TcExtension> TcModule<E> {
    /// The group in `slot`, created on first access.
    pub(super) fn group_mut(&mut self, slot: usize) -> &mut Group<E> {
        self.groups[slot].get_or_insert_with(Default::default)
    }

    /// Runs `f` on the extension with the group in `slot` as the
    /// extension sees it (created on first access).
    pub(super) fn with_group<T>(
        &mut self,
        slot: usize,
        f: impl FnOnce(&mut E, GroupAccess<'_, E>) -> T,
    ) -> T {
        let (running, main) = (self.running == Some(slot), self.main_axes());
        let g = self.groups[slot].get_or_insert_with(Default::default);
        // slot < GROUP_COUNT (32) fits u16.
        f(
            &mut self.ext,
            GroupAccess::new(slot as u16 + 1, g, running, main),
        )
    }

    /// Writes a register of device 0.
    pub(super) fn write_global(
        &mut self,
        key: TcObject,
        addr: ObjectAddress,
        v: Value,
    ) -> Result<(), AccessError> {
        let i = v.as_i32().unwrap_or(0);
        let d = v.as_f64().unwrap_or(0.0);
        match key {
            TcObject::Clean => self.clean(),
            TcObject::AxisNr => self.axis_nr[usize::from(addr.sub)] = axis_u8(i),
            TcObject::TcPlane => self.plane = TcPlane::from_code(i).unwrap_or_default(),
            TcObject::ReInit => {
                self.position_request()?;
                for g in self.groups.iter_mut().flatten() {
                    g.buffer.clear();
                }
            }
            TcObject::Reset => (0..GROUP_COUNT).for_each(|slot| self.reset_group(slot)),
            TcObject::RotAngle => self.rotation.angle_deg = d,
            TcObject::RotCenterX => self.rotation.center.x = d,
            TcObject::RotCenterY => self.rotation.center.y = d,
            group_key => self.write_group(group_key, addr, v),
        }
        Ok(())
    }

    /// Reads a register of devices 0..2.
    pub(super) fn read_register(
        &mut self,
        key: TcObject,
        addr: ObjectAddress,
    ) -> Result<Value, AccessError> {
        Ok(match key {
            TcObject::AxisNr => Value::I32(i32::from(self.axis_nr[usize::from(addr.sub)])),
            TcObject::TcPlane => Value::I32(self.plane.code()),
            TcObject::RotAngle => Value::F64(self.rotation.angle_deg),
            TcObject::RotCenterX => Value::F64(self.rotation.center.x),
            TcObject::RotCenterY => Value::F64(self.rotation.center.y),
            group_key => return self.read_group(group_key, slot_of(addr)),
        })
    }

    fn read_group(&mut self, key: TcObject, slot: usize) -> Result<Value, AccessError> {
        let running = self.running == Some(slot);
        let g = self.group_mut(slot);
        Ok(match key {
            TcObject::Status => {
                let mut s = StatusBits::empty();
                s.set(StatusBits::RUN, running);
                s.set(StatusBits::PROF_MARKED, g.buffer.is_marked());
                Value::I32(s.bits())
            }
            TcObject::Error => Value::I32(g.error.bits()),
            TcObject::XAxis => Value::I32(i32::from(g.axes[0])),
            TcObject::YAxis => Value::I32(i32::from(g.axes[1])),
            TcObject::ZAxis => Value::I32(i32::from(g.axes[2])),
            TcObject::Radius => Value::F64(g.tool().radius),
            TcObject::WkzLen => Value::F64(g.tool().length),
            // WKZINDEX is below 1024.
            TcObject::WkzIndex => Value::I32(g.wkz.get() as i32),
            TcObject::TransitionMode => Value::I32(g.transition.code()),
            // Write-only objects never reach read (checked by the table).
            _ => return Err(AccessError::WriteOnly),
        })
    }

    /// Writes a register of devices 1 and 2. Registers that may not change
    /// while the group runs set InitError and keep their value.
    fn write_group(&mut self, key: TcObject, addr: ObjectAddress, v: Value) {
        let slot = slot_of(addr);
        let running = self.running == Some(slot);
        let i = v.as_i32().unwrap_or(0);
        let d = v.as_f64().unwrap_or(0.0);
        let g = self.group_mut(slot);
        let locked = matches!(
            key,
            TcObject::XAxis
                | TcObject::YAxis
                | TcObject::ZAxis
                | TcObject::WkzIndex
                | TcObject::Left
                | TcObject::Right
        );
        if running && locked {
            g.error |= ErrorBits::INIT_ERROR;
            return;
        }
        match key {
            TcObject::Error => g.clear_error(),
            TcObject::GroupReset => self.reset_group(slot),
            TcObject::Status if i == 1 => self.start(slot),
            TcObject::Status => self.stop(slot),
            TcObject::XAxis => g.axes[0] = axis_u8(i),
            TcObject::YAxis => g.axes[1] = axis_u8(i),
            TcObject::ZAxis => g.axes[2] = axis_u8(i),
            TcObject::Radius => g.tool_mut().radius = d,
            TcObject::WkzLen => g.tool_mut().length = d,
            TcObject::WkzIndex => self.change_tool(slot, i),
            TcObject::Left => g.side = Some(Side::Left),
            TcObject::Right => g.side = Some(Side::Right),
            TcObject::TransitionMode => g.transition = TransitionMode::from_code(i),
            _ => {}
        }
    }

    /// WKZINDEX written (not running): a different index is a tool change
    /// the extension hears of.
    fn change_tool(&mut self, slot: usize, i: i32) {
        let Some(w) = WkzIndex::new(i) else { return };
        let g = self.group_mut(slot);
        let outgoing = std::mem::replace(&mut g.wkz, w);
        if outgoing != w {
            self.with_group(slot, |ext, g| ext.tool_changed(outgoing, g));
        }
    }

    /// Device 0 Clean: every group, table and rotation back to defaults.
    fn clean(&mut self) {
        self.ext.clean();
        self.groups.iter_mut().for_each(|g| *g = None);
        self.running = None;
        self.departure = None;
        self.axis_nr = DEFAULT_AXIS_NR;
        self.plane = TcPlane::default();
        self.rotation = Rotation::default();
        self.feed_adaption = FeedAdaption::default();
    }

    /// The group RESET: the group's registers and table back to default
    /// (see `CorrGroup::reset`), Run cleared.
    fn reset_group(&mut self, slot: usize) {
        self.clear_run(slot);
        if let Some(g) = self.groups[slot].as_mut() {
            g.reset();
            self.with_group(slot, |ext, g| ext.group_reset(g));
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
        let g = self.group_mut(slot);
        let ready =
            g.side.is_some() && g.plane_axes(plane).distinct() && !other_running && !g.faulted;
        if ready {
            g.buffer.restart();
            self.running = Some(slot);
            self.departure = None;
        } else {
            g.error |= ErrorBits::INIT_ERROR;
        }
    }
}
