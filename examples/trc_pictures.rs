//! Draws one SVG per transition type into `docs/img/` (used by docs/trc.md):
//! the programmed contour in grey, the corrected path in blue, inserted
//! transition elements in red, the approach in green.
//!
//! Run: `cargo run --example trc_pictures`

#![allow(clippy::panic)]

use std::fmt::Write as _;

use emulator::Emulator;
use tc_module::{Logged, Origin, SpoolElement};
use tc_request::Reply;
use trace::parse_trace;

struct Picture {
    file: &'static str,
    title: &'static str,
    side: &'static str,
    linear: bool,
    program: &'static str,
}

const PICTURES: &[Picture] = &[
    Picture {
        file: "outside-circular",
        title: "outside corner, TransitionMode 0: arc about the corner",
        side: "Left",
        linear: false,
        program: "LIN X4 Y0\nLIN X10 Y0\nLIN X10 Y-10",
    },
    Picture {
        file: "outside-linear-90",
        title: "outside corner <= 90°, TransitionMode 1: two lines",
        side: "Left",
        linear: true,
        program: "LIN X4 Y0\nLIN X10 Y0\nLIN X10 Y-10",
    },
    Picture {
        file: "outside-linear-135",
        title: "outside corner > 90°, TransitionMode 1: three lines",
        side: "Left",
        linear: true,
        program: "LIN X4 Y0\nLIN X10 Y0\nLIN X0 Y-10",
    },
    Picture {
        file: "inside-line-line",
        title: "inside corner: offsets cut at their intersection",
        side: "Left",
        linear: false,
        program: "LIN X4 Y0\nLIN X10 Y0\nLIN X10 Y10",
    },
    Picture {
        file: "inside-line-arc",
        title: "inside corner of a line and an arc",
        side: "Left",
        linear: false,
        program: "LIN X4 Y0\nLIN X10 Y0\nCIR CW X20 Y10 I10 J0",
    },
    Picture {
        file: "approach-arc",
        title: "approach with an arc, then a tangent line (nothing inserted)",
        side: "Left",
        linear: false,
        program: "CIR CCW X0 Y20 I0 J10\nLIN X-10 Y20",
    },
];

fn run(program: &str, correction: Option<(&str, bool)>) -> Vec<Logged> {
    let mut text = String::new();
    if let Some((side, linear)) = correction {
        let sub = if side == "Left" { 9 } else { 10 };
        let _ = writeln!(
            text,
            "W 1300/1/1/6 d 2\nW 1300/1/1/{sub} i 0\nW 1300/2/1/1 i {}\nW 1300/1/1/3 i 1",
            i32::from(linear)
        );
    }
    text.push_str(program);
    text.push('\n');
    if correction.is_some() {
        text.push_str("W 1300/1/1/3 i 0\n");
    }
    let trace = match parse_trace("picture", &text) {
        Ok(t) => t,
        Err(e) => panic!("picture program: {e}"),
    };
    let mut emu = Emulator::default();
    emu.set_spool_log(true);
    for step in &trace.steps {
        let reply = emu.run(&step.request);
        assert_eq!(reply, Reply::Ok, "picture program: {}", step.text);
    }
    emu.tc_mut().spooler_mut().take_log()
}

fn polyline(l: &Logged) -> Vec<[f64; 2]> {
    let e = &l.element;
    let n = if matches!(e.path(), tc_module::Path::Arc(_)) {
        48
    } else {
        1
    };
    (0..=n)
        .map(|k| {
            let p = e.point_at(&l.start, &l.end, e.length() * k as f64 / n as f64);
            [p[0], p[1]]
        })
        .collect()
}

fn svg(p: &Picture) -> String {
    let plain = run(p.program, None);
    let corrected = run(p.program, Some((p.side, p.linear)));
    let all: Vec<[f64; 2]> = plain.iter().chain(&corrected).flat_map(polyline).collect();
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for q in &all {
        x0 = x0.min(q[0]);
        y0 = y0.min(q[1]);
        x1 = x1.max(q[0]);
        y1 = y1.max(q[1]);
    }
    let (w, h, pad) = (460.0, 300.0, 30.0);
    let s = ((w - 2.0 * pad) / (x1 - x0).max(1e-9)).min((h - 2.0 * pad) / (y1 - y0).max(1e-9));
    let tx = |q: [f64; 2]| ((q[0] - x0) * s + pad, h - ((q[1] - y0) * s + pad));
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{}" viewBox="0 0 {w} {}">"#,
        h + 24.0,
        h + 24.0
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        out,
        r#"<text x="8" y="{}" font-family="sans-serif" font-size="11">{} ({}, r = 2)</text>"#,
        h + 16.0,
        p.title,
        p.side
    );
    let mut draw = |els: &[Logged], colour: &dyn Fn(&SpoolElement) -> &'static str, width: f64| {
        for e in els {
            let pts: Vec<String> = polyline(e)
                .into_iter()
                .map(|q| {
                    let (x, y) = tx(q);
                    format!("{x:.2},{y:.2}")
                })
                .collect();
            let _ = writeln!(
                out,
                r#"<polyline fill="none" stroke="{}" stroke-width="{width}" points="{}"/>"#,
                colour(&e.element),
                pts.join(" ")
            );
        }
    };
    draw(&plain, &|_| "#bbb", 4.0);
    let colour = |e: &SpoolElement| -> &'static str {
        match e.origin() {
            Origin::Approach => "#2a2",
            Origin::Transition => "#d22",
            _ => "#24c",
        }
    };
    draw(&corrected, &colour, 2.0);
    out.push_str("</svg>\n");
    out
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/img");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        std::process::exit(1);
    }
    for p in PICTURES {
        let path = dir.join(format!("{}.svg", p.file));
        if let Err(e) = std::fs::write(&path, svg(p)) {
            eprintln!("cannot write {}: {e}", path.display());
            std::process::exit(1);
        }
        println!("wrote {}", path.display());
    }
}
