//! Any object of bus 1300, found by its address.

use uoi::ObjectAddress;

use crate::bus::TC_BUS;
use crate::otc::{OtcObject, OTC_AXIS_OBJECTS, OTC_GROUP_OBJECTS};
use crate::tc::{TcObject, TC_OBJECTS};

/// Any object of bus 1300: one of the TC module's or one of OTC's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BusObject {
    /// Devices 0 to 2.
    Tc(TcObject),
    /// Devices 3 and 4.
    Otc(OtcObject),
}

impl BusObject {
    /// The object that answers for `addr`, if any (the bus must be 1300).
    pub fn at(addr: ObjectAddress) -> Option<Self> {
        if addr.bus != TC_BUS {
            return None;
        }
        let tc = TC_OBJECTS.iter().find(|r| r.matches(addr));
        let otc = || {
            OTC_GROUP_OBJECTS
                .iter()
                .chain(&OTC_AXIS_OBJECTS)
                .find(|r| r.matches(addr))
        };
        match tc {
            Some(r) => Some(Self::Tc(r.key)),
            None => otc().map(|r| Self::Otc(r.key)),
        }
    }
}
