//! The one point type of the correction engine: a plane point or vector
//! `(h, v)` in the group's plane, and the two products every rule is
//! written with. Arrays `[f64; 2]` appear only where the engine meets
//! positions of every axis (`PlaneAxes::point`) and the spool records.

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
