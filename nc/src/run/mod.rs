//! The interpreter: runs a parsed program block by block and turns it into
//! the requests of `tc-request` (object writes, motion commands, `EXEC`),
//! which a [`Controller`] carries out. It keeps the modal state (motion
//! kind, G90/G91 and the absolute position, feed, plane, tool, TRC side),
//! the parameters and variables and the D table, the selection mode and
//! the feed adaptation. The correction is the controller's; the selection
//! modes only add elements around it (`selection.rs`, `inside_corner.rs`).
//!
//! The program is pulled block by block; only the blocks of the outermost
//! open `$FOR`/`$WHILE` are held so that the loop can jump back, `$IF` and
//! `$ELSE` skip forward. At most [`MAX_EXECUTED_BLOCKS`] blocks are
//! executed.

mod block;
mod dtable;
mod error;
mod eval;
mod feed;
mod flow;
mod inside_corner;
mod objects;
mod otc;
mod plane;
mod selection;
mod structure;
mod trc_state;
mod vars;
mod window;

use std::collections::HashMap;
use std::io::BufRead;

use tc_request::{AxisPos, Reply, Request};

use crate::error::{Location, NcError};
use crate::model::Block;
use crate::stream::Blocks;

pub use dtable::DTable;
pub use error::{Located, RunError, RunErrorKind, Warning, WarningKind};
pub use objects::{wear_axis, WEAR_RADIUS, WEAR_RADIUS_CONT};
pub use trc_state::MAX_CONTOUR_BLOCKS;
use trc_state::{FeedAdaption, Selection, Side};

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
    pub warnings: Vec<Warning>,
    /// Errors the controller signalled while the program ran on (OTC error
    /// bits with their ISG ids, [`RunErrorKind::Otc`]), with the block that
    /// caused them.
    pub faults: Vec<RunError>,
    /// Most blocks held at once for jumping back (the body of the
    /// outermost open loop; 1 for a program without loops).
    pub peak_held_blocks: usize,
    /// Warnings beyond the first [`crate::MAX_KEPT_ERRORS`], only counted.
    pub more_warnings: u64,
    /// Faults beyond the first [`crate::MAX_KEPT_ERRORS`], only counted.
    pub more_faults: u64,
}

impl Report {
    /// Keeps warning `w`, or only counts it once [`crate::MAX_KEPT_ERRORS`]
    /// are kept.
    pub fn warn(&mut self, w: Warning) {
        keep_or_count(&mut self.warnings, &mut self.more_warnings, w);
    }

    /// Keeps fault `f`, or only counts it once [`crate::MAX_KEPT_ERRORS`]
    /// are kept.
    pub fn fault(&mut self, f: RunError) {
        keep_or_count(&mut self.faults, &mut self.more_faults, f);
    }
}

fn keep_or_count<T>(kept: &mut Vec<T>, more: &mut u64, e: T) {
    if kept.len() < crate::MAX_KEPT_ERRORS {
        kept.push(e);
    } else {
        *more += 1;
    }
}

/// Motion kind of G0/G1/G2/G3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MotionKind {
    Rapid,
    Linear,
    Cw,
    Ccw,
}

/// The interpreter's state between blocks.
struct Interpreter<'c> {
    report: &'c mut Report,
    ctl: &'c mut dyn Controller,
    at: At,
    /// Whether a block is being carried out (`at` names it): errors before
    /// the first block have no location.
    in_block: bool,
    /// Column of the word being carried out, for its errors.
    col: usize,
    /// The place errors name instead, while a read `G238` contour runs
    /// (each of its blocks in turn).
    pinned: Option<Location>,
    /// Selection and deselection of the correction.
    sel: Selection,
    /// Feed adaptation (`G10`/`G11`, `#TANGFEED`).
    feed: FeedAdaption,
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
    loops: Vec<structure::Loop>,
    otc_seen: i32,
}

/// Runs `blocks` (a whole parsed program without errors) on `ctl`; see
/// [`run_blocks`].
pub fn run_program(
    blocks: &[Block],
    ctl: &mut dyn Controller,
    report: &mut Report,
) -> Result<(), RunError> {
    run_blocks(blocks.iter().cloned().map(Ok), ctl, report)
}

/// Runs the blocks `blocks` yields, pulled one at a time, on `ctl`; see
/// [`run_reader`], which does the same without an allocation per block.
pub fn run_blocks<I>(
    blocks: I,
    ctl: &mut dyn Controller,
    report: &mut Report,
) -> Result<(), RunError>
where
    I: Iterator<Item = Result<Block, NcError>>,
{
    run_source(window::FromIter(blocks), ctl, report)
}

/// Runs the program `blocks` reads (checked before, e.g. by
/// [`crate::check_program`]: a block in error stops the run there), pulled
/// block by block, on `ctl`, ending with `EXEC` (run until the spooler is
/// empty). Only the blocks of the outermost open `$FOR`/`$WHILE` are held,
/// for jumping back; [`Blocks::line`] tells afterwards how far it read.
///
/// Warnings and controller faults go to `report`, also when the run stops.
/// Stops at the first error: a construct not implemented, an unset
/// variable, a request the controller refuses, a block in error.
pub fn run_reader<R: BufRead>(
    blocks: &mut Blocks<R>,
    ctl: &mut dyn Controller,
    report: &mut Report,
) -> Result<(), RunError> {
    run_source(blocks, ctl, report)
}

fn run_source<S: window::BlockSource>(
    source: S,
    ctl: &mut dyn Controller,
    report: &mut Report,
) -> Result<(), RunError> {
    let mut window = window::Window::new(source);
    let mut it = Interpreter::new(ctl, report);
    let result = run_window(&mut it, &mut window);
    it.report.peak_held_blocks = it.report.peak_held_blocks.max(window.peak());
    result
}

/// The run loop: block after block from the window, jumps and skips.
fn run_window<S: window::BlockSource>(
    it: &mut Interpreter<'_>,
    window: &mut window::Window<S>,
) -> Result<(), RunError> {
    if let Some(b) = window.get(0)? {
        it.enter(b);
    }
    it.pos = match it.ctl.call(&Request::Pos, it.at) {
        Reply::Pos(p) => p,
        other => return Err(it.error(unexpected(Request::Pos, other))),
    };
    let mut pc = 0;
    let mut executed = 0u64;
    while let Some(block) = window.get(pc).map_err(|e| it.located(e))? {
        it.enter(block);
        executed += 1;
        if executed > MAX_EXECUTED_BLOCKS {
            let limit = MAX_EXECUTED_BLOCKS;
            return Err(it.error(RunErrorKind::TooManyBlocks { limit }));
        }
        let next = match structure::control(block)? {
            Some(item) => it.flow(item, pc),
            None => match it.block(block) {
                Ok(true) => break,
                Ok(false) => Ok(structure::Next::On),
                Err(e) => Err(e),
            },
        }
        .map_err(|e| it.error(e))?;
        pc = match next {
            structure::Next::On => pc + 1,
            structure::Next::Back(to) => to,
            structure::Next::Skip(to) => window
                .skip(pc, to, it.in_loop())
                .map_err(|e| it.located(e))?,
        };
        if !it.in_loop() {
            window.release_before(pc);
        }
    }
    it.end_of_program().map_err(|e| it.error(e))?;
    it.send(&Request::Exec(None)).map_err(|e| it.error(e))?;
    Ok(())
}

impl Interpreter<'_> {
    /// The program's end (`M30` or its last block): a `G238` contour
    /// without its `G40` is an error; a fault of the correction not yet
    /// answered stops the run.
    fn end_of_program(&mut self) -> Result<(), RunErrorKind> {
        if self.contour_open() {
            return Err(RunErrorKind::InsideCorner("the contour has no G40"));
        }
        self.flush_contour()?;
        self.check_fault()
    }
}

/// An answer of the wrong kind to `request`.
fn unexpected(request: Request, reply: Reply) -> RunErrorKind {
    RunErrorKind::UnexpectedReply {
        request: Box::new(request),
        reply: Box::new(reply),
    }
}

impl<'c> Interpreter<'c> {
    fn new(ctl: &'c mut dyn Controller, report: &'c mut Report) -> Self {
        Interpreter {
            ctl,
            report,
            at: At::default(),
            in_block: false,
            col: 1,
            pinned: None,
            sel: Selection::default(),
            feed: FeedAdaption::default(),
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
            loops: Vec::new(),
            otc_seen: 0,
        }
    }

    /// Block `block` is carried out from now on (its first word).
    fn enter(&mut self, block: &Block) {
        self.at = At {
            line: block.line,
            number: block.number,
        };
        self.in_block = true;
        self.col = block.column(0);
        self.pinned = None;
    }

    /// The current block and word, once a block is carried out.
    fn location(&self) -> Option<Location> {
        if self.pinned.is_some() {
            return self.pinned;
        }
        self.in_block.then_some(Location {
            line: self.at.line,
            block_number: self.at.number,
            column: self.col,
        })
    }

    /// An error at the current block and word.
    fn error(&self, kind: RunErrorKind) -> RunError {
        let location = match kind {
            RunErrorKind::CorrectionFault { .. } => self.sel.fault_at.or(self.location()),
            _ => self.location(),
        };
        RunError { location, kind }
    }

    /// Warning `kind` at the current block and word, for the report.
    fn warn(&mut self, kind: WarningKind) {
        let w = Warning {
            location: self.location(),
            kind,
        };
        self.report.warn(w);
    }

    /// An error of the window placed at the current block when it has no
    /// place of its own.
    fn located(&self, e: RunError) -> RunError {
        match e.location {
            Some(_) => e,
            None => self.error(e.kind),
        }
    }

    /// Sends `req` and answers its reply; an access or protocol error
    /// answer is an error. A full spooler (`Full`, nothing changed) is
    /// worked off first, as a controller's interpreter waits for its
    /// interpolator: `EXEC`, then the request once more.
    fn request(&mut self, req: &Request) -> Result<Reply, RunErrorKind> {
        let reply = self.ctl.call(req, self.at);
        let reply = self.after_full(req, reply)?;
        match self.refused(req, &reply) {
            Some(e) => Err(e),
            None => Ok(reply),
        }
    }

    /// As [`Self::request`], for a request whose answer is only `ok` or
    /// an error (writes, motions, `EXEC`).
    fn send(&mut self, req: &Request) -> Result<(), RunErrorKind> {
        if self.held(req)? {
            return Ok(());
        }
        let reply = self.ctl.call(req, self.at);
        if matches!(reply, Reply::Ok) {
            return Ok(());
        }
        let reply = self.after_full(req, reply)?;
        self.refused(req, &reply).map_or(Ok(()), Err)
    }

    /// `reply` to `req`, or when it was `Full` (the spooler full, nothing
    /// changed) the answer to `req` sent once more after `EXEC`.
    fn after_full(&mut self, req: &Request, reply: Reply) -> Result<Reply, RunErrorKind> {
        if matches!(reply, Reply::Access(uoi::AccessError::Full))
            && !matches!(req, Request::Exec(_))
        {
            self.send(&Request::Exec(None))?;
            return Ok(self.ctl.call(req, self.at));
        }
        Ok(reply)
    }

    /// Why `reply` refuses `req`, if it does.
    fn refused(&mut self, req: &Request, reply: &Reply) -> Option<RunErrorKind> {
        let request = || Box::new(req.clone());
        Some(match reply {
            Reply::Access(uoi::AccessError::State) if self.sel.fault_at.is_some() => {
                RunErrorKind::CorrectionFault {
                    bits: self.fault_bits().unwrap_or_default(),
                }
            }
            Reply::Access(uoi::AccessError::State) => RunErrorKind::Faulted {
                request: request(),
                error_bits: self.fault_bits(),
            },
            Reply::Access(e) => RunErrorKind::Refused {
                request: request(),
                error: *e,
            },
            Reply::Protocol(e) => RunErrorKind::Rejected {
                request: request(),
                error: *e,
            },
            _ => return None,
        })
    }

    /// The names of the group's error bits set, if they can be read.
    fn fault_bits(&mut self) -> Option<Vec<String>> {
        let read = Request::Read(objects::ERROR, uoi::ValueType::I32);
        let Reply::Value(uoi::Value::I32(bits)) = self.ctl.call(&read, self.at) else {
            return None;
        };
        Some(objects::error_bit_names(bits))
    }
}
