//! Every command's `--help` states the exit statuses of that command,
//! not one text shared by all.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::Command;

/// The `--help` text of `addipos ARGS... --help`.
fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(args)
        .arg("--help")
        .output()
        .expect("run addipos");
    assert!(out.status.success(), "{args:?} --help failed");
    String::from_utf8(out.stdout).expect("utf-8 help")
}

#[test]
fn each_command_states_its_own_exit_statuses() {
    let own = [
        (&["serve"][..], "SIGTERM"),
        (&["call"][..], "no UOI answer"),
        (&["replay"][..], "--shard 4/3"),
        (&["run"][..], "an OTC error"),
        (&["plot"][..], "the picture is still written"),
        (&["objects"][..], "the reference is printed"),
        (&["tools", "show"][..], "Exit status: 0"),
        (&["tools", "export"][..], "Exit status: 0"),
        (&["tools", "import"][..], "Exit status: 0"),
    ];
    for (args, says) in own {
        let text = help(args);
        assert!(text.contains("Exit status: 0"), "{args:?}: {text}");
        assert!(text.contains(says), "{args:?} should say {says:?}: {text}");
    }
    let texts: Vec<String> = ["serve", "call", "replay", "run", "plot", "objects"]
        .iter()
        .map(|c| help(&[c]))
        .map(|t| t[t.find("Exit status").unwrap_or(0)..].to_owned())
        .collect();
    for (i, a) in texts.iter().enumerate() {
        for b in &texts[i + 1..] {
            assert_ne!(a, b, "two commands share one exit-status text");
        }
    }
}

fn root_file(path: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .expect("repository file")
}

#[test]
fn texts_name_the_settings_file_where_it_is() {
    assert!(std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("emulator/config/default.toml")
        .is_file());
    let serve = help(&["serve"]);
    assert!(serve.contains("emulator/config/default.toml"), "{serve}");
    let readme = root_file("README.md");
    assert!(!readme.contains("(`config/default.toml`)"), "README");
    assert!(readme.contains("emulator/config/default.toml"), "README");
}

#[test]
fn tools_show_and_export_do_not_promise_an_import_failure() {
    for cmd in ["show", "export"] {
        let text = help(&["tools", cmd]);
        assert!(!text.contains("the file to import"), "tools {cmd}: {text}");
    }
    assert!(help(&["tools", "import"]).contains("the file to import is invalid"));
}

#[test]
fn docs_say_what_the_emulator_does() {
    let host = root_file("docs/host-api.md");
    let row = host
        .lines()
        .find(|l| l.starts_with("| `embedded:config=FILE`"))
        .expect("the embedded:config row");
    assert!(row.contains("`realtime`"), "{row}");
    let opcua = root_file("docs/opcua.md");
    assert!(!opcua.contains("no real time"), "docs/opcua.md");
    for doc in ["README.md", "docs/host-api.md"] {
        for line in root_file(doc)
            .lines()
            .filter(|l| l.contains("make -C examples/c run"))
        {
            assert!(line.contains("PROFILE=release"), "{doc}: {line}");
        }
    }
}

#[test]
fn an_nc_parse_error_exits_the_same_from_run_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("bad.nc");
    std::fs::write(&prog, "N10 G01 X10 Y@\n").unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .arg(&prog)
        .output()
        .unwrap();
    let plot = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("plot")
        .arg(&prog)
        .arg("-o")
        .arg(dir.path().join("bad.svg"))
        .output()
        .unwrap();
    assert_eq!(
        run.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(
        plot.status.code(),
        run.status.code(),
        "{}",
        String::from_utf8_lossy(&plot.stderr)
    );
    let trace = dir.path().join("bad.trace");
    std::fs::write(&trace, "FROB\n").unwrap();
    let plot = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("plot")
        .arg(&trace)
        .arg("-o")
        .arg(dir.path().join("t.svg"))
        .output()
        .unwrap();
    assert_eq!(
        plot.status.code(),
        Some(1),
        "a trace that does not parse, as from replay"
    );
}

#[cfg(unix)]
#[test]
fn the_c_example_builds_into_target_not_the_source_tree() {
    let out = Command::new("make")
        .args(["-n", "-C", "examples/c", "run", "check", "PROFILE=release"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    let Ok(out) = out else {
        eprintln!("no make: skipped");
        return;
    };
    let plan = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{plan}");
    let target = format!("{}/target/", env!("CARGO_MANIFEST_DIR"));
    for line in plan.lines().filter(|l| l.contains(" -o ")) {
        let output = line.split(" -o ").nth(1).and_then(|r| r.split(' ').next());
        assert!(
            output.is_some_and(|o| o.starts_with(&target)),
            "a program built outside target/: {line}"
        );
    }
    assert!(plan.contains("--release"), "{plan}");
}
