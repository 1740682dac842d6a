//! Run-time errors name the column of the word or statement that caused
//! them, as parse errors do.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use nc::run::{run_program, Report};
use nc::{parse_program, NcError};

/// Runs `text` on the engine; the error that stopped it and the report.
fn run(text: &str) -> (Option<NcError>, Report) {
    let (blocks, errors) = parse_program(text);
    assert!(errors.is_empty(), "{errors:?}");
    let mut engine = support::Engine::with_capacity(100_000);
    let mut report = Report::default();
    let e = run_program(&blocks, &mut engine, &mut report).err();
    (e, report)
}

fn stop(text: &str) -> NcError {
    run(text).0.expect("the run stops with an error")
}

fn at(e: &NcError) -> (usize, Option<u32>, usize) {
    (e.line, e.block_number, e.column)
}

#[test]
fn unset_p_parameter_in_an_axis_word() {
    let e = stop("N5 G1 X1\nN7 G1 X10 Y[P3 * 2]\n");
    assert!(e.message.contains("P3"), "{e}");
    assert_eq!(at(&e), (2, Some(7), 11));
}

#[test]
fn unset_variable_in_an_assignment_after_other_words() {
    let e = stop("N8 G1 X1 R2 = V.P.NOPE + 1\n");
    assert!(e.message.contains("V.P.NOPE"), "{e}");
    assert_eq!(at(&e), (1, Some(8), 10));
}

#[test]
fn a_write_the_controller_refuses() {
    // ACC_WEIGHT is 1..100: the engine answers Range to 500.
    let e = stop("R1 = 500\nN10 G17 G1 X5 #OTC [ACC_WEIGHT=R1]\n");
    assert!(e.message.contains("Range"), "{e}");
    assert_eq!(at(&e), (2, Some(10), 15));
}

#[test]
fn a_motion_the_controller_refuses() {
    let e = stop("N1 G90 F100\nN2 G1 Y1 X[2000000000]\n");
    assert!(e.message.contains("Range"), "{e}");
    assert_eq!(at(&e), (2, Some(2), 7));
}

#[test]
fn g141_is_refused_at_its_word() {
    let e = stop("N9 G1 G141 X1\n");
    assert!(e.message.contains("G141"), "{e}");
    assert_eq!(at(&e), (1, Some(9), 7));
}

#[test]
fn a_loop_that_never_ends_at_its_statement() {
    let e = stop("N3 $FOR P1 = 1, 5, 0\n$ENDFOR\n");
    assert!(e.message.contains("step 0"), "{e}");
    assert_eq!(at(&e), (1, Some(3), 4));
}

#[test]
fn a_d_word_out_of_range_and_warnings_at_their_words() {
    let e = stop("N4 G1 X1 D300\n");
    assert_eq!(at(&e), (1, Some(4), 10));
    let (e, report) = run("N1 G17 G139 G41\n");
    assert!(e.is_none(), "{e:?}");
    assert_eq!(at(&report.warnings[0]), (1, Some(1), 8));
}

#[test]
fn an_otc_fault_at_its_command() {
    // OTC switched on without a grinding tool: P-ERR-21391, the run goes on.
    let (e, report) = run("N1 G17 G1 X1\nN2 X2 #OTC ON [RADIUS]\n");
    assert!(e.is_none(), "{e:?}");
    let fault = report.faults.first().expect("the OTC type check fires");
    assert!(fault.message.contains("21391"), "{fault}");
    assert_eq!(at(fault), (2, Some(2), 7));
}

#[test]
fn a_control_statement_beside_words_is_a_parse_error_at_the_second_word() {
    // The $IF line is in error, so its $ENDIF has no opening statement.
    let (_, errors) = parse_program("N1 $IF 1 G1 X1\nN2 G1 X1 G236\n$ENDIF\n");
    assert_eq!(errors.len(), 3, "{errors:?}");
    assert!(errors[0].message.contains("stand alone"), "{}", errors[0]);
    assert_eq!(at(&errors[0]), (1, Some(1), 10));
}
