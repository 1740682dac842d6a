//! The connection behind a Python `Machine` and its handles: the host
//! library's [`addipos_host::Machine`] until `close`, and the way every call
//! reaches it (the GIL released while it runs).

use std::sync::{Arc, Mutex, MutexGuard};

use pyo3::prelude::*;

use crate::errors;

/// One open connection, shared by the `Machine` object and its handles.
#[derive(Debug)]
pub struct Link {
    machine: Mutex<Option<Arc<addipos_host::Machine>>>,
}

impl Link {
    /// A link to an open machine.
    pub fn new(machine: addipos_host::Machine) -> Self {
        Self {
            machine: Mutex::new(Some(Arc::new(machine))),
        }
    }

    fn slot(&self) -> MutexGuard<'_, Option<Arc<addipos_host::Machine>>> {
        self.machine.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The machine, or `Connection` once closed.
    pub fn machine(&self) -> Result<Arc<addipos_host::Machine>, addipos_host::Error> {
        self.slot().clone().ok_or_else(errors::closed)
    }

    /// Whether `close` ran.
    pub fn is_closed(&self) -> bool {
        self.slot().is_none()
    }

    /// Closes the connection: a wait in progress (another thread's) ends,
    /// the recording is written out, later calls answer `Connection`.
    /// Closing twice is allowed.
    pub fn close(&self) {
        if let Some(m) = self.slot().take() {
            m.close();
        }
    }

    /// Runs `call` on the machine with the GIL released; a failure becomes
    /// the exception of its code.
    pub fn call<T: Send>(
        &self,
        py: Python<'_>,
        call: impl FnOnce(&addipos_host::Machine) -> addipos_host::Result<T> + Send,
    ) -> PyResult<T> {
        let machine = self.machine().map_err(|e| errors::to_py(py, &e))?;
        py.detach(move || call(&machine))
            .map_err(|e| errors::to_py(py, &e))
    }
}
