//! Run-time errors name the column of the word or statement that caused
//! them, as parse errors do.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use nc::run::{run_program, Located, Report, RunError, RunErrorKind, WarningKind};
use nc::{parse_program, NcError};
use uoi::AccessError;

/// Runs `text` on the engine; the error that stopped it and the report.
fn run(text: &str) -> (Option<RunError>, Report) {
    let (blocks, errors) = parse_program(text);
    assert!(errors.is_empty(), "{errors:?}");
    let mut engine = support::Engine::with_capacity(100_000);
    let mut report = Report::default();
    let e = run_program(&blocks, &mut engine, &mut report).err();
    (e, report)
}

fn stop(text: &str) -> RunError {
    run(text).0.expect("the run stops with an error")
}

/// Line, block number and column of what a run reports.
fn at<K>(e: &Located<K>) -> (usize, Option<u32>, usize) {
    let at = e.location.expect("a place in the program");
    (at.line, at.block_number, at.column)
}

fn at_parse(e: &NcError) -> (usize, Option<u32>, usize) {
    (e.line, e.block_number, e.column)
}

#[test]
fn unset_p_parameter_in_an_axis_word() {
    let e = stop("N5 G1 X1\nN7 G1 X10 Y[P3 * 2]\n");
    let name = "P3".to_string();
    assert_eq!(e.kind, RunErrorKind::Unset { name });
    assert_eq!(at(&e), (2, Some(7), 11));
    let text = "line 2, block N7, column 11: P3 is read before it was set";
    assert_eq!(e.to_string(), text);
}

#[test]
fn unset_variable_in_an_assignment_after_other_words() {
    let e = stop("N8 G1 X1 R2 = V.P.NOPE + 1\n");
    let name = "V.P.NOPE".to_string();
    assert_eq!(e.kind, RunErrorKind::Unset { name });
    assert_eq!(at(&e), (1, Some(8), 10));
}

#[test]
fn a_write_the_controller_refuses() {
    // ACC_WEIGHT is 1..100: the engine answers Range to 500.
    let e = stop("R1 = 500\nN10 G17 G1 X5 #OTC [ACC_WEIGHT=R1]\n");
    let RunErrorKind::Refused { request, error } = &e.kind else {
        panic!("{e:?}")
    };
    assert_eq!(*error, AccessError::Range);
    assert_eq!(request.to_string(), "W 1300/3/1/6 i 500");
    assert_eq!(at(&e), (2, Some(10), 15));
    let text = "line 2, block N10, column 15: `W 1300/3/1/6 i 500`: the controller answered Range";
    assert_eq!(e.to_string(), text);
}

#[test]
fn a_motion_the_controller_refuses() {
    let e = stop("N1 G90 F100\nN2 G1 Y1 X[2000000000]\n");
    let RunErrorKind::Refused { error, .. } = &e.kind else {
        panic!("{e:?}")
    };
    assert_eq!(*error, AccessError::Range);
    assert_eq!(at(&e), (2, Some(2), 7));
}

#[test]
fn g141_is_refused_at_its_word() {
    let e = stop("N9 G1 G141 X1\n");
    assert_eq!(e.kind, RunErrorKind::ContourMasking);
    assert_eq!(at(&e), (1, Some(9), 7));
}

#[test]
fn a_loop_that_never_ends_at_its_statement() {
    let e = stop("N3 $FOR P1 = 1, 5, 0\n$ENDFOR\n");
    assert_eq!(e.kind, RunErrorKind::ForStepZero);
    assert_eq!(at(&e), (1, Some(3), 4));
}

#[test]
fn a_d_word_out_of_range_and_warnings_at_their_words() {
    let e = stop("N4 G1 X1 D300\n");
    assert_eq!(e.kind, RunErrorKind::DataSet { d: 300 });
    assert_eq!(at(&e), (1, Some(4), 10));
    // A mode run as G138 is told at the selection made under it.
    let (e, report) = run("N1 G17 G139 G41\n");
    assert!(e.is_none(), "{e:?}");
    let word = "G139";
    assert_eq!(report.warnings[0].kind, WarningKind::SelectionRule { word });
    assert_eq!(at(&report.warnings[0]), (1, Some(1), 13));
}

#[test]
fn an_otc_fault_at_its_command() {
    // OTC switched on without a grinding tool: P-ERR-21391, the run goes on.
    let (e, report) = run("N1 G17 G1 X1\nN2 X2 #OTC ON [RADIUS]\n");
    assert!(e.is_none(), "{e:?}");
    let fault = report.faults.first().expect("the OTC type check fires");
    let RunErrorKind::Otc { bit, name } = fault.kind else {
        panic!("{fault:?}")
    };
    assert_eq!(bit, 1);
    assert!(name.contains("P-ERR-21391"), "{fault}");
    assert_eq!(at(fault), (2, Some(2), 7));
}

#[test]
fn a_faulted_group_names_its_error_bits() {
    // A full circle whose end is not on it: CenterError at N3, whose
    // profile raised it (found when N4 is answered State).
    let text = "N1 G17 G1 X0 Y0\nN2 G41 X1\nN3 G2 X10 Y0 I3 J0\nN4 G1 X20\nN5 G40 X30\n";
    let e = stop(text);
    let RunErrorKind::CorrectionFault { bits } = &e.kind else {
        panic!("{e:?}")
    };
    assert!(bits.iter().any(|b| b == "CenterError"), "{e}");
    assert_eq!(at(&e), (3, Some(3), 7));
    assert!(
        e.to_string()
            .contains("faulted on this block's profile (ERROR: "),
        "{e}"
    );
}

#[test]
fn a_control_statement_beside_words_is_a_parse_error_at_the_second_word() {
    // The $IF line is in error, so its $ENDIF has no opening statement.
    let (_, errors) = parse_program("N1 $IF 1 G1 X1\nN2 G1 X1 G77\n$ENDIF\n");
    assert_eq!(errors.len(), 3, "{errors:?}");
    assert!(errors[0].message.contains("stand alone"), "{}", errors[0]);
    assert_eq!(at_parse(&errors[0]), (1, Some(1), 10));
}
