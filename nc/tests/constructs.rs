//! One test per construct of the block model.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use nc::*;

fn one(line: &str) -> Block {
    let (mut blocks, errors) = parse_program(line);
    assert!(errors.is_empty(), "{line}: {errors:?}");
    assert_eq!(blocks.len(), 1, "{line}");
    blocks.remove(0)
}

fn num(n: f64) -> Expr {
    Expr::Number(n)
}

fn vg(path: &[&str]) -> Var {
    Var::V {
        scope: 'G',
        path: path
            .iter()
            .map(|n| Segment {
                name: n.to_string(),
                index: None,
            })
            .collect(),
    }
}

#[test]
fn block_number_g_codes_and_axes_without_spaces() {
    let b = one("N315 G1 G91X10 Y-5.5 Z.5");
    assert_eq!((b.line, b.number), (1, Some(315)));
    assert_eq!(
        b.items,
        vec![
            Item::G(GCode::Linear),
            Item::G(GCode::Incremental),
            Item::Axis(Axis::X, num(10.0)),
            Item::Axis(Axis::Y, num(-5.5)),
            Item::Axis(Axis::Z, num(0.5)),
        ]
    );
}

#[test]
fn every_listed_g_code_is_known() {
    let text =
        "G0 G00 G1 G2 G3 G05 G10 G11 G17 G18 G19 G25 G26 G40 G41 G42 G90 G91 G138 G139 G140 G141";
    assert_eq!(one(text).items.len(), 22);
}

#[test]
fn centre_feed_tool_words_and_m30() {
    let b = one("N90 G2 X10 Y10 I-15 J0 K1 F1000 D100 T1 M30");
    assert!(b.items.contains(&Item::Centre(CentreAxis::I, num(-15.0))));
    assert!(b.items.contains(&Item::Feed(num(1000.0))));
    assert!(b.items.contains(&Item::ToolData(num(100.0))));
    assert!(b.items.contains(&Item::Tool(num(1.0))));
    assert_eq!(b.items.last(), Some(&Item::M(30)));
}

#[test]
fn rotary_and_extra_axes() {
    let b = one("A1 B45 C2 U3 V4");
    let axes: Vec<Axis> = b
        .items
        .iter()
        .map(|i| match i {
            Item::Axis(a, _) => *a,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(axes, [Axis::A, Axis::B, Axis::C, Axis::U, Axis::V]);
}

#[test]
fn word_values_are_parameters_or_bracketed_expressions() {
    assert_eq!(parse_program("X R1").1.len(), 1, "a space splits the word");
    let b = one("XR1 Y-R2 Z[R1+2*3]");
    assert_eq!(b.items[0], Item::Axis(Axis::X, Expr::Var(Var::R(1))));
    assert_eq!(
        b.items[1],
        Item::Axis(Axis::Y, Expr::Neg(Box::new(Expr::Var(Var::R(2)))))
    );
    let product = Expr::Chain(Box::new(num(2.0)), Box::new([(BinOp::Mul, num(3.0))]));
    let sum = Expr::Chain(
        Box::new(Expr::Var(Var::R(1))),
        Box::new([(BinOp::Add, product)]),
    );
    assert_eq!(b.items[2], Item::Axis(Axis::Z, sum));
}

#[test]
fn assignments_of_r_p_and_v_variables() {
    let b = one("N30 R1=10 R2 = 4 P3=20.3 V.P.NAME = R1 V.G.WZ_AKT.R = 5");
    assert_eq!(b.items[0], Item::Assign(Var::R(1), num(10.0)));
    assert_eq!(b.items[1], Item::Assign(Var::R(2), num(4.0)));
    assert_eq!(b.items[2], Item::Assign(Var::P(3), num(20.3)));
    assert!(matches!(
        &b.items[3],
        Item::Assign(Var::V { scope: 'P', .. }, Expr::Var(Var::R(1)))
    ));
    assert_eq!(b.items[4], Item::Assign(vg(&["WZ_AKT", "R"]), num(5.0)));
}

#[test]
fn expressions_with_precedence_brackets_functions_and_spaces() {
    let b = one("V.G.WZ_AKT.R = V.G.WZ_AKT.R - V.P.VERSCHLEISS");
    assert!(matches!(
        &b.items[0],
        Item::Assign(_, Expr::Chain(_, rest)) if matches!(**rest, [(BinOp::Sub, _)])
    ));
    // One chain of the multiplicative group, left to right.
    let b = one("R1 = -(2 + 3) * SQRT(ABS(-16)) / COS(0)");
    let Item::Assign(_, Expr::Chain(first, rest)) = &b.items[0] else {
        panic!("{:?}", b.items)
    };
    assert!(matches!(**first, Expr::Neg(_)));
    let [(BinOp::Mul, Expr::Call(Func::Sqrt, _)), (BinOp::Div, Expr::Call(Func::Cos, _))] = &**rest
    else {
        panic!("{rest:?}")
    };
    let b = one("R1 = V.G.WZ_AKT.WEAR[0] + V.G.WZ_AKT.WEAR.X");
    assert_eq!(b.items.len(), 1);
}

#[test]
fn for_loop_with_spaces_and_commas() {
    let (blocks, errors) =
        parse_program("N100 $FOR V.P.LAUF = 0,100,10  (Grinding cycle)\n$ENDFOR");
    assert!(errors.is_empty(), "{errors:?}");
    let b = &blocks[0];
    let Item::For {
        var,
        start,
        end,
        step,
    } = &b.items[0]
    else {
        panic!()
    };
    assert!(matches!(var, Var::V { scope: 'P', .. }));
    assert_eq!(
        (&**start, &**end, &**step),
        (&num(0.0), &num(100.0), &num(10.0))
    );
    let (blocks, errors) = parse_program("N90 $FOR P1=0, 20, 1\nN120 $ENDFOR");
    assert!(errors.is_empty(), "{errors:?}");
    assert!(matches!(
        &blocks[0].items[0],
        Item::For { var: Var::P(1), .. }
    ));
    assert_eq!(blocks[1].items, vec![Item::EndFor]);
}

#[test]
fn if_else_and_while_pair_up() {
    let text = "$IF R1 > 2 AND V.G.OTC_ACTIVE == 1\nX1\n$ELSE\nX2\n$ENDIF\n$WHILE R1 <= 3\nR1 = R1 + 1\n$ENDWHILE\n";
    let (blocks, errors) = parse_program(text);
    assert!(errors.is_empty(), "{errors:?}");
    assert!(matches!(
        &blocks[0].items[0],
        Item::If(Expr::Chain(_, rest)) if matches!(**rest, [(BinOp::And, _)])
    ));
    assert_eq!(blocks[2].items, vec![Item::Else]);
    assert!(matches!(
        &blocks[5].items[0],
        Item::While(Expr::Chain(_, rest)) if matches!(**rest, [(BinOp::Le, _)])
    ));
    assert_eq!(blocks[7].items, vec![Item::EndWhile]);
}

#[test]
fn otc_switch_and_every_option() {
    let b = one("#OTC ON [RADIUS, AUTO]");
    assert_eq!(
        b.items[0],
        Item::Otc(OtcCommand {
            switch: Some(true),
            options: vec![
                OtcOption::Kind(OtcKind::Radius),
                OtcOption::Mode(OtcMode::Auto)
            ],
        })
    );
    let b = one("#OTC[LENGTH TOOL_DIR SURF_NORM_DIR DISC CONT WEAR_CONST=100000 WEAR_CONST_TOOL ACC_WEIGHT = 50]");
    let Item::Otc(otc) = &b.items[0] else {
        panic!()
    };
    assert_eq!(otc.switch, None);
    assert_eq!(otc.options.len(), 8);
    assert_eq!(otc.options[5], OtcOption::WearConst(num(100000.0)));
    assert_eq!(otc.options[6], OtcOption::WearConstTool);
    assert_eq!(otc.options[7], OtcOption::AccWeight(num(50.0)));
    let b = one("N90 #OTC OFF          (deselect OTC)");
    assert!(matches!(
        &b.items[0],
        Item::Otc(OtcCommand {
            switch: Some(false),
            ..
        })
    ));
}

#[test]
fn tool_param_set_and_get() {
    let b = one("#set ToolParam(R1; R2; R3)# #getToolParam(10;1;R20)#");
    assert_eq!(
        b.items[0],
        Item::SetToolParam {
            line: Box::new(Expr::Var(Var::R(1))),
            column: Box::new(Expr::Var(Var::R(2))),
            value: Box::new(Expr::Var(Var::R(3))),
        }
    );
    assert_eq!(
        b.items[1],
        Item::GetToolParam {
            line: Box::new(num(10.0)),
            column: Box::new(num(1.0)),
            target: Var::R(20)
        }
    );
}

#[test]
fn kin_trafo_and_hsc_are_accepted() {
    assert_eq!(one("N50 #KIN ID[4]").items, vec![Item::Kinematic(4)]);
    assert_eq!(one("#TRAFO ON").items, vec![Item::Trafo(true)]);
    assert_eq!(one("#TRAFO OFF").items, vec![Item::Trafo(false)]);
    let b = one("N85 #HSC ON[BSPLINE PATH_DEV 5 MERGE = 0]");
    assert_eq!(
        b.items,
        vec![Item::Hsc {
            on: true,
            options: "BSPLINE PATH_DEV 5 MERGE = 0".into()
        }]
    );
    assert_eq!(
        one("#HSC OFF").items,
        vec![Item::Hsc {
            on: false,
            options: String::new()
        }]
    );
}

#[test]
fn header_and_comments() {
    let b = one("%wr_quad_disc.nc ; rest");
    assert_eq!(b.items, vec![Item::ProgramName("wr_quad_disc.nc".into())]);
    let b = one("N10 (a) X1 (b) ; Y(c");
    assert_eq!(b.items, vec![Item::Axis(Axis::X, num(1.0))]);
    let (blocks, errors) = parse_program("(only a comment)\n\n; and this\n   \nN5\n");
    assert!(errors.is_empty());
    assert_eq!(blocks.len(), 1);
    assert_eq!((blocks[0].line, blocks[0].number), (5, Some(5)));
}

#[test]
fn streaming_yields_blocks_one_by_one() {
    let text = "N1 X1\r\nN2 X2\r\nN3 X3\r\n";
    let mut blocks = Blocks::new(std::io::Cursor::new(text));
    assert_eq!(blocks.next().unwrap().unwrap().number, Some(1));
    assert_eq!(blocks.next().unwrap().unwrap().number, Some(2));
    assert_eq!(blocks.next().unwrap().unwrap().number, Some(3));
    assert!(blocks.next().is_none());
}
