//! Why an access error happened, in the words a user acts on: the range
//! an object takes, the feed that is too slow and the smallest feed
//! there is, the group that is faulted and how to clear it. The access
//! error's name and code stay as they are (a trace names only them);
//! this is what the library's message adds after it.

use tc_module::limits::{within_limit, MAX_COORD, MIN_STEP};
use tc_objects::{bit_meaning, camel_name, ErrorBits, OTC_AXIS_OBJECTS, OTC_GROUP_OBJECTS};
use tc_objects::{TcObject, GROUPS, TC_OBJECTS};
use tc_request::{Motion, Request, AXIS_NAMES};
use uoi::{lookup, AccessError, ObjectAddress, ObjectDesc, Value};

/// What a write refused with `Range` should have been: the object's
/// name and range (`RADIUS takes >= 0`).
pub fn write_range(addr: ObjectAddress, value: Value) -> Option<String> {
    let (name, range) = row(&TC_OBJECTS, addr)
        .or_else(|| row(&OTC_GROUP_OBJECTS, addr))
        .or_else(|| row(&OTC_AXIS_OBJECTS, addr))?;
    Some(format!("{name} takes {range}; {value} is outside it"))
}

fn row<K>(table: &[ObjectDesc<K>], addr: ObjectAddress) -> Option<(&'static str, uoi::ValueRange)> {
    lookup(table, addr).ok().map(|r| (r.name, r.range))
}

/// The smallest feed (units/min) that steps at least the smallest step
/// per cycle of `cycle_s` seconds.
pub fn smallest_feed(cycle_s: f64) -> f64 {
    MIN_STEP * 60.0 / cycle_s
}

/// What in a motion refused with `Range` is out of range: its feed (too
/// slow, negative, not a number) or a coordinate beyond ±1e9.
pub fn motion_range(m: &Motion, cycle_s: f64) -> Option<String> {
    let (words, feed) = match m {
        Motion::Lin { words, feed } | Motion::Rap { words, feed } => (words, *feed),
        Motion::Cir { words, feed, .. } => (words, *feed),
        Motion::Ja { words } => (words, None),
        _ => return None,
    };
    if let Some(f) = feed {
        let least = smallest_feed(cycle_s);
        if !f.is_finite() || f.abs() > MAX_COORD {
            return Some(format!("the feed F{f} is not a number within ±1e9"));
        }
        if f < 0.0 {
            return Some(format!(
                "the feed F{f} is negative (a feed is above 0; 0 in C, or no F, is the modal feed)"
            ));
        }
        if f < least {
            return Some(format!(
                "the feed F{f} is below the smallest feed, F{} (units/min: one step of {MIN_STEP} \
                 per interpolation cycle of {} ms)",
                tidy(least),
                tidy(cycle_s * 1e3)
            ));
        }
    }
    let beyond = words
        .iter()
        .zip(AXIS_NAMES)
        .find_map(|(w, name)| w.filter(|&v| !within_limit(v)).map(|v| (name, v)));
    beyond.map(|(name, v)| format!("{name}{v} lies beyond ±1e9, the limit of every coordinate"))
}

/// A number without the noise of its binary form (`0.006`, not
/// `0.006000000000000001`).
fn tidy(v: f64) -> String {
    let s = format!("{v:.9}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Why a motion was refused with `State` when a group is faulted: the
/// group, its ERROR bits with what they mean, and how to clear it.
/// `errors` gives each group's ERROR register (`None`: unread).
pub fn faulted_groups(errors: &[(u16, Option<i32>)]) -> Option<String> {
    let faulted: Vec<String> = errors
        .iter()
        .filter_map(|&(g, bits)| bits.filter(|&b| b != 0).map(|b| (g, b)))
        .map(|(g, b)| {
            let names: Vec<String> = ErrorBits::from_bits_retain(b)
                .iter_names()
                .map(|(n, _)| {
                    let name = camel_name(n);
                    match bit_meaning(&name) {
                        Some(m) => format!("{name}: {m}"),
                        None => name,
                    }
                })
                .collect();
            format!(
                "group {g} is faulted (ERROR {} = 0x{b:x}: {}); writing ERROR (any value) clears \
                 it",
                TcObject::Error.of(g),
                names.join("; ")
            )
        })
        .collect();
    (!faulted.is_empty()).then(|| faulted.join(", and "))
}

/// The ERROR registers to read to explain a `State` refusal of `req`
/// (a motion: refused while a group is faulted).
pub fn error_registers(req: &Request, e: AccessError) -> Vec<(u16, ObjectAddress)> {
    if e != AccessError::State || !matches!(req, Request::Motion(_)) {
        return Vec::new();
    }
    GROUPS.map(|g| (g, TcObject::Error.of(g))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_messages_say_the_range_the_smallest_feed_and_the_faulted_group() {
        let radius = TcObject::Radius.of(1);
        let w = write_range(radius, Value::F64(5e9)).unwrap();
        assert!(w.starts_with("RADIUS takes"), "{w}");
        let mut words = [None; 8];
        words[0] = Some(1.0);
        let slow = Motion::Lin {
            words,
            feed: Some(0.1),
        };
        let m = motion_range(&slow, 0.001).unwrap();
        assert!(m.contains("smallest feed, F0.6 "), "{m}");
        let f = faulted_groups(&[(1, Some(2)), (2, Some(0))]).unwrap();
        assert!(f.contains("group 1 is faulted"), "{f}");
        assert!(f.contains("KorrError"), "{f}");
        assert!(f.contains("writing ERROR"), "{f}");
        assert_eq!(faulted_groups(&[(1, Some(0))]), None);
    }
}
