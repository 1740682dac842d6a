//! The little of HTTP/1.1 the view speaks: one request head read (parsed
//! by `httparse`) within a time limit, one answer written, every answer
//! with the same security headers, the connection closed after it (the
//! event stream excepted, which stays open until the page goes).

use std::time::Duration;

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

/// Largest request head taken (a browser's is well under 2 KiB).
pub const MAX_HEAD: usize = 8 * 1024;

/// Headers taken at most.
const MAX_HEADERS: usize = 32;

/// The Content-Security-Policy of every answer: the page's own origin
/// only, no inline script or style, no frame around it.
pub const CSP: &str = "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self'; \
                       connect-src 'self'; object-src 'none'; base-uri 'none'; \
                       form-action 'none'; frame-ancestors 'none'";

/// The headers every answer carries.
const SECURITY_HEADERS: &str = "X-Content-Type-Options: nosniff\r\n\
                                Referrer-Policy: no-referrer\r\n\
                                Cache-Control: no-store\r\n";

/// A request's method, path and query, and its bearer token if any.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Head {
    /// `GET`, `POST`, ...
    pub method: String,
    /// The path without the query.
    pub path: String,
    /// The query, undecoded (empty without one).
    pub query: String,
    /// The token of an `Authorization: Bearer` header.
    pub bearer: Option<String>,
}

/// Why no request head could be read.
#[derive(Debug, thiserror::Error)]
pub enum HeadError {
    /// The socket failed or closed early.
    #[error("socket: {0}")]
    Io(#[from] std::io::Error),
    /// Not HTTP, or a head larger than [`MAX_HEAD`].
    #[error("bad request head")]
    Bad,
    /// Nothing complete within the time limit.
    #[error("no request within the time limit")]
    Slow,
}

/// Reads one request head within `limit`.
pub async fn read_head<R: AsyncRead + Unpin>(
    r: &mut R,
    limit: Duration,
) -> Result<Head, HeadError> {
    tokio::time::timeout(limit, read_head_now(r))
        .await
        .map_err(|_| HeadError::Slow)?
}

async fn read_head_now<R: AsyncRead + Unpin>(r: &mut R) -> Result<Head, HeadError> {
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        let n = r.read(&mut chunk).await?;
        if n == 0 {
            return Err(HeadError::Io(std::io::ErrorKind::UnexpectedEof.into()));
        }
        buf.extend_from_slice(&chunk[..n]);
        if let Some(head) = parse(&buf)? {
            return Ok(head);
        }
        if buf.len() > MAX_HEAD {
            return Err(HeadError::Bad);
        }
    }
}

/// The head in `buf`, `None` while incomplete.
fn parse(buf: &[u8]) -> Result<Option<Head>, HeadError> {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut req = httparse::Request::new(&mut headers);
    match req.parse(buf) {
        Ok(httparse::Status::Partial) => Ok(None),
        Err(_) => Err(HeadError::Bad),
        Ok(httparse::Status::Complete(_)) => {
            let target = req.path.unwrap_or("/");
            let (path, query) = target.split_once('?').unwrap_or((target, ""));
            let bearer = req
                .headers
                .iter()
                .find(|h| h.name.eq_ignore_ascii_case("authorization"))
                .and_then(|h| std::str::from_utf8(h.value).ok())
                .and_then(|v| v.strip_prefix("Bearer "))
                .map(|t| t.trim().to_string());
            Ok(Some(Head {
                method: req.method.unwrap_or("").to_string(),
                path: path.to_string(),
                query: query.to_string(),
                bearer,
            }))
        }
    }
}

/// The value of `name` in a query (decoded).
pub fn query_value(query: &str, name: &str) -> Option<String> {
    form_urlencoded::parse(query.as_bytes())
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.into_owned())
}

/// One whole answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    /// `200 OK`, `404 Not Found`, ...
    pub status: &'static str,
    /// The media type of the body.
    pub content_type: &'static str,
    /// The body.
    pub body: Vec<u8>,
    /// An `Allow` header (for `405`).
    pub allow: Option<&'static str>,
}

impl Answer {
    /// `200 OK` with `body`.
    pub fn ok(content_type: &'static str, body: impl Into<Vec<u8>>) -> Self {
        Self {
            status: "200 OK",
            content_type,
            body: body.into(),
            allow: None,
        }
    }

    /// An error answer with a line of text.
    pub fn error(status: &'static str, text: &str) -> Self {
        Self {
            status,
            content_type: "text/plain; charset=utf-8",
            body: format!("{text}\n").into_bytes(),
            allow: None,
        }
    }

    /// The answer as bytes on the wire.
    pub fn to_bytes(&self) -> Vec<u8> {
        let allow = self
            .allow
            .map(|a| format!("Allow: {a}\r\n"))
            .unwrap_or_default();
        let mut out = format!(
            "HTTP/1.1 {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n\
             Content-Security-Policy: {CSP}\r\n{SECURITY_HEADERS}{allow}Connection: close\r\n\r\n",
            self.status,
            self.content_type,
            self.body.len()
        )
        .into_bytes();
        out.extend_from_slice(&self.body);
        out
    }
}

/// The head of the event stream's answer.
pub fn event_stream_head() -> Vec<u8> {
    format!(
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\n\
         Content-Security-Policy: {CSP}\r\n{SECURITY_HEADERS}Connection: keep-alive\r\n\r\n"
    )
    .into_bytes()
}

/// Writes `bytes` within `limit`; a client that does not take them in
/// time is given up (`TimedOut`).
pub async fn write_within<W: AsyncWrite + Unpin>(
    w: &mut W,
    bytes: &[u8],
    limit: Duration,
) -> std::io::Result<()> {
    match tokio::time::timeout(limit, w.write_all(bytes)).await {
        Ok(r) => r,
        Err(_) => Err(std::io::ErrorKind::TimedOut.into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_head_with_its_query_and_bearer_token() {
        let h = parse(b"GET /state?token=a%2Bb HTTP/1.1\r\nAuthorization: Bearer xyz\r\n\r\n")
            .unwrap()
            .unwrap();
        assert_eq!((h.method.as_str(), h.path.as_str()), ("GET", "/state"));
        assert_eq!(query_value(&h.query, "token").as_deref(), Some("a+b"));
        assert_eq!(h.bearer.as_deref(), Some("xyz"));
        assert!(parse(b"GET / HTTP/1.1\r\n").unwrap().is_none());
        assert!(parse(b"\x00\x01garbage\r\n\r\n").is_err());
    }

    #[test]
    fn every_answer_carries_the_policy() {
        let a = String::from_utf8(Answer::error("404 Not Found", "no").to_bytes()).unwrap();
        assert!(a.contains("Content-Security-Policy: default-src 'self';"));
        assert!(String::from_utf8(event_stream_head())
            .unwrap()
            .contains("Content-Security-Policy"));
    }
}
