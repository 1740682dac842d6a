//! Tool data through the server and the `tools` command: values written
//! over the bus survive a restart; export → Clean (over the bus) → import
//! brings every value back bit-identically.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::{bin, ServeProcess};
use tc_objects::{OtcObject, TcObject};
use uoi::tcp::BlockingClient;
use uoi::{Value, ValueType};

/// A fresh data directory of its own.
fn data_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-rt-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    dir
}

fn serve(dir: &Path) -> ServeProcess {
    let d = dir.to_str().unwrap();
    ServeProcess::start(&["--listen", "127.0.0.1:0", "--data-dir", d], &[])
}

/// Awkward radii and wear constants: each (group, entry) gets its own.
fn values() -> Vec<(u16, i32, f64, f64)> {
    vec![
        (1, 0, 0.1 + 0.2, 1.0 / 3.0),
        (1, 7, -0.0, 5e-324),
        (2, 1023, 1e9, 123456.789),
        (32, 3, -123.456789012345, 1e300),
    ]
}

/// Writes every value over the bus (WKZINDEX first, then the fields).
fn write_all(c: &mut BlockingClient) {
    for (g, w, r, k) in values() {
        c.write(TcObject::WkzIndex.of(g), Value::I32(w)).unwrap();
        c.write(TcObject::Radius.of(g), Value::F64(r)).unwrap();
        c.write(OtcObject::ToolWearConst.of(g), Value::F64(k))
            .unwrap();
    }
}

/// Reads every value back and compares bit for bit (`zero`: all 0).
fn check_all(c: &mut BlockingClient, zero: bool) {
    for (g, w, r, k) in values() {
        c.write(TcObject::WkzIndex.of(g), Value::I32(w)).unwrap();
        let (r, k) = if zero { (0.0, 0.0) } else { (r, k) };
        for (a, want) in [
            (TcObject::Radius.of(g), r),
            (OtcObject::ToolWearConst.of(g), k),
        ] {
            match c.read(a, ValueType::F64).unwrap() {
                Value::F64(v) => assert_eq!(v.to_bits(), want.to_bits(), "{a}: {v:?} {want:?}"),
                other => panic!("{a}: {other:?}"),
            }
        }
    }
}

fn tools(dir: &Path, args: &[&str]) -> String {
    let out = bin()
        .arg("tools")
        .args(args)
        .arg("--data-dir")
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn export_clean_import_restores_every_value_bit_identically() {
    let dir = data_dir("clean");
    let s = serve(&dir);
    let mut c = BlockingClient::connect(&s.addr).unwrap();
    write_all(&mut c);
    drop(c);
    // Killed: the journal alone holds the values.
    s.stop();

    let s = serve(&dir);
    let mut c = BlockingClient::connect(&s.addr).unwrap();
    check_all(&mut c, false);
    drop(c);
    s.stop();
    let exported = tools(&dir, &["export"]);

    let s = serve(&dir);
    let mut c = BlockingClient::connect(&s.addr).unwrap();
    c.write(TcObject::Clean.address(), Value::I32(1)).unwrap();
    check_all(&mut c, true);
    drop(c);
    s.stop();

    let file = dir.join("export.txt");
    fs::write(&file, &exported).unwrap();
    tools(&dir, &["import", file.to_str().unwrap()]);
    let s = serve(&dir);
    let mut c = BlockingClient::connect(&s.addr).unwrap();
    check_all(&mut c, false);
    drop(c);
    s.stop();
    assert_eq!(tools(&dir, &["export"]), exported);
    let _ = fs::remove_dir_all(&dir);
}
