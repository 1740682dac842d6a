//! Coordinate rotation of interpolation commands (uoi-map.md device 0
//! index 20..22; trc-geometry.md "Coordinate rotation").

use nalgebra::{Point2, Rotation2, Vector2};

/// Rotation angle (degrees, CCW in the main plane) and centre.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rotation {
    /// RotAngle, degrees.
    pub angle_deg: f64,
    /// RotCenterX / RotCenterY, main plane coordinates.
    pub center: [f64; 2],
}

impl Rotation {
    /// Whether the rotation changes nothing.
    pub fn is_identity(&self) -> bool {
        self.angle_deg == 0.0
    }

    /// Turns a plane point about the centre.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        if self.is_identity() {
            return p;
        }
        let c = Point2::new(self.center[0], self.center[1]);
        let r = Rotation2::new(self.angle_deg.to_radians());
        let q = c + r * (Point2::new(p[0], p[1]) - c);
        [q.x, q.y]
    }

    /// Undoes [`Rotation::apply`].
    pub fn invert(&self, p: [f64; 2]) -> [f64; 2] {
        if self.is_identity() {
            return p;
        }
        let c = Point2::new(self.center[0], self.center[1]);
        let r = Rotation2::new(-self.angle_deg.to_radians());
        let q = c + r * Vector2::new(p[0] - c.x, p[1] - c.y);
        [q.x, q.y]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turn_about_centre() {
        let r = Rotation {
            angle_deg: 90.0,
            center: [1.0, 1.0],
        };
        let q = r.apply([2.0, 1.0]);
        assert!((q[0] - 1.0).abs() < 1e-12 && (q[1] - 2.0).abs() < 1e-12);
        let back = r.invert(q);
        assert!((back[0] - 2.0).abs() < 1e-12 && (back[1] - 1.0).abs() < 1e-12);
    }
}
