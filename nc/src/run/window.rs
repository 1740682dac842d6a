//! The block window: blocks pulled from the program as the run needs them,
//! and held only while a loop may jump back to them.
//!
//! Blocks are numbered from 0 in program order. The window holds the
//! blocks from `base` on; the interpreter releases the ones before the
//! block it runs next whenever no `$FOR`/`$WHILE` is open, so a program
//! without loops holds one block at a time, and one with loops the body of
//! its outermost open loop. Released blocks lend their storage to the next
//! ones read.

use std::io::BufRead;

use crate::error::NcError;
use crate::model::{Block, Item};
use crate::stream::Blocks;

use super::{RunError, RunErrorKind};

/// Where the blocks of a run come from.
pub trait BlockSource {
    /// The next block into `block` (whose storage may be reused); `None`
    /// at the end.
    fn next_into(&mut self, block: &mut Block) -> Option<Result<(), NcError>>;
}

impl<R: BufRead> BlockSource for &mut Blocks<R> {
    fn next_into(&mut self, block: &mut Block) -> Option<Result<(), NcError>> {
        Blocks::next_into(self, block)
    }
}

/// Blocks from any iterator (a program held whole, a test's list).
pub struct FromIter<I>(pub I);

impl<I: Iterator<Item = Result<Block, NcError>>> BlockSource for FromIter<I> {
    fn next_into(&mut self, block: &mut Block) -> Option<Result<(), NcError>> {
        self.0.next().map(|r| r.map(|b| *block = b))
    }
}

/// Blocks of a program pulled from `source` and held for jumping back, in
/// a ring of slots that are reused in place (no block is moved or
/// allocated per block read).
pub struct Window<S> {
    source: S,
    /// The ring: `len` held blocks from slot `head` on, wrapping around.
    slots: Vec<Block>,
    head: usize,
    len: usize,
    /// Number of the block in slot `head`.
    base: usize,
    peak: usize,
}

/// Where a forward skip ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipTo {
    /// After the `$ENDFOR` of the `$FOR` skipped from.
    EndFor,
    /// After the `$ENDWHILE` of the `$WHILE` skipped from.
    EndWhile,
    /// After the `$ELSE` or `$ENDIF` of the `$IF` skipped from.
    ElseOrEndIf,
    /// After the `$ENDIF` of the `$ELSE` skipped from.
    EndIf,
}

/// Slots kept when no block is held; more are given back.
const KEEP_SLOTS: usize = 64;

impl<S: BlockSource> Window<S> {
    /// A window on the blocks `source` yields (it must not yield errors:
    /// the program was checked before).
    pub fn new(source: S) -> Self {
        Window {
            source,
            slots: Vec::new(),
            head: 0,
            len: 0,
            base: 0,
            peak: 0,
        }
    }

    /// Most blocks held at once so far.
    pub fn peak(&self) -> usize {
        self.peak
    }

    /// The slot of the `offset`-th held block (`offset` at most the
    /// number of slots).
    fn slot(&self, offset: usize) -> usize {
        let k = self.head + offset;
        if k >= self.slots.len() {
            k - self.slots.len()
        } else {
            k
        }
    }

    /// Block `k`, pulled from the program when it is the next one; `None`
    /// after the program's end.
    pub fn get(&mut self, k: usize) -> Result<Option<&Block>, RunError> {
        let Some(offset) = k.checked_sub(self.base) else {
            return Err(internal(format!(
                "block {k} of the program is no longer held"
            )));
        };
        while self.len <= offset {
            if self.len == self.slots.len() {
                self.grow();
            }
            let at = self.slot(self.len);
            match self.source.next_into(&mut self.slots[at]) {
                Some(Ok(())) => self.len += 1,
                Some(Err(e)) => return Err(not_parsed(e)),
                None => return Ok(None),
            }
        }
        self.peak = self.peak.max(self.len);
        Ok(Some(&self.slots[self.slot(offset)]))
    }

    /// Doubles the ring (at least one slot), the held blocks first.
    fn grow(&mut self) {
        self.slots.rotate_left(self.head);
        self.head = 0;
        let more = self.slots.len().max(1);
        self.slots
            .resize_with(self.slots.len() + more, Block::default);
    }

    /// Drops the blocks before block `k`: no loop can jump back to them
    /// (their slots are reused).
    pub fn release_before(&mut self, k: usize) {
        let n = k.saturating_sub(self.base).min(self.len);
        self.head = self.slot(n);
        self.len -= n;
        self.base += n;
        if self.len == 0 {
            self.base = self.base.max(k);
            // A long loop left: its storage goes back.
            if self.slots.len() > KEEP_SLOTS {
                self.slots.truncate(KEEP_SLOTS);
                self.head = 0;
            }
        }
    }

    /// The block after the end of the structure opened at block `from`
    /// (nested structures skipped whole). With `keep` false the skipped
    /// blocks are released as the skip goes (no loop is open).
    pub fn skip(&mut self, from: usize, to: SkipTo, keep: bool) -> Result<usize, RunError> {
        let mut depth = 0usize;
        let mut k = from + 1;
        loop {
            if !keep {
                self.release_before(k);
            }
            let Some(block) = self.get(k)? else {
                return Err(internal(format!(
                    "the structure of block {from} has no end"
                )));
            };
            let at_end = match block.items.first() {
                Some(Item::For { .. } | Item::If(_) | Item::While(_)) => {
                    depth += 1;
                    false
                }
                Some(Item::Else) if depth == 0 => to == SkipTo::ElseOrEndIf,
                Some(Item::EndFor | Item::EndWhile | Item::EndIf) if depth > 0 => {
                    depth -= 1;
                    false
                }
                Some(Item::EndFor) => to == SkipTo::EndFor,
                Some(Item::EndWhile) => to == SkipTo::EndWhile,
                Some(Item::EndIf) => matches!(to, SkipTo::EndIf | SkipTo::ElseOrEndIf),
                _ => false,
            };
            if at_end {
                return Ok(k + 1);
            }
            k += 1;
        }
    }
}

/// A jump the checked program cannot need (a block released too early, a
/// structure without its end): reported, never a panic, without a place
/// of its own (the interpreter gives it the block it runs).
fn internal(what: String) -> RunError {
    RunError {
        location: None,
        kind: RunErrorKind::Internal(what),
    }
}

/// A line in error met by the run (a program not checked first), at its
/// place.
fn not_parsed(e: NcError) -> RunError {
    RunError {
        location: Some(e.location()),
        kind: RunErrorKind::Parse(e.message),
    }
}
