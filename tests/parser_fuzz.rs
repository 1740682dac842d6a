//! Random input to the trace parser: never a panic, and every error names
//! the line it came from.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use proptest::prelude::*;
use trace::parse_trace;

/// Integers at the limits of i32, u32, i64 and u64, with signs in every
/// position.
const EDGES: &[&str] = &[
    "2147483647",
    "-2147483648",
    "2147483648",
    "-2147483649",
    "0x7fffffff",
    "0x80000000",
    "-0x80000000",
    "-0x80000001",
    "0xffffffff",
    "-0xffffffff",
    "0x100000000",
    "9223372036854775807",
    "-9223372036854775808",
    "-9223372036854775809",
    "18446744073709551616",
    "0x7fffffffffffffff",
    "0x8000000000000000",
    "-0x8000000000000000",
    "-0x-8000000000000000",
    "0x-8000000000000000",
    "0xffffffffffffffff",
    "-0xffffffffffffffff",
    "0x10000000000000000",
    "-0x-1",
    "0x+1f",
    "+0x+1f",
    "--1",
    "+-1",
];

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
        // Signs before and after `0x`, and values at and past the i32 and
        // i64 limits.
        "[+-]{0,2}(0[xX])?[+-]{0,2}[0-9a-fA-F]{0,20}",
        prop::sample::select(EDGES.to_vec()).prop_map(str::to_string),
        "\\PC{0,8}",
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::collection::vec(token(), 0..7).prop_map(|t| t.join(" ")),
        "\\PC{0,40}",
    ]
}

/// The fuzz tests are only worth their time with overflow checks on (the
/// test profile's default; no profile in Cargo.toml may turn them off).
#[test]
fn overflow_checks_are_on() {
    let max = std::hint::black_box(i32::MAX);
    let add = std::panic::catch_unwind(|| max + std::hint::black_box(1));
    assert!(add.is_err(), "overflow checks are off in the test profile");
}

#[test]
fn integer_edges_in_every_position_never_panic() {
    for v in EDGES {
        for line in [
            format!("W 1300/1/1/8 i {v}"),
            format!("R 1300/1/1/8 i => {v}"),
            format!("SSF X {v}"),
            format!("EXEC {v}"),
            format!("QUEUE => {v}"),
            format!("LIN X{v}"),
        ] {
            let text = format!("{line}\n");
            if let Err(e) = parse_trace("edge.trace", &text) {
                assert!(e.to_string().starts_with("edge.trace:1: "), "{e}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    #[test]
    fn random_lines_never_panic(lines in prop::collection::vec(line(), 1..8)) {
        let text = lines.join("\n");
        match parse_trace("fuzz.trace", &text) {
            Ok(trace) => {
                // A parsed trace must also replay without a panic.
                let _ = trace::replay(&trace);
            }
            Err(e) => {
                prop_assert!(e.line >= 1 && e.line <= lines.len());
                let prefix = format!("fuzz.trace:{}: ", e.line);
                prop_assert!(e.to_string().starts_with(&prefix));
            }
        }
    }
}
