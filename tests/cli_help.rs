//! Every command's `--help` states the exit statuses of that command
//! (issue 21), not one text shared by all.

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
