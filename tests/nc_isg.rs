//! The ISG functions of NC programs (docs/nc.md): the initial G25, arcs by
//! radius, the selection and deselection modes G237, G238 and G239, the
//! feed adaptation G11 with #TANGFEED, and faults that always stop a run.
//! Every expected element here is worked out by hand from the rules in
//! docs/nc.md and docs/trc.md (the formulas are written out), not taken
//! from a run; the manual's example programs are in tests/nc/.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::Command;

use nc::nc_run::NcRun;
use nc::run::{RunErrorKind, WarningKind};
use proptest::prelude::*;
use tc_request::SpoolRecord;
use trace::{fresh_emulator, parse_trace, replay, Header};

/// A run on the emulator a trace without header options replays on.
fn run_nc(text: &str) -> NcRun {
    let Ok(run) = nc::nc_run::run_nc(&mut fresh_emulator(&Header::new("nc")), text);
    run
}

const TOL: f64 = 1e-9;

/// Every element the run spooled, in order.
fn spooled(run: &NcRun) -> Vec<SpoolRecord> {
    run.exchanges
        .iter()
        .flat_map(|x| x.spooled.iter().copied())
        .collect()
}

fn program(name: &str) -> String {
    let path = format!("{}/tests/nc/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).unwrap()
}

/// A run that must end without error or fault.
fn clean(text: &str) -> NcRun {
    let run = run_nc(text);
    assert!(run.parse_errors.is_empty(), "{:?}", run.parse_errors);
    assert!(run.error.is_none(), "{}", run.error.as_ref().unwrap());
    assert!(run.report.faults.is_empty(), "{:?}", run.report.faults);
    run
}

/// The error that stopped a run: its kind, line and block number.
fn stopped(text: &str) -> (RunErrorKind, usize, Option<u32>) {
    let run = run_nc(text);
    assert!(run.parse_errors.is_empty(), "{:?}", run.parse_errors);
    let e = run.error.expect("the run stops");
    let at = e.location.expect("a block");
    (e.kind, at.line, at.block_number)
}

/// What an element is, in the X-Y plane: line or arc (centre, ccw), end.
#[derive(Debug, Clone, Copy)]
enum El {
    L(f64, f64),
    C(f64, f64, [f64; 2], bool),
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOL
}

/// The elements match `want` one for one (X and Y of the end, and the
/// centre and direction of an arc).
fn assert_elements(got: &[SpoolRecord], want: &[El]) {
    assert_eq!(got.len(), want.len(), "{got:#?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let ok = match (w, &g.arc) {
            (El::L(x, y), None) => near(g.end[0], *x) && near(g.end[1], *y),
            (El::C(x, y, c, ccw), Some(a)) => {
                near(g.end[0], *x)
                    && near(g.end[1], *y)
                    && near(a.centre[0], c[0])
                    && near(a.centre[1], c[1])
                    && a.ccw == *ccw
            }
            _ => false,
        };
        assert!(ok, "element {k}: want {w:?}, got {g:?}");
    }
}

// ---------------------------------------------------------------- G25

#[test]
fn a_program_without_g25_or_g26_gets_linear_transitions() {
    // Left of a square walked clockwise: every corner an outside corner
    // of 90°, two lines each (G25), no arc.
    let text = "G17 G1 X0 Y0 F1000\nV.G.WZR = 2\nG41 X0 Y10\nX10\nY0\nG40 X20\n";
    let run = clean(text);
    let els = spooled(&run);
    assert!(els.iter().all(|e| e.arc.is_none()), "{els:#?}");
    // From (0, 0): approach to (-2, 10), corner (-2, 12), (0, 12); the
    // top offset line y = 12 to (10, 12), corner (12, 12), (12, 10); the
    // right side x = 12 to its offset end (12, 0); departure (20, 0).
    assert_elements(
        &els,
        &[
            El::L(0.0, 0.0),
            El::L(-2.0, 10.0),
            El::L(-2.0, 12.0),
            El::L(0.0, 12.0),
            El::L(10.0, 12.0),
            El::L(12.0, 12.0),
            El::L(12.0, 10.0),
            El::L(12.0, 0.0),
            El::L(20.0, 0.0),
        ],
    );
    // G26 programmed: an arc of radius 2 about each corner instead.
    let run = clean(&format!("G26\n{text}"));
    let arcs = spooled(&run).iter().filter(|e| e.arc.is_some()).count();
    assert_eq!(arcs, 2);
}

// ------------------------------------------------------ arcs by radius

#[test]
fn an_arc_by_radius_below_and_above_180_degrees() {
    // Chord (0,0) -> (10,0), half chord 5, |R| = 13: the centre is 12 off
    // the chord's middle (5, 0). G3 R13: left of the chord, (5, 12); G3
    // the other side, (5, -12); G2 R13: right, (5, -12); G2 R-13:
    // left, (5, 12).
    for (word, r, centre) in [
        ("G3", "13", [5.0, 12.0]),
        ("G3", "-13", [5.0, -12.0]),
        ("G2", "13", [5.0, -12.0]),
        ("G2", "-13", [5.0, 12.0]),
    ] {
        let run = clean(&format!("G17 G1 X0 Y0\n{word} X10 Y0 R{r}\n"));
        let ccw = word == "G3";
        assert_elements(
            &spooled(&run),
            &[El::L(0.0, 0.0), El::C(10.0, 0.0, centre, ccw)],
        );
    }
    // R exactly half the chord, and 1e-10 under it: a half circle.
    for r in ["5", "4.9999999999"] {
        let run = clean(&format!("G1 X0 Y0\nG2 X10 R{r}\n"));
        assert_elements(
            &spooled(&run),
            &[El::L(0.0, 0.0), El::C(10.0, 0.0, [5.0, 0.0], false)],
        );
    }
}

#[test]
fn arcs_by_radius_in_the_other_planes_take_k() {
    // G18 (Z-X): from (X0, Z0) to Z10 with R5: centre Z5, X0.
    let run = clean("G18 G1 X0 Z0\nG3 Z10 R5\n");
    let arc = spooled(&run)[1].arc.expect("an arc");
    assert!(
        near(arc.centre[0], 5.0) && near(arc.centre[1], 0.0),
        "{arc:?}"
    );
}

#[test]
fn bad_arcs_by_radius_name_their_block() {
    let short = stopped("G1 X0 Y0\nN7 G2 X10 R4.9\n");
    assert_eq!(
        short,
        (
            RunErrorKind::RadiusTooShort {
                radius: 4.9,
                half_chord: 5.0
            },
            2,
            Some(7)
        )
    );
    let (kind, line, _) = stopped("G1 X0 Y0\nG2 X10 R5 I5\n");
    assert_eq!(
        (kind, line),
        (RunErrorKind::RadiusWord("together with I, J or K"), 2)
    );
    let (kind, _, _) = stopped("G1 X0 Y0\nG2 X0 Y0 R5\n");
    assert!(matches!(kind, RunErrorKind::RadiusWord(w) if w.contains("full circle")));
    let (kind, _, _) = stopped("G1 X0 Y0\nG1 X10 R5\n");
    assert_eq!(kind, RunErrorKind::RadiusWord("needs G2 or G3"));
}

// ----------------------------------------------------------------- G237

#[test]
fn bsp01_runs_perpendicular_selection_and_deselection() {
    let run = clean(&program("bsp01.nc"));
    // Right of the contour, radius 5: d = -5. B1 = N60, the arc about
    // (10, 60) from (10, 10), radius 50, CCW: its start tangent is (1, 0),
    // S + d nL(t) = (10, 10) - 5 (0, 1) = (10, 5); the offset circle has
    // radius 50 + 5 = 55 and ends at (65, 60). N70 (x = 65 offset) meets
    // N80's offset circle (centre (60, 150), radius 55) at an inside
    // corner: y = 150 - sqrt(55² - 5²). N80 ends at (5, 150); G237 goes
    // back perpendicular to its programmed end (10, 150).
    let cut = 150.0 - (55.0f64 * 55.0 - 25.0).sqrt();
    let corrected = [
        El::L(10.0, 5.0),
        El::C(65.0, 60.0, [10.0, 60.0], true),
        El::L(65.0, cut),
        El::C(5.0, 150.0, [60.0, 150.0], true),
        El::L(10.0, 150.0),
    ];
    let display = [
        El::L(0.0, 0.0),
        El::L(10.0, 10.0),
        El::C(60.0, 60.0, [10.0, 60.0], true),
        El::L(60.0, 100.0),
        El::C(10.0, 150.0, [60.0, 150.0], true),
        El::L(0.0, 0.0),
    ];
    let mut want = vec![El::L(0.0, 0.0), El::L(10.0, 10.0)];
    want.extend(corrected);
    want.extend(display);
    assert_elements(&spooled(&run), &want);
}

#[test]
fn perpendicular_selection_of_a_line_and_its_axes() {
    // Left, radius 3, B1 from (0, 0) to (40, 30): t = (0.8, 0.6),
    // nL(t) = (-0.6, 0.8): S' = (-1.8, 2.4), B1's offset end (38.2, 32.4).
    // G40 after it: back from there to (40, 30). Z moves only with B1.
    let text = "G1 X0 Y0 Z0 F500\nV.G.WZR = 3\nG237 G41 X40 Y30 Z-5\nG40\nG0 X0 Y0\n";
    let run = clean(text);
    let els = spooled(&run);
    assert_elements(
        &els,
        &[
            El::L(0.0, 0.0),
            El::L(-1.8, 2.4),
            El::L(38.2, 32.4),
            El::L(40.0, 30.0),
            El::L(0.0, 0.0),
        ],
    );
    assert_eq!(els[1].end[2], 0.0, "the inserted element keeps Z");
    assert_eq!(els[2].end[2], -5.0, "B1 makes the whole change of Z");
}

#[test]
fn g41_again_under_g237_is_isg_90191() {
    let text = "G1 X0 Y0\nV.G.WZR = 1\nG237 G41 X10\nN4 G42 X20\nG40\n";
    assert_eq!(
        stopped(text),
        (RunErrorKind::PerpendicularReselect, 4, Some(4))
    );
}

// ----------------------------------------------------------------- G239

#[test]
fn g239_demo2_keeps_the_equidistant_point() {
    let run = clean(&program("g239_demo2.nc"));
    let els = spooled(&run);
    // The last corrected line ends on its offset end (120, 20 + 10); the
    // X-only moves after G40 keep Y = 30 (under G138 they would go to
    // Y = 20).
    let tail: Vec<(f64, f64)> = els
        .iter()
        .rev()
        .take(3)
        .map(|e| (e.end[0], e.end[1]))
        .collect();
    assert_eq!(tail, vec![(200.0, 30.0), (150.0, 30.0), (120.0, 30.0)]);
    let end = run.position.unwrap();
    assert_eq!((end[0], end[1]), (200.0, 30.0));
}

#[test]
fn g239_increments_count_from_the_equidistant_point() {
    let text = "G1 X0 Y0\nV.G.WZR = 10\nG239 G41 X30 Y20\nX120\nG40\nG91 G0 X10\n";
    let els = spooled(&clean(text));
    let last = els.last().unwrap();
    assert_eq!((last.end[0], last.end[1]), (130.0, 30.0));
}

#[test]
fn an_arc_right_after_a_g239_deselection_is_an_error() {
    let text = "G1 X0 Y0\nV.G.WZR = 1\nG239 G41 X10\nX20\nG40\nN6 G2 X30 Y0 I5\n";
    assert_eq!(stopped(text), (RunErrorKind::ArcAfterG239, 6, Some(6)));
}

// ----------------------------------------------------------------- G238

#[test]
fn musterstern_is_selected_at_its_inside_corner() {
    let run = clean(&program("musterstern.nc"));
    let els = spooled(&run);
    // 11 elements draw the contour; then the tool path. The tips of the
    // star are inside corners for the left side: their cut points lie on
    // the axes at 100 - sqrt(20² + 80²) / 2 (the offset lines of the two
    // edges at a tip meet on its axis of symmetry, 10 from each edge:
    // 10 / sin(half the tip angle) = 10 sqrt(6800) / 20 from the tip).
    let c = 100.0 - 6800f64.sqrt() / 2.0;
    let path = &els[11..];
    let ends: Vec<(f64, f64)> = path.iter().map(|e| (e.end[0], e.end[1])).collect();
    let close = |p: (f64, f64), q: (f64, f64)| near(p.0, q.0) && near(p.1, q.1);
    assert!(close(ends[0], (0.0, c)), "P1 -> C first: {ends:?}");
    for tip in [(-c, 0.0), (0.0, -c), (c, 0.0)] {
        assert!(ends.iter().any(|e| close(*e, tip)), "{tip:?} in {ends:?}");
    }
    let n = ends.len();
    assert!(close(ends[n - 2], (0.0, c)), "Bn ends at C: {ends:?}");
    assert!(close(ends[n - 1], (0.0, 0.0)), "departure from C: {ends:?}");
    // B1 corrected from C to its offset end: (-20, 20) + 10 nL(t1),
    // t1 = (-20, -80) / sqrt(6800).
    let l = 6800f64.sqrt();
    let b1_end = (-20.0 + 10.0 * 80.0 / l, 20.0 - 10.0 * 20.0 / l);
    assert!(close(ends[1], b1_end), "{ends:?}");
    // P1 -> C, the eight edges, four concave corners of two lines each
    // (G25), the departure: 1 + 8 + 8 + 1.
    assert_eq!(n, 18, "{ends:?}");
    assert!(path.iter().all(|e| e.arc.is_none()));
}

#[test]
fn g238_with_an_arc_as_last_block() {
    // A square (0,0) (40,0) (40,40) (0,40) closed by an arc about (10, 20)
    // (radius sqrt(500), counter-clockwise), left, radius 2: the corner
    // arc -> first line at P2 (0, 0) is an inside corner. The offset line
    // y = 2 of B1 meets the offset circle (radius sqrt(500) - 2) at
    // x = 10 - sqrt((sqrt(500) - 2)² - 18²); so does y = 38 of the top.
    let text = "G1 X10 Y10 F1000\nV.G.WZR = 2\nG238 G41 G1 X0 Y0\nX40\nY40\nX0\n\
                G3 X0 Y0 I10 J-20\nG40 G1 X10 Y10\n";
    let run = clean(text);
    let r = 500f64.sqrt() - 2.0;
    let x0 = 10.0 - (r * r - 324.0).sqrt();
    assert_elements(
        &spooled(&run),
        &[
            El::L(10.0, 10.0),
            El::L(x0, 2.0),
            El::L(38.0, 2.0),
            El::L(38.0, 38.0),
            El::L(x0, 38.0),
            El::C(x0, 2.0, [10.0, 20.0], true),
            El::L(10.0, 10.0),
        ],
    );
    // An arc as the first contour block too: refused at B1 (decision 357).
    let both = text.replace(
        "G238 G41 G1 X0 Y0\nX40\n",
        "G238 G41 G1 X0 Y0\nG2 X40 Y0 I20 J20\nG1 ",
    );
    match stopped(&both) {
        (RunErrorKind::InsideCorner(w), 4, _) => assert!(w.contains("must be a line"), "{w}"),
        other => panic!("{other:?}"),
    }
}

/// The star of musterstern.nc with `edit` applied to its program.
fn star(edit: impl Fn(String) -> String) -> String {
    edit(program("musterstern.nc"))
}

#[test]
fn g238_errors_name_their_block() {
    let why = |text: String| match stopped(&text) {
        (RunErrorKind::InsideCorner(w), line, block) => (w, line, block),
        other => panic!("{other:?}"),
    };
    // Not closed: Bn (N380) does not end at P2.
    let (w, _, block) = why(star(|t| t.replace("N380 G01 X0 Y100", "N380 G01 X0 Y90")));
    assert!(w.contains("must end where"), "{w}");
    assert_eq!(block, Some(380));
    // Right of the star walked this way, the tips are outside corners.
    let (w, _, block) = why(star(|t| t.replace("N230 G41", "N230 G42")));
    assert!(w.contains("not an inside corner"), "{w}");
    assert_eq!(block, Some(380));
    // The selection block an arc.
    let (w, _, block) = why(star(|t| {
        t.replace("N240 G01 X0 Y100", "N240 G02 X0 Y100 I0 J50")
    }));
    assert!(w.contains("selection block must be a line"), "{w}");
    assert_eq!(block, Some(240));
    // P1 nearer than the radius to the contour: start at (0, 95).
    let (w, _, block) = why(star(|t| t.replace("N200 G00 X0Y0", "N200 G00 X0Y95")));
    assert!(w.contains("nearer than the radius"), "{w}");
    assert_eq!(block, Some(240));
    // The departure an arc.
    let (w, _, block) = why(star(|t| {
        t.replace("N400 G00 X0Y0", "N400 G02 X0 Y0 I0 J-29.384")
    }));
    assert!(w.contains("departure"), "{w}");
    assert_eq!(block, Some(400));
    // A radius change inside the contour.
    let (w, _, block) = why(star(|t| {
        t.replace("N350 X20 Y-20", "N350 X20 Y-20 V.G.WZR = 5")
    }));
    assert!(w.contains("radius"), "{w}");
    assert_eq!(block, Some(350));
    // A side programmed again inside the contour.
    let (w, _, block) = why(star(|t| t.replace("N350 X20 Y-20", "N350 G41 X20 Y-20")));
    assert!(w.contains("side"), "{w}");
    assert_eq!(block, Some(350));
}

#[test]
fn a_selection_block_crossing_the_contour_is_refused() {
    // From (0, -150) up to P2 (0, 100) the selection block crosses the
    // star's lower edges: refused at the selection block.
    let text = star(|t| t.replace("N200 G00 X0Y0", "N200 G00 X0Y-150"));
    match stopped(&text) {
        (RunErrorKind::InsideCorner(w), _, Some(240)) => assert!(w.contains("crosses"), "{w}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn g238_while_trc_runs_is_21317_and_g05_under_it_is_21316() {
    let text = "G1 X0 Y0\nV.G.WZR = 1\nG41 X10\nN4 G238 X20\nG40\n";
    assert_eq!(
        stopped(text),
        (RunErrorKind::InsideCornerWhileRunning, 4, Some(4))
    );
    let run = run_nc("G238\nN2 G05 G1 X1\n");
    let w = run.report.warnings.first().expect("21316");
    assert_eq!(w.kind, WarningKind::TangentialIgnored);
    assert_eq!(w.location.unwrap().block_number, Some(2));
}

#[test]
fn modes_given_only_in_figures_warn_once_each() {
    let text = "G1 X0 Y0\nV.G.WZR = 1\nG41 X10\nG40 X20\nG236 G41 X30\nG40 X40\nG41 X50\n\
                G05 G40 X60\n";
    let run = clean(text);
    let words: Vec<String> = run
        .report
        .warnings
        .iter()
        .map(|w| w.kind.to_string())
        .collect();
    assert_eq!(words.len(), 3, "{words:?}");
    for (w, word) in words.iter().zip(["G139", "G236", "G05"]) {
        assert!(w.starts_with(word), "{w}");
    }
}

// ------------------------------------------------------------------ G11

#[test]
fn tangfeed_adapts_the_feed_of_arcs_from_rmin_on() {
    let run = clean(&program("tangfeed.nc"));
    let feeds: Vec<(bool, f64)> = spooled(&run)
        .iter()
        .map(|e| (e.arc.is_some(), e.feed))
        .collect();
    // N50: R10 >= RMIN 3, tool inside (left of a CCW arc): R' = 8,
    // F = 600 * 8 / 10 = 480. N70 (R2 < 3) and N90 (R5 < 6): 600.
    // Every line and transition: 600.
    let arcs: Vec<f64> = feeds.iter().filter(|f| f.0).map(|f| f.1).collect();
    assert_eq!(arcs, vec![480.0, 600.0, 600.0]);
    assert!(
        feeds.iter().filter(|f| !f.0).all(|f| f.1 == 600.0),
        "{feeds:?}"
    );
}

#[test]
fn g11_without_rmin_adapts_every_arc_and_g10_ends_it() {
    // Left of a CW arc (tool outside): R' = 10 + 2, F = 1000 * 12 / 10.
    let text = "G1 X0 Y0 F1000\nV.G.WZR = 2\nG11 G41 X0 Y10\nG2 X20 Y10 I10 J0\n\
                G10 G2 X40 Y10 I10 J0\nG1 G40 X50\n";
    let els = spooled(&clean(text));
    let arcs: Vec<f64> = els
        .iter()
        .filter(|e| e.arc.is_some())
        .map(|e| e.feed)
        .collect();
    assert_eq!(arcs.len(), 2, "{els:#?}");
    assert!(near(arcs[0], 1200.0), "{arcs:?}");
    assert_eq!(arcs[1], 1000.0);
    // The older #SET TANGFEED RMIN [..] form sets RMIN too.
    let text2 = text.replace("G11 G41", "#SET TANGFEED RMIN [11]\nG11 G41");
    let els = spooled(&clean(&text2));
    assert!(els.iter().all(|e| e.feed == 1000.0), "{els:#?}");
}

#[test]
fn the_written_trace_carries_feeds_and_replays() {
    let run = clean(&program("tangfeed.nc"));
    let text = run.trace("tangfeed");
    assert!(text.contains(" F480\n"), "{text}");
    let trace = parse_trace("tangfeed.trace", &text).unwrap();
    assert!(replay(&trace).is_empty());
    // A feed named wrong in an expectation is a mismatch.
    let wrong = text.replacen(" F480\n", " F600\n", 1);
    let trace = parse_trace("wrong.trace", &wrong).unwrap();
    assert_eq!(replay(&trace).len(), 1);
}

// --------------------------------------------------------------- faults

/// A program whose last profile before `end` does not fit: N4 turns left
/// by 3, and the offset x = 45 of N4 never reaches the offset y = 5 of
/// the line before it (KorrError, docs/trc.md "Corner").
fn notch(end: &str) -> String {
    format!("G1 X0 Y0\nV.G.WZR = 5\nG41 X50\nN4 Y3\n{end}")
}

#[test]
fn a_fault_of_the_last_profile_before_g40_or_m30_stops_the_run() {
    for end in ["N6 G40\nM30\n", "N6 M30\n"] {
        let (kind, _, block) = stopped(&notch(end));
        let RunErrorKind::CorrectionFault { bits } = kind else {
            panic!("{kind:?}")
        };
        assert_eq!(bits, vec!["KorrError".to_string()]);
        assert_eq!(block, Some(4));
    }
}

#[test]
fn run_exits_1_naming_the_block_and_the_bit() {
    let dir = tempfile::tempdir().unwrap();
    for (name, end) in [("g40.nc", "N6 G40\n"), ("m30.nc", "N6 M30\n")] {
        let path = dir.path().join(name);
        std::fs::write(&path, notch(end)).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
            .arg("run")
            .arg(&path)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("KorrError"), "{stderr}");
        assert!(stderr.contains("block N4"), "{stderr}");
    }
}

// ------------------------------------------------- random contours

/// A random open polyline of 2..6 lines from the origin, each 5..50 long
/// and turning by at most 120° either way.
fn polyline() -> impl Strategy<Value = Vec<(f64, f64)>> {
    proptest::collection::vec((5.0f64..50.0, -2.0f64..2.0), 2..6).prop_map(|steps| {
        let (mut x, mut y, mut a) = (0.0f64, 0.0f64, 0.3f64);
        let mut pts = Vec::new();
        for (len, turn) in steps {
            a += turn;
            x += len * a.cos();
            y += len * a.sin();
            pts.push(((x * 1e4).round() / 1e4, (y * 1e4).round() / 1e4));
        }
        pts
    })
}

fn blocks(pts: &[(f64, f64)]) -> String {
    pts.iter().map(|(x, y)| format!("X{x} Y{y}\n")).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// G237: the element before B1 goes from B1's start perpendicular to
    /// it, |d| long; the element after Bn comes back perpendicular to it,
    /// |d| long, to Bn's programmed end.
    #[test]
    fn g237_inserts_perpendicular_elements_of_length_d(
        pts in polyline(), r in 0.5f64..3.0, left in any::<bool>()
    ) {
        let side = if left { "G41" } else { "G42" };
        let text = format!("G1 X0 Y0 F1000\nV.G.WZR = {r}\nG237 {side}\n{}G40\n", blocks(&pts));
        let run = run_nc(&text);
        prop_assume!(run.error.is_none());
        let els = spooled(&run);
        // els[0] is the G1 X0 Y0 that stays at the origin.
        let first = els[1];
        let (dx, dy) = (first.end[0], first.end[1]);
        prop_assert!(((dx * dx + dy * dy).sqrt() - r).abs() < 1e-9);
        let t = (pts[0].0, pts[0].1);
        prop_assert!((dx * t.0 + dy * t.1).abs() < 1e-6 * (t.0.hypot(t.1)));
        let last = els[els.len() - 1];
        let e = pts[pts.len() - 1];
        let p = pts[pts.len() - 2];
        prop_assert!(near(last.end[0], e.0) && near(last.end[1], e.1));
        let (bx, by) = (last.start[0] - e.0, last.start[1] - e.1);
        prop_assert!(((bx * bx + by * by).sqrt() - r).abs() < 1e-9);
        prop_assert!((bx * (e.0 - p.0) + by * (e.1 - p.1)).abs() < 1e-6 * 50.0);
    }

    /// G239: after G40 the tool stands on Bn's equidistant point, and a
    /// move naming only X keeps Y there.
    #[test]
    fn g239_leaves_the_tool_on_the_equidistant(
        pts in polyline(), r in 0.5f64..3.0, x in -50.0f64..50.0
    ) {
        let text = format!(
            "G1 X0 Y0 F1000\nV.G.WZR = {r}\nG239 G41\n{}G40\nG1 X{x}\n",
            blocks(&pts)
        );
        let run = run_nc(&text);
        prop_assume!(run.error.is_none());
        let els = spooled(&run);
        let bn_end = els[els.len() - 2].end;
        let e = pts[pts.len() - 1];
        let p = pts[pts.len() - 2];
        let len = (e.0 - p.0).hypot(e.1 - p.1);
        // E + d nL(t), d = r (left), t = (e - p) / len.
        let q = (e.0 - r * (e.1 - p.1) / len, e.1 + r * (e.0 - p.0) / len);
        prop_assert!(near(bn_end[0], q.0) && near(bn_end[1], q.1));
        let end = run.position.unwrap();
        prop_assert!(near(end[0], x) && near(end[1], q.1));
    }
}

// ------------------------------------------- review round: G238 and more

#[test]
fn g238_with_an_arc_first_and_a_line_last() {
    // B1: G3 R100 from (0,0) to (100,0), centre (50, sqrt(7500)), left
    // radius 10: offset radius 90. Bn: (0,100) -> (0,0), offset x = 10.
    // C: x = 10 on the offset circle, y = sqrt(7500) - sqrt(90² - 40²).
    let text = "N10 G138 V.G.WZR=10\nN20 G01 X50 Y50 F1000\nN30 G238\nN40 G41 X0 Y0\n\
                N50 G3 X100 Y0 R100\nN60 G1 X100 Y100\nN70 X0 Y100\nN80 X0 Y0\nN90 G40\n\
                N100 G1 X50 Y50\n";
    let run = clean(text);
    let k = 7500f64.sqrt();
    let c = k - 6500f64.sqrt();
    assert_elements(
        &spooled(&run),
        &[
            El::L(50.0, 50.0),
            El::L(10.0, c),
            El::C(90.0, c, [50.0, k], true),
            El::L(90.0, 90.0),
            El::L(10.0, 90.0),
            El::L(10.0, c),
            El::L(50.0, 50.0),
        ],
    );
}

#[test]
fn g238_checks_its_departure_before_anything_is_spooled() {
    let text = star(|t| t.replace("N400 G00 X0Y0", "N400 G02 X0 Y0 I0 J-29.384"));
    let run = run_nc(&text);
    assert!(run.error.is_some());
    // Only the 11 elements that draw the contour before N210.
    assert_eq!(spooled(&run).len(), 11);
}

#[test]
fn g238_again_while_its_contour_is_read_is_21317() {
    let text = star(|t| t.replace("N320 X-100 Y0", "N320 G238 X-100 Y0"));
    let (kind, _, block) = stopped(&text);
    assert_eq!(
        (kind, block),
        (RunErrorKind::InsideCornerWhileRunning, Some(320))
    );
}

#[test]
fn g05_before_g238_in_the_same_block_is_ignored_with_21316() {
    let text = star(|t| {
        t.replace("N210 G238", "N210")
            .replace("N230 G41", "N230 G05 G238 G41")
    });
    let run = clean(&text);
    let w: Vec<_> = run.report.warnings.iter().map(|w| w.kind.clone()).collect();
    assert!(w.contains(&WarningKind::TangentialIgnored), "{w:?}");
    let c = 100.0 - 6800f64.sqrt() / 2.0;
    let first = spooled(&run)[11];
    assert!(
        near(first.end[0], 0.0) && near(first.end[1], c),
        "{first:?}"
    );
}

#[test]
fn g238_with_radius_0_runs_on_the_contour() {
    let run = clean(&star(|t| t.replace("V.G.WZR = 10", "V.G.WZR = 0")));
    let ends: Vec<(f64, f64)> = spooled(&run)[11..]
        .iter()
        .map(|e| (e.end[0], e.end[1]))
        .collect();
    assert_eq!(ends[0], (0.0, 100.0), "P1 -> C = P2: {ends:?}");
    assert_eq!(ends[ends.len() - 2], (0.0, 100.0), "{ends:?}");
}

#[test]
fn modal_words_inside_a_g238_contour_act_from_their_block() {
    // G26 at N340: the concave corner N310 -> N320 keeps G25's two lines,
    // the three after it get an arc each.
    let run = clean(&star(|t| t.replace("N340 X0 Y-100", "N340 G26 X0 Y-100")));
    let path = &spooled(&run)[11..];
    let arcs = path.iter().filter(|e| e.arc.is_some()).count();
    assert_eq!(arcs, 3, "{path:#?}");
    assert!(path[2].arc.is_none() && path[3].arc.is_none());
}

#[test]
fn g239_keeps_the_offset_bn_was_corrected_with() {
    // The radius changes to 5 after the last block: Bn was spooled with 10
    // (to Y30), and the program goes on from there.
    let text = "G1 X0 Y0\nV.G.WZR = 10\nG239 G41 X30 Y20\nX120\nV.G.WZR = 5\nG40\nG0 X150\n";
    let els = spooled(&clean(text));
    let tail: Vec<(f64, f64)> = els
        .iter()
        .rev()
        .take(2)
        .map(|e| (e.end[0], e.end[1]))
        .collect();
    assert_eq!(tail, vec![(150.0, 30.0), (120.0, 30.0)]);
}

#[test]
fn the_g237_element_runs_at_the_feed_of_its_block() {
    let text = "G1 X0 Y0 F1000\nV.G.WZR = 10\nN30 G237 G41 X100 Y0 F500\nG40\n";
    let els = spooled(&clean(text));
    assert_eq!(
        (els[1].end[0], els[1].end[1], els[1].feed),
        (0.0, 10.0, 500.0)
    );
}

#[test]
fn a_trc_option_is_an_error_naming_it() {
    let (kind, line, _) = stopped("G1 X0\n#TRC [G236_LIN=1]\n");
    assert_eq!(
        (kind, line),
        (RunErrorKind::TrcOption("G236_LIN".into()), 2)
    );
}
