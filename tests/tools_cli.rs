//! The `addipos tools show|export|import` commands on a data directory.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::Command;

use tool_store::{Record, Strictness, ToolField, ToolKey, ToolStore, ToolValue};

/// A fresh data directory of its own for one test.
fn data_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-tools-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Runs `addipos tools <args> --data-dir <dir>`: exit code, stdout, stderr.
fn tools(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("tools")
        .args(args)
        .arg("--data-dir")
        .arg(dir)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn set(group: u8, index: u16, field: ToolField, value: ToolValue) -> Record {
    Record::Set {
        group,
        key: ToolKey::new(index, field).unwrap(),
        value,
    }
}

/// Values that only survive when every bit is kept.
fn awkward_records() -> Vec<Record> {
    use ToolField::*;
    vec![
        set(1, 1, ToolType, ToolValue::I32(2)),
        set(1, 1, Radius, ToolValue::F64(30.0)),
        set(1, 1, Length, ToolValue::F64(0.1 + 0.2)),
        set(1, 1, WearConst, ToolValue::F64(100000.0)),
        set(3, 0, Radius, ToolValue::F64(-0.0)),
        set(3, 0, MaxInfeed, ToolValue::F64(5e-324)),
        set(3, 1023, Length, ToolValue::F64(1.0 / 3.0)),
        set(32, 7, TiltAngle, ToolValue::F64(-450000.0)),
        set(32, 7, Radius, ToolValue::F64(1e9)),
        set(32, 7, MaxInfeed, ToolValue::F64(f64::MAX)),
    ]
}

/// A data directory with the awkward values, partly compacted into tool
/// files and partly still in the journal.
fn filled_dir(name: &str) -> PathBuf {
    let dir = data_dir(name);
    let records = awkward_records();
    let (mut store, _) = ToolStore::open_dir(dir.join("tools"), Strictness::Strict).unwrap();
    store.append(&records[..4]).unwrap();
    store.compact().unwrap();
    store.append(&records[4..]).unwrap();
    dir
}

/// Every value of the store in `dir`, as bits.
fn stored(dir: &Path) -> Vec<(u8, ToolKey, ToolValue)> {
    let (store, _) = ToolStore::open_dir(dir.join("tools"), Strictness::Strict).unwrap();
    store.values().collect()
}

#[test]
fn show_lists_changed_entries_in_bus_units() {
    let dir = filled_dir("show");
    let (code, out, err) = tools(&dir, &["show"]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<Vec<&str>> = out
        .lines()
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(rows[0][..4], ["group", "entry", "typ", "radius"]);
    assert_eq!(rows[1][..3], ["0..3", "mm", "mm"]);
    // Radius 300000 in the file is 30 mm on the bus.
    let g1 = [
        "1",
        "1",
        "2",
        "30.0",
        "0.30000000000000004",
        "100000.0",
        "0.0",
        "0.0",
    ];
    assert_eq!(rows[2], g1);
    assert_eq!(rows[3][..2], ["3", "0"]);
    assert_eq!(rows.len(), 2 + 4, "{out}");

    let (code, out, _) = tools(&dir, &["show", "--group", "32", "--json"]);
    assert_eq!(code, 0);
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    let entries = doc["entries"].as_array().unwrap();
    assert_eq!(entries.len(), 1);
    assert_eq!(entries[0]["group"], 32);
    assert_eq!(entries[0]["grinding_disc_tilt_angle"], -450000.0);
    assert_eq!(entries[0]["radius"].as_f64(), Some(1e9));
    assert_eq!(entries[0]["grinding_max_infeed"].as_f64(), Some(f64::MAX));
}

#[test]
fn show_of_an_empty_data_dir_says_so() {
    let dir = data_dir("empty");
    let (code, out, _) = tools(&dir, &["show"]);
    assert_eq!(code, 0);
    assert!(out.contains("every entry is at its defaults"), "{out}");
    assert!(!dir.join("tools").exists(), "show must not create anything");
}

#[test]
fn export_writes_the_tool_file_syntax_with_the_group_per_line() {
    let dir = filled_dir("export");
    let (code, out, err) = tools(&dir, &["export", "--group", "1"]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<_> = out.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(
        lines,
        [
            "g1 wz[1].typ 2",
            "g1 wz[1].radius 300000",
            "g1 wz[1].laenge 3000.0000000000004",
            "g1 wz[1].grinding_wear_const 100000",
        ]
    );
}

#[test]
fn hand_written_file_in_the_manuals_style_imports() {
    let dir = filled_dir("manual");
    let file = dir.join("grinder.wz");
    let text = "\
# Grinding disc, written by hand
wz[1].typ                  2
wz[1].radius               300000   # 30 mm
wz[2].laenge               125000
# Wear constant : Unit 0.1 um/m
wz[2].grinding_wear_const  100000
";
    fs::write(&file, text).unwrap();
    let (code, out, err) = tools(&dir, &["import", "--group", "5", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("imported 4 tool value(s)"), "{out}");
    let values = stored(&dir);
    let get = |g, i, f| {
        let k = ToolKey::new(i, f).unwrap();
        values.iter().find(|v| v.0 == g && v.1 == k).map(|v| v.2)
    };
    assert_eq!(get(5, 1, ToolField::ToolType), Some(ToolValue::I32(2)));
    assert_eq!(get(5, 1, ToolField::Radius), Some(ToolValue::F64(30.0)));
    assert_eq!(get(5, 2, ToolField::Length), Some(ToolValue::F64(12.5)));
    // Entries the file does not name keep their values.
    assert_eq!(get(1, 1, ToolField::Radius), Some(ToolValue::F64(30.0)));
    assert_eq!(values.len(), awkward_records().len() + 4);
    // The values are in the tool file of group 5, compacted.
    let group5 = fs::read_to_string(dir.join("tools/group05.wz")).unwrap();
    assert!(group5.contains("wz[1].radius 300000\n"), "{group5}");
}

#[test]
fn bad_import_changes_nothing_and_names_file_and_line() {
    let dir = filled_dir("bad");
    let before = stored(&dir);
    let files_before = snapshot(&dir);
    let file = dir.join("bad.txt");
    let text = "\
g2 wz[1].typ 1
this is not a tool value
g2 wz[1].colour 3
g2 wz[1].typ 2
g2 wz[2].grinding_disc_tilt_angle 450001
g2 wz[3].radius 10
";
    fs::write(&file, text).unwrap();
    let (code, _, err) = tools(&dir, &["import", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    let name = file.display().to_string();
    for (line, what) in [
        (2, "expected `wz[<index>].<field> <value>`"),
        (3, "unknown field `colour`"),
        (4, "duplicate key g2 wz[1].typ (first set on line 1)"),
        (5, "out of range"),
    ] {
        let want = format!("{name}:{line}: ");
        let hit = err.lines().find(|l| l.starts_with(&want));
        assert!(hit.is_some_and(|l| l.contains(what)), "{want}{what}\n{err}");
    }
    assert!(!err.contains(":6:"), "{err}");
    assert!(err.contains("nothing was changed"), "{err}");
    assert_eq!(stored(&dir), before);
    assert_eq!(snapshot(&dir), files_before);
}

/// Names and contents of the files in the tool folder.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<_> = fs::read_dir(dir.join("tools"))
        .unwrap()
        .map(|e| e.unwrap())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

/// export, remove the tool files, import, export again: the same text and
/// the same bits, in both formats.
fn round_trip(format: &[&str]) {
    let dir = filled_dir(&format!("round{}", format.len()));
    let before = stored(&dir);
    let file = dir.join("export.out");
    let f = file.to_str().unwrap();
    let (code, _, err) = tools(&dir, &[&["export", f], format].concat());
    assert_eq!(code, 0, "{err}");
    fs::remove_dir_all(dir.join("tools")).unwrap();
    let (code, _, err) = tools(&dir, &[&["import", f], format].concat());
    assert_eq!(code, 0, "{err}");
    assert_eq!(stored(&dir), before, "values differ after the round trip");
    let (code, again, _) = tools(&dir, &[&["export"], format].concat());
    assert_eq!(code, 0);
    assert_eq!(again, fs::read_to_string(&file).unwrap());
}

#[test]
fn export_remove_import_export_is_bit_identical() {
    round_trip(&[]);
}

#[test]
fn json_export_remove_import_export_is_bit_identical() {
    round_trip(&["--json"]);
}

#[test]
fn replace_makes_the_file_the_whole_tool_data() {
    let dir = filled_dir("replace");
    let file = dir.join("one.txt");
    fs::write(&file, "g4 wz[9].typ 3\n").unwrap();
    let (code, out, err) = tools(&dir, &["import", "--replace", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("every other value is back at its default"),
        "{out}"
    );
    let key = ToolKey::new(9, ToolField::ToolType).unwrap();
    assert_eq!(stored(&dir), [(4, key, ToolValue::I32(3))]);
}

#[test]
fn import_is_refused_while_the_lock_is_held() {
    let dir = filled_dir("locked");
    let before = stored(&dir);
    let file = dir.join("one.txt");
    fs::write(&file, "g4 wz[9].typ 3\n").unwrap();
    // As a running server holds it.
    let lock = File::create(dir.join("tools/.lock")).unwrap();
    lock.lock().unwrap();
    let (code, _, err) = tools(&dir, &["import", file.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is locked: a server"), "{err}");
    assert_eq!(stored(&dir), before);
    // Reading needs no lock.
    let (code, out, _) = tools(&dir, &["export"]);
    assert_eq!(code, 0);
    assert!(out.contains("g1 wz[1].radius 300000"), "{out}");
    drop(lock);
    let (code, _, err) = tools(&dir, &["import", file.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn corrupt_tool_file_is_named_with_its_line() {
    let dir = filled_dir("corrupt");
    fs::write(dir.join("tools/group02.wz"), "wz[1].typ 1\nwz[1].typ 9\n").unwrap();
    let (code, _, err) = tools(&dir, &["show"]);
    assert_eq!(code, 2);
    let path = dir.join("tools/group02.wz").display().to_string();
    assert!(err.contains(&format!("{path}:2: ")), "{err}");
}
