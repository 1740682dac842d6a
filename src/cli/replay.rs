//! `addipos replay FILES`: conformance traces replayed against a fresh
//! emulator each, in-process or over the wire; the first mismatches of
//! each trace printed, the rest counted; optionally one part of the
//! traces (`--shard`) and a JUnit report (`--junit`).

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use indicatif::ProgressBar;

use addipos_host::{RemoteSession, SessionError};
use trace::{fresh_emulator, printable, replay_stream, trace_files, Header, Mismatch, TraceReader};

use super::junit::{write_junit, CaseResult, Suite, NO_REQUEST};
use super::progress::bytes_bar;
use super::remote_args::{connect, RemoteArgs};
use super::shard::{parse_shard, Shard};
use super::{Failure, Outcome};

/// Mismatch lines printed per trace unless `--max-reports` says otherwise:
/// enough to see a pattern, few enough that one systematic mistake in a
/// long trace does not bury the others (decision 313).
const DEFAULT_MAX_REPORTS: usize = 30;

/// Arguments of `addipos replay`.
#[derive(Args)]
pub struct ReplayArgs {
    /// Trace files, or folders whose *.trace files are replayed.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Replay over the wire against this server instead of in-process
    /// (HOST:PORT, localhost:PORT, or a bare PORT).
    #[arg(long, value_name = "ADDR")]
    pub server: Option<String>,
    /// Print a line for every trace, not only failing ones.
    #[arg(short, long)]
    pub verbose: bool,
    /// Also write the results as JUnit XML to FILE: one test case per
    /// trace, its first mismatches as the failure message.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Replay only part K of N of the traces (1 <= K <= N): the traces at
    /// positions K, K+N, K+2N ... of the list the arguments give. N jobs
    /// given the same arguments replay every trace exactly once
    /// (docs/trace-format.md, "Replays in CI").
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
    /// Mismatch lines printed per trace at most; the rest are counted
    /// (0: no limit).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_REPORTS)]
    pub max_reports: usize,
    #[command(flatten)]
    pub remote: RemoteArgs,
}

/// Why the traces to replay could not be found, or replayed.
#[derive(Debug, thiserror::Error)]
enum ReplayError {
    /// A path named that does not exist.
    #[error("{0}: no such file or folder")]
    NoSuchPath(String),
    /// A path that cannot be looked at, or a folder that cannot be
    /// listed.
    #[error("{shown}: {error}")]
    Unreadable {
        /// The path, control characters escaped.
        shown: String,
        /// Why.
        error: std::io::Error,
    },
    /// A folder without traces.
    #[error("no traces found: {0} holds no *.trace file")]
    NoTraces(String),
    /// The server could not set up a fresh emulator for a trace: the
    /// other traces cannot run either.
    #[error("{name}: the server did not set up a fresh emulator: {error}")]
    SetUp {
        /// The trace file.
        name: String,
        /// Why.
        error: SessionError,
    },
}

/// The trace files the arguments name: files as given, folders as their
/// `*.trace` files. A path that does not exist, or a folder without
/// traces, is an error.
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, ReplayError> {
    let mut out = Vec::new();
    for p in paths {
        let shown = printable(&p.display().to_string()).into_owned();
        let unreadable = |error, shown: &str| ReplayError::Unreadable {
            shown: shown.to_string(),
            error,
        };
        let meta = std::fs::metadata(p).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => ReplayError::NoSuchPath(shown.clone()),
            _ => unreadable(e, &shown),
        })?;
        if !meta.is_dir() {
            out.push(p.clone());
            continue;
        }
        let files = trace_files(p).map_err(|e| unreadable(e, &shown))?;
        if files.is_empty() {
            return Err(ReplayError::NoTraces(shown));
        }
        out.extend(files);
    }
    Ok(out)
}

/// Where the mismatches of one trace go: printed up to a cap, counted all.
struct Reports<'a> {
    case: CaseResult,
    max: usize,
    bar: &'a ProgressBar,
}

impl Reports<'_> {
    fn report(&mut self, line: String) {
        self.case.mismatches += 1;
        if self.max == 0 || self.case.shown.len() < self.max {
            let line = printable(&line).into_owned();
            self.bar.suspend(|| println!("{line}"));
            self.case.shown.push(line);
        }
    }

    /// The line saying how many mismatches were not printed, if any.
    fn finish(&self) {
        let more = self.case.mismatches - self.case.shown.len();
        if more > 0 {
            self.bar.suspend(|| {
                println!(
                    "{}: {more} more mismatches not shown (of {}; --max-reports {})",
                    self.case.file, self.case.mismatches, self.max
                )
            });
        }
    }
}

/// Replays one trace file as it is read; the server's setup failing is
/// `Err` (the server is lost, the other traces cannot run either).
fn replay_file(
    path: &Path,
    remote: Option<&mut RemoteSession>,
    max: usize,
    bar: &ProgressBar,
) -> Result<CaseResult, ReplayError> {
    // A file name's control characters are escaped wherever it is shown.
    let name = printable(&path.display().to_string()).into_owned();
    let mut out = Reports {
        case: CaseResult {
            file: name.clone(),
            ..CaseResult::default()
        },
        max,
        bar,
    };
    let opened = File::open(path)
        .map_err(|e| format!("{name}: cannot read: {e}"))
        .and_then(|f| {
            let read = BufReader::new(bar.wrap_read(f));
            TraceReader::open(&name, read).map_err(|e| e.to_string())
        });
    let mut reader = match opened {
        Ok(r) => r,
        Err(e) => {
            out.case.error = Some(e);
            return Ok(out.case);
        }
    };
    let header = reader.header().clone();
    let mut report = |m: Mismatch| out.report(m.to_string());
    let done = match remote {
        Some(r) => {
            set_up(r, &header).map_err(|error| ReplayError::SetUp {
                name: name.clone(),
                error,
            })?;
            replay_stream(&mut reader, r, &mut report)
        }
        None => replay_stream(&mut reader, &mut fresh_emulator(&header), &mut report),
    };
    match done {
        Ok(done) => out.case.steps = done.steps,
        Err(e) => out.case.error = Some(e.to_string()),
    }
    out.finish();
    Ok(out.case)
}

/// A fresh conformance session on the server for a trace of `header`.
fn set_up(session: &mut RemoteSession, header: &Header) -> Result<(), SessionError> {
    // A capacity is at most 1,000,000: it fits u64.
    let capacity = header.spool_capacity as u64;
    session.set_up(header.start, header.cycle.secs(), capacity)
}

/// Prints what a trace's replay ended with, beyond its mismatches.
fn say(case: &CaseResult, verbose: bool, bar: &ProgressBar) {
    if let Some(e) = &case.error {
        bar.suspend(|| println!("{}", printable(e)));
    } else if case.no_request() {
        bar.suspend(|| println!("{}: {NO_REQUEST}", case.file));
    } else if verbose && case.passed() {
        bar.suspend(|| println!("{}: ok ({} requests)", case.file, case.steps));
    }
}

/// `files` with each file once, at its first place (a file named twice,
/// or named and found in a folder, is one trace: decision 413).
fn each_once(files: Vec<PathBuf>) -> Vec<PathBuf> {
    let mut seen = std::collections::HashSet::new();
    files
        .into_iter()
        .filter(|f| seen.insert(std::fs::canonicalize(f).unwrap_or_else(|_| f.clone())))
        .collect()
}

/// The traces to replay: those the arguments name, or this job's part.
fn chosen_files(args: &ReplayArgs) -> Result<Vec<PathBuf>, Failure> {
    let files = each_once(expand(&args.files).map_err(Failure::trouble)?);
    Ok(match args.shard {
        None => files,
        Some(shard) => {
            let all = files.len();
            let part = shard.pick(files);
            eprintln!("shard {shard}: {} of {all} traces", part.len());
            part
        }
    })
}

/// The JUnit report's file, created before the replay so that a path
/// that cannot be written is found at once, and its suite.
struct Report {
    path: PathBuf,
    file: File,
    suite: Suite,
}

impl Report {
    fn create(path: &Path, shard: Option<Shard>) -> Result<Self, Failure> {
        let file = File::create(path)
            .map_err(|e| Failure::trouble(format!("{}: cannot write: {e}", path.display())))?;
        let name = match shard {
            Some(s) => format!("addipos replay, shard {s}"),
            None => "addipos replay".into(),
        };
        let suite = Suite {
            name,
            timestamp: chrono::Utc::now().format("%Y-%m-%dT%H:%M:%S").to_string(),
            hostname: host_name(),
        };
        Ok(Self {
            path: path.to_path_buf(),
            file,
            suite,
        })
    }

    fn write(self, cases: &[CaseResult]) -> Outcome {
        write_junit(std::io::BufWriter::new(self.file), &self.suite, cases)
            .map_err(|e| Failure::trouble(format!("{}: cannot write: {e}", self.path.display())))
    }
}

/// This machine's name, as JUnit's `hostname` (`localhost` when it
/// cannot be told).
fn host_name() -> String {
    #[cfg(unix)]
    {
        let uname = rustix::system::uname();
        let name = uname.nodename().to_string_lossy();
        if !name.is_empty() {
            return name.into_owned();
        }
    }
    "localhost".into()
}

/// Runs `addipos replay`: over the wire when `--server` is given.
pub fn cmd_replay(args: &ReplayArgs) -> Outcome {
    let files = chosen_files(args)?;
    let report = args
        .junit
        .as_deref()
        .map(|p| Report::create(p, args.shard))
        .transpose()?;
    let mut remote = args
        .server
        .as_deref()
        .map(|s| connect(s, &args.remote).map(RemoteSession::new))
        .transpose()
        .map_err(Failure::trouble)?;
    let total: u64 = files
        .iter()
        .filter_map(|f| std::fs::metadata(f).ok())
        .map(|m| m.len())
        .sum();
    let bar = bytes_bar(total);
    let mut cases = Vec::with_capacity(files.len());
    for f in &files {
        bar.set_message(printable(&f.display().to_string()).into_owned());
        let start = Instant::now();
        let mut case =
            replay_file(f, remote.as_mut(), args.max_reports, &bar).map_err(Failure::trouble)?;
        case.secs = start.elapsed().as_secs_f64();
        say(&case, args.verbose, &bar);
        cases.push(case);
    }
    bar.finish_and_clear();
    let passed = cases.iter().filter(|c| c.passed()).count();
    println!("{passed} passed, {} failed", cases.len() - passed);
    if let Some(r) = report {
        r.write(&cases)?;
    }
    if passed == cases.len() {
        Ok(())
    } else {
        Err(Failure::reported())
    }
}
