//! `addipos plot FILE -o OUT.svg`: an NC program or a trace drawn as SVG
//! (programmed contour, corrected tool-centre path, executed path).

use std::path::PathBuf;

use clap::Args;

use nc::nc_run::run_nc_with_tools;
use plot::{
    collect_paths_with, nc_steps, render, trace_steps, Paths, PlotStep, MAX_STEPPED_CYCLES,
};
use trace::{fresh_emulator, load_trace, Header};

use super::progress::count_bar;
use super::run::read_tool_values;
use super::{Failure, Outcome};

/// Arguments of `addipos plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// An NC program (*.nc) or a conformance trace (*.trace).
    pub file: PathBuf,
    /// Where the SVG picture goes.
    #[arg(short, long, value_name = "OUT.svg")]
    pub output: PathBuf,
    /// Tool data written before an NC program runs (as for `addipos run`).
    #[arg(long, value_name = "FILE")]
    pub tools: Option<PathBuf>,
    /// The compensation group the tool file is for.
    #[arg(long, value_name = "G", default_value_t = 1,
          value_parser = clap::value_parser!(u8).range(1..=32))]
    pub group: u8,
}

/// The paths of an NC program, and whether its run failed; a program
/// that does not parse is a failure (exit 1, as from `run`), one that
/// cannot be read is trouble (exit 2).
fn nc_paths(args: &PlotArgs, name: &str) -> Result<(Paths, bool), Failure> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| Failure::trouble(format!("{name}: cannot read: {e}")))?;
    let tools = read_tool_values(args.tools.as_deref(), args.group).map_err(Failure::trouble)?;
    // The emulator a trace without header options replays on.
    let Ok(run) = run_nc_with_tools(&mut fresh_emulator(&Header::new("nc")), &text, &tools);
    if let Some(e) = run.parse_errors.first() {
        return Err(Failure::failed(format!("{name}: {e}")));
    }
    for e in run.error.iter().chain(&run.report.faults) {
        eprintln!("error: {name}: {e}");
    }
    let header = Header::new(name);
    Ok((paths_shown(&header, &nc_steps(&run)), run.failed()))
}

/// The paths of the steps, with a progress bar on a terminal.
fn paths_shown(header: &Header, steps: &[PlotStep]) -> Paths {
    let bar = count_bar(steps.len() as u64, "requests");
    let paths = collect_paths_with(header, steps, &mut |k| bar.set_position(k as u64));
    bar.finish_and_clear();
    paths
}

/// Runs `addipos plot`.
pub fn cmd_plot(args: &PlotArgs) -> Outcome {
    let name = args.file.display().to_string();
    let is_trace = args.file.extension().is_some_and(|e| e == "trace");
    let (paths, failed) = if is_trace {
        // A trace that cannot be read is trouble; one that does not parse
        // fails (exit 1), as from `replay`.
        std::fs::File::open(&args.file)
            .map_err(|e| Failure::trouble(format!("{name}: cannot read: {e}")))?;
        let t = load_trace(&args.file).map_err(|e| Failure::failed(e.to_string()))?;
        (paths_shown(&t.header, &trace_steps(&t)), false)
    } else {
        nc_paths(args, &name)?
    };
    if paths.truncated {
        eprintln!(
            "note: {name}: only the first {MAX_STEPPED_CYCLES} cycles are drawn one by one; \
             the executed path shows only where each later EXEC ended"
        );
    }
    let svg = render(&paths, &name);
    std::fs::write(&args.output, svg)
        .map_err(|e| Failure::trouble(format!("{}: cannot write: {e}", args.output.display())))?;
    if failed {
        Err(Failure::reported())
    } else {
        Ok(())
    }
}
