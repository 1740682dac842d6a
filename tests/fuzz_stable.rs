//! The fuzz targets on stable (docs/fuzzing.md): the checks of
//! `fuzz_checks` run on the seed corpus, on the saved
//! regressions, and on a bounded number of proptest cases each, so that
//! `cargo test` keeps them exercised without nightly or libFuzzer.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::Path;

use bytes::{Bytes, BytesMut};
use fuzz_checks::{
    frame_decoder, frame_sequence, request_stream, serve_stream, trace_line, Connection,
};
use otc_ext::OtcExtension;
use proptest::prelude::*;
use tc_module::object_map::object_table;
use tc_module::MAX_COORD;
use tc_objects::TcObject;
use tc_request::{ArcDir, Motion, Request, AXES};
use tokio_util::codec::Encoder;
use trace::MAX_LINE_BYTES;
use uoi::wire::{ClientCodec, Request as WireRequest};
use uoi::{ObjectAddress, Value, ValueType};

/// Cases per target: enough to reach past the first checks of every op,
/// few enough that the three run in seconds in a debug build.
const CASES: u32 = 2_000;

/// The files of `dir` (none when it does not exist), sorted.
fn files(dir: &str) -> Vec<(String, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut out: Vec<(String, Vec<u8>)> = entries
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
        .collect();
    out.sort();
    out
}

/// Runs `check` on every file of the seed corpus and the regressions of
/// `target`, and of `extra`; how many it ran.
fn run_files(target: &str, extra: &[&str], check: fn(&[u8])) -> usize {
    let seeds = format!("fuzz/seeds/{target}");
    let regressions = format!("fuzz/regressions/{target}");
    let mut n = 0;
    for dir in [seeds.as_str(), regressions.as_str()].iter().chain(extra) {
        for (name, bytes) in files(dir) {
            let run = std::panic::catch_unwind(|| check(&bytes));
            assert!(run.is_ok(), "{target} fails on {name}");
            n += 1;
        }
    }
    n
}

#[test]
fn seed_corpus_and_regressions_pass() {
    assert!(run_files("frame_decoder", &[], frame_decoder) > 0);
    assert!(run_files("frame_sequence", &[], frame_sequence) > 0);
    assert!(run_files("trace_line", &["traces"], trace_line) > 0);
}

/// Found by `frame_sequence` (60 s smoke run): RADIUS -1.68e212 was
/// taken, and a corrected `LIN X8 Y0` spooled an end at Y -1.68e212.
/// Fixed by the ranges of RADIUS, WkzLen and the rotation centre and the
/// limit on what enters the spooler.
#[test]
fn radius_beyond_the_coordinate_limit() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions/frame_sequence");
    let bytes = std::fs::read(dir.join("radius-beyond-coordinate-limit.bin")).unwrap();
    serve_stream(&bytes, &mut Connection::default());
}

#[test]
fn a_line_past_the_reader_limit_and_invalid_utf8() {
    let mut text = b"R 1300/0/3/0 i => 17\n".to_vec();
    text.extend(std::iter::repeat_n(b'X', MAX_LINE_BYTES + 1));
    trace_line(&text);
    trace_line(b"LIN X1\n< LIN X\xff1\nPOS\n");
}

/// Coordinates: mostly small, sometimes at or past the limits, or not
/// finite.
fn coord() -> BoxedStrategy<f64> {
    prop_oneof![
        8 => (-50i32..50).prop_map(f64::from),
        4 => -100.0..100.0f64,
        1 => prop::sample::select(vec![
            MAX_COORD,
            -MAX_COORD,
            MAX_COORD * 1.5,
            1e12,
            -1e100,
            1e300,
            -0.0,
            1e-300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]),
        1 => any::<f64>(),
    ]
    .boxed()
}

fn words() -> BoxedStrategy<[Option<f64>; AXES]> {
    prop::array::uniform8(prop::option::weighted(0.3, coord())).boxed()
}

fn feed() -> BoxedStrategy<Option<f64>> {
    prop::option::weighted(0.3, prop_oneof![1.0..5000.0f64, coord()]).boxed()
}

fn motion() -> BoxedStrategy<Motion> {
    prop_oneof![
        (words(), feed()).prop_map(|(words, feed)| Motion::Lin { words, feed }),
        (words(), feed()).prop_map(|(words, feed)| Motion::Rap { words, feed }),
        (
            any::<bool>(),
            words(),
            prop::array::uniform3(prop::option::weighted(0.6, coord())),
            feed()
        )
            .prop_map(|(ccw, words, centre, feed)| Motion::Cir {
                dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                words,
                centre,
                feed,
            }),
        words().prop_map(|words| Motion::Ja { words }),
        prop::array::uniform8(any::<bool>()).prop_map(|axes| Motion::Js { axes }),
        (0u8..AXES as u8, prop_oneof![Just(2001), any::<i32>()])
            .prop_map(|(axis, function)| Motion::Ssf { axis, function }),
        Just(Motion::Rs),
    ]
    .boxed()
}

/// The address of bus 1300 at `device`, `index`, `sub`: Clean's address
/// with those replaced (docs/decisions.md, decision 522).
fn on_the_bus(device: u16, index: u16, sub: u16) -> ObjectAddress {
    ObjectAddress {
        device,
        index,
        sub,
        ..TcObject::Clean.address()
    }
}

/// A write or read of an object of the emulator's map (of the first
/// groups), with a value of its type mostly; now and then any address.
fn access() -> BoxedStrategy<Request> {
    // Each object at each of its subindices, in the first three groups.
    let rows: Vec<(u16, u16, u16, ValueType)> = object_table::<OtcExtension>()
        .iter()
        .flat_map(|r| {
            let first = *r.index.start();
            let indices = first..=(*r.index.end()).min(first + 2);
            let (subs, d, ty) = (r.sub.clone(), r.device, r.ty);
            indices.flat_map(move |i| subs.clone().map(move |s| (d, i, s, ty)))
        })
        .collect();
    let row = prop::sample::select(rows);
    let any_addr =
        any::<(u16, u16, u16, u16)>().prop_map(|(b, d, i, s)| ObjectAddress::new(b, d, i, s));
    prop_oneof![
        6 => (row.clone(), value(), any::<bool>()).prop_map(|((d, i, s, ty), v, typed)| {
            let a = on_the_bus(d, i, s);
            let v = match (typed, ty, v) {
                (true, ValueType::F64, Value::I32(n)) => Value::F64(f64::from(n)),
                (true, ValueType::I32, Value::F64(x)) => Value::I32(x as i32),
                (_, _, v) => v,
            };
            Request::Write(a, v)
        }),
        2 => row.prop_map(|(d, i, s, ty)| Request::Read(on_the_bus(d, i, s), ty)),
        1 => (any_addr, value()).prop_map(|(a, v)| Request::Write(a, v)),
    ]
    .boxed()
}

fn value() -> BoxedStrategy<Value> {
    prop_oneof![
        (-2i32..20).prop_map(Value::I32),
        any::<i32>().prop_map(Value::I32),
        coord().prop_map(Value::F64),
    ]
    .boxed()
}

/// A request of the TC side, emulator-control ops included.
fn request() -> BoxedStrategy<Request> {
    prop_oneof![
        8 => motion().prop_map(Request::Motion),
        9 => access(),
        3 => (0u64..300).prop_map(|n| Request::Exec(Some(n))),
        1 => Just(Request::Exec(None)),
        2 => Just(Request::Pos),
        2 => Just(Request::Queue),
        1 => (
            prop::array::uniform8(coord()),
            prop_oneof![Just(1e-3), -1.0..2.0f64],
            prop_oneof![Just(0u64), 0u64..200_000],
        )
            .prop_map(|(start, cycle_s, spool_capacity)| Request::Setup {
                start,
                cycle_s,
                spool_capacity,
            }),
        1 => any::<bool>().prop_map(|logging| Request::SpoolLog { logging }),
    ]
    .boxed()
}

/// A frame of any op as a client could send it: the TC requests, and
/// object-layer requests with payloads of any bytes.
fn frame() -> BoxedStrategy<Vec<u8>> {
    let payload = prop::collection::vec(any::<u8>(), 0..40).prop_map(Bytes::from);
    let wire = prop_oneof![
        request().prop_map(|r| r.to_wire()),
        (any::<u8>(), payload.clone()).prop_map(|(c, p)| WireRequest::Ext(c, p)),
        payload.prop_map(WireRequest::Hello),
    ];
    (any::<u32>(), wire)
        .prop_map(|(id, req)| {
            let mut out = BytesMut::new();
            ClientCodec.encode((id, &req), &mut out).unwrap();
            out.to_vec()
        })
        .boxed()
}

/// Bytes with up to three bytes changed (an index is taken modulo the
/// length), and sometimes cut short.
fn damaged(bytes: BoxedStrategy<Vec<u8>>) -> BoxedStrategy<Vec<u8>> {
    let edits = prop::collection::vec((any::<usize>(), any::<u8>()), 0..3);
    (bytes, edits, prop::option::weighted(0.1, any::<usize>()))
        .prop_map(|(mut b, edits, cut)| {
            if !b.is_empty() {
                for (at, v) in edits {
                    let at = at % b.len();
                    b[at] = v;
                }
            }
            if let Some(cut) = cut {
                b.truncate(cut % (b.len() + 1));
            }
            b
        })
        .boxed()
}

/// A client's stream of frames, some damaged.
fn stream() -> BoxedStrategy<Vec<u8>> {
    let frames = prop::collection::vec(frame(), 0..12)
        .prop_map(|f| f.concat())
        .boxed();
    prop_oneof![
        3 => frames.clone(),
        2 => damaged(frames),
        1 => prop::collection::vec(any::<u8>(), 0..200),
    ]
    .boxed()
}

/// A conformance session with its spool log on, and the writes that start
/// correction group 1 in it (reset, radius, side, STATUS on), so that the
/// motion after them is corrected.
fn running_group() -> BoxedStrategy<Vec<Request>> {
    let radius = prop_oneof![3 => 0.5..20.0f64, 1 => coord()];
    let side = prop_oneof![Just(TcObject::Left), Just(TcObject::Right)];
    (radius, side)
        .prop_map(|(r, side)| {
            let w = |key: TcObject, v| Request::Write(key.of(1), v);
            vec![
                Request::Setup {
                    start: [0.0; AXES],
                    cycle_s: 1e-3,
                    spool_capacity: 0,
                },
                Request::SpoolLog { logging: true },
                w(TcObject::GroupReset, Value::I32(0)),
                w(TcObject::Radius, Value::F64(r)),
                w(side, Value::I32(0)),
                w(TcObject::Status, Value::I32(1)),
            ]
        })
        .boxed()
}

/// A stream of TC requests only (most of them well formed), for the
/// emulator.
fn request_frames() -> BoxedStrategy<Vec<u8>> {
    let requests = prop::collection::vec(request(), 1..40);
    let start = prop::option::weighted(0.5, running_group());
    let frames = (start, requests)
        .prop_map(|(start, r)| {
            // A session's spool log is fetched at the end, and checked.
            let end = vec![Request::SpoolLog { logging: false }];
            request_stream(&[start.unwrap_or_default(), r, end].concat())
        })
        .boxed();
    prop_oneof![4 => frames.clone(), 1 => damaged(frames), 1 => stream()].boxed()
}

/// Lines of a trace: requests written back, lines of likely words, and
/// any characters or bytes.
fn trace_text() -> BoxedStrategy<Vec<u8>> {
    let word = prop_oneof![
        Just("=>".to_string()),
        Just("<".to_string()),
        Just("err".to_string()),
        Just("ok".to_string()),
        Just("@tol".to_string()),
        Just("@start".to_string()),
        Just("@cycle".to_string()),
        Just("#".to_string()),
        "[XYZABCUVIJKF]-?[0-9.e]{0,6}",
        "[XYZABCUVIJKF]-?[0-9]{0,3}\\.[0-9]{1,20}(e-?[0-9]{1,3})?",
        "[+-]{0,2}(0[xX])?[0-9a-fA-F]{0,12}",
        "\\PC{0,8}",
    ];
    let verb = prop::sample::select(vec![
        "LIN",
        "RAP",
        "CIR CW",
        "CIR ccw",
        "JA",
        "JS",
        "SSF",
        "RS",
        "EXEC",
        "POS",
        "QUEUE",
        "W 1300/1/1/6 d",
        "W 1300/0/3/0 i",
        "R 1300/1/1/3 i",
    ]);
    // Numbers as a user types them, not as `Display` writes them.
    let typed = (verb, prop::collection::vec(word.clone(), 0..5))
        .prop_map(|(v, w)| format!("{v} {}", w.join(" ")));
    let line = prop_oneof![
        4 => request().prop_map(|r| r.to_string()),
        3 => typed,
        2 => (request(), prop::collection::vec(word.clone(), 0..4))
            .prop_map(|(r, w)| format!("{r} {}", w.join(" "))),
        2 => prop::collection::vec(word, 0..6).prop_map(|w| w.join(" ")),
        1 => "\\PC{0,40}",
    ];
    let text = prop::collection::vec(line, 0..10)
        .prop_map(|l| l.join("\n").into_bytes())
        .boxed();
    prop_oneof![4 => text.clone(), 1 => damaged(text), 1 => prop::collection::vec(any::<u8>(), 0..200)].boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn frame_decoder_holds(read in any::<u8>(), bytes in stream()) {
        frame_decoder(&[[read].as_slice(), &bytes].concat());
    }

    #[test]
    fn trace_line_holds(text in trace_text()) {
        trace_line(&text);
    }

    #[test]
    fn frame_sequence_holds(bytes in request_frames()) {
        frame_sequence(&bytes);
    }
}
