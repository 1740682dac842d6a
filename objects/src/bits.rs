//! The bits of the ERROR and STATUS registers of a compensation group
//! (device 1 sub 1 and sub 3) and of OTC's OtcError register (device 3
//! sub 7), with what each means (docs/objects.md).

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

bitflags! {
    /// OtcError register bits (device 3 sub 7).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct OtcErrorBits: i32 {
        /// bit0: OTC ON with a tool that is not a grinding tool (P-ERR-21391).
        const TOOL_TYPE = 1;
        /// bit1: command out of sequence (ISG 90050).
        const SEQUENCE = 2;
        /// bit2: position request refused while OTC is on (ISG 21572).
        const POS_REQUEST = 4;
        /// bit3: a PLC unit used with a type or mode that ignores it.
        const NOT_ALLOWED = 8;
    }
}

/// The name of a bit as the reference and traces spell it: `INIT_ERROR`
/// → `InitError`.
pub fn camel_name(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut cs = w.chars();
            cs.next().map_or(String::new(), |c| {
                c.to_uppercase()
                    .chain(cs.flat_map(char::to_lowercase))
                    .collect()
            })
        })
        .collect()
}

/// What a register bit means, by its [`camel_name`].
pub fn bit_meaning(name: &str) -> Option<&'static str> {
    Some(match name {
        "InitError" => "STATUS=1 refused (no side, plane axes equal, another group runs) or an init register written while running",
        "KorrError" => "the tool does not fit at an inside corner (gouging)",
        "CalcError" => "the offset arc's radius vanishes, or an arc has no radius",
        "PlaneError" => "an arc that does not lie in the group's main plane",
        "CenterError" => "an arc whose start and end lie at different distances from its centre",
        "Run" => "the correction runs",
        "ProfMarked" => "a profile is held in the one-profile buffer",
        "ToolType" => "OTC switched on without a grinding tool",
        "Sequence" => "a switch out of order: OTC off while the radius correction runs, ProcType or Mode changed while OTC is on",
        "PosRequest" => "a direct command or ReInit refused while OTC is on (AllowPosReq 0)",
        "NotAllowed" => "an enabled PLC unit that the processing type or mode ignores",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use bitflags::Flags;

    use super::*;

    fn names<F: Flags>() -> impl Iterator<Item = String> {
        F::FLAGS.iter().map(|f| camel_name(f.name()))
    }

    #[test]
    fn every_bit_has_a_meaning() {
        let all: Vec<String> = names::<ErrorBits>()
            .chain(names::<StatusBits>())
            .chain(names::<OtcErrorBits>())
            .collect();
        assert_eq!(all.len(), 11);
        for n in all {
            assert!(bit_meaning(&n).is_some(), "{n}");
        }
        assert_eq!(camel_name("PROF_MARKED"), "ProfMarked");
    }
}
