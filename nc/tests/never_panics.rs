//! Random and mutated program text never panics, and every error has a line.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use proptest::prelude::*;

const SEED: &str = include_str!("../../tests/nc/otc_surf_norm_dir.nc");
const PIECES: &[&str] = &[
    "N10 ",
    "G1 ",
    "G41",
    "X",
    "Y-",
    "Z[",
    "]",
    "R1",
    "=",
    " + ",
    "*",
    "(",
    ")",
    ";",
    "#OTC ON [",
    "RADIUS",
    ",",
    "#set ToolParam(",
    ";",
    ")#",
    "$FOR P1=0,",
    "$ENDFOR",
    "$IF ",
    "V.G.WZ_AKT.",
    "WEAR[",
    "SQRT(",
    "\u{2013}",
    "\u{a0}",
    "%",
    "\n",
    "1.5",
    ".",
    "-",
    "M30",
    "#KIN ID[",
];

fn check(text: &str) {
    let lines = text.split('\n').count();
    let (_, errors) = nc::parse_program(text);
    for e in errors {
        assert!(e.line >= 1 && e.line <= lines, "{e:?}");
        assert!(e.column >= 1, "{e:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_text_never_panics(text in "\\PC{0,200}") {
        check(&text);
    }

    #[test]
    fn programs_of_nc_pieces_never_panic(pieces in prop::collection::vec(prop::sample::select(PIECES), 0..60)) {
        check(&pieces.concat());
    }

    #[test]
    fn mutated_seed_never_panics(cuts in prop::collection::vec((0..SEED.len(), prop::sample::select(PIECES)), 1..8)) {
        let mut text = SEED.to_string();
        for (at, piece) in cuts {
            let mut at = at.min(text.len());
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            text.insert_str(at, piece);
        }
        check(&text);
    }
}
