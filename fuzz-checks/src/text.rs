//! [`trace_line`](super::trace_line): the trace reader and the request
//! parser on any bytes.

use tc_request::text::parse_request;
use tc_request::Request;

use trace::TraceReader;

use crate::limits::MAX_TRACE_INPUT;

/// A request written back in trace syntax parses to the same request and
/// the same text; its wire form decodes to it too.
fn check_text_round_trip(req: &Request) {
    let text = req.to_string();
    let again = match parse_request(&text) {
        Ok(r) => r,
        Err(e) => panic!("`{text}`, written from {req:?}, does not parse: {e}"),
    };
    // Debug compares NaN words as equal; `==` would not.
    assert_eq!(format!("{again:?}"), format!("{req:?}"), "text `{text}`");
    assert_eq!(again.to_string(), text);
    let wire = Request::from_wire(&req.to_wire());
    assert_eq!(
        format!("{wire:?}"),
        format!("{:?}", Ok::<_, ()>(req)),
        "wire"
    );
}

/// The trace reader on any bytes as a file, and the request parser on
/// each line of it. Checks that nothing panics (invalid UTF-8 and long
/// lines included); the reader yields nothing after an error, and its
/// steps and errors name lines in order within the input; every request
/// that parses is written back (`Display`) to text that parses to the same
/// request, and its wire form decodes to it.
pub fn trace_line(data: &[u8]) {
    let data = &data[..data.len().min(MAX_TRACE_INPUT)];
    let lines = data.split(|b| *b == b'\n').count();
    match TraceReader::open("fuzz.trace", data) {
        Ok(reader) => {
            let mut last = 0;
            let mut ended = false;
            for item in reader {
                assert!(!ended, "an item after an error");
                let line = match item {
                    Ok(step) => {
                        check_text_round_trip(&step.request);
                        step.line
                    }
                    Err(e) => {
                        ended = true;
                        e.line
                    }
                };
                assert!(line > last && line <= lines, "line {line} after {last}");
                last = line;
            }
        }
        Err(e) => assert!(e.line >= 1 && e.line <= lines, "error line {}", e.line),
    }
    for line in data.split(|b| *b == b'\n') {
        if let Ok(Ok(req)) = std::str::from_utf8(line).map(parse_request) {
            check_text_round_trip(&req);
        }
    }
}
