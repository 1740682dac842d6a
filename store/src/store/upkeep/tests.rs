//! A full disk must not wedge the store.

use super::*;
use crate::field::ToolField;
use crate::storage::{FaultKind, FaultyStorage, MemStorage, Op};
use crate::table::ToolKey;
use crate::{CompactionBound, Strictness, ToolValue};
use std::collections::BTreeMap;
use std::time::Duration;

type Disk = FaultyStorage<MemStorage>;
type Model = BTreeMap<(u8, u16), u64>;

/// The 256 KB volume of the issue.
const VOLUME: u64 = 256 << 10;

/// RADIUS of entry `index` of `group`: a value with many digits, as a
/// measured radius has.
fn radius(group: u8, index: u16, n: u64) -> Record {
    Record::Set {
        group,
        key: ToolKey::new(index, ToolField::Radius).unwrap(),
        value: ToolValue::F64((n as f64 + 0.5) / 7.0),
    }
}

/// The `n`-th of 512 live values: 16 groups of 32 entries.
fn live_key(n: u64) -> (u8, u16) {
    ((n % 16) as u8 + 1, (n / 16 % 32) as u16)
}

fn open(disk: Disk) -> ToolStore<Disk> {
    ToolStore::open(disk, Strictness::Strict).unwrap().0
}

/// `writes` writes over the 512 live values as the writer thread makes
/// them, one batch each, 1 ms apart from `t0`; the model of what was
/// acknowledged; the errors.
fn write_live(
    store: &mut ToolStore<Disk>,
    model: &mut Model,
    writes: std::ops::Range<u64>,
    t0: Instant,
) -> Vec<StoreError> {
    let mut errors = Vec::new();
    for n in writes {
        let now = t0 + Duration::from_millis(n);
        let (group, index) = live_key(n);
        match store.append_at(&[radius(group, index, n)], now) {
            Ok(()) => {
                model.insert((group, index), n);
            }
            Err(e) => errors.push(e),
        }
        store.maintain_at(now);
    }
    errors
}

/// The values a store holds, as the model has them.
fn held(store: &ToolStore<Disk>, model: &Model) {
    for (&(group, index), &n) in model {
        let Record::Set { key, value, .. } = radius(group, index, n) else {
            unreachable!()
        };
        assert_eq!(store.get(group, key), value, "g{group} wz[{index}]");
    }
    assert_eq!(store.values().count(), model.len());
}

/// 512 live values, 6,000 writes on a 256 KB volume: every write is
/// acknowledged (the journal is compacted long before it fills the
/// volume), and after a restart every value is there and writes go on.
#[test]
fn a_small_volume_is_not_wedged_by_the_journal() {
    let mut store = open(FaultyStorage::new(MemStorage::new()).with_capacity(VOLUME));
    let (mut model, t0) = (Model::new(), Instant::now());
    let errors = write_live(&mut store, &mut model, 0..6000, t0);
    assert!(errors.is_empty(), "{} refused: {}", errors.len(), errors[0]);
    assert_eq!(model.len(), 512);
    // Compacted before less than 64 KiB beyond what the tool files need
    // was left (checked after each batch: one record more at most).
    let used = store.storage().used();
    assert!(used < VOLUME - (64 << 10) + 64, "{used} bytes used");
    assert!(store.storage().calls(Op::WriteFile) > 0, "compacted");
    // A crash: restart on what the disk holds.
    let disk = store.into_storage().into_inner();
    let mut store = open(FaultyStorage::new(disk).with_capacity(VOLUME));
    held(&store, &model);
    let errors = write_live(&mut store, &mut model, 6000..7000, t0);
    assert!(errors.is_empty(), "after restart: {}", errors[0]);
    held(&store, &model);
}

/// The disk filled by something else: writes are refused (memory stays),
/// compaction is tried a few times, not on every write; once there is
/// room again writes work, and a restart has every acknowledged value.
#[test]
fn a_disk_filled_by_others_refuses_then_heals() {
    let disk = FaultyStorage::new(MemStorage::new()).with_capacity(VOLUME);
    let mut store = open(disk);
    let (mut model, t0) = (Model::new(), Instant::now());
    assert!(write_live(&mut store, &mut model, 0..600, t0).is_empty());
    assert_eq!(store.storage().calls(Op::WriteFile), 0, "not compacted yet");
    let used = store.storage().used();
    store.storage_mut().set_capacity(used);
    // 6,000 writes over 6 s of a full disk.
    let errors = write_live(&mut store, &mut model, 600..6600, t0);
    assert_eq!(errors.len(), 6000);
    assert!(errors.iter().all(StoreError::is_disk_full), "{}", errors[0]);
    // Compaction would free the journal: tried at 0.6 s, then after
    // pauses of 1 and 2 s (the next one, 4 s later, comes after 6.6 s).
    assert_eq!(store.storage().calls(Op::WriteFile), 3);
    held(&store, &model);
    store.storage_mut().set_capacity(VOLUME);
    let errors = write_live(&mut store, &mut model, 6600..7600, t0);
    assert!(errors.is_empty(), "room again: {}", errors[0]);
    let disk = store.into_storage().into_inner();
    let store = open(FaultyStorage::new(disk).with_capacity(VOLUME));
    held(&store, &model);
}

/// A write refused for want of room compacts at once, which frees the
/// journal's room, and is written again: acknowledged without waiting for
/// the disk to have room from elsewhere.
#[test]
fn a_full_disk_is_met_by_compacting_first() {
    let disk = FaultyStorage::new(MemStorage::new()).fail_at(Op::Append, 3, FaultKind::Full);
    let mut store = open(disk);
    let (mut model, t0) = (Model::new(), Instant::now());
    let errors = write_live(&mut store, &mut model, 0..3, t0);
    assert!(errors.is_empty(), "{}", errors[0]);
    assert_eq!(store.storage().calls(Op::WriteFile), 2, "groups 1 and 2");
    assert_eq!(store.journal_size().1, 1, "only the third write is left");
    let disk = store.into_storage().into_inner();
    held(&open(FaultyStorage::new(disk)), &model);
}

/// Compaction that keeps failing is tried again after 1, 2, 4, 8, 16,
/// 16 ... s, not after every write.
#[test]
fn failed_compactions_pause_instead_of_retrying_on_every_write() {
    let bound = CompactionBound {
        records: 1,
        ..CompactionBound::default()
    };
    let disk = FaultyStorage::new(MemStorage::new()).fail_from(Op::WriteFile, 1);
    let mut store = open(disk).with_compaction_bound(bound);
    let (mut model, t0) = (Model::new(), Instant::now());
    // 64 s of writes, one per millisecond.
    let errors = write_live(&mut store, &mut model, 0..64_000, t0);
    assert!(errors.is_empty(), "appends still work: {}", errors[0]);
    // At 0, 1, 3, 7, 15, 31, 47 and 63 s.
    assert_eq!(store.storage().calls(Op::WriteFile), 8);
    let next = store.compaction_paused_until().unwrap();
    assert_eq!(next - t0, Duration::from_secs(79));
}

/// A poisoned journal (a half record that could not be cut off) is
/// compacted before the next write, but not on every write while the
/// disk keeps failing.
#[test]
fn a_poisoned_journal_is_repaired_with_pauses() {
    let disk = FaultyStorage::new(MemStorage::new())
        .fail_at(Op::Append, 2, FaultKind::Short(5))
        .fail_at(Op::Truncate, 1, FaultKind::Fail)
        .fail_at(Op::WriteFile, 1, FaultKind::Fail);
    let mut store = open(disk);
    let (mut model, t0) = (Model::new(), Instant::now());
    let errors = write_live(&mut store, &mut model, 0..500, t0);
    // Write 1 fails short, write 2 finds the repair failing, writes 3 to
    // 499 come within the pause of 1 s and are refused without a try.
    assert_eq!(errors.len(), 499);
    assert_eq!(store.storage().calls(Op::WriteFile), 1);
    let errors = write_live(&mut store, &mut model, 1100..1110, t0);
    assert!(errors.is_empty(), "repaired after the pause: {}", errors[0]);
    let disk = store.into_storage().into_inner();
    held(&open(FaultyStorage::new(disk)), &model);
}
