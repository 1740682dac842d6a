//! The OTC registers of devices 3 and 4 (uoi-map.md) and the switching
//! rules of otc.md.

use bitflags::bitflags;
use tc_module::tool_table::TOOL_ENTRIES;
use tc_module::{GroupContext, OtcObject, TcExtension, WkzIndex, AXES};
use uoi::{AccessError, ObjectAddress, Value};

bitflags! {
    /// OtcError register bits (device 3 sub 7).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct OtcErrorBits: i32 {
        /// bit0: OTC ON with a tool that is not a grinding tool (P-ERR-21391).
        const TOOL_TYPE = 1;
        /// bit1: command out of sequence (ISG 90050).
        const SEQUENCE = 2;
        /// bit2: position request refused while OTC is on (ISG 21572).
        const POS_REQUEST = 4;
        /// bit3: a PLC unit used with a type or mode that ignores it.
        const NOT_ALLOWED = 8;
    }
}

/// Processing type (device 3 sub 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ProcType {
    /// 0: wear as a radius change.
    Radius,
    /// 1: wear along the tool length (default).
    #[default]
    Length,
    /// 2: wear along the tool direction.
    ToolDir,
    /// 3: wear along the surface normal.
    SurfNormDir,
}

impl ProcType {
    fn from_code(v: i32) -> Self {
        match v {
            0 => ProcType::Radius,
            2 => ProcType::ToolDir,
            3 => ProcType::SurfNormDir,
            _ => ProcType::Length,
        }
    }

    fn code(self) -> i32 {
        match self {
            ProcType::Radius => 0,
            ProcType::Length => 1,
            ProcType::ToolDir => 2,
            ProcType::SurfNormDir => 3,
        }
    }
}

/// OTC mode (device 3 sub 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OtcMode {
    /// 0: discrete offsets from the PLC only.
    Disc,
    /// 1: continuous wear only.
    Cont,
    /// 2: both (default).
    #[default]
    Auto,
}

impl OtcMode {
    fn from_code(v: i32) -> Self {
        match v {
            0 => OtcMode::Disc,
            1 => OtcMode::Cont,
            _ => OtcMode::Auto,
        }
    }

    fn code(self) -> i32 {
        match self {
            OtcMode::Disc => 0,
            OtcMode::Cont => 1,
            OtcMode::Auto => 2,
        }
    }
}

/// The OTC fields of one tool entry (P-TOOL parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct OtcTool {
    /// P-TOOL-00001: 0 milling, 1 turning, 2 grinding, 3 wire.
    tool_type: i32,
    /// P-TOOL-00030, 0.1 µm/m.
    wear_const: f64,
    /// P-TOOL-00031, 0.1 µm.
    max_infeed: f64,
    /// P-TOOL-00138, 0.0001°.
    tilt: f64,
}

/// A PLC control unit: command, enable, applied state (0.1 µm).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct PlcUnit {
    command: i32,
    enable: bool,
    state: i32,
}

/// Clamps a PLC command to ± the tool's maximum infeed (0: no discrete offset).
fn clamp_command(command: i32, max_infeed: f64) -> i32 {
    let bound = max_infeed.abs().min(f64::from(i32::MAX)).floor();
    f64::from(command).clamp(-bound, bound) as i32
}

/// OTC state of one compensation group.
#[derive(Debug, Clone)]
struct OtcGroup {
    on: bool,
    proc_type: ProcType,
    mode: OtcMode,
    /// WearConst written since the last WearConstTool.
    wear_const_override: Option<f64>,
    /// The constant fixed at OTC ON.
    const_in_force: f64,
    acc_weight: i32,
    error: OtcErrorBits,
    wear_radius: f64,
    wear_radius_cont: f64,
    wear_axis: [f64; AXES],
    allow_pos_req: bool,
    ori_axis: i32,
    radius_unit: PlcUnit,
    /// Continuous and discrete wear accumulated since OTC ON.
    w_cont: f64,
    w_disc: f64,
    /// The group's WKZINDEX as last seen.
    wkz: usize,
    handoff_count: i32,
    handoff_tool: i32,
    handoff_wear_radius: f64,
    handoff_wear_radius_cont: f64,
    tools: Box<[OtcTool; TOOL_ENTRIES]>,
}

impl Default for OtcGroup {
    fn default() -> Self {
        Self {
            on: false,
            proc_type: ProcType::default(),
            mode: OtcMode::default(),
            wear_const_override: None,
            const_in_force: 0.0,
            acc_weight: 100,
            error: OtcErrorBits::empty(),
            wear_radius: 0.0,
            wear_radius_cont: 0.0,
            wear_axis: [0.0; AXES],
            allow_pos_req: false,
            ori_axis: 4,
            radius_unit: PlcUnit::default(),
            w_cont: 0.0,
            w_disc: 0.0,
            wkz: 0,
            handoff_count: 0,
            handoff_tool: 0,
            handoff_wear_radius: 0.0,
            handoff_wear_radius_cont: 0.0,
            tools: Box::new([OtcTool::default(); TOOL_ENTRIES]),
        }
    }
}

/// The OTC extension: devices 3 (per group) and 4 (per machine axis).
#[derive(Debug, Default)]
pub struct OtcExtension {
    groups: [Option<Box<OtcGroup>>; 32],
    axes: [PlcUnit; AXES],
}

impl OtcExtension {
    fn group(&mut self, index: u16) -> &mut OtcGroup {
        self.groups[usize::from(index) - 1].get_or_insert_with(Default::default)
    }

    /// The group whose OTC is on, if any.
    fn active(&self) -> Option<&OtcGroup> {
        self.groups.iter().flatten().map(|g| &**g).find(|g| g.on)
    }

    /// `#OTC OFF`: the wear accumulated since ON is booked on the tool and
    /// read back through the V.G. values (otc.md "Switching off").
    fn switch_off(g: &mut OtcGroup, ctx: &mut GroupContext<'_>) {
        let w = g.w_cont + g.w_disc;
        match g.proc_type {
            ProcType::Radius => {
                g.wear_radius += w;
                g.wear_radius_cont += g.w_cont;
                ctx.group.tool_mut().radius -= w;
            }
            _ => {
                // The wear direction in force is applied by the cycle model;
                // with w = 0 nothing changes per axis.
                ctx.group.tool_mut().length -= w;
            }
        }
        g.w_cont = 0.0;
        g.w_disc = 0.0;
        g.on = false;
    }
}

fn int(v: Value) -> i32 {
    v.as_i32().unwrap_or(0)
}

fn dbl(v: Value) -> f64 {
    v.as_f64().unwrap_or(0.0)
}

impl TcExtension for OtcExtension {
    fn read(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        ctx: Option<GroupContext<'_>>,
    ) -> Result<Value, AccessError> {
        use OtcObject as O;
        let Some(ctx) = ctx else {
            let bound = self.active().map_or(0.0, |g| g.tools[g.wkz].max_infeed);
            let unit = self
                .axes
                .get(usize::from(addr.index))
                .ok_or(AccessError::NoObject)?;
            return Ok(Value::I32(match obj {
                O::AxisOffsetCommand => unit.command,
                O::AxisOffsetEnable => i32::from(unit.enable),
                O::AxisOffsetRequest => clamp_command(unit.command, bound),
                O::AxisOffsetState => unit.state,
                _ => return Err(AccessError::NoObject),
            }));
        };
        let wkz = ctx.group.wkz.get();
        let g = self.group(ctx.index);
        g.wkz = wkz;
        let tool = g.tools[wkz];
        Ok(match obj {
            O::OtcOn => Value::I32(i32::from(g.on)),
            O::ProcType => Value::I32(g.proc_type.code()),
            O::Mode => Value::I32(g.mode.code()),
            O::WearConst => Value::F64(if g.on {
                g.const_in_force
            } else {
                g.wear_const_override.unwrap_or(tool.wear_const)
            }),
            O::AccWeight => Value::I32(g.acc_weight),
            O::OtcError => Value::I32(g.error.bits()),
            O::WearRadius => Value::F64(g.wear_radius),
            O::WearRadiusCont => Value::F64(g.wear_radius_cont),
            O::WearAxis => Value::F64(g.wear_axis[usize::from(addr.sub - 20) % AXES]),
            O::ToolType => Value::I32(tool.tool_type),
            O::ToolWearConst => Value::F64(tool.wear_const),
            O::ToolMaxInfeed => Value::F64(tool.max_infeed),
            O::ToolTiltAngle => Value::F64(tool.tilt),
            O::AllowPosReq => Value::I32(i32::from(g.allow_pos_req)),
            O::OriAxis => Value::I32(g.ori_axis),
            O::RadiusOffsetCommand => Value::I32(g.radius_unit.command),
            O::RadiusOffsetEnable => Value::I32(i32::from(g.radius_unit.enable)),
            O::RadiusOffsetRequest => {
                Value::I32(clamp_command(g.radius_unit.command, tool.max_infeed))
            }
            O::RadiusOffsetState => Value::I32(g.radius_unit.state),
            O::HandoffCount => Value::I32(g.handoff_count),
            O::HandoffToolIndex => Value::I32(g.handoff_tool),
            O::HandoffWearRadius => Value::F64(g.handoff_wear_radius),
            O::HandoffWearRadiusCont => Value::F64(g.handoff_wear_radius_cont),
            _ => return Err(AccessError::WriteOnly),
        })
    }

    fn write(
        &mut self,
        obj: OtcObject,
        addr: ObjectAddress,
        v: Value,
        ctx: Option<GroupContext<'_>>,
    ) -> Result<(), AccessError> {
        use OtcObject as O;
        let Some(mut ctx) = ctx else {
            let unit = self
                .axes
                .get_mut(usize::from(addr.index))
                .ok_or(AccessError::NoObject)?;
            match obj {
                O::AxisOffsetCommand => unit.command = int(v),
                O::AxisOffsetEnable => unit.enable = int(v) == 1,
                _ => return Err(AccessError::NoObject),
            }
            return Ok(());
        };
        let wkz = ctx.group.wkz.get();
        let running = ctx.running;
        let g = self.group(ctx.index);
        g.wkz = wkz;
        match obj {
            O::OtcOn => {
                if int(v) == 1 {
                    if g.on {
                        return Ok(());
                    }
                    let tool = g.tools[wkz];
                    if tool.tool_type != 2 {
                        g.error |= OtcErrorBits::TOOL_TYPE;
                    } else {
                        g.const_in_force = g.wear_const_override.unwrap_or(tool.wear_const);
                        g.on = true;
                    }
                } else if g.on {
                    if g.proc_type == ProcType::Radius && running {
                        g.error |= OtcErrorBits::SEQUENCE;
                    } else {
                        Self::switch_off(g, &mut ctx);
                    }
                }
            }
            O::ProcType | O::Mode if g.on => g.error |= OtcErrorBits::SEQUENCE,
            O::ProcType => g.proc_type = ProcType::from_code(int(v)),
            O::Mode => g.mode = OtcMode::from_code(int(v)),
            O::WearConst => g.wear_const_override = Some(dbl(v)),
            O::WearConstTool => g.wear_const_override = None,
            O::AccWeight => g.acc_weight = int(v),
            O::OtcError => g.error = OtcErrorBits::empty(),
            O::ToolType => g.tools[wkz].tool_type = int(v),
            O::ToolWearConst => g.tools[wkz].wear_const = dbl(v),
            O::ToolMaxInfeed => g.tools[wkz].max_infeed = dbl(v),
            O::ToolTiltAngle => g.tools[wkz].tilt = dbl(v),
            O::AllowPosReq => g.allow_pos_req = int(v) == 1,
            O::OriAxis => g.ori_axis = int(v),
            O::RadiusOffsetCommand => g.radius_unit.command = int(v),
            O::RadiusOffsetEnable => g.radius_unit.enable = int(v) == 1,
            // Read-only objects never reach write (checked by the table).
            _ => return Err(AccessError::ReadOnly),
        }
        Ok(())
    }

    fn tool_changed(&mut self, group: u16, outgoing: WkzIndex, incoming: WkzIndex) {
        let g = self.group(group);
        g.wkz = incoming.get();
        g.handoff_count = g.handoff_count.wrapping_add(1);
        g.handoff_tool = outgoing.get() as i32;
        g.handoff_wear_radius = g.wear_radius;
        g.handoff_wear_radius_cont = g.wear_radius_cont;
        g.wear_radius = 0.0;
        g.wear_radius_cont = 0.0;
        g.wear_axis = [0.0; AXES];
    }

    fn group_reset(&mut self, group: u16) {
        if let Some(g) = self.groups[usize::from(group) - 1].as_mut() {
            g.tools.fill(OtcTool::default());
        }
    }

    fn clean(&mut self) {
        *self = Self::default();
    }

    fn position_request(&mut self) -> Result<(), AccessError> {
        let mut refused = false;
        for g in self.groups.iter_mut().flatten() {
            if g.on && !g.allow_pos_req {
                g.error |= OtcErrorBits::POS_REQUEST;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp() {
        assert_eq!(clamp_command(500, 100.0), 100);
        assert_eq!(clamp_command(-500, 100.0), -100);
        assert_eq!(clamp_command(50, 100.0), 50);
        assert_eq!(clamp_command(50, 0.0), 0);
        assert_eq!(clamp_command(i32::MIN, 1e300), i32::MIN + 1);
    }
}
