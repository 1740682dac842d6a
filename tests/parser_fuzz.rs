//! Random input to the trace parser: never a panic, and every error names
//! the line it came from.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use addipos::trace::parse_trace;
use proptest::prelude::*;

/// Tokens that make random lines look like trace lines often enough to get
/// past the first checks.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("W".to_string()),
        Just("R".to_string()),
        Just("LIN".to_string()),
        Just("CIR".to_string()),
        Just("CW".to_string()),
        Just("JA".to_string()),
        Just("JS".to_string()),
        Just("SSF".to_string()),
        Just("EXEC".to_string()),
        Just("POS".to_string()),
        Just("QUEUE".to_string()),
        Just("=>".to_string()),
        Just("<".to_string()),
        Just("err".to_string()),
        Just("ok".to_string()),
        Just("@tol".to_string()),
        Just("@cycle".to_string()),
        Just("i".to_string()),
        Just("d".to_string()),
        "1300/[0-9]{1,6}/[0-9]{1,6}/[0-9]{1,6}",
        "[XYZABCUVIJKF]-?[0-9.e]{0,6}",
        "-?(0x)?[0-9a-f]{0,12}",
        "\\PC{0,8}",
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::collection::vec(token(), 0..7).prop_map(|t| t.join(" ")),
        "\\PC{0,40}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    #[test]
    fn random_lines_never_panic(lines in prop::collection::vec(line(), 1..8)) {
        let text = lines.join("\n");
        match parse_trace("fuzz.trace", &text) {
            Ok(trace) => {
                // A parsed trace must also replay without a panic.
                let _ = addipos::trace::replay(&trace);
            }
            Err(e) => {
                prop_assert!(e.line >= 1 && e.line <= lines.len());
                let prefix = format!("fuzz.trace:{}: ", e.line);
                prop_assert!(e.to_string().starts_with(&prefix));
            }
        }
    }
}
