//! Errors: where (line, block number, column) and that all are reported.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use nc::{parse_program, NcError};

fn errors(text: &str) -> Vec<NcError> {
    parse_program(text).1
}

fn only(text: &str) -> NcError {
    let mut e = errors(text);
    assert_eq!(e.len(), 1, "{text}: {e:?}");
    e.remove(0)
}

fn at(e: &NcError) -> (usize, Option<u32>, usize) {
    (e.line, e.block_number, e.column)
}

#[test]
fn unknown_g_code_with_line_block_and_column() {
    let e = only("N1 X0\nN20 G1 G240 X5");
    assert_eq!(at(&e), (2, Some(20), 8));
    assert!(e.message.contains("`G240`"), "{}", e.message);
    assert_eq!(
        e.to_string(),
        format!("line 2, block N20, column 8: {}", e.message)
    );
}

#[test]
fn unknown_address_and_malformed_values() {
    assert_eq!(at(&only("N5 X1 Q7")), (1, Some(5), 7));
    assert_eq!(at(&only("X1.2.3")), (1, None, 5));
    assert_eq!(at(&only("N7 Y")), (1, Some(7), 4));
    assert_eq!(at(&only("N7 X[1+]")), (1, Some(7), 4));
    assert_eq!(at(&only("N7 G")), (1, Some(7), 4));
    assert_eq!(at(&only("N7 M")), (1, Some(7), 4));
    assert_eq!(at(&only("Nx X1")), (1, None, 1));
    assert_eq!(at(&only("N1 X1 N2")), (1, Some(1), 7));
}

#[test]
fn typographic_dash_of_the_manual_is_refused_with_a_hint() {
    let e = only("N150 V.G.WZ_AKT.R = V.G.WZ_AKT.R \u{2013} V.P.VERSCHLEISS");
    assert_eq!(at(&e), (1, Some(150), 6));
    assert!(e.message.contains("write '-'"), "{}", e.message);
}

#[test]
fn malformed_commands_and_statements() {
    for bad in [
        "#OTC",
        "#OTC ON [RADIUS",
        "#OTC ON [GRIND]",
        "#OTC [ACC_WEIGHT=0]",
        "#set ToolParam(1; 2; 3)",
        "#get ToolParam(1; 2; 3)#",
        "#KIN 4",
        "#TRAFO",
        "#FOO",
        "$FOR = 1, 2",
        "$LOOP",
        "V.Q.X = 1",
        "(no end",
    ] {
        let e = only(bad);
        assert_eq!((e.line, e.column), (1, 1), "{bad}: {e:?}");
    }
}

/// `R` with a number and no `=` is an arc's radius, so `R1 10` is the
/// radius 1 and an unknown word `10`.
#[test]
fn an_r_word_without_equals_is_a_radius() {
    let e = only("R1 10");
    assert_eq!((e.line, e.column), (1, 4), "{e:?}");
    assert!(errors("G2 X10 R5\nR5=2\nR7 = R5\nG3 X0 R-5\nG3 X1 R[R5*2]").is_empty());
}

/// A new user's `#OTC ON [RADIUS, FOO]` was told a `]` was missing; the
/// unknown option is named, with the options there are.
#[test]
fn an_unknown_otc_option_is_named_after_a_separator() {
    for bad in [
        "#OTC ON [RADIUS, FOO]",
        "#OTC ON [RADIUS FOO]",
        "#OTC [FOO]",
    ] {
        let e = only(bad);
        assert!(
            e.message.contains("an #OTC option (RADIUS"),
            "{bad}: {}",
            e.message
        );
        assert!(!e.message.contains("']'"), "{bad}: {}", e.message);
    }
    assert!(errors("#OTC ON [RADIUS, CONT]").is_empty());
    assert!(errors("#OTC ON [RADIUS CONT WEAR_CONST=5]").is_empty());
}

/// A new user's `R1 = SIN[30]` was told the value was malformed; the
/// message says that a function takes round brackets.
#[test]
fn a_function_with_square_brackets_is_told_the_round_ones() {
    let e = only("R1 = SIN[30]");
    assert!(e.message.contains("SIN(30), not SIN[30]"), "{}", e.message);
    assert!(errors("R1 = SIN(30) + COS[0] * 0").len() == 1);
    assert!(errors("R1 = SIN(30) + [2 * 3]").is_empty());
}

#[test]
fn header_without_name() {
    assert_eq!(at(&only("%")), (1, None, 2));
}

#[test]
fn several_errors_are_all_reported_and_good_blocks_kept() {
    let text = "N1 G1 X0\nN2 Q1\nN3 X1\nN4 G999\nN5 #OTC ON [RADIUS\nN6 Y2\n";
    let (blocks, errors) = parse_program(text);
    let numbers: Vec<_> = blocks.iter().map(|b| b.number).collect();
    assert_eq!(numbers, [Some(1), Some(3), Some(6)]);
    let lines: Vec<_> = errors.iter().map(|e| (e.line, e.block_number)).collect();
    assert_eq!(lines, [(2, Some(2)), (4, Some(4)), (5, Some(5))]);
}

#[test]
fn unpaired_control_statements() {
    let e = errors("N1 $ENDFOR\nN2 $FOR P1=0,1,1\nN3 $IF R1\nN4 $ENDWHILE\n");
    let got: Vec<_> = e.iter().map(|e| (e.line, e.message.as_str())).collect();
    assert_eq!(
        got,
        [
            (1, "$ENDFOR without its opening statement"),
            (4, "$ENDWHILE without its opening statement"),
            (2, "$FOR without $ENDFOR"),
            (3, "$IF without $ENDIF"),
        ]
    );
}

#[test]
fn invalid_utf8_and_nbsp_are_errors() {
    let (_, e) = (
        0,
        nc::Blocks::new(&b"N1 X1\nN2 \xff\n"[..]).collect::<Vec<_>>(),
    );
    assert!(e[0].is_ok());
    assert_eq!(e[1].as_ref().unwrap_err().line, 2);
    assert_eq!(at(&only("N200 G40 X300\u{a0}\u{a0}")), (1, Some(200), 14));
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let deep = format!("R1 = {}1{}", "(".repeat(100_000), ")".repeat(100_000));
    assert_eq!(errors(&deep).len(), 1);
    let signs = format!("R1 = {}1", "- ".repeat(100_000));
    assert_eq!(errors(&signs).len(), 1);
}

#[test]
fn control_structures_nest_at_most_so_deep() {
    let deep = nc::MAX_CONTROL_NESTING + 3;
    let text = "N1 $IF 1\n".repeat(deep);
    let e = errors(&text);
    // The three too deep, then one error per structure left open.
    assert_eq!(e.len(), 3 + nc::MAX_CONTROL_NESTING, "{:?}", &e[..4]);
    let first = &e[0];
    assert_eq!(first.line, nc::MAX_CONTROL_NESTING + 1);
    assert!(first.message.contains("nest deeper"), "{}", first.message);
    let ok = "N1 $IF 1\n".repeat(nc::MAX_CONTROL_NESTING)
        + &"N2 $ENDIF\n".repeat(nc::MAX_CONTROL_NESTING);
    assert!(errors(&ok).is_empty());
}

#[test]
fn columns_on_a_line_with_umlauts_count_characters() {
    // The words' columns are asked for left to right, the error's last.
    let (blocks, _) = parse_program("(äöü) X1 Y2 Z3\n");
    let columns: Vec<usize> = (0..3).map(|k| blocks[0].column(k)).collect();
    assert_eq!(columns, [7, 10, 13]);
    assert_eq!(at(&only("(äöü) X1 Y2 Q3")), (1, None, 13));
    assert_eq!(at(&only("(ä) X1 (ö) Y2 (ü) Q3")), (1, None, 19));
}
