//! The machine's axes (docs/objects.md, device 4; docs/trace-format.md): 8 axes, index
//! 0..7, named `X Y Z A B C U V` in traces and NC programs.

/// Number of machine axes.
pub const AXES: usize = 8;

/// Trace names of the machine axes, by index.
pub const AXIS_NAMES: [char; AXES] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V'];

/// A position of all machine axes.
pub type AxisPos = [f64; AXES];

/// Axis words of a command: `Some(v)` for each named machine axis.
pub type AxisWords = [Option<f64>; AXES];

/// The machine axis index of an axis letter (case-insensitive).
pub fn axis_index(letter: char) -> Option<usize> {
    let up = letter.to_ascii_uppercase();
    AXIS_NAMES.iter().position(|&n| n == up)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letters() {
        assert_eq!(axis_index('x'), Some(0));
        assert_eq!(axis_index('V'), Some(7));
        assert_eq!(axis_index('W'), None);
    }
}
