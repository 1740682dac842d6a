//! The one request model through its three faces: text written and read
//! back, wire encoded and decoded, replies encoded and decoded; and random
//! frames through the whole decoder without a panic.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use bytes::{Bytes, BytesMut};
use proptest::prelude::*;
use tc_request::text::parse_request;
use tc_request::wire::TcOp;
use tc_request::{
    ArcDir, ArcRecord, Motion, Origin, Reply, Request, SpoolRecord, AXES, MAX_EXEC_CYCLES,
};
use uoi::wire::{decode_answer, decode_request, encode_answer, encode_request, PREFIX_LEN};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

fn num() -> impl Strategy<Value = f64> {
    prop_oneof![-1e6..1e6f64, Just(0.0), Just(-2.5), 1e-9..1e-3f64]
}

fn words() -> impl Strategy<Value = [Option<f64>; AXES]> {
    prop::array::uniform8(prop::option::of(num()))
}

fn motion() -> BoxedStrategy<Motion> {
    let feed = prop::option::of(1.0..1e5f64);
    prop_oneof![
        (words(), feed.clone()).prop_map(|(words, feed)| Motion::Lin { words, feed }),
        (words(), feed.clone()).prop_map(|(words, feed)| Motion::Rap { words, feed }),
        (
            any::<bool>(),
            words(),
            prop::array::uniform3(prop::option::of(num())),
            feed
        )
            .prop_map(|(ccw, words, centre, feed)| Motion::Cir {
                dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                words,
                centre,
                feed
            }),
        words().prop_map(|words| Motion::Ja { words }),
        prop::array::uniform8(any::<bool>()).prop_map(|axes| Motion::Js { axes }),
        (0..8u8, any::<i32>()).prop_map(|(axis, function)| Motion::Ssf { axis, function }),
        Just(Motion::Rs),
    ]
    .boxed()
}

fn addr() -> impl Strategy<Value = ObjectAddress> {
    (any::<u16>(), any::<u16>(), any::<u16>(), any::<u16>())
        .prop_map(|(b, d, i, s)| ObjectAddress::new(b, d, i, s))
}

/// Requests that have a trace syntax.
fn trace_request() -> BoxedStrategy<Request> {
    prop_oneof![
        (addr(), any::<bool>())
            .prop_map(|(a, d)| Request::Read(a, if d { ValueType::F64 } else { ValueType::I32 })),
        (addr(), any::<i32>()).prop_map(|(a, v)| Request::Write(a, Value::I32(v))),
        (addr(), num()).prop_map(|(a, v)| Request::Write(a, Value::F64(v))),
        motion().prop_map(Request::Motion),
        prop::option::of(0..=MAX_EXEC_CYCLES).prop_map(Request::Exec),
        Just(Request::Pos),
        Just(Request::Queue),
        (any::<bool>(), 0.0..1e6f64).prop_map(|(on, rmin)| Request::FeedAdaption { on, rmin }),
    ]
    .boxed()
}

fn any_request() -> BoxedStrategy<Request> {
    prop_oneof![
        trace_request(),
        (prop::array::uniform8(num()), 1e-6..1.0f64, any::<u64>()).prop_map(
            |(start, cycle_s, spool_capacity)| Request::Setup {
                start,
                cycle_s,
                spool_capacity
            }
        ),
        any::<bool>().prop_map(|logging| Request::SpoolLog { logging }),
    ]
    .boxed()
}

fn record() -> BoxedStrategy<SpoolRecord> {
    (
        prop::option::of((0..8u8, 0..8u8, 0..8u8, num(), num(), any::<bool>())),
        prop::array::uniform8(num()),
        prop::array::uniform8(num()),
        1.0..1e4f64,
        any::<bool>(),
        0..5u8,
    )
        .prop_map(|(arc, start, end, feed, rapid, o)| SpoolRecord {
            arc: arc.map(|(h, v, t, x, y, ccw)| ArcRecord {
                plane: [h, v, t],
                centre: [x, y],
                ccw,
            }),
            start,
            end,
            feed,
            rapid,
            origin: Origin::from_code(o).unwrap(),
        })
        .boxed()
}

fn reply() -> BoxedStrategy<(TcOp, Reply)> {
    prop_oneof![
        Just((TcOp::Motion, Reply::Ok)),
        Just((TcOp::Exec, Reply::Access(AccessError::State))),
        prop::array::uniform8(num()).prop_map(|p| (TcOp::Pos, Reply::Pos(p))),
        any::<u64>().prop_map(|n| (TcOp::Queue, Reply::Queue(n))),
        (prop::collection::vec(record(), 0..50), any::<bool>())
            .prop_map(|(els, more)| (TcOp::SpoolLog, Reply::Spool(els, more))),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2_000))]

    #[test]
    fn text_reads_back_what_it_writes(req in trace_request().prop_filter(
        "JA and JS name at least one axis in trace syntax",
        |r| !matches!(
            r,
            Request::Motion(Motion::Ja { words }) if words.iter().all(Option::is_none)
        ) && !matches!(
            r,
            Request::Motion(Motion::Js { axes }) if !axes.iter().any(|a| *a)
        ),
    )) {
        let text = req.to_string();
        prop_assert_eq!(parse_request(&text), Ok(req), "{}", text);
    }

    #[test]
    fn wire_decodes_what_it_encodes(req in any_request()) {
        let mut frame = BytesMut::new();
        encode_request(3, &req.to_wire(), &mut frame);
        let body = Bytes::copy_from_slice(&frame[PREFIX_LEN..]);
        let (id, wire) = decode_request(body).expect("a frame we encoded");
        prop_assert_eq!(id, 3);
        prop_assert_eq!(Request::from_wire(&wire), Ok(req));
    }

    #[test]
    fn replies_decode_what_they_encode((op, reply) in reply()) {
        let mut frame = BytesMut::new();
        encode_answer(4, op.code(), &reply.to_wire(), &mut frame);
        let body = Bytes::copy_from_slice(&frame[PREFIX_LEN..]);
        let wire_op = uoi::wire::Op::Ext(op.code());
        let (id, ans) = decode_answer(body, wire_op).expect("an answer we encoded");
        prop_assert_eq!(id, 4);
        prop_assert_eq!(Reply::from_wire(wire_op, &ans), Some(reply));
    }
}

/// Valid frames of every TC op, to mutate.
fn seeds() -> Vec<Vec<u8>> {
    let mut words = [None; AXES];
    words[0] = Some(1.0);
    [
        Request::Motion(Motion::Cir {
            dir: ArcDir::Ccw,
            words,
            centre: [Some(1.0), None, None],
            feed: Some(5.0),
        }),
        Request::Exec(Some(3)),
        Request::Pos,
        Request::Queue,
        Request::Setup {
            start: [0.0; AXES],
            cycle_s: 1e-3,
            spool_capacity: 0,
        },
        Request::SpoolLog { logging: true },
    ]
    .iter()
    .map(|r| {
        let mut f = BytesMut::new();
        encode_request(1, &r.to_wire(), &mut f);
        f[PREFIX_LEN..].to_vec()
    })
    .collect()
}

/// A valid TC frame with a mask XOR-ed over its payload, or a valid header
/// of any extension op with a payload of random bytes and length.
fn frame() -> impl Strategy<Value = Vec<u8>> {
    let masked = (0..6usize, prop::collection::vec(any::<u8>(), 0..160)).prop_map(|(k, mask)| {
        let mut f = seeds()[k].clone();
        let payload = 12..f.len();
        for (b, m) in f[payload].iter_mut().zip(mask) {
            *b ^= m;
        }
        f
    });
    let random = (0x10..0x80u8, prop::collection::vec(any::<u8>(), 0..200)).prop_map(|(op, p)| {
        let mut f = seeds()[2][..12].to_vec();
        f[3] = op;
        f.extend(p);
        f
    });
    prop_oneof![masked, random]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    /// Mutated TC frames through the object layer and the TC decoder:
    /// never a panic; what decodes re-encodes to a frame that decodes the
    /// same way.
    #[test]
    fn tc_decoder_never_panics(f in frame()) {
        let Ok((_, wire)) = decode_request(Bytes::from(f)) else { return Ok(()) };
        let Ok(req) = Request::from_wire(&wire) else { return Ok(()) };
        let mut again = BytesMut::new();
        encode_request(1, &req.to_wire(), &mut again);
        let body = Bytes::copy_from_slice(&again[PREFIX_LEN..]);
        let (_, wire2) = decode_request(body).expect("re-encoded frame decodes");
        let req2 = Request::from_wire(&wire2).expect("re-encoded request decodes");
        // NaN words compare unequal: compare the encodings.
        prop_assert_eq!(req2.to_wire(), req.to_wire());
    }
}
