//! Control flow of a program held as a block list: where each `$FOR`,
//! `$IF`, `$ELSE`, `$WHILE` jumps to.

use std::collections::HashMap;

use crate::error::NcError;
use crate::model::{Block, Item};

/// For each control block, the index of the block its structure jumps to.
#[derive(Debug, Default)]
pub struct Jumps {
    /// `$FOR` → its `$ENDFOR`, and `$ENDFOR` → its `$FOR`.
    pub for_pair: HashMap<usize, usize>,
    /// `$WHILE` → its `$ENDWHILE`, and back.
    pub while_pair: HashMap<usize, usize>,
    /// `$IF` → its `$ELSE` (or `$ENDIF`), `$ELSE` → its `$ENDIF`.
    pub if_next: HashMap<usize, usize>,
}

/// The control statement of a block, if it holds one; it must stand alone.
pub fn control(block: &Block) -> Result<Option<&Item>, NcError> {
    let is_control = |i: &Item| {
        matches!(
            i,
            Item::For { .. }
                | Item::EndFor
                | Item::If(_)
                | Item::Else
                | Item::EndIf
                | Item::While(_)
                | Item::EndWhile
        )
    };
    match block.items.iter().find(|i| is_control(i)) {
        None => Ok(None),
        Some(item) if block.items.len() == 1 => Ok(Some(item)),
        Some(_) => Err(NcError {
            line: block.line,
            block_number: block.number,
            column: 1,
            message: "a $ control statement must stand alone in its block".into(),
        }),
    }
}

/// Pairs up the control statements of `blocks` (the parser checked that
/// they nest).
pub fn jumps(blocks: &[Block]) -> Result<Jumps, NcError> {
    let mut j = Jumps::default();
    let mut open: Vec<usize> = Vec::new();
    for (k, block) in blocks.iter().enumerate() {
        let unpaired = || NcError {
            line: block.line,
            block_number: block.number,
            column: 1,
            message: "control statement without its opening statement".into(),
        };
        match control(block)? {
            Some(Item::For { .. } | Item::If(_) | Item::While(_)) => open.push(k),
            Some(Item::Else) => {
                let at = open.pop().ok_or_else(unpaired)?;
                j.if_next.insert(at, k);
                open.push(k);
            }
            Some(Item::EndFor) => pair(&mut j.for_pair, open.pop().ok_or_else(unpaired)?, k),
            Some(Item::EndWhile) => pair(&mut j.while_pair, open.pop().ok_or_else(unpaired)?, k),
            Some(Item::EndIf) => {
                j.if_next.insert(open.pop().ok_or_else(unpaired)?, k);
            }
            _ => {}
        }
    }
    Ok(j)
}

fn pair(map: &mut HashMap<usize, usize>, a: usize, b: usize) {
    map.insert(a, b);
    map.insert(b, a);
}
