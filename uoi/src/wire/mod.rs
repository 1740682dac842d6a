//! The binary wire protocol (docs/protocol.md), in three layers:
//!
//! * [`frame`]: length prefix, the fixed header, op codes, protocol errors;
//! * [`layout`]: the payloads of READ and WRITE, declared with `zerocopy`;
//! * [`message`]: requests and answers and their frames. Extension ops
//!   (codes in [`EXT_OPS`]) carry a payload this layer does not interpret;
//!   the request layer of the bus behind the server decodes it.
//!
//! [`codec`] puts the frames on a byte stream (tokio-util).

#[cfg(feature = "tcp")]
pub mod codec;
pub mod frame;
pub mod layout;
pub mod message;

#[cfg(feature = "tcp")]
pub use codec::{ClientCodec, CodecError, Reply, ServerCodec};
pub use frame::{
    Header, Op, ProtocolError, EXT_OPS, HEADER_LEN, MAGIC, MAX_FRAME, PREFIX_LEN, VERSION,
};
pub use message::{
    decode_answer, decode_request, decode_request_with, encode_answer, encode_frame,
    encode_request, exact, Answer, Rejected, Request,
};
