//! Streamed runs: blocks pulled from the reader as the run needs them,
//! only an open loop's body held, and a full spooler worked off.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod support;

use std::cell::Cell;
use std::io::{BufReader, Read};
use std::rc::Rc;

use nc::run::{run_blocks, run_reader, At, Controller, Report};
use nc::{check_program, Blocks};
use tc_request::{Reply, Request};
use uoi::Value;

/// Longest line the generated program has, in bytes (checked).
const MAX_LINE: u64 = 40;

/// The program of `total` lines: moves, a `$FOR` loop of 10 moves run 3
/// times at line 1000, an `$IF` whose 1000 blocks are skipped at line
/// 100,000, `M30` last.
fn line_text(k: usize, total: usize) -> String {
    const LOOP: usize = 1000;
    const SKIP: usize = 100_000;
    match k {
        0 => "%LONG".into(),
        1 => "N1 G17 G90 G1 F6000".into(),
        LOOP => "$FOR P1 = 1, 3, 1".into(),
        k if k > LOOP && k <= LOOP + 10 => format!("G1 X[P1 * 10] Y{}", k - LOOP),
        k if k == LOOP + 11 => "$ENDFOR".into(),
        SKIP => "$IF P1 > 100".into(),
        k if k > SKIP && k <= SKIP + 1000 => format!("N{k} G1 X{k} Y1"),
        k if k == SKIP + 1001 => "$ENDIF".into(),
        k if k + 1 == total => "M30".into(),
        k => format!("N{k} G1 X{} Y{}", k % 1000, k % 7),
    }
}

/// Motions the program above makes.
fn motions_of(total: usize) -> u64 {
    // Every line but header, N1, the loop's 12, the IF's 1002 and M30 is
    // one move; the loop's 10 run 3 times.
    (total - 2 - 12 - 1002 - 1) as u64 + 30
}

/// The program's text made line by line as it is read, counting the bytes
/// handed out.
struct Generated {
    next: usize,
    total: usize,
    line: Vec<u8>,
    at: usize,
    given: Rc<Cell<u64>>,
}

impl Generated {
    fn new(total: usize, given: Rc<Cell<u64>>) -> Self {
        Generated {
            next: 0,
            total,
            line: Vec::new(),
            at: 0,
            given,
        }
    }
}

impl Read for Generated {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.line.len() {
            if self.next == self.total {
                return Ok(0);
            }
            self.line = format!("{}\n", line_text(self.next, self.total)).into_bytes();
            assert!(self.line.len() as u64 <= MAX_LINE);
            self.next += 1;
            self.at = 0;
        }
        let n = buf.len().min(self.line.len() - self.at);
        buf[..n].copy_from_slice(&self.line[self.at..self.at + n]);
        self.at += n;
        self.given.set(self.given.get() + n as u64);
        Ok(n)
    }
}

/// Answers everything like a controller that never fills up, and checks
/// at every request that the program was not read far ahead of the block
/// that sent it.
struct Streaming {
    given: Rc<Cell<u64>>,
    motions: u64,
    worst_ahead: u64,
}

impl Controller for Streaming {
    fn call(&mut self, req: &Request, at: At) -> Reply {
        let due = at.line as u64 * MAX_LINE;
        self.worst_ahead = self.worst_ahead.max(self.given.get().saturating_sub(due));
        match req {
            Request::Pos => Reply::Pos([0.0; 8]),
            Request::Read(..) => Reply::Value(Value::F64(0.0)),
            Request::Motion(_) => {
                self.motions += 1;
                Reply::Ok
            }
            _ => Reply::Ok,
        }
    }
}

#[test]
fn a_long_program_runs_streamed_holding_only_the_open_loop() {
    const TOTAL: usize = 300_000;
    let given = Rc::new(Cell::new(0));
    let errors = check_program(BufReader::new(Generated::new(TOTAL, given.clone())));
    assert!(errors.is_empty(), "{errors:?}");

    let given = Rc::new(Cell::new(0));
    let reader = BufReader::new(Generated::new(TOTAL, given.clone()));
    let mut ctl = Streaming {
        given,
        motions: 0,
        worst_ahead: 0,
    };
    let mut report = Report::default();
    run_reader(&mut Blocks::new(reader), &mut ctl, &mut report).unwrap();

    assert_eq!(ctl.motions, motions_of(TOTAL));
    // The loop's 12 blocks, not the program's 300,000.
    assert!(
        (12..=13).contains(&report.peak_held_blocks),
        "{}",
        report.peak_held_blocks
    );
    // Read as it runs: never more than the reader's buffer ahead.
    assert!(ctl.worst_ahead <= 16 * 1024, "{}", ctl.worst_ahead);
}

fn zigzag(n: usize) -> String {
    let mut text =
        String::from("N1 G17 G90 #set ToolParam(1; 4; 2)#\nN2 D1 G41 G1 X10 Y0 F60000\n");
    let mut last_y = 0;
    for k in 0..n {
        let y = if k % 2 == 0 { 5 } else { 0 };
        if k % 3 == 0 {
            // A half circle over the step: its centre halfway.
            let j = f64::from(y - last_y) / 2.0;
            text.push_str(&format!("G2 X{} Y{y} I2.5 J{j}\n", 15 + 5 * k));
        } else {
            text.push_str(&format!("G1 X{} Y{y}\n", 15 + 5 * k));
        }
        last_y = y;
    }
    text.push_str("G40 G1 X0 Y-10\nM30\n");
    text
}

fn spooled(text: &str, capacity: usize) -> (Vec<tc_request::SpoolRecord>, Vec<String>) {
    let mut engine = support::Engine::with_capacity(capacity);
    engine.tc.spooler_mut().set_logging(true);
    let mut report = Report::default();
    run_blocks(Blocks::new(text.as_bytes()), &mut engine, &mut report).unwrap();
    let log = engine.tc.spooler_mut().take_log();
    (log.iter().map(|e| e.record()).collect(), engine.log)
}

#[test]
fn a_full_spooler_is_worked_off_with_exec_and_the_request_sent_again() {
    let text = zigzag(40);
    let (roomy, roomy_log) = spooled(&text, 100_000);
    let (tight, tight_log) = spooled(&text, 8);
    assert!(!roomy_log.iter().any(|l| l.contains("Full")));
    let full = tight_log
        .iter()
        .position(|l| l.ends_with("=> err Full"))
        .expect("the 8-element spooler fills up");
    assert_eq!(tight_log[full + 1], "EXEC");
    assert_eq!(
        format!("{} => err Full", tight_log[full + 2]),
        tight_log[full]
    );
    // The same elements, in the same order.
    assert_eq!(tight.len(), roomy.len());
    assert_eq!(tight, roomy);
}

/// Records the motions as text.
#[derive(Default)]
struct Moves(Vec<String>);

impl Controller for Moves {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        match req {
            Request::Pos => Reply::Pos([0.0; 8]),
            Request::Motion(_) => {
                self.0.push(req.to_string());
                Reply::Ok
            }
            _ => Reply::Ok,
        }
    }
}

#[test]
fn loops_jump_back_into_held_blocks_after_the_window_moved_on() {
    // A small loop first (the window grows), plain blocks (its slots go
    // round), then a loop of 30 blocks with an $IF and a $WHILE inside,
    // run twice (the window grows again while it wraps around).
    let mut text = String::from("$FOR P1 = 1, 2, 1\nG1 X[P1]\n$ENDFOR\n");
    for k in 0..7 {
        text.push_str(&format!("G1 Y{k}\n"));
    }
    text.push_str("$FOR P2 = 1, 2, 1\n");
    for j in 0..20 {
        text.push_str(&format!("G1 X[P2 * 100 + {j}]\n"));
    }
    text.push_str("$IF P2 == 2\nG1 Y-1\n$ELSE\nG1 Y-2\n$ENDIF\n");
    text.push_str("$WHILE R1 < P2 * 2\nR1 = R1 + 1\nG1 Z[R1]\n$ENDWHILE\n$ENDFOR\nG1 X9\n");

    let mut expected = vec!["LIN X1".to_string(), "LIN X2".into()];
    expected.extend((0..7).map(|k| format!("LIN Y{k}")));
    let mut r1 = 0;
    for p2 in 1..=2 {
        expected.extend((0..20).map(|j| format!("LIN X{}", p2 * 100 + j)));
        expected.push(if p2 == 2 { "LIN Y-1" } else { "LIN Y-2" }.into());
        while r1 < p2 * 2 {
            r1 += 1;
            expected.push(format!("LIN Z{r1}"));
        }
    }
    expected.push("LIN X9".into());

    let mut moves = Moves::default();
    let mut report = Report::default();
    run_reader(&mut Blocks::new(text.as_bytes()), &mut moves, &mut report).unwrap();
    assert_eq!(moves.0, expected);
    // The second loop's 31 blocks, from its $FOR to its $ENDFOR.
    assert_eq!(report.peak_held_blocks, 31);
    // The same through the iterator form.
    let mut moves = Moves::default();
    run_blocks(
        Blocks::new(text.as_bytes()),
        &mut moves,
        &mut Report::default(),
    )
    .unwrap();
    assert_eq!(moves.0, expected);
}

mod check_pass {
    use nc::{check_program, parse_program};
    use proptest::prelude::*;

    const LINES: [&str; 16] = [
        "N10 G1 X10 Y-5.5 F600",
        "G2 X0 Y0 I5 J0",
        "$FOR P1 = 1, 3, 1",
        "$ENDFOR",
        "$IF R1 > 2",
        "$ELSE",
        "$ENDIF",
        "$WHILE R1 < 3",
        "$ENDWHILE",
        "R1 = R1 + 1 X[R1]",
        "#OTC ON [RADIUS]",
        "%PROG",
        "N5 $IF 1 G1 X1",
        "G1 X1.2.3",
        "G236 Q1",
        "V.P.A = 1 V.5",
    ];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// The check pass (plain words only recognised) finds exactly the
        /// errors the full parse finds.
        #[test]
        fn the_check_pass_finds_the_errors_of_the_full_parse(
            picks in proptest::collection::vec((0usize..LINES.len(), "[ -~]{0,12}"), 0..30)
        ) {
            let text: String = picks
                .iter()
                .map(|(k, junk)| format!("{} {junk}\n", LINES[*k]))
                .collect();
            prop_assert_eq!(check_program(text.as_bytes()), parse_program(&text).1);
        }
    }
}
