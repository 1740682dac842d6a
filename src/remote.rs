//! The emulator behind the wire: conversions between `tc-module` commands
//! and elements and their wire form, and the [`Handler`] the TCP server
//! drives.

use std::collections::VecDeque;

use tc_module::{ArcDir, AxisPos, Motion, Origin, Path, SpoolElement, AXES};
use uoi::tcp::Handler;
use uoi::wire::{Answer, Element, MotionKind, Request, WireMotion, SPOOL_BATCH};
use uoi::AccessError;

use crate::Emulator;

/// A motion command in wire form.
pub fn motion_to_wire(m: &Motion) -> WireMotion {
    let mut w = WireMotion {
        kind: MotionKind::Rs,
        ccw: false,
        words: [None; AXES],
        centre: [None; 3],
        feed: None,
        axis: 0,
        function: 0,
    };
    match *m {
        Motion::Lin { words, feed, rapid } => {
            w.kind = if rapid {
                MotionKind::Rap
            } else {
                MotionKind::Lin
            };
            w.words = words;
            w.feed = feed;
        }
        Motion::Cir {
            dir,
            words,
            centre,
            feed,
        } => {
            w.kind = MotionKind::Cir;
            w.ccw = dir == ArcDir::Ccw;
            w.words = words;
            w.centre = centre;
            w.feed = feed;
        }
        Motion::Ja { words } => {
            w.kind = MotionKind::Ja;
            w.words = words;
        }
        Motion::Js { axes } => {
            w.kind = MotionKind::Js;
            w.words = axes.map(|on| on.then_some(0.0));
        }
        Motion::Ssf { axis, function } => {
            w.kind = MotionKind::Ssf;
            w.axis = axis;
            w.function = function;
        }
        Motion::Rs => {}
    }
    w
}

/// The motion command a wire request stands for.
pub fn motion_from_wire(w: &WireMotion) -> Motion {
    match w.kind {
        MotionKind::Lin | MotionKind::Rap => Motion::Lin {
            words: w.words,
            feed: w.feed,
            rapid: w.kind == MotionKind::Rap,
        },
        MotionKind::Cir => Motion::Cir {
            dir: if w.ccw { ArcDir::Ccw } else { ArcDir::Cw },
            words: w.words,
            centre: w.centre,
            feed: w.feed,
        },
        MotionKind::Ja => Motion::Ja { words: w.words },
        MotionKind::Js => Motion::Js {
            axes: w.words.map(|v| v.is_some()),
        },
        MotionKind::Ssf => Motion::Ssf {
            axis: w.axis,
            function: w.function,
        },
        MotionKind::Rs => Motion::Rs,
    }
}

fn origin_code(o: Origin) -> u8 {
    match o {
        Origin::Plain => 0,
        Origin::Approach => 1,
        Origin::Corrected => 2,
        Origin::Transition => 3,
    }
}

fn origin_from(c: u8) -> Origin {
    match c {
        1 => Origin::Approach,
        2 => Origin::Corrected,
        3 => Origin::Transition,
        _ => Origin::Plain,
    }
}

/// A spooled element in wire form.
pub fn element_to_wire(e: &SpoolElement) -> Element {
    Element {
        arc: match &e.path {
            Path::Line => None,
            Path::Arc(a) => Some(([a.plane.h, a.plane.v, a.plane.third], a.centre, a.ccw)),
        },
        start: e.start,
        end: e.end,
        feed: e.feed,
        rapid: e.rapid,
        origin: origin_code(e.origin),
    }
}

/// The spooled element a wire element stands for, or `None` when its plane
/// names an axis that does not exist.
pub fn element_from_wire(e: &Element) -> Option<SpoolElement> {
    let origin = origin_from(e.origin);
    Some(match e.arc {
        None => SpoolElement::line(e.start, e.end, e.feed, e.rapid, origin),
        Some(([h, v, third], centre, ccw)) => {
            if [h, v, third].iter().any(|&a| usize::from(a) >= AXES) {
                return None;
            }
            let plane = tc_module::PlaneAxes { h, v, third };
            SpoolElement::arc(e.start, e.end, plane, centre, ccw, e.feed, origin)
        }
    })
}

/// The emulator as the TCP server's handler.
pub struct EmulatorService {
    emu: Emulator,
    pending: VecDeque<Element>,
}

impl EmulatorService {
    /// Serves a fresh emulator at `start` with cycle `cycle_s`.
    pub fn new(start: AxisPos, cycle_s: f64) -> Self {
        Self {
            emu: Emulator::new(start, cycle_s),
            pending: VecDeque::new(),
        }
    }
}

fn done(r: Result<(), AccessError>) -> Answer {
    match r {
        Ok(()) => Answer::Ok,
        Err(e) => Answer::Access(e),
    }
}

impl Handler for EmulatorService {
    fn handle(&mut self, req: &Request) -> Answer {
        match *req {
            Request::Read(a, ty) => match self.emu.read(a, ty) {
                Ok(v) => Answer::Value(v),
                Err(e) => Answer::Access(e),
            },
            Request::Write(a, v) => done(self.emu.write(a, v)),
            Request::Motion(ref m) => done(self.emu.command(&motion_from_wire(m))),
            Request::Exec(n) => {
                self.emu.exec(n);
                Answer::Ok
            }
            Request::Pos => Answer::Pos(self.emu.position()),
            Request::Queue => Answer::Queue(self.emu.queue_len() as u64),
            Request::Setup { start, cycle_s } => {
                let ok = start
                    .iter()
                    .all(|v| v.is_finite() && v.abs() <= tc_module::module::MAX_COORD)
                    && cycle_s.is_finite()
                    && cycle_s > 0.0
                    && cycle_s <= 1.0;
                if !ok {
                    return Answer::Access(AccessError::Range);
                }
                *self = Self::new(start, cycle_s);
                Answer::Ok
            }
            Request::SpoolLog { logging } => {
                self.pending
                    .extend(self.emu.take_spool_log().iter().map(element_to_wire));
                self.emu.set_spool_log(logging);
                let n = self.pending.len().min(SPOOL_BATCH);
                let batch: Vec<Element> = self.pending.drain(..n).collect();
                Answer::Spool(batch, !self.pending.is_empty())
            }
        }
    }
}

/// A trace target on the far side of a connection.
pub struct RemoteTarget {
    client: uoi::tcp::BlockingClient,
}

fn transport(e: impl std::fmt::Display) -> String {
    format!("(connection: {e})")
}

impl RemoteTarget {
    /// Connects to a server.
    pub fn connect(addr: &str) -> std::io::Result<Self> {
        Ok(Self {
            client: uoi::tcp::BlockingClient::connect(addr)?,
        })
    }

    /// A fresh emulator at the trace's start, with the spool log on.
    pub fn prepare(&mut self, trace: &crate::trace::Trace) -> Result<(), String> {
        let setup = Request::Setup {
            start: trace.start,
            cycle_s: trace.cycle_s,
        };
        match self.client.call(&setup).map_err(transport)? {
            Answer::Ok => {}
            other => return Err(format!("setup refused: {other:?}")),
        }
        crate::trace::Target::take_spooled(self).map(|_| ())
    }

    /// One request on the wire.
    pub fn call(&mut self, req: &Request) -> Result<Answer, uoi::tcp::ClientError> {
        self.client.call(req)
    }
}

/// The wire request for a trace request.
pub fn request_to_wire(req: &crate::trace::Request) -> Request {
    use crate::trace::Request as T;
    match *req {
        T::Write(a, v) => Request::Write(a, v),
        T::Read(a, ty) => Request::Read(a, ty),
        T::Motion(ref m) => Request::Motion(motion_to_wire(m)),
        T::Exec(n) => Request::Exec(n),
        T::Pos => Request::Pos,
        T::Queue => Request::Queue,
    }
}

impl crate::trace::Target for RemoteTarget {
    fn run(&mut self, req: &crate::trace::Request) -> crate::trace::TargetAnswer {
        use crate::trace::TargetAnswer as T;
        match self.client.call(&request_to_wire(req)) {
            Ok(Answer::Ok) => T::Ok,
            Ok(Answer::Value(v)) => T::Value(v),
            Ok(Answer::Pos(p)) => T::Pos(p),
            Ok(Answer::Queue(n)) => T::Queue(usize::try_from(n).unwrap_or(usize::MAX)),
            Ok(Answer::Access(e)) => T::Err(e.name().to_string()),
            Ok(other) => T::Err(format!("(unexpected answer {other:?})")),
            Err(e) => T::Err(transport(e)),
        }
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolElement>, String> {
        let mut out = Vec::new();
        loop {
            match self
                .client
                .call(&Request::SpoolLog { logging: true })
                .map_err(transport)?
            {
                Answer::Spool(els, more) => {
                    for e in &els {
                        out.push(element_from_wire(e).ok_or("spool element with a bad plane")?);
                    }
                    if !more {
                        return Ok(out);
                    }
                }
                other => return Err(format!("(unexpected answer {other:?})")),
            }
        }
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], String> {
        let mut out = [0u8; 3];
        for (sub, o) in out.iter_mut().enumerate() {
            let addr = uoi::ObjectAddress::new(1300, 0, 2, sub as u16);
            let v = self
                .client
                .read(addr, uoi::ValueType::I32)
                .map_err(transport)?;
            *o = v.as_i32().and_then(|i| u8::try_from(i).ok()).unwrap_or(0);
        }
        Ok(out)
    }
}

/// Replays a trace over the wire: a fresh emulator on the server, then the
/// same comparison as in-process.
pub fn replay_remote(
    trace: &crate::trace::Trace,
    target: &mut RemoteTarget,
) -> Vec<crate::trace::Mismatch> {
    if let Err(e) = target.prepare(trace) {
        return vec![crate::trace::Mismatch {
            file: trace.file.clone(),
            line: 0,
            request: "(setup)".into(),
            expected: "a fresh emulator".into(),
            got: e,
        }];
    }
    crate::trace::replay_on(trace, target)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motions_round_trip_through_the_wire_form() {
        let mut words = [None; AXES];
        words[0] = Some(1.0);
        words[2] = Some(-3.0);
        let mut axes = [false; AXES];
        axes[1] = true;
        for m in [
            Motion::Lin {
                words,
                feed: Some(600.0),
                rapid: false,
            },
            Motion::Lin {
                words,
                feed: None,
                rapid: true,
            },
            Motion::Cir {
                dir: ArcDir::Ccw,
                words,
                centre: [Some(1.0), None, Some(2.0)],
                feed: None,
            },
            Motion::Ja { words },
            Motion::Js { axes },
            Motion::Ssf {
                axis: 3,
                function: 2001,
            },
            Motion::Rs,
        ] {
            assert_eq!(motion_from_wire(&motion_to_wire(&m)), m);
        }
    }
}
