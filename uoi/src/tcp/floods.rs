//! The server's log lines that a client can make it repeat (a flood of
//! connections, of wrong tokens, of oversized frames): each kind is written
//! at most once a second, with the count of lines left out since
//! ([`LogLimit`]). One set per server, shared by its connections.

use crate::LogLimit;

/// One limiter per kind of line a client can trigger.
#[derive(Debug)]
pub(crate) struct FloodLogs {
    /// A HELLO with a wrong token.
    pub(crate) wrong_token: LogLimit,
    /// A request, or a bad frame, before the access token.
    pub(crate) before_token: LogLimit,
    /// A frame over the size limit.
    pub(crate) too_large: LogLimit,
    /// A connection closed to make room for a new one.
    pub(crate) evicted: LogLimit,
    /// A new connection refused: no place.
    pub(crate) refused: LogLimit,
    /// A new connection refused: its address opens them too fast.
    pub(crate) too_fast: LogLimit,
    /// A failed accept.
    pub(crate) accept_failed: LogLimit,
}

impl Default for FloodLogs {
    fn default() -> Self {
        Self {
            wrong_token: LogLimit::per_second(),
            before_token: LogLimit::per_second(),
            too_large: LogLimit::per_second(),
            evicted: LogLimit::per_second(),
            refused: LogLimit::per_second(),
            too_fast: LogLimit::per_second(),
            accept_failed: LogLimit::per_second(),
        }
    }
}
