//! Plane geometry of the tool radius correction (docs/trc.md "How a
//! corner is decided" and the pictures after it), one module per concept:
//! the plane point ([`V2`]), offsets of lines and arcs, corner classes,
//! transitions at outside corners, the carriers' intersections, the parts
//! an inside-corner point must lie on, the whole turn of programmed full
//! circles ([`full_circle`]), and the rules' angle comparisons as sign
//! tests. Pure functions on plane points `(h, v)`; every tolerance in
//! [`tolerance`].
//!
//! The modules form layers, each using only those before it: `vector`
//! and `tolerance`; `angle` and `intersect`; `offset`; `corner`, `part`,
//! `transition` and `full_circle`.

mod angle;
mod corner;
pub mod full_circle;
mod intersect;
mod offset;
mod part;
pub mod tolerance;
mod transition;
mod vector;

pub use corner::{classify, CornerKind};
pub use offset::{Contour, Offset, OffsetError};
pub use part::{inside_point, Part};
pub use transition::{transition, Transition};
pub use vector::V2;
