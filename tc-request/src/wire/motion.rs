//! A motion command in its `MOTION` payload.

use zerocopy::byteorder::little_endian::F64;

use super::layout::{MotionReq, SLOT_F, SLOT_I, WORD_SLOTS};
use crate::axes::{AxisWords, AXES};
use crate::motion::{ArcDir, Motion};

/// The kind codes of the `MOTION` payload (docs/protocol.md, MotionReq).
mod kind {
    pub const LIN: u8 = 1;
    pub const RAP: u8 = 2;
    pub const CIR: u8 = 3;
    pub const JA: u8 = 4;
    pub const JS: u8 = 5;
    pub const SSF: u8 = 6;
    pub const RS: u8 = 7;
}

/// The words of a command: axes, `I J K`, `F`.
type Slots = [Option<f64>; WORD_SLOTS];

fn slots(words: &AxisWords, centre: &[Option<f64>; 3], feed: Option<f64>) -> Slots {
    let mut s = [None; WORD_SLOTS];
    s[..AXES].copy_from_slice(words);
    s[SLOT_I..SLOT_F].copy_from_slice(centre);
    s[SLOT_F] = feed;
    s
}

fn axes_of(s: &Slots) -> AxisWords {
    std::array::from_fn(|k| s[k])
}

/// The kind code, the CCW flag, the SSF axis and function, and the words.
fn parts(m: &Motion) -> (u8, bool, u8, i32, Slots) {
    let none = [None; 3];
    match *m {
        Motion::Lin { words, feed } => (kind::LIN, false, 0, 0, slots(&words, &none, feed)),
        Motion::Rap { words, feed } => (kind::RAP, false, 0, 0, slots(&words, &none, feed)),
        Motion::Cir {
            dir,
            words,
            centre,
            feed,
        } => (
            kind::CIR,
            dir == ArcDir::Ccw,
            0,
            0,
            slots(&words, &centre, feed),
        ),
        Motion::Ja { words } => (kind::JA, false, 0, 0, slots(&words, &none, None)),
        Motion::Js { axes } => (
            kind::JS,
            false,
            0,
            0,
            slots(&axes.map(|a| a.then_some(0.0)), &none, None),
        ),
        Motion::Ssf { axis, function } => (kind::SSF, false, axis, function, [None; WORD_SLOTS]),
        Motion::Rs => (kind::RS, false, 0, 0, [None; WORD_SLOTS]),
    }
}

/// The `MOTION` payload of a command.
pub fn encode(m: &Motion) -> MotionReq {
    let (kind, ccw, axis, function, s) = parts(m);
    let mut present = 0u16;
    for (k, w) in s.iter().enumerate() {
        if w.is_some() {
            present |= 1 << k;
        }
    }
    MotionReq {
        kind,
        ccw: u8::from(ccw),
        axis,
        pad: 0,
        present: present.into(),
        pad2: [0; 2],
        function: function.into(),
        words: s.map(|w| F64::new(w.unwrap_or(0.0))),
    }
}

/// Present bits of the axis words.
const AXIS_BITS: u16 = (1 << AXES) - 1;
/// Present bits of `I J K`.
const CENTRE_BITS: u16 = 0b111 << SLOT_I;
/// Present bit of `F`.
const FEED_BIT: u16 = 1 << SLOT_F;

/// Whether every field the payload's kind does not use is zero: padding,
/// present bits of words the kind does not take, the direction byte
/// (0 or 1 on `CIR`), the axis and function (`SSF` only).
fn reserved_fields_clear(r: &MotionReq) -> bool {
    let (words, max_ccw, ssf) = match r.kind {
        kind::LIN | kind::RAP => (AXIS_BITS | FEED_BIT, 0, false),
        kind::CIR => (AXIS_BITS | CENTRE_BITS | FEED_BIT, 1, false),
        kind::JA | kind::JS => (AXIS_BITS, 0, false),
        kind::SSF => (0, 0, true),
        _ => (0, 0, false),
    };
    r.pad == 0
        && r.pad2 == [0; 2]
        && r.present.get() & !words == 0
        && r.ccw <= max_ccw
        && (ssf || (r.axis == 0 && r.function.get() == 0))
}

/// The command a `MOTION` payload carries; `None` for an unknown kind or
/// a reserved field that is not zero.
pub fn decode(r: &MotionReq) -> Option<Motion> {
    if !reserved_fields_clear(r) {
        return None;
    }
    let present = r.present.get();
    let s: Slots = std::array::from_fn(|k| (present & (1 << k) != 0).then(|| r.words[k].get()));
    let words = axes_of(&s);
    let feed = s[SLOT_F];
    Some(match r.kind {
        kind::LIN => Motion::Lin { words, feed },
        kind::RAP => Motion::Rap { words, feed },
        kind::CIR => Motion::Cir {
            dir: if r.ccw == 1 { ArcDir::Ccw } else { ArcDir::Cw },
            words,
            centre: [s[SLOT_I], s[SLOT_I + 1], s[SLOT_I + 2]],
            feed,
        },
        kind::JA => Motion::Ja { words },
        kind::JS => Motion::Js {
            axes: words.map(|w| w.is_some()),
        },
        kind::SSF => Motion::Ssf {
            axis: r.axis,
            function: r.function.get(),
        },
        kind::RS => Motion::Rs,
        _ => return None,
    })
}
