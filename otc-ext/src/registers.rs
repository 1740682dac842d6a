//! The OTC registers of devices 3 and 4 (docs/objects.md), the request
//! registers' bound, writes while OTC is on (docs/otc.md) and the
//! hooks the TC module calls ([`TcExtension`] for [`OtcExtension`]);
//! switching is in `switching`, the per-cycle model in `wear` and
//! `per_cycle`.

use tc_module::{GroupAccess, Groups, TcExtension, WkzIndex, AXES};
use uoi::{AccessError, ObjectAddress, ObjectDesc, Value};

use crate::extension::OtcExtension;
use crate::objects::{OtcObject, AXIS_OBJECTS, GROUP_OBJECTS, WEAR_AXIS_SUBS};
use crate::per_cycle::WearModel;
use crate::plc::clamp_command;
use crate::quantity::{TenthMicrons, TiltAngle, WearRate};
use crate::state::{OtcErrorBits, OtcGroup, OtcTool};
use crate::switching::{booked_entry, check_units, switches_off};
use tc_objects::{OtcMode, ProcType};

type Access<'a> = GroupAccess<'a, OtcExtension>;

impl OtcExtension {
    /// Rule 7: the bound of the request registers, ToolMaxInfeed of the
    /// current entry of the group whose OTC is on, else of group 1's.
    fn request_bound(&self, groups: &mut Groups<'_, Self>) -> TenthMicrons {
        groups
            .get(self.on_group.unwrap_or(1))
            .map_or(TenthMicrons::default(), |g| g.tool().ext.max_infeed)
    }
}

fn int(v: Value) -> i32 {
    v.as_i32().unwrap_or(0)
}

fn dbl(v: Value) -> f64 {
    v.as_f64().unwrap_or(0.0)
}

fn read_group_state(
    obj: OtcObject,
    addr: ObjectAddress,
    s: &OtcGroup,
    tool: &OtcTool,
    bound: TenthMicrons,
) -> Option<Value> {
    use OtcObject as O;
    let i = |v: i32| Some(Value::I32(v));
    let d = |v: f64| Some(Value::F64(v));
    match obj {
        O::OtcOn => i(i32::from(s.on)),
        O::ProcType => i(s.proc_type.code()),
        O::Mode => i(s.mode.code()),
        O::WearConst if s.on => d(s.const_in_force.0),
        O::WearConst => d(s.wear_const_override.unwrap_or(tool.wear_const).0),
        O::AccWeight => i(s.acc_weight),
        O::OtcError => i(s.error.bits()),
        O::WearRadius => d(s.wear_radius),
        O::WearRadiusCont => d(s.wear_radius_cont),
        O::WearAxis => d(s.wear_axis[usize::from(addr.sub - WEAR_AXIS_SUBS.start())]),
        O::AllowPosReq => i(i32::from(s.allow_pos_req)),
        // OriAxis is 0..7 (the table's range).
        O::OriAxis => i(s.ori_axis as i32),
        O::RadiusOffsetCommand => i(s.radius_unit.command),
        O::RadiusOffsetEnable => i(i32::from(s.radius_unit.enable)),
        O::RadiusOffsetRequest => i(clamp_command(s.radius_unit.command, bound)),
        O::RadiusOffsetState => i(s.radius_unit.state()),
        O::HandoffCount => i(s.handoff_count),
        O::HandoffToolIndex => i(s.handoff_tool),
        O::HandoffWearRadius => d(s.handoff_wear_radius),
        O::HandoffWearRadiusCont => d(s.handoff_wear_radius_cont),
        O::ToolType => i(tool.tool_type),
        O::ToolWearConst => d(tool.wear_const.0),
        O::ToolMaxInfeed => d(tool.max_infeed.0),
        O::ToolTiltAngle => d(tool.tilt.0),
        _ => None,
    }
}

/// Writes a tool field of the entry at WKZINDEX; `false` if `obj` is none.
fn write_tool(obj: OtcObject, v: Value, tool: &mut OtcTool) -> bool {
    use OtcObject as O;
    match obj {
        O::ToolType => tool.tool_type = int(v),
        O::ToolWearConst => tool.wear_const = WearRate(dbl(v)),
        O::ToolMaxInfeed => tool.max_infeed = TenthMicrons(dbl(v)),
        O::ToolTiltAngle => tool.tilt = TiltAngle(dbl(v)),
        _ => return false,
    }
    true
}

/// Writes a register of the group's OTC state; `false` if `obj` is none.
fn write_state(obj: OtcObject, v: Value, s: &mut OtcGroup) -> bool {
    use OtcObject as O;
    match obj {
        O::ProcType | O::Mode if s.on => s.error |= OtcErrorBits::SEQUENCE,
        O::ProcType => s.proc_type = ProcType::from_code(int(v)),
        O::Mode => s.mode = OtcMode::from_code(int(v)),
        O::WearConst => s.wear_const_override = Some(WearRate(dbl(v))),
        O::WearConstTool => s.wear_const_override = None,
        O::AccWeight => s.acc_weight = int(v),
        O::OtcError => s.error = OtcErrorBits::empty(),
        O::AllowPosReq => s.allow_pos_req = int(v) == 1,
        // The table limits OriAxis to 0..7.
        O::OriAxis => s.ori_axis = usize::try_from(int(v)).unwrap_or(0),
        O::RadiusOffsetCommand => s.radius_unit.command = int(v),
        O::RadiusOffsetEnable => s.radius_unit.enable = int(v) == 1,
        _ => return false,
    }
    true
}

impl TcExtension for OtcExtension {
    type Key = OtcObject;
    type Group = OtcGroup;
    type Tool = OtcTool;
    type Model<'a> = WearModel<'a>;
    const GROUP_OBJECTS: &'static [ObjectDesc<OtcObject>] = &GROUP_OBJECTS;
    const OBJECTS: &'static [ObjectDesc<OtcObject>] = &AXIS_OBJECTS;

    fn read_group(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        mut groups: Groups<'_, Self>,
    ) -> Result<Value, AccessError> {
        let bound = self.request_bound(&mut groups);
        let g = groups.get(addr.index).ok_or(AccessError::NoObject)?;
        // Write-only objects never reach read (checked by the table).
        read_group_state(obj, addr, g.state(), &g.tool().ext, bound).ok_or(AccessError::WriteOnly)
    }

    fn write_group(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        v: Value,
        mut groups: Groups<'_, Self>,
    ) -> Result<(), AccessError> {
        if obj == OtcObject::OtcOn {
            return self.write_on(addr.index, int(v) == 1, groups);
        }
        let mut g = groups.get(addr.index).ok_or(AccessError::NoObject)?;
        // The tool fields are the module's to set (`write_tool`).
        if write_state(obj, v, g.state_mut()) {
            if obj == OtcObject::RadiusOffsetEnable && int(v) == 1 && g.state().on {
                check_units(&mut g, &self.axes);
            }
            return Ok(());
        }
        // Read-only objects never reach write (checked by the table).
        Err(AccessError::ReadOnly)
    }

    fn read(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        mut groups: Groups<'_, Self>,
    ) -> Result<Value, AccessError> {
        use OtcObject as O;
        let bound = self.request_bound(&mut groups);
        let unit = self
            .axes
            .get(usize::from(addr.index))
            .ok_or(AccessError::NoObject)?;
        Ok(Value::I32(match obj {
            O::AxisOffsetCommand => unit.command,
            O::AxisOffsetEnable => i32::from(unit.enable),
            O::AxisOffsetRequest => clamp_command(unit.command, bound),
            O::AxisOffsetState => unit.state(),
            _ => return Err(AccessError::NoObject),
        }))
    }

    fn write(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        v: Value,
        mut groups: Groups<'_, Self>,
    ) -> Result<(), AccessError> {
        use OtcObject as O;
        let unit = self
            .axes
            .get_mut(usize::from(addr.index))
            .ok_or(AccessError::NoObject)?;
        match obj {
            O::AxisOffsetCommand => unit.command = int(v),
            O::AxisOffsetEnable => unit.enable = int(v) == 1,
            _ => return Err(AccessError::ReadOnly),
        }
        if obj == O::AxisOffsetEnable && int(v) == 1 {
            if let Some(mut g) = self.on_group.and_then(|i| groups.get(i)) {
                check_units(&mut g, &self.axes);
            }
        }
        Ok(())
    }

    fn write_tool(obj: OtcObject, v: Value, tool: &mut OtcTool) -> bool {
        write_tool(obj, v, tool)
    }

    fn tool_after(
        &self,
        obj: OtcObject,
        v: Value,
        group: &tc_module::Group<Self>,
        running: bool,
        main: tc_module::MainAxes,
    ) -> Result<Option<tc_module::ToolEntry<OtcTool>>, AccessError> {
        if obj != OtcObject::OtcOn || int(v) == 1 || !switches_off(&group.ext, running) {
            return Ok(None);
        }
        booked_entry(&group.ext, group.tool(), &self.axes, main).map(Some)
    }

    fn tool_changed(&mut self, outgoing: WkzIndex, mut g: Access<'_>) {
        let s = g.state_mut();
        s.handoff_count = s.handoff_count.wrapping_add(1);
        // WKZINDEX is below 1024.
        s.handoff_tool = outgoing.get() as i32;
        s.handoff_wear_radius = s.wear_radius;
        s.handoff_wear_radius_cont = s.wear_radius_cont;
        s.wear_radius = 0.0;
        s.wear_radius_cont = 0.0;
        s.wear_axis = [0.0; AXES];
    }

    fn clean(&mut self) {
        *self = Self::default();
    }

    fn cycle_model<'a>(&'a mut self, groups: Groups<'a, Self>) -> WearModel<'a> {
        WearModel::new(self, groups)
    }

    fn position_request(&mut self, mut groups: Groups<'_, Self>) -> Result<(), AccessError> {
        let mut refused = false;
        for mut g in groups.iter_mut() {
            let s = g.state_mut();
            if s.on && !s.allow_pos_req {
                s.error |= OtcErrorBits::POS_REQUEST;
                refused = true;
            }
        }
        if refused {
            Err(AccessError::State)
        } else {
            Ok(())
        }
    }
}
