//! `replay --junit FILE`: the results of a replay as JUnit XML, one test
//! case per trace, the format CI dashboards read (decision 310).

use std::io::Write;

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use quick_xml::Writer;

/// How one trace's replay ended, as a test case.
#[derive(Debug, Clone, Default)]
pub struct CaseResult {
    /// The trace file, as named on the command line or found in a folder.
    pub file: String,
    /// Seconds the replay took.
    pub secs: f64,
    /// Requests replayed.
    pub steps: usize,
    /// Mismatches found (all of them, shown or not).
    pub mismatches: usize,
    /// The mismatch lines shown (the first `--max-reports`).
    pub shown: Vec<String>,
    /// The trace could not be read, parsed to its end, or set up on the
    /// server: a JUnit `error`, not a `failure`.
    pub error: Option<String>,
}

impl CaseResult {
    /// Whether the trace passed.
    pub fn passed(&self) -> bool {
        self.mismatches == 0 && self.error.is_none()
    }

    /// The body of a failure: the lines shown, and how many more there were.
    fn failure_text(&self) -> String {
        let mut text = self.shown.join("\n");
        let more = self.mismatches.saturating_sub(self.shown.len());
        if more > 0 {
            text.push_str(&format!("\n... and {more} more mismatches"));
        }
        text
    }
}

/// Writes the JUnit XML of `cases` (suite `name`) to `out`.
pub fn write_junit(out: impl Write, name: &str, cases: &[CaseResult]) -> std::io::Result<()> {
    let mut w = Writer::new_with_indent(out, b' ', 2);
    let failures = cases
        .iter()
        .filter(|c| c.error.is_none() && c.mismatches > 0)
        .count();
    let errors = cases.iter().filter(|c| c.error.is_some()).count();
    let time: f64 = cases.iter().map(|c| c.secs).sum();
    let counts = [
        ("tests", cases.len().to_string()),
        ("failures", failures.to_string()),
        ("errors", errors.to_string()),
        ("skipped", "0".to_string()),
        ("time", format!("{time:.3}")),
    ];
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let mut suites = BytesStart::new("testsuites");
    suites.push_attribute(("name", name));
    // The schema CI tools read has no `skipped` on `testsuites`.
    let totals = counts.iter().filter(|(k, _)| *k != "skipped");
    suites.extend_attributes(totals.map(|(k, v)| (*k, v.as_str())));
    w.write_event(Event::Start(suites))?;
    let mut suite = BytesStart::new("testsuite");
    suite.push_attribute(("name", name));
    suite.extend_attributes(counts.iter().map(|(k, v)| (*k, v.as_str())));
    w.write_event(Event::Start(suite))?;
    for c in cases {
        write_case(&mut w, c)?;
    }
    w.write_event(Event::End(BytesEnd::new("testsuite")))?;
    w.write_event(Event::End(BytesEnd::new("testsuites")))?;
    Ok(())
}

/// One `testcase`, with its `failure` or `error` if it did not pass.
fn write_case<W: Write>(w: &mut Writer<W>, c: &CaseResult) -> std::io::Result<()> {
    let mut case = BytesStart::new("testcase");
    case.push_attribute(("name", c.file.as_str()));
    case.push_attribute(("classname", "addipos.replay"));
    case.push_attribute(("time", format!("{:.3}", c.secs).as_str()));
    case.push_attribute(("assertions", c.steps.to_string().as_str()));
    if c.passed() {
        return w.write_event(Event::Empty(case));
    }
    w.write_event(Event::Start(case))?;
    let (tag, message, kind, text) = match &c.error {
        Some(e) => ("error", e.clone(), "TraceError", c.failure_text()),
        None => {
            let first = c.shown.first().cloned().unwrap_or_default();
            let message = format!("{} mismatches; first: {first}", c.mismatches);
            ("failure", message, "Mismatch", c.failure_text())
        }
    };
    let mut el = BytesStart::new(tag);
    el.push_attribute(("message", message.as_str()));
    el.push_attribute(("type", kind));
    w.write_event(Event::Start(el))?;
    w.write_event(Event::Text(BytesText::new(&text)))?;
    w.write_event(Event::End(BytesEnd::new(tag)))?;
    w.write_event(Event::End(BytesEnd::new("testcase")))
}
