//! The command line of `addipos serve`: its options and their help.

use std::path::PathBuf;

/// The command line of `serve` (its help texts are these comments).
#[derive(Debug, Default, clap::Args)]
pub struct ServeArgs {
    /// Settings file (TOML, keys as in emulator/config/default.toml;
    /// `--print-default-config` prints it).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Listen address, overriding the settings: HOST:PORT,
    /// localhost:PORT, or a bare PORT (on 127.0.0.1).
    #[arg(long, value_name = "ADDR")]
    pub listen: Option<String>,
    /// Allow listening on a non-loopback address.
    #[arg(long)]
    pub allow_remote: bool,
    /// Folder of the server's files (tool data, access token, OPC UA
    /// certificate),
    /// overriding `data_dir` of the settings (default `data`).
    #[arg(long, value_name = "DIR")]
    pub data_dir: Option<PathBuf>,
    /// Keep tool data in memory only: no tool file or journal is read or
    /// written (a throw-away emulator). The access token and the OPC UA
    /// certificate, when used, are still kept in the data directory.
    #[arg(long)]
    pub no_persist: bool,
    /// Start even when tool files or the tool journal hold bad lines:
    /// they are skipped and reported instead of refusing to start.
    #[arg(long)]
    pub ignore_bad_tools: bool,
    /// Serve OPC UA too (docs/opcua.md), at ADDR or else at `listen` of
    /// the `[opcua]` settings (127.0.0.1:4840).
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "")]
    pub opcua: Option<String>,
    /// Run the executor with the wall clock, FACTOR times faster (0.01 to
    /// 10000, default 1): EXEC then waits for the clock. Overrides
    /// `realtime` of the settings. Conformance sessions (SETUP) stay
    /// stepped.
    #[arg(long, value_name = "FACTOR", num_args = 0..=1, default_missing_value = "1")]
    pub realtime: Option<f64>,
    /// Record everything the shared emulator carries out (every
    /// connection, the OPC UA face) as one trace into FILE, for `addipos
    /// replay` (docs/host-api.md, "Recording").
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// Serve the live web view (docs/web.md) at ADDR: HOST:PORT or a bare
    /// PORT (on 127.0.0.1); without ADDR at 127.0.0.1:8300. Another than
    /// a loopback address needs --allow-remote and the access token, as
    /// the UOI face.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = DEFAULT_WEB)]
    pub web: Option<String>,
}

/// Where `--web` without an address serves the view.
const DEFAULT_WEB: &str = "127.0.0.1:8300";
