//! [`nc_program`](super::nc_program): the NC front end on any bytes,
//! parsed and, when they parse, interpreted on the real emulator.

use nc::run::{run_reader, At, Controller, Located, Report};
use nc::{Block, Blocks, Location, NcError};
use tc_module::{CycleTime, ExecLeft, AXES};
use tc_request::{Reply, Request};
use tool_store::{ToolField, ToolKey, ToolValue};
use uoi::AccessError;

use emulator::Emulator;

use crate::limits::{MAX_NC_INPUT, NC_EXEC_SLICES, NC_REQUEST_BUDGET};

/// Spooler capacity of the harness's emulator (the smallest allowed).
const SMALL_SPOOLER: usize = 8;

/// The emulator behind the interpreter, within the harness's bounds: at
/// most [`NC_REQUEST_BUDGET`] requests (then every request is refused,
/// which ends the run with an error) and [`NC_EXEC_SLICES`] stepped slices
/// of `EXEC` in all (then an `EXEC` stops where it is).
struct Bounded {
    emu: Emulator,
    requests: u64,
    slices: u32,
    last: Option<Request>,
}

impl Bounded {
    /// A fresh emulator, its spool log on, with a grinding disc in entry 1
    /// of group 1 (so that `#OTC ON` runs OTC) and radii in entries 2..4.
    fn new() -> Self {
        // The smallest spooler, so that a long program meets a full one.
        let mut emu =
            Emulator::new([0.0; AXES], CycleTime::DEFAULT).with_spool_capacity(SMALL_SPOOLER);
        emu.set_spool_log(true);
        let key = |index, field| ToolKey::new(index, field);
        let values = [
            (key(1, ToolField::ToolType), ToolValue::I32(2)),
            (key(1, ToolField::Radius), ToolValue::F64(30.0)),
            (key(1, ToolField::WearConst), ToolValue::F64(1e5)),
            (key(1, ToolField::MaxInfeed), ToolValue::F64(2e5)),
            (key(2, ToolField::Radius), ToolValue::F64(10.0)),
            (key(3, ToolField::Radius), ToolValue::F64(0.5)),
            (key(4, ToolField::Radius), ToolValue::F64(-2.0)),
        ];
        let values = values.into_iter().filter_map(|(k, v)| Some((1, k?, v)));
        emulator::tools::entries::load(emu.tc_mut(), values);
        Bounded {
            emu,
            requests: 0,
            slices: 0,
            last: None,
        }
    }

    /// `EXEC`, slice by slice while slices are left.
    fn exec(&mut self, cycles: Option<u64>) -> Reply {
        let mut left = self.emu.exec_slice(cycles);
        while let ExecLeft::Rest(rest) = left {
            if self.slices >= NC_EXEC_SLICES {
                break;
            }
            self.slices += 1;
            left = self.emu.exec_slice(rest);
        }
        Reply::Ok
    }
}

impl Controller for Bounded {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        self.requests += 1;
        if self.requests > NC_REQUEST_BUDGET {
            return Reply::Access(AccessError::State);
        }
        self.last = Some(req.clone());
        let reply = match req {
            Request::Exec(cycles) => self.exec(*cycles),
            r => self.emu.run(r),
        };
        let _ = self.emu.take_spool_log();
        reply
    }
}

/// The block number written at the start of `line` (`N` and digits that
/// fit), if any.
fn written_number(line: &[u8]) -> Option<u32> {
    let text = std::str::from_utf8(line).ok()?;
    let text = text.strip_suffix('\r').unwrap_or(text);
    let rest = text.trim_start_matches([' ', '\t']);
    let rest = rest.strip_prefix(['N', 'n'])?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    rest[..digits].parse().ok()
}

/// `e` names a line of the input, from 1, a column from 1, and the block
/// number written on that line when it has one.
fn check_error(what: &str, e: &NcError, lines: &[&[u8]]) {
    assert!(!e.message.is_empty(), "{what} without a message: {e:?}");
    check_place(what, &e.location(), e, lines);
}

/// As [`check_error`], for what a run reports: it has a place.
fn check_reported<K: std::fmt::Debug + std::fmt::Display>(
    what: &str,
    e: &Located<K>,
    lines: &[&[u8]],
) {
    assert!(
        !e.kind.to_string().is_empty(),
        "{what} without a message: {e:?}"
    );
    let Some(at) = &e.location else {
        panic!("{what} without a place: {e:?}");
    };
    check_place(what, at, e, lines);
}

fn check_place(what: &str, at: &Location, e: &dyn std::fmt::Debug, lines: &[&[u8]]) {
    assert!(
        at.line >= 1 && at.line <= lines.len(),
        "{what} names line {} of {}: {e:?}",
        at.line,
        lines.len()
    );
    assert!(at.column >= 1, "{what} without a column: {e:?}");
    let width = String::from_utf8_lossy(lines[at.line - 1]).chars().count();
    assert!(
        at.column <= width + 1,
        "{what} beyond its line's end: {e:?}"
    );
    if let Some(n) = written_number(lines[at.line - 1]) {
        assert_eq!(at.block_number, Some(n), "{what} on a line of N{n}: {e:?}");
    }
}

/// Blocks come in line order, each with the number written on its line.
fn check_blocks(blocks: &[Block], lines: &[&[u8]]) {
    let mut before = 0;
    for b in blocks {
        assert!(
            b.line > before && b.line <= lines.len(),
            "block at line {}",
            b.line
        );
        before = b.line;
        if let Some(n) = written_number(lines[b.line - 1]) {
            assert_eq!(b.number, Some(n), "block at line {}", b.line);
        }
    }
}

/// The NC parser on any bytes as a program and, when it finds no error,
/// the interpreter running the blocks on the real emulator (a grinding
/// disc in D1, radii in D2..D4). Checks that nothing panics; every parse
/// error, run error, warning and controller fault names a line of the
/// input, a column, and the block number written on that line when it has
/// one; blocks come in line order with their numbers; a run that ends
/// without an error (and within the harness's bounds) ends with `EXEC`.
/// Runs are bounded by the harness (see [`NC_REQUEST_BUDGET`]), and by
/// the interpreter's own limit of executed blocks.
pub fn nc_program(data: &[u8]) {
    let data = &data[..data.len().min(MAX_NC_INPUT)];
    let mut lines: Vec<&[u8]> = data.split(|b| *b == b'\n').collect();
    if data.ends_with(b"\n") {
        lines.pop();
    }
    let mut blocks = Vec::new();
    let mut errors = Vec::new();
    for result in Blocks::new(data) {
        match result {
            Ok(b) => blocks.push(b),
            Err(e) => errors.push(e),
        }
    }
    check_blocks(&blocks, &lines);
    for e in &errors {
        check_error("parse error", e, &lines);
    }
    if !errors.is_empty() {
        assert_eq!(nc::check_program(data), errors, "the check pass");
        return;
    }
    // The check pass finds the same errors; the run pulls the blocks
    // through a small reader buffer, so lines straddle its refills.
    let reader = |cap| std::io::BufReader::with_capacity(cap, data);
    assert!(nc::check_program(reader(64)).is_empty(), "the check pass");
    let mut ctl = Bounded::new();
    let mut report = Report::default();
    let mut source = Blocks::new(reader(1 + data.len() % 61));
    let result = run_reader(&mut source, &mut ctl, &mut report);
    for e in &report.warnings {
        check_reported("warning", e, &lines);
    }
    for e in &report.faults {
        check_reported("fault", e, &lines);
    }
    match result {
        Err(e) => check_reported("run error", &e, &lines),
        Ok(()) if ctl.requests <= NC_REQUEST_BUDGET => {
            assert_eq!(ctl.last, Some(Request::Exec(None)), "a run ends with EXEC");
        }
        Ok(()) => {}
    }
}
