//! docs/nc.md's worked example: the program in its `nc` block runs, and
//! prints exactly the lines the page shows.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::Command;

/// The text of the first fenced block of `lang` after `heading`.
fn block<'a>(doc: &'a str, heading: &str, lang: &str) -> &'a str {
    let from = doc.find(heading).unwrap_or_else(|| panic!("no {heading}"));
    let fence = format!("```{lang}\n");
    let start = doc[from..].find(&fence).unwrap() + from + fence.len();
    let len = doc[start..].find("```").unwrap();
    &doc[start..start + len]
}

#[test]
fn the_worked_example_runs_as_documented() {
    let doc = std::fs::read_to_string("docs/nc.md").expect("docs/nc.md");
    let program = block(&doc, "## A worked example", "nc");
    let shown = block(&doc, "## A worked example", "text");
    let dir = std::env::temp_dir().join(format!("addipos-ncref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("square.nc");
    std::fs::write(&path, program).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .arg(&path)
        .output()
        .expect("run addipos");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.is_empty(), "no warnings: {stderr}");
    assert!(
        stdout.starts_with(shown),
        "documented:\n{shown}\nprinted:\n{stdout}"
    );
    let rest: Vec<&str> = stdout[shown.len()..].lines().collect();
    assert!(rest
        .iter()
        .all(|l| l.starts_with("V.G.WZ_AKT.") && l.ends_with(" = 0")));
}

#[test]
fn run_help_and_readme_point_to_the_reference() {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(["run", "--help"])
        .output()
        .expect("run addipos");
    assert!(String::from_utf8_lossy(&out.stdout).contains("docs/nc.md"));
    let readme = std::fs::read_to_string("README.md").unwrap();
    assert!(readme.contains("docs/nc.md"));
}

#[test]
fn readme_commands_redraw_the_committed_pictures() {
    let readme = std::fs::read_to_string("README.md").unwrap();
    let dir = std::env::temp_dir().join(format!("addipos-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut drawn = 0;
    for line in readme.lines() {
        let Some(args) = line.strip_prefix("cargo run --release -- plot ") else {
            continue;
        };
        let words: Vec<&str> = args.split_whitespace().collect();
        let Some(o) = words.iter().position(|w| *w == "-o") else {
            continue;
        };
        let committed = words[o + 1];
        if !committed.starts_with("docs/") {
            continue;
        }
        let fresh = dir.join(format!("{drawn}.svg"));
        let status = Command::new(env!("CARGO_BIN_EXE_addipos"))
            .arg("plot")
            .args(&words[..o])
            .arg("-o")
            .arg(&fresh)
            .status()
            .expect("run addipos");
        assert!(status.success(), "{line}");
        let want = std::fs::read_to_string(committed).unwrap();
        let got = std::fs::read_to_string(&fresh).unwrap();
        assert!(got == want, "{committed} is not what `{line}` draws");
        drawn += 1;
    }
    assert_eq!(drawn, 3, "the README draws wzkg25, wzkg26 and otc_general");
}

/// The small grinding program of the `#OTC` section runs with the tool
/// file it names, with no error, and books radius wear.
#[test]
fn the_otc_example_runs_and_books_wear() {
    let doc = std::fs::read_to_string("docs/nc.md").expect("docs/nc.md");
    let program = block(&doc, "## OTC: `#OTC`", "nc");
    let dir = std::env::temp_dir().join(format!("addipos-ncotc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("otc.nc");
    std::fs::write(&path, program).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .arg(&path)
        .args(["--tools", "docs/nc/disc.wz"])
        .output()
        .expect("run addipos");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let wear: f64 = stdout
        .lines()
        .find_map(|l| l.strip_prefix("V.G.WZ_AKT.WEAR_RADIUS = "))
        .expect("WEAR_RADIUS printed")
        .parse()
        .expect("a number");
    assert!(wear > 0.0, "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}
