//! `addipos replay FILES`: conformance traces replayed against a fresh
//! emulator each, in-process or over the wire, every mismatch printed.

use std::path::{Path, PathBuf};

use trace::remote::{setup_failed, RemoteTarget};
use trace::{fresh_emulator, open_trace, replay_stream, trace_files, Target};

use super::remote_args::{connect, RemoteArgs};
use super::{Failure, Outcome};

/// The trace files the arguments name: files as given, folders as their
/// `*.trace` files. A path that does not exist, or a folder without
/// traces, is an error.
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => format!("{}: no such file or folder", p.display()),
            _ => format!("{}: {e}", p.display()),
        })?;
        if !meta.is_dir() {
            out.push(p.clone());
            continue;
        }
        let files = trace_files(p).map_err(|e| format!("{}: {e}", p.display()))?;
        if files.is_empty() {
            return Err(format!(
                "no traces found: {} holds no *.trace file",
                p.display()
            ));
        }
        out.extend(files);
    }
    Ok(out)
}

/// Replays one trace file as it is read, printing every mismatch; true
/// when it passed.
fn replay_file(path: &Path, remote: Option<&mut RemoteTarget>, verbose: bool) -> bool {
    let mut reader = match open_trace(path) {
        Ok(r) => r,
        Err(e) => {
            println!("{e}");
            return false;
        }
    };
    let header = reader.header().clone();
    let mut emulator;
    let target: &mut dyn Target = match remote {
        Some(r) => match r.prepare(&header) {
            Ok(()) => r,
            Err(e) => {
                println!("{}", setup_failed(&header, e));
                return false;
            }
        },
        None => {
            emulator = fresh_emulator(&header);
            &mut emulator
        }
    };
    match replay_stream(&mut reader, target, &mut |m| println!("{m}")) {
        Ok(done) if done.mismatches == 0 => {
            if verbose {
                println!("{}: ok ({} requests)", header.file, done.steps);
            }
            true
        }
        Ok(_) => false,
        Err(e) => {
            println!("{e}");
            false
        }
    }
}

/// Runs `addipos replay`: over the wire when `server` is given.
pub fn cmd_replay(
    files: &[PathBuf],
    server: Option<&str>,
    verbose: bool,
    remote_args: &RemoteArgs,
) -> Outcome {
    let files = expand(files).map_err(Failure::trouble)?;
    let mut remote = server
        .map(|s| connect(s, remote_args))
        .transpose()
        .map_err(Failure::trouble)?;
    let (mut passed, mut failed) = (0usize, 0usize);
    for f in &files {
        if replay_file(f, remote.as_mut(), verbose) {
            passed += 1;
        } else {
            failed += 1;
        }
    }
    println!("{passed} passed, {failed} failed");
    if failed == 0 {
        Ok(())
    } else {
        Err(Failure::reported())
    }
}
