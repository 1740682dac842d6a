//! `addipos.Machine`: one connection, as `addipos.open` gives it — the
//! object interface (handles, reads, writes), motion, the executor,
//! the position, recording. A context manager: `with addipos.open() as m:`
//! closes it at the end of the block.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use addipos_host::{find_object, Descriptor, Target, AXES};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::errors;
use crate::handle::{self, Handle};
use crate::interruptible;
use crate::link::Link;
use crate::numbers;
use crate::pyside;
use crate::spooled;
use crate::words::{self, Allowed};

/// One connection to a TC module (from `addipos.open`).
#[pyclass(name = "Machine", module = "addipos", frozen)]
#[derive(Debug)]
pub struct PyMachine {
    link: Arc<Link>,
    target: String,
}

/// A timeout in seconds as a duration; not a finite number ≥ 0 is
/// `addipos.Argument`.
fn seconds(py: Python<'_>, s: f64) -> PyResult<Duration> {
    Duration::try_from_secs_f64(s)
        .map_err(|_| errors::argument(py, format!("timeout {s}: not a number of seconds ≥ 0")))
}

impl PyMachine {
    /// Opens `target`; with `record`, the session is recorded there
    /// (and `$ADDIPOS_RECORD` is not read).
    pub fn open(
        py: Python<'_>,
        target: &str,
        record: Option<PathBuf>,
        timeout: Option<f64>,
    ) -> PyResult<Self> {
        let timeout = timeout.map(|s| seconds(py, s)).transpose()?;
        let target = target.to_string();
        let opened = py.detach(move || -> addipos_host::Result<addipos_host::Machine> {
            let m = match &record {
                None => addipos_host::Machine::open(&target)?,
                Some(path) => {
                    let m = addipos_host::Machine::open_target(&Target::parse(&target)?)?;
                    m.record(path)?;
                    m
                }
            };
            if let Some(t) = timeout {
                m.set_timeout(t);
            }
            Ok(m)
        });
        let m = opened.map_err(|e| errors::to_py(py, &e))?;
        Ok(Self {
            target: m.target().to_string(),
            link: Arc::new(Link::new(m)),
        })
    }

    fn handle_of(h: &Bound<'_, Handle>) -> addipos_host::Handle {
        h.get().raw
    }

    fn motion(
        &self,
        py: Python<'_>,
        call: impl FnOnce(&addipos_host::Machine) -> addipos_host::Result<()> + Send,
    ) -> PyResult<()> {
        self.link.call(py, call)
    }
}

/// The connection; handles, reads and writes; motion and the executor;
/// recording (one block: PyO3 takes one `#[pymethods]` per class).
#[pymethods]
impl PyMachine {
    // The connection.

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// Closes the connection, with the GIL released (another thread's
    /// wait ends at once; other Python threads go on meanwhile).
    #[pyo3(signature = (*_exc))]
    fn __exit__(&self, py: Python<'_>, _exc: &Bound<'_, PyTuple>) -> bool {
        let link = Arc::clone(&self.link);
        py.detach(move || link.close());
        false
    }

    /// Closes the connection: a wait of another thread ends, the recording
    /// is written out, later calls raise `addipos.Connection`. Closing
    /// twice does nothing.
    fn close(&self, py: Python<'_>) {
        let link = Arc::clone(&self.link);
        py.detach(move || link.close());
    }

    /// Whether the connection is closed.
    #[getter]
    fn closed(&self) -> bool {
        self.link.is_closed()
    }

    /// The target, as a target string names it (`"embedded"`, ...).
    #[getter]
    fn target(&self) -> &str {
        &self.target
    }

    /// The real-time factor, or `None` when stepped.
    #[getter]
    fn realtime(&self, py: Python<'_>) -> PyResult<Option<f64>> {
        self.link.call(py, |m| Ok(m.realtime()))
    }

    /// The longest `exec` wait, in seconds (30 by default).
    fn set_timeout(&self, py: Python<'_>, seconds: f64) -> PyResult<()> {
        let t = self::seconds(py, seconds)?;
        self.link.call(py, move |m| {
            m.set_timeout(t);
            Ok(())
        })
    }

    fn __repr__(&self) -> String {
        let state = if self.link.is_closed() { " closed" } else { "" };
        format!("<addipos.Machine {}{state}>", self.target)
    }

    // Handles, reads and writes.

    /// A handle to the object `bus/device/index/subindex` (`uoi_init`);
    /// raises `addipos.NoObject` or `addipos.NoSubindex` when it does not
    /// exist.
    fn init(
        &self,
        py: Python<'_>,
        bus: &Bound<'_, PyAny>,
        device: &Bound<'_, PyAny>,
        index: &Bound<'_, PyAny>,
        subindex: &Bound<'_, PyAny>,
    ) -> PyResult<Handle> {
        // A number beyond i32, of any size, names no object, as one beyond
        // 0..65535 (NoObject, not OverflowError).
        let part = |name: &str, n: &Bound<'_, PyAny>| match numbers::saturating_int(n) {
            Some(v) => Ok(i32::try_from(v).unwrap_or(-1)),
            None => Err(errors::argument(
                py,
                format!("init: {name}={} is not an integer", handle::repr(n)),
            )),
        };
        let d = Descriptor {
            bus_number: part("bus", bus)?,
            device_number: part("device", device)?,
            index: part("index", index)?,
            sub_index: part("subindex", subindex)?,
        };
        let raw = self.link.call(py, move |m| m.handle(&d))?;
        // The object exists: the library has just found it.
        let ty = find_object(&d)
            .map(|(_, ty)| ty)
            .unwrap_or(uoi::ValueType::I32);
        Ok(Handle::new(Arc::clone(&self.link), raw, d, ty))
    }

    /// Releases a handle (`uoi_clean_handle`): it raises
    /// `addipos.StaleHandle` from now on.
    fn release(&self, py: Python<'_>, h: &Bound<'_, Handle>) -> PyResult<()> {
        let raw = Self::handle_of(h);
        self.link.call(py, move |m| m.release(raw))
    }

    /// Reads an i32 object through handle `h`.
    fn read_int(&self, py: Python<'_>, h: &Bound<'_, Handle>) -> PyResult<i32> {
        handle::read_int(&self.link, py, Self::handle_of(h))
    }

    /// Reads a double object through handle `h`.
    fn read_double(&self, py: Python<'_>, h: &Bound<'_, Handle>) -> PyResult<f64> {
        handle::read_double(&self.link, py, Self::handle_of(h))
    }

    /// Writes an i32 object through handle `h`.
    fn write_int(
        &self,
        py: Python<'_>,
        h: &Bound<'_, Handle>,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        handle::write_int(&self.link, py, Self::handle_of(h), value)
    }

    /// Writes a double object through handle `h`.
    fn write_double(&self, py: Python<'_>, h: &Bound<'_, Handle>, value: f64) -> PyResult<()> {
        handle::write_double(&self.link, py, Self::handle_of(h), value)
    }

    // Motion and the executor.

    /// `LIN`: a feed line to the absolute end point of the axes named
    /// (`X=50, Y=0`); `F` sets the modal feed (units/min).
    #[pyo3(signature = (**words))]
    fn lin(&self, py: Python<'_>, words: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let w = words::read(
            py,
            "lin",
            words,
            Allowed {
                feed: true,
                centre: false,
            },
        )?;
        self.motion(py, move |m| m.lin(w.axes, w.feed))
    }

    /// `RAP`: a rapid line to the axes named (`F` only sets the modal
    /// feed).
    #[pyo3(signature = (**words))]
    fn rap(&self, py: Python<'_>, words: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let w = words::read(
            py,
            "rap",
            words,
            Allowed {
                feed: true,
                centre: false,
            },
        )?;
        self.motion(py, move |m| m.rap(w.axes, w.feed))
    }

    /// `CIR`: an arc in the main plane, `"CW"` or `"CCW"`, to the axes
    /// named, with the centre `I J K` seen from the start.
    #[pyo3(signature = (direction, **words))]
    fn cir(
        &self,
        py: Python<'_>,
        direction: &str,
        words: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let dir = words::arc_dir(py, direction)?;
        let w = words::read(
            py,
            "cir",
            words,
            Allowed {
                feed: true,
                centre: true,
            },
        )?;
        self.motion(py, move |m| m.cir(dir, w.axes, w.centre, w.feed))
    }

    /// `JA`: direct positioning of the axes named; drops what waits in the
    /// spooler and the correction buffer.
    #[pyo3(signature = (**words))]
    fn ja(&self, py: Python<'_>, words: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let w = words::read(
            py,
            "ja",
            words,
            Allowed {
                feed: false,
                centre: false,
            },
        )?;
        self.motion(py, move |m| m.ja(w.axes))
    }

    /// `JS`: direct stop of the axes named (`m.js("X", "Y")`; names or
    /// numbers 0..7).
    #[pyo3(signature = (*axes))]
    fn js(&self, py: Python<'_>, axes: &Bound<'_, PyTuple>) -> PyResult<()> {
        let mut mask = [false; AXES];
        for a in axes.iter() {
            let i = words::axis(py, "js", &a)?;
            if let Some(bit) = mask.get_mut(i) {
                *bit = true;
            }
        }
        self.motion(py, move |m| m.js(mask))
    }

    /// `SSF`: special function `function` to an axis (a name or 0..7);
    /// `m.ssf("X", 2001)` spools the held profile.
    fn ssf(
        &self,
        py: Python<'_>,
        axis: &Bound<'_, PyAny>,
        function: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let a = words::axis(py, "ssf", axis)?;
        let function = numbers::i32_of(function).ok_or_else(|| {
            errors::argument(
                py,
                format!(
                    "ssf: function {} is not a 32-bit integer (-2147483648..2147483647)",
                    handle::repr(function)
                ),
            )
        })?;
        self.motion(py, move |m| m.ssf(a, function))
    }

    /// `RS`: the legacy `rs()`, the coordinate rotation back to 0.
    fn rs(&self, py: Python<'_>) -> PyResult<()> {
        self.motion(py, |m| m.rs())
    }

    /// `EXEC`: runs `cycles` interpolation cycles, or with `None` until
    /// the spooler is empty. Stepped it runs them now; in real time it
    /// waits for the clock. Raises `addipos.Timeout` after the timeout
    /// (what ran stays run).
    ///
    /// The GIL is released while it waits; in real time or on a server,
    /// Ctrl-C (or any signal handler that raises) ends the wait within a
    /// few milliseconds and raises there (`KeyboardInterrupt`); what ran
    /// stays run.
    #[pyo3(signature = (cycles=None))]
    fn exec(&self, py: Python<'_>, cycles: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let n = match cycles {
            None => None,
            Some(c) => Some(c.extract::<u64>().map_err(|_| {
                errors::argument(
                    py,
                    format!("exec: cycles={} is not a count ≥ 0", handle::repr(c)),
                )
            })?),
        };
        let machine = self.link.machine().map_err(|e| errors::to_py(py, &e))?;
        if !machine.exec_waits() {
            // Stepped and embedded: computing, not waiting (and bounded by
            // the timeout): no thread of its own.
            return self.link.call(py, move |m| m.exec(n));
        }
        interruptible::exec(py, machine, n)
    }

    /// The executed position of the 8 axes, an `addipos.Position`
    /// (`X Y Z A B C U V`).
    fn pos(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let p = self.link.call(py, |m| m.position())?;
        pyside::position(py, p)
    }

    /// Motion waiting: spooled elements plus plane-null profiles waiting
    /// with the held one.
    fn queue(&self, py: Python<'_>) -> PyResult<u64> {
        self.link.call(py, |m| m.queue())
    }

    // The spool log.

    /// Keeps the elements every request spools from now on (`True`), for
    /// `take_spooled`, or stops keeping them (`False`).
    fn spool_log(&self, py: Python<'_>, on: bool) -> PyResult<()> {
        self.link.call(py, move |m| {
            m.set_spool_log(on);
            Ok(())
        })
    }

    /// The elements spooled since the last call while the spool log is on,
    /// as `addipos.Element` tuples: the corrected path.
    fn take_spooled(&self, py: Python<'_>) -> PyResult<Vec<Py<PyAny>>> {
        let taken = self.link.call(py, |m| Ok(m.take_spooled()))?;
        taken.iter().map(|e| spooled::element(py, e)).collect()
    }

    // Recording.

    /// Records the session as a trace into the file `path`; only before
    /// the first request (else `addipos.Record`).
    fn record(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        self.link.call(py, move |m| m.record(&path))
    }

    /// Ends the recording: everything is written to the file.
    fn stop_recording(&self, py: Python<'_>) -> PyResult<()> {
        self.link.call(py, |m| {
            m.stop_recording();
            Ok(())
        })
    }

    /// Whether a recording is going on.
    #[getter]
    fn recording(&self, py: Python<'_>) -> PyResult<bool> {
        self.link.call(py, |m| Ok(m.recording()))
    }

    /// Why the recording stopped or did not start, if it did not go on
    /// (a write error, a file `$ADDIPOS_RECORD` names that cannot be
    /// created); `None` otherwise.
    #[getter]
    fn record_failure(&self, py: Python<'_>) -> PyResult<Option<String>> {
        self.link.call(py, |m| Ok(m.record_failure()))
    }
}
