//! Frames on a byte stream: `tokio-util` codecs for the server side
//! (requests in, answers out) and the client side (requests out, answer
//! frames in). The length prefix keeps both sides in step, so a bad frame
//! does not spoil the next; only a prefix over [`MAX_FRAME`] ends the
//! stream, because nothing after it can be trusted.

use bytes::{Buf, Bytes, BytesMut};
use tokio_util::codec::{Decoder, Encoder};

use super::frame::{Header, EXT_OPS, HEADER_LEN, MAX_FRAME, PREFIX_LEN};
use super::message::{
    decode_request, decode_request_with, encode_answer, encode_request, Answer, Rejected, Request,
};

/// Offset of the op byte in the header.
const OP_AT: usize = std::mem::offset_of!(Header, op);

/// Why a stream of frames cannot go on.
#[derive(Debug, thiserror::Error)]
pub enum CodecError {
    /// The connection failed, or closed in the middle of a frame.
    #[error("connection: {0}")]
    Io(#[from] std::io::Error),
    /// A length prefix over [`MAX_FRAME`]: answered `FrameTooLarge`, then
    /// the connection is closed.
    #[error("frame of {0} bytes is larger than {MAX_FRAME}")]
    FrameTooLarge(usize),
}

/// The body length (header + payload) of the frame at the start of `src`
/// once it is complete; room is reserved for an incomplete one.
fn body_len(src: &mut BytesMut) -> Result<Option<usize>, CodecError> {
    let Some(prefix) = src.first_chunk::<PREFIX_LEN>() else {
        if src.is_empty() {
            // Everything taken: reclaim the whole buffer for the next read
            // (no copy), so a read never makes do with its tail end.
            src.reserve(READ_ROOM);
        }
        return Ok(None);
    };
    let len = u32::from_le_bytes(*prefix) as usize;
    if len > MAX_FRAME {
        return Err(CodecError::FrameTooLarge(len));
    }
    if src.len() < PREFIX_LEN + len {
        // Room for the rest of this frame only: the buffer never grows
        // past one largest frame.
        src.reserve(PREFIX_LEN + len - src.len());
        return Ok(None);
    }
    Ok(Some(len))
}

/// The room a read buffer is given back when it is empty: one largest
/// frame, or a batch of pipelined small ones.
const READ_ROOM: usize = MAX_FRAME + PREFIX_LEN;

/// Takes one frame body (header + payload) off `src`, once it is complete.
fn take_body(src: &mut BytesMut) -> Result<Option<Bytes>, CodecError> {
    let Some(len) = body_len(src)? else {
        return Ok(None);
    };
    src.advance(PREFIX_LEN);
    Ok(Some(src.split_to(len).freeze()))
}

/// The server's codec: decodes request frames, encodes [`Reply`]s.
#[derive(Debug, Clone, Copy, Default)]
pub struct ServerCodec;

impl ServerCodec {
    /// Whether `buf` (a read buffer) starts with something the decoder
    /// takes without reading more: a whole frame, or a length prefix over
    /// [`MAX_FRAME`].
    pub fn has_frame(buf: &[u8]) -> bool {
        let Some(prefix) = buf.first_chunk::<PREFIX_LEN>() else {
            return false;
        };
        let len = u32::from_le_bytes(*prefix) as usize;
        len > MAX_FRAME || buf.len() >= PREFIX_LEN + len
    }
}

/// One answer frame as the server sends it.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    /// The request id echoed.
    pub id: u32,
    /// The op code echoed.
    pub op: u8,
    /// The answer.
    pub answer: Answer,
}

impl Decoder for ServerCodec {
    /// A request, or what to answer a frame that is not one.
    type Item = Result<(u32, Request), Rejected>;
    type Error = CodecError;

    /// READ and WRITE are decoded in place (no split of the buffer, no
    /// reference count per frame); an extension op's body is split off and
    /// its payload shared with the read buffer, not copied.
    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Self::Item>, CodecError> {
        let Some(len) = body_len(src)? else {
            return Ok(None);
        };
        let end = PREFIX_LEN + len;
        // The op byte of this frame, if its body is long enough to hold it.
        let op = (len > OP_AT).then(|| src[PREFIX_LEN + OP_AT]);
        if op.is_some_and(|c| EXT_OPS.contains(&c)) {
            src.advance(PREFIX_LEN);
            return Ok(Some(decode_request(src.split_to(len).freeze())));
        }
        // Not an extension op: `decode_request_with` does not call the closure.
        let item = decode_request_with(&src[PREFIX_LEN..end], Bytes::copy_from_slice);
        src.advance(end);
        Ok(Some(item))
    }
}

/// `FrameTooLarge` unless a payload of `len` bytes fits one frame: the
/// peer would refuse the frame and close.
fn fits(len: usize) -> Result<(), CodecError> {
    if HEADER_LEN + len <= MAX_FRAME {
        Ok(())
    } else {
        Err(CodecError::FrameTooLarge(HEADER_LEN + len))
    }
}

impl Encoder<Reply> for ServerCodec {
    type Error = CodecError;

    /// `FrameTooLarge`, and nothing written, for an extension answer too
    /// large for one frame (the request layer keeps its answers smaller).
    fn encode(&mut self, reply: Reply, dst: &mut BytesMut) -> Result<(), CodecError> {
        if let Answer::Ext(payload) = &reply.answer {
            fits(payload.len())?;
        }
        encode_answer(reply.id, reply.op, &reply.answer, dst);
        Ok(())
    }
}

/// The client's codec: encodes `(id, request)`, decodes answer frame
/// bodies (the client knows which op each answers).
#[derive(Debug, Clone, Copy, Default)]
pub struct ClientCodec;

impl Decoder for ClientCodec {
    /// An answer frame body (header + payload).
    type Item = Bytes;
    type Error = CodecError;

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Bytes>, CodecError> {
        take_body(src)
    }
}

impl Encoder<(u32, &Request)> for ClientCodec {
    type Error = CodecError;

    /// `FrameTooLarge`, and nothing sent, for an extension request too
    /// large for one frame.
    fn encode(&mut self, (id, req): (u32, &Request), dst: &mut BytesMut) -> Result<(), CodecError> {
        if let Request::Ext(_, payload) | Request::Hello(payload) = req {
            fits(payload.len())?;
        }
        encode_request(id, req, dst);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_extension_payload_too_large_for_a_frame_is_refused() {
        let big = Bytes::from(vec![0u8; MAX_FRAME - HEADER_LEN + 1]);
        let mut dst = BytesMut::new();
        let req = Request::Ext(0x10, big.clone());
        assert!(matches!(
            ClientCodec.encode((1, &req), &mut dst),
            Err(CodecError::FrameTooLarge(_))
        ));
        let reply = Reply {
            id: 1,
            op: 0x21,
            answer: Answer::Ext(big),
        };
        assert!(matches!(
            ServerCodec.encode(reply, &mut dst),
            Err(CodecError::FrameTooLarge(_))
        ));
        assert!(dst.is_empty());
        let fits = Request::Ext(0x10, Bytes::from(vec![0u8; MAX_FRAME - HEADER_LEN]));
        assert!(ClientCodec.encode((1, &fits), &mut dst).is_ok());
        assert_eq!(dst.len(), PREFIX_LEN + MAX_FRAME);
    }
    use crate::wire::frame::ProtocolError;
    use crate::{ObjectAddress, ValueType};

    /// A bus of the example: the wire carries any bus number (bus 1300's
    /// objects are named in tc-objects, which this layer does not know;
    /// docs/decisions.md, decision 521).
    const EXAMPLE_BUS: u16 = 7;

    #[test]
    fn frames_split_anywhere_decode_once_complete() {
        let req = Request::Read(ObjectAddress::new(EXAMPLE_BUS, 0, 3, 0), ValueType::I32);
        let mut whole = BytesMut::new();
        ClientCodec.encode((5, &req), &mut whole).unwrap();
        ClientCodec.encode((6, &req), &mut whole).unwrap();
        for cut in 0..whole.len() {
            let mut src = BytesMut::from(&whole[..cut]);
            let mut got = Vec::new();
            while let Some(item) = ServerCodec.decode(&mut src).unwrap() {
                got.push(item);
            }
            src.extend_from_slice(&whole[cut..]);
            while let Some(item) = ServerCodec.decode(&mut src).unwrap() {
                got.push(item);
            }
            assert_eq!(got, vec![Ok((5, req.clone())), Ok((6, req.clone()))]);
            assert!(src.is_empty());
        }
    }

    #[test]
    fn has_frame_only_for_what_decodes_without_more_input() {
        let req = Request::Read(ObjectAddress::new(EXAMPLE_BUS, 0, 3, 0), ValueType::I32);
        let mut whole = BytesMut::new();
        ClientCodec.encode((5, &req), &mut whole).unwrap();
        for cut in 0..whole.len() {
            assert!(!ServerCodec::has_frame(&whole[..cut]), "cut at {cut}");
        }
        assert!(ServerCodec::has_frame(&whole));
        // A too-short frame decodes (as a rejection), an oversized prefix
        // as an error: both without more input.
        assert!(ServerCodec::has_frame(&[3, 0, 0, 0, 1, 2, 3]));
        assert!(ServerCodec::has_frame(
            &((MAX_FRAME + 1) as u32).to_le_bytes()
        ));
        assert!(!ServerCodec::has_frame(&(MAX_FRAME as u32).to_le_bytes()));
    }

    #[test]
    fn oversized_prefix_is_an_error_and_short_frame_a_rejection() {
        let mut src = BytesMut::from(&((MAX_FRAME + 1) as u32).to_le_bytes()[..]);
        assert!(matches!(
            ServerCodec.decode(&mut src),
            Err(CodecError::FrameTooLarge(n)) if n == MAX_FRAME + 1
        ));
        let mut src = BytesMut::from(&[3u8, 0, 0, 0, 1, 2, 3][..]);
        let item = ServerCodec.decode(&mut src).unwrap().unwrap();
        assert_eq!(item.map_err(|r| r.error), Err(ProtocolError::FrameTooShort));
    }
}
