//! `addipos replay` in CI: JUnit XML checked against the element and
//! attribute structure of the JUnit schema CI tools read, `--shard` parts
//! disjoint and whole, `--max-reports` capping the output, and a server
//! that gives no UOI answer refused as unreachable (exit 2).

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::collections::BTreeSet;
use std::io::{Read, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use tc_objects::TcObject;

fn addipos(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(args)
        .output()
        .expect("run addipos")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A fresh folder of its own for one test.
fn empty_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-ci-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 temp path")
}

/// The elements of the JUnit schema CI tools read (the Ant/Jenkins
/// `junit-10.xsd`) and the attributes each may carry.
fn schema_attributes(element: &str) -> Option<&'static [&'static str]> {
    Some(match element {
        "testsuites" => &["name", "time", "tests", "failures", "disabled", "errors"],
        "testsuite" => &[
            "name",
            "tests",
            "failures",
            "errors",
            "time",
            "disabled",
            "skipped",
            "timestamp",
            "hostname",
            "id",
            "package",
        ],
        "testcase" => &["name", "assertions", "time", "classname", "status"],
        "failure" | "error" | "skipped" => &["type", "message"],
        "properties" | "system-out" | "system-err" => &[],
        "property" => &["name", "value"],
        _ => return None,
    })
}

/// The children each element may have in that schema.
fn schema_children(element: &str) -> &'static [&'static str] {
    match element {
        "testsuites" => &["testsuite"],
        "testsuite" => &["properties", "testcase", "system-out", "system-err"],
        "testcase" => &["skipped", "error", "failure", "system-out", "system-err"],
        "properties" => &["property"],
        _ => &[],
    }
}

/// Checks `node` and everything under it against the schema's structure.
fn check_schema(node: roxmltree::Node) {
    let name = node.tag_name().name();
    let allowed = schema_attributes(name).unwrap_or_else(|| panic!("<{name}> is no JUnit element"));
    for a in node.attributes() {
        assert!(
            allowed.contains(&a.name()),
            "<{name} {}=..> not in the schema",
            a.name()
        );
    }
    for required in ["name", "tests", "failures", "errors"] {
        if name == "testsuite" {
            assert!(node.has_attribute(required), "<testsuite> lacks {required}");
        }
    }
    if name == "testcase" {
        assert!(node.has_attribute("name") && node.has_attribute("classname"));
    }
    for child in node.children().filter(|c| c.is_element()) {
        let c = child.tag_name().name();
        assert!(schema_children(name).contains(&c), "<{c}> inside <{name}>");
        check_schema(child);
    }
}

fn count(node: roxmltree::Node, attr: &str) -> usize {
    node.attribute(attr).expect(attr).parse().expect("a count")
}

#[test]
fn junit_report_follows_the_schema_and_the_results() {
    let dir = empty_dir("junit");
    std::fs::write(dir.join("a-pass.trace"), "R 1300/0/3/0 i => 17\n").unwrap();
    let wrong = "R 1300/0/3/0 i => 18\n".repeat(40);
    std::fs::write(dir.join("b-fail.trace"), &wrong).unwrap();
    std::fs::write(dir.join("c-malformed.trace"), "R 1300/0/3/0 i\nFROB <&>\n").unwrap();
    let report = dir.join("report.xml");
    let out = addipos(&[
        "replay",
        s(&dir),
        "--junit",
        s(&report),
        "--max-reports",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    let xml = std::fs::read_to_string(&report).expect("report written");
    let doc = roxmltree::Document::parse(&xml).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "testsuites");
    check_schema(root);

    let suite = root
        .children()
        .find(|c| c.has_tag_name("testsuite"))
        .unwrap();
    assert_eq!(count(suite, "tests"), 3);
    assert_eq!(count(suite, "failures"), 1);
    assert_eq!(count(suite, "errors"), 1);
    let cases: Vec<_> = suite
        .children()
        .filter(|c| c.has_tag_name("testcase"))
        .collect();
    assert_eq!(cases.len(), 3);
    let name = |c: &roxmltree::Node| c.attribute("name").unwrap().to_owned();
    assert!(name(&cases[0]).ends_with("a-pass.trace"));
    assert_eq!(cases[0].children().filter(|c| c.is_element()).count(), 0);

    let failure = cases[1]
        .children()
        .find(|c| c.has_tag_name("failure"))
        .unwrap();
    let message = failure.attribute("message").unwrap();
    assert!(message.starts_with("40 mismatches; first: "), "{message}");
    assert!(message.contains("b-fail.trace:1: `R 1300/0/3/0 i`: expected 18, got 17"));
    let body = failure.text().unwrap_or_default();
    assert_eq!(body.lines().count(), 4, "3 shown and the count: {body}");
    assert!(body.contains("... and 37 more mismatches"), "{body}");

    let error = cases[2]
        .children()
        .find(|c| c.has_tag_name("error"))
        .unwrap();
    let message = error.attribute("message").unwrap();
    assert!(
        message.contains("c-malformed.trace:2: unknown request `FROB`"),
        "{message}"
    );
}

/// The traces a shard replayed, from `replay -v`.
fn replayed(dir: &Path, shard: &str) -> Vec<String> {
    let out = addipos(&["replay", "-v", "--shard", shard, s(dir)]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    text(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_suffix(": ok (1 requests)"))
        .map(str::to_owned)
        .collect()
}

#[test]
fn shards_are_disjoint_and_make_the_whole_corpus() {
    let dir = empty_dir("shard");
    let names: BTreeSet<String> = (0..11)
        .map(|k| {
            let p = dir.join(format!("t{k:02}.trace"));
            std::fs::write(&p, "R 1300/0/3/0 i => 17\n").unwrap();
            p.display().to_string()
        })
        .collect();
    for n in [1usize, 3, 4, 11, 13] {
        let mut union = BTreeSet::new();
        for k in 1..=n {
            let part = replayed(&dir, &format!("{k}/{n}"));
            assert_eq!(part, replayed(&dir, &format!("{k}/{n}")), "deterministic");
            for t in part {
                assert!(union.insert(t.clone()), "{t} in two parts of {n}");
            }
        }
        assert_eq!(union, names, "parts of {n} make the whole");
    }
    let out = addipos(&["replay", "--shard", "4/3", s(&dir)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("is not K/N"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn max_reports_caps_the_lines_and_counts_the_rest() {
    let dir = empty_dir("cap");
    let p = dir.join("many.trace");
    std::fs::write(&p, "R 1300/0/3/0 i => 18\n".repeat(100)).unwrap();
    let mismatch_lines = |out: &Output| {
        text(&out.stdout)
            .lines()
            .filter(|l| l.contains("expected 18, got 17"))
            .count()
    };
    let default = addipos(&["replay", s(&p)]);
    assert_eq!(mismatch_lines(&default), 30);
    assert!(text(&default.stdout).contains("many.trace: 70 more mismatches not shown (of 100"));
    let five = addipos(&["replay", "--max-reports", "5", s(&p)]);
    assert_eq!(mismatch_lines(&five), 5);
    assert!(text(&five.stdout).contains("95 more mismatches not shown"));
    let all = addipos(&["replay", "--max-reports", "0", s(&p)]);
    assert_eq!(mismatch_lines(&all), 100);
    assert!(!text(&all.stdout).contains("not shown"));
    assert_eq!(all.status.code(), Some(1));
}

/// A listener that is no UOI server: it answers every connection with an
/// HTTP error (`garbage`), or reads and never answers.
fn fake_server(garbage: bool) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    std::thread::spawn(move || {
        let mut open = Vec::new();
        for mut conn in listener.incoming().flatten() {
            if garbage {
                let _ = conn.write_all(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n");
            } else {
                let mut buf = [0u8; 64];
                let _ = conn.read(&mut buf);
            }
            open.push(conn);
        }
    });
    addr
}

fn assert_unreachable(out: &Output) {
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("could not reach a UOI server"), "{err}");
    assert!(err.contains("got no UOI answer"), "{err}");
    assert!(!text(&out.stdout).contains(":0:"), "{}", text(&out.stdout));
}

#[test]
fn a_server_answering_garbage_is_unreachable() {
    let addr = fake_server(true);
    let plane = TcObject::TcPlane.address().to_string();
    assert_unreachable(&addipos(&["call", &addr, "R", &plane, "i"]));
    let dir = empty_dir("garbage");
    std::fs::write(dir.join("one.trace"), "R 1300/0/3/0 i => 17\n").unwrap();
    assert_unreachable(&addipos(&["replay", "--server", &addr, s(&dir)]));
}

#[test]
fn a_silent_server_is_unreachable_after_the_stated_wait() {
    let addr = fake_server(false);
    let plane = TcObject::TcPlane.address().to_string();
    let out = addipos(&["call", &addr, "--timeout", "0.5", "R", &plane, "i"]);
    assert_unreachable(&out);
    assert!(
        text(&out.stderr).contains("within 0.5 s"),
        "{}",
        text(&out.stderr)
    );
    let dir = empty_dir("silent");
    std::fs::write(dir.join("one.trace"), "R 1300/0/3/0 i => 17\n").unwrap();
    let out = addipos(&["replay", "--timeout", "0.5", "--server", &addr, s(&dir)]);
    assert_unreachable(&out);
}
