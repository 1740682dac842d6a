use super::*;
use crate::field::ToolField;
use crate::replay::{replay, replay_lenient};
use proptest::prelude::*;

fn set(group: u8, index: u16, field: ToolField, value: ToolValue) -> Record {
    Record::Set {
        group,
        key: ToolKey::new(index, field).unwrap(),
        value,
    }
}

#[test]
fn record_text_has_group_assignment_and_checksum() {
    let r = set(3, 5, ToolField::Radius, ToolValue::F64(30.0));
    let line = r.encode();
    let crc = crc32fast::hash(b"g3 wz[5].radius 300000");
    assert_eq!(line, format!("g3 wz[5].radius 300000 *{crc:08x}\n"));
    assert_eq!(Record::decode(line.trim_end().as_bytes()), Ok(r));
}

#[test]
fn reset_and_clean_records_round_trip() {
    for r in [Record::ResetGroup { group: 32 }, Record::Clean] {
        let line = r.encode();
        assert_eq!(Record::decode(line.trim_end().as_bytes()), Ok(r));
    }
    assert!(Record::ResetGroup { group: 1 }
        .encode()
        .starts_with("g1 reset *"));
    assert!(Record::Clean.encode().starts_with("clean *"));
}

#[test]
fn check_refuses_bad_group_and_value() {
    assert!(Record::ResetGroup { group: 0 }.check().is_err());
    assert!(Record::ResetGroup { group: 33 }.check().is_err());
    assert!(set(1, 0, ToolField::ToolType, ToolValue::I32(4))
        .check()
        .is_err());
    assert!(set(1, 0, ToolField::Radius, ToolValue::F64(f64::NAN))
        .check()
        .is_err());
    assert!(set(1, 0, ToolField::Radius, ToolValue::I32(1))
        .check()
        .is_err());
    assert!(set(32, 1023, ToolField::ToolType, ToolValue::I32(3))
        .check()
        .is_ok());
}

#[test]
fn decode_reports_what_is_wrong() {
    let with_crc = |body: &str| format!("{body} *{:08x}", crc32fast::hash(body.as_bytes()));
    assert_eq!(Record::decode(b"g1 reset"), Err(RecordError::NoChecksum));
    assert_eq!(
        Record::decode(b"g1 reset *0000000"),
        Err(RecordError::NoChecksum)
    );
    assert_eq!(
        Record::decode(b"g1 reset *00000000"),
        Err(RecordError::Checksum)
    );
    let bad_group = with_crc("g33 reset");
    assert!(matches!(
        Record::decode(bad_group.as_bytes()),
        Err(RecordError::GroupOutOfRange(_))
    ));
    let unknown = with_crc("g1 wz[1].gueltig 1");
    assert!(matches!(
        Record::decode(unknown.as_bytes()),
        Err(RecordError::Line(LineError::UnknownField(_)))
    ));
    let garbage = with_crc("hello");
    assert!(matches!(
        Record::decode(garbage.as_bytes()),
        Err(RecordError::Malformed(_))
    ));
    assert!(matches!(
        Record::decode(b"\xff\xfe *00000000"),
        Err(RecordError::Malformed(_))
    ));
}

fn sample() -> Vec<Record> {
    vec![
        set(1, 1, ToolField::ToolType, ToolValue::I32(2)),
        set(1, 1, ToolField::Radius, ToolValue::F64(30.0)),
        Record::ResetGroup { group: 2 },
        set(2, 7, ToolField::Length, ToolValue::F64(-0.0)),
        Record::Clean,
        set(4, 1023, ToolField::TiltAngle, ToolValue::F64(-450000.0)),
    ]
}

#[test]
fn replay_gives_every_record() {
    let bytes = encode_batch(&sample());
    let r = replay(&bytes).unwrap();
    assert_eq!(r.records, sample());
    assert_eq!(r.torn_tail, None);
    assert_eq!(r.valid_len, bytes.len() as u64);
    assert_eq!(replay(b"").unwrap(), Replay::default());
}

#[test]
fn torn_tail_at_every_byte_of_the_last_record_is_dropped() {
    let records = sample();
    let before = encode_lines(&records[..5]);
    let full = encode_lines(&records);
    for cut in before.len() + 1..full.len() {
        let r = replay(&full[..cut]).unwrap();
        assert_eq!(r.records, records[..5], "cut at {cut}");
        let tail = r.torn_tail.unwrap();
        assert_eq!((tail.line, tail.offset), (6, before.len() as u64));
        assert_eq!(tail.bytes, (cut - before.len()) as u64);
        assert_eq!(r.valid_len, before.len() as u64);
    }
    // Cut exactly at the record's start: nothing torn.
    assert_eq!(replay(&full[..before.len()]).unwrap().torn_tail, None);
}

/// A bit flip in the last complete record is not a
/// torn write (a write cut short leaves no newline after a wrong byte):
/// it refuses the replay with its line, as anywhere else.
#[test]
fn complete_last_line_with_bad_checksum_is_corruption() {
    let mut bytes = encode_lines(&sample());
    let at = bytes.len() - 4;
    bytes[at] ^= 0x01;
    let e = replay(&bytes).unwrap_err();
    assert_eq!(
        e,
        JournalError {
            line: 6,
            error: RecordError::Checksum
        }
    );
    // A bit flip in its text rather than its checksum: the same.
    let mut bytes = encode_lines(&sample());
    let at = bytes.len() - 14;
    bytes[at] ^= 0x01;
    assert_eq!(replay(&bytes).unwrap_err().line, 6);
    // Skipped when told to, and nothing is taken for a torn tail.
    let lenient = replay_lenient(&bytes);
    assert_eq!(lenient.records, sample()[..5]);
    assert_eq!((lenient.skipped.len(), lenient.torn_tail), (1, None));
    assert_eq!(lenient.valid_len, bytes.len() as u64);
}

#[test]
fn a_torn_tail_is_only_ever_a_line_without_its_newline() {
    let full = encode_lines(&sample());
    for cut in 1..full.len() {
        match replay(&full[..cut]) {
            Ok(r) => {
                let tail = r.torn_tail.map(|t| t.reason);
                let whole = full[..cut].ends_with(b"\n");
                assert_eq!(tail.is_none(), whole, "cut at {cut}");
                assert!(tail.is_none_or(|t| t == RecordError::Incomplete));
            }
            Err(e) => panic!("cut at {cut}: {e}"),
        }
    }
}

#[test]
fn bad_record_before_the_last_is_corruption_with_line() {
    let mut bytes = encode_lines(&sample());
    // Flip a digit in line 2 ("g1 wz[1].radius 300000").
    let at = bytes.windows(6).position(|w| w == b"300000").unwrap();
    bytes[at] = b'4';
    let e = replay(&bytes).unwrap_err();
    assert_eq!(
        e,
        JournalError {
            line: 2,
            error: RecordError::Checksum
        }
    );
    assert_eq!(e.to_string(), "line 2: checksum mismatch");

    let lenient = replay_lenient(&bytes);
    assert_eq!(lenient.skipped, [e]);
    assert_eq!(lenient.records.len(), 5);
    assert_eq!(lenient.valid_len, bytes.len() as u64);
}

fn any_record() -> impl Strategy<Value = Record> {
    let value = prop_oneof![
        (0..=3).prop_map(|v| (ToolField::ToolType, ToolValue::I32(v))),
        any::<f64>()
            .prop_filter("within the bus range", |v| v.abs() <= 1e9)
            .prop_map(|v| (ToolField::Radius, ToolValue::F64(v))),
        (-1e9..1e9f64).prop_map(|v| (ToolField::Length, ToolValue::F64(v))),
        (0.0..1e9f64).prop_map(|v| (ToolField::WearConst, ToolValue::F64(v))),
        (-1e9..1e9f64).prop_map(|v| (ToolField::MaxInfeed, ToolValue::F64(v))),
        (-450000.0..=450000.0f64).prop_map(|v| (ToolField::TiltAngle, ToolValue::F64(v))),
    ];
    prop_oneof![
        8 => (1..=32u8, 0..1024u16, value).prop_map(|(g, i, (f, v))| set(g, i, f, v)),
        1 => (1..=32u8).prop_map(|group| Record::ResetGroup { group }),
        1 => Just(Record::Clean),
    ]
}

proptest! {
    #[test]
    fn append_then_replay_gives_the_same_records(
        records in proptest::collection::vec(any_record(), 0..30)
    ) {
        let bytes = encode_batch(&records);
        let r = replay(&bytes).unwrap();
        prop_assert_eq!(r.records, records);
        prop_assert_eq!(r.torn_tail, None);
    }
}

#[test]
fn documented_examples_decode() {
    for line in [
        "g3 wz[5].radius 300000 *26a0b7f4",
        "g3 reset *b7948462",
        "clean *f1b0ad49",
    ] {
        assert!(Record::decode(line.as_bytes()).is_ok(), "{line}");
    }
}

/// A journal of batches as the store writes it: its first line, then
/// each batch closed by its `batch` line.
fn journal_of(batches: &[&[Record]]) -> Vec<u8> {
    let mut bytes = format_line().into_bytes();
    for b in batches {
        bytes.extend(encode_batch(b));
    }
    bytes
}

/// `bytes` with the first `at` bytes of its part from `from` on never
/// written (NUL): a power cut that kept the later part of the last write.
fn torn_later(bytes: &[u8], from: usize, at: usize) -> Vec<u8> {
    let mut torn = bytes.to_vec();
    let end = (from + at).min(torn.len());
    torn[from..end].iter_mut().for_each(|b| *b = 0);
    torn
}

#[test]
fn a_last_batch_torn_by_a_power_cut_is_dropped_at_every_cut() {
    let records = sample();
    let good = journal_of(&[&records[..2], &records[2..3]]);
    let full = journal_of(&[&records[..2], &records[2..3], &records[3..]]);
    let last = full.len() - good.len();
    for at in 1..=last {
        // The later part kept, NUL bytes before it.
        let torn = torn_later(&full, good.len(), at);
        let r = replay(&torn).unwrap_or_else(|e| panic!("later part from {at}: {e}"));
        assert_eq!(r.records, records[..3], "later part from {at}");
        let tail = r.torn_tail.unwrap();
        // All of it NUL, its newline too: a line cut short.
        let reason = if at < last {
            RecordError::TornBatch
        } else {
            RecordError::Incomplete
        };
        assert_eq!(tail.reason, reason, "later part from {at}");
        assert_eq!(
            (tail.offset, r.valid_len),
            (good.len() as u64, good.len() as u64)
        );
        // The earlier part kept, the rest never written.
        let cut = &full[..good.len() + at - 1];
        let r = replay(cut).unwrap_or_else(|e| panic!("earlier part to {at}: {e}"));
        assert_eq!(r.records, records[..3], "earlier part to {at}");
        assert_eq!(r.valid_len, good.len() as u64);
    }
    // Nothing torn: every record.
    assert_eq!(replay(&full).unwrap().records, records);
}

#[test]
fn the_first_batch_of_a_journal_torn_by_a_power_cut_is_dropped() {
    let full = journal_of(&[&sample()]);
    for at in 1..full.len() {
        let torn = torn_later(&full, 0, at);
        let r = replay(&torn).unwrap_or_else(|e| panic!("later part from {at}: {e}"));
        // Only its first line torn: the batch is intact and counts.
        let whole = at < format_line().len();
        let expected = if whole { sample() } else { Vec::new() };
        assert_eq!(r.records, expected, "later part from {at}");
        assert_eq!(r.torn_tail.is_none(), whole, "later part from {at}");
    }
}

#[test]
fn a_damaged_batch_followed_by_an_intact_one_is_corruption() {
    let records = sample();
    let full = journal_of(&[&records[..2], &records[2..3], &records[3..]]);
    let second = journal_of(&[&records[..2]]).len();
    let torn = torn_later(&full, second, 10);
    let e = replay(&torn).unwrap_err();
    // Line 1 marks the form; lines 2-4 are the first batch.
    assert_eq!(e.line, 5, "{e}");
    assert!(matches!(e.error, RecordError::Batch(_)), "{e}");
    assert!(
        e.to_string().contains("acknowledged data is damaged"),
        "{e}"
    );
    // Skipped when told to: the intact batches count.
    let lenient = replay_lenient(&torn);
    assert_eq!(lenient.records.len(), records.len() - 1);
    assert_eq!(lenient.skipped.len(), 1);
}

#[test]
fn a_flipped_bit_in_the_last_batch_is_corruption_not_a_torn_write() {
    let full = journal_of(&[&sample()[..2], &sample()[2..]]);
    // In the last record's text, then in the line closing the batch.
    let trailer = full.windows(6).rposition(|w| w == b"batch ").unwrap();
    for at in [trailer - 14, full.len() - 4] {
        let mut bytes = full.clone();
        bytes[at] ^= 0x01;
        let e = replay(&bytes).unwrap_err();
        assert_eq!(e.error, RecordError::Checksum, "flip at {at}: {e}");
    }
}

#[test]
fn a_journal_of_the_older_form_then_batches_reads_whole() {
    let records = sample();
    let mut bytes = encode_lines(&records[..3]);
    bytes.extend(encode_batch(&records[3..5]));
    bytes.extend(encode_batch(&records[5..]));
    let r = replay(&bytes).unwrap();
    assert_eq!(r.records, records);
    assert_eq!((r.torn_tail, r.valid_len), (None, bytes.len() as u64));
}
