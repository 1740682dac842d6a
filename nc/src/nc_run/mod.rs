//! `addipos run`: an NC program parsed, interpreted into requests and run
//! on a fresh target (any [`Runner`]: the CLI and the plot pass an
//! emulator), every request handed on with its answer and the elements it
//! spooled, so that the run can be printed and written as an equivalent
//! conformance trace as it goes ([`run_checked_nc`], streamed: memory
//! stays flat for a program of any length), or kept whole ([`run_nc`],
//! for tests and plots). Decision 492.

use std::io::{self, BufRead};

use tc_objects::TcObject;
use tc_request::{AxisPos, Reply, Request, Runner, SpoolRecord};
use tool_store::{ToolKey, ToolValue};
use uoi::{Value, ValueType};

use crate::run::{
    run_reader, wear_axis, At, Controller, Report, RunError, WEAR_RADIUS, WEAR_RADIUS_CONT,
};
use crate::{check_program, Blocks, NcError};

mod exchange;
mod text;

pub use exchange::Exchange;
pub use text::{axis_text, trace_head, trace_lines, SpoolLabels};

/// A whole run: the exchanges, and what went wrong.
#[derive(Debug, Clone, Default)]
pub struct NcRun {
    /// Every request in order.
    pub exchanges: Vec<Exchange>,
    /// The parser's errors (nothing runs when there is one).
    pub parse_errors: Vec<NcError>,
    /// The error that stopped the run, if one did.
    pub error: Option<RunError>,
    /// Warnings and controller faults of the run.
    pub report: Report,
    /// The machine axes used as X, Y, Z (for `I J K` of arcs).
    pub axis_nr: [u8; 3],
    /// The executed position at the end.
    pub position: Option<AxisPos>,
    /// The V.G. wear values read at the end: name and value.
    pub wear: Vec<(String, f64)>,
}

/// What a run leaves besides its exchanges.
#[derive(Debug, Clone, Default)]
pub struct NcOutcome {
    /// The error that stopped the run, if one did.
    pub error: Option<RunError>,
    /// Warnings and controller faults of the run.
    pub report: Report,
    /// The machine axes used as X, Y, Z (for `I J K` of arcs).
    pub axis_nr: [u8; 3],
    /// The executed position at the end.
    pub position: Option<AxisPos>,
    /// The radius of correction group 1 at the end (mm), as the
    /// correction uses it: the tool's radius less the booked radius wear.
    pub radius: Option<f64>,
    /// The V.G. wear values read at the end: name and value.
    pub wear: Vec<(String, f64)>,
}

/// Why a streamed run stopped before its end.
#[derive(Debug, thiserror::Error)]
pub enum NcRunError<E: std::error::Error + 'static> {
    /// The sink could not write an exchange out (its message names
    /// where: the standard output, the trace file).
    #[error(transparent)]
    Output(#[from] io::Error),
    /// The target could not carry a request out (a broken connection).
    #[error("the target failed: {0}")]
    Target(#[source] E),
}

/// Where each exchange of a run goes as it happens, with the machine axes
/// used as X, Y, Z; an output error stops the writing (it is returned at
/// the end of the run).
pub type ExchangeSink<'s> = dyn FnMut(Exchange, [u8; 3]) -> io::Result<()> + 's;

/// The target, handing everything it is asked to a sink.
struct Recorder<'t, 'r, 's, T: Runner + ?Sized> {
    target: &'t mut T,
    sink: &'r mut ExchangeSink<'s>,
    failed: Option<NcRunError<T::Error>>,
}

impl<T: Runner + ?Sized> Recorder<'_, '_, '_, T> {
    /// Runs `req` on the target: its answer, what it spooled and the axes
    /// allocated as X, Y, Z.
    fn exchange(&mut self, req: &Request) -> Result<(Reply, Vec<SpoolRecord>, [u8; 3]), T::Error> {
        let reply = self.target.run(req)?;
        let spooled = self.target.take_spooled()?;
        Ok((reply, spooled, self.target.axis_nr()?))
    }
}

impl<T: Runner + ?Sized> Controller for Recorder<'_, '_, '_, T> {
    fn call(&mut self, req: &Request, at: At) -> Reply {
        if self.failed.is_some() {
            // The output or the target failed: nothing more is run, the
            // run stops here.
            return Reply::Access(uoi::AccessError::State);
        }
        let (reply, spooled, axis_nr) = match self.exchange(req) {
            Ok(x) => x,
            Err(e) => {
                self.failed = Some(NcRunError::Target(e));
                return Reply::Access(uoi::AccessError::State);
            }
        };
        let x = Exchange {
            at,
            request: req.clone(),
            reply: reply.clone(),
            spooled,
        };
        if let Err(e) = (self.sink)(x, axis_nr) {
            self.failed = Some(NcRunError::Output(e));
        }
        reply
    }
}

/// The V.G. wear variables read at the end of a run.
fn wear_objects() -> Vec<(String, uoi::ObjectAddress)> {
    let mut out = vec![
        ("V.G.WZ_AKT.WEAR_RADIUS".to_string(), WEAR_RADIUS),
        ("V.G.WZ_AKT.WEAR_RADIUS_CONT".to_string(), WEAR_RADIUS_CONT),
    ];
    out.extend((0..8).map(|a| (format!("V.G.WZ_AKT.WEAR[{a}]"), wear_axis(a))));
    out
}

/// Parses `text` and runs it on `target`, fresh (the emulator a trace
/// without header options replays on, say).
pub fn run_nc<T: Runner + ?Sized>(target: &mut T, text: &str) -> Result<NcRun, T::Error> {
    run_nc_with_tools(target, text, &[])
}

/// Writes the tool values of `tools` (group, entry and field, value) as
/// requests, so that the trace of the run holds them too; WKZINDEX of each
/// group touched is 0 again afterwards.
fn preload<T: Runner + ?Sized>(
    rec: &mut Recorder<'_, '_, '_, T>,
    tools: &[(u8, ToolKey, ToolValue)],
) {
    let at = At::default();
    let wkz = |g: u8| TcObject::WkzIndex.of(u16::from(g));
    for (group, key, value) in tools {
        rec.call(
            &Request::Write(wkz(*group), Value::I32(i32::from(key.index))),
            at,
        );
        let v = match value {
            ToolValue::I32(i) => Value::I32(*i),
            ToolValue::F64(f) => Value::F64(*f),
        };
        rec.call(&Request::Write(key.field.address(u16::from(*group)), v), at);
    }
    let mut groups: Vec<u8> = tools.iter().map(|t| t.0).collect();
    groups.dedup();
    for g in groups {
        rec.call(&Request::Write(wkz(g), Value::I32(0)), at);
    }
}

/// As [`run_nc`], with tool data written first (a tool file's values):
/// an NC program's `D` word then selects an entry that holds them.
pub fn run_nc_with_tools<T: Runner + ?Sized>(
    target: &mut T,
    text: &str,
    tools: &[(u8, ToolKey, ToolValue)],
) -> Result<NcRun, T::Error> {
    let parse_errors = check_program(text.as_bytes());
    if !parse_errors.is_empty() {
        return Ok(NcRun {
            parse_errors,
            ..NcRun::default()
        });
    }
    let mut exchanges = Vec::new();
    let mut keep = |x: Exchange, _: [u8; 3]| {
        exchanges.push(x);
        Ok(())
    };
    let outcome = match run_checked_nc(target, text.as_bytes(), tools, &mut keep) {
        Ok(o) => o,
        Err(NcRunError::Target(e)) => return Err(e),
        // Collecting into memory cannot fail.
        Err(NcRunError::Output(_)) => NcOutcome::default(),
    };
    Ok(NcRun {
        exchanges,
        parse_errors,
        error: outcome.error,
        report: outcome.report,
        axis_nr: outcome.axis_nr,
        position: outcome.position,
        wear: outcome.wear,
    })
}

/// Runs the program `reader` delivers on `target`, fresh, after the tool
/// data `tools`; every request goes to `sink` with its answer and
/// spooled elements as it happens, so memory stays flat for a program of
/// any length. The program must have been checked first
/// ([`crate::check_program`]): a block in error stops the run there.
/// Errors: the first output error of `sink`, or the target's failure.
pub fn run_checked_nc<T: Runner + ?Sized, R: BufRead>(
    target: &mut T,
    reader: R,
    tools: &[(u8, ToolKey, ToolValue)],
    sink: &mut ExchangeSink<'_>,
) -> Result<NcOutcome, NcRunError<T::Error>> {
    let mut rec = Recorder {
        target,
        sink,
        failed: None,
    };
    preload(&mut rec, tools);
    let mut report = Report::default();
    let mut blocks = Blocks::new(reader);
    let error = run_reader(&mut blocks, &mut rec, &mut report).err();
    if let Some(e) = &error {
        // Run what was spooled before the error, so that the position and
        // the wear show where the machine stopped.
        let at = e.location.map_or(At::default(), |at| At {
            line: at.line,
            number: at.block_number,
        });
        rec.call(&Request::Exec(None), at);
    }
    let end = At {
        line: blocks.line(),
        number: None,
    };
    let (position, wear, radius) = read_end(&mut rec, end);
    if let Some(e) = rec.failed {
        return Err(e);
    }
    Ok(NcOutcome {
        axis_nr: rec.target.axis_nr().map_err(NcRunError::Target)?,
        error,
        report,
        position,
        wear,
        radius,
    })
}

/// What a run ends with: the executed position, the V.G. wear values and
/// the radius of group 1, read (and handed on) at `end`.
fn read_end<T: Runner + ?Sized>(
    rec: &mut Recorder<'_, '_, '_, T>,
    end: At,
) -> (Option<AxisPos>, Vec<(String, f64)>, Option<f64>) {
    let position = match rec.call(&Request::Pos, end) {
        Reply::Pos(p) => Some(p),
        _ => None,
    };
    let mut wear = Vec::new();
    for (name, addr) in wear_objects() {
        if let Reply::Value(Value::F64(v)) = rec.call(&Request::Read(addr, ValueType::F64), end) {
            wear.push((name, v));
        }
    }
    let radius = match rec.call(&Request::Read(RADIUS, ValueType::F64), end) {
        Reply::Value(Value::F64(r)) => Some(r),
        _ => None,
    };
    (position, wear, radius)
}

/// The radius of correction group 1 (mm).
const RADIUS: uoi::ObjectAddress = TcObject::Radius.of(1);

impl NcOutcome {
    /// The booked radius wear beyond the tool's radius, if there is: the
    /// wear variable's name, the wear and the tool's radius (mm; the
    /// radius in use plus the wear). A disc cannot lose more radius than it
    /// has; the controller books it all the same (decision 316), `run`
    /// warns.
    pub fn wear_beyond_radius(&self) -> Option<(&str, f64, f64)> {
        let in_use = self.radius?;
        let (name, wear) = self
            .wear
            .iter()
            .find(|(name, _)| name == "V.G.WZ_AKT.WEAR_RADIUS")?;
        (in_use < 0.0 && *wear > 0.0).then_some((name.as_str(), *wear, in_use + wear))
    }
}

impl NcRun {
    /// Whether the run failed: a parse error, an error that stopped it or
    /// a controller fault.
    pub fn failed(&self) -> bool {
        !self.parse_errors.is_empty() || self.error.is_some() || !self.report.faults.is_empty()
    }

    /// Every spooled element in trace `<` syntax, with its block.
    pub fn spool_lines(&self) -> Vec<String> {
        let mut labels = SpoolLabels::default();
        self.exchanges
            .iter()
            .flat_map(|x| labels.lines(x, self.axis_nr))
            .collect()
    }

    /// The run as a conformance trace named `name`: every request with its
    /// answer as the expectation and the elements it spooled.
    pub fn trace(&self, name: &str) -> String {
        let mut t = trace_head(name);
        for x in &self.exchanges {
            t.push_str(&trace_lines(x, self.axis_nr));
        }
        t
    }
}
