//! 10,000 random frames into the request decoder: never a panic; whatever
//! decodes re-encodes to the same bytes; broken frames keep their id; the
//! server codec (which decodes in place) agrees with the decoder of owned
//! frame bodies.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use bytes::{BufMut, Bytes, BytesMut};
use proptest::prelude::*;
use tokio_util::codec::Decoder;
use uoi::wire::{decode_request, encode_request, Request, ServerCodec, PREFIX_LEN};
use uoi::{ObjectAddress, Value, ValueType};

/// A bus of the example: the decoder takes any bus number (docs/decisions.md,
/// decision 521).
const EXAMPLE_BUS: u16 = 7;

/// Valid frames to mutate, so the fuzzing gets past the header often.
fn seeds() -> Vec<Vec<u8>> {
    let a = ObjectAddress::new(EXAMPLE_BUS, 1, 2, 8);
    let reqs = [
        Request::Read(a, ValueType::I32),
        Request::Write(a, Value::F64(1.5)),
        Request::Write(a, Value::I32(-3)),
        Request::Ext(0x10, Bytes::from_static(&[1; 108])),
        Request::Ext(0x21, Bytes::new()),
        Request::Ext(0x7f, Bytes::from_static(&[0; 8])),
        Request::Ext(0x31, Bytes::from_static(&[1, 0, 0, 0])),
    ];
    reqs.iter()
        .map(|r| {
            let mut f = BytesMut::new();
            encode_request(1, r, &mut f);
            f[PREFIX_LEN..].to_vec()
        })
        .collect()
}

fn frame() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..256),
        (
            0..7usize,
            prop::collection::vec((any::<usize>(), any::<u8>()), 1..6),
            any::<usize>()
        )
            .prop_map(|(k, flips, cut)| {
                let mut f = seeds()[k].clone();
                for (at, b) in flips {
                    let n = f.len();
                    f[at % n] = b;
                }
                if cut % 3 == 0 {
                    f.truncate(cut % (f.len() + 1));
                }
                f
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    #[test]
    fn decoder_never_panics_and_round_trips(f in frame()) {
        match decode_request(Bytes::from(f.clone())) {
            Ok((id, req)) => {
                let mut again = BytesMut::new();
                encode_request(id, &req, &mut again);
                // NaN values compare unequal: compare encodings, not requests.
                let back = decode_request(Bytes::copy_from_slice(&again[PREFIX_LEN..]));
                prop_assert!(back.is_ok(), "re-encoded request does not decode: {:?}", req);
                if let Ok((id2, req2)) = back {
                    prop_assert_eq!(id2, id);
                    let mut twice = BytesMut::new();
                    encode_request(id2, &req2, &mut twice);
                    prop_assert_eq!(twice, again);
                }
            }
            Err(rejected) => {
                if f.len() >= 12 {
                    prop_assert_eq!(rejected.id, u32::from_le_bytes([f[4], f[5], f[6], f[7]]));
                }
            }
        }
    }

    #[test]
    fn server_codec_decodes_like_decode_request(f in frame(), tail in prop::collection::vec(any::<u8>(), 0..8)) {
        let mut src = BytesMut::new();
        src.put_u32_le(f.len() as u32);
        src.put_slice(&f);
        src.put_slice(&tail);
        let got = ServerCodec.decode(&mut src).expect("no framing error");
        // Debug text, as NaN values compare unequal.
        let want = decode_request(Bytes::from(f));
        prop_assert_eq!(format!("{:?}", got), format!("{:?}", Some(want)));
        prop_assert_eq!(&src[..], &tail[..]);
    }
}
