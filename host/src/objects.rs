//! Object descriptors: the four numbers a host program names an object
//! by, checked against the table of every bus-1300 object before a handle
//! is issued.

use tc_objects::{OTC_AXIS_OBJECTS, OTC_GROUP_OBJECTS, TC_BUS, TC_OBJECTS};
use uoi::{lookup, AccessError, ObjectAddress, ObjectDesc, ValueType};

/// An object descriptor as a PCAP program fills it in: BusNumber,
/// DeviceNumber, Index, SubIndex (the C ABI's `uoi_descriptor`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Descriptor {
    /// BusNumber: 1300 for the TC module.
    pub bus_number: i32,
    /// DeviceNumber: 0 initialisation, 1 groups and tool tables, 2 TC
    /// extensions, 3 OTC per group, 4 OTC per machine axis.
    pub device_number: i32,
    /// Index: the object (device 0), the group (1 to 3) or the axis (4).
    pub index: i32,
    /// SubIndex: the function number.
    pub sub_index: i32,
}

impl Descriptor {
    /// The descriptor of `addr`.
    pub fn of(addr: ObjectAddress) -> Self {
        Self {
            bus_number: addr.bus.into(),
            device_number: addr.device.into(),
            index: addr.index.into(),
            sub_index: addr.sub.into(),
        }
    }
}

impl std::fmt::Display for Descriptor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}/{}/{}/{}",
            self.bus_number, self.device_number, self.index, self.sub_index
        )
    }
}

/// The type of the row of `table` that answers for `addr`.
fn type_in<K>(table: &[ObjectDesc<K>], addr: ObjectAddress) -> Result<ValueType, AccessError> {
    lookup(table, addr).map(|row| row.ty)
}

/// The address and value type of the object `d` names: `NoObject` when
/// bus, device or index does not exist (a number outside 0..=65535
/// included), `NoSubindex` when the index exists but the subindex does
/// not.
pub fn find_object(d: &Descriptor) -> Result<(ObjectAddress, ValueType), AccessError> {
    let part = |n: i32| u16::try_from(n).map_err(|_| AccessError::NoObject);
    let (bus, device, index) = (part(d.bus_number)?, part(d.device_number)?, part(d.index)?);
    if bus != TC_BUS {
        return Err(AccessError::NoObject);
    }
    // No object has subindex 65535: one outside the u16 range is looked
    // up as that, so that an existing index answers NoSubindex.
    let sub = u16::try_from(d.sub_index).unwrap_or(u16::MAX);
    let addr = ObjectAddress::new(bus, device, index, sub);
    let answers = [
        type_in(&TC_OBJECTS, addr),
        type_in(&OTC_GROUP_OBJECTS, addr),
        type_in(&OTC_AXIS_OBJECTS, addr),
    ];
    if let Some(ty) = answers.iter().find_map(|a| a.ok()) {
        return Ok((addr, ty));
    }
    if answers.contains(&Err(AccessError::NoSubindex)) {
        return Err(AccessError::NoSubindex);
    }
    Err(AccessError::NoObject)
}

#[cfg(test)]
mod tests {
    use super::*;
    use emulator::Emulator;
    use tc_objects::TcObject;
    use uoi::Bus;

    #[test]
    fn the_lookup_agrees_with_the_emulators_table_everywhere() {
        let emu = Emulator::default();
        let table = emu.tc().objects();
        // Every address of bus 1300 in the box, objects or not: Clean's
        // address with its device, index and subindex replaced.
        let clean = TcObject::Clean.address();
        for device in 0..6 {
            for index in 0..40 {
                for sub in 0..70 {
                    let addr = ObjectAddress {
                        device,
                        index,
                        sub,
                        ..clean
                    };
                    let want = lookup(table, addr).map(|r| (addr, r.ty));
                    let got = find_object(&Descriptor::of(addr));
                    assert_eq!(got, want, "{addr}");
                }
            }
        }
    }

    #[test]
    fn numbers_outside_the_address_range_do_not_exist() {
        // TcPlane's and group 1's ERROR descriptors with one number
        // changed (docs/decisions.md, decision 522).
        let plane = Descriptor::of(TcObject::TcPlane.address());
        let error = Descriptor::of(TcObject::Error.of(1));
        let bus = plane.bus_number;
        assert_eq!(
            find_object(&Descriptor {
                bus_number: bus + 1,
                ..plane
            }),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            find_object(&Descriptor {
                bus_number: -bus,
                ..plane
            }),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            find_object(&Descriptor {
                device_number: -1,
                ..plane
            }),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            find_object(&Descriptor {
                index: 70_000,
                ..error
            }),
            Err(AccessError::NoObject)
        );
        assert_eq!(
            find_object(&Descriptor {
                sub_index: -1,
                ..error
            }),
            Err(AccessError::NoSubindex)
        );
        assert_eq!(
            find_object(&Descriptor {
                device_number: 9,
                sub_index: -1,
                ..error
            }),
            Err(AccessError::NoObject)
        );
        let radius = find_object(&Descriptor::of(TcObject::Radius.of(1))).unwrap();
        assert_eq!(radius.1, ValueType::F64);
        assert_eq!(radius.0, TcObject::Radius.of(1));
    }
}
