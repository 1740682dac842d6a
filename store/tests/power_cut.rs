//! Power cuts in the middle of a group commit, simulated by the fault
//! storage: the journal keeps the later part of the cut batch's write
//! (NUL bytes where its beginning was never written, then
//! complete-looking records) or its earlier part, and nothing is cleaned
//! up. Across many cuts on the same disk: every start succeeds, and every
//! acknowledged value is there.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::collections::BTreeMap;

use tool_store::{
    FaultKind, FaultyStorage, MemStorage, Op, Record, RecordError, Strictness, ToolField, ToolKey,
    ToolStore, ToolValue,
};

/// Power cuts in one run.
const CUTS: u64 = 300;

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % n
    }
}

type Model = BTreeMap<(u8, ToolKey), ToolValue>;

fn apply(model: &mut Model, r: &Record) {
    match *r {
        Record::Set { group, key, value } => {
            model.insert((group, key), value);
        }
        Record::ResetGroup { group } => model.retain(|(g, _), _| *g != group),
        Record::Clean => model.clear(),
    }
}

/// A batch of 1 to 8 changes: mostly radii (never the default 0), now
/// and then a group reset.
fn batch(rng: &mut Rng) -> Vec<Record> {
    (0..=rng.below(8))
        .map(|_| {
            let group = 1 + rng.below(3) as u8;
            if rng.below(20) == 0 {
                return Record::ResetGroup { group };
            }
            let key = ToolKey::new(rng.below(30) as u16, ToolField::Radius).unwrap();
            let value = ToolValue::F64(0.5 + rng.below(2000) as f64 / 4.0);
            Record::Set { group, key, value }
        })
        .collect()
}

fn values(store: &ToolStore<FaultyStorage<MemStorage>>) -> Model {
    store.values().map(|(g, k, v)| ((g, k), v)).collect()
}

/// Appends batches until the power cut; returns the disk and the batch
/// the cut interrupted (never acknowledged: it may be on the disk whole,
/// or not at all).
fn run_until_cut(
    mut store: ToolStore<FaultyStorage<MemStorage>>,
    model: &mut Model,
    rng: &mut Rng,
) -> (MemStorage, Vec<Record>) {
    for _ in 0..100 {
        if rng.below(10) == 0 {
            let _ = store.compact();
        }
        let records = batch(rng);
        match store.append(&records) {
            Ok(()) => records.iter().for_each(|r| apply(model, r)),
            Err(_) => {
                assert!(store.storage().is_off(), "the cut came");
                return (store.into_storage().into_inner(), records);
            }
        }
    }
    panic!("no power cut in 100 batches");
}

/// After a start: every acknowledged value, and the interrupted batch
/// whole or not at all (then it joins the model).
fn check(found: &Model, model: &mut Model, cut_batch: &[Record], cut: u64) {
    if found == model {
        return;
    }
    let mut with_cut = model.clone();
    cut_batch.iter().for_each(|r| apply(&mut with_cut, r));
    assert_eq!(
        found, &with_cut,
        "after cut {cut}: neither without nor with the cut batch"
    );
    *model = with_cut;
}

#[test]
fn every_start_after_a_power_cut_succeeds_with_every_acknowledged_value() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut disk = MemStorage::new();
    let mut model = Model::new();
    let mut dropped_batches = 0;
    let mut cut_batch = Vec::new();
    for cut in 0..CUTS {
        let at_call = 1 + rng.below(6) as usize;
        let at = rng.below(400) as usize;
        let later = rng.below(4) != 0;
        let storage = FaultyStorage::new(disk).fail_at(
            Op::Append,
            at_call,
            FaultKind::PowerCut { at, later },
        );
        let (store, report) = ToolStore::open(storage, Strictness::Strict)
            .unwrap_or_else(|e| panic!("start after cut {cut}: {e}"));
        check(&values(&store), &mut model, &cut_batch, cut);
        if let Some(t) = &report.torn_tail {
            if t.reason == RecordError::TornBatch {
                dropped_batches += 1;
                let copy = report.journal_copy.as_deref().expect("a copy kept");
                assert!(store.storage().calls(Op::WriteFile) >= 1, "{copy}");
            }
        }
        (disk, cut_batch) = run_until_cut(store, &mut model, &mut rng);
    }
    let (store, _) = ToolStore::open(disk, Strictness::Strict).unwrap();
    let last: Model = store.values().map(|(g, k, v)| ((g, k), v)).collect();
    check(&last, &mut model, &cut_batch, CUTS);
    // Most cuts keep the later part of a batch: its drop is the point.
    assert!(
        dropped_batches > CUTS / 3,
        "{dropped_batches} batches dropped"
    );
}
