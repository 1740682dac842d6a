//! `addipos replay --junit` and the terminal with what CI brings: control
//! characters in a trace's content and file name, traces without a
//! request, a report path that cannot be written, empty shards, suites
//! of several shards, and a trace named twice.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::Path;
use std::process::{Command, Output};

fn addipos(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(args)
        .output()
        .expect("run addipos")
}

fn os(s: &str) -> &std::ffi::OsStr {
    std::ffi::OsStr::new(s)
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The `testsuite` element of a report, parsed (the report must be
/// well-formed XML 1.0).
fn suite_of(xml: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse(xml).unwrap_or_else(|e| panic!("not well-formed: {e}\n{xml:?}"))
}

fn suite<'a>(doc: &'a roxmltree::Document<'a>) -> roxmltree::Node<'a, 'a> {
    doc.root_element()
        .children()
        .find(|c| c.has_tag_name("testsuite"))
        .unwrap()
}

/// No control character but the line break in `out`.
fn no_controls(out: &[u8]) -> bool {
    let s = text(out);
    !s.chars()
        .any(|c| c != '\n' && (c.is_control() || c == '\u{1b}'))
}

#[cfg(unix)]
#[test]
fn control_characters_are_escaped_in_the_xml_and_on_the_terminal() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    // A file name with SOH and ESC; content with STX, ESC and NUL.
    let name = std::ffi::OsStr::from_bytes(b"ctl\x01\x1b[31m.trace");
    let trace = dir.path().join(name);
    std::fs::write(&trace, b"R 1300/0/3/0 i => 18\n\x02FROB\x1b[2J\x00\n").unwrap();
    let report = dir.path().join("r.xml");
    let out = addipos(&[
        os("replay"),
        trace.as_os_str(),
        os("--junit"),
        report.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    assert!(no_controls(&out.stdout), "{:?}", text(&out.stdout));
    assert!(no_controls(&out.stderr), "{:?}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains(r"ctl\x01\x1b[31m.trace"),
        "{:?}",
        text(&out.stdout)
    );
    let xml = std::fs::read_to_string(&report).unwrap();
    let doc = suite_of(&xml);
    let case = suite(&doc)
        .children()
        .find(|c| c.has_tag_name("testcase"))
        .unwrap();
    assert!(case.attribute("name").unwrap().contains(r"ctl\x01\x1b[31m"));
    let error = case.children().find(|c| c.has_tag_name("error")).unwrap();
    let message = error.attribute("message").unwrap();
    assert!(message.contains(r"\x02FROB\x1b[2J\x00"), "{message}");
}

#[test]
fn a_trace_without_a_request_fails_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty.trace");
    std::fs::write(&empty, "").unwrap();
    let comments = dir.path().join("comments.trace");
    std::fs::write(&comments, "@name cut short\n# nothing else\n").unwrap();
    let report = dir.path().join("r.xml");
    let out = addipos(&[
        os("replay"),
        empty.as_os_str(),
        comments.as_os_str(),
        os("--junit"),
        report.as_os_str(),
    ]);
    let said = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{said}");
    assert!(said.contains("0 passed, 2 failed"), "{said}");
    assert!(said.contains("empty.trace: no request"), "{said}");
    let xml = std::fs::read_to_string(&report).unwrap();
    let doc = suite_of(&xml);
    let s = suite(&doc);
    assert_eq!(s.attribute("failures"), Some("2"), "{xml}");
    for case in s.children().filter(|c| c.has_tag_name("testcase")) {
        let failure = case.children().find(|c| c.has_tag_name("failure"));
        let message = failure.and_then(|f| f.attribute("message")).unwrap_or("");
        assert!(message.contains("no request"), "{xml}");
    }
}

#[test]
fn an_unwritable_report_is_refused_before_the_replay() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("a.trace");
    std::fs::write(&trace, "R 1300/0/3/0 i => 17\n").unwrap();
    let report = dir.path().join("no-such-folder").join("r.xml");
    let out = addipos(&[
        os("replay"),
        trace.as_os_str(),
        os("--junit"),
        report.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("no-such-folder"),
        "{}",
        text(&out.stderr)
    );
    assert!(
        !text(&out.stdout).contains("passed"),
        "nothing was replayed: {}",
        text(&out.stdout)
    );
}

/// `replay --shard K/N --junit` of `traces`; the report's text.
fn shard_report(dir: &Path, shard: &str, traces: &[&Path]) -> (Output, String) {
    let report = dir.join(format!("r-{}.xml", shard.replace('/', "-")));
    let mut args = vec![os("replay"), os("--shard"), os(shard)];
    args.extend(traces.iter().map(|t| t.as_os_str()));
    args.extend([os("--junit"), report.as_os_str()]);
    let out = addipos(&args);
    (out, std::fs::read_to_string(&report).unwrap_or_default())
}

#[test]
fn shards_name_their_suites_and_an_empty_one_has_no_negative_time() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.trace");
    let b = dir.path().join("b.trace");
    std::fs::write(&a, "R 1300/0/3/0 i => 17\n").unwrap();
    std::fs::write(&b, "R 1300/0/3/0 i => 17\n").unwrap();
    let mut names = Vec::new();
    for k in 1..=3 {
        let (out, xml) = shard_report(dir.path(), &format!("{k}/3"), &[&a, &b]);
        assert!(out.status.success(), "{}", text(&out.stdout));
        assert!(!xml.contains("\"-0"), "{xml}");
        let doc = suite_of(&xml);
        let s = suite(&doc);
        names.push(s.attribute("name").unwrap().to_owned());
        assert!(
            s.attribute("name").unwrap().contains(&format!("{k}/3")),
            "{xml}"
        );
        let stamp = s.attribute("timestamp").expect("timestamp");
        assert_eq!(stamp.len(), "2026-01-01T00:00:00".len(), "{stamp}");
        assert!(!s.attribute("hostname").expect("hostname").is_empty());
    }
    names.sort();
    names.dedup();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn a_trace_named_twice_counts_once() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.trace");
    std::fs::write(&a, "R 1300/0/3/0 i => 17\n").unwrap();
    let again = dir.path().join(".").join("a.trace");
    let out = addipos(&[
        os("replay"),
        a.as_os_str(),
        again.as_os_str(),
        dir.path().as_os_str(),
    ]);
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}");
    assert!(said.contains("1 passed, 0 failed"), "{said}");
}

#[test]
fn the_trace_format_lists_every_error_name() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/trace-format.md"))
        .unwrap();
    let start = doc.find("Error names are").expect("the error-name list");
    let list = &doc[start..start + doc[start..].find("\n\n").unwrap()];
    for e in uoi::AccessError::ALL {
        assert!(
            list.contains(&format!("`{}`", e.name())),
            "docs/trace-format.md does not list `{}`: {list}",
            e.name()
        );
    }
}
