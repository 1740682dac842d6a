//! The embedded emulator in real time: a spooled line finishes in
//! wall-clock time in proportion to its length and feed (generous bounds:
//! 0.5x to 3x of the expected time, the machine may be busy), a factor
//! of 10 runs it ten times faster, `exec` waits without running ahead of
//! the clock, and a recorded real-time session replays stepped.

// Helpers of the tests may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::time::{Duration, Instant};

use addipos_host::{EmbeddedOptions, Machine, RealTimeFactor};

fn machine(factor: f64) -> Machine {
    Machine::embedded(EmbeddedOptions {
        realtime: Some(RealTimeFactor::new(factor).unwrap()),
        ..EmbeddedOptions::default()
    })
}

fn x(v: f64) -> addipos_host::AxisWords {
    [Some(v), None, None, None, None, None, None, None]
}

/// Spools a line of `length` at `feed` and polls the queue until it is
/// empty, as a PCAP program does; the wall time it took.
fn time_of_line(m: &Machine, length: f64, feed: f64) -> Duration {
    m.lin(x(length), Some(feed)).unwrap();
    let t0 = Instant::now();
    while m.queue().unwrap() > 0 {
        std::thread::sleep(Duration::from_millis(2));
    }
    let took = t0.elapsed();
    assert!((m.position().unwrap()[0] - length).abs() < 1e-9);
    took
}

fn assert_about(took: Duration, expected: f64) {
    let s = took.as_secs_f64();
    assert!(
        (0.5 * expected..=3.0 * expected).contains(&s),
        "took {s} s, expected about {expected} s"
    );
}

#[test]
fn a_line_takes_its_length_over_its_feed() {
    // 100 mm at F6000 (100 mm/s): 1 s.
    assert_about(time_of_line(&machine(1.0), 100.0, 6000.0), 1.0);
}

#[test]
fn factor_ten_runs_ten_times_faster() {
    // 1000 mm at F6000 is 10 s of machine time: 1 s at factor 10.
    assert_about(time_of_line(&machine(10.0), 1000.0, 6000.0), 1.0);
}

#[test]
fn exec_waits_for_the_clock_and_never_runs_ahead() {
    let clock_start = Instant::now();
    let m = machine(10.0);
    m.lin(x(1000.0), Some(6000.0)).unwrap();
    let t0 = Instant::now();
    // 3000 cycles of 1 ms at factor 10: 0.3 s of wall time, 300 mm.
    m.exec(Some(3000)).unwrap();
    let took = t0.elapsed().as_secs_f64();
    let at = m.position().unwrap()[0];
    assert!(
        took >= 0.29,
        "exec returned after {took} s, before the clock ran 3000 cycles"
    );
    // At most what the clock has allowed since it started: 1000 mm/s.
    let allowed = clock_start.elapsed().as_secs_f64() * 10.0 * 100.0;
    assert!(
        at >= 300.0 - 1e-9 && at <= allowed,
        "at {at}, allowed {allowed}"
    );
    m.exec(None).unwrap();
    assert_eq!(m.queue().unwrap(), 0);
    assert!((m.position().unwrap()[0] - 1000.0).abs() < 1e-9);
}

#[test]
fn a_recorded_real_time_session_replays_stepped() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("rt.trace");
    let m = machine(20.0);
    m.record(&file).unwrap();
    m.lin(x(50.0), Some(6000.0)).unwrap();
    m.lin(
        [Some(50.0), Some(30.0), None, None, None, None, None, None],
        None,
    )
    .unwrap();
    while m.queue().unwrap() > 0 {
        std::thread::sleep(Duration::from_millis(3));
        m.position().unwrap();
    }
    m.exec(Some(100)).unwrap();
    m.position().unwrap();
    m.stop_recording();
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("\nEXEC "), "{text}");
    let t = trace::load_trace(&file).unwrap();
    let mismatches = trace::replay(&t);
    assert!(mismatches.is_empty(), "{mismatches:?}\n{text}");
}
