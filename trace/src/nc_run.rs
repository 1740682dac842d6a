//! `addipos run`: an NC program parsed, interpreted into requests and run
//! on a fresh emulator, every request handed on with its answer and the
//! elements it spooled, so that the run can be printed and written as an
//! equivalent conformance trace as it goes ([`run_checked_nc`], streamed:
//! memory stays flat for a program of any length), or kept whole
//! ([`run_nc`], for tests and plots).

use std::fmt::Write as _;
use std::io::{self, BufRead};

use nc::run::{
    run_reader, wear_axis, At, Controller, Report, RunError, WEAR_RADIUS, WEAR_RADIUS_CONT,
};
use nc::{check_program, Blocks, NcError};
use tc_objects::TcObject;
use tc_request::{AxisPos, Origin, Reply, Request, SpoolRecord, AXIS_NAMES};
use tool_store::{ToolKey, ToolValue};

use uoi::{Value, ValueType};

use crate::replay::{format_record_fed, fresh_emulator};
use emulator::Emulator;

/// One request of the run, its answer and what it spooled.
#[derive(Debug, Clone)]
pub struct Exchange {
    /// The block it came from.
    pub at: At,
    /// The request.
    pub request: Request,
    /// The answer.
    pub reply: Reply,
    /// Elements it spooled.
    pub spooled: Vec<SpoolRecord>,
}

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

/// Where each exchange of a run goes as it happens, with the machine axes
/// used as X, Y, Z; an output error stops the writing (it is returned at
/// the end of the run).
pub type ExchangeSink<'s> = dyn FnMut(Exchange, [u8; 3]) -> io::Result<()> + 's;

/// The emulator, handing everything it is asked to a sink.
struct Recorder<'r, 's> {
    emu: Emulator,
    sink: &'r mut ExchangeSink<'s>,
    failed: Option<io::Error>,
}

impl Controller for Recorder<'_, '_> {
    fn call(&mut self, req: &Request, at: At) -> Reply {
        if self.failed.is_some() {
            // The output failed: nothing more is run, the run stops here.
            return Reply::Access(uoi::AccessError::State);
        }
        let reply = self.emu.run(req);
        let spooled = self.emu.take_spool_log();
        {
            let x = Exchange {
                at,
                request: req.clone(),
                reply: reply.clone(),
                spooled,
            };
            if let Err(e) = (self.sink)(x, self.emu.tc().axis_nr()) {
                self.failed = Some(e);
            }
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

/// Parses `text` and runs it on a fresh emulator (the one a trace without
/// header options replays on).
pub fn run_nc(text: &str) -> NcRun {
    run_nc_with_tools(text, &[])
}

/// Writes the tool values of `tools` (group, entry and field, value) as
/// requests, so that the trace of the run holds them too; WKZINDEX of each
/// group touched is 0 again afterwards.
fn preload(rec: &mut Recorder<'_, '_>, tools: &[(u8, ToolKey, ToolValue)]) {
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
pub fn run_nc_with_tools(text: &str, tools: &[(u8, ToolKey, ToolValue)]) -> NcRun {
    let parse_errors = check_program(text.as_bytes());
    if !parse_errors.is_empty() {
        return NcRun {
            parse_errors,
            ..NcRun::default()
        };
    }
    let mut exchanges = Vec::new();
    let mut keep = |x: Exchange, _: [u8; 3]| {
        exchanges.push(x);
        Ok(())
    };
    // Collecting into memory cannot fail.
    let outcome = run_checked_nc(text.as_bytes(), tools, &mut keep).unwrap_or_default();
    NcRun {
        exchanges,
        parse_errors,
        error: outcome.error,
        report: outcome.report,
        axis_nr: outcome.axis_nr,
        position: outcome.position,
        wear: outcome.wear,
    }
}

/// Runs the program `reader` delivers on a fresh emulator (the one a trace
/// without header options replays on), after the tool data `tools`; every
/// request goes to `sink` with its answer and spooled elements as it
/// happens, so memory stays flat for a program of any length. The program
/// must have been checked first ([`nc::check_program`]): a block in error
/// stops the run there. Errors: the first output error of `sink`.
pub fn run_checked_nc<R: BufRead>(
    reader: R,
    tools: &[(u8, ToolKey, ToolValue)],
    sink: &mut ExchangeSink<'_>,
) -> io::Result<NcOutcome> {
    let mut rec = Recorder {
        emu: fresh_emulator(&default_header()),
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
    if let Some(e) = rec.failed {
        return Err(e);
    }
    Ok(NcOutcome {
        axis_nr: rec.emu.tc().axis_nr(),
        error,
        report,
        position,
        wear,
        radius,
    })
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

/// The header of a trace with no options: what `run_nc` runs on.
fn default_header() -> crate::model::Header {
    crate::model::Header::new("nc")
}

/// `=> ...`: the answer as a trace expectation.
fn expectation(reply: &Reply) -> Option<String> {
    Some(match reply {
        Reply::Ok => "ok".into(),
        Reply::Value(v) => v.to_string(),
        Reply::Pos(p) => axis_text(p),
        Reply::Queue(n) => n.to_string(),
        Reply::Access(e) => format!("err {}", e.name()),
        Reply::Spool(..) | Reply::Protocol(_) => return None,
    })
}

/// `X.. Y.. ..` of all axes.
pub fn axis_text(p: &AxisPos) -> String {
    let words: Vec<String> = AXIS_NAMES
        .iter()
        .zip(p)
        .map(|(n, v)| format!("{n}{v}"))
        .collect();
    words.join(" ")
}

fn block_comment(at: At) -> String {
    format!("# {}", block_name(at))
}

/// The first line of the trace of a run of program `name`.
pub fn trace_head(name: &str) -> String {
    format!("@name NC program {name}\n")
}

/// Labels each spooled element with the block it comes from. The
/// correction holds one profile until the next block shows its corner
/// (docs/trc.md, "The one-profile buffer"): the approach and corrected
/// elements spooled at a block belong to the motion block before it, a
/// transition to the corner between the two, an uncorrected element or a
/// departure to the block that spooled it (decision 315).
#[derive(Debug, Clone, Copy, Default)]
pub struct SpoolLabels {
    /// The block of the last motion request: the profile held, if any.
    last_motion: Option<At>,
}

impl SpoolLabels {
    /// The spooled elements of an exchange in trace `<` syntax, each with
    /// its block (and the block it was spooled at where that differs), one
    /// line each (without line ends). Call it for every exchange in order.
    pub fn lines(&mut self, x: &Exchange, axis_nr: [u8; 3]) -> Vec<String> {
        let held = self.last_motion;
        let out = x
            .spooled
            .iter()
            .map(|rec| {
                let el = format_record_fed(rec, axis_nr);
                format!("< {el}    # {}", label(rec.origin, held, x.at))
            })
            .collect();
        if matches!(x.request, Request::Motion(_)) {
            self.last_motion = Some(x.at);
        }
        out
    }
}

/// `N10 (line 3)`, or `line 3` for a block without a number.
fn block_name(at: At) -> String {
    match at.number {
        Some(n) => format!("N{n} (line {})", at.line),
        None => format!("line {}", at.line),
    }
}

/// Where an element of `origin`, spooled at block `now` while the profile
/// of block `held` (if any) was held, comes from.
fn label(origin: Origin, held: Option<At>, now: At) -> String {
    match (origin, held) {
        (Origin::Approach | Origin::Corrected, Some(h)) if h != now => {
            format!("{}, spooled at {}", block_name(h), block_name(now))
        }
        (Origin::Transition, Some(h)) if h != now => {
            format!("transition {} to {}", block_name(h), block_name(now))
        }
        _ => block_name(now),
    }
}

/// An exchange as trace lines (line ends included): the request with its
/// answer as the expectation, then the elements it spooled.
pub fn trace_lines(x: &Exchange, axis_nr: [u8; 3]) -> String {
    let mut t = format!("{}", x.request);
    if let Some(e) = expectation(&x.reply) {
        let _ = write!(t, " => {e}");
    }
    let _ = writeln!(t, "    {}", block_comment(x.at));
    for rec in &x.spooled {
        let _ = writeln!(t, "< {}", format_record_fed(rec, axis_nr));
    }
    t
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
