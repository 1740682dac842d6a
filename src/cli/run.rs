//! `addipos run PROG.nc`: run an NC program on a fresh emulator, print
//! what it spooled, the final position and the wear; `--trace` writes the
//! equivalent conformance trace.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use addipos::nc_run::{axis_text, run_nc_with_tools, NcRun};
use tool_store::{ToolKey, ToolValue};

use super::{EXIT_FAILED, EXIT_TROUBLE};

/// Arguments of `addipos run`.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The NC program (ISG / DIN 66025 subset).
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
fn tool_values(args: &RunArgs) -> Result<Vec<(u8, ToolKey, ToolValue)>, String> {
    read_tool_values(args.tools.as_deref(), args.group)
}

/// The values of a tool file (none without one) for `group`, checked like
/// a tool file.
pub fn read_tool_values(
    path: Option<&std::path::Path>,
    group: u8,
) -> Result<Vec<(u8, ToolKey, ToolValue)>, String> {
    let Some(path) = path else {
        return Ok(Vec::new());
    };
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    let table = tool_store::parse_group_file(&name, &text).map_err(|e| e.to_string())?;
    Ok(table.iter().map(|(k, v)| (group, k, v)).collect())
}

/// Runs `addipos run`.
pub fn cmd_run(args: &RunArgs) -> ExitCode {
    let name = args.program.display().to_string();
    let text = match std::fs::read_to_string(&args.program) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {name}: cannot read: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let tools = match tool_values(args) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(EXIT_TROUBLE);
        }
    };
    let run = run_nc_with_tools(&text, &tools);
    print_run(&run);
    report_problems(&run, &name);
    if let Some(out) = args.trace.as_ref().filter(|_| run.parse_errors.is_empty()) {
        if let Err(e) = std::fs::write(out, run.trace(&name)) {
            eprintln!("error: {}: cannot write: {e}", out.display());
            return ExitCode::from(EXIT_TROUBLE);
        }
    }
    if run.failed() {
        ExitCode::from(EXIT_FAILED)
    } else {
        ExitCode::SUCCESS
    }
}

fn print_run(run: &NcRun) {
    for line in run.spool_lines() {
        println!("{line}");
    }
    if let Some(p) = &run.position {
        println!("POS {}", axis_text(p));
    }
    for (name, v) in &run.wear {
        println!("{name} = {v}");
    }
}

fn report_problems(run: &NcRun, name: &str) {
    for w in &run.report.warnings {
        eprintln!("warning: {name}: {w}");
    }
    let errors = run
        .parse_errors
        .iter()
        .chain(&run.error)
        .chain(&run.report.faults);
    for e in errors {
        eprintln!("error: {name}: {e}");
    }
}
