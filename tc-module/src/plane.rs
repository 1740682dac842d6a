//! Main planes and axis allocation (docs/objects.md device 0 index 2 and
//! 3; docs/trc.md "Coordinates"): where positions of every axis meet the
//! plane points of the correction.

use tc_objects::{PLANE_XY, PLANE_YZ, PLANE_ZX};
pub use tc_request::{AxisPos, AxisWords, AXES, AXIS_NAMES};

use crate::geometry::V2;

/// The main plane for circles and correction: 17 X-Y, 18 Z-X, 19 Y-Z
/// (NC G17/G18/G19).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TcPlane {
    /// 17: X-Y, third axis Z.
    #[default]
    Xy,
    /// 18: Z-X, third axis Y.
    Zx,
    /// 19: Y-Z, third axis X.
    Yz,
}

impl TcPlane {
    /// The plane for a register value 17/18/19.
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            PLANE_XY => Some(TcPlane::Xy),
            PLANE_ZX => Some(TcPlane::Zx),
            PLANE_YZ => Some(TcPlane::Yz),
            _ => None,
        }
    }

    /// The register value 17/18/19.
    pub const fn code(self) -> i32 {
        match self {
            TcPlane::Xy => PLANE_XY,
            TcPlane::Zx => PLANE_ZX,
            TcPlane::Yz => PLANE_YZ,
        }
    }

    /// Picks `(h, v, third)` out of an X/Y/Z allocation.
    pub const fn pick(self, xyz: [u8; 3]) -> PlaneAxes {
        let [x, y, z] = xyz;
        match self {
            TcPlane::Xy => PlaneAxes {
                h: x,
                v: y,
                third: z,
            },
            TcPlane::Zx => PlaneAxes {
                h: z,
                v: x,
                third: y,
            },
            TcPlane::Yz => PlaneAxes {
                h: y,
                v: z,
                third: x,
            },
        }
    }
}

/// The machine's main axes (device 0): the axes allocated as X, Y, Z
/// (AxisNr) and the main plane TcPlane builds from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MainAxes {
    /// The machine axes used as X, Y, Z.
    pub xyz: [u8; 3],
    /// The main plane: its first and second axes and the third main axis.
    pub plane: PlaneAxes,
}

/// Machine axes of a main plane: `h` and `v` span it (CCW turns h to v),
/// `third` is the tool axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PlaneAxes {
    /// 1st plane axis.
    pub h: u8,
    /// 2nd plane axis.
    pub v: u8,
    /// Third main axis (tool length).
    pub third: u8,
}

impl PlaneAxes {
    /// Whether the two plane axes are different machine axes.
    pub const fn distinct(self) -> bool {
        self.h != self.v
    }

    /// Whether `h` and `v` are the same pair as `other`'s.
    pub const fn same_plane(self, other: PlaneAxes) -> bool {
        self.h == other.h && self.v == other.v
    }

    /// The plane point `(h, v)` of a position.
    #[inline]
    pub fn point(self, p: &AxisPos) -> V2 {
        V2::new(p[usize::from(self.h)], p[usize::from(self.v)])
    }

    /// Writes a plane point into a position (`v` last).
    #[inline]
    pub fn set_point(self, p: &mut AxisPos, q: V2) {
        p[usize::from(self.h)] = q.x;
        p[usize::from(self.v)] = q.y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::axis_index;

    #[test]
    fn planes_pick_axes() {
        assert_eq!(
            TcPlane::Xy.pick([0, 1, 2]),
            PlaneAxes {
                h: 0,
                v: 1,
                third: 2
            }
        );
        assert_eq!(
            TcPlane::Zx.pick([0, 1, 2]),
            PlaneAxes {
                h: 2,
                v: 0,
                third: 1
            }
        );
        assert_eq!(
            TcPlane::Yz.pick([0, 1, 2]),
            PlaneAxes {
                h: 1,
                v: 2,
                third: 0
            }
        );
        for c in [17, 18, 19] {
            assert_eq!(TcPlane::from_code(c).map(TcPlane::code), Some(c));
        }
        assert_eq!(TcPlane::from_code(20), None);
        assert_eq!(axis_index('v'), Some(7));
        assert_eq!(axis_index('W'), None);
    }
}
