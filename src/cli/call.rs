//! `addipos call ADDR REQUEST`: one request in trace syntax sent to a
//! server, its answer printed.

use tc_request::text::parse_request;
use tc_request::{Reply, AXIS_NAMES};

use super::remote_args::{connect, protocol_hint, token_hint, RemoteArgs};
use super::{Failure, Outcome};

/// Runs `addipos call`: `words` is the request in trace syntax.
pub fn cmd_call(addr: &str, words: &[String], remote_args: &RemoteArgs) -> Outcome {
    let text = words.join(" ");
    let req = parse_request(&text).map_err(|e| Failure::trouble(format!("`{text}`: {e}")))?;
    let mut client = connect(addr, remote_args).map_err(Failure::trouble)?;
    let reply = client
        .call(&req)
        .map_err(|e| Failure::failed(format!("{e}{}", token_hint(&e))))?;
    match reply {
        Reply::Ok => println!("ok"),
        Reply::Value(v) => println!("{v}"),
        Reply::Queue(n) => println!("{n}"),
        Reply::Pos(p) => {
            let words: Vec<String> = AXIS_NAMES
                .iter()
                .zip(p)
                .map(|(n, v)| format!("{n}{v}"))
                .collect();
            println!("{}", words.join(" "));
        }
        Reply::Access(e) => {
            println!("err {}", e.name());
            return Err(Failure::reported());
        }
        Reply::Protocol(e) => return Err(Failure::failed(format!("{e}{}", protocol_hint(e)))),
        other => return Err(Failure::failed(format!("unexpected answer {other:?}"))),
    }
    Ok(())
}
