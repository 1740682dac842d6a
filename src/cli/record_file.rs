//! Where `serve --record FILE` writes its trace: the command line opens
//! the destination (only the command line and the storage layer touch
//! files), the shared emulator's recorder (`emulator::record::ServeRecorder`)
//! writes to it on its writer thread (decision 510).

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The trace's file: its `flush`, which the recorder calls once at the
/// end, hands the data to the disk too (a FIFO or a terminal has nothing
/// to sync).
#[derive(Debug)]
pub struct TraceFile(File);

impl Write for TraceFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()?;
        let _ = self.0.sync_data();
        Ok(())
    }
}

/// The destination, opened when the recorder's writer thread asks.
enum Destination {
    /// A file created at the start (an error stops the start).
    Created(File),
    /// A FIFO: opening it waits for its reader, which must not hold the
    /// server's start, so the writer thread opens it.
    Fifo(PathBuf),
}

/// Creates `path`, or leaves a FIFO at `path` for the writer thread to
/// open; the opener the recorder runs on its thread.
pub fn opener(path: &Path) -> io::Result<impl FnOnce() -> io::Result<TraceFile> + Send + 'static> {
    let dest = if is_fifo(path) {
        Destination::Fifo(path.to_path_buf())
    } else {
        Destination::Created(File::create(path)?)
    };
    Ok(move || match dest {
        Destination::Created(f) => Ok(TraceFile(f)),
        Destination::Fifo(p) => OpenOptions::new().write(true).open(p).map(TraceFile),
    })
}

/// Whether `path` is a FIFO.
fn is_fifo(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo())
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}
