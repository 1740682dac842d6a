//! The Python package's exception classes (python/addipos/__init__.py and
//! its stubs) are the host library's table of codes: one class per code,
//! named as the code, an access error's class under `AccessError`, its
//! `CODE` the code's number, every class in `__all__` and in the table
//! the extension module raises by (decision 512).

// Helpers of the tests may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use addipos_host::ErrorCode;

fn package_file(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../python/addipos")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The classes of `text` that carry a `CODE = 0x...`: name, bases and the
/// number, in the order of the file.
fn coded_classes(text: &str) -> Vec<(String, String, u32)> {
    let mut out = Vec::new();
    let mut class: Option<(String, String)> = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("class ") {
            let (name, rest) = rest.split_once('(').unwrap();
            let (bases, _) = rest.split_once(')').unwrap();
            class = Some((name.to_string(), bases.to_string()));
        } else if let Some(hex) = line.trim().strip_prefix("CODE = 0x") {
            let (name, bases) = class.clone().expect("CODE inside a class");
            out.push((name, bases, u32::from_str_radix(hex, 16).unwrap()));
        }
    }
    out
}

/// The base class a code's class derives from first.
fn base(code: ErrorCode) -> &'static str {
    if code.access_error().is_some() {
        "AccessError"
    } else {
        "Error"
    }
}

#[test]
fn every_code_is_a_class_of_the_package_with_its_number() {
    let init = package_file("__init__.py");
    let classes = coded_classes(&init);
    let table: Vec<(String, u32)> = ErrorCode::ALL
        .iter()
        .map(|c| (c.name().to_string(), c.code()))
        .collect();
    let found: Vec<(String, u32)> = classes.iter().map(|(n, _, v)| (n.clone(), *v)).collect();
    assert_eq!(
        found, table,
        "python/addipos/__init__.py: class NAME, CODE = 0x..."
    );
    for ((name, bases, _), &code) in classes.iter().zip(ErrorCode::ALL) {
        let first = bases.split(',').next().unwrap().trim();
        assert_eq!(first, base(code), "class {name}({bases})");
        // The docstring says the number too.
        assert!(
            init.contains(&format!("0x{:08X})", code.code())),
            "{name}: its docstring names 0x{:08X}",
            code.code()
        );
    }
}

#[test]
fn every_class_is_exported_raised_by_its_code_and_in_the_stubs() {
    let init = package_file("__init__.py");
    let stubs = package_file("__init__.pyi");
    let (_, table) = init
        .split_once("_CLASSES: Dict[int, Type[Error]] = {")
        .unwrap();
    let (table, _) = table.split_once('}').unwrap();
    let (_, all) = init.split_once("__all__ = [").unwrap();
    let (all, _) = all.split_once(']').unwrap();
    for &code in ErrorCode::ALL {
        let name = code.name();
        assert!(
            table.contains(&format!("        {name},\n")),
            "{name} in _CLASSES"
        );
        assert!(
            all.contains(&format!("    \"{name}\",\n")),
            "{name} in __all__"
        );
        assert!(
            stubs.contains(&format!("class {name}({}", base(code))),
            "{name} in __init__.pyi"
        );
    }
}
