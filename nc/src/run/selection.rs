//! How the radius correction is selected and deselected in a program
//! (docs/nc.md, "Selection and deselection"): the modal group `G138`
//! `G139` `G236` `G237` `G238` `G239` and the one-block `G05`, on top of
//! the controller's own approach and departure. `G138` is the
//! controller's rule; `G139`, `G236` and `G05` run as `G138` with a
//! warning; `G237` inserts perpendicular elements; `G239` leaves the tool
//! on the equidistant; `G238` is in `inside_corner.rs`.
//!
//! Every motion that goes into a running correction is remembered with
//! its block, so that a fault of the correction names the block whose
//! profile raised it, also when it is found only at `G40` or at the end.

use tc_request::{AxisPos, AxisWords, Motion, Request};
use uoi::{Value, ValueType};

use super::plane::{self, Seg};
use super::trc_state::{Contour, SelMode, Side};
use super::{objects, Interpreter, RunErrorKind, WarningKind};

impl Interpreter<'_> {
    /// A mode word (`G138`..`G239`): in force from the next selection or
    /// deselection; `G238` only while no correction runs (ISG 21317).
    pub(super) fn set_mode(&mut self, mode: SelMode) -> Result<(), RunErrorKind> {
        let running = self.trc.is_some() || self.sel.pending.is_some() || self.contour_open();
        if mode == SelMode::InsideCorner && running {
            return Err(RunErrorKind::InsideCornerWhileRunning);
        }
        self.sel.mode = mode;
        Ok(())
    }

    /// `G05` in a block: whether it acts, with the block's mode word in
    /// force; ignored with a warning while `G238` is (ISG 21316).
    pub(super) fn tangential_acts(&mut self, col: usize) -> bool {
        if self.sel.mode == SelMode::InsideCorner {
            self.col = col;
            self.warn(WarningKind::TangentialIgnored);
            return false;
        }
        true
    }

    /// One warning per program for a mode run as `G138`.
    fn warn_runs_as_direct(&mut self, tangential: bool) {
        let word = if tangential {
            Some(("G05", 2))
        } else {
            self.sel.mode.runs_as_direct()
        };
        if let Some((word, k)) = word {
            if !self.sel.warned[k] {
                self.sel.warned[k] = true;
                self.warn(WarningKind::SelectionRule { word });
            }
        }
    }

    /// `G41`/`G42`.
    pub(super) fn select(&mut self, side: Side, tangential: bool) -> Result<(), RunErrorKind> {
        if self.contour_open() {
            return Err(RunErrorKind::InsideCorner(
                "a side programmed again while the contour runs",
            ));
        }
        // A G238 contour waiting for its departure runs first.
        self.flush_contour()?;
        self.sel.after_g239 = false;
        let running = self.trc.is_some() || self.sel.pending.is_some();
        if running && self.sel.mode == SelMode::Perpendicular {
            return Err(RunErrorKind::PerpendicularReselect);
        }
        if self.trc == Some(side) {
            return Ok(());
        }
        self.transition_initial()?;
        match self.sel.mode {
            SelMode::InsideCorner if !tangential => {
                self.sel.contour = Some(Contour::new(side));
                Ok(())
            }
            SelMode::Perpendicular if !tangential => {
                self.sel.pending = Some(side);
                Ok(())
            }
            _ => {
                self.warn_runs_as_direct(tangential);
                self.start_trc(side)
            }
        }
    }

    /// The controller's correction started on side `side` (a running one
    /// ended first).
    pub(super) fn start_trc(&mut self, side: Side) -> Result<(), RunErrorKind> {
        if self.trc.is_some() {
            self.write(objects::STATUS, Value::I32(0))?;
        }
        let addr = match side {
            Side::Left => objects::LEFT,
            Side::Right => objects::RIGHT,
        };
        self.write(addr, Value::I32(1))?;
        self.write(objects::STATUS, Value::I32(1))?;
        self.trc = Some(side);
        self.sel.last = None;
        self.sel.unchecked = true;
        Ok(())
    }

    /// ISG's initial transition is `G25` (linear): written before the first
    /// selection of a program that programmed neither `G25` nor `G26`.
    fn transition_initial(&mut self) -> Result<(), RunErrorKind> {
        if self.transition.is_none() {
            self.write(objects::TRANSITION_MODE, Value::I32(1))?;
            self.transition = Some(1);
        }
        Ok(())
    }

    /// `G40`.
    pub(super) fn deselect(&mut self, tangential: bool) -> Result<(), RunErrorKind> {
        if self.contour_open() {
            return self.close_contour();
        }
        if self.sel.pending.take().is_some() || self.trc.is_none() {
            return Ok(());
        }
        let held = self.sel.last;
        let d = match (self.trc, self.sel.bn_offset) {
            (_, Some(d)) => d,
            (Some(side), None) if self.sel.mode == SelMode::WithoutBlock => {
                self.offset_for(side)?
            }
            _ => 0.0,
        };
        self.write(objects::STATUS, Value::I32(0))?;
        self.trc = None;
        self.check_fault()?;
        let mode = if tangential {
            SelMode::Direct
        } else {
            self.sel.mode
        };
        match (mode, held) {
            (SelMode::Perpendicular, Some(bn)) => self.perpendicular_back(&bn),
            (SelMode::WithoutBlock, Some(bn)) => {
                let q = bn.offset_end(d);
                let (h, v) = plane::plane_axes(self.plane);
                self.pos[h] = q[0];
                self.pos[v] = q[1];
                self.sel.after_g239 = true;
                Ok(())
            }
            _ => {
                self.warn_runs_as_direct(tangential);
                Ok(())
            }
        }
    }

    /// `G237` deselection: from Bn's offset end straight back to its
    /// programmed end, moving only the plane axes.
    fn perpendicular_back(&mut self, bn: &Seg) -> Result<(), RunErrorKind> {
        self.plane_line(bn.end())
    }

    /// A line's words completed with the plane axes at the program's
    /// position.
    fn name_plane_axes(&self, motion: &mut Motion) {
        let (h, v) = plane::plane_axes(self.plane);
        if let Motion::Lin { words, .. } | Motion::Rap { words, .. } = motion {
            words[h].get_or_insert(self.pos[h]);
            words[v].get_or_insert(self.pos[v]);
        }
    }

    /// Words that name only the plane axes, at `p`.
    pub(super) fn plane_words(&self, p: plane::P2) -> AxisWords {
        let (h, v) = plane::plane_axes(self.plane);
        let mut words: AxisWords = [None; tc_request::AXES];
        words[h] = Some(p[0]);
        words[v] = Some(p[1]);
        words
    }

    /// The plane part of a motion from `start` to the end of `motion`.
    pub(super) fn seg_of(&self, motion: &Motion, start: &AxisPos) -> Option<Seg> {
        let (h, v) = plane::plane_axes(self.plane);
        let s = [start[h], start[v]];
        let e = [self.pos[h], self.pos[v]];
        match motion {
            Motion::Lin { .. } | Motion::Rap { .. } => Some(Seg::Line { s, e }),
            Motion::Cir { dir, centre, .. } => {
                let off = |axis: usize| match axis {
                    0..=2 => centre[axis].unwrap_or(0.0),
                    _ => 0.0,
                };
                let c = [s[0] + off(h), s[1] + off(v)];
                let ccw = *dir == tc_request::ArcDir::Ccw;
                Some(Seg::Arc { s, e, c, ccw })
            }
            _ => None,
        }
    }

    /// Carries out a motion from `start` (the position before it) with
    /// the selection modes: a `G238` contour is read, a pending `G237`
    /// selection is made, a running correction remembers it.
    pub(super) fn motion(&mut self, motion: Motion, start: AxisPos) -> Result<(), RunErrorKind> {
        let seg = self.seg_of(&motion, &start);
        let departure = self.sel.contour.is_some();
        let Some(mut motion) = self.contour_motion(motion, seg)? else {
            return Ok(());
        };
        let is_arc = matches!(motion, Motion::Cir { .. });
        let after_g239 = std::mem::take(&mut self.sel.after_g239);
        if after_g239 && is_arc {
            return Err(RunErrorKind::ArcAfterG239);
        }
        if after_g239 || departure {
            // The controller's last programmed end is not where the
            // program stands: name both plane axes.
            self.name_plane_axes(&mut motion);
        }
        let in_plane = seg.filter(Seg::has_length);
        if let (Some(side), Some(b1)) = (self.sel.pending, in_plane) {
            self.perpendicular_select(side, &b1, &motion)?;
        }
        self.send_motion(&motion, in_plane)
    }

    /// Sends a motion; into a running correction it is remembered (its
    /// block for a fault, its plane part as the held block).
    pub(super) fn send_motion(
        &mut self,
        motion: &Motion,
        in_plane: Option<Seg>,
    ) -> Result<(), RunErrorKind> {
        self.send(&Request::Motion(*motion))?;
        if self.trc.is_some() {
            // Answered: a fault found from now on is this profile's.
            self.sel.fault_at = self.location();
            if in_plane.is_some() {
                self.sel.last = in_plane;
                self.sel.bn_offset = None;
            }
        }
        Ok(())
    }

    /// `G237` selection before B1: a line from B1's programmed start S to
    /// its offset start S' (for an arc the controller's approach is that
    /// line), then the correction started with the tool at S' and B1
    /// starting at S.
    fn perpendicular_select(
        &mut self,
        side: Side,
        b1: &Seg,
        motion: &Motion,
    ) -> Result<(), RunErrorKind> {
        let (arc, feed) = match *motion {
            Motion::Cir { feed, .. } => (true, feed),
            Motion::Lin { feed, .. } | Motion::Rap { feed, .. } => (false, feed),
            _ => (false, None),
        };
        self.sel.pending = None;
        self.start_trc(side)?;
        if arc {
            return Ok(());
        }
        // A profile ending at S along B1's tangent, entered as an
        // approach and ended at once: the controller spools S -> S' and
        // keeps S as the end of the last profile.
        let s = b1.start();
        let t = b1.start_tangent();
        self.lead_in_from([s[0] - t[0], s[1] - t[1]])?;
        // At B1's feed: the inserted element keeps the block's F.
        let words = self.plane_words(s);
        self.send(&Request::Motion(Motion::Lin { words, feed }))?;
        self.write(objects::STATUS, Value::I32(0))?;
        self.write(objects::STATUS, Value::I32(1))
    }

    /// With the correction running and nothing held: the next profile
    /// starts at `from` (a profile there, dropped by ReInit, so nothing
    /// is spooled and the tool stays where it is).
    pub(super) fn lead_in_from(&mut self, from: plane::P2) -> Result<(), RunErrorKind> {
        self.plane_line(from)?;
        self.write(objects::RE_INIT, Value::I32(1))
    }

    /// A line to `p` naming only the plane axes, at the modal feed.
    pub(super) fn plane_line(&mut self, p: plane::P2) -> Result<(), RunErrorKind> {
        let words = self.plane_words(p);
        self.send(&Request::Motion(Motion::Lin { words, feed: None }))
    }

    /// The signed offset `d = s * radius` for side `side`, the radius read
    /// from the controller (a negative radius flips the side).
    pub(super) fn offset_for(&mut self, side: Side) -> Result<f64, RunErrorKind> {
        Ok(side.sign() * self.read_object(objects::RADIUS, ValueType::F64)?)
    }

    /// A radius change (`D`, `V.G.WZ_AKT.R`): refused while a `G238`
    /// contour is read; while a correction runs, the offset the held block
    /// Bn was corrected with is kept for a `G239` deselection.
    pub(super) fn radius_change(&mut self) -> Result<(), RunErrorKind> {
        if self.contour_open() {
            return Err(RunErrorKind::InsideCorner(
                "the radius cannot change while the contour runs",
            ));
        }
        if let (Some(side), Some(_), None) = (self.trc, self.sel.last, self.sel.bn_offset) {
            self.sel.bn_offset = Some(self.offset_for(side)?);
        }
        Ok(())
    }

    /// A `G238` contour is being read (its `G40` not yet come).
    pub(super) fn contour_open(&self) -> bool {
        self.sel
            .contour
            .as_ref()
            .is_some_and(|c| c.closed.is_none())
    }

    /// After a deselection or at the end: a fault of the correction not
    /// yet answered (the last profile's) stops the run, naming the block
    /// whose profile raised it.
    pub(super) fn check_fault(&mut self) -> Result<(), RunErrorKind> {
        if !std::mem::take(&mut self.sel.unchecked) {
            return Ok(());
        }
        let bits = self.read_object(objects::ERROR, ValueType::I32)?;
        // ERROR is an i32 read as f64: exact.
        let bits = bits as i32;
        if bits == 0 {
            return Ok(());
        }
        Err(RunErrorKind::CorrectionFault {
            bits: objects::error_bit_names(bits),
        })
    }
}
