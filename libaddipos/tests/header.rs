//! The committed C header is what cbindgen makes of the code now, with
//! the error codes of the host library's one table (decision 512); the
//! manual's table of codes lists the same codes.

// Helpers of the tests may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::fmt::Write as _;
use std::path::Path;

use addipos_host::ErrorCode;

#[test]
fn the_committed_header_is_up_to_date() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).unwrap();
    let bindings = cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .unwrap();
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let fresh = with_codes(&polish(&String::from_utf8(fresh).unwrap()));
    let path = crate_dir.join("include/addipos.h");
    if std::env::var_os("ADDIPOS_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "libaddipos/include/addipos.h is stale: run `ADDIPOS_BLESS=1 cargo test -p libaddipos --test header` and commit it"
    );
}

#[test]
fn the_manual_lists_every_code_with_its_number() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let manual = std::fs::read_to_string(root.join("docs/host-api.md")).unwrap();
    let listed: Vec<(String, String)> = manual
        .lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("| `ADDIPOS_")?;
            let (name, rest) = rest.split_once("` | ")?;
            let (number, _) = rest.split_once(" |")?;
            Some((format!("ADDIPOS_{name}"), number.to_string()))
        })
        .collect();
    let mut table = vec![("ADDIPOS_OK".to_string(), "0".to_string())];
    table.extend(
        ErrorCode::ALL
            .iter()
            .map(|c| (c_name(*c), format!("0x{:08X}", c.code()))),
    );
    assert_eq!(listed, table, "docs/host-api.md's table of codes");
}

/// `ADDIPOS_E_TOO_MANY_HANDLES` for `TooManyHandles`.
fn c_name(code: ErrorCode) -> String {
    let mut name = String::from("ADDIPOS_E_");
    for (i, ch) in code.name().chars().enumerate() {
        if ch.is_ascii_uppercase() && i > 0 {
            name.push('_');
        }
        name.push(ch.to_ascii_uppercase());
    }
    name
}

/// `ADDIPOS_OK` and every code of the table as `#define`s with their
/// meaning, in unsigned hexadecimal (`0xADD00001u`: a decimal above
/// INT32_MAX has no portable type).
fn codes() -> String {
    let mut out = String::from("/**\n * Success.\n */\n#define ADDIPOS_OK 0x00000000u\n\n");
    for &c in ErrorCode::ALL {
        out.push_str("/**\n");
        for line in c.meaning().lines() {
            let _ = writeln!(out, " *{line}");
        }
        let origin = if c.access_error().is_some() {
            "CANopen"
        } else {
            "Code"
        };
        let _ = writeln!(
            out,
            " * ({origin} 0x{code:08X}.)\n */\n#define {name} 0x{code:08X}u\n",
            code = c.code(),
            name = c_name(c),
        );
    }
    out
}

/// The header with the codes before cbindgen's first item (after the
/// includes).
fn with_codes(header: &str) -> String {
    let includes = "#include <stddef.h>\n\n";
    let (head, items) = header.split_once(includes).expect("the includes");
    format!("{head}{includes}{}{items}", codes())
}

/// What cbindgen writes, made clean for every C and C++ standard: its `//`
/// comments (not C89) as `/* */`.
fn polish(header: &str) -> String {
    let mut out = String::with_capacity(header.len());
    for line in header.lines() {
        match line.split_once("// ") {
            Some((code, comment)) if !code.trim_start().starts_with('*') => {
                let _ = writeln!(out, "{code}/* {comment} */");
            }
            _ => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    out
}
