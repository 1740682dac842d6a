//! What enters the correction: a programmed profile in machine axes, and
//! the transition mode its outside corners take.

use crate::geometry::Contour;
use crate::plane::AxisPos;

/// A programmed profile as it enters the correction (rotated, machine
/// axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// The element in the group's plane.
    pub contour: Contour,
    /// Programmed start, all axes.
    pub start: AxisPos,
    /// Programmed end, all axes.
    pub end: AxisPos,
    /// Feed, units/min.
    pub feed: f64,
    /// Feed of its corrected arc element(s): `feed`, or the adapted feed
    /// under [`FeedAdaption`].
    pub arc_feed: f64,
    /// A rapid move.
    pub rapid: bool,
}

/// Feed adaptation of corrected arcs (NC G10/G11, `#TANGFEED RMIN`; set
/// with `TcModule::set_feed_adaption`, no register of the bus): the feed of a corrected arc becomes `F * R'/R`, R the
/// programmed radius and `R' = R - σ d` the corrected one, so that F holds
/// where the tool touches the contour; only for arcs with `R >= rmin`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FeedAdaption {
    /// G11 adapts, G10 (default) does not.
    pub on: bool,
    /// RMIN: the smallest programmed radius adapted (default 0).
    pub rmin: f64,
}

impl FeedAdaption {
    /// The feed of the corrected arc of programmed radius `r` whose
    /// corrected radius is `r_corr`, at programmed feed `feed`.
    pub fn arc_feed(&self, feed: f64, r: f64, r_corr: f64) -> f64 {
        if self.on && r >= self.rmin && r > 0.0 && r_corr > 0.0 {
            feed * r_corr / r
        } else {
            feed
        }
    }
}

/// Transition inserted at outside corners (device 2 sub 1; NC G26/G25).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TransitionMode {
    /// 0: one arc about the programmed corner (G26). Default.
    #[default]
    Circular,
    /// 1: straight lines (G25).
    Linear,
}

impl TransitionMode {
    /// The register value.
    pub const fn code(self) -> i32 {
        match self {
            TransitionMode::Circular => 0,
            TransitionMode::Linear => 1,
        }
    }

    /// The mode for a register value (the table allows 0 and 1).
    pub const fn from_code(code: i32) -> Self {
        if code == 1 {
            TransitionMode::Linear
        } else {
            TransitionMode::Circular
        }
    }
}
