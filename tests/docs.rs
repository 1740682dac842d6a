//! The project's documents stand alone: the object reference matches the
//! object table, the OTC picture is what its generator draws, and no file
//! points outside the repository.

use std::fs;
use std::path::{Path, PathBuf};

use emulator::{bits_without_meaning, devices_without_section, object_reference};

/// The generator of docs/otc-path.svg (its `main` writes the file).
#[path = "../examples/otc_picture.rs"]
#[allow(dead_code)]
mod otc_picture;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn objects_md_is_the_generated_reference() {
    let path = root().join("docs/objects.md");
    let fresh = object_reference();
    if std::env::var_os("ADDIPOS_WRITE_DOCS").is_some() {
        fs::write(&path, &fresh).unwrap();
    }
    let on_disk = fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == fresh,
        "docs/objects.md is stale: run `cargo run -- objects > docs/objects.md`"
    );
}

#[test]
fn otc_path_svg_is_the_generated_picture() {
    let path = root().join(otc_picture::PICTURE);
    let fresh = otc_picture::otc_path_svg().unwrap();
    if std::env::var_os("ADDIPOS_WRITE_DOCS").is_some() {
        fs::write(&path, &fresh).unwrap();
    }
    let on_disk = fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == fresh,
        "{} is stale: run `cargo run --example otc_picture`",
        otc_picture::PICTURE
    );
    let docs = fs::read_to_string(root().join("docs/otc.md")).unwrap();
    assert!(
        docs.contains("](otc-path.svg)"),
        "docs/otc.md shows the picture"
    );
}

/// The request and spool lines of `text` (no headers, comments or blank
/// lines), as written.
fn request_lines(text: &str) -> Vec<&str> {
    text.lines()
        .map(str::trim_end)
        .filter(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with('@'))
        .collect()
}

#[test]
fn otc_md_example_is_the_example_trace() {
    let docs = fs::read_to_string(root().join("docs/otc.md")).unwrap();
    let example = docs
        .split("## A worked example")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .unwrap();
    let blocks: String = example
        .split("```")
        .skip(1)
        .step_by(2)
        .map(|b| b.trim_start_matches('\n'))
        .collect();
    let trace = fs::read_to_string(root().join("traces/otc-example-docs.trace")).unwrap();
    assert_eq!(request_lines(&blocks), request_lines(&trace));
}

#[test]
fn every_device_and_bit_is_described() {
    assert_eq!(devices_without_section(), Vec::<u16>::new());
    assert_eq!(bits_without_meaning(), Vec::<String>::new());
    let text = object_reference();
    for row in tc_module::object_map::object_table::<otc_ext::OtcExtension>() {
        assert!(
            text.contains(&format!("| {} |", row.name)),
            "{} missing",
            row.name
        );
    }
    assert!(!text.contains("|  |\n"), "a row without meaning");
}

/// Text files of the repository (not `target/`, not hidden folders).
fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') && name != ".ci" || name == "target" {
            continue;
        }
        if p.is_dir() {
            text_files(&p, out);
        } else if let Ok(text) = fs::read_to_string(&p) {
            let _ = text;
            out.push(p);
        }
    }
}

#[test]
fn no_file_points_outside_the_repository() {
    // Built in pieces so that this file does not match itself.
    let needles = [["shared", "/"].concat(), ["..", "/", "shared"].concat()];
    let mut files = Vec::new();
    text_files(&root(), &mut files);
    assert!(files.len() > 20, "walked too few files: {}", files.len());
    let mut hits = Vec::new();
    for f in &files {
        let text = fs::read_to_string(f).unwrap_or_default();
        for (n, line) in text.lines().enumerate() {
            if needles.iter().any(|needle| line.contains(needle.as_str())) {
                hits.push(format!("{}:{}: {line}", f.display(), n + 1));
            }
        }
    }
    assert!(
        hits.is_empty(),
        "paths outside the repository:\n{}",
        hits.join("\n")
    );
}
