//! How `call` and `replay --server` reach a server: the options for the
//! timeouts and the access token, and the messages when it goes wrong.

use std::path::PathBuf;
use std::time::Duration;

use clap::Args;

use addipos_host::{WireClient, WireError};
use emulator::parse_address;
use uoi::tcp::{AccessToken, BadToken, ClientError, ClientOptions, Waited};
use uoi::wire::ProtocolError;

/// Why `call` or `replay --server` could not reach a server.
#[derive(Debug, thiserror::Error)]
pub enum ReachError {
    /// The address is not one (`parse_address`'s reason).
    #[error("{0}")]
    Address(#[source] emulator::AddressError),
    /// The token file could not be read (its error names it).
    #[error(transparent)]
    TokenFile(std::io::Error),
    /// The `--token` given is not a token.
    #[error("--token: {0}")]
    Token(BadToken),
    /// No connection within the connection timeout.
    #[error(transparent)]
    NoConnection(ClientError),
    /// Connected, but no answer within the wait.
    #[error(
        "could not reach a UOI server at {addr} ({resolved}): got no UOI answer within {} s \
         (is it an addipos server? --timeout sets the wait)",
        after.as_secs_f64()
    )]
    Silent {
        /// The address as typed.
        addr: String,
        /// What it resolved to.
        resolved: String,
        /// The wait.
        after: Duration,
    },
    /// Connected, but the peer answered something else or closed.
    #[error(
        "could not reach a UOI server at {addr} ({resolved}): got no UOI answer \
         (it answered something else, or closed the connection: {error})"
    )]
    NotUoi {
        /// The address as typed.
        addr: String,
        /// What it resolved to.
        resolved: String,
        /// What the client saw.
        error: ClientError,
    },
    /// The connection failed otherwise (refused, the token asked for).
    #[error("cannot connect to {addr} ({resolved}): {error}{}", client_hint(error))]
    Refused {
        /// The address as typed.
        addr: String,
        /// What it resolved to.
        resolved: String,
        /// What the client saw.
        error: ClientError,
    },
    /// The wire client failed otherwise.
    #[error(transparent)]
    Wire(WireError),
}

/// A `--timeout` that is not a number of seconds above 0.
#[derive(Debug, thiserror::Error)]
#[error("`{0}` is not a number of seconds above 0")]
struct BadSecs(String);

/// How `call` and `replay --server` reach the server.
#[derive(Args)]
pub struct RemoteArgs {
    /// Longest wait, in seconds, for the connection and for each answer
    /// [default: 5 for the connection, 30 for an answer].
    #[arg(long, value_name = "SECS", value_parser = parse_secs)]
    timeout: Option<Duration>,
    /// Access token to present (a server with allow_remote asks remote
    /// clients for it).
    #[arg(
        long,
        value_name = "TOKEN",
        env = "ADDIPOS_TOKEN",
        hide_env_values = true
    )]
    token: Option<String>,
    /// File holding the access token (the server's <data_dir>/access-token);
    /// takes precedence over --token and ADDIPOS_TOKEN.
    #[arg(long, value_name = "FILE")]
    token_file: Option<PathBuf>,
}

fn parse_secs(s: &str) -> Result<Duration, BadSecs> {
    s.parse::<f64>()
        .ok()
        .filter(|v| *v > 0.0)
        .and_then(|v| Duration::try_from_secs_f64(v).ok())
        .ok_or_else(|| BadSecs(s.to_string()))
}

impl RemoteArgs {
    /// The client options these arguments give.
    fn options(&self) -> Result<ClientOptions, ReachError> {
        let mut opts = ClientOptions::default();
        if let Some(t) = self.timeout {
            opts.connect_timeout = t;
            opts.request_timeout = t;
        }
        opts.token = match (&self.token_file, &self.token) {
            (Some(f), _) => Some(super::token::read_token_file(f).map_err(ReachError::TokenFile)?),
            (None, Some(t)) => Some(AccessToken::new(t).map_err(ReachError::Token)?),
            (None, None) => None,
        };
        Ok(opts)
    }
}

/// A hint for an `Unauthorized` answer.
pub fn token_hint(e: &WireError) -> &'static str {
    e.client_error().map_or("", client_hint)
}

/// A hint for a client's `Unauthorized` answer.
fn client_hint(e: &ClientError) -> &'static str {
    match e {
        ClientError::Protocol(p) => protocol_hint(*p),
        _ => "",
    }
}

/// What to do about a protocol error, if the user can do something.
pub fn protocol_hint(e: ProtocolError) -> &'static str {
    match e {
        ProtocolError::Unauthorized => {
            " (pass the server's access token with --token-file FILE, --token or ADDIPOS_TOKEN)"
        }
        _ => "",
    }
}

/// Connects `call` or `replay --server` to a server given as the user
/// typed its address, or says why not: nothing listening, or something
/// that is no UOI server (silent, or answering something else), found
/// within the connection timeout (decision 312).
pub fn connect(addr: &str, args: &RemoteArgs) -> Result<WireClient, ReachError> {
    let resolved = parse_address(addr).map_err(ReachError::Address)?;
    let opts = args.options()?;
    let at = resolved.to_string();
    let cannot = |e: ClientError| {
        let (addr, resolved) = (addr.to_string(), resolved.to_string());
        match e {
            ClientError::TimedOut {
                waited: Waited::Connect,
                ..
            } => ReachError::NoConnection(e),
            ClientError::TimedOut { after, .. } => ReachError::Silent {
                addr,
                resolved,
                after,
            },
            ClientError::Unexpected(_) | ClientError::Io(_) if is_answerless(&e) => {
                ReachError::NotUoi {
                    addr,
                    resolved,
                    error: e,
                }
            }
            error => ReachError::Refused {
                addr,
                resolved,
                error,
            },
        }
    };
    WireClient::probe(&at, &opts).map_err(cannot)?;
    WireClient::connect(&at, opts).map_err(|e| match e {
        WireError::Connect(e) | WireError::Exchange(e) => cannot(e),
        e => ReachError::Wire(e),
    })
}

/// Whether a client error after the connection was made means the peer
/// gave no UOI answer: an answer that does not decode, or the connection
/// closed or reset instead of an answer.
fn is_answerless(e: &ClientError) -> bool {
    match e {
        ClientError::Unexpected(_) => true,
        ClientError::Io(io) => matches!(
            io.kind(),
            std::io::ErrorKind::UnexpectedEof
                | std::io::ErrorKind::ConnectionReset
                | std::io::ErrorKind::ConnectionAborted
                | std::io::ErrorKind::BrokenPipe
                | std::io::ErrorKind::InvalidData
        ),
        _ => false,
    }
}
