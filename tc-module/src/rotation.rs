//! Coordinate rotation of interpolation commands (docs/objects.md device
//! 0 index 20..22: RotAngle, RotCenterX, RotCenterY): the programmed end
//! point and arc centre turn about the centre in the main plane.

use nalgebra::{Point2, Rotation2};

use crate::geometry::V2;

/// Rotation angle (degrees, CCW in the main plane) and centre.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rotation {
    /// RotAngle, degrees.
    pub angle_deg: f64,
    /// RotCenterX / RotCenterY, main plane coordinates.
    pub center: V2,
}

impl Rotation {
    /// Whether the rotation changes nothing.
    pub fn is_identity(&self) -> bool {
        self.angle_deg == 0.0
    }

    /// Turns a plane point about the centre.
    pub fn apply(&self, p: V2) -> V2 {
        if self.is_identity() {
            return p;
        }
        let c = Point2::from(self.center);
        let r = Rotation2::new(self.angle_deg.to_radians());
        (c + r * (Point2::from(p) - c)).coords
    }

    /// Undoes [`Rotation::apply`].
    pub fn invert(&self, p: V2) -> V2 {
        if self.is_identity() {
            return p;
        }
        let c = Point2::from(self.center);
        let r = Rotation2::new(-self.angle_deg.to_radians());
        (c + r * (p - c.coords)).coords
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turn_about_centre() {
        let r = Rotation {
            angle_deg: 90.0,
            center: V2::new(1.0, 1.0),
        };
        let q = r.apply(V2::new(2.0, 1.0));
        assert!((q - V2::new(1.0, 2.0)).norm() < 1e-12);
        let back = r.invert(q);
        assert!((back - V2::new(2.0, 1.0)).norm() < 1e-12);
    }
}
