//! Starting `addipos serve` on damaged tool data: a bad line of
//! a tool file or of the journal (other than its torn last record) refuses
//! the start, naming the file and the line; `--ignore-bad-tools` starts
//! anyway, logs every skipped line and keeps a copy of each damaged file;
//! a torn last journal record (cut off before its newline) is dropped
//! with a log line and the server starts.
//!
//! A complete last record with a bad checksum is damage, not a
//! torn write; leftover temporary files are removed at start.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use common::{bin, ServeProcess};
use tc_objects::TcObject;
use tool_store::{Record, ToolField, ToolKey, ToolValue};
use uoi::tcp::BlockingClient;
use uoi::{Value, ValueType};

/// A fresh data directory for `name` holding `files` in its tool folder.
fn data_dir(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("tool-start-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("tools")).unwrap();
    for (file, text) in files {
        std::fs::write(dir.join("tools").join(file), text).unwrap();
    }
    dir
}

/// Runs `serve` on `dir` expecting it not to start: its exit code and
/// stderr (bounded: a server that does start is killed and fails).
fn refused(dir: &Path) -> (i32, String) {
    let mut child = bin()
        .args(["serve", "--listen", "127.0.0.1:0", "--data-dir"])
        .arg(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("serve");
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if t0.elapsed() > Duration::from_secs(15) {
            let _ = child.kill();
            panic!("serve started on bad tool data");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = child.wait_with_output().expect("output");
    (
        status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn start(dir: &Path, extra: &[&str]) -> ServeProcess {
    let d = dir.to_str().unwrap();
    let mut args = vec!["--data-dir", d, "--listen", "127.0.0.1:0"];
    args.extend_from_slice(extra);
    ServeProcess::start(&args, &[])
}

/// RADIUS of entry `index` of group `g`, read from the server.
fn radius(addr: &str, g: u16, index: i32) -> f64 {
    let mut c = BlockingClient::connect(addr).expect("connect");
    c.write(TcObject::WkzIndex.of(g), Value::I32(index))
        .expect("WKZINDEX");
    match c.read(TcObject::Radius.of(g), ValueType::F64) {
        Ok(Value::F64(v)) => v,
        other => panic!("{other:?}"),
    }
}

/// The journal line (with its newline) setting RADIUS of (`g`, `index`) to `mm`.
fn radius_record(g: u8, index: u16, mm: f64) -> String {
    Record::Set {
        group: g,
        key: ToolKey::new(index, ToolField::Radius).unwrap(),
        value: ToolValue::F64(mm),
    }
    .encode()
}

const GOOD: &str = "# hand-written\nwz[1].radius 300000\n";

/// A damage: its name, the tool folder's files, the place the error must
/// name and a word of what is wrong.
type Damage = (
    &'static str,
    Vec<(&'static str, String)>,
    &'static str,
    &'static str,
);

/// Each damage, the file it is in, the line that must be named, and a
/// word of what is wrong.
fn damages() -> Vec<Damage> {
    let good = |extra: &str| format!("{GOOD}{extra}");
    let journal = format!(
        "{}{}\n{}",
        radius_record(2, 1, 1.0),
        // A record cut off in the middle of the journal.
        &radius_record(2, 2, 2.0)[..12],
        radius_record(2, 3, 3.0)
    );
    vec![
        (
            "garbage",
            vec![("group01.wz", good("this is not a tool line\n"))],
            "group01.wz:3",
            "value",
        ),
        (
            "duplicate",
            vec![("group01.wz", good("wz[2].typ 2\nwz[1].radius 1\n"))],
            "group01.wz:4",
            "duplicate",
        ),
        (
            "range",
            vec![("group01.wz", good("wz[2].typ 7\n"))],
            "group01.wz:3",
            "range",
        ),
        (
            "unknown",
            vec![("group01.wz", good("wz[2].gueltig 1\n"))],
            "group01.wz:3",
            "unknown field",
        ),
        (
            "truncated",
            vec![("group01.wz", good("wz[2].radius\n"))],
            "group01.wz:3",
            "no value",
        ),
        (
            "journal",
            vec![("group01.wz", good("")), ("journal.wzj", journal)],
            "journal.wzj:2",
            "checksum",
        ),
    ]
}

#[test]
fn damaged_tool_data_refuses_the_start_with_file_and_line() {
    for (name, files, place, what) in damages() {
        let dir = data_dir(
            name,
            &files
                .iter()
                .map(|(f, t)| (*f, t.as_str()))
                .collect::<Vec<_>>(),
        );
        let (code, err) = refused(&dir);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(place), "{name}: {place} not named: {err}");
        assert!(err.contains(what), "{name}: `{what}` not said: {err}");
        assert!(
            err.contains("--ignore-bad-tools"),
            "{name}: no way out: {err}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn ignore_bad_tools_starts_and_logs_each_skipped_line() {
    for (name, files, place, _) in damages() {
        let name = format!("{name}-ignored");
        let dir = data_dir(
            &name,
            &files
                .iter()
                .map(|(f, t)| (*f, t.as_str()))
                .collect::<Vec<_>>(),
        );
        let server = start(&dir, &["--ignore-bad-tools"]);
        assert_eq!(radius(&server.addr, 1, 1), 30.0, "{name}: good line lost");
        if place.starts_with("journal") {
            // The records around the bad one count.
            assert_eq!(radius(&server.addr, 2, 1), 1.0, "{name}");
            assert_eq!(radius(&server.addr, 2, 3), 3.0, "{name}");
        }
        let log = server.stop();
        assert!(
            log.contains("skipped a bad tool") && log.contains(place),
            "{name}: {place} not logged: {log}"
        );
        // The damaged file was kept as it was before the repair.
        let file = place.split(':').next().unwrap();
        let original = &files.iter().find(|(f, _)| *f == file).unwrap().1;
        let copies = bad_copies(&dir, file);
        assert_eq!(copies.len(), 1, "{name}: {copies:?}");
        assert_eq!(&std::fs::read_to_string(&copies[0]).unwrap(), original);
        assert!(log.contains(&*copies[0].to_string_lossy()), "{name}: {log}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The copies `<file>.bad-<time>` kept in the tool folder of `dir`.
fn bad_copies(dir: &Path, file: &str) -> Vec<PathBuf> {
    std::fs::read_dir(dir.join("tools"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(&format!("{file}.bad-")))
        })
        .collect()
}

/// A bit flip in the last complete journal record is
/// not a torn write. The start is refused with the file and the line, and
/// nothing is cut off the journal; `--ignore-bad-tools` starts without
/// it, after keeping a copy of the journal as it was.
#[test]
fn a_bit_flip_in_the_last_complete_record_refuses_the_start() {
    let mut journal = format!("{}{}", radius_record(3, 4, 12.5), radius_record(3, 5, 1.0));
    // "g3 wz[5].radius 10000 *crc\n": a digit of the value flipped.
    let at = journal.rfind("10000").unwrap();
    journal.replace_range(at..at + 1, "3");
    let dir = data_dir("bitflip", &[("journal.wzj", &journal)]);
    let (code, err) = refused(&dir);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("journal.wzj:2") && err.contains("checksum"),
        "{err}"
    );
    let left = std::fs::read_to_string(dir.join("tools").join("journal.wzj")).unwrap();
    assert_eq!(left, journal, "the journal was changed");

    let server = start(&dir, &["--ignore-bad-tools"]);
    assert_eq!(radius(&server.addr, 3, 4), 12.5);
    assert_eq!(radius(&server.addr, 3, 5), 0.0);
    let log = server.stop();
    assert!(log.contains("journal.wzj:2"), "{log}");
    let copies = bad_copies(&dir, "journal.wzj");
    assert_eq!(copies.len(), 1, "{copies:?}");
    assert_eq!(std::fs::read_to_string(&copies[0]).unwrap(), journal);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A temporary file left by a compaction cut short
/// (here a 0-byte one, as a full disk left it) is removed at start, and
/// the log says so.
#[test]
fn leftover_temporary_files_are_removed_at_start() {
    let dir = data_dir(
        "leftover",
        &[
            ("group01.wz", GOOD),
            ("group01.wz.tmp", ""),
            ("group02.wz.tmp", "wz[1].ra"),
        ],
    );
    let server = start(&dir, &[]);
    assert_eq!(radius(&server.addr, 1, 1), 30.0);
    let log = server.stop();
    for name in ["group01.wz.tmp", "group02.wz.tmp"] {
        assert!(!dir.join("tools").join(name).exists(), "{name} left");
        assert!(log.contains(&format!("removed {name}")), "{name}: {log}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_torn_last_journal_record_is_dropped_and_logged() {
    let journal = format!(
        "{}{}",
        radius_record(3, 4, 12.5),
        &radius_record(3, 5, 1.0)[..15]
    );
    let dir = data_dir("torn", &[("journal.wzj", &journal)]);
    let server = start(&dir, &[]);
    assert_eq!(radius(&server.addr, 3, 4), 12.5);
    assert_eq!(radius(&server.addr, 3, 5), 0.0);
    let log = server.stop();
    assert!(
        log.contains("dropped the torn last record") && log.contains("line=2"),
        "{log}"
    );
    let left = std::fs::read_to_string(dir.join("tools").join("journal.wzj")).unwrap();
    assert_eq!(left, radius_record(3, 4, 12.5), "torn tail cut off");
    let _ = std::fs::remove_dir_all(&dir);
}
