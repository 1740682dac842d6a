//! The correction engine: the one-profile buffer (docs/trc.md "The
//! one-profile buffer").
//!
//! While a group runs, every profile is first held here. When the next one
//! arrives, the held one is corrected together with the corner to the new
//! one and both are spooled; the new one is held. Every element it spools
//! carries its origin and its contour normal (docs/otc.md "Processing
//! types and their directions").
//!
//! What a profile spools is admitted as a whole or not at all: every end
//! point and arc centre within the coordinate limit (else `Range`) and
//! room in the spooler for it and for the profile then held (else
//! `Full`); a refused profile leaves spooler and buffer as they were.
//! Plane-null profiles waiting with the held one count toward the
//! spooler's capacity.
//!
//! One step of [`Buffer::push`], top to bottom: the profile's offset; what
//! it finishes (`Finish`: the corner with the held profile, `join.rs`, or
//! an approach); the spooling of that (the held profile, `held.rs`, the
//! plane-null profiles waiting with it and the transition); the admission
//! of all of it by the [`Sink`] (`sink.rs`), with the points the new held
//! profile will spool; and only then the buffer changes.

use uoi::AccessError;

use crate::bits::ErrorBits;
use crate::geometry::{OffsetError, V2};

mod held;
mod join;
mod profile;
mod sink;

pub use crate::geometry::Contour;
use held::{Entry, Held, Hold, NullMove, MAX_HELD};
use join::{corner, spool_transition};
pub use profile::{FeedAdaption, Profile, TransitionMode};
pub use sink::Sink;

/// Most elements a transition spools (three lines).
const MAX_TRANSITION: usize = 3;

/// Places plane-null profiles leave free for the corner that will spool
/// them: its transition and the profile held after it. With them free,
/// the next profile in the plane is always admitted once the executor has
/// emptied the spooler.
pub const CORNER_ROOM: usize = MAX_TRANSITION + MAX_HELD;

/// Storage for waiting plane-null profiles kept when they leave.
const KEEP_NULLS: usize = 64;

/// Why the buffer did not take a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// A TC-level error while running: the ERROR bit to set; the caller
    /// faults the group (the access itself is answered ok). Nothing was
    /// spooled.
    Fault(ErrorBits),
    /// Refused with an access error (`Range`, `Full`); nothing changed.
    Access(AccessError),
}

impl From<ErrorBits> for Refusal {
    fn from(bits: ErrorBits) -> Self {
        Refusal::Fault(bits)
    }
}

impl From<AccessError> for Refusal {
    fn from(e: AccessError) -> Self {
        Refusal::Access(e)
    }
}

/// What a new profile finishes: the corner with the held profile, or (an
/// approach) the held profile with its own offset end, if one is held.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Finish {
    /// Joined to the held profile.
    Corner(join::Join),
    /// Nothing held, or the held profile has another offset (the radius
    /// changed while running: it is finished as at SSF 2001).
    Approach,
}

impl Finish {
    /// How the new profile enters the buffer after it.
    fn entry(&self) -> Entry {
        match self {
            Finish::Corner(j) => Entry::Corner {
                from: j.b_from,
                continued: j.continued,
            },
            Finish::Approach => Entry::Approach,
        }
    }
}

/// The one-profile buffer of a group. Empty means the next profile is an
/// approach.
#[derive(Debug, Clone, Default)]
pub struct Buffer {
    held: Option<Held>,
    nulls: Vec<NullMove>,
    /// The contour normal at the end of the last element spooled.
    last_normal: Option<V2>,
}

fn offset_error(e: OffsetError) -> ErrorBits {
    match e {
        OffsetError::Calc => ErrorBits::CALC_ERROR,
        OffsetError::Center => ErrorBits::CENTER_ERROR,
    }
}

impl Buffer {
    /// Whether a profile is held (STATUS bit ProfMarked).
    pub fn is_marked(&self) -> bool {
        self.held.is_some()
    }

    /// The contour normal at the end of the last element the correction
    /// spooled: what a departure leaves.
    pub fn last_normal(&self) -> Option<V2> {
        self.last_normal
    }

    /// Plane-null profiles waiting with the held one.
    pub fn waiting_nulls(&self) -> usize {
        self.nulls.len()
    }

    /// Places the buffer will take in the spooler when it is flushed: the
    /// held profile's elements (at most) and the waiting plane-null ones.
    pub fn pending(&self) -> usize {
        self.held.as_ref().map_or(0, Held::reserve) + self.nulls.len()
    }

    /// Drops the held profile without spooling it, and the contour normal
    /// where the tool stands (ReInit, direct command, RESET, fault).
    pub fn clear(&mut self) {
        self.held = None;
        self.clear_nulls();
        self.last_normal = None;
    }

    /// STATUS=1: drops what may still be held (nothing after a STATUS=0),
    /// but keeps the contour normal where the last corrected element
    /// ended: switching the correction on and off again without motion
    /// leaves the departure that follows as it was (decision 334).
    pub fn restart(&mut self) {
        self.held = None;
        self.clear_nulls();
    }

    /// Forgets the waiting plane-null profiles, giving back large storage.
    fn clear_nulls(&mut self) {
        self.nulls.clear();
        if self.nulls.capacity() > KEEP_NULLS {
            self.nulls.shrink_to(KEEP_NULLS);
        }
    }

    /// A new profile enters with offset `d` (side × radius). On a
    /// TC-level error the bit to set is returned and nothing was spooled
    /// (the caller faults the group); on an access error nothing changed.
    pub fn push(
        &mut self,
        prof: &Profile,
        d: f64,
        mode: TransitionMode,
        sink: &mut Sink,
    ) -> Result<(), Refusal> {
        sink.begin();
        if prof.contour.is_plane_null() {
            return self.push_plane_null(prof, sink);
        }
        let off = prof.contour.offset(d).map_err(offset_error)?;
        let finish = match &self.held {
            Some(a) if a.off.d == d => {
                Finish::Corner(corner(a, &off, prof.contour.is_full_circle(), mode)?)
            }
            _ => Finish::Approach,
        };
        let normal = self.spool_finished(&finish, prof, sink);
        let hold = Hold::of(prof, &off, finish.entry());
        hold.check_points(prof, &off, sink);
        sink.admit(hold.reserve())?;
        if normal.is_some() {
            if !self.nulls.is_empty() {
                self.clear_nulls();
            }
            self.last_normal = normal;
        }
        // Built in place: the profile is copied once, into the buffer.
        self.held = Some(Held {
            prof: *prof,
            off,
            hold,
        });
        Ok(())
    }

    /// Spools what `finish` ends (the held profile, the plane-null profiles
    /// waiting with it and a transition); the contour normal where it ends,
    /// `None` when nothing was held.
    fn spool_finished(&self, finish: &Finish, next: &Profile, sink: &mut Sink) -> Option<V2> {
        let a = self.held.as_ref()?;
        match finish {
            Finish::Corner(join) => {
                let n = a.spool(join.a_end, &self.nulls, sink);
                if let Some(t) = join.transition {
                    spool_transition(t, a.corner(), next, sink);
                }
                Some(n)
            }
            Finish::Approach => Some(a.spool(a.off.end, &self.nulls, sink)),
        }
    }

    /// A plane-null profile waits with the held one, or is spooled at once
    /// at the current tool position when nothing is held. Waiting, it
    /// takes a place of the spooler's capacity and leaves
    /// [`CORNER_ROOM`] free for the corner that will spool it.
    fn push_plane_null(&mut self, prof: &Profile, sink: &mut Sink) -> Result<(), Refusal> {
        let null = NullMove::of(prof);
        if self.held.is_none() {
            null.spool(self.last_normal, sink);
            return Ok(sink.admit(0)?);
        }
        sink.check_end(sink.here(), &prof.end);
        let pending = self.pending() + 1;
        sink.admit(pending)?;
        if pending + CORNER_ROOM > sink.capacity() {
            return Err(AccessError::Full.into());
        }
        self.nulls.push(null);
        Ok(())
    }

    /// Spools the held profile with its own offset end, then the plane-null
    /// profiles waiting with it (STATUS=0, SSF 2001). The buffer is empty
    /// afterwards: the next profile is an approach. Its places were kept,
    /// its points checked as it came in.
    pub fn flush(&mut self, sink: &mut Sink) {
        if let Some(a) = &self.held {
            self.last_normal = Some(a.spool(a.off.end, &self.nulls, sink));
        }
        self.held = None;
        self.clear_nulls();
    }
}
