//! How `call` and `replay --server` reach a server: the options for the
//! timeouts and the access token, and the messages when it goes wrong.

use std::path::PathBuf;
use std::time::Duration;

use clap::Args;

use addipos::{WireClient, WireError};
use emulator::parse_address;
use uoi::tcp::{AccessToken, ClientError, ClientOptions, Waited};
use uoi::wire::ProtocolError;

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

fn parse_secs(s: &str) -> Result<Duration, String> {
    s.parse::<f64>()
        .ok()
        .filter(|v| *v > 0.0)
        .and_then(|v| Duration::try_from_secs_f64(v).ok())
        .ok_or_else(|| format!("`{s}` is not a number of seconds above 0"))
}

impl RemoteArgs {
    /// The client options these arguments give.
    fn options(&self) -> Result<ClientOptions, String> {
        let mut opts = ClientOptions::default();
        if let Some(t) = self.timeout {
            opts.connect_timeout = t;
            opts.request_timeout = t;
        }
        opts.token = match (&self.token_file, &self.token) {
            (Some(f), _) => Some(super::token::read_token_file(f).map_err(|e| e.to_string())?),
            (None, Some(t)) => Some(AccessToken::new(t).map_err(|e| format!("--token: {e}"))?),
            (None, None) => None,
        };
        Ok(opts)
    }
}

/// A hint for an `Unauthorized` answer.
pub fn token_hint(e: &WireError) -> &'static str {
    match e.client_error() {
        Some(ClientError::Protocol(p)) => protocol_hint(*p),
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
pub fn connect(addr: &str, args: &RemoteArgs) -> Result<WireClient, String> {
    let resolved = parse_address(addr)?;
    let opts = args.options()?;
    let at = resolved.to_string();
    let cannot = |e: ClientError| match e {
        ClientError::TimedOut {
            waited: Waited::Connect,
            ..
        } => e.to_string(),
        ClientError::TimedOut { after, .. } => format!(
            "could not reach a UOI server at {addr} ({resolved}): got no UOI answer within {} s \
             (is it an addipos server? --timeout sets the wait)",
            after.as_secs_f64()
        ),
        ClientError::Unexpected(_) | ClientError::Io(_) if is_answerless(&e) => format!(
            "could not reach a UOI server at {addr} ({resolved}): got no UOI answer \
             (it answered something else, or closed the connection: {e})"
        ),
        ClientError::Protocol(p) => format!(
            "cannot connect to {addr} ({resolved}): {e}{}",
            protocol_hint(p)
        ),
        e => format!("cannot connect to {addr} ({resolved}): {e}"),
    };
    WireClient::probe(&at, &opts).map_err(cannot)?;
    WireClient::connect(&at, opts).map_err(|e| match e {
        WireError::Connect(e) | WireError::Exchange(e) => cannot(e),
        e => e.to_string(),
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
