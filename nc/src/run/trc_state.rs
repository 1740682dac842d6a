//! The interpreter's state of the radius correction's selection modes
//! and feed adaptation (docs/nc.md): what `selection.rs`,
//! `inside_corner.rs` and `feed.rs` keep between blocks. A leaf: it imports
//! nothing of the interpreter, so the interpreter can hold it.

use tc_request::Request;

use super::plane::{Seg, P2};
use crate::error::Location;

/// TRC side of G41/G42.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Side {
    Left,
    Right,
}

impl Side {
    /// +1 left, -1 right: the sign of the offset `d` of a positive radius.
    pub(super) fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
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
    /// The signed offset Bn was corrected with, when the radius changed
    /// after it was sent (`None`: the radius in force).
    pub bn_offset: Option<f64>,
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
            bn_offset: None,
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

/// Most blocks of one `G238` contour (read whole before it runs).
pub const MAX_CONTOUR_BLOCKS: usize = 100_000;

/// A request of a `G238` contour as read, with its block.
pub(super) struct Read {
    /// The request the block asked for.
    pub request: Request,
    /// The plane part of a motion.
    pub seg: Option<Seg>,
    /// Its block and word.
    pub at: Option<Location>,
}

/// A `G238` contour: read up to its `G40`, then checked and held until its
/// departure shows that it is a line.
pub(super) struct Contour {
    /// G41 or G42.
    pub side: Side,
    /// The selection block, once read.
    pub selection: Option<Read>,
    /// B1 .. Bn, and every other request of those blocks, in order.
    pub items: Vec<Read>,
    /// Set at `G40`, once checked: the cut point C.
    pub closed: Option<P2>,
    /// Requests between `G40` and the departure, in order.
    pub after: Vec<Read>,
}

impl Contour {
    /// A contour selected on side `side`, nothing read yet.
    pub(super) fn new(side: Side) -> Contour {
        Contour {
            side,
            selection: None,
            items: Vec::new(),
            closed: None,
            after: Vec::new(),
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
