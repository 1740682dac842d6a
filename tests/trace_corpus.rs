//! Replays the whole conformance corpus in `traces/` and checks that it
//! pins every object of the TC object map and every access error.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::PathBuf;

use emulator::Emulator;
use tc_objects::{OTC_AXIS_DEVICE, TC_BUS};
use tc_request::Request;
use trace::{replay, Expect, Trace};
use uoi::{AccessError, Bus};

fn corpus() -> Vec<Trace> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("traces");
    trace::load_corpus(&dir).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn whole_corpus_replays_without_mismatch() {
    let traces = corpus();
    assert!(traces.len() >= 40, "only {} traces", traces.len());
    let mut failed = Vec::new();
    for t in &traces {
        for m in replay(t) {
            failed.push(m.to_string());
        }
    }
    assert!(failed.is_empty(), "mismatches:\n{}", failed.join("\n"));
}

#[test]
fn every_object_of_the_map_is_in_a_trace() {
    let traces = corpus();
    let addressed: Vec<uoi::ObjectAddress> = traces
        .iter()
        .flat_map(|t| &t.steps)
        .filter_map(|s| match s.request {
            Request::Read(a, _) | Request::Write(a, _) => Some(a),
            _ => None,
        })
        .collect();
    let mut missing = Vec::new();
    // The whole map: the TC rows and the rows the OTC extension appends.
    let emu = Emulator::default();
    let rows = emu.tc().objects();
    assert!(
        rows.iter().any(|r| r.device == OTC_AXIS_DEVICE),
        "extension rows missing"
    );
    for row in rows {
        for sub in row.sub.clone() {
            let hit = addressed.iter().any(|a| {
                a.bus == TC_BUS
                    && a.device == row.device
                    && row.index.contains(&a.index)
                    && a.sub == sub
            });
            if !hit {
                missing.push(format!(
                    "{} ({}/{}/{:?}/{})",
                    row.name, TC_BUS, row.device, row.index, sub
                ));
            }
        }
    }
    assert!(missing.is_empty(), "objects no trace touches: {missing:?}");
}

#[test]
fn every_access_error_is_expected_somewhere() {
    let traces = corpus();
    // `Storage` needs a disk that refuses a write: the fault-injection
    // tests of the tool store provoke it, a trace cannot.
    let missing: Vec<&str> = AccessError::ALL
        .iter()
        .filter(|e| **e != AccessError::Storage)
        .filter(|e| {
            !traces
                .iter()
                .flat_map(|t| &t.steps)
                .any(|s| s.expect == Expect::Err(**e))
        })
        .map(|e| e.name())
        .collect();
    assert!(
        missing.is_empty(),
        "access errors no trace expects: {missing:?}"
    );
}

#[test]
fn every_otc_error_bit_is_read_back_set_somewhere() {
    let traces = corpus();
    // Reads of OtcError (device 3, sub 7) with the value the trace expects.
    let answers: Vec<i32> = traces
        .iter()
        .flat_map(|t| &t.steps)
        .filter_map(|s| match (&s.request, &s.expect) {
            (Request::Read(a, _), Expect::Int(v)) if a.device == 3 && a.sub == 7 => Some(*v),
            _ => None,
        })
        .collect();
    let missing: Vec<String> = otc_ext::OtcErrorBits::all()
        .iter_names()
        .filter(|(_, bit)| !answers.iter().any(|v| v & bit.bits() != 0))
        .map(|(name, _)| name.to_owned())
        .collect();
    assert!(
        missing.is_empty(),
        "OtcError bits no trace provokes: {missing:?}"
    );
}
