//! Control flow: `$FOR`, `$WHILE`, `$IF`, `$ELSE` and their ends, on a
//! program pulled block by block. A loop is kept on a stack with the block
//! it jumps back to; a condition that is false skips forward.

use crate::model::Item;
use crate::Var;

use super::eval;
use super::structure::{in_range, Loop, LoopKind, Next, END_FOR, END_WHILE};
use super::window::SkipTo;
use super::{Interpreter, RunErrorKind};

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
