//! One block: its words gathered into a plan, then carried out in the
//! controller's order: plane, transitions, tool, `#OTC`, TRC, motion.

use tc_request::{ArcDir, AxisPos, AxisWords, Motion};
use uoi::Value;

use super::eval::eval;
use super::objects;
use super::otc::whole;
use super::plane::{self, RadiusArc};
use super::trc_state::{SelMode, Side};
use super::{Interpreter, MotionKind, RunErrorKind, WarningKind};
use crate::model::{Axis, Block, CentreAxis, GCode, Item, OtcCommand};

/// TRC change a block asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Trc {
    Off,
    On(Side),
}

/// What one block asks for, gathered from its words, each with the column
/// of the word that asked (for its errors).
#[derive(Default)]
struct Plan<'b> {
    words: AxisWords,
    centre: [Option<f64>; 3],
    /// Column of the block's first axis or centre word.
    motion_col: Option<usize>,
    plane: Option<(i32, usize)>,
    transition: Option<(i32, usize)>,
    tool: Option<(u32, usize)>,
    trc: Option<(Trc, usize)>,
    /// `G05` in this block (tangential selection or deselection), with
    /// its column.
    tangential: Option<usize>,
    /// `R`: the radius of an arc given by its end point.
    radius: Option<f64>,
    otc: Vec<(&'b OtcCommand, usize)>,
    end: bool,
}

fn axis_index(a: Axis) -> usize {
    match a {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
        Axis::A => 3,
        Axis::B => 4,
        Axis::C => 5,
        Axis::U => 6,
        Axis::V => 7,
    }
}

impl Interpreter<'_> {
    /// Carries out a block (no control statement); true at the program's end.
    pub(super) fn block(&mut self, block: &Block) -> Result<bool, RunErrorKind> {
        let mut plan = Plan::default();
        for (k, item) in block.items.iter().enumerate() {
            self.col = block.column(k);
            self.gather(item, &mut plan)?;
        }
        self.apply(&plan)?;
        Ok(plan.end)
    }

    /// The value of a word: a plain number at once, else evaluated.
    #[inline]
    fn value(&mut self, e: &crate::Expr) -> Result<f64, RunErrorKind> {
        match e {
            crate::Expr::Number(v) if v.is_finite() => Ok(*v),
            e => eval(e, self),
        }
    }

    fn gather<'b>(&mut self, item: &'b Item, plan: &mut Plan<'b>) -> Result<(), RunErrorKind> {
        match item {
            Item::ProgramName(_) | Item::Kinematic(_) | Item::Trafo(_) | Item::Hsc { .. } => {}
            Item::G(g) => self.g_code(*g, plan)?,
            Item::Axis(a, e) => {
                plan.words[axis_index(*a)] = Some(self.value(e)?);
                plan.motion_col.get_or_insert(self.col);
            }
            Item::Centre(c, e) => {
                let k = match c {
                    CentreAxis::I => 0,
                    CentreAxis::J => 1,
                    CentreAxis::K => 2,
                };
                plan.centre[k] = Some(self.value(e)?);
                plan.motion_col.get_or_insert(self.col);
            }
            Item::Feed(e) => self.feed_pending = Some(self.value(e)?),
            Item::ToolData(e) => {
                let d = whole(eval(e, self)?, "D")?;
                let d = u32::try_from(d)
                    .ok()
                    .filter(|d| *d <= 255)
                    .ok_or(RunErrorKind::DataSet { d })?;
                plan.tool = Some((d, self.col));
            }
            Item::Tool(_) => self.warn(WarningKind::ToolWord),
            Item::TrcOption(_) | Item::ArcRadius(_) | Item::TangFeed(_) => {
                self.trc_word(item, plan)?
            }
            Item::M(30) => plan.end = true,
            Item::M(m) => return Err(RunErrorKind::MFunction(*m)),
            Item::Assign(var, e) => {
                let v = eval(e, self)?;
                self.assign(var, v)?;
            }
            Item::Otc(cmd) => plan.otc.push((cmd, self.col)),
            Item::SetToolParam {
                line,
                column,
                value,
            } => self.set_tool_param(line, column, value)?,
            Item::GetToolParam {
                line,
                column,
                target,
            } => {
                let (l, c) = (eval(line, self)?, eval(column, self)?);
                let v = self.dtable.get(l, c)?;
                self.assign(target, v)?;
            }
            _ => return Err(RunErrorKind::ControlNotAlone),
        }
        Ok(())
    }

    /// The words of the radius correction's ISG functions: `#TRC`, an
    /// arc's `R`, `#TANGFEED`.
    fn trc_word(&mut self, item: &Item, plan: &mut Plan) -> Result<(), RunErrorKind> {
        match item {
            Item::TrcOption(name) => return Err(RunErrorKind::TrcOption(name.clone())),
            Item::ArcRadius(e) => {
                plan.radius = Some(self.value(e)?);
                plan.motion_col.get_or_insert(self.col);
            }
            Item::TangFeed(rmin) => {
                let rmin = match rmin {
                    Some(e) => self.value(e)?,
                    None => 0.0,
                };
                self.set_tangfeed(rmin)?;
            }
            _ => {}
        }
        Ok(())
    }

    fn set_tool_param(
        &mut self,
        line: &crate::Expr,
        column: &crate::Expr,
        value: &crate::Expr,
    ) -> Result<(), RunErrorKind> {
        let (l, c, v) = (eval(line, self)?, eval(column, self)?, eval(value, self)?);
        if self.trc.is_some() && self.tool.is_some_and(|d| f64::from(d) == l) {
            return Err(RunErrorKind::ToolParamInUse { line: l });
        }
        self.dtable.set(l, c, v)
    }

    fn g_code(&mut self, g: GCode, plan: &mut Plan) -> Result<(), RunErrorKind> {
        use GCode::*;
        match g {
            Rapid => self.motion = Some(MotionKind::Rapid),
            Linear => self.motion = Some(MotionKind::Linear),
            ArcCw => self.motion = Some(MotionKind::Cw),
            ArcCcw => self.motion = Some(MotionKind::Ccw),
            Absolute => self.incremental = false,
            Incremental => self.incremental = true,
            PlaneXy => plan.plane = Some((17, self.col)),
            PlaneZx => plan.plane = Some((18, self.col)),
            PlaneYz => plan.plane = Some((19, self.col)),
            TransitionLinear => plan.transition = Some((1, self.col)),
            TransitionCircular => plan.transition = Some((0, self.col)),
            TrcOff => plan.trc = Some((Trc::Off, self.col)),
            TrcLeft => plan.trc = Some((Trc::On(Side::Left), self.col)),
            TrcRight => plan.trc = Some((Trc::On(Side::Right), self.col)),
            TrcTangential => plan.tangential = Some(self.col),
            TrcDirect => self.set_mode(SelMode::Direct)?,
            TrcIndirect => self.set_mode(SelMode::Indirect)?,
            TrcOnPath => self.set_mode(SelMode::OnPath)?,
            TrcPerpendicular => self.set_mode(SelMode::Perpendicular)?,
            TrcInsideCorner => self.set_mode(SelMode::InsideCorner)?,
            TrcWithoutBlock => self.set_mode(SelMode::WithoutBlock)?,
            FeedConstant => self.set_feed_adaption(false)?,
            FeedAdapted => self.set_feed_adaption(true)?,
            // No masking is what the engine does anyway.
            MaskingOff => {}
            MaskingOn => return Err(RunErrorKind::ContourMasking),
        }
        Ok(())
    }

    fn apply(&mut self, plan: &Plan) -> Result<(), RunErrorKind> {
        if let Some((p, col)) = plan.plane.filter(|(p, _)| self.plane != Some(*p)) {
            self.col = col;
            self.write(objects::TC_PLANE, Value::I32(p))?;
            self.plane = Some(p);
        }
        if let Some((t, col)) = plan.transition.filter(|(t, _)| self.transition != Some(*t)) {
            self.col = col;
            self.write(objects::TRANSITION_MODE, Value::I32(t))?;
            self.transition = Some(t);
        }
        if let Some((d, col)) = plan.tool {
            self.col = col;
            self.select_tool(d)?;
        }
        for (cmd, col) in &plan.otc {
            self.col = *col;
            self.otc(cmd)?;
        }
        let tangential = plan.tangential.is_some_and(|col| self.tangential_acts(col));
        if let Some((trc, col)) = plan.trc {
            self.col = col;
            match trc {
                Trc::Off => self.deselect(tangential)?,
                Trc::On(side) => self.select(side, tangential)?,
            }
        }
        if let Some(col) = plan.motion_col {
            self.col = col;
        }
        self.motion_of(plan)
    }

    /// `D n`: the tool entry, and the D table's radius and length.
    fn select_tool(&mut self, d: u32) -> Result<(), RunErrorKind> {
        self.radius_change()?;
        let data = if d == 0 {
            Some((0.0, 0.0))
        } else {
            self.dtable.tool(d)
        };
        if self.trc.is_none() {
            // d <= 255 was checked.
            self.write(objects::WKZINDEX, Value::I32(d as i32))?;
        } else if data.is_none() {
            self.warn(WarningKind::ToolDataKept { d });
        }
        if let Some((radius, length)) = data {
            self.write(objects::RADIUS, Value::F64(radius))?;
            self.write(objects::WKZ_LEN, Value::F64(length))?;
        }
        self.tool = Some(d);
        Ok(())
    }

    /// The block's motion, if it has axis words (or an arc's centre).
    fn motion_of(&mut self, plan: &Plan) -> Result<(), RunErrorKind> {
        // An axis or centre word was read (its column kept).
        if plan.motion_col.is_none() {
            return Ok(());
        }
        let has_centre = plan.centre.iter().any(Option::is_some);
        let Some(kind) = self.motion else {
            return Err(RunErrorKind::NoMotionKind);
        };
        let mut words: AxisWords = plan.words;
        let start = self.pos;
        for (w, pos) in words.iter_mut().zip(self.pos.iter_mut()) {
            if let Some(v) = w {
                if self.incremental {
                    *v += *pos;
                }
                *pos = *v;
            }
        }
        let feed = self.feed_pending.take();
        let is_arc = matches!(kind, MotionKind::Cw | MotionKind::Ccw);
        let centre = match plan.radius {
            Some(r) if is_arc => self.centre_of_radius(kind, &start, &plan.centre, r)?,
            _ => plan.centre,
        };
        let motion = match kind {
            MotionKind::Rapid | MotionKind::Linear if plan.radius.is_some() => {
                return Err(RunErrorKind::RadiusWord("needs G2 or G3"));
            }
            MotionKind::Rapid | MotionKind::Linear if has_centre => {
                return Err(RunErrorKind::CentreWithoutArc);
            }
            MotionKind::Rapid => Motion::Rap { words, feed },
            MotionKind::Linear => Motion::Lin { words, feed },
            MotionKind::Cw | MotionKind::Ccw => Motion::Cir {
                dir: if kind == MotionKind::Cw {
                    ArcDir::Cw
                } else {
                    ArcDir::Ccw
                },
                words,
                centre,
                feed,
            },
        };
        self.motion(motion, start)
    }
}

impl Interpreter<'_> {
    /// The centre offsets `I J K` of an arc from `start` to the position
    /// reached, given by its radius `r` (docs/nc.md, "Arcs by radius").
    fn centre_of_radius(
        &self,
        kind: MotionKind,
        start: &AxisPos,
        centre: &[Option<f64>; 3],
        r: f64,
    ) -> Result<[Option<f64>; 3], RunErrorKind> {
        if centre.iter().any(Option::is_some) {
            return Err(RunErrorKind::RadiusWord("together with I, J or K"));
        }
        let (h, v) = plane::plane_axes(self.plane);
        let (s, e) = ([start[h], start[v]], [self.pos[h], self.pos[v]]);
        let c = match plane::centre_from_radius(s, e, r, kind == MotionKind::Ccw) {
            Ok(c) => c,
            Err(RadiusArc::FullCircle) => {
                return Err(RunErrorKind::RadiusWord(
                    "with start = end: a full circle needs I, J or K",
                ))
            }
            Err(RadiusArc::TooShort { half_chord }) => {
                return Err(RunErrorKind::RadiusTooShort {
                    radius: r,
                    half_chord,
                })
            }
        };
        let mut out = [None; 3];
        // The plane axes are X, Y or Z: the centre words I, J, K.
        out[h] = Some(c[0] - s[0]);
        out[v] = Some(c[1] - s[1]);
        Ok(out)
    }
}
