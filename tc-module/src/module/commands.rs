//! Motion commands: interpolation (spooled as it is, or corrected by the
//! running group), special functions, direct commands and `rs()`
//! (docs/trc.md "The one-profile buffer"; docs/objects.md "ERROR bits" for
//! the errors while running).

use uoi::AccessError;

use super::intake::{check_words, Intake};
use super::{Departure, TcModule};
use crate::bits::ErrorBits;
use crate::correction::{Profile, Refusal, Sink};
use crate::element::{ContourNormal, NormalRule, Origin, SpoolElement};
use crate::extension::{Groups, TcExtension};
use crate::geometry::tolerance::MIN_RADIUS;
use crate::geometry::Contour;
use crate::limits::MIN_STEP;
use crate::plane::AxisWords;
use crate::plane::AXES;
use crate::rotation::Rotation;
use tc_request::{ArcDir, Motion, SSF_FLUSH};

impl<E: TcExtension> TcModule<E> {
    /// Executes a motion command.
    pub fn command(&mut self, m: &Motion) -> Result<(), AccessError> {
        // Matched by reference: the axis words are not copied.
        match m {
            Motion::Lin { words, feed } => self.interpolate(words, None, *feed, false),
            Motion::Rap { words, feed } => self.interpolate(words, None, *feed, true),
            Motion::Cir {
                dir,
                words,
                centre,
                feed,
            } => self.interpolate(words, Some((*dir, *centre)), *feed, false),
            Motion::Ja { words } => self.jog_absolute(words),
            Motion::Js { .. } => {
                self.position_request()?;
                self.direct_command();
                self.resync_programmed();
                self.refresh_offset();
                Ok(())
            }
            Motion::Ssf { axis, function } => self.special_function(*axis, *function),
            Motion::Rs => {
                self.rotation = Rotation::default();
                Ok(())
            }
        }
    }

    /// Asks the extension whether a position request may happen.
    pub(super) fn position_request(&mut self) -> Result<(), AccessError> {
        let main = self.main_axes();
        let groups = Groups::new(&mut self.groups[..], self.running, main);
        self.ext.position_request(groups)
    }

    /// `JA`: the named axes move to their targets at once.
    fn jog_absolute(&mut self, words: &AxisWords) -> Result<(), AccessError> {
        check_words(words)?;
        self.position_request()?;
        self.direct_command();
        for (i, w) in words.iter().enumerate() {
            if let Some(v) = *w {
                self.executor.set_axis(i, v);
            }
        }
        self.resync_programmed();
        self.refresh_offset();
        Ok(())
    }

    /// `SSF axis function`: 2001 to an axis of the running group flushes
    /// its buffer and keeps it running; anything else is accepted and
    /// does nothing.
    fn special_function(&mut self, axis: u8, function: i32) -> Result<(), AccessError> {
        if usize::from(axis) >= AXES {
            return Err(AccessError::Range);
        }
        if function != SSF_FLUSH {
            return Ok(());
        }
        if let Some(slot) = self.running {
            let in_group = self.groups[slot]
                .as_ref()
                .is_some_and(|g| g.axes.contains(&axis));
            if in_group {
                self.flush(slot);
            }
        }
        Ok(())
    }

    /// `JA`/`JS`: the spooler queue and the running group's buffer are
    /// discarded; the correction keeps running, next profile is an approach.
    fn direct_command(&mut self) {
        self.spooler.discard();
        self.executor.abandon_element();
        self.departure = None;
        if let Some(slot) = self.running {
            if let Some(g) = self.groups[slot].as_mut() {
                g.buffer.clear();
            }
        }
    }

    /// Spools the buffered profile of a running group (STATUS=0, SSF 2001).
    pub(super) fn flush(&mut self, slot: usize) {
        let q = self.tool_position();
        let plane = self.plane;
        let Some(g) = self.groups[slot].as_mut() else {
            return;
        };
        let mut sink = Sink::new(&mut self.spooler, q, g.plane_axes(plane), g.tool().length);
        g.buffer.flush(&mut sink);
    }

    /// STATUS=0 of the running `slot`: the buffered profile is spooled and
    /// the next uncorrected element is the departure.
    pub(super) fn stop(&mut self, slot: usize) {
        if self.running != Some(slot) {
            return;
        }
        self.flush(slot);
        let plane = self.plane;
        self.departure = self.groups[slot].as_ref().map(|g| {
            Departure(g.buffer.last_normal().map(|v| ContourNormal {
                plane: g.plane_axes(plane),
                rule: NormalRule::Fixed(v),
            }))
        });
        self.running = None;
    }

    /// `LIN`/`RAP`/`CIR`: refused while a group is faulted; checked and
    /// rotated as it enters; then corrected by the running group or
    /// spooled as it is. Refused with `Range` when something it spools
    /// would lie beyond the limit, with `Full` when the spooler has no
    /// room for it; refused, it changes nothing.
    fn interpolate(
        &mut self,
        words: &AxisWords,
        arc: Option<(ArcDir, [Option<f64>; 3])>,
        feed: Option<f64>,
        rapid: bool,
    ) -> Result<(), AccessError> {
        if self.groups.iter().flatten().any(|g| g.faulted) {
            return Err(AccessError::State);
        }
        let cmd = self.intake(words, arc, feed, rapid)?;
        let Some(slot) = self.running else {
            return self.spool_uncorrected(&cmd);
        };
        match self.correct(slot, &cmd) {
            Ok(()) => self.accept(&cmd),
            // Accepted: geometry problems are TC-level errors (ERROR
            // bits), answered ok.
            Err(Refusal::Fault(bits)) => {
                self.accept(&cmd);
                self.fault(slot, bits);
            }
            Err(Refusal::Access(e)) => return Err(e),
        }
        Ok(())
    }

    /// No group runs: one element from the tool position to the target.
    fn spool_uncorrected(&mut self, cmd: &Intake) -> Result<(), AccessError> {
        let q = self.tool_position();
        let main = self.main_plane();
        let (end, uncorrected) = (&cmd.target, Origin::Uncorrected);
        let element = match cmd.arc {
            None => SpoolElement::line(&q, end, main, cmd.feed, cmd.rapid, uncorrected),
            Some((dir, c)) => {
                let s = main.point(&cmd.start) - c;
                if s.x.hypot(s.y) <= MIN_RADIUS {
                    // Refused: nothing changes, not even the modal feed.
                    return Err(AccessError::Range);
                }
                let ccw = dir == ArcDir::Ccw;
                SpoolElement::arc(&q, end, main, c, ccw, cmd.feed, uncorrected)
            }
        };
        if !self.spooler.has_room(1) {
            return Err(AccessError::Full);
        }
        self.accept(cmd);
        let element = self.uncorrected(element);
        self.spooler.push(&q, end, element);
        Ok(())
    }

    /// The running group corrects the profile: the ERROR bit on a
    /// geometry failure, an access error when it is refused.
    fn correct(&mut self, slot: usize, cmd: &Intake) -> Result<(), Refusal> {
        let plane = self.plane;
        let main = self.main_plane();
        let q = self.tool_position();
        let adaption = self.feed_adaption;
        let Some(g) = self.groups[slot].as_mut() else {
            return Ok(());
        };
        let gp = g.plane_axes(plane);
        if cmd.arc.is_some() && !gp.same_plane(main) {
            return Err(ErrorBits::PLANE_ERROR.into());
        }
        let (from, to) = (gp.point(&cmd.start), gp.point(&cmd.target));
        let contour = match cmd.arc {
            None => Contour::Line { from, to },
            Some((dir, centre)) => Contour::Arc {
                from,
                to,
                centre,
                sigma: dir.sigma(),
            },
        };
        let (d, mode) = (g.offset(), g.transition);
        let arc_feed = match contour {
            Contour::Arc {
                from,
                centre,
                sigma,
                ..
            } if !cmd.rapid => {
                let r = (from - centre).norm();
                adaption.arc_feed(cmd.feed, r, r - sigma * d)
            }
            _ => cmd.feed,
        };
        if self.executor.step_at(arc_feed) < MIN_STEP {
            return Err(Refusal::Access(AccessError::Range));
        }
        let prof = Profile {
            contour,
            start: cmd.start,
            end: cmd.target,
            feed: cmd.feed,
            arc_feed,
            rapid: cmd.rapid,
        };
        let mut sink = Sink::new(&mut self.spooler, q, gp, g.tool().length);
        g.buffer.push(&prof, d, mode, &mut sink)
    }

    /// A motion error while running: the group faults and Run clears.
    fn fault(&mut self, slot: usize, bits: ErrorBits) {
        if let Some(g) = self.groups[slot].as_mut() {
            g.fault(bits);
        }
        self.clear_run(slot);
    }
}
