//! Offsetting one open contour with this engine and with the crate
//! `cavalier_contours`: segments per second at 1k, 10k, 100k and 1M
//! segments, and the ratio ours ÷ cavalier's raw offset step from the
//! same run (printed as a table at the end).
//!
//! The contour is a saw-tooth along +X that alternates a sharp tooth (two
//! flanks) and a rounded one (flank, CW fillet tangent to both flanks,
//! flank). The tool runs on the left (above), so every valley is an inside
//! corner, every sharp tip an outside corner (circular transition, like
//! cavalier's round joins) and the fillets are tangent (smooth corners).
//! Both inputs come from the one description in [`saw_tooth`]: vertices
//! with bulge for cavalier, LIN / CIR with centre offsets for us.
//!
//! Rows:
//! * `ours/buffer`: `Buffer::push` through a `Sink` into a `Spooler` that
//!   is emptied every [`DRAIN`] profiles as an executor would;
//! * `ours/command`: the whole `TcModule::command` path (intake, rotation,
//!   correction, spooler), emptied the same way;
//! * `cavalier 0.9` (newest) and `cavalier 0.7` (the API the
//!   first comparison used: `pline_offset::create_raw_offset_polyline`): `parallel_offset`
//!   and the raw offset step alone (offset pieces joined corner by corner,
//!   no self-intersection clean-up).

#![allow(missing_docs, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use cavalier_contours::polyline::internal::raw_pline_offset::create_raw_offset;
use cavalier_contours::polyline::{PlineCreation, PlineSource, PlineSourceMut, Polyline};
use cavalier_contours_07::polyline::internal::pline_offset::create_raw_offset_polyline;
use cavalier_contours_07::polyline::{
    PlineCreation as PlineCreation07, PlineSource as PlineSource07,
    PlineSourceMut as PlineSourceMut07, Polyline as Polyline07,
};
use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput};
use tc_module::correction::{Buffer, Contour, Profile, Sink};
use tc_module::V2;
use tc_module::{ArcDir, Motion, PlaneAxes, Spooler, TcModule, TransitionMode, AXES};
use tc_objects::TcObject;
use uoi::{ObjectBus, Value};

/// Segment counts of the contour.
const SIZES: [usize; 4] = [1_000, 10_000, 100_000, 1_000_000];
/// Tooth pitch along X and tooth height.
const PITCH: f64 = 10.0;
const HEIGHT: f64 = 10.0;
/// Fillet radius at the tip of a rounded tooth.
const FILLET: f64 = 1.0;
/// Tool radius, left of the contour: cavalier's positive offset is to the
/// left too. A valley (53° opening) takes it 2·r up each flank.
const RADIUS: f64 = 0.5;
/// The spooler is emptied (all but the element under way) this often.
const DRAIN: usize = 1024;
const FEED: f64 = 6000.0;
const XY: PlaneAxes = PlaneAxes {
    h: 0,
    v: 1,
    third: 2,
};

/// One segment of the contour: to `to`, straight or about a centre.
#[derive(Debug, Clone, Copy)]
struct Step {
    to: [f64; 2],
    /// Centre and direction (counter-clockwise?) of an arc.
    arc: Option<([f64; 2], bool)>,
}

/// The saw-tooth of `segments` segments from the origin: pairs of a sharp
/// tooth (2 segments) and a rounded tooth (3 segments).
fn saw_tooth(segments: usize) -> Vec<Step> {
    let line = |x: f64, y: f64| Step {
        to: [x, y],
        arc: None,
    };
    // Fillet tangent to both flanks: centre on the tip's bisector.
    let half = (PITCH / 2.0).atan2(HEIGHT); // half opening angle at the tip
    let flank = (PITCH / 2.0).hypot(HEIGHT);
    let (ux, uy) = (PITCH / 2.0 / flank, HEIGHT / flank);
    let back = FILLET / half.tan(); // tip to tangent point, along a flank
    let drop = FILLET / half.sin(); // tip to fillet centre
    let mut out = Vec::with_capacity(segments);
    let mut x0 = 0.0;
    while out.len() < segments {
        let tip = x0 + PITCH / 2.0;
        out.push(line(tip, HEIGHT));
        out.push(line(x0 + PITCH, 0.0));
        let (x1, tip) = (x0 + PITCH, x0 + 1.5 * PITCH);
        out.push(line(tip - back * ux, HEIGHT - back * uy));
        out.push(Step {
            to: [tip + back * ux, HEIGHT - back * uy],
            arc: Some(([tip, HEIGHT - drop], false)),
        });
        out.push(line(x1 + PITCH, 0.0));
        x0 += 2.0 * PITCH;
    }
    out.truncate(segments);
    out
}

/// Signed sweep of an arc from `s` to `e` about `c` (positive CCW).
fn sweep(s: [f64; 2], e: [f64; 2], c: [f64; 2], ccw: bool) -> f64 {
    let (u, w) = ([s[0] - c[0], s[1] - c[1]], [e[0] - c[0], e[1] - c[1]]);
    let a = (u[0] * w[1] - u[1] * w[0]).atan2(u[0] * w[0] + u[1] * w[1]);
    match (ccw, a > 0.0) {
        (true, false) => a + TAU,
        (false, true) => a - TAU,
        _ => a,
    }
}

/// Vertices `(x, y, bulge)` of the contour, bulge = tan(sweep / 4).
fn vertices(steps: &[Step]) -> Vec<(f64, f64, f64)> {
    let mut at = [0.0, 0.0];
    let mut out = Vec::with_capacity(steps.len() + 1);
    for s in steps {
        let bulge = s
            .arc
            .map_or(0.0, |(c, ccw)| (sweep(at, s.to, c, ccw) / 4.0).tan());
        out.push((at[0], at[1], bulge));
        at = s.to;
    }
    out.push((at[0], at[1], 0.0));
    out
}

fn pos(p: [f64; 2]) -> [f64; AXES] {
    let mut a = [0.0; AXES];
    a[0] = p[0];
    a[1] = p[1];
    a
}

/// The profiles as they enter the one-profile buffer.
fn profiles(steps: &[Step]) -> Vec<Profile> {
    let mut at = [0.0, 0.0];
    let mut out = Vec::with_capacity(steps.len());
    for s in steps {
        let (from, to) = (V2::new(at[0], at[1]), V2::new(s.to[0], s.to[1]));
        let contour = match s.arc {
            None => Contour::Line { from, to },
            Some((c, ccw)) => Contour::Arc {
                from,
                to,
                centre: V2::new(c[0], c[1]),
                sigma: if ccw { 1.0 } else { -1.0 },
            },
        };
        out.push(Profile {
            contour,
            start: pos(at),
            end: pos(s.to),
            feed: FEED,
            arc_feed: FEED,
            rapid: false,
        });
        at = s.to;
    }
    out
}

/// The same contour as LIN / CIR commands (centre offsets I J from the start).
fn motions(steps: &[Step]) -> Vec<Motion> {
    let mut at = [0.0, 0.0];
    let mut out = Vec::with_capacity(steps.len());
    for (i, s) in steps.iter().enumerate() {
        let mut words = [None; AXES];
        words[0] = Some(s.to[0]);
        words[1] = Some(s.to[1]);
        let feed = (i == 0).then_some(FEED);
        out.push(match s.arc {
            None => Motion::Lin { words, feed },
            Some((c, ccw)) => Motion::Cir {
                dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                words,
                centre: [Some(c[0] - at[0]), Some(c[1] - at[1]), None],
                feed,
            },
        });
        at = s.to;
    }
    out
}

fn polyline(v: &[(f64, f64, f64)]) -> Polyline<f64> {
    let mut p = Polyline::with_capacity(v.len(), false);
    for &(x, y, b) in v {
        p.add(x, y, b);
    }
    p
}

fn polyline_07(v: &[(f64, f64, f64)]) -> Polyline07<f64> {
    let mut p = Polyline07::with_capacity(v.len(), false);
    for &(x, y, b) in v {
        p.add(x, y, b);
    }
    p
}

/// What an executor leaves: the element under way.
fn drain(sp: &mut Spooler) {
    while sp.len() > 1 {
        sp.pop_front();
    }
}

/// Ours through the one-profile buffer; returns the spooler for checks.
fn run_buffer(profiles: &[Profile], spooler: &mut Spooler) {
    let mut buffer = Buffer::default();
    let mut sink = Sink::new(spooler, [0.0; AXES], XY, 0.0);
    for (i, p) in profiles.iter().enumerate() {
        buffer
            .push(p, RADIUS, TransitionMode::Circular, &mut sink)
            .expect("the saw-tooth corrects");
        if i % DRAIN == DRAIN - 1 {
            drain(sink.spooler());
        }
    }
    buffer.flush(&mut sink);
}

/// A module with group 1 running on the left, tool radius [`RADIUS`],
/// circular transitions.
fn running_module() -> TcModule {
    let mut tc = TcModule::default();
    for (addr, v) in [
        (TcObject::WkzIndex.of(1), Value::I32(1)),
        (TcObject::Radius.of(1), Value::F64(RADIUS)),
        (TcObject::Left.of(1), Value::I32(0)),
        (TcObject::TransitionMode.of(1), Value::I32(0)),
        (TcObject::Status.of(1), Value::I32(1)),
    ] {
        tc.write_checked(addr, v).expect("setup write");
    }
    tc
}

fn run_command(tc: &mut TcModule, motions: &[Motion]) {
    for (i, m) in motions.iter().enumerate() {
        tc.command(m).expect("accepted");
        if i % DRAIN == DRAIN - 1 {
            drain(tc.spooler_mut());
        }
    }
}

/// Per-iteration times of every sample, by (size, row).
static SAMPLES: Mutex<BTreeMap<(usize, &'static str), Vec<f64>>> = Mutex::new(BTreeMap::new());

fn record(size: usize, row: &'static str, per_iter: f64) {
    let mut s = SAMPLES.lock().unwrap();
    s.entry((size, row)).or_default().push(per_iter);
}

/// Times `iters` runs of `run` (after `setup`, which is not timed) and
/// records the time per run.
fn timed<S, T>(
    size: usize,
    row: &'static str,
    iters: u64,
    mut setup: impl FnMut() -> S,
    mut run: impl FnMut(&mut S) -> T,
) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..iters {
        let mut s = setup();
        let t = Instant::now();
        let out = black_box(run(&mut s));
        total += t.elapsed();
        drop(out);
        drop(s);
    }
    record(size, row, total.as_secs_f64() / iters as f64);
    total
}

/// Both engines end on the offset of the last programmed point.
fn check_same_contour(steps: &[Step]) {
    let mut sp = Spooler::default();
    run_buffer(&profiles(steps), &mut sp);
    let ours = sp.last_end().expect("spooled");
    let raw: Polyline<f64> = create_raw_offset(&polyline(&vertices(steps)), RADIUS, 1e-5).polyline;
    let last = raw.last().expect("offset");
    let dist = (ours[0] - last.x).hypot(ours[1] - last.y);
    assert!(dist < 1e-9, "end points differ by {dist}");
}

const ROWS: [&str; 6] = [
    "ours/buffer",
    "ours/command",
    "cavalier 0.9/parallel_offset",
    "cavalier 0.9/raw offset",
    "cavalier 0.7/parallel_offset",
    "cavalier 0.7/raw offset",
];

fn bench_size(c: &mut Criterion, n: usize) {
    let steps = saw_tooth(n);
    check_same_contour(&steps);
    let (profiles, motions) = (profiles(&steps), motions(&steps));
    let v = vertices(&steps);
    let (pl, pl07) = (polyline(&v), polyline_07(&v));
    let mut g = c.benchmark_group("offset saw-tooth");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(if n >= 100_000 { 10 } else { 20 });
    g.sampling_mode(SamplingMode::Flat);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(3));
    let id = |row| BenchmarkId::new(row, n);
    g.bench_function(id(ROWS[0]), |b| {
        b.iter_custom(|it| {
            timed(n, ROWS[0], it, Spooler::default, |sp| {
                run_buffer(&profiles, sp)
            })
        })
    });
    g.bench_function(id(ROWS[1]), |b| {
        b.iter_custom(|it| {
            timed(n, ROWS[1], it, running_module, |tc| {
                run_command(tc, &motions)
            })
        })
    });
    g.bench_function(id(ROWS[2]), |b| {
        b.iter_custom(|it| timed(n, ROWS[2], it, || (), |_| pl.parallel_offset(RADIUS)))
    });
    g.bench_function(id(ROWS[3]), |b| {
        b.iter_custom(|it| {
            timed(
                n,
                ROWS[3],
                it,
                || (),
                |_| create_raw_offset::<_, _, Polyline<f64>>(&pl, RADIUS, 1e-5),
            )
        })
    });
    g.bench_function(id(ROWS[4]), |b| {
        b.iter_custom(|it| timed(n, ROWS[4], it, || (), |_| pl07.parallel_offset(RADIUS)))
    });
    g.bench_function(id(ROWS[5]), |b| {
        b.iter_custom(|it| {
            timed(
                n,
                ROWS[5],
                it,
                || (),
                |_| create_raw_offset_polyline::<_, _, Polyline07<f64>>(&pl07, RADIUS, 1e-5),
            )
        })
    });
    g.finish();
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Segments per second (median of the samples) of every row, and ours
/// (buffer) ÷ each raw offset step.
fn print_table() {
    let mut s = SAMPLES.lock().unwrap();
    println!("\nsegments/s (median of samples), ratio = ours/buffer ÷ raw offset step");
    println!(
        "{:>9} {}",
        "segments",
        ROWS.map(|r| format!("{r:>29}")).join("")
    );
    for n in SIZES {
        let mut rate = [f64::NAN; ROWS.len()];
        for (i, row) in ROWS.iter().enumerate() {
            if let Some(v) = s.get_mut(&(n, *row)) {
                rate[i] = n as f64 / median(v);
            }
        }
        let cells: String = rate.iter().map(|r| format!("{:>29.3e}", r)).collect();
        println!("{n:>9} {cells}");
        println!(
            "{:>9} ratio vs raw 0.9: {:.2}   vs raw 0.7: {:.2}",
            "",
            rate[0] / rate[3],
            rate[0] / rate[5]
        );
    }
}

/// One pass of one row for an instruction count, not a timing:
/// `OFFSET_ONCE=buffer:100000` (or `command:`, `raw09:`, `raw07:`) runs
/// it once and exits. Under `valgrind --tool=callgrind
/// --toggle-collect=*once_*` only the pass itself is counted; the
/// difference of two sizes divided by their difference is the count per
/// segment.
fn run_once(spec: &str) {
    let (row, n) = spec.split_once(':').expect("OFFSET_ONCE=row:segments");
    let n: usize = n.parse().expect("segments");
    let bytes = std::mem::size_of::<tc_module::SpoolElement>();
    eprintln!("a spool element takes {bytes} bytes");
    let steps = saw_tooth(n);
    match row {
        "buffer" => {
            let profiles = profiles(&steps);
            let mut sp = Spooler::default();
            once_buffer(&profiles, &mut sp);
            println!("{:?}", sp.last_end().map(|p| [p[0], p[1]]));
        }
        "command" => {
            let motions = motions(&steps);
            let mut tc = running_module();
            once_command(&mut tc, &motions);
            println!("{:?}", tc.tool_position()[..2].to_vec());
        }
        "raw09" => {
            let pl = polyline(&vertices(&steps));
            println!("{}", once_raw09(&pl));
        }
        "raw07" => {
            let pl = polyline_07(&vertices(&steps));
            println!("{}", once_raw07(&pl));
        }
        _ => panic!("row {row}: buffer, command, raw09 or raw07"),
    }
}

#[inline(never)]
fn once_buffer(profiles: &[Profile], sp: &mut Spooler) {
    run_buffer(profiles, sp);
}

#[inline(never)]
fn once_command(tc: &mut TcModule, motions: &[Motion]) {
    run_command(tc, motions);
}

#[inline(never)]
fn once_raw09(pl: &Polyline<f64>) -> usize {
    create_raw_offset::<_, _, Polyline<f64>>(pl, RADIUS, 1e-5)
        .polyline
        .vertex_count()
}

#[inline(never)]
fn once_raw07(pl: &Polyline07<f64>) -> usize {
    create_raw_offset_polyline::<_, _, Polyline07<f64>>(pl, RADIUS, 1e-5).vertex_count()
}

fn main() {
    if let Ok(spec) = std::env::var("OFFSET_ONCE") {
        run_once(&spec);
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    for n in SIZES {
        bench_size(&mut c, n);
    }
    c.final_summary();
    print_table();
}
