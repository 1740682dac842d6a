//! The committed C header is what cbindgen makes of the code now.

// Helpers of the tests may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

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
    let fresh = polish(&String::from_utf8(fresh).unwrap());
    let path = crate_dir.join("include/addipos.h");
    if std::env::var_os("ADDIPOS_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "host/include/addipos.h is stale: run `ADDIPOS_BLESS=1 cargo test -p addipos-host --test header` and commit it"
    );
}

/// What cbindgen writes, made clean for every C and C++ standard: its `//`
/// comments (not C89) as `/* */`, and the codes as unsigned hexadecimal
/// (`0xADD00001u`: a decimal above INT32_MAX has no portable type).
fn polish(header: &str) -> String {
    let mut out = String::with_capacity(header.len());
    for line in header.lines() {
        let line = match line.split_once("// ") {
            Some((code, comment)) if !code.trim_start().starts_with('*') => {
                format!("{code}/* {comment} */")
            }
            _ => line.to_string(),
        };
        out.push_str(&hex_code(&line).unwrap_or(line));
        out.push('\n');
    }
    out
}

/// `#define ADDIPOS_E_X 123` as `#define ADDIPOS_E_X 0x0000007Bu`.
fn hex_code(line: &str) -> Option<String> {
    let rest = line.strip_prefix("#define ADDIPOS_")?;
    let (name, value) = rest.split_once(' ')?;
    if !(name.starts_with("E_") || name == "OK") {
        return None;
    }
    let v: u32 = value.trim().parse().ok()?;
    Some(format!("#define ADDIPOS_{name} 0x{v:08X}u"))
}
