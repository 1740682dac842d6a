//! The interpreter: blocks in, requests out, against a controller that
//! records what it is asked.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use nc::parse_program;
use nc::run::{
    run_program, At, Controller, Report, RunError, RunErrorKind, WarningKind, MAX_EXECUTED_BLOCKS,
};
use tc_request::{Reply, Request};
use uoi::Value;

/// Answers everything `ok` (reads: 0), keeps the requests as text.
#[derive(Default)]
struct Log(Vec<String>);

impl Controller for Log {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        self.0.push(req.to_string());
        match req {
            Request::Pos => Reply::Pos([0.0; 8]),
            Request::Read(_, uoi::ValueType::I32) => Reply::Value(Value::I32(0)),
            Request::Read(..) => Reply::Value(Value::F64(0.0)),
            _ => Reply::Ok,
        }
    }
}

fn run(text: &str) -> (Vec<String>, Report, Result<(), RunError>) {
    let (blocks, errors) = parse_program(text);
    assert!(errors.is_empty(), "{errors:?}");
    let mut log = Log::default();
    let mut report = Report::default();
    let r = run_program(&blocks, &mut log, &mut report);
    (log.0, report, r)
}

fn requests(text: &str) -> Vec<String> {
    let (log, _, r) = run(text);
    r.unwrap();
    log
}

#[test]
fn modal_motion_incremental_and_feed() {
    let log = requests("N1 G1 X10 Y5 F600\nN2 G91 X5\nN3 G0 Y-5\nN4 G90 G3 X0 Y0 I-7.5 J0\n");
    assert_eq!(
        log,
        [
            "POS",
            "LIN X10 Y5 F600",
            "LIN X15",
            "RAP Y0",
            "CIR CCW X0 Y0 I-7.5 J0",
            "EXEC"
        ]
    );
}

#[test]
fn plane_tool_trc_and_transitions_come_before_the_motion() {
    let text = "#set ToolParam(3; 4; 9)# #set ToolParam(3; 7; -0.5)#\n\
                #set ToolParam(3; 2; 100)#\n\
                N10 G18 D3 G25 G42 G1 X1 F100\nN20 G40 X2\nN30 G41 G26 X3\nN40 M30\nN50 X9\n";
    let log = requests(text);
    assert_eq!(
        log,
        [
            "POS",
            "W 1300/0/3/0 i 18",
            "W 1300/2/1/1 i 1",
            "W 1300/1/1/8 i 3",
            "W 1300/1/1/6 d 8.5",
            "W 1300/1/1/12 d 100",
            "W 1300/1/1/10 i 1",
            "W 1300/1/1/3 i 1",
            "LIN X1 F100",
            "W 1300/1/1/3 i 0",
            // After G40 and at the end: a fault of the last profile?
            "R 1300/1/1/1 i",
            "LIN X2",
            "W 1300/2/1/1 i 0",
            "W 1300/1/1/9 i 1",
            "W 1300/1/1/3 i 1",
            "LIN X3",
            "R 1300/1/1/1 i",
            "EXEC"
        ]
    );
}

#[test]
fn loops_conditions_and_variables() {
    let text = "R1 = 0\n$FOR P1 = 1, 3, 1\nR1 = R1 + P1\n$ENDFOR\n\
                $IF R1 == 6\nV.P.A = 1\n$ELSE\nV.P.A = 2\n$ENDIF\n\
                $WHILE V.P.A < 4\nV.P.A = V.P.A + 1\nG1 X[V.P.A * 10]\n$ENDWHILE\n";
    let log = requests(text);
    assert_eq!(log, ["POS", "LIN X20", "LIN X30", "LIN X40", "EXEC"]);
}

#[test]
fn dynamic_radius_and_otc_are_object_writes() {
    let text = "V.G.WZ_AKT.R = V.G.WZ_AKT.R - 0.01\n#OTC ON [RADIUS, CONT, WEAR_CONST=5, \
                ACC_WEIGHT=50]\n#OTC OFF\n";
    let log = requests(text);
    assert_eq!(
        log,
        [
            "POS",
            "R 1300/1/1/6 d",
            "W 1300/1/1/6 d -0.01",
            // Switching acts where the program stands on the path.
            "EXEC",
            "W 1300/3/1/2 i 0",
            "R 1300/3/1/7 i",
            "W 1300/3/1/3 i 1",
            "R 1300/3/1/7 i",
            "W 1300/3/1/4 d 5",
            "R 1300/3/1/7 i",
            "W 1300/3/1/6 i 50",
            "R 1300/3/1/7 i",
            "W 1300/3/1/1 i 1",
            "R 1300/3/1/7 i",
            "EXEC",
            "W 1300/3/1/1 i 0",
            "R 1300/3/1/7 i",
            "EXEC"
        ]
    );
}

#[test]
fn tool_param_get_reads_the_d_table() {
    let log = requests("#set ToolParam(10; 4; 2.5)#\n#get ToolParam(10; 4; R7)#\nG1 X[R7]\n");
    assert_eq!(log, ["POS", "LIN X2.5", "EXEC"]);
}

#[test]
fn unimplemented_constructs_are_errors_of_their_kind_with_their_block() {
    let unset = RunErrorKind::Unset {
        name: "V.P.NOPE".into(),
    };
    for (text, kind, what) in [
        ("N1 G1 X1\nN5 M3\n", RunErrorKind::MFunction(3), "M3"),
        ("N1 G141\n", RunErrorKind::ContourMasking, "G141"),
        ("N7 G1 X[V.P.NOPE]\n", unset, "V.P.NOPE"),
        ("N7 X1\n", RunErrorKind::NoMotionKind, "motion kind"),
        ("N7 G1 X1 I2\n", RunErrorKind::CentreWithoutArc, "G2 or G3"),
        (
            "N7 R1 = 1 / 0\n",
            RunErrorKind::DivisionByZero,
            "division by zero",
        ),
    ] {
        let (_, _, r) = run(text);
        let e = r.unwrap_err();
        assert_eq!(e.kind, kind, "{text}: {e}");
        assert!(e.to_string().contains(what), "{text}: {e}");
        let at = e.location.expect("a place");
        assert!(at.block_number.is_some(), "{text}: {e}");
    }
}

#[test]
fn a_chain_that_leaves_the_finite_numbers_on_the_way_is_an_error() {
    // (1e30)^11 / 1e30: the eleventh factor leaves the finite numbers.
    let big = format!("1{}", "0".repeat(30));
    let product = [big.as_str(); 11].join(" * ");
    let text = format!("N3 R1 = {product} / {big}\n");
    let (_, _, r) = run(&text);
    let e = r.unwrap_err();
    assert_eq!(e.kind, RunErrorKind::NotFinite, "{e}");
    assert_eq!(
        e.to_string(),
        "line 1, block N3, column 4: the expression has no finite value"
    );
}

#[test]
fn an_endless_loop_stops_at_the_bound() {
    let (log, _, r) = run("N5 $WHILE 1\nN6 R1 = R1 + 1\nN7 $ENDWHILE\n");
    let e = r.unwrap_err();
    let limit = MAX_EXECUTED_BLOCKS;
    assert_eq!(e.kind, RunErrorKind::TooManyBlocks { limit });
    assert!(e.to_string().contains(&limit.to_string()), "{e}");
    assert_eq!(log, ["POS"]);
}

#[test]
fn g139_and_g05_run_as_g138_with_a_warning() {
    let (_, report, r) = run("N1 G139 G41\nN2 G05 G40\nN3 T1\n");
    r.unwrap();
    assert_eq!(report.warnings.len(), 3);
    let kinds: Vec<&WarningKind> = report.warnings.iter().map(|w| &w.kind).collect();
    assert_eq!(
        kinds,
        [
            &WarningKind::SelectionRule { word: "G139" },
            &WarningKind::SelectionRule { word: "G05" },
            &WarningKind::ToolWord
        ]
    );
    let at = report.warnings[0].location.expect("a place");
    assert_eq!(at.block_number, Some(1));
}

#[test]
fn warnings_beyond_the_bound_are_counted_not_kept() {
    let extra = 7;
    let text = "N1 T1\n".repeat(nc::MAX_KEPT_ERRORS + extra);
    let (_, report, r) = run(&text);
    r.unwrap();
    assert_eq!(report.warnings.len(), nc::MAX_KEPT_ERRORS);
    assert_eq!(report.more_warnings, extra as u64);
}

#[test]
fn parse_errors_beyond_the_bound_are_counted_not_kept() {
    let extra = 5;
    let text = "N1 Q7\n".repeat(nc::MAX_KEPT_ERRORS + extra);
    let (kept, more) = nc::check_program_counted(text.as_bytes());
    assert_eq!(kept.len(), nc::MAX_KEPT_ERRORS);
    assert_eq!(more, extra as u64);
    assert_eq!(kept[0].line, 1);
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    const LINES: [&str; 24] = [
        "N1 G1 X10 Y5 F600",
        "G91 X-3 Y[R1*2]",
        "G90",
        "G2 X0 Y0 I5",
        "G3 I-5 J0",
        "G41",
        "G42 X1",
        "G40 X0",
        "G17",
        "G18",
        "G25",
        "G26",
        "D1",
        "D0",
        "D300",
        "#set ToolParam(1; 4; 10)#",
        "#get ToolParam(R1; 99; R2)#",
        "R1 = R1 / R3",
        "V.G.WZ_AKT.R = V.G.WZ_AKT.R - 0.01",
        "#OTC ON [RADIUS, WEAR_CONST=5, ACC_WEIGHT=1.5]",
        "#OTC OFF",
        "$FOR P1 = 0, 3, 1",
        "$ENDFOR",
        "M30",
    ];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Any mix of the constructs runs or stops with an error naming a
        /// line; it never panics.
        #[test]
        fn interpreter_never_panics(picks in proptest::collection::vec(0usize..LINES.len(), 0..40)) {
            let text: Vec<&str> = picks.iter().map(|&k| LINES[k]).collect();
            let (blocks, errors) = parse_program(&text.join("\n"));
            if errors.is_empty() {
                let mut log = Log::default();
                let mut report = Report::default();
                if let Err(e) = run_program(&blocks, &mut log, &mut report) {
                    prop_assert!(e.location.is_some_and(|at| at.line >= 1), "{e}");
                }
            }
        }
    }
}
