//! The request log of the shared emulator (`addipos serve --record`):
//! every request the emulator carried out, from every connection and the
//! OPC UA face, in the order it carried them out, with its answer and the
//! elements it spooled; in real time, the cycles the clock ran between
//! requests as `EXEC n`. The service hands each of them to a
//! [`RequestLog`]; what writes it as a trace (and where) is the log's
//! business ([`crate::record::ServeRecorder`] streams it as a trace).

use tc_request::{Reply, Request, SpoolRecord};

/// Why a request log took no more: the log's own error, shown as it
/// words it (the service logs it and stops recording).
pub type LogError = Box<dyn std::error::Error + Send + Sync>;

/// Where the shared emulator's requests go while it is recorded. A log
/// that fails answers `Err` with the reason: the service then stops
/// recording, logs the reason and goes on serving.
pub trait RequestLog: Send + std::fmt::Debug {
    /// A request carried out, with its reply and the elements it spooled
    /// (`axis_nr`: the machine axes allocated as X, Y, Z, for the `I J K`
    /// of arcs).
    fn exchange(
        &mut self,
        req: &Request,
        reply: &Reply,
        spooled: &[SpoolRecord],
        axis_nr: [u8; 3],
    ) -> Result<(), LogError>;

    /// Cycles the real-time clock ran while no request was carried out.
    /// A log may merge the idle cycles up to its next entry into one
    /// `EXEC n` (so an idle server writes one line, not hundreds a
    /// second); this one writes them at once.
    fn idle(&mut self, cycles: u64) -> Result<(), LogError> {
        self.exchange(&Request::Exec(Some(cycles)), &Reply::Ok, &[], [0, 1, 2])
    }

    /// A line of comment (what has no trace form).
    fn note(&mut self, text: &str) -> Result<(), LogError>;

    /// Everything so far (idle cycles merged included) on its way to the
    /// file (at shutdown).
    fn finish(&mut self) -> Result<(), LogError>;
}
