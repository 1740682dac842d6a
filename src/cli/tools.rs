//! The `addipos tools` command: show, export and import the tool data a
//! server keeps in its data directory, offline, on the files themselves
//! (format in docs/tool-files.md).

mod json;
mod snapshot;
mod table;
mod text;
mod values;

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use tool_store::{Record, Strictness, ToolStore};

use emulator::{Config, DEFAULT_CONFIG};

use super::{Failure, Outcome};
use snapshot::{SnapshotError, StoreAt};
use values::{Import, ToolSet};

/// Why a `tools` subcommand could not run.
#[derive(Debug, thiserror::Error)]
enum ToolsError {
    /// The settings file cannot be read.
    #[error("cannot read {path}: {error}")]
    Unreadable {
        /// The file.
        path: String,
        /// Why.
        error: std::io::Error,
    },
    /// The settings are bad.
    #[error("{origin}: {error}")]
    Settings {
        /// The settings file, or the built-in settings.
        origin: String,
        /// What is wrong.
        error: emulator::ConfigError,
    },
    /// The export file cannot be written.
    #[error("cannot write {path}: {error}")]
    Unwritable {
        /// The file.
        path: String,
        /// Why.
        error: std::io::Error,
    },
    /// The tool folder cannot be made.
    #[error("cannot create {path}: {error}")]
    NoFolder {
        /// The folder.
        path: String,
        /// Why.
        error: std::io::Error,
    },
    /// The tool folder is held by another (a server).
    #[error(transparent)]
    Locked(#[from] tool_store::LockError),
    /// The tool data cannot be read.
    #[error(transparent)]
    Snapshot(#[from] SnapshotError),
    /// The tool data is bad, or the import cannot be saved.
    #[error(transparent)]
    Store(#[from] StoreAt),
}

/// Exit statuses of `tools import`, for `--help`.
const TOOLS_EXIT_HELP: &str = "Exit status: 0 success; 1 the file to import is invalid \
(every bad line is listed; nothing was changed); 2 could not run (bad arguments or settings, \
a file that cannot be read or written, bad tool data in the data directory, a server holding \
the data directory).";

/// Exit statuses of `tools show` and `tools export`, which change
/// nothing, for `--help`.
const TOOLS_READ_EXIT_HELP: &str = "Exit status: 0 success; 2 could not run (bad arguments \
or settings, a file that cannot be read or written, bad tool data in the data directory).";

/// The `tools` subcommands.
#[derive(Subcommand)]
pub enum ToolsCommand {
    /// Print the tool entries that differ from their defaults.
    ///
    /// One row per entry with every field in the bus unit (radius and
    /// laenge in mm).
    #[command(after_help = TOOLS_READ_EXIT_HELP)]
    Show {
        #[command(flatten)]
        dir: DirArgs,
        /// Only this compensation group (1..=32).
        #[arg(long, value_name = "G", value_parser = clap::value_parser!(u8).range(1..=32))]
        group: Option<u8>,
        /// Print JSON for scripts: {"entries": [{"group", "entry", every
        /// field}]}, values in the bus unit.
        #[arg(long)]
        json: bool,
    },
    /// Write every group's tool values into one file.
    ///
    /// One line `g<group> wz[<index>].<field> <value>` per value that
    /// differs from its default, in the tool files' units (radius and
    /// laenge in 0.1 µm); `#` starts a comment. Values read back
    /// bit-identical with `tools import`.
    #[command(after_help = TOOLS_READ_EXIT_HELP)]
    Export {
        #[command(flatten)]
        dir: DirArgs,
        /// The file to write (replaced if it exists); standard output if
        /// none.
        file: Option<PathBuf>,
        /// Only this compensation group (1..=32).
        #[arg(long, value_name = "G", value_parser = clap::value_parser!(u8).range(1..=32))]
        group: Option<u8>,
        /// Write JSON instead (as `tools show --json`).
        #[arg(long)]
        json: bool,
    },
    /// Set tool values from a file; values it does not name keep theirs.
    ///
    /// The file is as `tools export` writes it, or a group's tool file in
    /// the manual's style (`wz[1].radius 300000`, with --group). The whole
    /// file is checked first; if any line is bad, every bad line is listed
    /// and nothing is changed. Then all values are written durably at once
    /// and the tool files rewritten. Entries and fields the file does not
    /// name keep their values (unless --replace). Refused while a server
    /// uses the data directory (stop it first).
    #[command(after_help = TOOLS_EXIT_HELP)]
    Import {
        #[command(flatten)]
        dir: DirArgs,
        /// The file to read.
        file: PathBuf,
        /// Only this compensation group (1..=32): lines without a
        /// `g<group>` prefix belong to it, lines of other groups are
        /// checked but left out.
        #[arg(long, value_name = "G", value_parser = clap::value_parser!(u8).range(1..=32))]
        group: Option<u8>,
        /// The file is JSON (as `tools export --json` writes it).
        #[arg(long)]
        json: bool,
        /// Make the file the whole tool data: every value it does not name
        /// goes back to its default (with --group: only in that group).
        /// Also recovers a data directory whose tool data cannot be read
        /// (without --group).
        #[arg(long)]
        replace: bool,
    },
}

/// Where the tool data is.
#[derive(Args)]
pub struct DirArgs {
    /// The server's data directory (its tool files are in DIR/tools)
    /// [default: data_dir of --config, or of the built-in settings].
    #[arg(long, value_name = "DIR")]
    data_dir: Option<PathBuf>,
    /// Settings file (as for `serve --config`) whose data_dir to use.
    #[arg(long, value_name = "FILE")]
    config: Option<PathBuf>,
}

impl DirArgs {
    /// The tool folder: `--data-dir`, or the settings' data_dir, + tools.
    fn tools_dir(&self) -> Result<PathBuf, ToolsError> {
        if let Some(d) = &self.data_dir {
            return Ok(tool_store::tools_dir(d));
        }
        let (source, text) = match &self.config {
            None => ("built-in settings".to_owned(), DEFAULT_CONFIG.to_owned()),
            Some(p) => (
                p.display().to_string(),
                std::fs::read_to_string(p).map_err(|error| ToolsError::Unreadable {
                    path: p.display().to_string(),
                    error,
                })?,
            ),
        };
        let cfg = Config::parse(&text).map_err(|error| ToolsError::Settings {
            origin: source,
            error,
        })?;
        Ok(tool_store::tools_dir(&cfg.data_dir))
    }
}

/// Runs a `tools` subcommand.
pub fn cmd_tools(command: ToolsCommand) -> Outcome {
    let result = match command {
        ToolsCommand::Show { dir, group, json } => {
            read_values(&dir, group).map(|values| print(&render(&values, json, true)))
        }
        ToolsCommand::Export {
            dir,
            file,
            group,
            json,
        } => read_values(&dir, group)
            .and_then(|values| export(&render(&values, json, false), file.as_deref())),
        ToolsCommand::Import {
            dir,
            file,
            group,
            json,
            replace,
        } => {
            return cmd_import(&dir, &file, group, json, replace);
        }
    };
    result.map_err(Failure::trouble)
}

/// The values that differ from their defaults (of `group` only, if
/// given), read without the lock; notes about the data on stderr.
fn read_values(dir: &DirArgs, group: Option<u8>) -> Result<Vec<ToolSet>, ToolsError> {
    let dir = dir.tools_dir()?;
    let (store, report) = snapshot::load(&dir)?;
    snapshot::report_notes(&dir, &report)
        .iter()
        .for_each(|n| eprintln!("{n}"));
    Ok(store
        .values()
        .filter(|(g, _, _)| group.is_none_or(|want| want == *g))
        .collect())
}

/// The show table, or the export text, or JSON.
fn render(values: &[ToolSet], json: bool, for_people: bool) -> String {
    match (json, for_people) {
        (true, _) => json::write(values),
        (false, true) if values.is_empty() => {
            "no tool values set: every entry is at its defaults\n".into()
        }
        (false, true) => table::write(values),
        (false, false) => text::write(values),
    }
}

fn print(text: &str) {
    print!("{text}");
}

fn export(text: &str, file: Option<&Path>) -> Result<(), ToolsError> {
    match file {
        None => {
            print(text);
            Ok(())
        }
        Some(p) => std::fs::write(p, text).map_err(|error| ToolsError::Unwritable {
            path: p.display().to_string(),
            error,
        }),
    }
}

fn cmd_import(dir: &DirArgs, file: &Path, group: Option<u8>, json: bool, replace: bool) -> Outcome {
    let name = file.display().to_string();
    let content = std::fs::read_to_string(file)
        .map_err(|e| Failure::trouble(format!("cannot read {name}: {e}")))?;
    let parsed = match json {
        true => json::parse(&name, &content, group),
        false => text::parse(&name, &content, group),
    };
    let import = parsed.map_err(|errors| {
        errors.iter().for_each(|e| eprintln!("{e}"));
        Failure::failed(format!(
            "{name}: {} bad line(s); nothing was changed",
            errors.len()
        ))
    })?;
    let summary = dir
        .tools_dir()
        .and_then(|d| apply(&d, &import, group, replace))
        .map_err(Failure::trouble)?;
    println!("{summary}");
    Ok(())
}

/// Writes the checked values into the tool folder `dir` under its lock:
/// one durable journal batch, then compaction into the tool files.
fn apply(
    dir: &Path,
    import: &Import,
    group: Option<u8>,
    replace: bool,
) -> Result<String, ToolsError> {
    std::fs::create_dir_all(dir).map_err(|error| ToolsError::NoFolder {
        path: dir.display().to_string(),
        error,
    })?;
    let _lock = tool_store::lock_exclusive(dir)?;
    // Replacing everything need not read the old data: bad lines in it
    // are skipped (and listed) instead of refusing.
    let strictness = match (replace, group) {
        (true, None) => Strictness::Lenient,
        _ => Strictness::Strict,
    };
    let (mut store, report) =
        ToolStore::open_dir(dir, strictness).map_err(|e| snapshot::store_error(dir, e))?;
    snapshot::report_notes(dir, &report)
        .iter()
        .for_each(|n| eprintln!("{n}"));
    let reset = match (replace, group) {
        (false, _) => None,
        (true, Some(group)) => Some(Record::ResetGroup { group }),
        (true, None) => Some(Record::Clean),
    };
    let sets = import
        .values
        .iter()
        .map(|&(group, key, value)| Record::Set { group, key, value });
    let records: Vec<Record> = reset.into_iter().chain(sets).collect();
    store
        .append(&records)
        .map_err(|e| snapshot::store_error(dir, e))?;
    if let Err(e) = store.compact() {
        eprintln!(
            "warning: the values are saved in the journal but the tool files were not rewritten: {}",
            snapshot::store_error(dir, e)
        );
    }
    Ok(summary(dir, import, replace))
}

/// What an import did, in one line.
fn summary(dir: &Path, import: &Import, replace: bool) -> String {
    let mut s = format!(
        "imported {} tool value(s) into {}",
        import.values.len(),
        dir.display()
    );
    s.push_str(if replace {
        "; every other value is back at its default"
    } else {
        "; values not in the file kept theirs"
    });
    if import.other_groups > 0 {
        s.push_str(&format!(
            "; {} of other groups left out",
            import.other_groups
        ));
    }
    s
}
