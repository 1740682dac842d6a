//! The one point type of the correction engine: a plane point or vector
//! `(h, v)` in the group's plane, and the two products every rule is
//! written with. Positions of every axis meet it in `PlaneAxes::point` and
//! `set_point`; an array `[f64; 2]` appears only in the reported spool
//! record (its arc centre).

use nalgebra::Vector2;

/// A plane point or vector `(h, v)`.
pub type V2 = Vector2<f64>;

/// Left normal of a unit tangent: `nL(t) = (-tv, th)`.
pub fn left_normal(t: V2) -> V2 {
    V2::new(-t.y, t.x)
}

/// 2-D cross product `a × b`.
pub fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}
