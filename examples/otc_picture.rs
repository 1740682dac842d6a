//! Draws `docs/otc-path.svg` (used by docs/otc.md): a contour ground with
//! the radius correction, executed once without OTC and once with OTC
//! RADIUS AUTO, the executed position recorded every interpolation cycle.
//! The wear is exaggerated so that it shows at the picture's scale.
//!
//! Run: `cargo run --example otc_picture`. `tests/docs.rs` checks that the
//! committed picture is what this code draws.

use emulator::Emulator;
use plot::{Plot, Stroke};
use tc_request::{Reply, Request};
use trace::{fresh_emulator, parse_trace};

/// Where the picture is written, relative to the repository.
pub const PICTURE: &str = "docs/otc-path.svg";

/// The machine's start position.
const START: &str = "@start X-10 Y0\n";

/// Tool 1 of group 1: a grinding disc of radius 5; OTC RADIUS AUTO with a
/// wear constant of 5 µm per mm of path (50000 × 0.1 µm/m) and the PLC's
/// channel unit enabled (its command follows during the run).
const TOOL: &str = "W 1300/1/1/8 i 1
W 1300/1/1/6 d 5
W 1300/3/1/30 i 2
W 1300/3/1/32 d 10000
W 1300/3/1/2 i 0
W 1300/3/1/3 i 2
W 1300/3/1/4 d 50000
W 1300/3/1/6 i 100
W 1300/3/1/51 i 1
";

/// G42: the tool outside the part, which is traversed counter-clockwise.
const CORRECTION_ON: &str = "W 1300/1/1/10 i 0\nW 1300/1/1/3 i 1\n";

/// `#OTC ON`.
const OTC_ON: &str = "W 1300/3/1/1 i 1\n";

/// The part: a bottom edge, an outside corner, a rounded corner, a step
/// with an inside corner.
const CONTOUR: &str = "LIN X0 Y0 F6000
LIN X40 Y0
LIN X40 Y15
CIR CCW X30 Y25 I-10 J0
LIN X10 Y25
LIN X10 Y35
LIN X0 Y35
";

/// G40, then the departure.
const CORRECTION_OFF: &str = "W 1300/1/1/3 i 0\n";
const DEPARTURE: &str = "LIN X-10 Y35\n";

/// Execution: after 700 cycles (on the right edge) the PLC asks for a
/// 0.5 mm radius offset, ramped at 1 µm per cycle (AccWeight 100).
const RUN: &str = "EXEC 700\nW 1300/3/1/50 i 5000\nEXEC\n";

/// Why the picture could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PictureError {
    /// A program line is malformed.
    #[error(transparent)]
    Trace(#[from] trace::TraceError),
    /// A request was not answered as the picture expects.
    #[error("`{request}` answered {reply:?}")]
    Refused {
        /// The request, as written.
        request: String,
        /// What the emulator answered.
        reply: Reply,
    },
}

/// Runs a program and records the executed position (X, Y) before the
/// first cycle and after every cycle.
fn executed_path(program: &str) -> Result<Vec<[f64; 2]>, PictureError> {
    let trace = parse_trace("otc-picture", program)?;
    let mut emu = fresh_emulator(&trace.header);
    emu.set_spool_log(false);
    let mut path = vec![plane(&emu)];
    for step in &trace.steps {
        match step.request {
            Request::Exec(Some(n)) => {
                for _ in 0..n {
                    emu.exec(Some(1));
                    path.push(plane(&emu));
                }
            }
            Request::Exec(None) => {
                while emu.queue_len() > 0 {
                    emu.exec(Some(1));
                    path.push(plane(&emu));
                }
            }
            ref request => match emu.run(request) {
                Reply::Ok | Reply::Value(_) => {}
                reply => {
                    return Err(PictureError::Refused {
                        request: step.text.clone(),
                        reply,
                    })
                }
            },
        }
    }
    Ok(path)
}

fn plane(emu: &Emulator) -> [f64; 2] {
    let p = emu.position();
    [p[0], p[1]]
}

/// The picture as SVG text.
pub fn otc_path_svg() -> Result<String, PictureError> {
    let programmed = executed_path(&[START, CONTOUR, DEPARTURE, RUN].concat())?;
    let corrected = [
        START,
        TOOL,
        CORRECTION_ON,
        CONTOUR,
        CORRECTION_OFF,
        DEPARTURE,
    ];
    let without = executed_path(&[&corrected[..], &[RUN]].concat().concat())?;
    let with = executed_path(&[&corrected[..], &[OTC_ON, RUN]].concat().concat())?;
    Ok(Plot::new("OTC RADIUS: executed path with and without the wear offset")
        .axes("X [mm]", "Y [mm]")
        .line("programmed contour", Stroke::solid("#bbb", 4.0), programmed)
        .line(
            "tool centre, radius correction only (no OTC)",
            Stroke::dashed("#24c", 1.5, "6 3"),
            without,
        )
        .line("tool centre with OTC RADIUS AUTO", Stroke::solid("#d22", 1.5), with)
        .note("Tool radius 5 mm, right of the contour (G42), feed 6000 mm/min, 1 ms cycle; POS every cycle.")
        .note("Wear exaggerated: WearConst 50000 (5 µm per mm of path); PLC radius offset 0.5 mm from cycle 700, AccWeight 100.")
        .to_svg())
}

fn main() {
    let svg = match otc_path_svg() {
        Ok(svg) => svg,
        Err(e) => {
            eprintln!("cannot draw the picture: {e}");
            std::process::exit(1);
        }
    };
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(PICTURE);
    if let Err(e) = std::fs::write(&path, svg) {
        eprintln!("cannot write {}: {e}", path.display());
        std::process::exit(1);
    }
    println!("wrote {}", path.display());
}
