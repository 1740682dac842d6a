//! The byte example of docs/protocol.md is what the encoder produces. The
//! example reads TcPlane, named through tc-objects; the test lives at the
//! root, where tc-objects is at hand, so `uoi` needs nothing above it.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use bytes::BytesMut;
use tc_objects::{TcObject, PLANE_XY};
use uoi::wire::{encode_answer, encode_request, Answer, Op, Request};
use uoi::{Value, ValueType};

fn hex(b: &[u8]) -> String {
    b.iter()
        .map(|x| format!("{x:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn documented_example_bytes() {
    let mut req = BytesMut::new();
    encode_request(
        1,
        &Request::Read(TcObject::TcPlane.address(), ValueType::I32),
        &mut req,
    );
    assert_eq!(
        hex(&req),
        "18 00 00 00 55 4f 01 01 01 00 00 00 00 00 00 00 14 05 00 00 03 00 00 00 69 00 00 00"
    );
    let mut ans = BytesMut::new();
    encode_answer(
        1,
        Op::Read.code(),
        &Answer::Value(Value::I32(PLANE_XY)),
        &mut ans,
    );
    assert_eq!(
        hex(&ans),
        "18 00 00 00 55 4f 01 01 01 00 00 00 00 00 00 00 69 00 00 00 11 00 00 00 00 00 00 00"
    );
}

#[test]
fn documented_hello_bytes() {
    let mut req = BytesMut::new();
    let hello = Request::Hello(bytes::Bytes::from_static(b"0123456789abcdef"));
    encode_request(1, &hello, &mut req);
    assert_eq!(
        hex(&req),
        "1c 00 00 00 55 4f 01 03 01 00 00 00 00 00 00 00 \
         30 31 32 33 34 35 36 37 38 39 61 62 63 64 65 66"
    );
}
