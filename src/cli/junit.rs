//! `replay --junit FILE`: the results of a replay as JUnit XML, one test
//! case per trace, the format CI dashboards read (decision 310).

use std::io::Write;

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use quick_xml::Writer;
use trace::printable;

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

/// What a trace without a request fails with (decision 412).
pub const NO_REQUEST: &str =
    "no request in the trace: an empty or cut-short trace checks nothing, so it fails";

impl CaseResult {
    /// Whether the trace passed: read to its end, at least one request
    /// replayed, no mismatch.
    pub fn passed(&self) -> bool {
        self.mismatches == 0 && self.error.is_none() && self.steps > 0
    }

    /// Whether the trace was read to its end without finding a request.
    pub fn no_request(&self) -> bool {
        self.error.is_none() && self.steps == 0
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

/// The suite of a report: its name (with the shard, if one), when it
/// ran and where.
#[derive(Debug, Clone)]
pub struct Suite {
    /// `name` of the suite (and of `testsuites`).
    pub name: String,
    /// The start, UTC in ISO 8601 without a zone, as
    /// the schema asks (`2026-11-28T02:40:00`).
    pub timestamp: String,
    /// The machine's host name.
    pub hostname: String,
}

/// Seconds as a JUnit time: three decimals, never negative (a sum of no
/// times is -0 in floating point).
fn seconds(t: f64) -> String {
    format!("{:.3}", t.max(0.0) + 0.0)
}

/// Writes the JUnit XML of `cases` (suite `suite`) to `out`. Every text
/// from a trace (file names, mismatches, errors) has its control
/// characters escaped, so the file is well-formed XML 1.0.
pub fn write_junit(out: impl Write, suite: &Suite, cases: &[CaseResult]) -> std::io::Result<()> {
    let mut w = Writer::new_with_indent(out, b' ', 2);
    let failures = cases
        .iter()
        .filter(|c| c.error.is_none() && !c.passed())
        .count();
    let errors = cases.iter().filter(|c| c.error.is_some()).count();
    let time = cases.iter().fold(0.0, |t, c| t + c.secs);
    let counts = [
        ("tests", cases.len().to_string()),
        ("failures", failures.to_string()),
        ("errors", errors.to_string()),
        ("skipped", "0".to_string()),
        ("time", seconds(time)),
    ];
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let name = printable(&suite.name);
    let mut suites = BytesStart::new("testsuites");
    suites.push_attribute(("name", name.as_ref()));
    // The schema CI tools read has no `skipped` on `testsuites`.
    let totals = counts.iter().filter(|(k, _)| *k != "skipped");
    suites.extend_attributes(totals.map(|(k, v)| (*k, v.as_str())));
    w.write_event(Event::Start(suites))?;
    let mut el = BytesStart::new("testsuite");
    el.push_attribute(("name", name.as_ref()));
    el.extend_attributes(counts.iter().map(|(k, v)| (*k, v.as_str())));
    el.push_attribute(("timestamp", printable(&suite.timestamp).as_ref()));
    el.push_attribute(("hostname", printable(&suite.hostname).as_ref()));
    w.write_event(Event::Start(el))?;
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
    case.push_attribute(("name", printable(&c.file).as_ref()));
    case.push_attribute(("classname", "addipos.replay"));
    case.push_attribute(("time", seconds(c.secs).as_str()));
    case.push_attribute(("assertions", c.steps.to_string().as_str()));
    if c.passed() {
        return w.write_event(Event::Empty(case));
    }
    w.write_event(Event::Start(case))?;
    let (tag, message, kind, text) = match &c.error {
        Some(e) => ("error", e.clone(), "TraceError", c.failure_text()),
        None if c.no_request() => ("failure", NO_REQUEST.into(), "NoRequest", String::new()),
        None => {
            let first = c.shown.first().cloned().unwrap_or_default();
            let message = format!("{} mismatches; first: {first}", c.mismatches);
            ("failure", message, "Mismatch", c.failure_text())
        }
    };
    let mut el = BytesStart::new(tag);
    el.push_attribute(("message", printable(&message).as_ref()));
    el.push_attribute(("type", kind));
    w.write_event(Event::Start(el))?;
    w.write_event(Event::Text(BytesText::new(&printable(&text))))?;
    w.write_event(Event::End(BytesEnd::new(tag)))?;
    w.write_event(Event::End(BytesEnd::new("testcase")))
}
