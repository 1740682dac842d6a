use super::*;
use crate::field::{FileField, ToolField};
use crate::storage::{FaultKind, FaultyStorage, MemStorage, Op};
use proptest::prelude::*;

type Model = BTreeMap<(u8, ToolKey), ToolValue>;

fn key(i: u16, f: ToolField) -> ToolKey {
    ToolKey::new(i, f).unwrap()
}

fn set(group: u8, index: u16, field: ToolField, value: ToolValue) -> Record {
    Record::Set {
        group,
        key: key(index, field),
        value,
    }
}

fn radius(group: u8, index: u16, mm: f64) -> Record {
    set(group, index, ToolField::Radius, ToolValue::F64(mm))
}

fn open<S: Storage>(s: S) -> (ToolStore<S>, OpenReport) {
    ToolStore::open(s, Strictness::Strict).unwrap()
}

fn snapshot<S: Storage>(store: &ToolStore<S>) -> Model {
    store.values().map(|(g, k, v)| ((g, k), v)).collect()
}

/// Applies records to a model the way the store should.
fn model_apply(model: &mut Model, records: &[Record]) {
    for r in records {
        match *r {
            Record::Set { group, key, value } if value == key.field.default_value() => {
                model.remove(&(group, key));
            }
            Record::Set { group, key, value } => {
                model.insert((group, key), value);
            }
            Record::ResetGroup { group } => model.retain(|(g, _), _| *g != group),
            Record::Clean => model.clear(),
        }
    }
}

#[test]
fn empty_storage_opens_with_defaults() {
    let (store, report) = open(MemStorage::new());
    assert_eq!(store.values().count(), 0);
    assert_eq!(store.get(1, key(0, ToolField::ToolType)), ToolValue::I32(0));
    assert!(store.group(1).is_none());
    assert_eq!(report, OpenReport::default());
}

#[test]
fn hand_written_group_file_loads() {
    let mut mem = MemStorage::new();
    let text = "# grinding disc\nwz[1].typ 2\nwz[1].radius 300000\nwz[1].grinding_wear_const 100000 # 10 mm/m\n";
    mem.put_file("group03.wz", text);
    let (store, report) = open(mem);
    assert_eq!(report.files_loaded, [3]);
    assert_eq!(store.get(3, key(1, ToolField::ToolType)), ToolValue::I32(2));
    assert_eq!(
        store.get(3, key(1, ToolField::Radius)),
        ToolValue::F64(30.0)
    );
    let wear = store.get(3, key(1, ToolField::WearConst));
    assert_eq!(wear, ToolValue::F64(100000.0));
    assert_eq!(store.group(3).map(GroupTable::len), Some(3));
}

#[test]
fn bad_group_file_refuses_strict_open_with_file_and_line() {
    let mut mem = MemStorage::new();
    mem.put_file("group02.wz", "wz[1].typ 2\nwz[1].typ 3\n");
    let e = ToolStore::open(mem.clone(), Strictness::Strict).unwrap_err();
    assert_eq!(
        e.to_string(),
        "group02.wz:2: duplicate key wz[1].typ (first set on line 1)"
    );
    let (store, report) = ToolStore::open(mem, Strictness::Lenient).unwrap();
    assert_eq!(report.file_errors.len(), 1);
    assert_eq!(store.get(2, key(1, ToolField::ToolType)), ToolValue::I32(2));
}

#[test]
fn appended_records_survive_reopen() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 5, 30.0), radius(2, 0, -0.0)])
        .unwrap();
    store
        .append(&[set(1, 5, ToolField::ToolType, ToolValue::I32(2))])
        .unwrap();
    let before = snapshot(&store);
    let (again, report) = open(store.into_storage());
    assert_eq!(report.replayed, 3);
    assert_eq!(snapshot(&again), before);
    assert_eq!(
        again.get(2, key(0, ToolField::Radius)),
        ToolValue::F64(-0.0)
    );
}

#[test]
fn invalid_record_writes_nothing() {
    let (mut store, _) = open(MemStorage::new());
    let bad = [radius(1, 1, 1.0), Record::ResetGroup { group: 40 }];
    let e = store.append(&bad).unwrap_err();
    assert!(matches!(e, StoreError::Invalid { index: 1, .. }), "{e}");
    assert!(store.storage().journal().is_empty());
    assert_eq!(store.values().count(), 0);
}

#[test]
fn reset_and_clean_survive_compaction_and_reopen() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 1, 1.0), radius(2, 2, 2.0), radius(3, 3, 3.0)])
        .unwrap();
    store.compact().unwrap();
    store.append(&[Record::ResetGroup { group: 2 }]).unwrap();
    let (mut store, _) = open(store.into_storage());
    assert_eq!(store.values().count(), 2);
    store.compact().unwrap();
    assert!(store.storage().journal().is_empty());
    let text = store.storage().file("group02.wz").map(<[u8]>::to_vec);
    assert!(
        text.is_some_and(|t| t.split(|&b| b == b'\n').all(|l| !l.starts_with(b"wz"))),
        "reset group keeps a header-only file"
    );
    store.append(&[Record::Clean]).unwrap();
    store.compact().unwrap();
    let (store, report) = open(store.into_storage());
    assert_eq!(store.values().count(), 0);
    assert_eq!(report.files_loaded, [1, 2, 3]);
}

/// A full disk must not stop a start after a power cut: the copy of a
/// journal with a torn last batch cannot be written, so the start goes on
/// without it (the torn batch was never acknowledged), says so in the
/// report and cuts the batch off (decision 527).
#[test]
fn a_torn_batch_is_cut_off_even_when_its_copy_cannot_be_kept() {
    let (mut store, _) = open(MemStorage::new());
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    let good = snapshot(&store);
    let good_len = store.storage().journal().len();
    store
        .append(&[radius(1, 2, 2.0), radius(1, 3, 3.0)])
        .unwrap();
    let mut mem = store.into_storage();
    let full_len = mem.journal().len();
    // The second batch's records are there, its closing line is not.
    mem.journal_mut().truncate(full_len - 4);
    let full = FaultyStorage::new(mem).fail_at(Op::WriteFile, 1, FaultKind::Full);
    let (store, report) = ToolStore::open(full, Strictness::Strict).expect("the start goes on");
    assert_eq!(snapshot(&store), good);
    assert_eq!(report.journal_copy, None);
    assert!(
        report
            .journal_copy_failed
            .as_deref()
            .is_some_and(|e| e.contains("journal.wzj.torn-")),
        "{report:?}"
    );
    assert_eq!(store.into_storage().into_inner().journal().len(), good_len);
}

#[test]
fn torn_tail_is_dropped_reported_and_cut_off() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 1, 1.0), radius(1, 2, 2.0)])
        .unwrap();
    let good = snapshot(&store);
    let good_len = store.storage().journal().len();
    store.append(&[radius(1, 3, 3.0)]).unwrap();
    let full = store.into_storage();
    for cut in good_len + 1..full.journal().len() {
        let mut mem = full.clone();
        mem.journal_mut().truncate(cut);
        let (mut store, report) = open(mem);
        assert_eq!(snapshot(&store), good, "cut at {cut}");
        let tail = report.torn_tail.unwrap();
        // The journal's first line, two records and the line closing
        // their batch before it.
        assert_eq!((tail.line, tail.offset), (5, good_len as u64));
        assert_eq!(
            store.storage().journal().len(),
            good_len,
            "torn bytes cut off"
        );
        // Appending after the cut tail gives a journal that replays cleanly.
        store.append(&[radius(1, 4, 4.0)]).unwrap();
        let (again, report) = open(store.into_storage());
        assert_eq!((report.torn_tail, again.values().count()), (None, 3));
    }
}

#[test]
fn corrupt_record_before_the_end_refuses_open_with_line() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 1, 1.0), radius(1, 2, 2.0), radius(1, 3, 3.0)])
        .unwrap();
    let mut mem = store.into_storage();
    let at = mem.journal().iter().position(|&b| b == b'\n').unwrap() + 5;
    mem.journal_mut()[at] = b'9'; // line 2: "g1 wz[9].radius ..."
    let e = ToolStore::open(mem.clone(), Strictness::Strict).unwrap_err();
    assert_eq!(e.to_string(), "journal.wzj:2: checksum mismatch");
    let (store, report) = ToolStore::open(mem, Strictness::Lenient).unwrap();
    assert_eq!(report.journal_errors.len(), 1);
    assert_eq!(store.values().count(), 2);
}

#[test]
fn needs_compaction_past_the_bound() {
    let bound = CompactionBound {
        bytes: 1 << 20,
        records: 3,
        ..CompactionBound::default()
    };
    let (store, _) = open(MemStorage::new());
    let mut store = store.with_compaction_bound(bound);
    assert!(!store.needs_compaction(), "an empty journal is never due");
    store
        .append(&[radius(1, 1, 1.0), radius(1, 2, 2.0)])
        .unwrap();
    assert!(!store.needs_compaction());
    store.append(&[radius(1, 3, 3.0)]).unwrap();
    assert!(store.needs_compaction());
    store.compact().unwrap();
    assert!(!store.needs_compaction());
    assert_eq!(store.journal_size(), (0, 0));
    let default = CompactionBound::default();
    assert_eq!((default.bytes, default.records), (4 << 20, 100_000));
}

/// A disk short of room calls for compaction once the
/// journal holds enough to be worth it: when less is free than the tool
/// files need (new files whole, the largest once more, in 4 KiB blocks,
/// at most 64 bytes a value and 320 of header) plus 64 KiB.
#[test]
fn a_disk_short_of_room_calls_for_compaction() {
    let (mut store, _) = open(MemStorage::new());
    let mut n = 0;
    while store.journal_size().0 < 16 << 10 {
        assert!(!store.short_of_room(0), "a small journal frees too little");
        store
            .append(&[radius(1, n % 32, f64::from(n) + 0.5)])
            .unwrap();
        n += 1;
    }
    // Group 1: 32 values, no file yet: one block new, one beside.
    assert_eq!(store.compaction_room(), 2 * 4096);
    assert!(store.short_of_room(2 * 4096 + (64 << 10) - 1));
    assert!(!store.short_of_room(2 * 4096 + (64 << 10)));
    assert!(!store.needs_compaction(), "not by the size bound");
    // A group of 1,024 values with a file: written beside the old one.
    let many: Vec<Record> = (0..1024)
        .map(|i| radius(2, i, (f64::from(i) + 0.5) / 7.0))
        .collect();
    store.append(&many).unwrap();
    store.compact().unwrap();
    assert_eq!(store.compaction_room(), 0, "nothing changed since");
    while store.journal_size().0 < 16 << 10 {
        store
            .append(&[radius(2, n % 1024, f64::from(n) + 0.5)])
            .unwrap();
        n += 1;
    }
    let blocks = (320 + 64 * 1024u64).div_ceil(4096);
    assert_eq!(store.compaction_room(), blocks * 4096);
    assert!(store.short_of_room(blocks * 4096 + (64 << 10) - 1));
    assert!(!store.short_of_room(blocks * 4096 + (64 << 10)));
}

/// Compaction rewrites only the groups changed since their file was
/// written; a Clean touches every group with a file.
#[test]
fn compaction_rewrites_the_changed_groups_only() {
    let (mut store, _) = open(FaultyStorage::new(MemStorage::new()));
    store
        .append(&[radius(1, 1, 1.0), radius(2, 2, 2.0), radius(3, 3, 3.0)])
        .unwrap();
    store.compact().unwrap();
    assert_eq!(store.storage().calls(Op::WriteFile), 3);
    store.append(&[radius(2, 2, 2.5)]).unwrap();
    store.compact().unwrap();
    assert_eq!(store.storage().calls(Op::WriteFile), 4, "group 2 only");
    store.compact().unwrap();
    assert_eq!(store.storage().calls(Op::WriteFile), 4, "nothing changed");
    store.append(&[Record::Clean]).unwrap();
    store.compact().unwrap();
    assert_eq!(
        store.storage().calls(Op::WriteFile),
        7,
        "every file emptied"
    );
    let (reopened, _) = open(store.into_storage().into_inner());
    assert_eq!(reopened.values().count(), 0);
}

/// Temporary files of a replacement cut short are
/// removed when the store opens, and reported.
#[test]
fn leftover_temporary_files_are_removed_at_open() {
    let mut mem = MemStorage::new();
    mem.put_file("group01.wz", "wz[1].radius 300000\n");
    mem.put_file("group01.wz.tmp", "");
    mem.put_file("group07.wz.tmp", "wz[1].ra");
    let (store, report) = open(mem);
    assert_eq!(
        report.removed_temporaries,
        ["group01.wz.tmp", "group07.wz.tmp"]
    );
    assert_eq!(store.storage().file("group01.wz.tmp"), None);
    assert_eq!(store.storage().file("group07.wz.tmp"), None);
    assert_eq!(store.values().count(), 1);
}

/// The store on a real directory, wrapped in fault injection.
fn faulty_dir(
    dir: &std::path::Path,
    faults: impl FnOnce(FaultyStorage<FsStorage>) -> FaultyStorage<FsStorage>,
) -> ToolStore<FaultyStorage<FsStorage>> {
    let storage = faults(FaultyStorage::new(FsStorage::new(dir)));
    ToolStore::open(storage, Strictness::Strict).unwrap().0
}

/// Three appends, the second one failing as `faults` says: the error is
/// returned, memory stays, and reopening the directory shows exactly the
/// first and third.
fn failed_append_leaves_no_trace(
    faults: impl FnOnce(FaultyStorage<FsStorage>) -> FaultyStorage<FsStorage>,
) {
    let dir = tempfile::tempdir().unwrap();
    let mut store = faulty_dir(dir.path(), faults);
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    let before = snapshot(&store);
    let err = store.append(&[radius(1, 1, 9.0), radius(1, 2, 9.0)]);
    assert!(matches!(err, Err(StoreError::Io { .. })), "{err:?}");
    assert_eq!(snapshot(&store), before, "memory not ahead of disk");
    store.append(&[radius(1, 3, 3.0)]).unwrap();
    let expected = snapshot(&store);
    let (reopened, report) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), expected);
    assert_eq!(report.torn_tail, None);
    assert_eq!(expected.len(), 2);
}

#[test]
fn failing_write_is_an_error_and_leaves_no_trace() {
    failed_append_leaves_no_trace(|s| s.fail_at(Op::Append, 2, FaultKind::Fail));
}

#[test]
fn failing_fsync_is_an_error_and_leaves_no_trace() {
    failed_append_leaves_no_trace(|s| s.fail_at(Op::Sync, 2, FaultKind::Fail));
}

#[test]
fn short_write_is_an_error_and_leaves_no_trace() {
    for n in [0, 1, 10, 30, 40] {
        failed_append_leaves_no_trace(|s| s.fail_at(Op::Append, 2, FaultKind::Short(n)));
    }
}

#[test]
fn short_write_that_cannot_be_undone_poisons_until_compaction() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = faulty_dir(dir.path(), |s| {
        s.fail_at(Op::Append, 2, FaultKind::Short(12))
            .fail_at(Op::Truncate, 1, FaultKind::Fail)
    });
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    let expected = snapshot(&store);
    assert!(store.append(&[radius(1, 2, 2.0)]).is_err());
    assert!(matches!(
        store.append(&[radius(1, 3, 3.0)]),
        Err(StoreError::Poisoned)
    ));
    // A crash now: the half record is a torn tail on the next start.
    let (reopened, report) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), expected);
    assert_eq!(report.torn_tail.map(|t| t.bytes), Some(12));
    // Or compaction repairs it in place.
    store.compact().unwrap();
    store.append(&[radius(1, 3, 3.0)]).unwrap();
    let (reopened, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), snapshot(&store));
}

#[test]
fn compaction_cut_short_loses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = faulty_dir(dir.path(), |s| {
        s.fail_at(Op::WriteFile, 2, FaultKind::Fail)
            .fail_at(Op::Truncate, 1, FaultKind::Fail)
    });
    store
        .append(&[radius(1, 1, 1.0), radius(2, 2, 2.0), radius(3, 3, 3.0)])
        .unwrap();
    store
        .append(&[Record::ResetGroup { group: 1 }, radius(1, 4, 4.0)])
        .unwrap();
    let expected = snapshot(&store);
    assert!(store.compact().is_err(), "second file write fails");
    let (reopened, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), expected);
    assert!(
        store.compact().is_err(),
        "files written, journal not emptied"
    );
    let (reopened, report) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(
        snapshot(&reopened),
        expected,
        "journal replayed over new files"
    );
    assert_eq!(report.files_loaded, [1, 2, 3]);
    store.compact().unwrap();
    let (reopened, report) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!((snapshot(&reopened), report.replayed), (expected, 0));
}

/// A bit flip in the last complete record refuses the
/// open with the file and the line, and nothing is cut off the journal.
#[test]
fn corrupt_last_complete_record_refuses_open_and_cuts_nothing() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 1, 1.0), radius(1, 2, 2.0), radius(1, 3, 3.0)])
        .unwrap();
    let mut mem = store.into_storage();
    // In the last record, before the line that closes the batch.
    let trailer = mem
        .journal()
        .windows(6)
        .rposition(|w| w == b"batch ")
        .unwrap();
    let at = trailer - 12;
    mem.journal_mut()[at] ^= 0x04;
    let damaged = mem.journal().to_vec();
    let e = ToolStore::open(mem.clone(), Strictness::Strict).unwrap_err();
    // Line 1 marks a journal of batches.
    assert_eq!(e.to_string(), "journal.wzj:4: checksum mismatch");
    let (store, report) = ToolStore::open(mem, Strictness::Lenient).unwrap();
    assert_eq!((report.torn_tail, report.journal_errors.len()), (None, 1));
    assert_eq!(store.values().count(), 2);
    assert_eq!(store.storage().journal(), damaged, "nothing cut");
}

/// A journal deleted under the store. The next batch
/// goes into the deleted file; the store notices, rewrites the tool files
/// from memory and writes the batch into a new journal before it counts:
/// what the disk holds then has every value, the earlier ones too.
#[test]
fn a_deleted_journal_is_made_anew_before_the_batch_counts() {
    let (mut store, _) = open(MemStorage::new());
    store
        .append(&[radius(1, 1, 1.0), radius(2, 1, 2.0)])
        .unwrap();
    store.storage_mut().delete_journal();
    store.append(&[radius(1, 2, 3.0)]).unwrap();
    let expected = snapshot(&store);
    let (reopened, report) = open(store.storage().clone());
    assert_eq!(snapshot(&reopened), expected, "a crash now loses nothing");
    assert_eq!((report.files_loaded, report.replayed), (vec![1, 2], 1));
    // Later batches go to the new journal as usual.
    store.append(&[radius(1, 3, 4.0)]).unwrap();
    let expected = snapshot(&store);
    assert_eq!(snapshot(&open(store.into_storage()).0), expected);
}

/// A journal replaced by an older copy must not bring old values back.
#[test]
fn a_replaced_journal_is_emptied_and_made_anew() {
    let (mut store, _) = open(MemStorage::new());
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    let old = store.storage().journal().to_vec();
    store
        .append(&[radius(1, 1, 5.0), radius(1, 2, 6.0)])
        .unwrap();
    store.storage_mut().replace_journal(old);
    store.append(&[radius(1, 3, 7.0)]).unwrap();
    let expected = snapshot(&store);
    assert_eq!(expected.len(), 3);
    assert_eq!(snapshot(&open(store.into_storage()).0), expected);
}

/// The same on a real directory: `rm journal.wzj` while the store runs.
#[test]
fn a_journal_deleted_on_disk_is_made_anew() {
    let dir = tempfile::tempdir().unwrap();
    let (mut store, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    store.append(&[radius(4, 1, 1.0)]).unwrap();
    std::fs::remove_file(dir.path().join(JOURNAL_FILE)).unwrap();
    store.append(&[radius(4, 2, 2.0)]).unwrap();
    let expected = snapshot(&store);
    let (reopened, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), expected);
    assert_eq!(expected.len(), 2);
}

/// Deleted after the start read it, before the first append: the values
/// it held (acknowledged before the start) must not be lost either.
#[test]
fn a_journal_deleted_before_the_first_append_is_made_anew() {
    let dir = tempfile::tempdir().unwrap();
    let (mut store, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    store
        .append(&[radius(4, 1, 1.0), radius(5, 1, 5.0)])
        .unwrap();
    drop(store);
    let (mut store, report) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(report.replayed, 2);
    std::fs::remove_file(dir.path().join(JOURNAL_FILE)).unwrap();
    store.append(&[radius(4, 2, 2.0)]).unwrap();
    let expected = snapshot(&store);
    let (reopened, _) = ToolStore::open_dir(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(snapshot(&reopened), expected);
    assert_eq!(expected.len(), 3);
}

/// If the tool files cannot be rewritten after the journal was lost, the
/// batch is refused: memory stays, the disk never shows it.
#[test]
fn a_lost_journal_that_cannot_be_made_anew_refuses_the_batch() {
    let storage = FaultyStorage::new(MemStorage::new()).fail_at(Op::WriteFile, 1, FaultKind::Fail);
    let (mut store, _) = open(storage);
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    let before = snapshot(&store);
    store.storage_mut().inner_mut().delete_journal();
    let e = store.append(&[radius(1, 1, 9.0)]).unwrap_err();
    assert!(matches!(e, StoreError::JournalLost(_)), "{e}");
    assert_eq!(snapshot(&store), before);
    // The disk works again: the next batch makes the journal anew.
    store.append(&[radius(1, 2, 2.0)]).unwrap();
    let expected = snapshot(&store);
    assert_eq!(
        snapshot(&open(store.into_storage().into_inner()).0),
        expected
    );
    assert_eq!(expected.len(), 2);
}

/// A look at the journal that fails counts as a lost journal: safe.
#[test]
fn a_failed_look_at_the_journal_rewrites_from_memory() {
    let storage = FaultyStorage::new(MemStorage::new()).fail_at(Op::Check, 2, FaultKind::Fail);
    let (mut store, _) = open(storage);
    store.append(&[radius(1, 1, 1.0)]).unwrap();
    store.append(&[radius(1, 2, 2.0)]).unwrap();
    assert_eq!(store.storage().calls(Op::WriteFile), 1, "group 1 rewritten");
    let expected = snapshot(&store);
    let disk = store.into_storage().into_inner();
    let mut made_anew = journal::format_line().into_bytes();
    made_anew.extend(encode_batch(&[radius(1, 2, 2.0)]));
    assert_eq!(disk.journal(), made_anew);
    assert_eq!(snapshot(&open(disk).0), expected);
}

fn any_record() -> impl Strategy<Value = Record> {
    let value = prop_oneof![
        (0..=3).prop_map(|v| (ToolField::ToolType, ToolValue::I32(v))),
        prop_oneof![Just(0.0), Just(-0.0), -1e9..1e9f64]
            .prop_map(|v| (ToolField::Radius, ToolValue::F64(v))),
        (-1e9..1e9f64).prop_map(|v| (ToolField::Length, ToolValue::F64(v))),
        (0.0..1e9f64).prop_map(|v| (ToolField::WearConst, ToolValue::F64(v))),
    ];
    prop_oneof![
        12 => (1..=4u8, 0..4u16, value).prop_map(|(g, i, (f, v))| set(g, i, f, v)),
        1 => (1..=4u8).prop_map(|group| Record::ResetGroup { group }),
        1 => Just(Record::Clean),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn appends_and_compactions_reopen_to_the_model(
        steps in proptest::collection::vec(
            (proptest::collection::vec(any_record(), 0..6), any::<bool>()), 0..12)
    ) {
        let (mut store, _) = open(MemStorage::new());
        let mut model = Model::new();
        for (batch, compact) in steps {
            store.append(&batch).unwrap();
            model_apply(&mut model, &batch);
            if compact {
                store.compact().unwrap();
            }
        }
        prop_assert_eq!(&snapshot(&store), &model);
        let (reopened, _) = open(store.into_storage());
        prop_assert_eq!(snapshot(&reopened), model);
    }
}
