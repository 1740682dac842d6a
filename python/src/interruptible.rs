//! A wait a Python program can cut short: `m.exec()` runs on a thread of
//! its own while the calling thread, the GIL released, looks every few
//! milliseconds whether a signal handler raised (Ctrl-C's
//! `KeyboardInterrupt`); then the wait is given up at once (what ran
//! stays run) and the exception is raised.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::prelude::*;

use crate::errors;

/// How often the calling thread looks for a signal during a wait.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// `EXEC` of `cycles` on `machine`, given up when a signal handler
/// raises.
pub fn exec(
    py: Python<'_>,
    machine: Arc<addipos_host::Machine>,
    cycles: Option<u64>,
) -> PyResult<()> {
    let interrupt = Arc::new(AtomicBool::new(false));
    let (done_tx, done) = mpsc::channel();
    // Shared with the GIL-free closure below (a receiver is not `Sync`).
    let done = Mutex::new(done);
    let waiter = {
        let interrupt = Arc::clone(&interrupt);
        std::thread::spawn(move || {
            let out = machine.exec_until(cycles, &interrupt);
            // The receiver is gone only once this function returned.
            let _ = done_tx.send(out);
        })
    };
    loop {
        let next = py.detach(|| {
            let done = done.lock().unwrap_or_else(|p| p.into_inner());
            done.recv_timeout(SIGNAL_POLL)
        });
        match next {
            Ok(out) => {
                let _ = waiter.join();
                return out.map_err(|e| errors::to_py(py, &e));
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let _ = waiter.join();
                return Err(errors::to_py(
                    py,
                    &addipos_host::Error::new(
                        addipos_host::ErrorCode::Internal,
                        "exec: the wait ended",
                    ),
                ));
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if let Err(signal) = py.check_signals() {
            interrupt.store(true, Ordering::Relaxed);
            py.detach(|| {
                let _ = waiter.join();
            });
            return Err(signal);
        }
    }
}
