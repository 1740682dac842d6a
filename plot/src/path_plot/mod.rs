//! The three paths of an NC program or a trace in one
//! plane, as SVG (`addipos plot`): the programmed contour (the motion requests' targets),
//! the corrected tool-centre path (the spooled elements) and the executed
//! path (the position of every interpolation cycle, OTC offset included).
//! Rapids are dashed; hovering over a piece shows its block. What a pixel
//! cannot show is left out, so that long programs draw in seconds.

use tc_request::{ArcDir, AxisPos, AxisWords, Motion, Request, SpoolRecord, AXES};

use crate::picture::{Plot, Stroke};
use emulator::Emulator;
use nc::nc_run::NcRun;
use trace::{fresh_emulator, Header, Trace};

mod points;

use points::{arc_points, thin};

/// Most executed positions kept (more are thinned out).
pub const MAX_EXECUTED_POINTS: usize = 200_000;
/// Most cycles stepped one by one; the rest of the run is executed at
/// once (its executed path then shows only where each EXEC ended).
pub const MAX_STEPPED_CYCLES: u64 = 5_000_000;
/// Width in pixels of the plotting area (as `picture` draws it).
const PLOT_PIXELS: f64 = 640.0;
/// Smallest change of direction worth a point, in pixels.
const PIXEL: f64 = 1.0;
/// Length in pixels up to which consecutive pieces are joined into one
/// polyline (its hover text then names the first and the last block).
const JOIN_PIXELS: f64 = 24.0;
/// How one of the three paths is drawn: colour, width in pixels, and the
/// dash of the executed path (its rapids are drawn with [`RAPID_DASH`]).
struct Look {
    colour: &'static str,
    width: f64,
    dash: &'static str,
}

/// The corrected tool-centre path: a wide light-blue band.
const CORRECTED: Look = Look {
    colour: "#8cf",
    width: 5.0,
    dash: "",
};
/// The programmed contour: a mid-grey line.
const PROGRAMMED: Look = Look {
    colour: "#666",
    width: 1.5,
    dash: "",
};
/// The executed path: a thin red dashed line, on top.
const EXECUTED: Look = Look {
    colour: "#d22",
    width: 1.2,
    dash: "5 3",
};
/// The dash of rapids on the programmed and the corrected path.
const RAPID_DASH: &str = "6 4";

/// Least extent along an axis that counts as motion along it (units).
const SPAN: f64 = 1e-9;

/// One request to plot, with where it came from (`N10 (line 3)`).
#[derive(Debug, Clone)]
pub struct PlotStep {
    /// Its block or line, shown on hover.
    pub label: String,
    /// The request.
    pub request: Request,
}

/// A piece of a path: the points of one element, from one block.
#[derive(Debug, Clone)]
pub struct Piece {
    /// Its block or line.
    pub label: String,
    /// A rapid move.
    pub rapid: bool,
    /// Its points in the plot's plane.
    pub points: Vec<[f64; 2]>,
}

/// The three paths of a run, in the plane `(h, v)` of machine axes.
#[derive(Debug, Clone, Default)]
pub struct Paths {
    /// The machine axes drawn horizontally and vertically.
    pub plane: [usize; 2],
    /// The programmed contour.
    pub programmed: Vec<Piece>,
    /// The corrected tool-centre path.
    pub corrected: Vec<Piece>,
    /// The executed positions, cycle by cycle (thinned out).
    pub executed: Vec<[f64; 2]>,
    /// Whether the cycle limit was reached (the rest was not stepped).
    pub truncated: bool,
}

/// The requests of an NC run, each with its block.
pub fn nc_steps(run: &NcRun) -> Vec<PlotStep> {
    run.exchanges
        .iter()
        .map(|x| PlotStep {
            label: match x.at.number {
                Some(n) => format!("N{n} (line {})", x.at.line),
                None => format!("line {}", x.at.line),
            },
            request: x.request.clone(),
        })
        .collect()
}

/// The requests of a trace, each with its line.
pub fn trace_steps(trace: &Trace) -> Vec<PlotStep> {
    trace
        .steps
        .iter()
        .map(|s| PlotStep {
            label: format!("line {}: {}", s.line, s.text),
            request: s.request.clone(),
        })
        .collect()
}

/// What a run records while its requests are carried out.
struct Recording {
    programmed: Vec<(String, bool, Vec<AxisPos>, Option<Arc3>)>,
    spooled: Vec<(String, SpoolRecord)>,
    executed: Vec<AxisPos>,
    eps: f64,
    cycles: u64,
}

/// A programmed arc: centre offsets I J K along the X Y Z axes and the
/// direction.
#[derive(Debug, Clone, Copy)]
struct Arc3 {
    centre: [Option<f64>; 3],
    ccw: bool,
}

impl Recording {
    /// Keeps `p` if it lies far enough from the last kept position;
    /// thins the whole record out when it grows too long.
    fn keep(&mut self, p: AxisPos) {
        if let Some(last) = self.executed.last() {
            if distance(last, &p) <= self.eps {
                return;
            }
        }
        self.executed.push(p);
        if self.executed.len() > MAX_EXECUTED_POINTS {
            self.eps = (self.eps * 2.0).max(1e-6);
            let eps = self.eps;
            let mut kept: Vec<AxisPos> = Vec::with_capacity(self.executed.len() / 2);
            for q in self.executed.drain(..) {
                if kept.last().is_none_or(|l| distance(l, &q) > eps) {
                    kept.push(q);
                }
            }
            self.executed = kept;
        }
    }
}

fn distance(a: &AxisPos, b: &AxisPos) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Runs the steps on a fresh emulator for `header`, stepping every EXEC
/// cycle by cycle, and returns the three paths.
pub fn collect_paths(header: &Header, steps: &[PlotStep]) -> Paths {
    collect_paths_with(header, steps, &mut |_| {})
}

/// [`collect_paths`], calling `done(k)` after each step with the number of
/// steps carried out so far (for a progress bar).
pub fn collect_paths_with(
    header: &Header,
    steps: &[PlotStep],
    done: &mut dyn FnMut(usize),
) -> Paths {
    let mut emu = fresh_emulator(header);
    let mut rec = Recording {
        programmed: Vec::new(),
        spooled: Vec::new(),
        executed: vec![header.start],
        eps: 0.0,
        cycles: 0,
    };
    let mut at = header.start;
    for (k, step) in steps.iter().enumerate() {
        if let Request::Motion(m) = &step.request {
            program_target(&mut rec, &mut at, &step.label, m);
        }
        match step.request {
            Request::Exec(n) => exec_stepped(&mut emu, &mut rec, n),
            ref r => {
                emu.run(r);
            }
        }
        for s in emu.take_spool_log() {
            rec.spooled.push((step.label.clone(), s));
        }
        done(k + 1);
    }
    let truncated = rec.cycles >= MAX_STEPPED_CYCLES;
    let axis_nr = emu.tc().axis_nr();
    project(rec, axis_nr, truncated)
}

/// Records the programmed target of a motion request.
fn program_target(rec: &mut Recording, at: &mut AxisPos, label: &str, m: &Motion) {
    let (words, rapid, arc): (&AxisWords, bool, Option<Arc3>) = match m {
        Motion::Lin { words, .. } => (words, false, None),
        Motion::Rap { words, .. } => (words, true, None),
        Motion::Cir {
            dir, words, centre, ..
        } => (
            words,
            false,
            Some(Arc3 {
                centre: *centre,
                ccw: *dir == ArcDir::Ccw,
            }),
        ),
        _ => return,
    };
    let start = *at;
    for (a, w) in at.iter_mut().zip(words) {
        if let Some(v) = w {
            *a = *v;
        }
    }
    rec.programmed
        .push((label.to_owned(), rapid, vec![start, *at], arc));
}

/// `EXEC n` (or until the spooler is empty) one cycle at a time, keeping
/// the position of each; past the cycle limit the rest runs at once.
fn exec_stepped(emu: &mut Emulator, rec: &mut Recording, n: Option<u64>) {
    let mut left = n;
    loop {
        if rec.cycles >= MAX_STEPPED_CYCLES {
            emu.exec(left);
            rec.keep(emu.position());
            return;
        }
        match left {
            Some(0) => return,
            Some(k) => left = Some(k - 1),
            None if emu.tc().spooler().is_empty() => {
                // Whatever EXEC still does with an empty spooler.
                emu.exec(None);
                rec.keep(emu.position());
                return;
            }
            None => {}
        }
        emu.exec(Some(1));
        rec.cycles += 1;
        rec.keep(emu.position());
    }
}

/// The plane drawn: that of the first spooled arc; else the axes
/// allocated as X and Y, unless the path spans only one of them while it
/// spans Z too (a program in X-Z without arcs, as the manuals' grinding
/// examples, or an OTC LENGTH offset along Z): then that axis and Z.
fn plane_of(rec: &Recording, axis_nr: [u8; 3]) -> [usize; 2] {
    let arc = rec.spooled.iter().find_map(|(_, s)| {
        s.arc
            .map(|a| [usize::from(a.plane[0]), usize::from(a.plane[1])])
    });
    let [x, y, z] = axis_nr.map(|a| usize::from(a).min(AXES - 1));
    arc.unwrap_or_else(|| match [x, y, z].map(|a| spans(rec, a)) {
        [true, false, true] => [x, z],
        [false, true, true] => [y, z],
        _ => [x, y],
    })
    .map(|a| a.min(AXES - 1))
}

/// Whether the programmed or the executed path moves along machine axis
/// `a`.
fn spans(rec: &Recording, a: usize) -> bool {
    let programmed = rec.programmed.iter().flat_map(|(_, _, ends, _)| ends);
    let mut along = programmed.chain(&rec.executed).map(|p| p[a]);
    let Some(first) = along.next() else {
        return false;
    };
    let (lo, hi) = along.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v)));
    hi - lo > SPAN
}

fn project(rec: Recording, axis_nr: [u8; 3], truncated: bool) -> Paths {
    let plane = plane_of(&rec, axis_nr);
    let flat = |p: &AxisPos| [p[plane[0]], p[plane[1]]];
    let programmed = rec
        .programmed
        .iter()
        .map(|(label, rapid, ends, arc)| {
            let (a, b) = (flat(&ends[0]), flat(&ends[1]));
            let points = match arc.and_then(|c| centre_in_plane(&c, a, plane, axis_nr)) {
                Some((centre, ccw)) => arc_points(a, b, centre, ccw),
                None => vec![a, b],
            };
            Piece {
                label: label.clone(),
                rapid: *rapid,
                points,
            }
        })
        .collect();
    let corrected = rec
        .spooled
        .iter()
        .map(|(label, s)| {
            let (a, b) = (flat(&s.start), flat(&s.end));
            let on_plane = s
                .arc
                .filter(|r| [usize::from(r.plane[0]), usize::from(r.plane[1])] == plane);
            Piece {
                label: label.clone(),
                rapid: s.rapid,
                points: match on_plane {
                    Some(r) => arc_points(a, b, r.centre, r.ccw),
                    None => vec![a, b],
                },
            }
        })
        .collect();
    Paths {
        plane,
        programmed,
        corrected,
        executed: rec.executed.iter().map(flat).collect(),
        truncated,
    }
}

/// The centre of a programmed arc in the plane, from its start and the
/// I J K offsets along the axes allocated as X Y Z (a missing offset is 0).
fn centre_in_plane(
    arc: &Arc3,
    start: [f64; 2],
    plane: [usize; 2],
    axis_nr: [u8; 3],
) -> Option<([f64; 2], bool)> {
    let offset = |axis: usize| {
        axis_nr
            .iter()
            .position(|&m| usize::from(m) == axis)
            .map(|k| arc.centre[k].unwrap_or(0.0))
    };
    Some((
        [start[0] + offset(plane[0])?, start[1] + offset(plane[1])?],
        arc.ccw,
    ))
}

/// Adds a path as pieces: consecutive pieces of the same kind are joined
/// until they are a few pixels long, so that tiny elements cost little;
/// the hover text names the blocks joined.
fn add_pieces(plot: &mut Plot, label: &str, look: &Look, pieces: &[Piece], eps: f64) {
    let solid = Stroke::solid(look.colour, look.width);
    let dashed = Stroke::dashed(look.colour, look.width * 0.8, RAPID_DASH);
    let flush = |plot: &mut Plot, run: &mut Vec<&Piece>| {
        let (Some(first), Some(last)) = (run.first(), run.last()) else {
            return;
        };
        let hover = if run.len() == 1 {
            first.label.clone()
        } else {
            format!("{} .. {}", first.label, last.label)
        };
        let points: Vec<[f64; 2]> = run.iter().flat_map(|p| p.points.iter().copied()).collect();
        let stroke = if first.rapid { &dashed } else { &solid };
        let name = if first.rapid {
            format!("{label}, rapid")
        } else {
            label.to_owned()
        };
        plot.piece(&name, stroke.clone(), thin(&points, eps), Some(hover));
        run.clear();
    };
    let mut run: Vec<&Piece> = Vec::new();
    let mut length = 0.0;
    for p in pieces {
        if run.first().is_some_and(|f| f.rapid != p.rapid) || length > JOIN_PIXELS * eps {
            flush(plot, &mut run);
            length = 0.0;
        }
        length += p
            .points
            .windows(2)
            .map(|w| (w[0][0] - w[1][0]).hypot(w[0][1] - w[1][1]))
            .sum::<f64>();
        run.push(p);
    }
    flush(plot, &mut run);
}

/// The paths as an SVG picture titled `title`.
pub fn render(paths: &Paths, title: &str) -> String {
    let b = bounds(paths);
    let extent = if b[0] > b[2] {
        1.0
    } else {
        (b[2] - b[0]).max(b[3] - b[1]).max(1e-9)
    };
    let eps = PIXEL * extent / PLOT_PIXELS;
    let names = tc_request::AXIS_NAMES;
    let (h, v) = (names[paths.plane[0]], names[paths.plane[1]]);
    let mut plot = Plot::new(title).axes(&h.to_string(), &v.to_string());
    // Where the paths coincide (no correction, no OTC) all three stay in
    // sight: the corrected path a wide light band underneath, the
    // programmed contour a mid-width line on it, the executed path dashed
    // on top (decision 318).
    add_pieces(
        &mut plot,
        "corrected tool centre (spooled)",
        &CORRECTED,
        &paths.corrected,
        eps,
    );
    add_pieces(
        &mut plot,
        "programmed contour",
        &PROGRAMMED,
        &paths.programmed,
        eps,
    );
    plot.piece(
        "executed path (cycle by cycle, OTC offset included)",
        Stroke::dashed(EXECUTED.colour, EXECUTED.width, EXECUTED.dash),
        thin(&paths.executed, eps),
        None,
    );
    if paths.truncated {
        plot = plot.note(&format!(
            "only the first {MAX_STEPPED_CYCLES} cycles are drawn one by one"
        ));
    }
    plot.note("hover over a piece for its block; rapids dashed")
        .to_svg()
}

/// Bounds of every point: min h, min v, max h, max v.
pub fn bounds(paths: &Paths) -> [f64; 4] {
    let all = paths
        .programmed
        .iter()
        .chain(&paths.corrected)
        .flat_map(|p| &p.points)
        .chain(&paths.executed);
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in all {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    b
}
