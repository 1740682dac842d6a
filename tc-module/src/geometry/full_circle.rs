//! Programmed full circles (decisions 48, 76, 77 and 330: a programmed
//! full circle keeps its whole turn). Which corrected full circles keep
//! their whole turn, and where such a turn ends: an element spooled from
//! its start to its end is read as a whole turn, never as a sliver, and a
//! circle started before its offset start runs a whole turn and on to its
//! own end (docs/trc.md "Full circles").

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

/// How a whole-turn circle spooled from its corrected start `c` ends
/// (decisions 76, 77 and 330).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TurnEnd {
    /// One arc from `c` to this point: a whole turn when it is `c`
    /// itself.
    Arc(V2),
    /// A whole turn ending on `c`, then an arc from `c` on to this point.
    TurnThen(V2),
}

/// Where a whole-turn circle of offset `off`, spooled from `from` (its
/// corrected start `c`, `shift` radians from the offset start), ends when
/// its corner asks for `x` (the offset end, or an inside corner's cut
/// point). An end at most [`FULL_CIRCLE`] past `c` is one turn ending on
/// `c`; one past it by at most the overlap `max(-shift, 0)` plus
/// [`FULL_CIRCLE`] lies beyond a whole turn: the turn ends on `c` and an
/// arc runs on to `x` (an element from `c` to a point just past it would
/// read as a sliver). Any other end is one arc from `c` to `x`.
pub fn whole_turn_end(off: &Offset, from: V2, shift: f64, x: V2) -> TurnEnd {
    let OffsetPath::Arc { centre, sigma, .. } = off.path else {
        return TurnEnd::Arc(x);
    };
    let (a, b) = (from - centre, x - centre);
    let past = sigma * cross(a, b).atan2(a.dot(&b));
    let tol = FULL_CIRCLE.rad();
    if (0.0..=tol).contains(&past) {
        TurnEnd::Arc(from)
    } else if past > tol && past <= (-shift).max(0.0) + tol {
        TurnEnd::TurnThen(x)
    } else {
        TurnEnd::Arc(x)
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
    fn a_turn_ends_on_its_start_then_runs_on_to_an_end_within_the_overlap() {
        for sigma in [1.0, -1.0] {
            let off = circle(sigma);
            let from = at(-sigma * 1e-5) * 12.0; // 1e-5 rad before the start
            let shift = start_shift(&off, from);
            // The offset end lies 1e-5 past `from`: a turn, then on to it.
            let end = whole_turn_end(&off, from, shift, off.end);
            assert_eq!(end, TurnEnd::TurnThen(off.end));
            // Within the tolerance past `from`: one turn, on `from`.
            let near = at(-sigma * (1e-5 - 5e-8)) * 12.0;
            assert_eq!(whole_turn_end(&off, from, shift, near), TurnEnd::Arc(from));
            // Just beyond the overlap and the tolerance: one arc to x.
            let beyond = at(sigma * 2e-7) * 12.0;
            assert_eq!(
                whole_turn_end(&off, from, shift, beyond),
                TurnEnd::Arc(beyond)
            );
            // A cut before the end is one arc, a turn less the rest.
            let cut = at(-sigma * 0.3) * 12.0;
            assert_eq!(whole_turn_end(&off, from, shift, cut), TurnEnd::Arc(cut));
            // Started on the offset start: a rounding step past it is the end.
            let past = at(sigma * 1e-12) * 12.0;
            let on = |x| whole_turn_end(&off, off.start, 0.0, x);
            assert_eq!(on(past), TurnEnd::Arc(off.start));
            assert_eq!(on(off.end), TurnEnd::Arc(off.start));
            // Not before the offset start: no overlap, nothing runs on.
            let ahead = at(sigma * 5e-8) * 12.0;
            assert_eq!(whole_turn_end(&off, ahead, 5e-8, past), TurnEnd::Arc(past));
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
        let end = whole_turn_end(&off, off.start, 0.0, off.start);
        assert_eq!(end, TurnEnd::Arc(off.start));
    }
}
