//! The ERROR and STATUS registers of a compensation group
//! (docs/objects.md "ERROR bits" and "STATUS bits": device 1 sub 1 and
//! sub 3).

use bitflags::bitflags;

bitflags! {
    /// ERROR register bits (device 1 sub 1).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct ErrorBits: i32 {
        /// bit0: initialisation error (bad parameters, change while running).
        const INIT_ERROR = 1;
        /// bit1: radius correction not possible (the tool does not fit).
        const KORR_ERROR = 2;
        /// bit2: computation error (offset radius vanishes).
        const CALC_ERROR = 4;
        /// bit3: arc outside the group's main plane.
        const PLANE_ERROR = 8;
        /// bit4: arc centre inconsistent (start and end radius differ).
        const CENTER_ERROR = 16;
    }
}

bitflags! {
    /// STATUS register bits (device 1 sub 3, read).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct StatusBits: i32 {
        /// bit0: the correction runs.
        const RUN = 1;
        /// bit1: a profile is held in the one-profile buffer.
        const PROF_MARKED = 2;
    }
}
