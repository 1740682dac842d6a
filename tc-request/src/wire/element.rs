//! A spool record in its `SPOOL_LOG` element layout.

use zerocopy::byteorder::little_endian::F64;

use super::layout::WireElement;
use crate::element::{ArcRecord, Origin, SpoolRecord};

/// The wire element of a record.
pub fn encode(e: &SpoolRecord) -> WireElement {
    let arc = e.arc.unwrap_or(ArcRecord {
        plane: [0; 3],
        centre: [0.0; 2],
        ccw: false,
    });
    WireElement {
        kind: if e.arc.is_some() { 2 } else { 1 },
        ccw: u8::from(arc.ccw),
        plane_h: arc.plane[0],
        plane_v: arc.plane[1],
        plane_third: arc.plane[2],
        rapid: u8::from(e.rapid),
        origin: e.origin.code(),
        pad: 0,
        start: e.start.map(F64::new),
        end: e.end.map(F64::new),
        centre: arc.centre.map(F64::new),
        feed: e.feed.into(),
    }
}

/// The record of a wire element; `None` for an unknown kind or origin.
pub fn decode(e: &WireElement) -> Option<SpoolRecord> {
    let arc = match e.kind {
        1 => None,
        2 => Some(ArcRecord {
            plane: [e.plane_h, e.plane_v, e.plane_third],
            centre: e.centre.map(|v| v.get()),
            ccw: e.ccw == 1,
        }),
        _ => return None,
    };
    Some(SpoolRecord {
        arc,
        start: e.start.map(|v| v.get()),
        end: e.end.map(|v| v.get()),
        feed: e.feed.get(),
        rapid: e.rapid == 1,
        origin: Origin::from_code(e.origin)?,
    })
}
