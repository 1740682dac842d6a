//! The NC front end under random and mutated programs, through parse and
//! interpretation on the real emulator (`fuzz_checks::nc_program`,
//! the body of the `nc_program` fuzz target, docs/fuzzing.md): nothing
//! panics or hangs, and every error names its line and the block number
//! written there.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use fuzz_checks::nc_program;
use proptest::prelude::*;
use proptest::sample::Index;

/// The seed programs, as typed in.
const SEEDS: [&str; 11] = [
    include_str!("nc/wzkg25.nc"),
    include_str!("nc/wzkg26.nc"),
    include_str!("nc/tool_data_change.nc"),
    include_str!("nc/dynamic_radius.nc"),
    include_str!("nc/otc_general.nc"),
    include_str!("nc/wr_quad_disc.nc"),
    include_str!("nc/otc_length.nc"),
    include_str!("nc/otc_tool_dir.nc"),
    include_str!("nc/otc_surf_norm_dir.nc"),
    include_str!("nc/toolparam_set.nc"),
    include_str!("nc/toolparam_get.nc"),
];

/// Words of the supported subset (some with values the controller
/// refuses), for the grammar and for insertions.
const WORDS: &[&str] = &[
    "G0",
    "G1",
    "G01",
    "G2",
    "G3",
    "G02",
    "G17",
    "G18",
    "G19",
    "G90",
    "G91",
    "G40",
    "G41",
    "G42",
    "G25",
    "G26",
    "G138",
    "G139",
    "G05",
    "G10",
    "G11",
    "G140",
    "G141",
    "X10",
    "X-25.5",
    "Y5",
    "Y-7",
    "Z3",
    "Z-300",
    "B45",
    "A1",
    "I5",
    "I-15",
    "J-5",
    "J0",
    "K2",
    "F600",
    "F1",
    "F0.5",
    "F60000",
    "D0",
    "D1",
    "D2",
    "D3",
    "D4",
    "D255",
    "D300",
    "T1",
    "M30",
    "R1=2",
    "R2=R1*3",
    "R3=R2/R1",
    "P1=0",
    "V.P.A=1",
    "X[R1+1]",
    "Y[SQRT(2)*R2]",
    "F[R1*100]",
    "V.G.WZ_AKT.R=V.G.WZ_AKT.R-0.5",
    "R5=V.G.WZ_AKT.WEAR_RADIUS",
    "R6=V.G.OTC_ACTIVE",
    "#OTC ON",
    "#OTC OFF",
    "#OTC[RADIUS, AUTO]",
    "#OTC ON [LENGTH]",
    "#OTC ON[RADIUS DISC]",
    "#OTC ON [TOOL_DIR, CONT, WEAR_CONST=500]",
    "#OTC [SURF_NORM_DIR ACC_WEIGHT=50]",
    "#OTC[WEAR_CONST_TOOL]",
    "#set ToolParam(2; 4; 3)#",
    "#get ToolParam(1; 4; R3)#",
    "#set ToolParam(R1; 1; 2)#",
    "#KIN ID[4]",
    "#TRAFO ON",
    "#TRAFO OFF",
    "#HSC ON[BSPLINE PATH_DEV 5 MERGE = 0]",
    "#HSC OFF",
    "(comment)",
    "; note",
];

/// Control lines, for insertions.
const CONTROL: &[&str] = &[
    "$FOR P1=0, 2, 1",
    "$ENDFOR",
    "$IF R1 > 1",
    "$ELSE",
    "$ENDIF",
    "$WHILE R9 < 2",
    "$ENDWHILE",
    "%prog",
];

/// Numbers put in place of a word's number.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "0.001",
    "-0.5",
    "7",
    "360",
    "99999",
    "1000000",
    "4294967295",
    "4294967296",
    "100000000000000000000",
    "1e5",
    "",
    ".",
    "--1",
];

/// One change to a program seen as words (whitespace-separated, line ends
/// kept as words of their own).
#[derive(Debug, Clone)]
enum Mutation {
    Insert(Index, &'static str),
    Delete(Index),
    Replace(Index, &'static str),
    Number(Index, &'static str),
    Digit(Index, Index, char),
    DuplicateLine(Index),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let word = prop::sample::select(WORDS);
    let control = prop::sample::select(CONTROL);
    let number = prop::sample::select(NUMBERS);
    prop_oneof![
        3 => (any::<Index>(), word.clone()).prop_map(|(i, w)| Mutation::Insert(i, w)),
        1 => (any::<Index>(), control).prop_map(|(i, w)| Mutation::Insert(i, w)),
        2 => any::<Index>().prop_map(Mutation::Delete),
        3 => (any::<Index>(), word).prop_map(|(i, w)| Mutation::Replace(i, w)),
        3 => (any::<Index>(), number).prop_map(|(i, n)| Mutation::Number(i, n)),
        3 => (any::<Index>(), any::<Index>(), prop::char::range('0', '9'))
            .prop_map(|(i, j, c)| Mutation::Digit(i, j, c)),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
    ]
}

/// The program as words, line ends as `"\n"`.
fn words_of(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        out.extend(line.split_whitespace().map(str::to_owned));
        out.push("\n".to_owned());
    }
    out
}

fn apply(words: &mut Vec<String>, m: &Mutation) {
    if words.is_empty() {
        words.push("\n".to_owned());
    }
    match m {
        Mutation::Insert(i, w) => words.insert(i.index(words.len() + 1), (*w).to_owned()),
        Mutation::Delete(i) => {
            words.remove(i.index(words.len()));
        }
        Mutation::Replace(i, w) => {
            let k = i.index(words.len());
            if words[k] != "\n" {
                words[k] = (*w).to_owned();
            }
        }
        Mutation::Number(i, n) => {
            let k = i.index(words.len());
            let w = &words[k];
            let head = w.trim_end_matches(|c: char| c.is_ascii_digit() || ".-".contains(c));
            if head.len() < w.len() {
                words[k] = format!("{head}{n}");
            }
        }
        Mutation::Digit(i, j, c) => {
            let k = i.index(words.len());
            let digits: Vec<usize> = words[k]
                .char_indices()
                .filter(|(_, d)| d.is_ascii_digit())
                .map(|(p, _)| p)
                .collect();
            if !digits.is_empty() {
                let p = digits[j.index(digits.len())];
                words[k].replace_range(p..=p, &c.to_string());
            }
        }
        Mutation::DuplicateLine(i) => {
            let k = i.index(words.len());
            let start = words[..k]
                .iter()
                .rposition(|w| w == "\n")
                .map_or(0, |p| p + 1);
            let end = words[k..]
                .iter()
                .position(|w| w == "\n")
                .map_or(words.len(), |p| k + p + 1);
            let line: Vec<String> = words[start..end].to_vec();
            words.splice(end..end, line);
        }
    }
}

fn text_of(words: &[String]) -> String {
    let mut out = String::new();
    for w in words {
        if w == "\n" {
            out.push('\n');
        } else {
            if !out.is_empty() && !out.ends_with('\n') {
                out.push(' ');
            }
            out.push_str(w);
        }
    }
    out
}

/// Axis words of a motion block.
const AXIS_WORDS: &[&str] = &["X10", "X-4", "X0", "Y5", "Y-12.5", "Y0", "Z2", "Z-1", "B30"];
/// Centre words of an arc.
const CENTRE_WORDS: &[&str] = &["I5", "I-15", "J-5", "J3", "I2 J2", "K1"];

/// A motion block: a motion kind or none, axis words (an arc with its
/// centre), a feed or none.
fn motion() -> impl Strategy<Value = String> {
    (
        prop::sample::select(&["", "G0", "G1", "G2", "G3", "G1 G91", "G90 G1"][..]),
        prop::collection::vec(prop::sample::select(AXIS_WORDS), 1..3),
        prop::sample::select(CENTRE_WORDS),
        prop::option::weighted(0.3, prop::sample::select(&["F600", "F5", "F60000"][..])),
    )
        .prop_map(|(kind, axes, centre, feed)| {
            let mut words = vec![kind];
            words.extend(axes);
            if kind.ends_with("G2") || kind.ends_with("G3") {
                words.push(centre);
            }
            words.extend(feed);
            words.join(" ").trim().to_owned()
        })
}

/// A block: a motion, or 1..3 words of the subset; with a block number
/// or not.
fn block() -> impl Strategy<Value = String> {
    let words = prop::collection::vec(prop::sample::select(WORDS), 1..4).prop_map(|w| w.join(" "));
    (
        prop::option::weighted(0.7, 0u32..2000),
        prop_oneof![3 => motion(), 2 => words],
    )
        .prop_map(|(n, block)| match n {
            Some(n) => format!("N{n} {block}"),
            None => block,
        })
}

/// Blocks and small loops and conditions of them, nested up to two deep;
/// bounded: a loop runs at most three times, and each has a variable of
/// its own (an inner loop on the outer one's variable could run forever,
/// as on a real controller).
fn piece() -> impl Strategy<Value = Vec<String>> {
    let leaf = block().prop_map(|b| vec![b]);
    leaf.prop_recursive(2, 24, 6, |inner| {
        let body = prop::collection::vec(inner, 1..5).prop_map(|v| v.concat());
        prop_oneof![
            (0u32..3, any::<u32>(), body.clone()).prop_map(|(n, k, body)| {
                let mut out = vec![format!("$FOR V.P.F{k} = 0, {n}, 1")];
                out.extend(body);
                out.push("$ENDFOR".into());
                out
            }),
            (0u32..3, body.clone(), prop::option::of(body.clone())).prop_map(|(v, yes, no)| {
                let mut out = vec![format!("$IF R1 > {v}")];
                out.extend(yes);
                if let Some(no) = no {
                    out.push("$ELSE".into());
                    out.extend(no);
                }
                out.push("$ENDIF".into());
                out
            }),
            (1u32..4, any::<u32>(), body).prop_map(|(n, k, body)| {
                let mut out = vec![format!("V.P.W{k} = 0"), format!("$WHILE V.P.W{k} < {n}")];
                out.extend(body);
                out.push(format!("V.P.W{k} = V.P.W{k} + 1"));
                out.push("$ENDWHILE".into());
                out
            }),
        ]
    })
}

/// A program: mostly a motion kind and a feed first (else most programs
/// stop at their first axis word), then pieces.
fn program() -> impl Strategy<Value = String> {
    let start = prop::sample::select(&["N1 G1 F600", "N1 G0 D2", "G90 G17 G01 F100 D1", ""][..]);
    (start, prop::collection::vec(piece(), 0..12)).prop_map(|(start, pieces)| {
        let mut lines = vec![start.to_string()];
        lines.extend(pieces.concat());
        lines.join("\n")
    })
}

/// Operators of every precedence group, for flat chains.
const OPERATORS: &[&str] = &[
    "+", "-", "*", "/", " AND ", " OR ", "==", "!=", "<", "<=", ">", ">=",
];

/// Operands of flat chains: numbers, parameters, variables, brackets,
/// signs, calls.
const OPERANDS: &[&str] = &[
    "1", "0", "2.5", "R1", "-1", "(1)", "SQRT(4)", "V.P.A", "[R2]", "-(-1)", "P1", "ABS(-2)",
];

/// `operands` and `operators` taken in turn into one flat chain of about
/// `len` bytes.
fn chain_of(operands: &[&str], operators: &[&str], len: usize) -> String {
    let mut s = String::with_capacity(len + 16);
    let mut k = 0;
    s.push_str(operands[0]);
    while s.len() < len {
        k += 1;
        s.push_str(operators[k % operators.len()]);
        s.push_str(operands[k % operands.len()]);
    }
    s
}

/// A short program around `line`: a feed, the variables the operands
/// read, `line`, a motion.
fn around(line: &str) -> String {
    format!("N1 G1 F600\nR2 = 3\nV.P.A = 1\n{line}\nN9 G1 X5 Y[R1]\nM30\n")
}

/// One line with a flat chain of up to 16,000 bytes (the harness reads
/// at most 16 KiB): in an assignment, an axis word or a condition.
fn flat_chain() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(prop::sample::select(OPERANDS), 1..4),
        prop::collection::vec(prop::sample::select(OPERATORS), 1..4),
        100usize..16_000,
        0usize..3,
    )
        .prop_map(|(operands, operators, len, form)| {
            let chain = chain_of(&operands, &operators, len);
            around(&match form {
                0 => format!("R1 = {chain}"),
                1 => format!("G1 X[{chain}]"),
                _ => format!("$IF {chain}\nG1 Y2\n$ENDIF"),
            })
        })
}

/// Brackets, signs, calls and variable indices nested about as deep as
/// allowed (`MAX_EXPR_NESTING`, 64), a little less or more.
fn deep_nesting() -> impl Strategy<Value = String> {
    const OPEN: [(&str, &str); 6] = [
        ("(", ")"),
        ("[", "]"),
        ("-", ""),
        ("SQRT(", ")"),
        ("-(", ")"),
        ("V.P.A[", "]"),
    ];
    (
        prop::collection::vec(prop::sample::select(&OPEN[..]), 1..3),
        40usize..90,
    )
        .prop_map(|(kinds, depth)| {
            let open: String = (0..depth).map(|k| kinds[k % kinds.len()].0).collect();
            let close: String = (0..depth).rev().map(|k| kinds[k % kinds.len()].1).collect();
            around(&format!("R1 = {open}1{close}"))
        })
}

/// The seeds of long flat expressions and deep nesting that the fuzz
/// target starts from besides the typed-in programs
/// (`fuzz/seeds/nc_program/`), by file name.
fn expression_seeds() -> Vec<(&'static str, String)> {
    let deep =
        |open: &str, close: &str, n: usize| format!("R1 = {}1{}", open.repeat(n), close.repeat(n));
    vec![
        (
            "flat_sum.nc",
            around(&format!("R1 = {}", chain_of(&["1"], &["+"], 16_000))),
        ),
        (
            "flat_product.nc",
            around(&format!("R1 = {}", chain_of(&["1"], &["*"], 16_000))),
        ),
        (
            "flat_and_or.nc",
            around(&format!(
                "$IF {}\nG1 Y2\n$ENDIF",
                chain_of(&["1"], &[" AND ", " OR "], 16_000)
            )),
        ),
        (
            "flat_compare.nc",
            around(&format!(
                "R1 = {}",
                chain_of(&["1", "2"], &["<", "==", ">="], 16_000)
            )),
        ),
        (
            "flat_mixed.nc",
            around(&format!("G1 X[{}]", chain_of(OPERANDS, OPERATORS, 16_000))),
        ),
        ("deep_brackets.nc", around(&deep("(", ")", 63))),
        (
            "deep_signs_calls.nc",
            around(&format!(
                "{}\n{}",
                deep("-", "", 63),
                deep("SQRT(", ")", 63)
            )),
        ),
        (
            "deep_refused.nc",
            around(&format!("{}\n{}", deep("(", ")", 65), deep("[", "]", 2000))),
        ),
    ]
}

/// The seed programs, the seeds of long expressions (which must be on disk
/// as generated here: `ADDIPOS_WRITE_SEEDS=1` writes them), and the
/// fuzzer's saved findings (`fuzz/regressions/nc_program/`, when there
/// are any).
#[test]
fn seed_programs_and_saved_findings_pass_the_check() {
    for seed in SEEDS {
        nc_program(seed.as_bytes());
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let seeds = root.join("fuzz/seeds/nc_program");
    for (name, text) in expression_seeds() {
        assert!(text.len() <= 16 * 1024, "{name}: {} bytes", text.len());
        nc_program(text.as_bytes());
        let path = seeds.join(name);
        if std::env::var_os("ADDIPOS_WRITE_SEEDS").is_some() {
            std::fs::create_dir_all(&seeds).unwrap();
            std::fs::write(&path, &text).unwrap();
        }
        let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            on_disk == text,
            "{name}: not as generated (ADDIPOS_WRITE_SEEDS=1)"
        );
    }
    let dir = root.join("fuzz/regressions/nc_program");
    for entry in std::fs::read_dir(dir).into_iter().flatten() {
        let path = entry.unwrap().path();
        let name = path.display().to_string();
        if path
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("open-"))
        {
            continue;
        }
        let run = std::panic::catch_unwind(|| nc_program(&std::fs::read(&path).unwrap()));
        assert!(run.is_ok(), "nc_program fails on {name}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// The seed programs with a few words inserted, deleted or replaced,
    /// numbers and digits changed, lines repeated.
    #[test]
    fn mutated_seed_programs(seed in prop::sample::select(&SEEDS[..]), changes in prop::collection::vec(mutation(), 1..6)) {
        let mut words = words_of(seed);
        for m in &changes {
            apply(&mut words, m);
        }
        nc_program(text_of(&words).as_bytes());
    }

    /// Programs of the supported words, loops and conditions.
    #[test]
    fn programs_of_the_grammar(text in program()) {
        nc_program(text.as_bytes());
    }
}

proptest! {
    // A chain of 16 KB takes about a quarter of a second through the
    // check in a debug build (parsed four times, and run).
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// A flat chain of operators up to the harness's input limit on one
    /// line (it once overflowed the stack).
    #[test]
    fn long_flat_expressions(text in flat_chain()) {
        nc_program(text.as_bytes());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, ..ProptestConfig::default() })]

    /// Expressions nested about as deep as allowed, or deeper.
    #[test]
    fn deep_expressions(text in deep_nesting()) {
        nc_program(text.as_bytes());
    }

    /// Any bytes (invalid UTF-8, control characters, long lines).
    #[test]
    fn any_bytes(data in prop::collection::vec(any::<u8>(), 0..400)) {
        nc_program(&data);
    }
}
