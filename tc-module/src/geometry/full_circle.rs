//! Programmed full circles (decisions 48, 76 and 77: a programmed full
//! circle keeps its whole turn). Which corrected full circles keep
//! their whole turn, and where such a turn ends so that the element
//! spooled from its start to its end is read as a whole turn, never as a
//! sliver.

use super::offset::{Offset, OffsetPath};
use super::tolerance::FULL_CIRCLE;
use super::vector::{cross, V2};

/// The angle (radians, in (-π, π]) from the offset start of the arc
/// `off` to the point `x`, about its centre and positive in its
/// direction of travel; 0 for a line.
pub fn start_shift(off: &Offset, x: V2) -> f64 {
    let OffsetPath::Arc { centre, sigma, .. } = off.path else {
        return 0.0;
    };
    let (a, b) = (off.start - centre, x - centre);
    sigma * cross(a, b).atan2(a.dot(&b))
}

/// Whether a programmed full circle whose corrected element starts at
/// `shift` radians from its offset start ([`start_shift`]) keeps its
/// whole turn: within [`FULL_CIRCLE`] of it, as the rule says; and, when
/// it continues from the previous element's end (corner case 1), also
/// from any point before it, where the turn from there to its offset end
/// is more than whole.
pub fn keeps_whole_turn(shift: f64, continued: bool) -> bool {
    shift.abs() <= FULL_CIRCLE.rad() || (continued && shift < 0.0)
}

/// Where a whole-turn circle of offset `off`, spooled from `from` (its
/// corrected start, `shift` radians from the offset start), ends when
/// its corner asks for `x`. A point at most the overlap `max(-shift, 0)`
/// plus [`FULL_CIRCLE`] past `from` lies at (or beyond) the end of the
/// whole turn: the turn ends exactly on `from`, one turn, as an element
/// from `from` to a point just past it would be read as a sliver.
/// Elsewhere `x` itself.
pub fn whole_turn_end(off: &Offset, from: V2, shift: f64, x: V2) -> V2 {
    let OffsetPath::Arc { centre, sigma, .. } = off.path else {
        return x;
    };
    let (a, b) = (from - centre, x - centre);
    let past = sigma * cross(a, b).atan2(a.dot(&b));
    let overlap = (-shift).max(0.0) + FULL_CIRCLE.rad();
    if (0.0..=overlap).contains(&past) {
        from
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Contour;

    fn v(x: f64, y: f64) -> V2 {
        V2::new(x, y)
    }

    fn at(angle: f64) -> V2 {
        v(angle.cos(), angle.sin())
    }

    /// A full circle about the origin, radius 10, starting at angle 0,
    /// offset outward to radius 12.
    fn circle(sigma: f64) -> Offset {
        let p = v(10.0, 0.0);
        let c = Contour::Arc {
            from: p,
            to: p,
            centre: v(0.0, 0.0),
            sigma,
        };
        c.offset(-2.0 * sigma).unwrap()
    }

    #[test]
    fn shift_is_signed_in_the_direction_of_travel() {
        for sigma in [1.0, -1.0] {
            let off = circle(sigma);
            assert_eq!(start_shift(&off, off.start), 0.0);
            let ahead = at(sigma * 0.25) * 12.0;
            assert!((start_shift(&off, ahead) - 0.25).abs() < 1e-15);
            let behind = at(-sigma * 1e-5) * 12.0;
            assert!((start_shift(&off, behind) + 1e-5).abs() < 1e-15);
        }
    }

    #[test]
    fn whole_turn_within_the_tolerance_or_continued_from_before() {
        let tol = FULL_CIRCLE.rad();
        for continued in [false, true] {
            assert!(keeps_whole_turn(0.0, continued));
            assert!(keeps_whole_turn(tol, continued));
            assert!(keeps_whole_turn(-tol, continued));
            assert!(!keeps_whole_turn(2.0 * tol, continued));
        }
        // Continued from a point before the offset start: more than a turn.
        assert!(keeps_whole_turn(-1e-5, true));
        assert!(!keeps_whole_turn(-1e-5, false));
    }

    #[test]
    fn a_turn_that_would_end_just_past_its_start_ends_on_it() {
        for sigma in [1.0, -1.0] {
            let off = circle(sigma);
            let from = at(-sigma * 1e-5) * 12.0; // 1e-5 rad before the start
            let shift = start_shift(&off, from);
            // The offset end lies 1e-5 past `from`: one turn, on `from`.
            assert_eq!(whole_turn_end(&off, from, shift, off.end), from);
            // Just beyond the overlap and the tolerance: x itself.
            let beyond = at(sigma * 2e-7) * 12.0;
            assert_eq!(whole_turn_end(&off, from, shift, beyond), beyond);
            // A cut before the end is kept.
            let cut = at(-sigma * 0.3) * 12.0;
            assert_eq!(whole_turn_end(&off, from, shift, cut), cut);
            // Started on the offset start: a rounding step past it is the end.
            let past = at(sigma * 1e-12) * 12.0;
            assert_eq!(whole_turn_end(&off, off.start, 0.0, past), off.start);
            assert_eq!(whole_turn_end(&off, off.start, 0.0, off.end), off.start);
        }
    }

    #[test]
    fn lines_are_left_alone() {
        let l = Contour::Line {
            from: v(0.0, 0.0),
            to: v(1.0, 0.0),
        };
        let off = l.offset(1.0).unwrap();
        assert_eq!(start_shift(&off, v(5.0, 5.0)), 0.0);
        assert_eq!(whole_turn_end(&off, off.start, 0.0, off.start), off.start);
    }
}
