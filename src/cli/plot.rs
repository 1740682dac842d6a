//! `addipos plot FILE -o OUT.svg`: an NC program or a trace drawn as SVG
//! (programmed contour, corrected tool-centre path, executed path).

use std::path::PathBuf;

use clap::Args;

use plot::{collect_paths, nc_steps, render, trace_steps, Paths};
use trace::nc_run::run_nc_with_tools;
use trace::{load_trace, Header};

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

/// The paths of an NC program, and whether its run failed.
fn nc_paths(args: &PlotArgs, name: &str) -> Result<(Paths, bool), String> {
    let text =
        std::fs::read_to_string(&args.file).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let tools = read_tool_values(args.tools.as_deref(), args.group)?;
    let run = run_nc_with_tools(&text, &tools);
    if let Some(e) = run.parse_errors.first() {
        return Err(format!("{name}: {e}"));
    }
    for e in run.error.iter().chain(&run.report.faults) {
        eprintln!("error: {name}: {e}");
    }
    let header = Header::new(name);
    Ok((collect_paths(&header, &nc_steps(&run)), run.failed()))
}

/// Runs `addipos plot`.
pub fn cmd_plot(args: &PlotArgs) -> Outcome {
    let name = args.file.display().to_string();
    let is_trace = args.file.extension().is_some_and(|e| e == "trace");
    let paths = if is_trace {
        load_trace(&args.file).map(|t| (collect_paths(&t.header, &trace_steps(&t)), false))
    } else {
        nc_paths(args, &name)
    };
    let (paths, failed) = paths.map_err(Failure::trouble)?;
    let svg = render(&paths, &name);
    std::fs::write(&args.output, svg)
        .map_err(|e| Failure::trouble(format!("{}: cannot write: {e}", args.output.display())))?;
    if failed {
        Err(Failure::reported())
    } else {
        Ok(())
    }
}
