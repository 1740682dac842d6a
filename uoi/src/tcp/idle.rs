//! The connection watchdog: one thread per server looks at every
//! connection [`TICKS`] times per timeout (the shortest of the idle
//! timeout, the write timeout and the eviction grace) and closes each one
//! that has made no progress for the idle timeout, or whose answers have
//! been stuck on a full socket for the write timeout; on shutdown it closes
//! them all. When the server is full, it names the connection quiet
//! longest, and closes it to make room ([`Watchdog::evict`]).
//!
//! Progress is a complete request read, a slice of a request served, or a
//! batch of answers written out in full. A client that takes its answers a few bytes at a time does not
//! hold its place: its batch must leave within the write timeout.
//!
//! A connection holds its place ([`Seat`]) until it is closed: a close
//! gives the place back at once, while the connection's task finishes (the
//! close wakes its blocked read or write) and drops the socket a moment
//! later.
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
use std::net::IpAddr;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, Weak};
use std::task::{Context, Poll};
use std::time::{Duration, Instant};

use futures_util::task::AtomicWaker;

use super::places::Seat;

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
    /// Closed to make room for a new connection: the server was full and
    /// this one had been quiet longest.
    Evicted = 4,
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
    /// The connection has presented the access token or completed a
    /// request: it is never closed to make room for a new one (while its
    /// answers are not stuck).
    trusted: AtomicBool,
    /// The connection's task while it waits for input.
    waker: AtomicWaker,
    /// Its place among the server's, given back when it is closed (or,
    /// closed by its peer, when it ends).
    seat: Mutex<Option<Seat>>,
}

impl Activity {
    fn new(seat: Option<Seat>) -> Self {
        Self {
            progress: AtomicU64::new(0),
            stuck: AtomicBool::new(false),
            state: AtomicU8::new(OPEN),
            trusted: AtomicBool::new(false),
            waker: AtomicWaker::new(),
            seat: Mutex::new(seat),
        }
    }

    /// The activity of no connection: never closed by the watchdog (the
    /// requests another face submits through a [`super::CoreHandle`]).
    pub(crate) fn unwatched() -> Self {
        Self::new(None)
    }

    /// Records progress: a complete request read, or a slice of a request
    /// served (a request being served is never idle). Only the
    /// connection's own task moves the count, so a plain load and store do (no locked
    /// read-modify-write per request).
    pub(crate) fn progress(&self) {
        let seen = self.progress.load(Ordering::Relaxed);
        self.progress.store(seen.wrapping_add(1), Ordering::Relaxed);
    }

    /// Records that the connection has presented the access token or
    /// completed a request: a newcomer may not take its place.
    pub(crate) fn trust(&self) {
        self.trusted.store(true, Ordering::Relaxed);
    }

    /// Whether a newcomer may take its place: not if it is trusted and
    /// takes its answers.
    fn evictable(&self) -> bool {
        !self.trusted.load(Ordering::Relaxed) || self.stuck.load(Ordering::Relaxed)
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

    /// Closes the connection (the first reason given stays), gives its
    /// place back and wakes it.
    pub(crate) fn close(&self, why: Closed) {
        let _ = self
            .state
            .compare_exchange(OPEN, why as u8, Ordering::AcqRel, Ordering::Acquire);
        drop(self.seat.lock().unwrap_or_else(|p| p.into_inner()).take());
        self.waker.wake();
    }

    /// Why the connection is closed, if it is.
    pub(crate) fn closed(&self) -> Option<Closed> {
        match self.state.load(Ordering::Acquire) {
            OPEN => None,
            s if s == Closed::Idle as u8 => Some(Closed::Idle),
            s if s == Closed::Write as u8 => Some(Closed::Write),
            s if s == Closed::Evicted as u8 => Some(Closed::Evicted),
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
    /// The eviction `grace` shortens the tick too: how long a connection
    /// has been quiet is known to a tick.
    fn new(idle: Duration, write: Duration, grace: Duration) -> (Duration, Self) {
        let tick = (idle.min(write).min(grace) / TICKS).max(MIN_TICK);
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
    /// The peer address whose place it holds.
    peer: IpAddr,
    /// The progress count at the last look (`None` before the first look:
    /// the connection may have opened just before it).
    seen: Option<u64>,
    /// Looks in a row that found no progress.
    quiet: u32,
    /// Looks in a row, after the first, that found the answers stuck
    /// with no progress (`None` while they are not: the first look that
    /// finds them stuck only notes it, they may have just got stuck).
    stuck: Option<u32>,
    /// Quiet since: when it opened, or the first look that saw its last
    /// progress (which came at most a tick before).
    quiet_since: Instant,
}

impl Entry {
    fn new(conn: &Arc<Activity>, peer: IpAddr, now: Instant) -> Self {
        Self {
            conn: Arc::downgrade(conn),
            peer,
            seen: None,
            quiet: 0,
            stuck: None,
            quiet_since: now,
        }
    }

    /// Whether `conn` has made progress since the last look (or since it
    /// opened, before the first look).
    fn moved(&self, conn: &Activity) -> bool {
        let progress = conn.progress.load(Ordering::Relaxed);
        self.seen.unwrap_or(0) != progress
    }

    /// How long `conn` has been quiet at least, at `now`; `None` if it has
    /// made progress since the last look.
    fn quiet_for(&self, conn: &Activity, now: Instant) -> Option<Duration> {
        (!self.moved(conn)).then(|| now.saturating_duration_since(self.quiet_since))
    }

    /// One look at `now`. Returns whether to keep watching the connection:
    /// not when it is gone, or closed.
    fn look(&mut self, limits: Limits, now: Instant) -> bool {
        let Some(conn) = self.conn.upgrade() else {
            return false;
        };
        if conn.closed().is_some() {
            return false;
        }
        let progress = conn.progress.load(Ordering::Relaxed);
        let stuck = conn.stuck.load(Ordering::Relaxed);
        if self.seen != Some(progress) {
            if self.moved(&conn) {
                self.quiet_since = now;
            }
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
        let now = Instant::now();
        self.lock().retain_mut(|e| e.look(limits, now));
    }

    /// Closes the open connection quiet longest, if for `grace` at least,
    /// among those from `within` (all when `None`) that may be evicted
    /// (not trusted, or with answers stuck); of those quiet equally long
    /// (as far as the looks tell), the oldest.
    fn evict(&self, within: Option<IpAddr>, grace: Duration, now: Instant) -> Option<Evicted> {
        let entries = self.lock();
        // Oldest first; `max_by_key` keeps the last of equals.
        let (conn, peer, quiet) = entries
            .iter()
            .rev()
            .filter(|e| within.is_none_or(|ip| e.peer == ip))
            .filter_map(|e| {
                let conn = e.conn.upgrade()?;
                if conn.closed().is_some() || !conn.evictable() {
                    return None;
                }
                let quiet = e.quiet_for(&conn, now)?;
                (quiet >= grace).then_some((conn, e.peer, quiet))
            })
            .max_by_key(|(_, _, quiet)| *quiet)?;
        conn.close(Closed::Evicted);
        Some(Evicted { peer, quiet })
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

/// A connection closed to make room.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Evicted {
    /// Its peer address.
    pub(crate) peer: IpAddr,
    /// How long it had been quiet at least.
    pub(crate) quiet: Duration,
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
    /// answers stuck for `write`, and evicted after `grace` of quiet at
    /// the earliest; `max_connections` bounds the entries kept between
    /// looks.
    pub(crate) fn start(
        idle: Duration,
        write: Duration,
        grace: Duration,
        max_connections: usize,
    ) -> io::Result<Self> {
        let entries = Arc::new(Entries::default());
        let (stop, stopped) = mpsc::channel::<()>();
        let (tick, limits) = Limits::new(idle, write, grace);
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

    /// Watches a new connection, holding `seat`.
    pub(crate) fn watch(&self, seat: Seat) -> Arc<Activity> {
        let peer = seat.ip();
        let conn = Arc::new(Activity::new(Some(seat)));
        let mut entries = self.entries.lock();
        if entries.len() >= self.prune_at {
            entries.retain(|e| e.conn.upgrade().is_some_and(|c| c.closed().is_none()));
        }
        entries.push(Entry::new(&conn, peer, Instant::now()));
        conn
    }

    /// Makes room for a new connection: closes the open connection quiet
    /// longest, if it has been quiet for the grace `grace` at least, among
    /// those from `within` (all when `None`). Its place is free on return.
    pub(crate) fn evict(&self, within: Option<IpAddr>, grace: Duration) -> Option<Evicted> {
        self.entries.evict(within, grace, Instant::now())
    }

    /// Closes every connection watched (the server is stopping).
    pub(crate) fn close_all(&self) {
        self.entries.close_all();
    }
}

#[cfg(test)]
mod tests;
