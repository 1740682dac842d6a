//! The interpreter: runs a parsed program block by block and turns it into
//! the requests of `tc-request` (object writes, motion commands, `EXEC`),
//! which a [`Controller`] carries out. It keeps the modal state (motion
//! kind, G90/G91 and the absolute position, feed, plane, tool, TRC side),
//! the parameters and variables and the D table; it has no geometry of its
//! own: the correction is the controller's.
//!
//! The program is held as a block list so that `$FOR`, `$WHILE` and `$IF`
//! can jump; at most [`MAX_EXECUTED_BLOCKS`] blocks are executed.

mod block;
mod dtable;
mod eval;
mod flow;
mod objects;
mod otc;
mod vars;

use std::collections::HashMap;

use tc_request::{AxisPos, Reply, Request};

use crate::error::NcError;
use crate::model::{Block, Item};
use crate::Var;

pub use dtable::DTable;
pub use objects::{wear_axis, WEAR_RADIUS, WEAR_RADIUS_CONT};

/// Most blocks one run executes (loops included) before it stops with an
/// error.
pub const MAX_EXECUTED_BLOCKS: u64 = 10_000_000;

/// The block a request comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct At {
    /// Line of the program, from 1.
    pub line: usize,
    /// Its `N` number, if any.
    pub number: Option<u32>,
}

/// What carries out the interpreter's requests: an emulator, a remote
/// server, a recorder around either.
pub trait Controller {
    /// Carries out `req`, sent for the block at `at`, and answers it.
    fn call(&mut self, req: &Request, at: At) -> Reply;
}

/// What a run reports besides its requests.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Constructs run in a simpler way than the program asks (e.g. G139
    /// run as G138), with where they stand.
    pub warnings: Vec<NcError>,
    /// Errors the controller signalled while the program ran on (OTC error
    /// bits with their ISG ids), with the block that caused them.
    pub faults: Vec<NcError>,
}

/// Motion kind of G0/G1/G2/G3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MotionKind {
    Rapid,
    Linear,
    Cw,
    Ccw,
}

/// TRC side of G41/G42.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
}

/// The interpreter's state between blocks.
struct Interpreter<'c> {
    report: &'c mut Report,
    ctl: &'c mut dyn Controller,
    at: At,
    pos: AxisPos,
    motion: Option<MotionKind>,
    incremental: bool,
    feed_pending: Option<f64>,
    plane: Option<i32>,
    transition: Option<i32>,
    tool: Option<u32>,
    trc: Option<Side>,
    r: HashMap<u32, f64>,
    p: HashMap<u32, f64>,
    v: HashMap<String, f64>,
    dtable: DTable,
    for_state: HashMap<usize, (f64, f64)>,
    otc_seen: i32,
}

/// Runs `blocks` (a whole parsed program without errors) on `ctl`, ending
/// with `EXEC` (run until the spooler is empty); warnings and controller
/// faults go to `report`, also when the run stops. Stops at the first
/// error: a construct not implemented, an unset variable, a request the
/// controller refuses.
pub fn run_program(
    blocks: &[Block],
    ctl: &mut dyn Controller,
    report: &mut Report,
) -> Result<(), NcError> {
    let jumps = flow::jumps(blocks)?;
    let mut it = Interpreter::new(ctl, report);
    let start = blocks.first().map_or(At::default(), |b| At {
        line: b.line,
        number: b.number,
    });
    it.at = start;
    it.pos = match it.ctl.call(&Request::Pos, start) {
        Reply::Pos(p) => p,
        other => return Err(it.error(format!("POS answered {other:?}"))),
    };
    let mut pc = 0;
    let mut executed = 0u64;
    while let Some(block) = blocks.get(pc) {
        it.at = At {
            line: block.line,
            number: block.number,
        };
        executed += 1;
        if executed > MAX_EXECUTED_BLOCKS {
            let msg = format!("more than {MAX_EXECUTED_BLOCKS} blocks executed: endless loop?");
            return Err(it.error(msg));
        }
        pc = match flow::control(block)? {
            Some(item) => it.flow(item, pc, blocks, &jumps),
            None => match it.block(block) {
                Ok(true) => break,
                Ok(false) => Ok(pc + 1),
                Err(e) => Err(e),
            },
        }
        .map_err(|e| it.error(e))?;
    }
    it.request(&Request::Exec(None)).map_err(|e| it.error(e))?;
    Ok(())
}

impl<'c> Interpreter<'c> {
    fn new(ctl: &'c mut dyn Controller, report: &'c mut Report) -> Self {
        Interpreter {
            ctl,
            report,
            at: At::default(),
            pos: [0.0; tc_request::AXES],
            motion: None,
            incremental: false,
            feed_pending: None,
            plane: None,
            transition: None,
            tool: None,
            trc: None,
            r: HashMap::new(),
            p: HashMap::new(),
            v: HashMap::new(),
            dtable: DTable::default(),
            for_state: HashMap::new(),
            otc_seen: 0,
        }
    }

    /// An error at the current block.
    fn error(&self, message: String) -> NcError {
        NcError {
            line: self.at.line,
            block_number: self.at.number,
            column: 1,
            message,
        }
    }

    /// Sends `req`; an access or protocol error answer is an error.
    fn request(&mut self, req: &Request) -> Result<Reply, String> {
        match self.ctl.call(req, self.at) {
            Reply::Access(uoi::AccessError::State) => Err(format!(
                "`{req}`: the controller answered State: correction group 1 is faulted{}",
                self.fault_bits()
            )),
            Reply::Access(e) => Err(format!("`{req}`: the controller answered {}", e.name())),
            Reply::Protocol(e) => Err(format!("`{req}`: refused: {e}")),
            reply => Ok(reply),
        }
    }

    /// Carries out a control statement at `pc`; the next block's index.
    fn flow(
        &mut self,
        item: &Item,
        pc: usize,
        blocks: &[Block],
        jumps: &flow::Jumps,
    ) -> Result<usize, String> {
        let partner = |map: &HashMap<usize, usize>| {
            map.get(&pc)
                .copied()
                .ok_or_else(|| "control statement without its partner".to_string())
        };
        match item {
            Item::For {
                var,
                start,
                end,
                step,
            } => {
                let first = eval::eval(start, self)?;
                let last = eval::eval(end, self)?;
                let step = eval::eval(step, self)?;
                if step == 0.0 {
                    return Err("$FOR with step 0 never ends".into());
                }
                self.assign(var, first)?;
                self.for_state.insert(pc, (last, step));
                Ok(if in_range(first, last, step) {
                    pc + 1
                } else {
                    partner(&jumps.for_pair)? + 1
                })
            }
            Item::EndFor => self.end_for(pc, partner(&jumps.for_pair)?, blocks),
            Item::While(c) => Ok(if eval::eval(c, self)? != 0.0 {
                pc + 1
            } else {
                partner(&jumps.while_pair)? + 1
            }),
            Item::EndWhile => partner(&jumps.while_pair),
            Item::If(c) => Ok(if eval::eval(c, self)? != 0.0 {
                pc + 1
            } else {
                partner(&jumps.if_next)? + 1
            }),
            Item::Else => Ok(partner(&jumps.if_next)? + 1),
            _ => Ok(pc + 1),
        }
    }

    /// ` (ERROR: CalcError ..)`: the group's error bits, for a message.
    fn fault_bits(&mut self) -> String {
        let read = Request::Read(objects::ERROR, uoi::ValueType::I32);
        let Reply::Value(uoi::Value::I32(bits)) = self.ctl.call(&read, self.at) else {
            return String::new();
        };
        let names: Vec<&str> = objects::ERROR_BITS
            .iter()
            .filter(|(bit, _)| bits & bit != 0)
            .map(|(_, name)| *name)
            .collect();
        format!(" (ERROR: {})", names.join(", "))
    }

    /// `$ENDFOR` at `pc` of the `$FOR` at `f`: the counter stepped, and
    /// back to the loop's first block while it is in range.
    fn end_for(&mut self, pc: usize, f: usize, blocks: &[Block]) -> Result<usize, String> {
        let for_item = blocks.get(f).and_then(|b| b.items.first());
        let (Some(Item::For { var, .. }), Some(&(last, step))) = (for_item, self.for_state.get(&f))
        else {
            return Err("$ENDFOR without its $FOR".into());
        };
        let next = self.read_var(var)? + step;
        self.assign(var, next)?;
        Ok(if in_range(next, last, step) {
            f + 1
        } else {
            pc + 1
        })
    }

    fn read_var(&mut self, var: &Var) -> Result<f64, String> {
        eval::Vars::read(self, var)
    }
}

/// Whether a `$FOR` counter at `v` still runs towards `end` by `step`.
fn in_range(v: f64, end: f64, step: f64) -> bool {
    // A tolerance of a millionth of the step, so that decimal steps reach
    // their end.
    let slack = step.abs() * 1e-6;
    if step > 0.0 {
        v <= end + slack
    } else {
        v >= end - slack
    }
}
