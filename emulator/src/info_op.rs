//! `INFO` (extension op `0x23`): what a client of the shared emulator
//! cannot see otherwise, read-only: how many Cleans the emulator has
//! carried out (a host library voids the handles issued before the last
//! one), whether it runs in real time, its cycles run, its settings, and
//! the server's identity, a random number drawn at each start (a handle
//! issued by a server that has restarted since is void too)
//! (docs/protocol.md, "INFO"). The op is the emulator's own: `uoi`
//! carries it opaque and `tc-request` knows nothing of it.

use bytes::Bytes;
use tc_module::{AxisPos, AXES};
use uoi::wire::{Answer, Request as WireRequest};

/// The op code of `INFO` (in `uoi::wire::EXT_OPS`, beside the TC ops).
pub const INFO_OP: u8 = 0x23;

/// Bytes of an `INFO` answer: five 8-byte fields, the start position and
/// the server's identity.
pub const INFO_LEN: usize = 8 * 5 + 8 * AXES + 8;

/// What `INFO` answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmulatorInfo {
    /// Cleans carried out ([`Emulator::clean_epoch`](crate::Emulator::clean_epoch)).
    pub cleans: u64,
    /// The real-time factor; `None`: stepped.
    pub realtime: Option<f64>,
    /// Cycles the executor has run since the start.
    pub cycles: u64,
    /// The interpolation cycle in seconds.
    pub cycle_s: f64,
    /// Elements the spooler holds.
    pub spool_capacity: u64,
    /// The machine position at the server's start.
    pub start: AxisPos,
    /// The server's identity: a random number drawn at its start, never 0
    /// (0 in an embedded emulator, which has no other life).
    pub server: u64,
}

/// A server identity: a random number, never 0, drawn anew at each call
/// (a server draws one at its start).
pub fn new_server_identity() -> u64 {
    // The system's random source; should it fail, the clock and the
    // process id still differ between two starts.
    getrandom::u64().unwrap_or_else(|_| {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        nanos ^ (u64::from(std::process::id()) << 32)
    }) | 1
}

/// The `INFO` request (no payload).
pub fn info_request() -> WireRequest {
    WireRequest::Ext(INFO_OP, Bytes::new())
}

/// Whether `req` is an `INFO` request (any payload: a payload is refused
/// by [`EmulatorInfo::answer`]'s caller).
pub fn is_info(req: &WireRequest) -> bool {
    matches!(req, WireRequest::Ext(INFO_OP, _))
}

impl EmulatorInfo {
    /// The wire answer: little-endian `cleans u64, realtime f64 (0:
    /// stepped), cycles u64, cycle_s f64, spool_capacity u64, start 8 ×
    /// f64, server u64`.
    pub fn to_wire(&self) -> Answer {
        let mut out = Vec::with_capacity(INFO_LEN);
        out.extend_from_slice(&self.cleans.to_le_bytes());
        out.extend_from_slice(&self.realtime.unwrap_or(0.0).to_le_bytes());
        out.extend_from_slice(&self.cycles.to_le_bytes());
        out.extend_from_slice(&self.cycle_s.to_le_bytes());
        out.extend_from_slice(&self.spool_capacity.to_le_bytes());
        for v in self.start {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.server.to_le_bytes());
        Answer::Ext(Bytes::from(out))
    }

    /// The info an answer to `INFO` carries; `None` when it is not one.
    pub fn from_wire(ans: &Answer) -> Option<Self> {
        let Answer::Ext(p) = ans else { return None };
        if p.len() != INFO_LEN {
            return None;
        }
        let word = |k: usize| -> [u8; 8] {
            let mut w = [0u8; 8];
            w.copy_from_slice(&p[8 * k..8 * k + 8]);
            w
        };
        let realtime = f64::from_le_bytes(word(1));
        let mut start = [0.0; AXES];
        for (k, v) in start.iter_mut().enumerate() {
            *v = f64::from_le_bytes(word(5 + k));
        }
        Some(Self {
            cleans: u64::from_le_bytes(word(0)),
            realtime: (realtime > 0.0).then_some(realtime),
            cycles: u64::from_le_bytes(word(2)),
            cycle_s: f64::from_le_bytes(word(3)),
            spool_capacity: u64::from_le_bytes(word(4)),
            start,
            server: u64::from_le_bytes(word(5 + AXES)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::wire::TcOp;

    #[test]
    fn the_op_is_free_and_its_answer_reads_back() {
        assert!(TcOp::from_code(INFO_OP).is_none(), "a TC op took 0x23");
        assert!(uoi::wire::EXT_OPS.contains(&INFO_OP));
        let info = EmulatorInfo {
            cleans: 3,
            realtime: Some(10.0),
            cycles: 12_345,
            cycle_s: 0.001,
            spool_capacity: 100_000,
            start: [1.0, -2.0, 0.5, 0.0, 0.0, 0.0, 0.0, 7.0],
            server: 0x1234_5678_9ABC_DEF0,
        };
        assert_eq!(EmulatorInfo::from_wire(&info.to_wire()), Some(info));
        let stepped = EmulatorInfo {
            realtime: None,
            ..info
        };
        assert_eq!(EmulatorInfo::from_wire(&stepped.to_wire()), Some(stepped));
        assert_eq!(EmulatorInfo::from_wire(&Answer::Ok), None);
        assert_eq!(
            EmulatorInfo::from_wire(&Answer::Ext(Bytes::from_static(&[0; 8]))),
            None
        );
        assert!(is_info(&info_request()));
    }
}
