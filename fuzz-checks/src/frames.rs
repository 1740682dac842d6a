//! [`frame_decoder`](super::frame_decoder): the server's and the client's
//! frame decoders on any byte stream.

use bytes::BytesMut;
use tc_request::Reply;
use tokio_util::codec::{Decoder, Encoder};
use uoi::wire::{
    decode_answer, encode_answer, Answer, ClientCodec, CodecError, Op, Rejected,
    Request as WireRequest, ServerCodec, HEADER_LEN, MAX_FRAME, PREFIX_LEN,
};

use crate::limits::MAX_INPUT;

/// The largest read buffer a decoder may hold after taking `chunk` bytes
/// more: room for one largest frame (reserved once, then reused), the
/// bytes not yet decoded, and the growth of one reallocation.
fn buffer_bound(chunk: usize) -> usize {
    4 * (PREFIX_LEN + MAX_FRAME + chunk)
}

/// The client's encoding of a decoded request: requests compare by it
/// (a request holding a NaN is not equal to itself).
fn request_bytes(id: u32, req: &WireRequest) -> Vec<u8> {
    let mut out = BytesMut::new();
    if let Err(e) = ClientCodec.encode((id, req), &mut out) {
        panic!("a decoded request does not encode: {e} ({req:?})");
    }
    out.to_vec()
}

/// A decoded item as compared: the request's encoding, or the rejection.
type Key = Result<Vec<u8>, Rejected>;

/// The length prefix at the start of `buf`.
fn prefix(buf: &[u8]) -> Option<usize> {
    buf.first_chunk::<PREFIX_LEN>()
        .map(|p| u32::from_le_bytes(*p) as usize)
}

/// Runs the server's decoder over `stream`, fed `chunk` bytes at a time
/// as reads would, checking each call; what it decoded, and whether it
/// ended on a prefix over the size limit.
fn server_items(stream: &[u8], chunk: usize) -> (Vec<Key>, bool) {
    let mut buf = BytesMut::new();
    let mut items = Vec::new();
    let mut fed = 0;
    for piece in stream.chunks(chunk.max(1)) {
        buf.extend_from_slice(piece);
        fed += piece.len();
        loop {
            let before = buf.len();
            let whole = ServerCodec::has_frame(&buf);
            let len = prefix(&buf);
            match ServerCodec.decode(&mut buf) {
                Ok(Some(item)) => {
                    assert!(whole, "decoded a frame `has_frame` did not see");
                    let taken = before - buf.len();
                    assert_eq!(Some(taken), len.map(|l| l + PREFIX_LEN), "frame size");
                    let start = fed - before;
                    items.push(check_request(&item, &stream[start..start + taken]));
                }
                Ok(None) => {
                    assert!(!whole, "`has_frame` saw a frame the decoder did not take");
                    assert_eq!(buf.len(), before, "asking for more consumed bytes");
                    break;
                }
                Err(CodecError::FrameTooLarge(n)) => {
                    assert!(whole && n > MAX_FRAME && Some(n) == len, "size error {n}");
                    return (items, true);
                }
                Err(e) => panic!("decoding from memory failed: {e}"),
            }
        }
        assert!(buf.capacity() <= buffer_bound(chunk), "read buffer grew");
    }
    (items, false)
}

/// A decoded request is the only encoding of itself (the decoder takes
/// canonical frames only, so re-encoding gives back the very bytes); a
/// rejection echoes the id and op of a readable header.
fn check_request(item: &Result<(u32, WireRequest), Rejected>, frame: &[u8]) -> Key {
    match item {
        Ok((id, req)) => {
            let bytes = request_bytes(*id, req);
            assert_eq!(bytes, frame, "re-encoded request differs from its frame");
            Ok(bytes)
        }
        Err(r) => {
            let echoed = match frame[PREFIX_LEN..].get(..HEADER_LEN) {
                Some(h) => (u32::from_le_bytes([h[4], h[5], h[6], h[7]]), h[3]),
                None => (0, 0),
            };
            assert_eq!((r.id, r.op), echoed, "rejection lost id or op");
            Err(*r)
        }
    }
}

/// Op codes an answer is decoded as: the object layer's and the TC side's
/// ops, and an extension op the TC side does not have.
const ANSWER_OPS: [u8; 10] = [0x01, 0x02, 0x03, 0x10, 0x20, 0x21, 0x22, 0x30, 0x31, 0x7F];

/// The frame of answer `ans` to request `id` of op `op`.
fn answer_frame(id: u32, op: Op, ans: &Answer) -> BytesMut {
    let mut out = BytesMut::new();
    encode_answer(id, op.code(), ans, &mut out);
    out
}

/// An answer frame for `(id, op)` re-encoded and decoded again gives the
/// same answer, and the reply it stands for does too.
pub(super) fn check_answer_round_trip(id: u32, op: Op, ans: &Answer) {
    let frame = answer_frame(id, op, ans);
    let again = decode_answer(frame.clone().split_off(PREFIX_LEN).freeze(), op);
    // Answers compare by their frames: an empty extension answer decodes
    // as `Ext` of nothing, which is the frame of `Ok`.
    let same = again
        .as_ref()
        .is_some_and(|(i, a)| *i == id && answer_frame(*i, op, a) == frame);
    assert!(
        same,
        "answer {ans:?} to {op:?} does not round-trip: {again:?}"
    );
    if let Some(reply) = Reply::from_wire(op, ans) {
        let back = Reply::from_wire(op, &reply.to_wire());
        let shown = format!("{:?}", Some(&reply));
        assert_eq!(format!("{:?}", back.as_ref()), shown, "reply round trip");
    }
}

/// The client's decoder over `stream`: each call takes one whole frame or
/// asks for more, and an answer it decodes round-trips.
fn client_frames(stream: &[u8]) {
    let mut buf = BytesMut::from(stream);
    loop {
        let before = buf.len();
        let len = prefix(&buf);
        match ClientCodec.decode(&mut buf) {
            Ok(Some(body)) => {
                assert_eq!(Some(before - buf.len()), len.map(|l| l + PREFIX_LEN));
                for op in ANSWER_OPS.iter().filter_map(|c| Op::from_code(*c)) {
                    if let Some((id, ans)) = decode_answer(body.clone(), op) {
                        check_answer_round_trip(id, op, &ans);
                    }
                }
            }
            Ok(None) => {
                assert_eq!(buf.len(), before, "asking for more consumed bytes");
                return;
            }
            Err(CodecError::FrameTooLarge(n)) => {
                assert!(n > MAX_FRAME);
                return;
            }
            Err(e) => panic!("decoding from memory failed: {e}"),
        }
    }
}

/// The frame decoders on any bytes: the first byte sets the size of the
/// reads the rest arrives in. Checks that no call panics; each call takes
/// one whole frame (as `ServerCodec::has_frame` predicts) or consumes
/// nothing and asks for more; the read buffer stays bounded; a decoded
/// request re-encodes to the very bytes of its frame; a rejection keeps
/// the header's id and op; what is decoded does not depend on how the
/// bytes were split into reads; and every answer the client decodes
/// round-trips, as the TC reply it stands for.
pub fn frame_decoder(data: &[u8]) {
    let data = &data[..data.len().min(MAX_INPUT)];
    let Some((first, stream)) = data.split_first() else {
        return;
    };
    let chunk = usize::from(*first) + 1;
    let whole = server_items(stream, stream.len());
    let split = server_items(stream, chunk);
    assert_eq!(whole, split, "decoding depends on the read size {chunk}");
    client_frames(stream);
}
