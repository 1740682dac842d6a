//! The watchdog's looks, sweeps, evictions and closes.

use super::*;

/// Idle after `TICKS` looks, answers stuck too long after 3.
const LIMITS: Limits = Limits {
    idle: TICKS,
    write: 3,
};

const LOCAL: IpAddr = IpAddr::V4(std::net::Ipv4Addr::LOCALHOST);
const HOUR: Duration = Duration::from_secs(3600);

fn seat() -> Seat {
    crate::tcp::places::test_seat(LOCAL)
}

fn watched() -> (Arc<Activity>, Entry) {
    let conn = Arc::new(Activity::new(None));
    let entry = Entry::new(&conn, LOCAL, Instant::now());
    (conn, entry)
}

/// `n` looks that keep watching and leave the connection open.
fn looks(n: u32, conn: &Activity, e: &mut Entry) {
    for _ in 0..n {
        assert!(e.look(LIMITS, Instant::now()));
        assert_eq!(conn.closed(), None);
    }
}

/// `TICKS` looks that keep watching and leave the connection open.
fn a_timeout_of_looks(conn: &Activity, e: &mut Entry) {
    looks(TICKS, conn, e);
}

#[test]
fn timeouts_in_looks_round_up_and_the_tick_follows_the_shorter() {
    let (tick, l) = Limits::new(Duration::from_secs(300), Duration::from_secs(30), HOUR);
    assert_eq!(tick, Duration::from_millis(3750));
    assert_eq!(l, Limits { idle: 80, write: 8 });
    let (tick, l) = Limits::new(Duration::from_secs(1), Duration::from_millis(1500), HOUR);
    assert_eq!(tick, Duration::from_millis(125));
    assert_eq!(l, Limits { idle: 8, write: 12 });
    // The grace of eviction, when shorter, sets the tick.
    let (tick, l) = Limits::new(
        Duration::from_secs(300),
        Duration::from_secs(30),
        Duration::from_secs(1),
    );
    assert_eq!(tick, Duration::from_millis(125));
    assert_eq!(
        l,
        Limits {
            idle: 2400,
            write: 240
        }
    );
}

#[test]
fn answers_stuck_for_the_write_timeout_close_the_connection() {
    let (conn, mut e) = watched();
    looks(1, &conn, &mut e);
    conn.progress();
    conn.write_stuck();
    // The look that first sees them stuck only notes it.
    looks(LIMITS.write, &conn, &mut e);
    assert!(!e.look(LIMITS, Instant::now()));
    assert_eq!(conn.closed(), Some(Closed::Write));
}

#[test]
fn a_batch_written_out_in_full_is_progress_bytes_alone_are_not() {
    let (conn, mut e) = watched();
    looks(1, &conn, &mut e);
    conn.write_stuck();
    looks(LIMITS.write, &conn, &mut e);
    // The batch leaves: the stuck count starts again.
    conn.written();
    looks(LIMITS.write, &conn, &mut e);
    conn.write_stuck();
    looks(LIMITS.write, &conn, &mut e);
    assert!(!e.look(LIMITS, Instant::now()));
    assert_eq!(conn.closed(), Some(Closed::Write));
}

#[test]
fn closed_after_a_full_timeout_of_quiet_looks_not_before() {
    let (conn, mut e) = watched();
    // The first look only notes the count: the connection may be new.
    a_timeout_of_looks(&conn, &mut e);
    assert!(!e.look(LIMITS, Instant::now()));
    assert_eq!(conn.closed(), Some(Closed::Idle));
}

#[test]
fn progress_starts_the_count_again() {
    let (conn, mut e) = watched();
    a_timeout_of_looks(&conn, &mut e);
    conn.progress();
    a_timeout_of_looks(&conn, &mut e);
    assert!(!e.look(LIMITS, Instant::now()));
    assert_eq!(conn.closed(), Some(Closed::Idle));
}

#[test]
fn closed_connections_are_dropped_from_the_watch() {
    let (conn, mut e) = watched();
    drop(conn);
    assert!(!e.look(LIMITS, Instant::now()));
}

#[test]
fn entries_of_closed_connections_are_pruned() {
    let dog = Watchdog::start(HOUR, HOUR, HOUR, 2).expect("thread");
    let mut open = Vec::new();
    for k in 0..100 {
        let conn = dog.watch(seat());
        if k % 10 == 0 {
            open.push(conn);
        }
    }
    let kept = dog.entries.lock().len();
    assert!(kept <= open.len() + dog.prune_at, "{kept} entries kept");
}

#[test]
fn a_sweep_closes_only_the_silent() {
    let entries = Entries::default();
    let (quiet, e1) = watched();
    let (busy, e2) = watched();
    entries.lock().extend([e1, e2]);
    for _ in 0..=TICKS {
        busy.progress();
        entries.sweep(LIMITS);
    }
    assert_eq!(quiet.closed(), Some(Closed::Idle));
    assert_eq!(busy.closed(), None);
    assert_eq!(entries.lock().len(), 1);
}

#[test]
fn close_all_closes_the_open_and_keeps_the_first_reason() {
    let dog = Watchdog::start(HOUR, HOUR, HOUR, 8).expect("thread");
    let (a, b) = (dog.watch(seat()), dog.watch(seat()));
    a.close(Closed::Idle);
    dog.close_all();
    assert_eq!(a.closed(), Some(Closed::Idle));
    assert_eq!(b.closed(), Some(Closed::Stop));
}

/// Three connections: `old` quiet since `t0`, `mid` since `t0 + 1 s`,
/// `new` opened at `t0 + 2 s`; `other` from another address, oldest.
fn three_and_another(t0: Instant) -> (Entries, [Arc<Activity>; 4]) {
    let entries = Entries::default();
    let other_ip = IpAddr::from([10, 0, 0, 9]);
    let at = |s| t0 + Duration::from_secs(s);
    let mk = |ip, when| {
        let conn = Arc::new(Activity::new(Some(crate::tcp::places::test_seat(ip))));
        let e = Entry::new(&conn, ip, when);
        (conn, e)
    };
    let (other, e0) = mk(other_ip, t0);
    let (old, e1) = mk(LOCAL, at(0));
    let (mid, e2) = mk(LOCAL, at(1));
    let (new, e3) = mk(LOCAL, at(2));
    entries.lock().extend([e0, e1, e2, e3]);
    (entries, [other, old, mid, new])
}

#[test]
fn eviction_closes_the_connection_quiet_longest_past_the_grace() {
    let t0 = Instant::now();
    let (entries, [other, old, mid, new]) = three_and_another(t0);
    let at = |ms| t0 + Duration::from_millis(ms);
    let grace = Duration::from_millis(1500);
    // Among those from 127.0.0.1, `old` has been quiet longest.
    let got = entries.evict(Some(LOCAL), grace, at(3000));
    assert_eq!(
        got,
        Some(Evicted {
            peer: LOCAL,
            quiet: Duration::from_secs(3)
        })
    );
    assert_eq!(old.closed(), Some(Closed::Evicted));
    assert!(old.seat.lock().expect("seat").is_none(), "place given back");
    // `mid` has made progress since the last look: it is not quiet.
    mid.progress();
    // `new` has been quiet 1 s, less than the grace.
    assert_eq!(entries.evict(Some(LOCAL), grace, at(3000)), None);
    assert_eq!((mid.closed(), new.closed()), (None, None));
    // With every address, the other host's connection is the one.
    let got = entries.evict(None, grace, at(3000)).expect("evicted");
    assert_eq!(got.peer, IpAddr::from([10, 0, 0, 9]));
    assert_eq!(other.closed(), Some(Closed::Evicted));
}

#[test]
fn of_connections_quiet_equally_long_the_oldest_goes() {
    let entries = Entries::default();
    let t0 = Instant::now();
    let conns: Vec<Arc<Activity>> = (0..3)
        .map(|_| Arc::new(Activity::new(Some(seat()))))
        .collect();
    entries
        .lock()
        .extend(conns.iter().map(|c| Entry::new(c, LOCAL, t0)));
    let later = t0 + Duration::from_secs(2);
    assert!(entries.evict(None, Duration::from_secs(1), later).is_some());
    let closed: Vec<bool> = conns.iter().map(|c| c.closed().is_some()).collect();
    assert_eq!(closed, [true, false, false]);
}

#[test]
fn a_look_that_sees_progress_starts_the_quiet_again() {
    let t0 = Instant::now();
    let (entries, [_other, old, _mid, _new]) = three_and_another(t0);
    old.progress();
    let at = |s| t0 + Duration::from_secs(s);
    entries.lock().iter_mut().for_each(|e| {
        e.look(LIMITS, at(5));
    });
    // Quiet since the look at 5 s: 0.5 s at 5.5 s, under a 1 s grace;
    // the others, quiet 3.5 s or more, go first.
    let grace = Duration::from_secs(1);
    let first = entries.evict(Some(LOCAL), grace, at(5) + grace / 2);
    assert!(first.is_some_and(|e| e.quiet >= Duration::from_millis(3500)));
    assert_eq!(old.closed(), None);
}

#[test]
fn a_close_wakes_the_waiting_reader() {
    let conn = Activity::new(None);
    let woken = Arc::new(Flag::default());
    let waker = std::task::Waker::from(Arc::clone(&woken));
    let mut cx = Context::from_waker(&waker);
    assert_eq!(conn.poll_closed(&mut cx), Poll::Pending);
    conn.close(Closed::Stop);
    assert!(woken.0.load(Ordering::SeqCst));
    assert_eq!(conn.poll_closed(&mut cx), Poll::Ready(Closed::Stop));
}

#[derive(Default)]
struct Flag(std::sync::atomic::AtomicBool);

impl std::task::Wake for Flag {
    fn wake(self: Arc<Self>) {
        self.0.store(true, Ordering::SeqCst);
    }
}
