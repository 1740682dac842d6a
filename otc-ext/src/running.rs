//! The wear of a group's running OTC period, as a dashboard shows it
//! (the OPC UA machine's tools, the web view): continuous wear and the
//! channel unit's discrete wear, without the axis unit (read as an
//! object of device 4).

use tc_module::{Group, TcModule};

use crate::wear::units::TakenUnits;
use crate::wear::TakenMut;
use crate::OtcExtension;

/// The wear (mm) of group `g`'s running OTC period without the axis unit,
/// and the machine axis whose unit it also takes, if any.
pub fn running_wear(tc: &TcModule<OtcExtension>, g: &Group<OtcExtension>) -> (f64, Option<usize>) {
    let s = &g.ext;
    let taken = TakenUnits::of(s.proc_type, s.mode, tc.main_axes().plane.third);
    let channel_only = TakenUnits {
        axis: None,
        ..taken
    };
    let mut unit = s.radius_unit;
    let w_disc = TakenMut::lend(channel_only, &mut unit, &mut []).w_disc();
    (s.wear.w_cont + w_disc, taken.axis)
}
