//! Input at its limits: a flat chain of operators of any length on one
//! line runs with a stack as deep as its nesting, not its length; nesting
//! deeper than allowed and a line longer than allowed are errors naming
//! their line, read in bounded memory.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{BufReader, Read};

use nc::run::{run_program, At, Controller, Report};
use nc::{check_program, parse_program, NcError, MAX_LINE_BYTES};
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

/// The requests of a run of `text`, which must parse and run.
fn requests(text: &str) -> Vec<String> {
    let (blocks, errors) = parse_program(text);
    assert!(errors.is_empty(), "{:?}", errors.first());
    let mut log = Log::default();
    let mut report = Report::default();
    let result = run_program(&blocks, &mut log, &mut report);
    assert!(result.is_ok(), "{:?}", result.err());
    log.0
}

/// `n` operands `first`, `rest`, `rest`, .. joined by `op`.
fn chain(first: &str, op: &str, rest: &str, n: usize) -> String {
    let mut s = String::with_capacity(n * (op.len() + rest.len()));
    s.push_str(first);
    for _ in 1..n {
        s.push_str(op);
        s.push_str(rest);
    }
    s
}

/// About 80,000 terms on one line: a 160 KB program, which overflowed the
/// stack when a chain was a tree as deep as it is long.
const TERMS: usize = 80_000;

#[test]
fn a_flat_sum_of_80000_terms_runs() {
    let text = format!("R1 = {}\nG1 X[R1]\n", chain("1", "+", "1", TERMS));
    assert!(text.len() > 160_000);
    assert_eq!(requests(&text), ["POS", "LIN X80000", "EXEC"]);
}

#[test]
fn flat_products_conjunctions_and_comparisons_run() {
    let product = format!("R1 = {}\nG1 X[R1]\n", chain("3", "*", "1", TERMS));
    assert_eq!(requests(&product), ["POS", "LIN X3", "EXEC"]);
    let and = format!("R1 = {}\nG1 X[R1 * 5]\n", chain("1", " AND ", "2", TERMS));
    assert_eq!(requests(&and), ["POS", "LIN X5", "EXEC"]);
    let or = format!("$IF {}\nG1 X7\n$ENDIF\n", chain("0", " OR ", "0", TERMS));
    assert_eq!(requests(&or), ["POS", "EXEC"]);
    // ((1 < 2) < 2) < 2 ..: 1 each time.
    let less = format!("R1 = {}\nG1 X[R1]\n", chain("1", "<", "2", TERMS));
    assert_eq!(requests(&less), ["POS", "LIN X1", "EXEC"]);
}

#[test]
fn a_long_chain_is_evaluated_left_to_right() {
    // 100 - 1 - 1 - .. (left to right) and 2^20 / 2 / 2 ..
    let minus = format!("G1 X[{}]\n", chain("100000", "-", "1", TERMS));
    assert_eq!(requests(&minus), ["POS", "LIN X20001", "EXEC"]);
    let halves = format!("G1 X[{}]\n", chain("1048576", "/", "2", 21));
    assert_eq!(requests(&halves), ["POS", "LIN X1", "EXEC"]);
    // Alternating + and - on one level, with products on the next.
    let mixed = format!("G1 X[{}]\n", chain("1", "+2*3-", "1", 1001));
    assert_eq!(requests(&mixed), ["POS", "LIN X5001", "EXEC"]);
}

#[test]
fn a_flat_chain_of_brackets_and_signs_runs() {
    let text = format!(
        "R1 = {}\nG1 X[R1]\n",
        chain("-(1)", "+", "-(-[2])", TERMS / 4)
    );
    assert_eq!(requests(&text), ["POS", "LIN X39997", "EXEC"]);
}

fn only_error(text: &str) -> NcError {
    let (_, mut errors) = parse_program(text);
    assert_eq!(errors.len(), 1, "{errors:?}");
    errors.remove(0)
}

#[test]
fn nesting_deeper_than_allowed_is_an_error_naming_its_line() {
    // 60 levels of brackets and signs run.
    let fine = format!("N1 G1 X[{}1{}]\n", "-(".repeat(30), ")".repeat(30));
    assert_eq!(requests(&fine), ["POS", "LIN X1", "EXEC"]);
    for deep in [
        format!("R1 = {}1{}", "(".repeat(65), ")".repeat(65)),
        format!("R1 = {}1", "-".repeat(65)),
        format!("R1 = {}1{}", "SQRT(".repeat(65), ")".repeat(65)),
        format!("R1 = {}1{}", "V.P.A[".repeat(65), "]".repeat(65)),
    ] {
        let e = only_error(&format!("N1 G1 X1\nN2 {deep}\nN3 G1 X2\n"));
        assert_eq!((e.line, e.block_number), (2, Some(2)), "{e}");
        assert!(e.message.contains("nested deeper than 64"), "{e}");
    }
}

/// A line of `X1 X1 ..` of `len` bytes.
fn long_line(len: usize) -> String {
    "X1 ".repeat(len / 3 + 1)[..len].to_string()
}

#[test]
fn a_line_longer_than_the_limit_is_an_error_and_the_next_lines_are_read() {
    let text = format!(
        "N1 G1 X1\nN2 {}\nN3 Q7\nN4 {} \n",
        long_line(MAX_LINE_BYTES),
        long_line(MAX_LINE_BYTES - 4)
    );
    // The fourth line is as long as allowed.
    assert_eq!(text.lines().nth(3).map(str::len), Some(MAX_LINE_BYTES));
    for capacity in [64, 8192, text.len()] {
        let errors = check_program(BufReader::with_capacity(capacity, text.as_bytes()));
        let got: Vec<(usize, Option<u32>)> =
            errors.iter().map(|e| (e.line, e.block_number)).collect();
        assert_eq!(got, [(2, Some(2)), (3, Some(3))], "{capacity}: {errors:?}");
        let limit = MAX_LINE_BYTES.to_string();
        assert!(errors[0].message.contains(&limit), "{}", errors[0]);
        assert_eq!(errors[0].column, 1);
    }
    // Held whole, the same.
    let (blocks, errors) = parse_program(&text);
    assert_eq!(errors.len(), 2);
    assert_eq!(blocks.len(), 2);
}

/// `X1 X1 ..` without a line end, as long as asked, after a first line.
/// A stretch of `X1 ` words.
const WORDS: &str = "X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 X1 ";

struct Endless {
    head: &'static [u8],
    left: u64,
}

impl Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if !self.head.is_empty() {
            let n = self.head.len().min(buf.len());
            buf[..n].copy_from_slice(&self.head[..n]);
            self.head = &self.head[n..];
            return Ok(n);
        }
        // Whole words, a stretch at a time.
        let n = buf.len().min(WORDS.len());
        let n = n.min(usize::try_from(self.left).unwrap_or(usize::MAX));
        buf[..n].copy_from_slice(&WORDS.as_bytes()[..n]);
        self.left -= n as u64;
        Ok(n)
    }
}

#[test]
fn a_streamed_line_of_48_mb_is_refused_once_at_its_line() {
    let reader = Endless {
        head: b"N1 G1 X1\nN7 ",
        left: 48 << 20,
    };
    let errors = check_program(BufReader::new(reader));
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!((errors[0].line, errors[0].block_number), (2, Some(7)));
    assert!(errors[0].message.contains("longer than"), "{}", errors[0]);
}
