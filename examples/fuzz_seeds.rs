//! Writes the seed corpus of the fuzz targets that take frames
//! (docs/fuzzing.md): for each trace of `traces/`, the frames a
//! conformance client sends to replay it, into
//! `fuzz/seeds/frame_sequence/` and `fuzz/seeds/frame_decoder/` (there
//! with a first byte, the read size, of 0). Run from the repository root:
//! `cargo run --example fuzz_seeds`.

use std::path::Path;

use fuzz_checks::{request_stream, trace_requests};
use trace::{load_corpus, TraceFileError};

/// Why the seeds could not be written.
#[derive(Debug, thiserror::Error)]
enum SeedError {
    /// The corpus could not be read.
    #[error(transparent)]
    Corpus(#[from] TraceFileError),
    /// A folder or a seed file could not be written.
    #[error("{name}: {source}")]
    Write {
        /// The folder or file, as shown.
        name: String,
        /// Why.
        source: std::io::Error,
    },
}

fn main() -> Result<(), SeedError> {
    let traces = load_corpus(Path::new("traces"))?;
    let seqs = Path::new("fuzz/seeds/frame_sequence");
    let frames = Path::new("fuzz/seeds/frame_decoder");
    for dir in [seqs, frames] {
        std::fs::create_dir_all(dir).map_err(|source| SeedError::Write {
            name: dir.display().to_string(),
            source,
        })?;
    }
    for trace in &traces {
        let file = Path::new(&trace.header.file);
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        let stream = request_stream(&trace_requests(trace));
        let name = format!("{stem}.bin");
        let write = |dir: &Path, bytes: &[u8]| {
            std::fs::write(dir.join(&name), bytes).map_err(|source| SeedError::Write {
                name: name.clone(),
                source,
            })
        };
        write(seqs, &stream)?;
        write(frames, &[[0u8].as_slice(), &stream].concat())?;
    }
    println!("{} traces written as seeds", traces.len());
    Ok(())
}
