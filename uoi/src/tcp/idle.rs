//! The connection watchdog: one thread per server looks at every
//! connection [`TICKS`] times per timeout (the shorter of the idle and the
//! write timeout) and closes each one that has made no progress for the
//! idle timeout, or whose answers have been stuck on a full socket for the
//! write timeout; on shutdown it closes them all.
//!
//! Progress is a complete request read, or a batch of answers written out
//! in full. A client that takes its answers a few bytes at a time does not
//! hold its place: its batch must leave within the write timeout.
//!
//! Why a thread and not a tokio timer per connection: a timer armed in the
//! serving runtime makes every park of that runtime dearer (the time
//! driver looks up the next expiry and reads the clock), and a connection
//! waits, so parks, once per sequential request. Here a request costs its
//! connection one relaxed atomic increment (a wait for input also registers
//! its waker) and the runtime keeps no timer.
//! A connection learns that it is closed from its reader ([`Activity::poll_closed`]),
//! not from a second future raced against every read.

use std::io;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, Weak};
use std::task::{Context, Poll};
use std::time::Duration;

use futures_util::task::AtomicWaker;

/// Looks per timeout. A connection is closed after between the timeout
/// and `timeout * (1 + 1 / TICKS)`, never before the timeout.
const TICKS: u32 = 8;

/// Shortest time between two looks.
const MIN_TICK: Duration = Duration::from_millis(1);

/// Why a connection is closed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Closed {
    /// No progress for the idle timeout.
    Idle = 1,
    /// Answers stuck on a full socket for the write timeout.
    Write = 2,
    /// The server is stopping.
    Stop = 3,
}

/// The state of a connection not closed.
const OPEN: u8 = 0;

/// What a connection shares with the watchdog.
#[derive(Debug)]
pub(crate) struct Activity {
    /// Progress so far: complete requests read and batches of answers
    /// written out in full. Only the connection's own task moves it.
    progress: AtomicU64,
    /// Answers are waiting on a full socket (the client does not read
    /// them, or too slowly); cleared when the batch is out.
    stuck: AtomicBool,
    /// [`OPEN`], or why the connection is closed ([`Closed`]).
    state: AtomicU8,
    /// The connection's task while it waits for input.
    waker: AtomicWaker,
}

impl Activity {
    fn new() -> Self {
        Self {
            progress: AtomicU64::new(0),
            stuck: AtomicBool::new(false),
            state: AtomicU8::new(OPEN),
            waker: AtomicWaker::new(),
        }
    }

    /// Records progress: a complete request read.
    pub(crate) fn progress(&self) {
        self.progress.fetch_add(1, Ordering::Relaxed);
    }

    /// Records that a write found the socket full: the answers wait.
    pub(crate) fn write_stuck(&self) {
        self.stuck.store(true, Ordering::Relaxed);
    }

    /// Records that every answer queued has been written: progress.
    pub(crate) fn written(&self) {
        self.stuck.store(false, Ordering::Relaxed);
        self.progress();
    }

    /// The progress count, for tests.
    #[cfg(test)]
    pub(crate) fn progress_count(&self) -> u64 {
        self.progress.load(Ordering::Relaxed)
    }

    /// Closes the connection (the first reason given stays) and wakes it.
    pub(crate) fn close(&self, why: Closed) {
        let _ = self
            .state
            .compare_exchange(OPEN, why as u8, Ordering::AcqRel, Ordering::Acquire);
        self.waker.wake();
    }

    /// Why the connection is closed, if it is.
    pub(crate) fn closed(&self) -> Option<Closed> {
        match self.state.load(Ordering::Acquire) {
            OPEN => None,
            s if s == Closed::Idle as u8 => Some(Closed::Idle),
            s if s == Closed::Write as u8 => Some(Closed::Write),
            _ => Some(Closed::Stop),
        }
    }

    /// For a reader that found no input: `Ready` if the connection is
    /// closed, else `Pending` with the task woken by a later [`close`](Self::close).
    pub(crate) fn poll_closed(&self, cx: &mut Context<'_>) -> Poll<Closed> {
        self.waker.register(cx.waker());
        // Looked at after registering: a close in between is not missed.
        match self.closed() {
            Some(why) => Poll::Ready(why),
            None => Poll::Pending,
        }
    }
}

/// The timeouts, in looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Limits {
    /// Looks without progress before an idle close.
    idle: u32,
    /// Looks with the answers stuck before a write-timeout close.
    write: u32,
}

impl Limits {
    /// The time between looks, and the timeouts counted in looks of it.
    fn new(idle: Duration, write: Duration) -> (Duration, Self) {
        let tick = (idle.min(write) / TICKS).max(MIN_TICK);
        let looks = |t: Duration| {
            let n = t.as_nanos().div_ceil(tick.as_nanos());
            u32::try_from(n).unwrap_or(u32::MAX)
        };
        let limits = Self {
            idle: looks(idle),
            write: looks(write),
        };
        (tick, limits)
    }
}

/// The watchdog's view of one connection.
#[derive(Debug)]
struct Entry {
    conn: Weak<Activity>,
    /// The progress count at the last look (`None` before the first look:
    /// the connection may have opened just before it).
    seen: Option<u64>,
    /// Looks in a row that found no progress.
    quiet: u32,
    /// Looks in a row, after the first, that found the answers stuck
    /// with no progress (`None` while they are not: the first look that
    /// finds them stuck only notes it, they may have just got stuck).
    stuck: Option<u32>,
}

impl Entry {
    fn new(conn: &Arc<Activity>) -> Self {
        Self {
            conn: Arc::downgrade(conn),
            seen: None,
            quiet: 0,
            stuck: None,
        }
    }

    /// One look. Returns whether to keep watching the connection: not
    /// when it is gone, or has just been closed.
    fn look(&mut self, limits: Limits) -> bool {
        let Some(conn) = self.conn.upgrade() else {
            return false;
        };
        let progress = conn.progress.load(Ordering::Relaxed);
        let stuck = conn.stuck.load(Ordering::Relaxed);
        if self.seen != Some(progress) {
            self.seen = Some(progress);
            self.quiet = 0;
            self.stuck = stuck.then_some(0);
            return true;
        }
        // No progress since the last look: one more full tick of silence.
        self.quiet += 1;
        self.stuck = stuck.then(|| self.stuck.map_or(0, |n| n + 1));
        let why = if self.quiet >= limits.idle {
            Closed::Idle
        } else if self.stuck.is_some_and(|n| n >= limits.write) {
            Closed::Write
        } else {
            return true;
        };
        conn.close(why);
        false
    }
}

/// The watched connections.
#[derive(Debug, Default)]
struct Entries(Mutex<Vec<Entry>>);

impl Entries {
    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Entry>> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// One look at every connection.
    fn sweep(&self, limits: Limits) {
        self.lock().retain_mut(|e| e.look(limits));
    }

    /// Closes every connection.
    fn close_all(&self) {
        for e in self.lock().drain(..) {
            if let Some(conn) = e.conn.upgrade() {
                conn.close(Closed::Stop);
            }
        }
    }
}

/// The watchdog of one server; its thread ends when this is dropped.
#[derive(Debug)]
pub(crate) struct Watchdog {
    entries: Arc<Entries>,
    /// Entries kept before closed connections are pruned between looks.
    prune_at: usize,
    /// Dropping it wakes the thread and ends it.
    _stop: mpsc::Sender<()>,
}

impl Watchdog {
    /// Starts the thread for connections idle after `idle`, or with
    /// answers stuck for `write`; `max_connections` bounds the entries kept
    /// between looks.
    pub(crate) fn start(
        idle: Duration,
        write: Duration,
        max_connections: usize,
    ) -> io::Result<Self> {
        let entries = Arc::new(Entries::default());
        let (stop, stopped) = mpsc::channel::<()>();
        let (tick, limits) = Limits::new(idle, write);
        let watched = Arc::clone(&entries);
        std::thread::Builder::new()
            .name("uoi-idle".into())
            .spawn(move || {
                while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(tick) {
                    watched.sweep(limits);
                }
            })?;
        Ok(Self {
            entries,
            prune_at: 2 * max_connections.max(1),
            _stop: stop,
        })
    }

    /// Watches a new connection.
    pub(crate) fn watch(&self) -> Arc<Activity> {
        let conn = Arc::new(Activity::new());
        let mut entries = self.entries.lock();
        if entries.len() >= self.prune_at {
            entries.retain(|e| e.conn.strong_count() > 0);
        }
        entries.push(Entry::new(&conn));
        conn
    }

    /// Closes every connection watched (the server is stopping).
    pub(crate) fn close_all(&self) {
        self.entries.close_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Idle after `TICKS` looks, answers stuck too long after 3.
    const LIMITS: Limits = Limits {
        idle: TICKS,
        write: 3,
    };

    fn watched() -> (Arc<Activity>, Entry) {
        let conn = Arc::new(Activity::new());
        let entry = Entry::new(&conn);
        (conn, entry)
    }

    /// `n` looks that keep watching and leave the connection open.
    fn looks(n: u32, conn: &Activity, e: &mut Entry) {
        for _ in 0..n {
            assert!(e.look(LIMITS));
            assert_eq!(conn.closed(), None);
        }
    }

    /// `TICKS` looks that keep watching and leave the connection open.
    fn a_timeout_of_looks(conn: &Activity, e: &mut Entry) {
        looks(TICKS, conn, e);
    }

    #[test]
    fn timeouts_in_looks_round_up_and_the_tick_follows_the_shorter() {
        let (tick, l) = Limits::new(Duration::from_secs(300), Duration::from_secs(30));
        assert_eq!(tick, Duration::from_millis(3750));
        assert_eq!(l, Limits { idle: 80, write: 8 });
        let (tick, l) = Limits::new(Duration::from_secs(1), Duration::from_millis(1500));
        assert_eq!(tick, Duration::from_millis(125));
        assert_eq!(l, Limits { idle: 8, write: 12 });
    }

    #[test]
    fn answers_stuck_for_the_write_timeout_close_the_connection() {
        let (conn, mut e) = watched();
        looks(1, &conn, &mut e);
        conn.progress();
        conn.write_stuck();
        // The look that first sees them stuck only notes it.
        looks(LIMITS.write, &conn, &mut e);
        assert!(!e.look(LIMITS));
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
        assert!(!e.look(LIMITS));
        assert_eq!(conn.closed(), Some(Closed::Write));
    }

    #[test]
    fn closed_after_a_full_timeout_of_quiet_looks_not_before() {
        let (conn, mut e) = watched();
        // The first look only notes the count: the connection may be new.
        a_timeout_of_looks(&conn, &mut e);
        assert!(!e.look(LIMITS));
        assert_eq!(conn.closed(), Some(Closed::Idle));
    }

    #[test]
    fn progress_starts_the_count_again() {
        let (conn, mut e) = watched();
        a_timeout_of_looks(&conn, &mut e);
        conn.progress();
        a_timeout_of_looks(&conn, &mut e);
        assert!(!e.look(LIMITS));
        assert_eq!(conn.closed(), Some(Closed::Idle));
    }

    #[test]
    fn closed_connections_are_dropped_from_the_watch() {
        let (conn, mut e) = watched();
        drop(conn);
        assert!(!e.look(LIMITS));
    }

    #[test]
    fn entries_of_closed_connections_are_pruned() {
        let dog = Watchdog::start(Duration::from_secs(3600), Duration::from_secs(3600), 2)
            .expect("thread");
        let mut open = Vec::new();
        for k in 0..100 {
            let conn = dog.watch();
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
        let dog = Watchdog::start(Duration::from_secs(3600), Duration::from_secs(3600), 8)
            .expect("thread");
        let (a, b) = (dog.watch(), dog.watch());
        a.close(Closed::Idle);
        dog.close_all();
        assert_eq!(a.closed(), Some(Closed::Idle));
        assert_eq!(b.closed(), Some(Closed::Stop));
    }

    #[test]
    fn a_close_wakes_the_waiting_reader() {
        let conn = Activity::new();
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
}
