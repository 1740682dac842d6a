//! The fixed-point units of the OTC registers and tool fields, as types:
//! the seed's units (0.1 µm/m, 0.1 µm, 0.0001°) stay the register values,
//! and each type says how it becomes interpolation units (mm) or degrees,
//! so no bare factor stands beside a bare `f64` (docs/objects.md, device 3).

/// A wear constant in 0.1 µm of wear per metre of path (WearConst,
/// ToolWearConst).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
pub struct WearRate(pub f64);

impl WearRate {
    /// Wear per interpolation unit of path: 0.1 µm per m is 1e-4 mm per
    /// 1e3 mm, so `k = WearConst · 1e-7` (docs/otc.md).
    pub const PER_PATH_UNIT: f64 = 1e-7;

    /// The wear `k · ds` over `ds` interpolation units of path.
    pub fn wear_over(self, ds: f64) -> f64 {
        self.0 * Self::PER_PATH_UNIT * ds
    }
}

/// A length in 0.1 µm (ToolMaxInfeed; the PLC units' commands and states
/// are whole numbers of it).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
pub struct TenthMicrons(pub f64);

impl TenthMicrons {
    /// Interpolation units (mm) per 0.1 µm.
    pub const MM: f64 = 1e-4;

    /// The largest magnitude a command may have when this is its bound:
    /// a bound's sign does not count.
    pub fn magnitude(self) -> f64 {
        self.0.abs()
    }
}

/// An angle in 0.0001° (ToolTiltAngle).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
pub struct TiltAngle(pub f64);

impl TiltAngle {
    /// Degrees per register unit.
    pub const DEGREES: f64 = 1e-4;

    /// The angle in degrees.
    pub fn degrees(self) -> f64 {
        self.0 * Self::DEGREES
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_as_the_registers_say() {
        // 1e5 · 0.1 µm/m over 1 m (1000 mm) of path: 10 mm.
        assert!((WearRate(100_000.0).wear_over(1000.0) - 10.0).abs() < 1e-12);
        assert_eq!(TiltAngle(300_000.0).degrees(), 30.0);
        assert_eq!(TenthMicrons(-5.0).magnitude(), 5.0);
        assert_eq!(TenthMicrons(10_000.0).0 * TenthMicrons::MM, 1.0);
    }
}
