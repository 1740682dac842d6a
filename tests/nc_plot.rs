//! `addipos plot`: NC programs and traces drawn as SVG with the
//! programmed contour, the corrected tool-centre path and the executed
//! path.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `addipos plot` with `extra` arguments; the exit code and the SVG.
fn plot(file: &Path, extra: &[&str], out_name: &str) -> (Option<i32>, String) {
    let dir = std::env::temp_dir().join(format!("nc-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(out_name);
    let status = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("plot")
        .arg(file)
        .arg("-o")
        .arg(&out)
        .args(extra)
        .status()
        .unwrap();
    let svg = std::fs::read_to_string(&out).unwrap_or_default();
    (status.code(), svg)
}

/// The `points` of every polyline whose hover text or stroke colour is
/// `colour`.
fn points_of(svg: &str, colour: &str) -> usize {
    svg.split("<polyline")
        .skip(1)
        .filter(|p| p.contains(&format!(r##"stroke="{colour}""##)))
        .filter_map(|p| p.split("points=\"").nth(1))
        .filter_map(|p| p.split('"').next())
        .map(|p| p.split(' ').filter(|w| w.contains(',')).count())
        .sum()
}

fn assert_three_paths(svg: &str) {
    assert!(svg.starts_with("<svg"), "{svg}");
    for label in [
        "programmed contour",
        "corrected tool centre (spooled)",
        "executed path (cycle by cycle, OTC offset included)",
    ] {
        assert!(svg.contains(label), "no legend `{label}`");
    }
    // Legend samples have 2 points each; the paths have more.
    for colour in ["#666", "#8cf", "#d22"] {
        assert!(points_of(svg, colour) > 4, "{colour} has no points");
    }
}

fn grinding_tools() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nc-plot-tools-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("grinding.txt");
    std::fs::write(
        &f,
        "wz[1].typ 2\nwz[1].radius 300000\nwz[1].grinding_wear_const 100000\n",
    )
    .unwrap();
    f
}

#[test]
fn a_seed_program_is_drawn_with_its_three_paths_and_blocks() {
    let prog = root().join("tests/nc/wzkg25.nc");
    let (code, svg) = plot(&prog, &[], "wzkg25.svg");
    assert_eq!(code, Some(0));
    assert_three_paths(&svg);
    assert!(
        svg.contains("<title>N1 (line 2)</title>"),
        "no block on hover"
    );
}

#[test]
fn an_otc_program_with_a_grinding_disc_is_drawn() {
    let prog = root().join("tests/nc/otc_general.nc");
    let tools = grinding_tools();
    let args = ["--tools", tools.to_str().unwrap(), "--group", "1"];
    let (code, svg) = plot(&prog, &args, "otc.svg");
    assert_eq!(code, Some(0));
    assert_three_paths(&svg);
}

#[test]
fn a_trace_is_replayed_and_drawn() {
    let (code, svg) = plot(&root().join("traces/exec-arc.trace"), &[], "arc.svg");
    assert_eq!(code, Some(0));
    assert_three_paths(&svg);
}

#[test]
fn a_bad_file_is_an_error() {
    let dir = std::env::temp_dir().join(format!("nc-plot-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.nc");
    std::fs::write(&bad, "N10 G01 X(((\n").unwrap();
    // A parse error fails (exit 1), as from `run` (decision 416).
    let (code, svg) = plot(&bad, &[], "bad.svg");
    assert_eq!(code, Some(1));
    assert!(svg.is_empty());
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(["plot", bad.to_str().unwrap(), "-o", "unused.svg"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.nc: line 1"), "{err}");
    let (code, _) = plot(&dir.join("missing.trace"), &[], "missing.svg");
    assert_eq!(code, Some(2));
}

/// The pictures shown in the README: each has the three paths, each with
/// points.
#[test]
fn readme_pictures_have_the_three_paths() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in ["wzkg25", "wzkg26", "otc_general"] {
        let svg = std::fs::read_to_string(root.join(format!("docs/nc/{name}.svg"))).unwrap();
        for label in [
            "programmed contour",
            "corrected tool centre",
            "executed path",
        ] {
            assert!(svg.contains(label), "{name}: no {label}");
        }
        assert!(
            svg.matches("<polyline").count() >= 3,
            "{name}: paths missing"
        );
    }
}
