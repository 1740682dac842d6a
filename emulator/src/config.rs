//! Settings of `addipos serve`: TOML, with built-in defaults
//! (`config/default.toml`, embedded in the binary).

use std::path::PathBuf;
use std::time::Duration;

#[cfg(feature = "opcua")]
use opcua_face::FaceConfig;
use serde::Deserialize;
use tc_module::limits::{check_point, MAX_COORD};
use tc_module::{check_capacity, DEFAULT_SPOOL_CAPACITY};
use tc_module::{AxisPos, CycleTime, AXES};
use uoi::tcp::{AccessPolicy, ServerConfig};

use crate::address::parse_address;
use crate::clock::RealTimeFactor;

/// Most connections `max_connections` may allow (each holds up to two
/// 64 KiB buffers).
pub const MAX_CONNECTIONS: usize = 65_536;

/// Longest eviction grace `evict_after_ms` may set: a new connection
/// finding the server full may wait one and a half times it.
pub const MAX_EVICT_AFTER_MS: u64 = 60_000;

/// The built-in settings.
pub const DEFAULT_CONFIG: &str = include_str!("../config/default.toml");

/// The settings file (every key optional; missing keys take the defaults).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Listen address, in a form [`parse_address`] reads.
    pub listen: String,
    /// Allow a non-loopback listen address; remote peers must then present
    /// the access token.
    pub allow_remote: bool,
    /// Ask programs on this machine (loopback peers) for the token too.
    pub token_on_loopback: bool,
    /// Folder of the server's own files (the tool files and journal, the
    /// access token); relative to the working directory.
    pub data_dir: PathBuf,
    /// Keep tool data on disk (`false`: a throw-away emulator).
    pub persist: bool,
    /// Start even when tool files or the journal hold bad lines (they are
    /// skipped and reported).
    pub ignore_bad_tools: bool,
    /// Connections served at once.
    pub max_connections: usize,
    /// Connections served at once from one peer address on another
    /// machine (programs on this one count against `max_connections`).
    pub max_connections_per_peer: usize,
    /// When the server is full, milliseconds without progress after which
    /// a connection may be closed to make room for a new one; 0: never.
    pub evict_after_ms: u64,
    /// Idle timeout in seconds.
    pub idle_timeout_s: u64,
    /// Seconds the answers waiting for a client that does not read them
    /// may take to leave before the connection is closed.
    pub write_timeout_s: u64,
    /// Interpolation cycle in ms.
    pub cycle_ms: f64,
    /// Elements the spooler holds.
    pub spool_capacity: u64,
    /// Machine position at start.
    pub start: [f64; AXES],
    /// Real time: the executor runs with the wall clock, this many times
    /// faster (0.01 to 10000); 0: stepped (`EXEC` runs the cycles).
    pub realtime: f64,
    /// The OPC UA face.
    pub opcua: OpcuaSettings,
}

/// The `[opcua]` settings: the OPC UA face of the same emulator
/// (docs/opcua.md).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OpcuaSettings {
    /// Serve OPC UA too.
    pub enabled: bool,
    /// Where OPC UA clients connect, in a form [`parse_address`] reads;
    /// loopback only unless `allow_remote`.
    pub listen: String,
    /// The machine's serial number in the Machine Tools model
    /// (`Identification/SerialNumber`, and its ProductInstanceUri).
    pub serial_number: String,
    /// Host names clients connect with, besides the listen address (each
    /// endpoint is described with each); absent: `localhost` and this
    /// machine's name.
    pub host_names: Option<Vec<String>>,
    /// The subject of the server's certificate.
    pub certificate: CertificateSettings,
}

/// The `[opcua.certificate]` settings: the subject of the OPC UA server's
/// certificate besides its common name (the application's name). Empty
/// parts are left out.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CertificateSettings {
    /// Organisation (O).
    pub organization: String,
    /// Organisational unit (OU).
    pub unit: String,
    /// Country (C): two letters, or empty.
    pub country: String,
    /// State or province (ST).
    pub state: String,
}

impl Default for CertificateSettings {
    fn default() -> Self {
        Self {
            organization: "addipos-tc".into(),
            unit: String::new(),
            country: String::new(),
            state: String::new(),
        }
    }
}

/// Characters a part of the certificate's subject may not hold (they
/// separate or escape the parts of a distinguished name).
#[cfg(feature = "opcua")]
const SUBJECT_SPECIALS: &[char] = &[',', '=', '+', '\\', '"', '<', '>', ';', '#'];

impl CertificateSettings {
    /// The subject, checked: no part holds a separator of a
    /// distinguished name or a control character, the country is two
    /// letters or empty.
    #[cfg(feature = "opcua")]
    fn subject(&self) -> Result<opcua_face::CertSubject, ConfigError> {
        for (key, v) in [
            ("organization", &self.organization),
            ("unit", &self.unit),
            ("country", &self.country),
            ("state", &self.state),
        ] {
            if v.chars()
                .any(|c| c.is_control() || SUBJECT_SPECIALS.contains(&c))
            {
                return Err(ConfigError(format!(
                    "[opcua.certificate] {key}: none of , = + \\ \" < > ; # in a certificate subject"
                )));
            }
        }
        let c = &self.country;
        if !(c.is_empty() || (c.len() == 2 && c.chars().all(|x| x.is_ascii_alphabetic()))) {
            return Err(ConfigError(format!(
                "[opcua.certificate] country = \"{c}\": two letters (ISO 3166), or empty"
            )));
        }
        Ok(opcua_face::CertSubject {
            organization: self.organization.clone(),
            unit: self.unit.clone(),
            country: c.to_ascii_uppercase(),
            state: self.state.clone(),
        })
    }
}

impl Default for OpcuaSettings {
    fn default() -> Self {
        Self {
            enabled: false,
            listen: "127.0.0.1:4840".into(),
            serial_number: "1".into(),
            host_names: None,
            certificate: CertificateSettings::default(),
        }
    }
}

/// The folder of the OPC UA face's certificate store in the data
/// directory.
pub const OPCUA_PKI_DIR: &str = "opcua";

impl Default for Config {
    fn default() -> Self {
        Self {
            listen: "127.0.0.1:1300".into(),
            allow_remote: false,
            token_on_loopback: false,
            data_dir: PathBuf::from("data"),
            persist: true,
            ignore_bad_tools: false,
            max_connections: 256,
            max_connections_per_peer: 16,
            evict_after_ms: 1000,
            idle_timeout_s: 300,
            write_timeout_s: 30,
            cycle_ms: 1.0,
            spool_capacity: DEFAULT_SPOOL_CAPACITY as u64,
            start: [0.0; AXES],
            realtime: 0.0,
            opcua: OpcuaSettings::default(),
        }
    }
}

/// A settings problem, with what to do about it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ConfigError(pub String);

/// Largest settings file read: a file beyond it is refused (settings are
/// a few hundred bytes; `/dev/zero` would never end).
pub const MAX_SETTINGS_BYTES: u64 = 1 << 20;

/// Reads a settings file: a regular file (a FIFO, a device, a folder is
/// refused before it is opened, so nothing waits for a writer) of at most
/// [`MAX_SETTINGS_BYTES`].
pub fn read_settings_file(path: &std::path::Path) -> Result<String, ConfigError> {
    use std::io::Read;
    let cannot = |e: std::io::Error| ConfigError(format!("cannot read: {e}"));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if !meta.is_file() {
        return Err(ConfigError(
            "not a regular file (a settings file is read only from a plain file)".into(),
        ));
    }
    let file = std::fs::File::open(path).map_err(cannot)?;
    let mut bytes = Vec::new();
    file.take(MAX_SETTINGS_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > MAX_SETTINGS_BYTES {
        return Err(ConfigError(format!(
            "larger than {} MiB: not a settings file",
            MAX_SETTINGS_BYTES >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|_| ConfigError("not UTF-8 text: not a settings file".into()))
}

/// A TOML error as the settings' error: where (line and column) and what,
/// never the text of the line (a file named by mistake may hold secrets),
/// and any quoted value left out.
fn settings_error(text: &str, e: &toml::de::Error) -> ConfigError {
    let at = e.span().map_or(String::new(), |span| {
        let before = text.get(..span.start).unwrap_or("");
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        format!(" at line {line}, column {column}")
    });
    let message = e.message().lines().next().unwrap_or("").trim();
    ConfigError(format!("bad settings{at}: {}", without_quoted(message)))
}

/// `message` with every double-quoted part (a value of the file) shown
/// as `"…"`; keys, quoted in backticks, stay.
fn without_quoted(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut inside = false;
    for c in message.chars() {
        if c == '"' {
            if !inside {
                out.push_str("\"…\"");
            }
            inside = !inside;
        } else if !inside {
            out.push(c);
        }
    }
    out
}

impl Config {
    /// Parses settings text (TOML); an error says where, and never
    /// repeats the text.
    pub fn parse(text: &str) -> Result<Self, ConfigError> {
        toml::from_str(text).map_err(|e| settings_error(text, &e))
    }

    /// Whether the server asks for an access token (kept in
    /// [`data_dir`](Self::data_dir)): from remote peers with
    /// `allow_remote`, from every peer with `token_on_loopback`.
    pub fn wants_token(&self) -> bool {
        self.allow_remote || self.token_on_loopback
    }

    /// The server settings, checked; the access token is still to be
    /// given (`access.token`) when [`wants_token`](Self::wants_token).
    pub fn server(&self) -> Result<ServerConfig, ConfigError> {
        let listen = parse_address(&self.listen)
            .map_err(|e| ConfigError(format!("listen = \"{}\": {e}", self.listen)))?;
        if !(1..=MAX_CONNECTIONS).contains(&self.max_connections) {
            return Err(ConfigError(format!(
                "max_connections = {} must lie in 1..={MAX_CONNECTIONS}",
                self.max_connections
            )));
        }
        if !(1..=MAX_CONNECTIONS).contains(&self.max_connections_per_peer) {
            return Err(ConfigError(format!(
                "max_connections_per_peer = {} must lie in 1..={MAX_CONNECTIONS}",
                self.max_connections_per_peer
            )));
        }
        if self.evict_after_ms > MAX_EVICT_AFTER_MS {
            return Err(ConfigError(format!(
                "evict_after_ms = {} must lie in 0..={MAX_EVICT_AFTER_MS} (0: no eviction)",
                self.evict_after_ms
            )));
        }
        if self.idle_timeout_s == 0 {
            return Err(ConfigError("idle_timeout_s must be at least 1".into()));
        }
        if self.write_timeout_s == 0 {
            return Err(ConfigError("write_timeout_s must be at least 1".into()));
        }
        Ok(ServerConfig {
            listen,
            allow_remote: self.allow_remote,
            max_connections: self.max_connections,
            max_connections_per_peer: self.max_connections_per_peer,
            per_peer_limit_on_loopback: false,
            evict_after: (self.evict_after_ms > 0)
                .then(|| Duration::from_millis(self.evict_after_ms)),
            idle_timeout: Duration::from_secs(self.idle_timeout_s),
            write_timeout: Duration::from_secs(self.write_timeout_s),
            access: AccessPolicy {
                token: None,
                on_loopback: self.token_on_loopback,
            },
            ..ServerConfig::default()
        })
    }

    /// The OPC UA face's settings, checked; `None` when it is off. It
    /// asks for the access token whenever the UOI face does.
    #[cfg(feature = "opcua")]
    pub fn opcua(&self) -> Result<Option<FaceConfig>, ConfigError> {
        if !self.opcua.enabled {
            return Ok(None);
        }
        let listen = parse_address(&self.opcua.listen)
            .map_err(|e| ConfigError(format!("[opcua] listen = \"{}\": {e}", self.opcua.listen)))?;
        Ok(Some(FaceConfig {
            listen,
            allow_remote: self.allow_remote,
            token: None,
            pki_dir: self.data_dir.join(OPCUA_PKI_DIR),
            host_names: self.opcua.host_names.clone(),
            subject: self.opcua.certificate.subject()?,
        }))
    }

    /// The interpolation cycle, checked.
    pub fn cycle(&self) -> Result<CycleTime, ConfigError> {
        CycleTime::from_secs(self.cycle_ms * 1e-3)
            .map_err(|e| ConfigError(format!("cycle_ms = {}: {e}", self.cycle_ms)))
    }

    /// The real-time factor, checked; `None`: stepped (`realtime = 0`).
    pub fn realtime(&self) -> Result<Option<RealTimeFactor>, ConfigError> {
        if self.realtime == 0.0 {
            return Ok(None);
        }
        RealTimeFactor::new(self.realtime)
            .map(Some)
            .map_err(|e| ConfigError(format!("realtime = {}: {e} (0: stepped)", self.realtime)))
    }

    /// What the emulator is served with (start, cycle, spooler capacity,
    /// real time), checked; the service is built from it
    /// ([`Config::service`], with the service).
    pub fn service_settings(&self) -> Result<ServiceSettings, ConfigError> {
        let realtime = self.realtime()?;
        let cycle = self.cycle()?;
        let capacity = check_capacity(self.spool_capacity)
            .map_err(|e| ConfigError(format!("spool_capacity = {}: {e}", self.spool_capacity)))?;
        check_point(&self.start)
            .map_err(|_| ConfigError(format!("start: every axis must lie within ±{MAX_COORD}")))?;
        Ok(ServiceSettings {
            start: self.start,
            cycle,
            spool_capacity: capacity,
            realtime,
        })
    }
}

/// The checked settings of the emulator served
/// ([`Config::service_settings`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServiceSettings {
    /// Where the machine stands at start.
    pub start: AxisPos,
    /// The interpolation cycle.
    pub cycle: CycleTime,
    /// The spooler's capacity, in elements.
    pub spool_capacity: usize,
    /// Real time, this many times faster; `None`: stepped.
    pub realtime: Option<RealTimeFactor>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_defaults_parse_and_equal_the_code_defaults() {
        let c = Config::parse(DEFAULT_CONFIG).unwrap();
        assert_eq!(c, Config::default());
        let s = c.server().unwrap();
        assert_eq!(s.listen.to_string(), "127.0.0.1:1300");
        assert_eq!(s.max_connections, 256);
        assert_eq!(s.max_connections_per_peer, 16);
        assert!(!s.per_peer_limit_on_loopback);
        assert_eq!(s.evict_after, Some(Duration::from_secs(1)));
        assert_eq!(s.write_timeout, Duration::from_secs(30));
        assert!(!c.wants_token());
        #[cfg(feature = "opcua")]
        assert_eq!(c.opcua().unwrap(), None);
    }

    #[test]
    #[cfg(feature = "opcua")]
    fn opcua_face_on_loopback_port_4840_with_its_store_in_the_data_dir() {
        let c = Config::parse("data_dir = \"d\"\n[opcua]\nenabled = true").unwrap();
        let face = c.opcua().unwrap().expect("on");
        assert_eq!(face.listen.to_string(), "127.0.0.1:4840");
        assert!(!face.allow_remote);
        assert_eq!(face.pki_dir, PathBuf::from("d").join("opcua"));
        let c = Config::parse("[opcua]\nenabled = true\nlisten = \"nowhere\"").unwrap();
        assert!(c.opcua().unwrap_err().0.contains("[opcua] listen"));
        assert!(Config::parse("[opcua]\nport = 1")
            .unwrap_err()
            .0
            .contains("port"));
    }

    #[test]
    #[cfg(feature = "opcua")]
    fn opcua_host_names_and_the_certificate_subject_from_the_settings() {
        let on = "[opcua]\nenabled = true\n";
        let face = Config::parse(on).unwrap().opcua().unwrap().expect("on");
        assert_eq!(face.host_names, None);
        assert_eq!(face.subject.organization, "addipos-tc");
        let text = format!(
            "{on}host_names = [\"cell-7\"]\n[opcua.certificate]\norganization = \"Works\"\ncountry = \"de\""
        );
        let face = Config::parse(&text).unwrap().opcua().unwrap().expect("on");
        assert_eq!(face.host_names, Some(vec!["cell-7".to_string()]));
        assert_eq!(
            (
                face.subject.organization.as_str(),
                face.subject.country.as_str()
            ),
            ("Works", "DE")
        );
        for bad in [
            "organization = \"A, O=B\"",
            "country = \"DEU\"",
            "unit = \"x\\ny\"",
        ] {
            let text = format!("{on}[opcua.certificate]\n{bad}");
            let err = Config::parse(&text).unwrap().opcua().unwrap_err().0;
            assert!(err.contains("[opcua.certificate]"), "{bad}: {err}");
        }
    }

    #[test]
    fn bad_settings_are_explained() {
        assert!(Config::parse("listn = \"x\"")
            .unwrap_err()
            .0
            .contains("listn"));
        let c = Config::parse("listen = \"nowhere\"").unwrap();
        assert!(c.server().unwrap_err().0.contains("nowhere"));
        for bad in ["0", "1e-320", "0.0001", "1000.5", "nan", "inf"] {
            let c = Config::parse(&format!("cycle_ms = {bad}")).unwrap();
            assert!(c.cycle().unwrap_err().0.contains("cycle_ms"), "{bad}");
            assert!(c.service().is_err());
        }
        for bad in [0, 7, 1_000_001] {
            let c = Config::parse(&format!("spool_capacity = {bad}")).unwrap();
            assert!(
                c.service().unwrap_err().0.contains("spool_capacity"),
                "{bad}"
            );
        }
        let c = Config::parse("start = [1e10, 0, 0, 0, 0, 0, 0, 0]").unwrap();
        assert!(c.service().unwrap_err().0.contains("start"));
        let c = Config::parse("max_connections = 2305843009213693952").unwrap();
        assert!(c.server().unwrap_err().0.contains("max_connections"));
        let c = Config::parse("max_connections_per_peer = 0").unwrap();
        assert!(c
            .server()
            .unwrap_err()
            .0
            .contains("max_connections_per_peer"));
        let c = Config::parse("write_timeout_s = 0").unwrap();
        assert!(c.server().unwrap_err().0.contains("write_timeout_s"));
        let c = Config::parse("evict_after_ms = 60001").unwrap();
        assert!(c.server().unwrap_err().0.contains("evict_after_ms"));
        let c = Config::parse("evict_after_ms = 0").unwrap();
        assert_eq!(c.server().unwrap().evict_after, None);
        for bad in ["-1", "0.001", "10001", "nan"] {
            let c = Config::parse(&format!("realtime = {bad}")).unwrap();
            assert!(c.service().unwrap_err().0.contains("realtime"), "{bad}");
        }
    }

    #[test]
    fn realtime_is_off_by_default_and_a_factor_turns_it_on() {
        assert_eq!(Config::default().service().unwrap().realtime(), None);
        let c = Config::parse("realtime = 10").unwrap();
        assert_eq!(c.service().unwrap().realtime(), Some(10.0));
    }
}
