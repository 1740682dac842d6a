//! Where in a program, and the one error type of the parser.

use std::fmt;

/// A place in an NC program: line, the block's `N` number, column.
///
/// `line` and `column` count from 1 (columns in characters, not bytes);
/// `block_number` is the block's `N` word when it had one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    /// Line of the program, from 1.
    pub line: usize,
    /// The block's `N` number, if the block had one.
    pub block_number: Option<u32>,
    /// Column, from 1, in characters.
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}", self.line)?;
        if let Some(n) = self.block_number {
            write!(f, ", block N{n}")?;
        }
        write!(f, ", column {}", self.column)
    }
}

/// An unknown or malformed piece of an NC program.
///
/// `line` and `column` count from 1 (columns in characters, not bytes);
/// `block_number` is the block's `N` word when it had one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NcError {
    /// Line of the program, from 1.
    pub line: usize,
    /// The block's `N` number, if the block had one before the error.
    pub block_number: Option<u32>,
    /// Column of the offending word, from 1, in characters.
    pub column: usize,
    /// What is wrong, for a person.
    pub message: String,
}

impl NcError {
    /// Where the error stands.
    pub fn location(&self) -> Location {
        Location {
            line: self.line,
            block_number: self.block_number,
            column: self.column,
        }
    }
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location(), self.message)
    }
}

impl std::error::Error for NcError {}
