//! `addipos call ADDR REQUEST`: one request in trace syntax sent to a
//! server, its answer printed.

use tc_request::text::parse_request;
use tc_request::{Reply, Request, AXIS_NAMES};
use uoi::AccessError;

use super::remote_args::{connect, protocol_hint, token_hint, RemoteArgs};
use super::{Failure, Outcome};

/// What an access error means for this request, after its machine-readable
/// name (decision 319).
fn meaning(e: AccessError, req: &Request) -> String {
    let addr = match req {
        Request::Read(a, _) | Request::Write(a, _) => Some(*a),
        _ => None,
    };
    match (e, addr) {
        (AccessError::NoObject, Some(a)) => format!(
            "no object {}/{}/{} (bus, device or index does not exist; `addipos objects` lists them)",
            a.bus, a.device, a.index
        ),
        (AccessError::NoSubindex, Some(a)) => format!(
            "object {}/{}/{} has no subindex {} (`addipos objects` lists them)",
            a.bus, a.device, a.index, a.sub
        ),
        (AccessError::State, _) => "refused in the current state: the correction group may be \
            in fault (read its ERROR register); writing the group's RESET clears the fault"
            .to_string(),
        (e, _) => e.text().to_string(),
    }
}

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
            println!("err {}: {}", e.name(), meaning(e, &req));
            return Err(Failure::reported());
        }
        Reply::Protocol(e) => return Err(Failure::failed(format!("{e}{}", protocol_hint(e)))),
        other => return Err(Failure::failed(format!("unexpected answer {other:?}"))),
    }
    Ok(())
}
