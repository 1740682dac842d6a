//! `addipos run PROG.nc`: run an NC program on a fresh emulator, print
//! what it spooled, the final position and the wear; `--trace` writes the
//! equivalent conformance trace. The program is read twice (a first pass
//! finds every error, and only a program without one runs) and streamed:
//! the output and the trace are written as the run goes.

use std::convert::Infallible;
use std::fs::File;
use std::io::{self, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;

use nc::check_program_counted;
use nc::nc_run::{
    axis_text, run_checked_nc, trace_head, trace_lines, Exchange, NcOutcome, NcRunError,
    SpoolLabels,
};
use nc::run::RunError;
use tool_store::{ToolKey, ToolValue};
use trace::{fresh_emulator, Header};

use super::{Failure, Outcome};

/// Why `run` (or `plot`'s NC run) could not read its input or write its
/// output.
#[derive(Debug, thiserror::Error)]
pub enum RunCmdError {
    /// The program or the tool file cannot be read.
    #[error("{name}: cannot read: {error}")]
    Unreadable {
        /// The file, as given.
        name: String,
        /// Why.
        error: io::Error,
    },
    /// A program from a pipe beyond [`MAX_PIPED_BYTES`].
    #[error(
        "{0}: a program from a pipe may hold at most 64 MiB ({MAX_PIPED_BYTES} bytes); give a \
         longer one as a regular file"
    )]
    PipeTooLong(String),
    /// Bad lines in the tool file (each said on stderr).
    #[error("{name}: {count} bad line(s) in the tool file; nothing was run")]
    BadToolLines {
        /// The tool file.
        name: String,
        /// How many.
        count: usize,
    },
    /// The trace file cannot be written.
    #[error("{path}: cannot write: {error}")]
    Unwritable {
        /// The trace file.
        path: String,
        /// Why.
        error: io::Error,
    },
    /// The standard output cannot be written.
    #[error("standard output: {0}")]
    Stdout(io::Error),
    /// The run stopped: an output of the sink failed (its message says
    /// which).
    #[error(transparent)]
    Run(#[from] NcRunError<Infallible>),
}

/// Arguments of `addipos run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The NC program (ISG / DIN 66025 subset; every word, G function and
    /// limit in docs/nc.md). A line may hold at most
    /// 1 MiB (1,048,576 bytes; a longer one is an error on its line). A
    /// program from a pipe (anything but a regular file, e.g. /dev/stdin)
    /// may hold at most 64 MiB: it is kept in memory for the check pass
    /// and the run. A regular file is read twice, never held whole, and may
    /// be of any length.
    pub program: PathBuf,
    /// Also write the run as a conformance trace (requests, their answers
    /// as expectations, the spooled elements) that `addipos replay` passes.
    #[arg(long, value_name = "OUT.trace")]
    pub trace: Option<PathBuf>,
    /// Tool data to write first: a tool file in the `wz[i].field value`
    /// style (docs/tool-files.md), e.g. a grinding disc for an OTC program
    /// (`wz[1].typ 2`). Its writes are part of the run and of the trace.
    #[arg(long, value_name = "FILE")]
    pub tools: Option<PathBuf>,
    /// The compensation group the tool file is for.
    #[arg(long, value_name = "G", default_value_t = 1,
          value_parser = clap::value_parser!(u8).range(1..=32))]
    pub group: u8,
}

/// The tool values of the `--tools` file, checked like a tool file.
fn tool_values(args: &RunArgs) -> Result<Vec<(u8, ToolKey, ToolValue)>, RunCmdError> {
    read_tool_values(args.tools.as_deref(), args.group)
}

/// The values of a tool file (none without one) for `group`, checked like
/// a tool file.
pub fn read_tool_values(
    path: Option<&std::path::Path>,
    group: u8,
) -> Result<Vec<(u8, ToolKey, ToolValue)>, RunCmdError> {
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    let name = path.display().to_string();
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(error) => return Err(RunCmdError::Unreadable { name, error }),
    };
    let (table, errors) = tool_store::parse_group_file_lenient(&name, &text);
    if !errors.is_empty() {
        // Every bad line, as `tools import` says them; nothing runs.
        errors.iter().for_each(|e| eprintln!("{e}"));
        return Err(RunCmdError::BadToolLines {
            name,
            count: errors.len(),
        });
    }
    Ok(table.iter().map(|(k, v)| (group, k, v)).collect())
}

/// Runs `addipos run`.
pub fn cmd_run(args: &RunArgs) -> Outcome {
    let name = args.program.display().to_string();
    let tools = tool_values(args).map_err(Failure::trouble)?;
    let source = Source::open(&args.program, &name).map_err(Failure::trouble)?;
    let (parse_errors, more) = source
        .reader()
        .map(check_program_counted)
        .map_err(|error| {
            Failure::trouble(RunCmdError::Unreadable {
                name: name.clone(),
                error,
            })
        })?;
    if !parse_errors.is_empty() {
        report_errors(&parse_errors, &name);
        report_more(more, "errors", &name);
        return Err(Failure::reported());
    }
    match run_streamed(args, &source, &name, &tools).map_err(Failure::trouble)? {
        outcome if failed(&outcome) => Err(Failure::reported()),
        _ => Ok(()),
    }
}

/// Most bytes of a program read from a pipe (anything but a regular
/// file), which is held in memory for both passes: 64 MiB (decision 242).
const MAX_PIPED_BYTES: u64 = 64 << 20;

/// Where the program is read from, twice (the check pass, then the run):
/// a regular file is opened again for the run, anything else (a pipe,
/// `/dev/stdin`) is read into memory once, at most [`MAX_PIPED_BYTES`].
enum Source {
    File(PathBuf),
    Memory(Vec<u8>),
}

impl Source {
    /// The program at `path` (called `name` in errors); errors: it cannot
    /// be read, or a pipe delivers more than [`MAX_PIPED_BYTES`].
    fn open(path: &Path, name: &str) -> Result<Source, RunCmdError> {
        let cannot = |error| RunCmdError::Unreadable {
            name: name.to_string(),
            error,
        };
        let file = File::open(path).map_err(cannot)?;
        if file.metadata().map_err(cannot)?.is_file() {
            return Ok(Source::File(path.to_path_buf()));
        }
        let mut text = Vec::new();
        let mut capped = io::Read::take(file, MAX_PIPED_BYTES + 1);
        io::Read::read_to_end(&mut capped, &mut text).map_err(cannot)?;
        if text.len() as u64 > MAX_PIPED_BYTES {
            return Err(RunCmdError::PipeTooLong(name.to_string()));
        }
        Ok(Source::Memory(text))
    }

    fn reader(&self) -> io::Result<Box<dyn io::BufRead + '_>> {
        Ok(match self {
            Source::File(path) => Box::new(BufReader::new(File::open(path)?)),
            Source::Memory(text) => Box::new(text.as_slice()),
        })
    }
}

/// The second pass: the program run, each exchange printed and written to
/// the trace as it happens; then the position, the wear and the problems.
fn run_streamed(
    args: &RunArgs,
    source: &Source,
    name: &str,
    tools: &[(u8, ToolKey, ToolValue)],
) -> Result<NcOutcome, RunCmdError> {
    let cannot_write = |path: &Path, error| RunCmdError::Unwritable {
        path: path.display().to_string(),
        error,
    };
    let mut trace = match &args.trace {
        Some(path) => {
            let mut w = File::create(path)
                .map(BufWriter::new)
                .map_err(|e| cannot_write(path, e))?;
            w.write_all(trace_head(name).as_bytes())
                .map_err(|e| cannot_write(path, e))?;
            Some((w, path))
        }
        None => None,
    };
    let mut out = BufWriter::new(io::stdout().lock());
    let reader = source.reader().map_err(|error| RunCmdError::Unreadable {
        name: name.to_string(),
        error,
    })?;
    let mut labels = SpoolLabels::default();
    let mut sink = |x: Exchange, axis_nr: [u8; 3]| -> io::Result<()> {
        for line in labels.lines(&x, axis_nr) {
            writeln!(out, "{line}")
                .map_err(|e| io::Error::new(e.kind(), format!("standard output: {e}")))?;
        }
        if let Some((w, path)) = &mut trace {
            let text = trace_lines(&x, axis_nr);
            w.write_all(text.as_bytes())
                .map_err(|e| io::Error::new(e.kind(), cannot_write(path, e).to_string()))?;
        }
        Ok(())
    };
    // The emulator a trace without header options replays on.
    let mut emulator = fresh_emulator(&Header::new("nc"));
    let outcome = run_checked_nc(&mut emulator, reader, tools, &mut sink)?;
    print_end(&mut out, &outcome).map_err(RunCmdError::Stdout)?;
    if let Some((mut w, path)) = trace {
        w.flush().map_err(|e| cannot_write(path, e))?;
    }
    report_problems(&outcome, name);
    Ok(outcome)
}

fn failed(outcome: &NcOutcome) -> bool {
    outcome.error.is_some() || !outcome.report.faults.is_empty()
}

fn print_end(out: &mut impl Write, outcome: &NcOutcome) -> io::Result<()> {
    if let Some(p) = &outcome.position {
        writeln!(out, "POS {}", axis_text(p))?;
    }
    for (name, v) in &outcome.wear {
        writeln!(out, "{name} = {}", to_register(*v))?;
    }
    out.flush()
}

/// Steps of the wear registers per millimetre: they count in 0.1 µm.
const REGISTER_STEPS_PER_MM: f64 = 10_000.0;

/// A value in mm rounded to the registers' resolution (0.1 µm), so that
/// `9.500000000001434` prints as `9.5`.
fn to_register(mm: f64) -> f64 {
    let v = (mm * REGISTER_STEPS_PER_MM).round() / REGISTER_STEPS_PER_MM;
    // No `-0` for a wear that rounds to nothing.
    if v == 0.0 {
        0.0
    } else {
        v
    }
}

fn report_errors<E: std::fmt::Display>(errors: &[E], name: &str) {
    for e in errors {
        eprintln!("error: {name}: {e}");
    }
}

/// Says how many problems of a kind were only counted, not kept.
fn report_more(more: u64, what: &str, name: &str) {
    if more > 0 {
        eprintln!("note: {name}: {more} more {what} not shown");
    }
}

fn report_problems(outcome: &NcOutcome, name: &str) {
    for w in &outcome.report.warnings {
        eprintln!("warning: {name}: {w}");
    }
    if let Some((var, wear, radius)) = outcome.wear_beyond_radius() {
        eprintln!(
            "warning: {name}: {var} = {} mm is more than the tool's radius {} mm: the disc \
             would be used up; the controller books it without an OtcError bit (decision 316)",
            to_register(wear),
            to_register(radius)
        );
    }
    report_more(outcome.report.more_warnings, "warnings", name);
    let errors: Vec<&RunError> = outcome.error.iter().chain(&outcome.report.faults).collect();
    report_errors(&errors, name);
    report_more(outcome.report.more_faults, "faults", name);
}
