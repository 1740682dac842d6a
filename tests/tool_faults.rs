//! Durable before acknowledged, with a disk that fails on purpose: the
//! emulator served over TCP keeps its tool data in a tool store
//! on a `FaultyStorage`. A write the disk refuses is answered `Storage`
//! and changes nothing; later writes work; after a restart (the store
//! reopened from what the disk holds, after a crash or a clean stop) no
//! acknowledged write is lost and no refused write is visible.
//!
//! Also a journal deleted under the server, and a small volume,
//! simulated and real, that the journal must not wedge.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Barrier, Mutex};
use std::time::Duration;

use common::{loopback, TestServer};
use emulator::tools::durable::Durable;
use emulator::EmulatorService;
use tc_module::CycleTime;
use tc_objects::{OtcObject, TcObject};
use tool_store::replay_journal as replay;
use tool_store::Writer;
use tool_store::{
    FaultKind, FaultyStorage, MemStorage, Op, Record, Storage, Strictness, ToolField, ToolKey,
    ToolStore, ToolValue,
};
use uoi::tcp::BlockingClient;
use uoi::wire::{Answer, Request};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

/// The disk: storage in memory that outlives the server using it, so the
/// store can be reopened from it ("restart").
#[derive(Debug, Clone, Default)]
struct Disk(Arc<Mutex<MemStorage>>, Duration);

impl Disk {
    /// What the disk holds now: what a restart after a crash sees.
    fn snapshot(&self) -> MemStorage {
        self.0.lock().unwrap().clone()
    }
}

impl Storage for Disk {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        self.0.lock().unwrap().read_file(name)
    }
    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        self.0.lock().unwrap().write_file_atomic(name, bytes)
    }
    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        self.0.lock().unwrap().read_journal()
    }
    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.0.lock().unwrap().append_journal(bytes)
    }
    fn sync_journal(&mut self) -> io::Result<()> {
        // A disk whose flush takes time: changes pile up for one batch.
        std::thread::sleep(self.1);
        self.0.lock().unwrap().sync_journal()
    }
    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        self.0.lock().unwrap().truncate_journal(len)
    }
    fn journal_in_place(&mut self) -> io::Result<bool> {
        self.0.lock().unwrap().journal_in_place()
    }
    fn available_space(&mut self) -> io::Result<Option<u64>> {
        self.0.lock().unwrap().available_space()
    }
    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        self.0.lock().unwrap().remove_temporaries()
    }
}

/// A server of a fresh emulator whose tool data goes to `disk` through
/// `faults` (a `FaultyStorage` around the disk).
fn serve(faults: impl FnOnce(FaultyStorage<Disk>) -> FaultyStorage<Disk>) -> Rig {
    serve_on(Disk::default(), faults)
}

/// As [`serve`], on `disk`.
fn serve_on(disk: Disk, faults: impl FnOnce(FaultyStorage<Disk>) -> FaultyStorage<Disk>) -> Rig {
    let storage = faults(FaultyStorage::new(disk.clone()));
    let (store, _) = ToolStore::open(storage, Strictness::Strict).expect("open");
    let mut service = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    service.set_tools(Box::new(Durable::new(
        Writer::start(store).expect("writer"),
    )));
    let server = TestServer::with(loopback(), service);
    let client = BlockingClient::connect(&server.addr.to_string()).expect("connect");
    Rig {
        server: Some(server),
        disk,
        client,
    }
}

struct Rig {
    server: Option<TestServer>,
    disk: Disk,
    client: BlockingClient,
}

const RADIUS: TcObject = TcObject::Radius;
const LENGTH: TcObject = TcObject::WkzLen;

impl Rig {
    fn write(&mut self, addr: ObjectAddress, v: Value) -> Answer {
        self.client.call(&Request::Write(addr, v)).expect("write")
    }

    /// Sets `field` (RADIUS, WkzLen) of entry `index` of group `g`.
    fn set(&mut self, g: u16, index: i32, field: TcObject, v: f64) -> Answer {
        let wkz = TcObject::WkzIndex.of(g);
        assert_eq!(self.write(wkz, Value::I32(index)), Answer::Ok);
        self.write(field.of(g), Value::F64(v))
    }

    /// `field` of entry `index` of group `g`, as the server holds it.
    fn get(&mut self, g: u16, index: i32, field: TcObject) -> f64 {
        let wkz = TcObject::WkzIndex.of(g);
        assert_eq!(self.write(wkz, Value::I32(index)), Answer::Ok);
        match self.client.read(field.of(g), ValueType::F64).expect("read") {
            Value::F64(v) => v,
            other => panic!("{other:?}"),
        }
    }

    /// Stops the server cleanly (the journal compacted into the files)
    /// and gives back the disk.
    fn stop(mut self) -> MemStorage {
        drop(self.server.take());
        self.disk.snapshot()
    }
}

/// The store reopened from `disk` (a restart): strict, so the journal and
/// the files must be sound.
fn reopen(disk: MemStorage) -> ToolStore<MemStorage> {
    ToolStore::open(disk, Strictness::Strict).expect("reopen").0
}

fn stored(store: &ToolStore<MemStorage>, g: u8, index: u16, field: ToolField) -> f64 {
    match store.get(g, ToolKey::new(index, field).unwrap()) {
        ToolValue::F64(v) => v,
        ToolValue::I32(v) => f64::from(v),
    }
}

/// No record of the journal on `disk` sets `field` of (`g`, `index`) to `v`.
fn never_journalled(disk: &MemStorage, g: u8, index: u16, field: ToolField, v: f64) {
    let records = replay(disk.journal()).expect("journal").records;
    let refused = Record::Set {
        group: g,
        key: ToolKey::new(index, field).unwrap(),
        value: ToolValue::F64(v),
    };
    assert!(!records.contains(&refused), "{refused:?} in the journal");
}

/// The second tool write meets `op` failing as `kind`: `Storage`, the old
/// value stays, the next write works; after a crash and after a clean
/// stop the store holds exactly the acknowledged writes.
fn refused_write_changes_nothing(op: Op, kind: FaultKind) {
    let mut rig = serve(|s| s.fail_at(op, 2, kind));
    assert_eq!(rig.set(1, 5, RADIUS, 1.5), Answer::Ok);
    assert_eq!(
        rig.set(1, 5, RADIUS, 2.5),
        Answer::Access(AccessError::Storage),
        "{op:?} {kind:?}"
    );
    assert_eq!(rig.get(1, 5, RADIUS), 1.5, "memory ran ahead of the disk");
    assert_eq!(rig.set(1, 5, LENGTH, 7.25), Answer::Ok);
    assert_eq!(rig.set(1, 6, RADIUS, 3.5), Answer::Ok);
    assert_eq!((rig.get(1, 5, LENGTH), rig.get(1, 6, RADIUS)), (7.25, 3.5));

    let crashed = rig.disk.snapshot();
    never_journalled(&crashed, 1, 5, ToolField::Radius, 2.5);
    let stopped = rig.stop();
    for disk in [crashed, stopped] {
        let store = reopen(disk);
        assert_eq!(
            stored(&store, 1, 5, ToolField::Radius),
            1.5,
            "{op:?} {kind:?}"
        );
        assert_eq!(stored(&store, 1, 5, ToolField::Length), 7.25);
        assert_eq!(stored(&store, 1, 6, ToolField::Radius), 3.5);
        assert_eq!(store.values().count(), 3);
    }
}

#[test]
fn a_failed_append_is_answered_storage_and_changes_nothing() {
    refused_write_changes_nothing(Op::Append, FaultKind::Fail);
}

#[test]
fn a_failed_fsync_is_answered_storage_and_changes_nothing() {
    refused_write_changes_nothing(Op::Sync, FaultKind::Fail);
}

#[test]
fn a_short_write_is_answered_storage_and_changes_nothing() {
    // Part of the record reaches the journal; it is cut off again.
    for bytes in [1, 10, 30] {
        refused_write_changes_nothing(Op::Append, FaultKind::Short(bytes));
    }
}

/// Group 1 with values at entries 5 and 7, all acknowledged.
fn tools_in_group_1(rig: &mut Rig) {
    assert_eq!(rig.set(1, 5, RADIUS, 1.5), Answer::Ok);
    assert_eq!(rig.set(1, 5, LENGTH, 20.0), Answer::Ok);
    assert_eq!(rig.set(1, 7, RADIUS, 4.0), Answer::Ok);
}

fn group_1_kept(rig: &mut Rig) {
    assert_eq!(rig.get(1, 5, RADIUS), 1.5);
    assert_eq!(rig.get(1, 5, LENGTH), 20.0);
    assert_eq!(rig.get(1, 7, RADIUS), 4.0);
}

#[test]
fn a_reset_or_clean_the_disk_refuses_keeps_the_tools() {
    // Appends 1..=3: the tools; 4: the RESET; 5: the Clean.
    let mut rig = serve(|s| {
        s.fail_at(Op::Append, 4, FaultKind::Fail)
            .fail_at(Op::Sync, 4, FaultKind::Fail)
    });
    tools_in_group_1(&mut rig);
    let reset = TcObject::GroupReset.of(1);
    assert_eq!(
        rig.write(reset, Value::I32(1)),
        Answer::Access(AccessError::Storage)
    );
    group_1_kept(&mut rig);
    assert_eq!(
        rig.write(TcObject::Clean.address(), Value::I32(1)),
        Answer::Access(AccessError::Storage)
    );
    group_1_kept(&mut rig);
    let crashed = reopen(rig.disk.snapshot());
    assert_eq!(crashed.values().count(), 3);
    assert_eq!(stored(&crashed, 1, 7, ToolField::Radius), 4.0);

    // The disk works again: RESET clears the group, durably.
    assert_eq!(rig.write(reset, Value::I32(1)), Answer::Ok);
    assert_eq!(rig.get(1, 5, RADIUS), 0.0);
    assert_eq!(rig.get(1, 7, RADIUS), 0.0);
    assert_eq!(reopen(rig.disk.snapshot()).values().count(), 0);
    assert_eq!(reopen(rig.stop()).values().count(), 0);
}

/// Two connections write the same field at once, round after round:
/// whatever order the server applied them in, the journal has the same
/// order, so the value in memory is the one a restart loads. The disk's
/// flush takes a while, so the writes of both connections share batches
/// and their answers race.
#[test]
fn memory_and_journal_agree_on_concurrent_writes_of_one_field() {
    const ROUNDS: u32 = 150;
    let disk = Disk(Arc::default(), Duration::from_micros(200));
    let mut rig = serve_on(disk, |s| s);
    let addr = rig.server.as_ref().unwrap().addr.to_string();
    assert_eq!(
        rig.write(TcObject::WkzIndex.of(3), Value::I32(9)),
        Answer::Ok
    );
    let step = Arc::new(Barrier::new(3));
    let writers: Vec<_> = (0..2)
        .map(|c| {
            let (addr, step) = (addr.clone(), Arc::clone(&step));
            std::thread::spawn(move || {
                let mut client = BlockingClient::connect(&addr).expect("connect");
                for round in 0..ROUNDS {
                    let reqs: Vec<Request> = (0..4)
                        .map(|k| {
                            let v = f64::from(round * 100 + c * 10 + k) + 0.5;
                            Request::Write(RADIUS.of(3), Value::F64(v))
                        })
                        .collect();
                    step.wait();
                    let answers = client.pipeline(&reqs).expect("pipeline");
                    assert!(answers.iter().all(|a| *a == Answer::Ok), "{answers:?}");
                    step.wait();
                }
            })
        })
        .collect();
    for round in 0..ROUNDS {
        step.wait();
        step.wait();
        let memory = rig.get(3, 9, RADIUS);
        let on_disk = stored(&reopen(rig.disk.snapshot()), 3, 9, ToolField::Radius);
        assert_eq!(memory, on_disk, "round {round}");
    }
    for w in writers {
        w.join().expect("writer");
    }
    let memory = rig.get(3, 9, RADIUS);
    let stopped = reopen(rig.stop());
    assert_eq!(stored(&stopped, 3, 9, ToolField::Radius), memory);
    assert!(stopped.storage().journal().is_empty(), "compacted at stop");
}

#[test]
fn writes_work_again_once_a_journal_that_could_not_be_repaired_is_compacted() {
    // Append 2 leaves half a record and cutting it off fails too: the
    // journal ends in a torn record the store cannot remove.
    let mut rig = serve(|s| {
        s.fail_at(Op::Append, 2, FaultKind::Short(12))
            .fail_at(Op::Truncate, 1, FaultKind::Fail)
    });
    assert_eq!(rig.set(2, 1, RADIUS, 1.5), Answer::Ok);
    assert_eq!(
        rig.set(2, 1, RADIUS, 2.5),
        Answer::Access(AccessError::Storage)
    );
    assert_eq!(rig.get(2, 1, RADIUS), 1.5);
    let crashed = rig.disk.snapshot();
    let (store, report) = ToolStore::open(crashed, Strictness::Strict).expect("reopen");
    assert!(report.torn_tail.is_some(), "the half record is a torn tail");
    assert_eq!(stored(&store, 2, 1, ToolField::Radius), 1.5);

    // The disk works again: so does the next write.
    assert_eq!(rig.set(2, 1, RADIUS, 3.5), Answer::Ok);
    assert_eq!(rig.get(2, 1, RADIUS), 3.5);
    let crashed = reopen(rig.disk.snapshot());
    assert_eq!(stored(&crashed, 2, 1, ToolField::Radius), 3.5);
    assert_eq!(stored(&reopen(rig.stop()), 2, 1, ToolField::Radius), 3.5);
}

/// A refused write with side effects changes nothing at all: the RESET
/// leaves the running correction and its side; OTC OFF leaves OTC on and
/// its wear, which a later OFF books.
#[test]
fn a_refused_reset_or_otc_off_changes_nothing_at_all() {
    // Appends: 1 RADIUS, 2 typ, 3 wear constant; 4 the RESET; 5 OTC OFF.
    let mut rig = serve(|s| {
        s.fail_at(Op::Append, 4, FaultKind::Fail)
            .fail_at(Op::Append, 5, FaultKind::Fail)
    });
    assert_eq!(rig.set(1, 1, RADIUS, 3.0), Answer::Ok);
    for (field, v) in [
        (OtcObject::ToolType, Value::I32(2)),
        (OtcObject::ToolWearConst, Value::F64(100_000.0)),
    ] {
        assert_eq!(rig.write(field.of(1), v), Answer::Ok);
    }
    // LENGTH, CONT: 0.01 of wear per unit of path, 10 units run.
    for (addr, v) in [
        (OtcObject::Mode.of(1), Value::I32(1)),
        (OtcObject::OtcOn.of(1), Value::I32(1)),
        (TcObject::Left.of(1), Value::I32(0)),
        (TcObject::Status.of(1), Value::I32(1)),
    ] {
        assert_eq!(rig.write(addr, v), Answer::Ok);
    }
    let status = |rig: &mut Rig| match rig.client.read(TcObject::Status.of(1), ValueType::I32) {
        Ok(Value::I32(v)) => v,
        other => panic!("{other:?}"),
    };
    assert_eq!(status(&mut rig), 1);
    let refused = Answer::Access(AccessError::Storage);
    assert_eq!(
        rig.write(TcObject::GroupReset.of(1), Value::I32(1)),
        refused
    );
    assert_eq!(
        status(&mut rig),
        1,
        "the refused RESET ended the correction"
    );
    assert_eq!(rig.write(TcObject::Status.of(1), Value::I32(0)), Answer::Ok);
    let wire = |r: &str| tc_request::text::parse_request(r).unwrap().to_wire();
    for r in ["LIN X10 F600", "EXEC"] {
        let ans = rig.client.call(&wire(r)).expect("motion");
        assert!(matches!(ans, Answer::Ext(_) | Answer::Ok), "{r}: {ans:?}");
    }
    assert_eq!(rig.write(OtcObject::OtcOn.of(1), Value::I32(0)), refused);
    let on = rig
        .client
        .read(OtcObject::OtcOn.of(1), ValueType::I32)
        .expect("read");
    assert_eq!(on, Value::I32(1), "the refused OFF switched OTC off");
    // The disk works again: the OFF books the whole wear.
    assert_eq!(rig.write(OtcObject::OtcOn.of(1), Value::I32(0)), Answer::Ok);
    match rig
        .client
        .read(OtcObject::WearAxis.sub_of(1, 2), ValueType::F64)
        .expect("read")
    {
        Value::F64(w) => assert!((w - 0.1).abs() < 1e-9, "WearAxis2 {w}"),
        other => panic!("{other:?}"),
    }
    // Booked on entry 1's length (−0.1), durably.
    let stored = reopen(rig.stop());
    let length = stored.get(1, tool_store::ToolKey::new(1, ToolField::Length).unwrap());
    match length {
        tool_store::ToolValue::F64(l) => assert!((l + 0.1).abs() < 1e-9, "length {l}"),
        other => panic!("{other:?}"),
    }
}

/// The journal deleted, then replaced, under a running
/// server. Each write after it is acknowledged only once the journal is
/// made anew; a crash then loses nothing, the writes before the deletion
/// included.
#[test]
fn a_journal_deleted_under_the_server_loses_no_acknowledged_write() {
    let mut rig = serve(|s| s);
    assert_eq!(rig.set(1, 5, RADIUS, 1.5), Answer::Ok);
    assert_eq!(rig.set(2, 1, LENGTH, 4.5), Answer::Ok);
    rig.disk.0.lock().unwrap().delete_journal();
    assert_eq!(rig.set(1, 5, RADIUS, 2.5), Answer::Ok);
    let crashed = reopen(rig.disk.snapshot());
    assert_eq!(stored(&crashed, 1, 5, ToolField::Radius), 2.5);
    assert_eq!(stored(&crashed, 2, 1, ToolField::Length), 4.5);
    // Replaced by the journal as it was before any write: old values must
    // not come back.
    rig.disk.0.lock().unwrap().replace_journal(Vec::new());
    let stale = radius_record(1, 5, 1.5);
    rig.disk
        .0
        .lock()
        .unwrap()
        .journal_mut()
        .extend(stale.bytes());
    assert_eq!(rig.set(3, 2, RADIUS, 6.0), Answer::Ok);
    let crashed = reopen(rig.disk.snapshot());
    assert_eq!(stored(&crashed, 1, 5, ToolField::Radius), 2.5);
    assert_eq!(stored(&crashed, 3, 2, ToolField::Radius), 6.0);
    assert_eq!(crashed.values().count(), 3);
    assert_eq!(reopen(rig.stop()).values().count(), 3);
}

/// The journal line setting RADIUS of (`g`, `index`) to `mm`.
fn radius_record(g: u8, index: u16, mm: f64) -> String {
    Record::Set {
        group: g,
        key: ToolKey::new(index, ToolField::Radius).unwrap(),
        value: ToolValue::F64(mm),
    }
    .encode()
}

/// A small volume: 256 KB.
const VOLUME: u64 = 256 << 10;

/// The `n`-th write of the 512 live values (16 groups of 32 entries):
/// its group, entry and a value with many digits.
fn live(n: u32) -> (u16, i32, f64) {
    (
        (n % 16) as u16 + 1,
        (n / 16 % 32) as i32,
        (f64::from(n) + 0.5) / 7.0,
    )
}

/// Writes `writes` of the live values over `client`, pipelined; the
/// answers to the RADIUS writes.
fn write_live(client: &mut BlockingClient, writes: std::ops::Range<u32>) -> Vec<Answer> {
    let mut answers = Vec::new();
    let all: Vec<u32> = writes.collect();
    for chunk in all.chunks(100) {
        let reqs: Vec<Request> = chunk
            .iter()
            .flat_map(|&n| {
                let (g, index, v) = live(n);
                [
                    Request::Write(TcObject::WkzIndex.of(g), Value::I32(index)),
                    Request::Write(RADIUS.of(g), Value::F64(v)),
                ]
            })
            .collect();
        let got = client.pipeline(&reqs).expect("pipeline");
        answers.extend(got.into_iter().skip(1).step_by(2));
    }
    answers
}

/// Every live value written last in `writes` is what `store` holds.
fn live_values_held(store: &ToolStore<MemStorage>, writes: std::ops::Range<u32>) {
    let last = writes.end;
    for n in writes.rev().take(512) {
        let (g, index, v) = live(n);
        let got = stored(store, g as u8, index as u16, ToolField::Radius);
        assert_eq!(got, v, "g{g} wz[{index}] (writes up to {last})");
    }
    assert_eq!(store.values().count(), 512);
}

/// On a simulated 256 KB volume: 512 live values and
/// 6,000 writes are all acknowledged (before, the journal filled the
/// volume after about 5,500 and every later write was refused, also after
/// a restart); after a crash every value is there and writes go on.
#[test]
fn a_small_volume_is_not_wedged_by_the_journal() {
    let mut rig = serve(|s| s.with_capacity(VOLUME));
    let answers = write_live(&mut rig.client, 0..6000);
    let refused = answers.iter().filter(|a| **a != Answer::Ok).count();
    assert_eq!(
        refused,
        0,
        "{:?}",
        answers.iter().find(|a| **a != Answer::Ok)
    );
    let crashed = rig.disk.snapshot();
    live_values_held(&reopen(crashed.clone()), 0..6000);
    drop(rig);
    let mut again = serve_on(Disk(Arc::new(Mutex::new(crashed)), Duration::ZERO), |s| {
        s.with_capacity(VOLUME)
    });
    let answers = write_live(&mut again.client, 6000..7000);
    assert!(
        answers.iter().all(|a| *a == Answer::Ok),
        "after the restart"
    );
    live_values_held(&reopen(again.stop()), 0..7000);
}

/// A tmpfs of `size` mounted at a fresh folder of the test's, unmounted
/// when dropped; `None` (with a note) where mounting is not allowed.
struct SmallVolume(PathBuf);

impl SmallVolume {
    fn mount(name: &str, size: &str) -> Option<Self> {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
        let _ = Command::new("umount")
            .arg(&dir)
            .stderr(std::process::Stdio::null())
            .status();
        std::fs::create_dir_all(&dir).unwrap();
        let mounted = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(&dir)
            .output();
        match mounted {
            Ok(out) if out.status.success() => Some(Self(dir)),
            other => {
                eprintln!("skipped: cannot mount a {size} tmpfs here (needs root): {other:?}");
                None
            }
        }
    }

    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for SmallVolume {
    fn drop(&mut self) {
        let _ = Command::new("umount")
            .arg(&self.0)
            .stderr(std::process::Stdio::null())
            .status();
        let _ = std::fs::remove_dir(&self.0);
    }
}

/// A file that takes all the room left on the volume at `dir`.
fn fill(dir: &Path) -> PathBuf {
    use std::io::Write;
    let path = dir.join("ballast");
    let mut f = std::fs::File::create(&path).unwrap();
    let block = vec![0x55u8; 4096];
    while f.write_all(&block).is_ok() {}
    while f.write_all(&block[..1]).is_ok() {}
    path
}

/// A server of a fresh emulator on the tool folder `tools` of a real disk.
fn serve_dir(tools: &Path) -> (TestServer, BlockingClient) {
    let (store, _) = ToolStore::open_dir(tools, Strictness::Strict).expect("open");
    let mut service = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    service.set_tools(Box::new(Durable::new(
        Writer::start(store).expect("writer"),
    )));
    let server = TestServer::with(loopback(), service);
    let client = BlockingClient::connect(&server.addr.to_string()).expect("connect");
    (server, client)
}

/// The tool folder `tools` as a store in memory (strictly loaded).
fn load_dir(tools: &Path) -> ToolStore<MemStorage> {
    let mut mem = MemStorage::new();
    for entry in std::fs::read_dir(tools).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bytes = std::fs::read(&path).unwrap();
        match name.as_str() {
            tool_store::JOURNAL_FILE => *mem.journal_mut() = bytes,
            ".lock" => {}
            _ => mem.put_file(&name, bytes),
        }
    }
    reopen(mem)
}

/// On a real 256 KB file system: 512 live values and
/// 6,000 writes, all acknowledged. Then the volume is filled by something
/// else: writes are refused (`Storage`) and leave no temporary file; once
/// the room is back they work, and after a restart every acknowledged
/// value is there.
#[test]
fn a_real_small_volume_is_not_wedged() {
    let Some(volume) = SmallVolume::mount("tool-faults-volume", "256k") else {
        return;
    };
    let tools = volume.path().join("tools");
    let (server, mut client) = serve_dir(&tools);
    let answers = write_live(&mut client, 0..6000);
    let refused = answers.iter().filter(|a| **a != Answer::Ok).count();
    assert_eq!(
        refused,
        0,
        "{:?}",
        answers.iter().find(|a| **a != Answer::Ok)
    );
    live_values_held(&load_dir(&tools), 0..6000);

    let ballast = fill(volume.path());
    let answers = write_live(&mut client, 6000..6600);
    assert!(
        answers.contains(&Answer::Access(AccessError::Storage)),
        "a full disk took every write"
    );
    let names: Vec<String> = std::fs::read_dir(&tools)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!names.iter().any(|n| n.ends_with(".tmp")), "{names:?}");
    std::fs::remove_file(ballast).unwrap();
    let answers = write_live(&mut client, 6600..7600);
    assert!(answers.iter().all(|a| *a == Answer::Ok), "room again");
    drop(client);
    drop(server);
    live_values_held(&load_dir(&tools), 6600..7600);
    let (server, mut client) = serve_dir(&tools);
    let answers = write_live(&mut client, 7600..8000);
    assert!(
        answers.iter().all(|a| *a == Answer::Ok),
        "after the restart"
    );
    drop(server);
}

/// A write with side effects that changes nothing of another group (OTC
/// OFF of group 2, nothing to book) leaves a tool write of group 1 that is
/// still on its way to the disk as it is: the write answered `Ok` is
/// applied, in memory and on the disk (decision 489).
#[test]
fn otc_off_of_another_group_keeps_a_tool_write_on_its_way() {
    let mut rig = serve_on(Disk(Arc::default(), Duration::from_millis(300)), |s| s);
    let grind = [
        (TcObject::WkzIndex.of(2), Value::I32(1)),
        (OtcObject::ToolType.of(2), Value::I32(2)),
        (OtcObject::ToolWearConst.of(2), Value::F64(100_000.0)),
        (OtcObject::Mode.of(2), Value::I32(1)),
        (OtcObject::OtcOn.of(2), Value::I32(1)),
        (TcObject::WkzIndex.of(1), Value::I32(1)),
    ];
    for (addr, v) in grind {
        assert_eq!(rig.write(addr, v), Answer::Ok, "{addr}");
    }
    let addr = rig.server.as_ref().expect("server").addr.to_string();
    let on_its_way = std::thread::spawn(move || {
        let mut c = BlockingClient::connect(&addr).expect("connect");
        c.call(&Request::Write(RADIUS.of(1), Value::F64(5.0)))
            .expect("write")
    });
    // The RADIUS write waits for the slow disk while OTC is switched off.
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(rig.write(OtcObject::OtcOn.of(2), Value::I32(0)), Answer::Ok);
    assert_eq!(on_its_way.join().expect("writer"), Answer::Ok);
    assert_eq!(rig.get(1, 1, RADIUS), 5.0, "the acknowledged write is lost");
    assert_eq!(stored(&reopen(rig.stop()), 1, 1, ToolField::Radius), 5.0);
}
