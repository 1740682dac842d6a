//! The programmed frame: how a command's words become a machine target
//! (limits, modal feed, unnamed axes, coordinate rotation of end point and
//! arc centre: docs/objects.md device 0 and "Limits of motion commands";
//! decisions 12, 13, 14 and 78).

use uoi::AccessError;

use super::TcModule;
use crate::extension::TcExtension;
use crate::geometry::V2;
use crate::limits::{check_point, within_limit, MIN_STEP, RAPID_FEED};
use crate::plane::AxisWords;
use crate::plane::{AxisPos, TcPlane};
use crate::rotation::Rotation;
use tc_request::ArcDir;

/// `Range` unless every given word is finite and within
/// [`MAX_COORD`](crate::limits::MAX_COORD).
pub fn check_words<const N: usize>(words: &[Option<f64>; N]) -> Result<(), AccessError> {
    if words.iter().flatten().all(|&v| within_limit(v)) {
        Ok(())
    } else {
        Err(AccessError::Range)
    }
}

/// An interpolation command after intake: checked, rotated, in machine
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intake {
    /// Start: the end of the last programmed profile.
    pub start: AxisPos,
    /// Machine target (rotated).
    pub target: AxisPos,
    /// The new programmed position (before rotation).
    pub programmed: AxisPos,
    /// Arc direction and centre in the main plane (rotated).
    pub arc: Option<(ArcDir, V2)>,
    /// The feed it runs at (the rapid feed for a rapid).
    pub feed: f64,
    /// The modal feed after it.
    pub modal_feed: f64,
    /// A rapid move.
    pub rapid: bool,
}

impl<E: TcExtension> TcModule<E> {
    /// Checks and rotates an interpolation command; `Range` for a word,
    /// feed, rotated end point or arc centre out of limits. Nothing
    /// changes here.
    pub(super) fn intake(
        &self,
        words: &AxisWords,
        arc: Option<(ArcDir, [Option<f64>; 3])>,
        feed: Option<f64>,
        rapid: bool,
    ) -> Result<Intake, AccessError> {
        check_words(words)?;
        if let Some((_, ijk)) = arc {
            check_words(&ijk)?;
        }
        let modal_feed = self.feed_for(feed)?;
        let (target, programmed) = self.target(words);
        check_point(&target)?;
        let start = self.contour_end;
        let arc = arc.map(|(dir, ijk)| (dir, self.centre(&start, ijk)));
        if let Some((_, c)) = arc {
            check_point(c.as_slice())?;
        }
        Ok(Intake {
            start,
            target,
            programmed,
            arc,
            feed: if rapid { RAPID_FEED } else { modal_feed },
            modal_feed,
            rapid,
        })
    }

    /// The feed a command runs at: its `F` word or the modal one. An `F`
    /// word must be within the limit and step at least
    /// [`MIN_STEP`](crate::limits::MIN_STEP) per cycle.
    fn feed_for(&self, feed: Option<f64>) -> Result<f64, AccessError> {
        match feed {
            Some(f) if !(within_limit(f) && self.executor.step_at(f) >= MIN_STEP) => {
                Err(AccessError::Range)
            }
            Some(f) => Ok(f),
            None => Ok(self.feed),
        }
    }

    /// Takes over an accepted interpolation command's modal feed and end point.
    pub(super) fn accept(&mut self, cmd: &Intake) {
        self.feed = cmd.modal_feed;
        self.programmed = cmd.programmed;
        self.contour_end = cmd.target;
    }

    /// The machine target and the new programmed position for axis words.
    fn target(&self, words: &AxisWords) -> (AxisPos, AxisPos) {
        let mut programmed = self.programmed;
        for (p, w) in programmed.iter_mut().zip(words) {
            if let Some(v) = *w {
                *p = v;
            }
        }
        let mut target = programmed;
        let plane = self.main_plane();
        plane.set_point(&mut target, self.rotation.apply(plane.point(&programmed)));
        (target, programmed)
    }

    /// The arc centre in machine coordinates from I J K (along the axes
    /// allocated as X, Y, Z), rotated with the command.
    fn centre(&self, start: &AxisPos, ijk: [Option<f64>; 3]) -> V2 {
        let [i, j, k] = ijk.map(|v| v.unwrap_or(0.0));
        let plane_off = match self.plane {
            TcPlane::Xy => V2::new(i, j),
            TcPlane::Zx => V2::new(k, i),
            TcPlane::Yz => V2::new(j, k),
        };
        let turn = Rotation {
            angle_deg: self.rotation.angle_deg,
            center: V2::zeros(),
        };
        self.main_plane().point(start) + turn.apply(plane_off)
    }

    /// After a direct command the programmed position follows the machine.
    pub(super) fn resync_programmed(&mut self) {
        let q = *self.executor.nominal();
        self.contour_end = q;
        let plane = self.main_plane();
        let mut p = q;
        plane.set_point(&mut p, self.rotation.invert(plane.point(&q)));
        self.programmed = p;
    }
}
