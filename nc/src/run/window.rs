//! The block window: blocks pulled from the program as the run needs them,
//! and held only while a loop may jump back to them.
//!
//! Blocks are numbered from 0 in program order. The window holds the
//! blocks from `base` on; the interpreter releases the ones before the
//! block it runs next whenever no `$FOR`/`$WHILE` is open, so a program
//! without loops holds one block at a time, and one with loops the body of
//! its outermost open loop.

use std::collections::VecDeque;

use crate::error::NcError;
use crate::model::{Block, Item};

/// Blocks of a program pulled from `source` and held for jumping back.
pub struct Window<I> {
    source: I,
    held: VecDeque<Block>,
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

impl<I: Iterator<Item = Result<Block, NcError>>> Window<I> {
    /// A window on the blocks `source` yields (it must not yield errors:
    /// the program was checked before).
    pub fn new(source: I) -> Self {
        Window {
            source,
            held: VecDeque::new(),
            base: 0,
            peak: 0,
        }
    }

    /// Most blocks held at once so far.
    pub fn peak(&self) -> usize {
        self.peak
    }

    /// Block `k`, pulled from the program when it is the next one; `None`
    /// after the program's end.
    pub fn get(&mut self, k: usize) -> Result<Option<&Block>, NcError> {
        let Some(offset) = k.checked_sub(self.base) else {
            return Err(internal(format!("block {k} of the program is no longer held")));
        };
        while self.held.len() <= offset {
            match self.source.next() {
                Some(block) => self.held.push_back(block?),
                None => return Ok(None),
            }
        }
        self.peak = self.peak.max(self.held.len());
        Ok(self.held.get(offset))
    }

    /// Drops the blocks before block `k`: no loop can jump back to them.
    pub fn release_before(&mut self, k: usize) {
        while self.base < k && self.held.pop_front().is_some() {
            self.base += 1;
        }
        if self.held.is_empty() {
            self.base = self.base.max(k);
        }
    }

    /// The block after the end of the structure opened at block `from`
    /// (nested structures skipped whole). With `keep` false the skipped
    /// blocks are released as the skip goes (no loop is open).
    pub fn skip(&mut self, from: usize, to: SkipTo, keep: bool) -> Result<usize, NcError> {
        let mut depth = 0usize;
        let mut k = from + 1;
        loop {
            if !keep {
                self.release_before(k);
            }
            let Some(block) = self.get(k)? else {
                return Err(internal(format!("the structure of block {from} has no end")));
            };
            let first = block.items.first();
            let at_end = match first {
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
/// structure without its end): reported, never a panic.
fn internal(what: String) -> NcError {
    NcError {
        line: 0,
        block_number: None,
        column: 1,
        message: format!("internal: {what}"),
    }
}
