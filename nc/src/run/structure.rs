//! The control structures of a program as the run sees them: which
//! control statement a block holds, the loops that are open, and where
//! the run goes after a block. `flow` carries the statements out.

use crate::error::Location;
use crate::model::{Block, Item};
use crate::Var;

use super::window::SkipTo;
use super::{RunError, RunErrorKind};

/// The control statement of a block, if it holds one; it must stand alone
/// (the parser checks that; blocks made by hand are checked here, the
/// error at the block's second word).
pub fn control(block: &Block) -> Result<Option<&Item>, RunError> {
    match block.items.iter().position(Item::is_control) {
        None => Ok(None),
        Some(_) if block.items.len() == 1 => Ok(block.items.first()),
        Some(_) => Err(RunError {
            location: Some(Location {
                line: block.line,
                block_number: block.number,
                column: block.column(1),
            }),
            kind: RunErrorKind::ControlNotAlone,
        }),
    }
}

pub(super) const END_WHILE: RunErrorKind = RunErrorKind::Unpaired {
    end: "$ENDWHILE",
    start: "$WHILE",
};

pub(super) const END_FOR: RunErrorKind = RunErrorKind::Unpaired {
    end: "$ENDFOR",
    start: "$FOR",
};

/// An open loop: where it starts, and how it goes on.
#[derive(Debug, Clone)]
pub(super) struct Loop {
    /// The block of its `$FOR` or `$WHILE`.
    pub(super) start: usize,
    pub(super) kind: LoopKind,
}

/// What kind of loop, and how a `$FOR` counts.
#[derive(Debug, Clone)]
pub(super) enum LoopKind {
    /// A `$FOR` loop: its counter, last value and step.
    For { var: Var, last: f64, step: f64 },
    /// A `$WHILE` loop.
    While,
}

/// Where the run goes after a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Next {
    /// The following block.
    On,
    /// Back to a held block.
    Back(usize),
    /// Forward past the end of a structure.
    Skip(SkipTo),
}

/// Whether a `$FOR` counter at `v` still runs towards `end` by `step`.
pub(super) fn in_range(v: f64, end: f64, step: f64) -> bool {
    // A tolerance of a millionth of the step, so that decimal steps reach
    // their end.
    let slack = step.abs() * 1e-6;
    if step > 0.0 {
        v <= end + slack
    } else {
        v >= end - slack
    }
}
