//! Crash test of durable tool data (issue 10): `addipos serve` as a child
//! process, many connections writing tool values pipelined, SIGKILL at a
//! random moment, restart on the same data directory. Every acknowledged
//! write must be there (or a write to the same field sent after it), no
//! field may hold a value that was never sent, and the tool files and the
//! journal left by the kill must load strictly.
//!
//! Each round is seeded from one run seed (printed with every failure;
//! `CRASH_SEED=<n>` repeats a run).

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::collections::{BTreeMap, HashMap};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Barrier};
use std::time::{Duration, Instant};

use bytes::{Bytes, BytesMut};
use common::ServeProcess;
use tool_store::{MemStorage, Storage, Strictness, ToolField, ToolStore, ToolValue};
use uoi::tcp::{BlockingClient, ClientOptions};
use uoi::wire::{decode_answer, encode_request, Answer, Op, Request};
use uoi::{ObjectAddress, Value, ValueType};

/// Crash rounds in one run.
const ROUNDS: u64 = 20;
/// Connections per round; connection `c` writes group `c + 1` only.
const CONNECTIONS: u8 = 32;
/// Tool writes each connection pipelines per round.
const WRITES: usize = 2000;
/// The kill comes this many milliseconds after the writes start, at most.
const MAX_DELAY_MS: u64 = 300;
/// Requests a connection sends ahead of its answers. The server serves a
/// connection's requests one after the other, and writes answers out once
/// no further request is buffered: a small window gets answers back while
/// the kill can still come.
const WINDOW: usize = 8;
/// Hang guard on every wait for the server.
const GUARD: Duration = Duration::from_secs(15);

/// One field of one entry of one group: (group, WKZINDEX, field).
type Key = (u8, u16, Field);

/// The two tool fields written directly on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Field {
    /// 1/g/6 RADIUS.
    Radius,
    /// 1/g/12 WkzLen.
    Length,
}

impl Field {
    fn sub(self) -> u8 {
        match self {
            Field::Radius => 6,
            Field::Length => 12,
        }
    }

    fn store(self) -> ToolField {
        match self {
            Field::Radius => ToolField::Radius,
            Field::Length => ToolField::Length,
        }
    }
}

/// splitmix64: a small reproducible generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

fn tc(device: u8, group: u8, sub: u8) -> ObjectAddress {
    ObjectAddress::new(1300, device.into(), group.into(), sub.into())
}

/// What one connection sends in a round: WKZINDEX first (request 0), then
/// the tool writes (request k + 1 is `writes[k]`).
struct Plan {
    group: u8,
    index: u16,
    writes: Vec<(Field, f64)>,
}

impl Plan {
    fn new(round: u64, group: u8, rng: &mut Rng) -> Self {
        let index = rng.below(1024) as u16;
        let writes = (0..WRITES)
            .map(|k| {
                let field = if rng.below(2) == 0 {
                    Field::Radius
                } else {
                    Field::Length
                };
                // Unique over the whole run, never 0, not a short decimal.
                let tag = ((round * 64 + u64::from(group)) * WRITES as u64 + k as u64 + 1) as f64;
                let sign = if k % 3 == 0 { -1.0 } else { 1.0 };
                (field, sign * tag / 7.0)
            })
            .collect();
        Self {
            group,
            index,
            writes,
        }
    }

    /// Every request's frame, in id order.
    fn frames(&self) -> Vec<Vec<u8>> {
        let wkz = Value::I32(i32::from(self.index));
        let first = Request::Write(tc(1, self.group, 8), wkz);
        let tools = self
            .writes
            .iter()
            .map(|(field, v)| Request::Write(tc(1, self.group, field.sub()), Value::F64(*v)));
        std::iter::once(first)
            .chain(tools)
            .enumerate()
            .map(|(id, req)| {
                let mut out = BytesMut::new();
                encode_request(id as u32, &req, &mut out);
                out.to_vec()
            })
            .collect()
    }
}

/// Sends a plan's frames on one connection, at most [`WINDOW`] ahead of
/// the answers, and collects the answers (indexed by request id) until all
/// came or the server went away. Returns them and how many requests were
/// (at least partly) sent.
fn run_connection(addr: &str, plan: &Plan, start: &Barrier) -> (Vec<Option<Answer>>, usize) {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_nodelay(true).expect("nodelay");
    s.set_read_timeout(Some(GUARD)).expect("timeout");
    let frames = plan.frames();
    start.wait();
    let total = frames.len();
    let (mut answers, mut sent) = (vec![None; total], 0);
    for received in 0..total {
        let upto = total.min(received + WINDOW);
        if sent < upto {
            let bytes: Vec<u8> = frames[sent..upto].concat();
            sent = upto;
            if s.write_all(&bytes).is_err() {
                break;
            }
        }
        let Some((id, ans)) = read_answer(&mut s) else {
            break;
        };
        answers[id as usize] = Some(ans);
    }
    (answers, sent)
}

/// The next answer; `None` once the server is gone.
fn read_answer(s: &mut TcpStream) -> Option<(u32, Answer)> {
    let mut prefix = [0u8; 4];
    let mut read = |buf: &mut [u8]| match s.read_exact(buf) {
        Ok(()) => Some(()),
        Err(e) if is_gone(&e) => None,
        Err(e) => panic!("no answer within {GUARD:?}: {e}"),
    };
    read(&mut prefix)?;
    let mut body = vec![0u8; u32::from_le_bytes(prefix) as usize];
    read(&mut body)?;
    Some(decode_answer(Bytes::from(body), Op::Write).expect("an answer frame"))
}

/// The connection ended because the server is gone (not a timeout).
fn is_gone(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::*;
    matches!(
        e.kind(),
        UnexpectedEof | ConnectionReset | ConnectionAborted | BrokenPipe
    )
}

/// The values each field may hold after the crash, as f64 bits.
type Model = BTreeMap<Key, Vec<u64>>;

/// Folds one connection's round into the model: a field may hold the last
/// acknowledged value written to it or any value sent after that one; if
/// no write to it was acknowledged, also what it held before the round.
fn expect_after(model: &mut Model, plan: &Plan, answers: &[Option<Answer>], sent: usize) -> usize {
    let mut per_key: HashMap<Key, (Option<usize>, Vec<u64>)> = HashMap::new();
    let mut acked = 0;
    // Request k + 1 is write k; request 0 is the WKZINDEX.
    for (k, (field, v)) in plan.writes.iter().enumerate().take(sent.saturating_sub(1)) {
        let entry = per_key.entry((plan.group, plan.index, *field)).or_default();
        if answers[k + 1] == Some(Answer::Ok) {
            acked += 1;
            entry.0 = Some(entry.1.len());
        }
        entry.1.push(v.to_bits());
    }
    for (key, (last_acked, sent)) in per_key {
        let allowed = model.entry(key).or_insert_with(|| vec![0.0f64.to_bits()]);
        match last_acked {
            Some(i) => *allowed = sent[i..].to_vec(),
            None => allowed.extend(sent),
        }
    }
    acked
}

/// The tool values the data directory holds, loaded strictly from a copy
/// (so the torn tail is not cut off the real journal here).
fn load_strictly(tools: &Path, why: &str) -> BTreeMap<(u8, u16, ToolField), u64> {
    let mut mem = MemStorage::new();
    for entry in std::fs::read_dir(tools).expect("tools dir") {
        let path = entry.expect("entry").path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".wz") {
            mem.put_file(&name, std::fs::read(&path).expect("read"));
        }
    }
    if let Ok(j) = std::fs::read(tools.join(tool_store::JOURNAL_FILE)) {
        mem.append_journal(&j).expect("journal");
    }
    let (store, _) = ToolStore::open(mem, Strictness::Strict)
        .unwrap_or_else(|e| panic!("{why}: the tool data does not load strictly: {e}"));
    store
        .values()
        .map(|(g, k, v)| {
            let bits = match v {
                ToolValue::F64(f) => f.to_bits(),
                ToolValue::I32(i) => f64::from(i).to_bits(),
            };
            ((g, k.index, k.field), bits)
        })
        .collect()
}

/// Reads every field of the model from the server, checks it against the
/// model and the strict load of the files, and pins the model to it.
fn verify(addr: &str, model: &mut Model, on_disk: &BTreeMap<(u8, u16, ToolField), u64>, why: &str) {
    let opts = ClientOptions {
        request_timeout: GUARD,
        ..ClientOptions::default()
    };
    let mut c = BlockingClient::connect_with(addr, &opts).expect("connect");
    let keys: Vec<Key> = model.keys().copied().collect();
    let reqs: Vec<Request> = keys
        .iter()
        .flat_map(|&(g, i, f)| {
            [
                Request::Write(tc(1, g, 8), Value::I32(i32::from(i))),
                Request::Read(tc(1, g, f.sub()), ValueType::F64),
            ]
        })
        .collect();
    let answers = c.pipeline(&reqs).expect("read back");
    for (n, key) in keys.iter().enumerate() {
        let Answer::Value(Value::F64(got)) = answers[2 * n + 1] else {
            panic!("{why}: {key:?}: answer {:?}", answers[2 * n + 1]);
        };
        let allowed = &model[key];
        assert!(
            allowed.contains(&got.to_bits()),
            "{why}: {key:?} holds {got}, not the last acknowledged value nor one sent after it \
             (allowed: {:?})",
            allowed
                .iter()
                .map(|b| f64::from_bits(*b))
                .collect::<Vec<_>>()
        );
        let file = on_disk.get(&(key.0, key.1, key.2.store())).copied();
        assert_eq!(
            file.unwrap_or(0.0f64.to_bits()),
            got.to_bits(),
            "{why}: {key:?}: the files say {file:?}, the server {got}"
        );
        model.insert(*key, vec![got.to_bits()]);
    }
    let known = |&(g, i, f): &(u8, u16, ToolField)| {
        [Field::Radius, Field::Length]
            .iter()
            .any(|x| x.store() == f && model.contains_key(&(g, i, *x)))
    };
    if let Some(stray) = on_disk.keys().find(|k| !known(k)) {
        panic!("{why}: the files hold {stray:?}, which was never written");
    }
}

fn serve(dir: &Path) -> ServeProcess {
    let dir = dir.to_str().expect("utf-8 path");
    ServeProcess::start(&["--data-dir", dir, "--listen", "127.0.0.1:0"], &[])
}

/// One round: writes on every connection, SIGKILL after `delay`; returns
/// (acknowledged, answered) writes.
fn crash_round(
    dir: &Path,
    round: u64,
    rng: &mut Rng,
    model: &mut Model,
    why: &str,
) -> (usize, usize) {
    let server = serve(dir);
    let on_disk = load_strictly(&dir.join("tools"), why);
    verify(&server.addr, model, &on_disk, why);
    let plans: Vec<Arc<Plan>> = (1..=CONNECTIONS)
        .map(|g| Arc::new(Plan::new(round, g, rng)))
        .collect();
    let delay = Duration::from_millis(rng.below(MAX_DELAY_MS + 1));
    let start = Arc::new(Barrier::new(plans.len() + 1));
    let clients: Vec<_> = plans
        .iter()
        .map(|p| {
            let (p, start, addr) = (Arc::clone(p), Arc::clone(&start), server.addr.clone());
            std::thread::spawn(move || run_connection(&addr, &p, &start))
        })
        .collect();
    start.wait();
    std::thread::sleep(delay);
    // `stop` is SIGKILL: no shutdown, no compaction.
    server.stop();
    let (mut acked, mut answered) = (0, 0);
    for (plan, client) in plans.iter().zip(clients) {
        let (answers, sent) = client.join().expect("client");
        answered += answers.iter().flatten().count();
        acked += expect_after(model, plan, &answers, sent);
    }
    eprintln!("{why}: kill after {delay:?}: {acked} writes acknowledged, {answered} answers");
    (acked, answered)
}

#[test]
fn acknowledged_tool_writes_survive_sigkill() {
    let seed = std::env::var("CRASH_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(1, |d| d.as_nanos() as u64)
        });
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("crash-{seed}"));
    let _ = std::fs::remove_dir_all(&dir);
    let t0 = Instant::now();
    let mut model = Model::new();
    let mut total = 0;
    for round in 0..ROUNDS {
        let mut rng = Rng(seed ^ round.wrapping_mul(0x2545_f491_4f6c_dd1d));
        let why = format!("CRASH_SEED={seed} round {round}");
        total += crash_round(&dir, round, &mut rng, &mut model, &why).0;
    }
    // The last crash checked, then a clean stop: compacted into the files.
    let why = format!("CRASH_SEED={seed} after the last round");
    let server = serve(&dir);
    let on_disk = load_strictly(&dir.join("tools"), &why);
    verify(&server.addr, &mut model, &on_disk, &why);
    let (status, log) = server.terminate(GUARD);
    assert!(status.success(), "{why}: serve ended with {status}: {log}");
    let journal =
        std::fs::read(dir.join("tools").join(tool_store::JOURNAL_FILE)).unwrap_or_default();
    assert!(journal.is_empty(), "{why}: journal not compacted at stop");
    let compacted = load_strictly(&dir.join("tools"), &why);
    assert_eq!(compacted, on_disk, "{why}: compaction changed values");
    eprintln!(
        "{ROUNDS} rounds, {total} writes acknowledged, {} fields, {:?}",
        model.len(),
        t0.elapsed()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
