//! Plane geometry of the tool radius correction (trc-geometry.md "Offset
//! geometry" and "Corner"), one module per concept: offsets of lines and
//! arcs, corner classes, transitions at outside corners, the carriers'
//! intersections, the parts an inside-corner point must lie on, the whole
//! turn of programmed full circles ([`full_circle`]), and the
//! rules' angle comparisons as sign tests ([`angle`]). Pure functions on
//! plane points `(h, v)`; every tolerance in [`tolerance`].

pub mod angle;
pub mod corner;
pub mod full_circle;
pub mod intersect;
pub mod offset;
pub mod part;
pub mod tolerance;
pub mod transition;

pub use angle::turn_angle;
pub use corner::{classify, CornerKind};
pub use intersect::Intersections;
pub use offset::{cross, left_normal, Contour, Offset, OffsetError, OffsetPath, V2};
pub use part::{inside_point, Part};
pub use transition::{transition, Transition, TransitionLines};
