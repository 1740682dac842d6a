//! `addipos plot FILE -o OUT.svg`: an NC program or a trace drawn as SVG
//! (programmed contour, corrected tool-centre path, executed path).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use addipos::nc_run::run_nc_with_tools;
use addipos::path_plot::{collect_paths, nc_steps, render, trace_steps, Paths};
use addipos::trace::{load_trace, Header};

use super::run::read_tool_values;
use super::{EXIT_FAILED, EXIT_TROUBLE};

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
    let header = Header {
        file: name.to_owned(),
        name: None,
        tol: addipos::trace::DEFAULT_TOL,
        start: [0.0; tc_request::AXES],
        cycle: tc_module::CycleTime::DEFAULT,
        spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY,
    };
    Ok((collect_paths(&header, &nc_steps(&run)), run.failed()))
}

/// Runs `addipos plot`.
pub fn cmd_plot(args: &PlotArgs) -> ExitCode {
    let name = args.file.display().to_string();
    let is_trace = args.file.extension().is_some_and(|e| e == "trace");
    let paths = if is_trace {
        load_trace(&args.file).map(|t| (collect_paths(&t.header, &trace_steps(&t)), false))
    } else {
        nc_paths(args, &name)
    };
    let (paths, failed) = match paths {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let svg = render(&paths, &name);
    if let Err(e) = std::fs::write(&args.output, svg) {
        eprintln!("error: {}: cannot write: {e}", args.output.display());
        return ExitCode::from(EXIT_TROUBLE);
    }
    if failed {
        ExitCode::from(EXIT_FAILED)
    } else {
        ExitCode::SUCCESS
    }
}
