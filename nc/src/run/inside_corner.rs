//! `G238`: the correction selected at an inside corner of a closed
//! contour (docs/nc.md, "Selection and deselection"). The selection block
//! (a line from P1, where the tool stands, to P2), the contour B1 .. Bn
//! (Bn ending at P2) and every other request of those blocks are held in
//! order up to `G40`, checked there, and held on until the departure (the
//! next motion) shows it is a line: nothing of the contour is spooled
//! before every check has passed. Then the controller is driven so that
//! it spools a line from P1 to the cut point C of the offset geometries of
//! Bn and B1, B1 corrected from C, the corners B1 → B2 .. Bn-1 → Bn as
//! usual, and Bn corrected to C (decision 355):
//!
//! 1. Bn a line: the correction started at P1, Bn entered once more as
//!    the approach (after a profile dropped by ReInit makes Bn's start the
//!    end of the last profile): its corner with B1 cuts it at C, so the
//!    tool goes from P1 straight to C. Bn an arc (B1 a line): the tool
//!    goes to C uncorrected, and B1 enters as the approach from there;
//! 2. the contour's requests as read;
//! 3. B1 once more: its corner with Bn cuts Bn at C; the copy of B1 the
//!    controller then holds is dropped by ReInit, so nothing of it is
//!    spooled, and the correction ends with nothing held.

use tc_request::{Motion, Request};
use uoi::Value;

use super::plane::{self, Seg, CLOSURE_TOL};
use super::trc_state::{Contour, Read, Side, MAX_CONTOUR_BLOCKS};
use super::{objects, At, Interpreter, RunErrorKind};

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
    pub const DEPARTURE_ARC: &str = "the departure after G40 must be a line";
    pub const NO_CUT: &str = "the offset geometries of the last and first block do not meet";
}

/// `m` at the modal feed.
fn without_feed(m: Motion) -> Motion {
    match m {
        Motion::Lin { words, .. } => Motion::Lin { words, feed: None },
        Motion::Rap { words, .. } => Motion::Rap { words, feed: None },
        Motion::Cir {
            dir, words, centre, ..
        } => Motion::Cir {
            dir,
            words,
            centre,
            feed: None,
        },
        other => other,
    }
}

/// The block a read motion came from, as requests name it.
fn block_of(read: &Read) -> At {
    read.at.map_or(At::default(), |l| At {
        line: l.line,
        number: l.block_number,
    })
}

impl Interpreter<'_> {
    /// A motion while a `G238` contour is read: held, not sent. After its
    /// `G40` the motion is the departure: a line, and the contour runs.
    pub(super) fn contour_motion(
        &mut self,
        motion: Motion,
        seg: Option<Seg>,
    ) -> Result<Option<Motion>, RunErrorKind> {
        let at = self.location();
        let Some(contour) = self.sel.contour.as_mut() else {
            return Ok(Some(motion));
        };
        let is_arc = matches!(motion, Motion::Cir { .. });
        if contour.closed.is_some() {
            if is_arc {
                return Err(RunErrorKind::InsideCorner(why::DEPARTURE_ARC));
            }
            self.flush_contour()?;
            return Ok(Some(motion));
        }
        let read = Read {
            request: Request::Motion(motion),
            seg,
            at,
        };
        if contour.selection.is_none() {
            if is_arc {
                return Err(RunErrorKind::InsideCorner(why::SELECTION_ARC));
            }
            contour.selection = Some(read);
        } else if contour.items.len() >= MAX_CONTOUR_BLOCKS {
            return Err(RunErrorKind::InsideCorner(why::TOO_LONG));
        } else {
            contour.items.push(read);
        }
        Ok(None)
    }

    /// Whether `req` is held by a `G238` contour (kept in order, sent when
    /// the contour runs): every request but reads while one is read or
    /// waits for its departure.
    pub(super) fn held(&mut self, req: &Request) -> Result<bool, RunErrorKind> {
        let at = self.location();
        let Some(contour) = self.sel.contour.as_mut() else {
            return Ok(false);
        };
        if matches!(req, Request::Read(..) | Request::Pos | Request::Queue) {
            return Ok(false);
        }
        if contour.items.len() + contour.after.len() >= 2 * MAX_CONTOUR_BLOCKS {
            return Err(RunErrorKind::InsideCorner(why::TOO_LONG));
        }
        let read = Read {
            request: req.clone(),
            seg: None,
            at,
        };
        match contour.closed {
            Some(_) => contour.after.push(read),
            None => contour.items.push(read),
        }
        Ok(true)
    }

    /// `G40` of a `G238` contour: checked whole; it runs when its
    /// departure comes (or at the end).
    pub(super) fn close_contour(&mut self) -> Result<(), RunErrorKind> {
        let Some(contour) = self.sel.contour.take() else {
            return Ok(());
        };
        let d = self.offset_for(contour.side)?;
        let c = self.check_contour(&contour, d)?;
        self.sel.contour = Some(Contour {
            closed: Some(c),
            ..contour
        });
        Ok(())
    }

    /// The plane parts of the contour's motions, with their places.
    fn contour_segs(contour: &Contour) -> Vec<(Seg, usize)> {
        contour
            .items
            .iter()
            .enumerate()
            .filter_map(|(k, r)| r.seg.filter(Seg::has_length).map(|s| (s, k)))
            .collect()
    }

    /// Every check of a contour before it runs; its cut point C. An error
    /// names its block.
    fn check_contour(&mut self, contour: &Contour, d: f64) -> Result<plane::P2, RunErrorKind> {
        let segs = Self::contour_segs(contour);
        let (Some(selection), Some(&(b1, k1)), Some(&(bn, kn))) =
            (contour.selection.as_ref(), segs.first(), segs.last())
        else {
            return Err(RunErrorKind::InsideCorner(why::NO_CONTOUR));
        };
        let sel = selection.seg.unwrap_or(Seg::Line {
            s: b1.start(),
            e: b1.start(),
        });
        let (p1, p2) = (sel.start(), sel.end());
        let at_bn = &contour.items[kn];
        if bn.is_full_circle() {
            return Err(self.blame(at_bn, why::FULL_CIRCLE));
        }
        if plane::dist(bn.end(), p2) > CLOSURE_TOL {
            return Err(self.blame(at_bn, why::NOT_CLOSED));
        }
        if matches!((b1, bn), (Seg::Arc { .. }, Seg::Arc { .. })) {
            return Err(self.blame(&contour.items[k1], why::FIRST_ARC));
        }
        let side = contour.side.sign();
        if !plane::is_inside_corner(&bn, &b1, d, side) {
            return Err(self.blame(at_bn, why::NOT_INSIDE));
        }
        if segs
            .iter()
            .any(|(seg, _)| seg.distance_to(p1) < d.abs() - plane::RADIUS_SLACK)
        {
            return Err(self.blame(selection, why::TOO_NEAR));
        }
        let inner = &segs[1..segs.len() - 1];
        let crosses = inner.iter().any(|(seg, _)| {
            let hits = seg.meets_line(p1, p2);
            hits.iter().any(|h| plane::dist(*h, p2) > CLOSURE_TOL)
        });
        if crosses {
            return Err(self.blame(selection, why::CROSSES));
        }
        plane::cut_point(&bn, &b1, d, p2).ok_or_else(|| self.blame(at_bn, why::NO_CUT))
    }

    /// The error `what`, placed at the block of `read`.
    fn blame(&mut self, read: &Read, what: &'static str) -> RunErrorKind {
        self.at = block_of(read);
        self.pinned = read.at;
        RunErrorKind::InsideCorner(what)
    }

    /// A checked contour spooled through the controller (the module's
    /// doc), then the requests held after its `G40`.
    pub(super) fn flush_contour(&mut self) -> Result<(), RunErrorKind> {
        let Some(contour) = self.sel.contour.take() else {
            return Ok(());
        };
        let segs = Self::contour_segs(&contour);
        let Contour {
            side,
            selection,
            items,
            closed,
            after,
        } = contour;
        let (Some(c), Some(selection), Some(&(_, k1))) = (closed, selection, segs.first()) else {
            return Ok(());
        };
        let here = (self.at, self.pinned);
        self.enter_contour(side, selection, c, &segs)?;
        let copy = items[k1].request.clone();
        for read in items {
            self.send_read(read)?;
        }
        // B1 once more: its corner with Bn cuts Bn at C; then dropped.
        if let Request::Motion(m) = copy {
            self.send(&Request::Motion(without_feed(m)))?;
        }
        self.write(objects::RE_INIT, Value::I32(1))?;
        self.write(objects::STATUS, Value::I32(0))?;
        self.trc = None;
        self.check_fault()?;
        for read in after {
            self.send_read(read)?;
        }
        (self.at, self.pinned) = here;
        Ok(())
    }

    /// A held request sent, at its block.
    fn send_read(&mut self, read: Read) -> Result<(), RunErrorKind> {
        self.at = block_of(&read);
        self.pinned = read.at;
        match read.request {
            Request::Motion(m) => self.send_motion(&m, read.seg.filter(Seg::has_length)),
            other => self.send(&other),
        }
    }

    /// Step 1 of the module's doc: the tool to C, the correction started,
    /// the next profile B1 from C.
    fn enter_contour(
        &mut self,
        side: Side,
        selection: Read,
        c: plane::P2,
        segs: &[(Seg, usize)],
    ) -> Result<(), RunErrorKind> {
        let (b1, bn) = (segs[0].0, segs[segs.len() - 1].0);
        self.at = block_of(&selection);
        self.pinned = selection.at;
        let p2 = b1.start();
        let Request::Motion(approach) = selection.request else {
            return Ok(());
        };
        match bn {
            Seg::Line { s, .. } => {
                // Bn once more as the approach: its corner with B1 cuts
                // it at C, so the tool goes from P1 straight to C.
                self.start_trc(side)?;
                if selection
                    .seg
                    .is_some_and(|sel| plane::dist(s, sel.start()) > 0.0)
                {
                    self.lead_in_from(s)?;
                }
                self.send(&Request::Motion(approach))
            }
            Seg::Arc { .. } => {
                // B1 is a line: the tool goes to C uncorrected, and B1
                // enters as the approach from there.
                let mut to_c = approach;
                self.set_plane(&mut to_c, c);
                self.send(&Request::Motion(to_c))?;
                self.start_trc(side)?;
                if plane::dist(c, p2) > 0.0 {
                    self.lead_in_from(p2)?;
                }
                Ok(())
            }
        }
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
