//! The spooler: a FIFO of elements waiting for the executor, plus the
//! spool log that traces check (trc-geometry.md "Spooler and execution").

use std::collections::VecDeque;

use crate::element::SpoolElement;
use crate::plane::AxisPos;

/// The spooler queue and its log.
#[derive(Debug, Default)]
pub struct Spooler {
    queue: VecDeque<SpoolElement>,
    log: Vec<SpoolElement>,
    logging: bool,
}

impl Spooler {
    /// Whether every spooled element is also kept in the log.
    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Appends an element.
    #[inline]
    pub fn push(&mut self, e: SpoolElement) {
        if self.logging {
            self.log.push(e);
        }
        self.queue.push_back(e);
    }

    /// Elements waiting (the one under way included).
    #[inline]
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether nothing waits.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// The end of the last waiting element.
    #[inline]
    pub fn last_end(&self) -> Option<AxisPos> {
        self.queue.back().map(|e| e.end)
    }

    /// The element under way.
    #[inline]
    pub fn front(&self) -> Option<&SpoolElement> {
        self.queue.front()
    }

    /// Removes the element under way.
    #[inline]
    pub fn pop_front(&mut self) -> Option<SpoolElement> {
        self.queue.pop_front()
    }

    /// Discards every waiting element (direct commands).
    pub fn discard(&mut self) {
        self.queue.clear();
    }

    /// Takes the log collected so far.
    pub fn take_log(&mut self) -> Vec<SpoolElement> {
        std::mem::take(&mut self.log)
    }
}
