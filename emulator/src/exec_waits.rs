//! `EXEC` in real time on the shared emulator: a wait, never a step ahead
//! of the clock (as in the host library). `EXEC n` is answered once the
//! clock has run `n` more cycles, `EXEC` once the spooler is empty. The
//! server awaits each wait without holding the emulator (a
//! [`Slice::Wait`](uoi::tcp::Slice)), so every other request is served
//! meanwhile; the service's ticks fire the waits that are over.

use tokio::sync::oneshot;
use uoi::tcp::Wait;

/// The bit that marks a wait's token as an `EXEC` wait (the tool
/// writes' tokens count up from 1 and never reach it).
pub(crate) const EXEC_WAIT_BIT: u64 = 1 << 63;

/// Most `EXEC` waits at once (one per connection at a time; waits of
/// connections that went away are dropped at the next tick).
pub const MAX_EXEC_WAITS: usize = 65_536;

/// What an `EXEC` waits for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Until {
    /// The clock has run this many cycles since the start.
    Cycle(u64),
    /// The spooler is empty.
    Empty,
}

#[derive(Debug)]
struct Pending {
    until: Until,
    done: oneshot::Sender<bool>,
}

/// The `EXEC` waits of the shared emulator.
#[derive(Debug, Default)]
pub(crate) struct ExecWaits {
    pending: Vec<Pending>,
    next: u64,
}

impl ExecWaits {
    /// A new wait; `None` when [`MAX_EXEC_WAITS`] wait already.
    pub fn add(&mut self, until: Until) -> Option<Wait> {
        self.pending.retain(|p| !p.done.is_closed());
        if self.pending.len() >= MAX_EXEC_WAITS {
            return None;
        }
        let (tx, rx) = oneshot::channel();
        self.next = self.next.wrapping_add(1);
        self.pending.push(Pending { until, done: tx });
        Some(Wait {
            done: rx,
            token: EXEC_WAIT_BIT | (self.next & !EXEC_WAIT_BIT),
        })
    }

    /// Ends the waits that are over at `passed` cycles with the spooler
    /// `empty` or not (and drops those nobody awaits any more).
    pub fn fire(&mut self, passed: u64, empty: bool) {
        let over = |u: Until| match u {
            Until::Cycle(c) => passed >= c,
            Until::Empty => empty,
        };
        let mut k = 0;
        while k < self.pending.len() {
            let p = &self.pending[k];
            if p.done.is_closed() || over(p.until) {
                let p = self.pending.swap_remove(k);
                let _ = p.done.send(true);
            } else {
                k += 1;
            }
        }
    }

    /// Ends every wait as not done (the server stops).
    pub fn end_all(&mut self) {
        for p in self.pending.drain(..) {
            let _ = p.done.send(false);
        }
    }

    /// Waits going on.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.pending.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wait_ends_when_its_cycle_or_an_empty_spooler_comes() {
        let mut w = ExecWaits::default();
        let mut a = w.add(Until::Cycle(100)).unwrap();
        let mut b = w.add(Until::Empty).unwrap();
        assert_ne!(a.token, b.token);
        assert!(a.token & EXEC_WAIT_BIT != 0);
        w.fire(99, false);
        assert!(a.done.try_recv().is_err());
        w.fire(100, false);
        assert_eq!(a.done.try_recv(), Ok(true));
        assert!(b.done.try_recv().is_err());
        w.fire(100, true);
        assert_eq!(b.done.try_recv(), Ok(true));
        assert_eq!(w.len(), 0);
        let gone = w.add(Until::Empty).unwrap();
        drop(gone);
        w.fire(0, false);
        assert_eq!(w.len(), 0, "a wait nobody awaits is dropped");
    }
}
