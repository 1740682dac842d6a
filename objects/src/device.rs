//! The devices of bus 1300: what each holds and what its index means
//! (the sections of docs/objects.md).

use crate::otc::{OTC_AXIS_DEVICE, OTC_GROUP_DEVICE};
use crate::tc::TcObject;

/// One device of the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeviceDesc {
    /// The DeviceNumber.
    pub number: u16,
    /// Its heading: `Device 1: compensation groups and their tool tables`.
    pub title: &'static str,
    /// What its index means, in words.
    pub index: &'static str,
}

/// Every device of bus 1300, in number order.
pub static DEVICES: [DeviceDesc; 5] = [
    DeviceDesc {
        number: TcObject::Clean.row().device,
        title: "Device 0: initialisation (global)",
        index: "Index: the object.",
    },
    DeviceDesc {
        number: TcObject::Radius.row().device,
        title: "Device 1: compensation groups and their tool tables",
        index: "Index: the group, 1..=32. Each group has a tool table of 1024 entries \
                (WKZINDEX 0..1023) holding a radius and a length.",
    },
    DeviceDesc {
        number: TcObject::TransitionMode.row().device,
        title: "Device 2: TC extensions",
        index: "Index: the group, 1..=32.",
    },
    DeviceDesc {
        number: OTC_GROUP_DEVICE,
        title: "Device 3: OTC online wear compensation, per group",
        index: "Index: the group, 1..=32. The Tool objects (30..33) read and write the entry \
                at the group's WKZINDEX, like RADIUS.",
    },
    DeviceDesc {
        number: OTC_AXIS_DEVICE,
        title: "Device 4: OTC control units of the machine axes",
        index: "Index: the machine axis, 0..7.",
    },
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{OTC_AXIS_OBJECTS, OTC_GROUP_OBJECTS, TC_OBJECTS};

    #[test]
    fn every_row_has_its_device_and_every_device_rows() {
        let rows = || {
            let tc = TC_OBJECTS.iter().map(|r| r.device);
            let otc = OTC_GROUP_OBJECTS
                .iter()
                .chain(&OTC_AXIS_OBJECTS)
                .map(|r| r.device);
            tc.chain(otc)
        };
        for d in rows() {
            assert!(DEVICES.iter().any(|x| x.number == d), "device {d}");
        }
        for (i, d) in DEVICES.iter().enumerate() {
            assert_eq!(usize::from(d.number), i);
            assert!(rows().any(|r| r == d.number), "{}", d.title);
        }
    }
}
