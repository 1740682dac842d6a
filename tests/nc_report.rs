//! What `addipos run` says: each spooled element labelled with the block
//! it comes from, wear beyond the tool's radius warned about and printed
//! at the registers' resolution, every bad line of a tool file reported.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::PathBuf;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .args(args)
        .output()
        .expect("run addipos")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn temp(name: &str, content: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-report-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

#[test]
fn held_profiles_are_labelled_with_their_own_block() {
    let out = run(&["tests/nc/wzkg25.nc", "--tools", "docs/nc/radius10.wz"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    // Path 1: N105 is the approach after G41, held until N115 arrives.
    let approach = lines
        .iter()
        .position(|l| l.starts_with("< LIN X12.92893") && l.contains("N105"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(lines[approach].ends_with("# N105 (line 13), spooled at N115 (line 15)"));
    assert!(lines[approach + 1].ends_with("# transition N105 (line 13) to N115 (line 15)"));
    // N115's own profile comes out when N120 arrives.
    assert!(lines.iter().any(|l| l.starts_with("< LIN X30 Y30 ")
        && l.ends_with("# N115 (line 15), spooled at N120 (line 16)")));
    // The held N130 is spooled by the G40 of N135; the departure is N140's.
    assert!(lines
        .iter()
        .any(|l| l.ends_with("# N130 (line 18), spooled at N135 (line 19)")));
    assert!(lines
        .iter()
        .any(|l| l.starts_with("< LIN X0 Y0 ") && l.ends_with("# N140 (line 20)")));
    // Before the correction, each element is its own block's.
    assert!(lines[1].ends_with("# N15 (line 4)"), "{}", lines[1]);
}

#[test]
fn wear_beyond_the_radius_is_warned_and_rounded() {
    let program = std::fs::read_to_string("tests/nc/otc_general.nc")
        .unwrap()
        .replace("N70 X1000", "N70 X20000");
    let p = temp("long_otc.nc", &program);
    let out = run(&[p.to_str().unwrap(), "--tools", "docs/nc/disc.wz"]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    let wear = stdout
        .lines()
        .find_map(|l| l.strip_prefix("V.G.WZ_AKT.WEAR_RADIUS = "))
        .unwrap_or_else(|| panic!("{stdout}"));
    // Whole steps of 0.1 µm: at most four decimals, no float noise.
    let decimals = wear.split_once('.').map_or(0, |(_, d)| d.len());
    assert!(decimals <= 4, "{wear}");
    let wear: f64 = wear.parse().unwrap();
    assert!(wear > 30.0, "{wear}");
    assert!(
        stderr.contains("V.G.WZ_AKT.WEAR_RADIUS = ")
            && stderr.contains("is more than the tool's radius 30 mm"),
        "{stderr}"
    );
    // The same program over the short path stays within the disc.
    let out = run(&["tests/nc/otc_general.nc", "--tools", "docs/nc/disc.wz"]);
    assert!(text(&out.stdout).contains("V.G.WZ_AKT.WEAR_RADIUS = 9.5\n"));
    assert!(
        !text(&out.stderr).contains("radius"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn every_bad_line_of_the_tool_file_is_reported() {
    let tools = temp(
        "bad.wz",
        "wz[1].radius 100000\nwz[1].frob 3\n# fine\nwz[1].radius x\nwz[1].radius 5\n",
    );
    let out = run(&["tests/nc/wzkg25.nc", "--tools", tools.to_str().unwrap()]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    for line in [2, 4, 5] {
        assert!(
            stderr.contains(&format!("bad.wz:{line}:")),
            "line {line}: {stderr}"
        );
    }
    assert!(!stderr.contains("bad.wz:1:"), "{stderr}");
    assert!(stderr.contains("3 bad line(s)"), "{stderr}");
    assert!(text(&out.stdout).is_empty(), "nothing runs");
}
