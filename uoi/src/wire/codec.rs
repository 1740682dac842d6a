//! Frames on a byte stream: `tokio-util` codecs for the server side
//! (requests in, answers out) and the client side (requests out, answer
//! frames in). The length prefix keeps both sides in step, so a bad frame
//! does not spoil the next; only a prefix over [`MAX_FRAME`] ends the
//! stream, because nothing after it can be trusted.

use bytes::{Buf, Bytes, BytesMut};
use tokio_util::codec::{Decoder, Encoder};

use super::frame::{MAX_FRAME, PREFIX_LEN};
use super::message::{decode_request, encode_answer, encode_request, Answer, Rejected, Request};

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

/// Takes one frame body (header + payload) off `src`, once it is complete.
fn take_body(src: &mut BytesMut) -> Result<Option<Bytes>, CodecError> {
    let Some(prefix) = src.first_chunk::<PREFIX_LEN>() else {
        return Ok(None);
    };
    let len = u32::from_le_bytes(*prefix) as usize;
    if len > MAX_FRAME {
        return Err(CodecError::FrameTooLarge(len));
    }
    if src.len() < PREFIX_LEN + len {
        src.reserve(PREFIX_LEN + len - src.len());
        return Ok(None);
    }
    src.advance(PREFIX_LEN);
    Ok(Some(src.split_to(len).freeze()))
}

/// The server's codec: decodes request frames, encodes [`Reply`]s.
#[derive(Debug, Clone, Copy, Default)]
pub struct ServerCodec;

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

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Self::Item>, CodecError> {
        Ok(take_body(src)?.map(decode_request))
    }
}

impl Encoder<Reply> for ServerCodec {
    type Error = CodecError;

    fn encode(&mut self, reply: Reply, dst: &mut BytesMut) -> Result<(), CodecError> {
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

    fn encode(&mut self, (id, req): (u32, &Request), dst: &mut BytesMut) -> Result<(), CodecError> {
        encode_request(id, req, dst);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::frame::ProtocolError;
    use crate::{ObjectAddress, ValueType};

    #[test]
    fn frames_split_anywhere_decode_once_complete() {
        let req = Request::Read(ObjectAddress::new(1300, 0, 3, 0), ValueType::I32);
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
