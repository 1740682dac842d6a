//! The D table of tool data: 255 data sets (D1..D255) of 16 columns,
//! written and read by `#set ToolParam` / `#get ToolParam`.

use super::RunErrorKind;

/// Data sets of the table.
pub const SETS: usize = 255;
/// Columns of a data set.
pub const COLUMNS: usize = 16;
/// Column: geometry, length.
pub const LENGTH: usize = 2;
/// Column: geometry, radius.
pub const RADIUS: usize = 4;
/// Column: wear, length (added to the length).
pub const LENGTH_WEAR: usize = 5;
/// Column: wear, radius (added to the radius).
pub const RADIUS_WEAR: usize = 7;

/// The program's D table; a data set counts as given once a column of it
/// was written.
#[derive(Debug, Clone)]
pub struct DTable {
    values: Vec<[f64; COLUMNS]>,
    given: Vec<bool>,
}

impl Default for DTable {
    fn default() -> Self {
        DTable {
            values: vec![[0.0; COLUMNS]; SETS],
            given: vec![false; SETS],
        }
    }
}

/// Row and column indices of `line` (1..255) and `column` (0..15).
fn cell(line: f64, column: f64) -> Result<(usize, usize), RunErrorKind> {
    if line.fract() != 0.0 || !(1.0..=SETS as f64).contains(&line) {
        return Err(RunErrorKind::ToolParamLine { line });
    }
    if column.fract() != 0.0 || !(0.0..COLUMNS as f64).contains(&column) {
        return Err(RunErrorKind::ToolParamColumn { column });
    }
    // Both checked to be small whole numbers above.
    Ok((line as usize - 1, column as usize))
}

impl DTable {
    /// `#set ToolParam(line; column; value)`.
    pub fn set(&mut self, line: f64, column: f64, value: f64) -> Result<(), RunErrorKind> {
        let (l, c) = cell(line, column)?;
        self.values[l][c] = value;
        self.given[l] = true;
        Ok(())
    }

    /// `#get ToolParam(line; column; ..)`.
    pub fn get(&self, line: f64, column: f64) -> Result<f64, RunErrorKind> {
        let (l, c) = cell(line, column)?;
        Ok(self.values[l][c])
    }

    /// Radius (geometry + wear) and length (geometry + wear) of data set
    /// `d` (1..255), if the program gave it values.
    pub fn tool(&self, d: u32) -> Option<(f64, f64)> {
        let row = usize::try_from(d).ok()?.checked_sub(1)?;
        if !*self.given.get(row)? {
            return None;
        }
        let v = &self.values[row];
        Some((v[RADIUS] + v[RADIUS_WEAR], v[LENGTH] + v[LENGTH_WEAR]))
    }
}
