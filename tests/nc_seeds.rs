//! Every NC program of `tests/nc/` (the manuals' programs, typed in)
//! through the command line: drawn by `addipos plot` with its three paths,
//! and run by `addipos run --trace` into a trace that `addipos replay`
//! passes in-process and over TCP against `addipos serve`.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

use common::{bin, ServeProcess};

/// How a seed program's run ends.
#[derive(Debug, Clone, Copy, PartialEq)]
enum End {
    /// Runs to its end.
    Clean,
    /// Stops with a run-time error (exit 1), still drawn and traced up to
    /// there.
    Stops,
    /// Does not parse as printed: the sample's bare `Y` in N60 (line 6).
    BareY,
}

/// Every program of `tests/nc/`, the tool data it runs with (a tool file's
/// text) and how it ends.
const SEEDS: [(&str, &str, End); 15] = [
    ("wzkg25.nc", RADIUS10, End::Clean),
    ("wzkg26.nc", RADIUS10, End::Clean),
    // Radius 5 mm in D100; the printed second circle does not close.
    ("tool_data_change.nc", "wz[100].radius 50000\n", End::Stops),
    ("dynamic_radius.nc", "wz[6].radius 50000\n", End::Clean),
    ("otc_general.nc", DISC, End::Clean),
    ("wr_quad_disc.nc", DISC, End::Clean),
    ("otc_length.nc", DISC, End::Clean),
    ("otc_tool_dir.nc", DISC, End::Clean),
    ("otc_surf_norm_dir.nc", DISC, End::Clean),
    ("toolparam_set.nc", "", End::BareY),
    ("toolparam_get.nc", "", End::BareY),
    // The ISG manual's selection examples (radius set in the program).
    ("bsp01.nc", "", End::Clean),
    ("musterstern.nc", "", End::Clean),
    ("g239_demo2.nc", "", End::Clean),
    ("tangfeed.nc", "", End::Clean),
];

const RADIUS10: &str = include_str!("../docs/nc/radius10.wz");
const DISC: &str = include_str!("../docs/nc/disc.wz");

/// The programs drawn in X-Z (they move in X and Z only).
const IN_X_Z: [&str; 3] = ["otc_length.nc", "otc_tool_dir.nc", "otc_surf_norm_dir.nc"];

fn seed_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/nc")
}

/// A fresh folder of its own for one test.
fn work_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-nc-seeds-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The list above names every file of `tests/nc/`.
fn check_the_list_is_complete() {
    let mut files: Vec<String> = std::fs::read_dir(seed_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    files.sort();
    let mut listed: Vec<String> = SEEDS.iter().map(|s| s.0.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed);
}

/// The program to run and the `--tools` arguments, in `dir`. A sample
/// with the bare `Y` is given without it (as printed it does not parse).
fn prepared(dir: &Path, name: &str, tools: &str, end: End) -> (PathBuf, Vec<String>) {
    let mut prog = seed_dir().join(name);
    if end == End::BareY {
        let text = std::fs::read_to_string(&prog).unwrap();
        let fixed = text.replace("N60 G41 X200 Y D10", "N60 G41 X200 D10");
        assert_ne!(fixed, text, "{name}: no bare Y");
        prog = dir.join(name);
        std::fs::write(&prog, fixed).unwrap();
    }
    let mut args = Vec::new();
    if !tools.is_empty() {
        let file = dir.join(format!("{name}.wz"));
        std::fs::write(&file, tools).unwrap();
        args = vec!["--tools".to_string(), file.to_str().unwrap().to_string()];
    }
    (prog, args)
}

fn addipos(args: &[&str]) -> Output {
    bin().args(args).output().expect("run addipos")
}

fn text(out: &[u8]) -> String {
    String::from_utf8_lossy(out).into_owned()
}

/// As printed, a sample with the bare `Y` is refused with its place.
fn assert_refused_as_printed(command: &str, name: &str, code: i32) {
    let prog = seed_dir().join(name);
    let mut args = vec![command, prog.to_str().unwrap()];
    if command == "plot" {
        args.extend(["-o", "unused.svg"]);
    }
    let out = addipos(&args);
    assert_eq!(out.status.code(), Some(code), "{command} {name}");
    let err = text(&out.stderr);
    assert!(
        err.contains("line 6, block N60, column 14"),
        "{name}: {err}"
    );
}

/// The polylines of the paths (the legend's samples left out) by stroke
/// colour: each as its points.
fn path_points(svg: &str, colour: &str) -> Vec<Vec<String>> {
    let body = svg.split("<g class=\"legend\"").next().unwrap();
    body.split("<polyline")
        .skip(1)
        .filter(|p| p.contains(&format!("stroke=\"{colour}\"")))
        .filter_map(|p| p.split("points=\"").nth(1)?.split('"').next())
        .map(|p| p.split(' ').map(str::to_owned).collect())
        .collect()
}

/// The picture has the programmed contour, the corrected tool centre and
/// the executed path, each with at least two different points.
fn assert_three_paths(name: &str, svg: &str) {
    assert!(
        svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
        "{name}"
    );
    for colour in ["#666", "#8cf", "#d22"] {
        let drawn = path_points(svg, colour)
            .iter()
            .any(|points| points.iter().any(|p| *p != points[0]));
        assert!(drawn, "{name}: no path in {colour}");
    }
}

/// The axis names of the picture (texts of one letter).
fn axis_names(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| t.split_once('>')?.1.split("</text>").next())
        .map(str::trim)
        .filter(|t| t.len() == 1 && t.chars().all(|c| c.is_ascii_uppercase()))
        .map(str::to_owned)
        .collect()
}

/// Runs `addipos COMMAND PROG FLAG DIR/NAME.EXT [tools]` on a seed program
/// (as prepared), checks its exit code (1 for a program that stops, else
/// 0) and gives the path written.
fn seed_command(
    dir: &Path,
    (command, flag, ext): (&str, &str, &str),
    (name, tools, end): (&str, &str, End),
) -> PathBuf {
    let (prog, tool_args) = prepared(dir, name, tools, end);
    let written = dir.join(format!("{name}.{ext}"));
    let mut args = vec![
        command,
        prog.to_str().unwrap(),
        flag,
        written.to_str().unwrap(),
    ];
    args.extend(tool_args.iter().map(String::as_str));
    let out = addipos(&args);
    let code = if end == End::Stops { 1 } else { 0 };
    assert_eq!(
        out.status.code(),
        Some(code),
        "{name}: {}",
        text(&out.stderr)
    );
    written
}

#[test]
fn every_seed_program_is_drawn_with_its_three_paths() {
    check_the_list_is_complete();
    let dir = work_dir("plot");
    for (name, tools, end) in SEEDS {
        if end == End::BareY {
            // A parse error exits 1 from plot as from run (decision 416).
            assert_refused_as_printed("plot", name, 1);
        }
        let svg_path = seed_command(&dir, ("plot", "-o", "svg"), (name, tools, end));
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        assert_three_paths(name, &svg);
        let plane = if IN_X_Z.contains(&name) {
            ["X", "Z"]
        } else {
            ["X", "Y"]
        };
        assert_eq!(axis_names(&svg), plane, "{name}");
    }
}

#[test]
fn every_seed_program_traced_by_run_replays_in_process_and_over_tcp() {
    let dir = work_dir("trace");
    let mut traces = Vec::new();
    for (name, tools, end) in SEEDS {
        if end == End::BareY {
            assert_refused_as_printed("run", name, 1);
        }
        let trace = seed_command(&dir, ("run", "--trace", "trace"), (name, tools, end));
        traces.push(trace.to_str().unwrap().to_owned());
    }
    let all: Vec<&str> = traces.iter().map(String::as_str).collect();
    let summary = format!("{} passed, 0 failed", all.len());
    let out = addipos(&[&["replay"][..], &all].concat());
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains(&summary), "{stdout}");
    let server = ServeProcess::start(&["--listen", "127.0.0.1:0"], &[]);
    let out = addipos(&[&["replay", "--server", &server.addr][..], &all].concat());
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", server.stop());
    assert!(stdout.contains(&summary), "{stdout}");
}
