//! The `addipos` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use addipos::trace::{parse_trace, replay};

/// Emulator of the ADDIPOS TC module (UOI bus 1300) with OTC wear compensation.
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replay conformance traces (*.trace) against a fresh emulator each and
    /// report every mismatch; exits non-zero if any trace fails.
    Replay {
        /// Trace files, or folders whose *.trace files are replayed.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Print a line for every trace, not only failing ones.
        #[arg(short, long)]
        verbose: bool,
    },
}

fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let rd = std::fs::read_dir(p).map_err(|e| format!("{}: {e}", p.display()))?;
            let mut files: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.extension().is_some_and(|x| x == "trace"))
                .collect();
            files.sort();
            out.extend(files);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

fn cmd_replay(files: &[PathBuf], verbose: bool) -> ExitCode {
    let files = match expand(files) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let (mut passed, mut failed) = (0usize, 0usize);
    for f in &files {
        let name = f.display().to_string();
        let text = match std::fs::read_to_string(f) {
            Ok(t) => t,
            Err(e) => {
                println!("{name}: cannot read: {e}");
                failed += 1;
                continue;
            }
        };
        let trace = match parse_trace(&name, &text) {
            Ok(t) => t,
            Err(e) => {
                println!("{e}");
                failed += 1;
                continue;
            }
        };
        let mismatches = replay(&trace);
        if mismatches.is_empty() {
            passed += 1;
            if verbose {
                println!("{name}: ok ({} requests)", trace.steps.len());
            }
        } else {
            failed += 1;
            for m in &mismatches {
                println!("{m}");
            }
        }
    }
    println!("{passed} passed, {failed} failed");
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Replay { files, verbose } => cmd_replay(&files, verbose),
    }
}
