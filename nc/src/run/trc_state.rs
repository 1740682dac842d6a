//! The interpreter's state of the radius correction's selection modes
//! and feed adaptation (docs/nc.md): what `selection.rs`,
//! `inside_corner.rs` and `feed.rs` keep between blocks. A leaf: it imports
//! nothing of the interpreter, so the interpreter can hold it.

use tc_request::Motion;

use super::plane::Seg;
use crate::error::Location;

/// TRC side of G41/G42.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Side {
    Left,
    Right,
}

/// The selection and deselection mode (the modal group of `G138`..`G239`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum SelMode {
    /// `G138`: direct, the controller's approach and departure.
    Direct,
    /// `G139` (initial state): indirect, run as `G138`.
    Indirect,
    /// `G236`: direct on the path, run as `G138`.
    OnPath,
    /// `G237`: perpendicular.
    Perpendicular,
    /// `G238`: at an inside corner of a closed contour.
    InsideCorner,
    /// `G239`: direct, deselection without a block.
    WithoutBlock,
}

/// The selection state of a run.
pub(super) struct Selection {
    /// The mode in force.
    pub mode: SelMode,
    /// `G139`, `G236`, `G05` already warned about (one warning each).
    pub warned: [bool; 3],
    /// `G237` selected, waiting for the first motion in the plane.
    pub pending: Option<Side>,
    /// The last motion in the plane that went into the running correction
    /// (the held block Bn at a deselection).
    pub last: Option<Seg>,
    /// The next motion follows a `G239` deselection: not an arc.
    pub after_g239: bool,
    /// A `G238` contour being read, up to its `G40`.
    pub contour: Option<Contour>,
    /// The next motion is the departure of a `G238` contour: a line.
    pub departure: bool,
    /// The block of the last request that went into the correction: the
    /// one a fault found later names.
    pub fault_at: Option<Location>,
    /// A correction ran since ERROR was last looked at.
    pub unchecked: bool,
}

impl Default for Selection {
    fn default() -> Self {
        Selection {
            mode: SelMode::Indirect,
            warned: [false; 3],
            pending: None,
            last: None,
            after_g239: false,
            contour: None,
            departure: false,
            fault_at: None,
            unchecked: false,
        }
    }
}

impl SelMode {
    /// The word that runs as `G138`, with its place among the warnings.
    pub(super) fn runs_as_direct(self) -> Option<(&'static str, usize)> {
        match self {
            SelMode::Indirect => Some(("G139", 0)),
            SelMode::OnPath => Some(("G236", 1)),
            _ => None,
        }
    }
}

/// Most motions of one `G238` contour (read whole before it runs).
pub const MAX_CONTOUR_BLOCKS: usize = 100_000;

/// A motion of the contour as read, with its block.
pub(super) struct Read {
    /// The motion as the block asked for it.
    pub motion: Motion,
    /// Its plane part.
    pub seg: Option<Seg>,
    /// Its block and word.
    pub at: Option<Location>,
}

/// A `G238` contour being read.
pub(super) struct Contour {
    /// G41 or G42.
    pub side: Side,
    /// The selection block, once read.
    pub selection: Option<Read>,
    /// B1 .. Bn, and motions off the plane among them, in order.
    pub motions: Vec<Read>,
}

impl Contour {
    /// A contour selected on side `side`, nothing read yet.
    pub(super) fn new(side: Side) -> Contour {
        Contour {
            side,
            selection: None,
            motions: Vec::new(),
        }
    }
}

/// What the program set, as last sent to the controller.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct FeedAdaption {
    /// `G11` in force.
    pub on: bool,
    /// RMIN in mm.
    pub rmin: f64,
}
