//! Control flow: `$FOR`, `$WHILE`, `$IF`, `$ELSE` and their ends, on a
//! program pulled block by block. A loop is kept on a stack with the block
//! it jumps back to; a condition that is false skips forward.

use crate::error::Location;
use crate::model::{Block, Item};
use crate::Var;

use super::eval;
use super::window::SkipTo;
use super::{Interpreter, RunError, RunErrorKind};

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

const END_WHILE: RunErrorKind = RunErrorKind::Unpaired {
    end: "$ENDWHILE",
    start: "$WHILE",
};

const END_FOR: RunErrorKind = RunErrorKind::Unpaired {
    end: "$ENDFOR",
    start: "$FOR",
};

/// An open loop: where it starts, and how it goes on.
#[derive(Debug, Clone)]
pub(super) struct Loop {
    /// The block of its `$FOR` or `$WHILE`.
    start: usize,
    kind: LoopKind,
}

#[derive(Debug, Clone)]
enum LoopKind {
    For { var: Var, last: f64, step: f64 },
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

impl Interpreter<'_> {
    /// Carries out the control statement of block `pc`.
    pub(super) fn flow(&mut self, item: &Item, pc: usize) -> Result<Next, RunErrorKind> {
        match item {
            Item::For {
                var,
                start,
                end,
                step,
            } => self.start_for(pc, var, start, end, step),
            Item::EndFor => self.end_for(),
            Item::While(c) => {
                let again = self.loops.last().is_some_and(|l| l.start == pc);
                if eval::eval(c, self)? != 0.0 {
                    if !again {
                        self.loops.push(Loop {
                            start: pc,
                            kind: LoopKind::While,
                        });
                    }
                    Ok(Next::On)
                } else {
                    if again {
                        self.loops.pop();
                    }
                    Ok(Next::Skip(SkipTo::EndWhile))
                }
            }
            Item::EndWhile => match self.loops.last() {
                Some(Loop {
                    start,
                    kind: LoopKind::While,
                }) => Ok(Next::Back(*start)),
                _ => Err(END_WHILE),
            },
            Item::If(c) => Ok(if eval::eval(c, self)? != 0.0 {
                Next::On
            } else {
                Next::Skip(SkipTo::ElseOrEndIf)
            }),
            Item::Else => Ok(Next::Skip(SkipTo::EndIf)),
            _ => Ok(Next::On),
        }
    }

    fn start_for(
        &mut self,
        pc: usize,
        var: &Var,
        start: &crate::Expr,
        end: &crate::Expr,
        step: &crate::Expr,
    ) -> Result<Next, RunErrorKind> {
        let first = eval::eval(start, self)?;
        let last = eval::eval(end, self)?;
        let step = eval::eval(step, self)?;
        if step == 0.0 {
            return Err(RunErrorKind::ForStepZero);
        }
        self.assign(var, first)?;
        if !in_range(first, last, step) {
            return Ok(Next::Skip(SkipTo::EndFor));
        }
        self.loops.push(Loop {
            start: pc,
            kind: LoopKind::For {
                var: var.clone(),
                last,
                step,
            },
        });
        Ok(Next::On)
    }

    /// `$ENDFOR`: the counter stepped, and back to the loop's first block
    /// while it is in range.
    fn end_for(&mut self) -> Result<Next, RunErrorKind> {
        let Some(open) = self.loops.pop() else {
            return Err(END_FOR);
        };
        let LoopKind::For { var, last, step } = &open.kind else {
            return Err(END_FOR);
        };
        let next = eval::Vars::read(self, var)? + step;
        self.assign(var, next)?;
        if in_range(next, *last, *step) {
            let back = open.start + 1;
            self.loops.push(open);
            Ok(Next::Back(back))
        } else {
            Ok(Next::On)
        }
    }

    /// Whether a loop is open (its blocks are held for jumping back).
    pub(super) fn in_loop(&self) -> bool {
        !self.loops.is_empty()
    }
}

/// Whether a `$FOR` counter at `v` still runs towards `end` by `step`.
fn in_range(v: f64, end: f64, step: f64) -> bool {
    // A tolerance of a millionth of the step, so that decimal steps reach
    // their end.
    let slack = step.abs() * 1e-6;
    if step > 0.0 {
        v <= end + slack
    } else {
        v >= end - slack
    }
}
