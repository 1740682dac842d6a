//! The OTC objects of bus 1300 (docs/objects.md, devices 3 and 4), from
//! the vocabulary crate `tc-objects`: the extension declares them and the
//! TC module appends them to its one map.

pub use tc_objects::{
    OtcObject, OTC_AXIS_DEVICE as AXIS_DEVICE, OTC_AXIS_OBJECTS as AXIS_OBJECTS,
    OTC_GROUP_DEVICE as GROUP_DEVICE, OTC_GROUP_OBJECTS as GROUP_OBJECTS, WEAR_AXIS_SUBS,
};

#[cfg(test)]
mod tests {
    use tc_module::object_map::{object_table, overlapping_rows};

    use crate::OtcExtension;

    #[test]
    fn otc_rows_extend_the_map_without_overlap() {
        let table = object_table::<OtcExtension>();
        assert_eq!(overlapping_rows(&table), vec![]);
        assert_eq!(
            table.len(),
            tc_objects::TC_OBJECTS.len() + super::GROUP_OBJECTS.len() + super::AXIS_OBJECTS.len()
        );
    }
}
