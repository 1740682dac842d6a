//! The OTC settings of a group that say what wear counts and where it
//! acts: the processing type (device 3 sub 2) and the mode (sub 3), with
//! their register codes, written once here for the engine (`otc-ext`) and
//! the NC front end (`nc`, `#OTC`).

/// Processing type (device 3 sub 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ProcType {
    /// 0: wear as a radius change.
    Radius,
    /// 1: wear along the tool length (default).
    #[default]
    Length,
    /// 2: wear along the tool direction.
    ToolDir,
    /// 3: wear along the surface normal.
    SurfNormDir,
}

impl ProcType {
    /// The type for a register value (the table allows 0..=3).
    pub fn from_code(v: i32) -> Self {
        match v {
            0 => ProcType::Radius,
            2 => ProcType::ToolDir,
            3 => ProcType::SurfNormDir,
            _ => ProcType::Length,
        }
    }

    /// The register value.
    pub fn code(self) -> i32 {
        match self {
            ProcType::Radius => 0,
            ProcType::Length => 1,
            ProcType::ToolDir => 2,
            ProcType::SurfNormDir => 3,
        }
    }
}

/// OTC mode (device 3 sub 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OtcMode {
    /// 0: discrete offsets from the PLC only.
    Disc,
    /// 1: continuous wear only.
    Cont,
    /// 2: both (default).
    #[default]
    Auto,
}

impl OtcMode {
    /// The mode for a register value (the table allows 0..=2).
    pub fn from_code(v: i32) -> Self {
        match v {
            0 => OtcMode::Disc,
            1 => OtcMode::Cont,
            _ => OtcMode::Auto,
        }
    }

    /// The register value.
    pub fn code(self) -> i32 {
        match self {
            OtcMode::Disc => 0,
            OtcMode::Cont => 1,
            OtcMode::Auto => 2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        for c in 0..=3 {
            assert_eq!(ProcType::from_code(c).code(), c);
        }
        for c in 0..=2 {
            assert_eq!(OtcMode::from_code(c).code(), c);
        }
    }
}
