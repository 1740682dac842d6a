//! Recording what an emulator carries out as a conformance trace
//! (docs/trace-format.md), so that `addipos replay` runs it again:
//! [`Recorder`] writes the lines (a host library's session, the shared
//! emulator's request log); [`ServeRecorder`] streams the shared
//! emulator's [`RequestLog`](crate::RequestLog) by a writer thread of its
//! own (`addipos serve --record`, decision 510).

mod serve;
mod stream;
mod writer;

pub use serve::{RecordError, ServeRecorder};
pub use stream::{WriterStop, QUEUE_CHUNKS, STALL_LIMIT};
pub use writer::{RecordHeader, Recorder};
