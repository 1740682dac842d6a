//! `G238`: the correction selected at an inside corner of a closed
//! contour (docs/nc.md, "G238"). The selection block (a line from P1,
//! where the tool stands, to P2) and the contour B1 .. Bn (Bn ending at
//! P2) are read whole up to `G40` and checked before anything of them is
//! spooled. Then the controller is driven so that it spools: a line from
//! P1 to the cut point C of the offset geometries of Bn and B1, B1
//! corrected from C, the corners B1 → B2 .. Bn-1 → Bn as usual, and Bn
//! corrected to C:
//!
//! 1. the line P1 → C, uncorrected;
//! 2. the correction started; B1 enters as the controller's approach, a
//!    line from where the tool stands (C) to B1's corrected end, which is
//!    B1's offset line from C;
//! 3. B2 .. Bn as programmed;
//! 4. B1 once more: its corner with Bn cuts Bn at C; the copy of B1 the
//!    controller then holds is dropped by ReInit, so nothing of it is
//!    spooled, and the correction ends with nothing held.

use tc_request::{Motion, Request};
use uoi::Value;

use super::plane::{self, Seg, CLOSURE_TOL};
use super::trc_state::{Read, Side, MAX_CONTOUR_BLOCKS};
use super::{objects, At, Interpreter, RunErrorKind};
use crate::error::Location;

/// Error text of each check, by the block it names.
mod why {
    pub const SELECTION_ARC: &str = "the selection block must be a line";
    pub const NO_CONTOUR: &str = "no contour between the selection block and G40";
    pub const NOT_CLOSED: &str =
        "the last contour block must end where the selection block ends (P2)";
    pub const FULL_CIRCLE: &str = "the last contour block must not be a full circle";
    pub const FIRST_ARC: &str =
        "the first or the last contour block must be a line here (docs/decisions.md)";
    pub const NOT_INSIDE: &str =
        "the corner between the last and the first contour block is not an inside corner";
    pub const TOO_NEAR: &str = "the selection point P1 is nearer than the radius to the contour";
    pub const CROSSES: &str = "the selection block crosses or touches the contour";
    pub const TOO_LONG: &str = "the contour has more than 100000 blocks";
    pub const NO_CUT: &str = "the offset geometries of the last and first block do not meet";
}

/// The block a read motion came from, as requests name it.
fn block_of(read: &Read) -> At {
    read.at.map_or(At::default(), |l| At {
        line: l.line,
        number: l.block_number,
    })
}

impl Interpreter<'_> {
    /// A motion while a `G238` contour is read: kept, not sent.
    pub(super) fn contour_motion(
        &mut self,
        motion: Motion,
        seg: Option<Seg>,
        at: Option<Location>,
    ) -> Result<(), RunErrorKind> {
        let read = Read { motion, seg, at };
        let Some(contour) = self.sel.contour.as_mut() else {
            return Ok(());
        };
        if contour.selection.is_none() {
            if matches!(read.motion, Motion::Cir { .. }) {
                return Err(RunErrorKind::InsideCorner(why::SELECTION_ARC));
            }
            contour.selection = Some(read);
            return Ok(());
        }
        if contour.motions.len() >= MAX_CONTOUR_BLOCKS {
            return Err(RunErrorKind::InsideCorner(why::TOO_LONG));
        }
        contour.motions.push(read);
        Ok(())
    }

    /// `G40` of a `G238` contour: checked whole, then run.
    pub(super) fn run_contour(&mut self) -> Result<(), RunErrorKind> {
        let Some(contour) = self.sel.contour.take() else {
            return Ok(());
        };
        let Some(selection) = contour.selection else {
            return Err(RunErrorKind::InsideCorner(why::NO_CONTOUR));
        };
        let segs: Vec<(Seg, usize)> = contour
            .motions
            .iter()
            .enumerate()
            .filter_map(|(k, r)| r.seg.filter(Seg::has_length).map(|s| (s, k)))
            .collect();
        let (Some(&(b1, _)), Some(&(bn, _))) = (segs.first(), segs.last()) else {
            return Err(RunErrorKind::InsideCorner(why::NO_CONTOUR));
        };
        let d = self.offset_for(contour.side)?;
        let c = self.check_contour(&contour.motions, &selection, &segs, d)?;
        self.spool_contour(contour.side, selection, contour.motions, c, (&b1, &bn))
    }

    /// Every check of a contour before it runs; its cut point C. An error
    /// names its block (`self.at` moved there).
    fn check_contour(
        &mut self,
        motions: &[Read],
        selection: &Read,
        segs: &[(Seg, usize)],
        d: f64,
    ) -> Result<plane::P2, RunErrorKind> {
        let (b1, k1) = segs[0];
        let (bn, kn) = segs[segs.len() - 1];
        let sel = selection.seg.unwrap_or(Seg::Line {
            s: b1.start(),
            e: b1.start(),
        });
        let p2 = sel.end();
        let at_bn = &motions[kn];
        if bn.is_full_circle() {
            return Err(self.blame(at_bn, why::FULL_CIRCLE));
        }
        if plane::dist(bn.end(), p2) > CLOSURE_TOL {
            return Err(self.blame(at_bn, why::NOT_CLOSED));
        }
        if matches!((b1, bn), (Seg::Arc { .. }, Seg::Arc { .. })) {
            return Err(self.blame(&motions[k1], why::FIRST_ARC));
        }
        if !plane::is_inside_corner(&bn, &b1, d) {
            return Err(self.blame(at_bn, why::NOT_INSIDE));
        }
        let p1 = sel.start();
        for (seg, _) in segs {
            if seg.distance_to(p1) < d.abs() - plane::RADIUS_SLACK {
                return Err(self.blame(selection, why::TOO_NEAR));
            }
        }
        let inner = &segs[1..segs.len() - 1];
        for (seg, _) in inner {
            let hits = seg.meets_line(p1, p2);
            if hits.iter().any(|h| plane::dist(*h, p2) > CLOSURE_TOL) {
                return Err(self.blame(selection, why::CROSSES));
            }
        }
        match plane::cut_point(&bn, &b1, d, p2) {
            Some(c) => Ok(c),
            None => Err(self.blame(at_bn, why::NO_CUT)),
        }
    }

    /// The error `what`, placed at the block of `read`.
    fn blame(&mut self, read: &Read, what: &'static str) -> RunErrorKind {
        self.at = block_of(read);
        self.pinned = read.at;
        RunErrorKind::InsideCorner(what)
    }

    /// Spools a checked contour through the controller (the module's doc).
    fn spool_contour(
        &mut self,
        side: Side,
        selection: Read,
        motions: Vec<Read>,
        c: plane::P2,
        ends: (&Seg, &Seg),
    ) -> Result<(), RunErrorKind> {
        let (b1, bn) = ends;
        let here = self.at;
        self.at = block_of(&selection);
        self.pinned = selection.at;
        let p2 = b1.start();
        match bn {
            Seg::Line { s, .. } => {
                // Bn once more as the approach: its corner with B1 cuts
                // it at C, so the tool goes from P1 straight to C.
                self.start_trc(side)?;
                if plane::dist(*s, self.tool_plane_end(&selection)) > 0.0 {
                    self.lead_in_from(*s)?;
                }
                let mut copy = selection.motion;
                self.set_plane(&mut copy, p2);
                self.send(&Request::Motion(copy))?;
            }
            Seg::Arc { .. } => {
                // B1 is a line: the tool goes to C uncorrected, and B1
                // enters as the approach from there.
                let mut to_c = selection.motion;
                self.set_plane(&mut to_c, c);
                self.send(&Request::Motion(to_c))?;
                self.start_trc(side)?;
                if plane::dist(c, p2) > 0.0 {
                    self.lead_in_from(p2)?;
                }
            }
        }
        for read in motions {
            self.at = block_of(&read);
            self.pinned = read.at;
            self.send_motion(&read.motion, read.seg.filter(Seg::has_length))?;
        }
        // B1 once more: its corner with Bn cuts Bn at C; then dropped.
        self.plane_line(b1.end())?;
        self.write(objects::RE_INIT, Value::I32(1))?;
        self.at = here;
        self.pinned = None;
        self.write(objects::STATUS, Value::I32(0))?;
        self.trc = None;
        self.sel.departure = true;
        self.check_fault()
    }

    /// Where the selection block starts in the plane (P1).
    fn tool_plane_end(&self, selection: &Read) -> plane::P2 {
        selection.seg.map_or([f64::NAN; 2], |s| s.start())
    }

    /// A line's plane words set to `p`.
    fn set_plane(&self, motion: &mut Motion, p: plane::P2) {
        let (h, v) = plane::plane_axes(self.plane);
        if let Motion::Lin { words, .. } | Motion::Rap { words, .. } = motion {
            words[h] = Some(p[0]);
            words[v] = Some(p[1]);
        }
    }
}
