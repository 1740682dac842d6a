//! Crash test of durable tool data: `addipos serve` as a child
//! process, many connections writing tool values pipelined, SIGKILL at a
//! random moment, restart on the same data directory. Every acknowledged
//! write must be there (or a write to the same field sent after it), no
//! field may hold a value that was never sent, and the tool files and the
//! journal left by the kill must load strictly.
//!
//! Further rounds where the journal is deleted while the writes run
//! (every fourth round), and a run on a small volume (a tmpfs, where
//! mounting one is allowed) that a ballast file fills while the writes
//! run: the writes it refuses are not acknowledged, no acknowledged one is
//! lost, writes work again once there is room, and the refusals are
//! logged at most once a second.
//!
//! Each round is seeded from one run seed (printed with every failure;
//! `CRASH_SEED=<n>` repeats a run).

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::collections::{BTreeMap, HashMap};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Barrier, OnceLock};
use std::time::{Duration, Instant};

use bytes::{Bytes, BytesMut};
use common::ServeProcess;
use tc_objects::TcObject;
use tool_store::{MemStorage, Storage, Strictness, ToolField, ToolStore, ToolValue};
use uoi::tcp::{BlockingClient, ClientOptions};
use uoi::wire::{decode_answer, encode_request, Answer, Op, Request};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

/// Crash rounds in one run.
const ROUNDS: u64 = 20;
/// Every this many rounds (from round 1), the journal is deleted halfway
/// to the kill.
const DELETE_EVERY: u64 = 4;
/// Crash rounds on the small volume that fills.
const FULL_ROUNDS: u64 = 8;
/// The small volume's size.
const VOLUME: &str = "2m";
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

/// WKZINDEX of `group`.
fn wkz_index(group: u8) -> ObjectAddress {
    TcObject::WkzIndex.of(group.into())
}

/// The object of `field` in `group`.
fn tool_object(group: u8, field: Field) -> ObjectAddress {
    field.store().address(group.into())
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
        let first = Request::Write(wkz_index(self.group), wkz);
        let tools = self
            .writes
            .iter()
            .map(|(field, v)| Request::Write(tool_object(self.group, *field), Value::F64(*v)));
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

/// When the journal was deleted, and whether a write sent after that was
/// acknowledged: the server then had noticed the deletion and made the
/// journal anew, so every write acknowledged before is durable again.
#[derive(Default)]
struct Watch {
    deleted_at: OnceLock<Instant>,
    noticed: AtomicBool,
}

impl Watch {
    /// Notes the answer to a tool write sent at `sent`.
    fn answered(&self, sent: Instant, answer: &Answer) {
        if *answer == Answer::Ok && self.deleted_at.get().is_some_and(|d| sent > *d) {
            self.noticed.store(true, Ordering::Release);
        }
    }
}

/// Sends a plan's frames on one connection, at most [`WINDOW`] ahead of
/// the answers, and collects the answers (indexed by request id) until all
/// came or the server went away. Returns them and how many requests were
/// (at least partly) sent.
fn run_connection(
    addr: &str,
    plan: &Plan,
    start: &Barrier,
    watch: &Watch,
) -> (Vec<Option<Answer>>, usize) {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_nodelay(true).expect("nodelay");
    s.set_read_timeout(Some(GUARD)).expect("timeout");
    let frames = plan.frames();
    start.wait();
    let total = frames.len();
    let (mut answers, mut sent) = (vec![None; total], 0);
    let mut sent_at = vec![Instant::now(); total];
    for received in 0..total {
        let upto = total.min(received + WINDOW);
        if sent < upto {
            let bytes: Vec<u8> = frames[sent..upto].concat();
            sent_at[sent..upto].fill(Instant::now());
            sent = upto;
            if s.write_all(&bytes).is_err() {
                break;
            }
        }
        let Some((id, ans)) = read_answer(&mut s) else {
            break;
        };
        if id > 0 {
            // A tool write (request 0 is the WKZINDEX, never on disk).
            watch.answered(sent_at[id as usize], &ans);
        }
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
                Request::Write(wkz_index(g), Value::I32(i32::from(i))),
                Request::Read(tool_object(g, f), ValueType::F64),
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

/// What happens to the disk while a round's writes run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Disturbance {
    /// Nothing.
    None,
    /// `rm journal.wzj` halfway to the kill.
    DeleteJournal,
    /// A ballast file fills the volume a third of the way to the kill;
    /// removed at two thirds (`room_again`) or only after the restart.
    FillDisk {
        /// The room comes back before the kill.
        room_again: bool,
    },
}

/// The ballast that fills the small volume at `root`.
fn ballast(root: &Path) -> PathBuf {
    root.join("ballast")
}

/// Writes a ballast file until the volume at `root` is full.
fn fill(root: &Path) {
    let mut f = std::fs::File::create(ballast(root)).expect("ballast");
    let block = vec![0x55u8; 4096];
    while f.write_all(&block).is_ok() {}
    while f.write_all(&block[..1]).is_ok() {}
}

/// Acts on the disk as `what` says while the writes run for `delay`. A
/// deleted journal: the kill waits until a write sent after the deletion
/// is acknowledged (until then, writes acknowledged before the deletion
/// were only in the deleted file: a crash loses them, as a user who
/// deletes the journal of a running server must expect).
fn disturb(what: Disturbance, dir: &Path, delay: Duration, watch: &Watch) {
    let root = dir.parent().expect("the volume");
    match what {
        Disturbance::None => std::thread::sleep(delay),
        Disturbance::DeleteJournal => {
            std::thread::sleep(delay / 2);
            let journal = dir.join("tools").join(tool_store::JOURNAL_FILE);
            // The journal may not exist yet (nothing written so far).
            let _ = std::fs::remove_file(journal);
            let _ = watch.deleted_at.set(Instant::now());
            std::thread::sleep(delay / 2);
            let t0 = Instant::now();
            while !watch.noticed.load(Ordering::Acquire) {
                assert!(
                    t0.elapsed() < GUARD,
                    "no write acknowledged after the deletion"
                );
                std::thread::sleep(Duration::from_millis(1));
            }
        }
        Disturbance::FillDisk { room_again } => {
            std::thread::sleep(delay / 3);
            fill(root);
            std::thread::sleep(delay / 3);
            if room_again {
                std::fs::remove_file(ballast(root)).expect("ballast");
            }
            std::thread::sleep(delay / 3);
        }
    }
}

/// What one round saw: acknowledged writes, writes refused with
/// `Storage`, the server's log.
struct Round {
    acked: usize,
    refused: usize,
    log: String,
}

/// One round: writes on every connection, the disk disturbed as `what`
/// says, SIGKILL after a random delay.
fn crash_round(
    dir: &Path,
    round: u64,
    rng: &mut Rng,
    model: &mut Model,
    what: Disturbance,
    why: &str,
) -> Round {
    let server = serve(dir);
    let on_disk = load_strictly(&dir.join("tools"), why);
    verify(&server.addr, model, &on_disk, why);
    // A disk left full by the last round has room again.
    let _ = std::fs::remove_file(ballast(dir.parent().expect("parent")));
    let plans: Vec<Arc<Plan>> = (1..=CONNECTIONS)
        .map(|g| Arc::new(Plan::new(round, g, rng)))
        .collect();
    let delay = Duration::from_millis(rng.below(MAX_DELAY_MS + 1));
    let start = Arc::new(Barrier::new(plans.len() + 1));
    let watch = Arc::new(Watch::default());
    let clients: Vec<_> = plans
        .iter()
        .map(|p| {
            let (p, start, addr) = (Arc::clone(p), Arc::clone(&start), server.addr.clone());
            let watch = Arc::clone(&watch);
            std::thread::spawn(move || run_connection(&addr, &p, &start, &watch))
        })
        .collect();
    start.wait();
    disturb(what, dir, delay, &watch);
    // `stop` is SIGKILL: no shutdown, no compaction.
    let log = server.stop();
    let (mut acked, mut answered, mut refused) = (0, 0, 0);
    let storage = Answer::Access(AccessError::Storage);
    for (plan, client) in plans.iter().zip(clients) {
        let (answers, sent) = client.join().expect("client");
        answered += answers.iter().flatten().count();
        refused += answers.iter().flatten().filter(|a| **a == storage).count();
        acked += expect_after(model, plan, &answers, sent);
    }
    let anew = lines(&log, "journal made anew");
    eprintln!(
        "{why}: {what:?}, kill after {delay:?}: {answered} answers, {acked} writes \
         acknowledged, {refused} refused; journal made anew {anew} times"
    );
    Round {
        acked,
        refused,
        log,
    }
}

/// The run's seed: `CRASH_SEED`, or the clock.
fn run_seed() -> u64 {
    std::env::var("CRASH_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(1, |d| d.as_nanos() as u64)
        })
}

/// After the last crash: the data checked, then a clean stop, which
/// compacts the journal into the files without changing a value.
fn stop_cleanly(dir: &Path, model: &mut Model, why: &str) {
    let server = serve(dir);
    let on_disk = load_strictly(&dir.join("tools"), why);
    verify(&server.addr, model, &on_disk, why);
    let (status, log) = server.terminate(GUARD);
    assert!(status.success(), "{why}: serve ended with {status}: {log}");
    let journal =
        std::fs::read(dir.join("tools").join(tool_store::JOURNAL_FILE)).unwrap_or_default();
    assert!(journal.is_empty(), "{why}: journal not compacted at stop");
    let compacted = load_strictly(&dir.join("tools"), why);
    assert_eq!(compacted, on_disk, "{why}: compaction changed values");
}

#[test]
fn acknowledged_tool_writes_survive_sigkill() {
    let seed = run_seed();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("crash-{seed}"))
        .join("data");
    let _ = std::fs::remove_dir_all(dir.parent().expect("parent"));
    let t0 = Instant::now();
    let mut model = Model::new();
    let mut total = 0;
    for round in 0..ROUNDS {
        let mut rng = Rng(seed ^ round.wrapping_mul(0x2545_f491_4f6c_dd1d));
        let why = format!("CRASH_SEED={seed} round {round}");
        let what = match round % DELETE_EVERY {
            1 => Disturbance::DeleteJournal,
            _ => Disturbance::None,
        };
        total += crash_round(&dir, round, &mut rng, &mut model, what, &why).acked;
    }
    let why = format!("CRASH_SEED={seed} after the last round");
    stop_cleanly(&dir, &mut model, &why);
    eprintln!(
        "{ROUNDS} rounds, {total} writes acknowledged, {} fields, {:?}",
        model.len(),
        t0.elapsed()
    );
    let _ = std::fs::remove_dir_all(dir.parent().expect("parent"));
}

/// A tmpfs of [`VOLUME`] mounted at `dir`, unmounted when dropped.
struct SmallVolume(PathBuf);

impl SmallVolume {
    /// `None` (with a note) where mounting is not allowed.
    fn mount(dir: PathBuf) -> Option<Self> {
        let quiet = |c: &mut Command| c.stdout(Stdio::null()).stderr(Stdio::null()).status();
        let _ = quiet(Command::new("umount").arg(&dir));
        std::fs::create_dir_all(&dir).expect("mount point");
        let mount = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={VOLUME}"), "tmpfs"])
            .arg(&dir)
            .output();
        match mount {
            Ok(out) if out.status.success() => Some(Self(dir)),
            other => {
                eprintln!("skipped: cannot mount a {VOLUME} tmpfs here (needs root): {other:?}");
                None
            }
        }
    }
}

impl Drop for SmallVolume {
    fn drop(&mut self) {
        let _ = Command::new("umount")
            .arg(&self.0)
            .stderr(Stdio::null())
            .status();
        let _ = std::fs::remove_dir(&self.0);
    }
}

/// Lines of `log` that say `what`.
fn lines(log: &str, what: &str) -> usize {
    log.lines().filter(|l| l.contains(what)).count()
}

#[test]
fn acknowledged_tool_writes_survive_a_full_disk_and_sigkill() {
    let seed = run_seed();
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("crash-full-{seed}"));
    let Some(volume) = SmallVolume::mount(root) else {
        return;
    };
    let dir = volume.0.join("data");
    let t0 = Instant::now();
    let mut model = Model::new();
    let (mut total, mut refused) = (0, 0);
    for round in 0..FULL_ROUNDS {
        let mut rng = Rng(seed ^ round.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let why = format!("CRASH_SEED={seed} full disk, round {round}");
        let what = Disturbance::FillDisk {
            room_again: round % 2 == 1,
        };
        let started = Instant::now();
        let r = crash_round(&dir, round, &mut rng, &mut model, what, &why);
        // At most one warning of each kind a second (the server lived
        // within `started..now`).
        let most = started.elapsed().as_secs() as usize + 1;
        for kind in ["tool data not stored", "tool journal not compacted"] {
            let n = lines(&r.log, kind);
            assert!(
                n <= most,
                "{why}: {n} lines of `{kind}` in {:?}",
                started.elapsed()
            );
        }
        total += r.acked;
        refused += r.refused;
    }
    let why = format!("CRASH_SEED={seed} full disk, after the last round");
    stop_cleanly(&dir, &mut model, &why);
    assert!(
        refused > 0,
        "{why}: the full disk refused nothing; the test did not fill it"
    );
    eprintln!(
        "{FULL_ROUNDS} rounds on a full disk, {total} writes acknowledged, {refused} refused, \
         {} fields, {:?}",
        model.len(),
        t0.elapsed()
    );
}
