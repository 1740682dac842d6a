//! Target strings: what `addipos_open` connects to.
//!
//! * `""` (or NULL): `$ADDIPOS_TARGET` if it is set and not empty, else
//!   `embedded`;
//! * `embedded`: an emulator inside the calling process with the built-in
//!   settings (`emulator::DEFAULT_CONFIG`), stepped: nothing moves but by
//!   `tc_exec`;
//! * `embedded:OPTION,OPTION...` with the options `realtime` (the
//!   executor runs with the wall clock), `realtime=FACTOR` (FACTOR times
//!   faster, 0.01 to 10000) and `config=FILE` (the settings of a file of
//!   `addipos serve`'s form: `cycle_ms`, `spool_capacity` and `start` are
//!   used; a path without commas);
//! * `HOST:PORT`, `localhost:PORT`, `[::1]:PORT` or a bare `PORT`: a
//!   running `addipos serve` (`crate::served`), optionally followed by
//!   `,token=TOKEN` or `,token_file=FILE` (`crate::served_target`).

use std::path::PathBuf;

use emulator::{Config, RealTimeFactor, DEFAULT_CONFIG};
use tc_module::check_capacity;
use tc_module::limits::check_point;
use tc_module::{AxisPos, CycleTime};

use crate::error::{Error, Result};

/// The environment variable read when the target is empty.
pub const TARGET_ENV: &str = "ADDIPOS_TARGET";

/// The settings of an embedded emulator.
#[derive(Debug, Clone, PartialEq)]
pub struct EmbeddedOptions {
    /// Real time with this factor; `None`: stepped.
    pub realtime: Option<RealTimeFactor>,
    /// Machine position at start.
    pub start: AxisPos,
    /// Interpolation cycle.
    pub cycle: CycleTime,
    /// The interpolation cycle in ms as the settings gave it (the trace
    /// header of a recording repeats it).
    pub cycle_ms: f64,
    /// Elements the spooler holds.
    pub spool_capacity: usize,
}

impl Default for EmbeddedOptions {
    /// The built-in settings, stepped.
    fn default() -> Self {
        let c = Config::default();
        Self {
            realtime: None,
            start: c.start,
            cycle: CycleTime::DEFAULT,
            cycle_ms: c.cycle_ms,
            spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY,
        }
    }
}

impl EmbeddedOptions {
    /// The emulator settings of a `serve` settings text (`cycle_ms`,
    /// `spool_capacity`, `start`), checked like `serve` checks them.
    pub fn from_config(text: &str) -> Result<Self> {
        let bad = |m: String| Error::argument(m);
        let c = Config::parse(text).map_err(|e| bad(e.0))?;
        let cycle = c.cycle().map_err(|e| bad(e.0))?;
        let spool_capacity = check_capacity(c.spool_capacity)
            .map_err(|e| bad(format!("spool_capacity = {}: {e}", c.spool_capacity)))?;
        check_point(&c.start)
            .map_err(|_| bad("start: every axis must lie within ±1e9".to_string()))?;
        let realtime = c.realtime().map_err(|e| bad(e.0))?;
        Ok(Self {
            realtime,
            start: c.start,
            cycle,
            cycle_ms: c.cycle_ms,
            spool_capacity,
        })
    }
}

/// What a connection talks to.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// An emulator inside this process.
    Embedded(EmbeddedOptions),
    /// A running `addipos serve` at this address (as written).
    Served(String),
}

/// The forms of a target string, for error messages.
pub const TARGET_FORMS: &str = "embedded, embedded:realtime, embedded:realtime=FACTOR, \
     embedded:config=FILE (options joined by commas), HOST:PORT, localhost:PORT or a bare PORT";

impl Target {
    /// Reads a target string (see the module documentation); an empty one
    /// is `$ADDIPOS_TARGET` or `embedded`.
    pub fn parse(text: &str) -> Result<Self> {
        let text = text.trim();
        if text.is_empty() {
            return match std::env::var(TARGET_ENV) {
                Ok(t) if !t.trim().is_empty() => Self::parse_given(&t)
                    .map_err(|e| Error::new(e.code(), format!("{TARGET_ENV}: {}", e.message()))),
                _ => Ok(Target::Embedded(EmbeddedOptions::default())),
            };
        }
        Self::parse_given(text)
    }

    /// Reads a target string that is not empty.
    fn parse_given(text: &str) -> Result<Self> {
        let text = text.trim();
        let bad = || Error::argument(format!("target `{text}`: use {TARGET_FORMS}"));
        if let Some(rest) = strip_prefix_ci(text, "embedded") {
            return match rest.strip_prefix(':') {
                None if rest.is_empty() => Ok(Target::Embedded(EmbeddedOptions::default())),
                None => Err(bad()),
                Some(options) => embedded(options).map(Target::Embedded),
            };
        }
        if is_address(text) {
            return Ok(Target::Served(text.to_string()));
        }
        Err(bad())
    }
}

/// `text` without `prefix`, compared case-insensitively.
fn strip_prefix_ci<'t>(text: &'t str, prefix: &str) -> Option<&'t str> {
    let head = text.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &text[prefix.len()..])
}

/// Whether `text` has the shape of a server address: a bare port, or
/// something ending in `:PORT`.
fn is_address(text: &str) -> bool {
    // Options (`,token=...`) follow the address.
    let text = text.split(',').next().unwrap_or("").trim();
    let port = |p: &str| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit());
    match text.rsplit_once(':') {
        Some((host, p)) => !host.is_empty() && port(p),
        None => port(text),
    }
}

/// The options of `embedded:...`.
fn embedded(options: &str) -> Result<EmbeddedOptions> {
    let mut opts = EmbeddedOptions::default();
    let mut realtime = None;
    for option in options.split(',').map(str::trim).filter(|o| !o.is_empty()) {
        let (key, value) = match option.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (option, None),
        };
        match (key.to_ascii_lowercase().as_str(), value) {
            ("realtime", None) => realtime = Some(RealTimeFactor::ONE),
            ("realtime", Some(f)) => realtime = Some(factor(f)?),
            ("config", Some(path)) => opts = read_config(&PathBuf::from(path))?,
            _ => {
                return Err(Error::argument(format!(
                    "embedded option `{option}`: use realtime, realtime=FACTOR or config=FILE"
                )))
            }
        }
    }
    if realtime.is_some() {
        opts.realtime = realtime;
    }
    Ok(opts)
}

/// A real-time factor.
fn factor(text: &str) -> Result<RealTimeFactor> {
    let f: f64 = text
        .parse()
        .map_err(|_| Error::argument(format!("realtime={text}: not a number")))?;
    RealTimeFactor::new(f).map_err(|e| Error::argument(format!("realtime={text}: {e}")))
}

/// The emulator settings of a settings file.
fn read_config(path: &std::path::Path) -> Result<EmbeddedOptions> {
    let text = emulator::read_settings_file(path)
        .map_err(|e| Error::argument(format!("config={}: {}", path.display(), e.0)))?;
    EmbeddedOptions::from_config(&text)
        .map_err(|e| Error::argument(format!("config={}: {}", path.display(), e.message())))
}

/// Whether the built-in settings parse (they are embedded in the
/// emulator; a test keeps them in step with [`EmbeddedOptions::default`]).
pub fn builtin_settings() -> Result<EmbeddedOptions> {
    EmbeddedOptions::from_config(DEFAULT_CONFIG)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorCode;

    #[test]
    fn the_builtin_settings_are_the_default_options() {
        assert_eq!(builtin_settings().unwrap(), EmbeddedOptions::default());
    }

    #[test]
    fn embedded_forms() {
        let e = |t: &str| match Target::parse(t).unwrap() {
            Target::Embedded(o) => o,
            other => panic!("{other:?}"),
        };
        assert_eq!(e("embedded"), EmbeddedOptions::default());
        assert_eq!(e(" Embedded: "), EmbeddedOptions::default());
        assert_eq!(e("embedded:realtime").realtime, Some(RealTimeFactor::ONE));
        let ten = e("embedded:realtime=10").realtime.unwrap();
        assert_eq!(ten.get(), 10.0);
        for bad in [
            "embedded:realtime=0",
            "embedded:realtime=fast",
            "embedded:speed=2",
            "embeddedx",
            "embedded:config=/no/such/file.toml",
            "emulator",
            "host:",
        ] {
            let err = Target::parse(bad).unwrap_err();
            assert_eq!(err.code(), ErrorCode::Argument, "{bad}");
        }
    }

    #[test]
    fn a_settings_file_sets_start_cycle_and_spooler() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.toml");
        std::fs::write(
            &path,
            "cycle_ms = 0.5\nspool_capacity = 8\nstart = [1,2,3,0,0,0,0,0]\n",
        )
        .unwrap();
        let t = format!("embedded:realtime=2,config={}", path.display());
        let Target::Embedded(o) = Target::parse(&t).unwrap() else {
            panic!("embedded")
        };
        assert_eq!(o.spool_capacity, 8);
        assert_eq!(o.cycle.secs(), 0.0005);
        assert_eq!(o.start[2], 3.0);
        assert_eq!(o.realtime.map(RealTimeFactor::get), Some(2.0));
        std::fs::write(&path, "spool_capacity = 7\n").unwrap();
        let e = Target::parse(&format!("embedded:config={}", path.display())).unwrap_err();
        assert!(e.message().contains("spool_capacity"), "{e}");
    }

    #[test]
    fn server_addresses_are_recognised() {
        for t in [
            "127.0.0.1:1300",
            "localhost:1300",
            "1300",
            "[::1]:1300",
            "plc7:1300",
        ] {
            let target = Target::parse(t).unwrap();
            assert_eq!(target, Target::Served(t.to_string()));
        }
    }
}
