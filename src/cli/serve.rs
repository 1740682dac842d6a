//! `addipos serve`: the settings with the command line applied, the access
//! token, the server's run until a stop signal, and clear errors when it
//! cannot start.

use std::net::SocketAddr;
use std::path::Path;

use emulator::record::{RecordHeader, ServeRecorder};
use emulator::{
    parse_address, read_settings_file, Config, ConfigError, EmulatorService, DEFAULT_CONFIG,
};
use opcua_face::{Face, FaceConfig};
use tokio_util::sync::CancellationToken;
use uoi::tcp::{AccessToken, Refused, Server};

use super::token;
use super::{Failure, Outcome};

mod args;

pub use args::ServeArgs;

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {},
        () = term => {},
    }
    tracing::info!("stop requested");
}

/// How often a server in real time runs its clock between requests (and
/// ends the EXEC waits that are over), so that the OPC UA face sees the
/// axes move.
const REALTIME_TICK: std::time::Duration = std::time::Duration::from_millis(2);

/// What `serve` runs with.
struct ServeSettings {
    server: uoi::tcp::ServerConfig,
    service: EmulatorService,
    /// The OPC UA face, when it is on.
    opcua: Option<FaceConfig>,
    /// The machine's serial number in the OPC UA face.
    serial_number: String,
    /// The web view, when it is on.
    web: Option<web_view::WebConfig>,
    /// The lock on the tool folder, held while serving.
    _tools_lock: Option<std::fs::File>,
}

/// Why `serve` could not start; each names where the bad value came
/// from.
#[derive(Debug, thiserror::Error)]
enum ServeError {
    /// An address option that is not an address (`parse_address`'s
    /// reason).
    #[error("--{option}: {reason}")]
    Address {
        /// The option.
        option: &'static str,
        /// Why.
        reason: emulator::AddressError,
    },
    /// A `--realtime` factor out of range.
    #[error("--realtime {factor}: {error}")]
    Realtime {
        /// The factor given.
        factor: f64,
        /// Why.
        error: emulator::clock::FactorError,
    },
    /// Bad settings.
    #[error("{origin}: {error}")]
    Settings {
        /// The settings file, or the built-in settings.
        origin: String,
        /// What is wrong.
        error: ConfigError,
    },
    /// The access token cannot be read or made.
    #[error("access token: {0}")]
    Token(std::io::Error),
    /// The tool data cannot be opened (the emulator's reason names the
    /// file and the line).
    #[error("{0}")]
    Tools(String),
    /// `--record`'s file cannot be created.
    #[error("--record {path}: cannot create: {error}")]
    Record {
        /// The file.
        path: String,
        /// Why.
        error: std::io::Error,
    },
}

/// An address option read, or the error naming the option.
fn address_of(option: &'static str, text: &str) -> Result<SocketAddr, ServeError> {
    parse_address(text).map_err(|reason| ServeError::Address { option, reason })
}

/// The command line over the settings; a bad value names its option.
fn apply_args(cfg: &mut Config, args: &ServeArgs) -> Result<(), ServeError> {
    if let Some(l) = &args.listen {
        cfg.listen = address_of("listen", l)?.to_string();
    }
    cfg.allow_remote |= args.allow_remote;
    if let Some(d) = &args.data_dir {
        cfg.data_dir = d.clone();
    }
    cfg.persist &= !args.no_persist;
    if let Some(f) = args.realtime {
        emulator::RealTimeFactor::new(f)
            .map_err(|error| ServeError::Realtime { factor: f, error })?;
        cfg.realtime = f;
    }
    cfg.ignore_bad_tools |= args.ignore_bad_tools;
    if let Some(addr) = &args.opcua {
        cfg.opcua.enabled = true;
        if !addr.is_empty() {
            cfg.opcua.listen = address_of("opcua", addr)?.to_string();
        }
    }
    Ok(())
}

/// The settings file (or the built-in settings) with the command line
/// applied, checked, and the tool data opened; every error names where
/// the bad value came from.
fn serve_settings(args: &ServeArgs) -> Result<ServeSettings, ServeError> {
    let config = args.config.as_deref();
    let source: String =
        config.map_or_else(|| "built-in settings".into(), |p| p.display().to_string());
    let in_source = |error: ConfigError| ServeError::Settings {
        origin: source.clone(),
        error,
    };
    let text = match config {
        None => DEFAULT_CONFIG.to_string(),
        Some(p) => read_settings_file(p).map_err(in_source)?,
    };
    let mut cfg = Config::parse(&text).map_err(in_source)?;
    apply_args(&mut cfg, args)?;
    let mut server = cfg.server().map_err(in_source)?;
    let mut service = cfg.service().map_err(in_source)?;
    let mut opcua = cfg.opcua().map_err(in_source)?;
    if cfg.wants_token() {
        let token = server_token(&cfg.data_dir).map_err(ServeError::Token)?;
        if let Some(face) = &mut opcua {
            face.token = Some(token.clone());
        }
        server.access.token = Some(token);
    }
    let lock = if cfg.persist {
        Some(
            service
                .open_tools(&cfg.data_dir, cfg.ignore_bad_tools)
                .map_err(|e| ServeError::Tools(e.to_string()))?,
        )
    } else {
        tracing::info!("tool data kept in memory only (--no-persist)");
        None
    };
    time_and_recording(&mut service, &cfg, args.record.as_deref())?;
    let web = web_settings(args, &server)?;
    Ok(ServeSettings {
        server,
        service,
        opcua,
        web,
        serial_number: cfg.opcua.serial_number.clone(),
        _tools_lock: lock,
    })
}

/// The web view's settings (`--web`): its address, and the UOI face's
/// rule for anything but loopback (`--allow-remote`, the access token).
fn web_settings(
    args: &ServeArgs,
    server: &uoi::tcp::ServerConfig,
) -> Result<Option<web_view::WebConfig>, ServeError> {
    let Some(addr) = &args.web else {
        return Ok(None);
    };
    let listen = address_of("web", addr)?;
    let mut web = web_view::WebConfig::new(listen);
    web.allow_remote = server.allow_remote;
    web.access = server.access.clone();
    Ok(Some(web))
}

/// Logs real time, and starts `--record`'s recording.
fn time_and_recording(
    service: &mut EmulatorService,
    cfg: &Config,
    record: Option<&Path>,
) -> Result<(), ServeError> {
    if let Some(f) = service.realtime() {
        tracing::info!("real time: the executor runs with the wall clock, {f} times faster");
    }
    if let Some(path) = record {
        let cannot = |error: std::io::Error| ServeError::Record {
            path: path.display().to_string(),
            error,
        };
        let open = super::record_file::opener(path).map_err(cannot)?;
        let header = record_header(cfg, service.realtime());
        let recorder =
            ServeRecorder::start(path.display().to_string(), open, &header).map_err(cannot)?;
        service.set_request_log(Box::new(recorder));
        tracing::info!(
            "recording every request carried out into {}",
            path.display()
        );
    }
    Ok(())
}

/// The header of `--record`'s trace: the emulator's settings, and what
/// kind of run it is.
fn record_header(cfg: &Config, realtime: Option<f64>) -> RecordHeader {
    let time = match realtime {
        Some(f) => format!(
            "real time (factor {f}): the cycles the clock ran between requests are written as \
             EXEC n, and an EXEC of a client, which waits for the clock, as a comment"
        ),
        None => "stepped: EXEC lines are the clients' EXEC requests".into(),
    };
    let tools = if cfg.persist {
        format!(
            "; tool data was loaded from {} at the start and is not in this trace (record with \
             --no-persist for a trace that replays from a fresh emulator)",
            cfg.data_dir.display()
        )
    } else {
        String::new()
    };
    RecordHeader {
        name: format!("addipos serve --record, {}", cfg.listen),
        start: cfg.start,
        cycle_ms: cfg.cycle_ms,
        // A checked capacity is at most 1,000,000.
        spool_capacity: cfg.spool_capacity as usize,
        note: format!(
            "everything the shared emulator carried out, from every connection and the OPC UA \
             face, in order; {time}{tools}"
        ),
    }
}

/// Runs the real-time clock of the shared emulator every
/// [`REALTIME_TICK`] until the server stops; then the `EXEC` requests
/// waiting for the clock are answered `Stopped` at once.
async fn tick_clock(core: uoi::tcp::CoreHandle, stop: CancellationToken) {
    loop {
        tokio::select! {
            () = tokio::time::sleep(REALTIME_TICK) => {}
            () = stop.cancelled() => {
                core.inspect(|h| {
                    if let Some(s) = h.downcast_mut::<EmulatorService>() {
                        s.stop_waits();
                    }
                })
                .await;
                return;
            }
        }
        let ticked = core
            .inspect(|h| {
                if let Some(s) = h.downcast_mut::<EmulatorService>() {
                    s.tick();
                }
            })
            .await;
        if ticked.is_none() {
            return;
        }
    }
}

/// The server's access token, read or generated; the log names its file
/// (not the token itself: logs are often read more widely than the file).
fn server_token(data_dir: &Path) -> std::io::Result<AccessToken> {
    let t = token::load_or_create(data_dir)?;
    let path = std::path::absolute(&t.path).unwrap_or_else(|_| t.path.clone());
    let file = path.display();
    if t.created {
        tracing::info!("generated a new access token in {file}");
    }
    tracing::info!(
        "clients must present the access token in {file} (call/replay: --token-file FILE)"
    );
    Ok(t.token)
}

/// Why the server could not listen on `addr`, and what to do about it.
fn listen_error(addr: SocketAddr, e: &std::io::Error) -> String {
    const HINT: &str = "choose another with --listen ADDR or `listen` in the settings file";
    // The server's own refusal of a non-loopback address, with the option
    // that allows it.
    match e.get_ref().and_then(|r| r.downcast_ref::<Refused>()) {
        Some(Refused::NotAllowed(a)) => {
            return format!("{a} is not a loopback address: listening there needs --allow-remote")
        }
        Some(refused) => return refused.to_string(),
        None => {}
    }
    match e.kind() {
        std::io::ErrorKind::AddrInUse => {
            format!("cannot listen on {addr}: address already in use ({HINT})")
        }
        _ => format!("cannot listen on {addr}: {e} ({HINT})"),
    }
}

/// Why the OPC UA face could not listen on `addr`, and what to do about it.
fn opcua_listen_error(addr: SocketAddr, e: &std::io::Error) -> String {
    const HINT: &str =
        "choose another with --opcua ADDR or `listen` in [opcua] of the settings file";
    match e.kind() {
        std::io::ErrorKind::AddrInUse => {
            format!("OPC UA: cannot listen on {addr}: address already in use ({HINT})")
        }
        _ if e.raw_os_error().is_none() => format!("OPC UA: {e}"),
        _ => format!("OPC UA: cannot listen on {addr}: {e} ({HINT})"),
    }
}

/// Serves the UOI face, and the OPC UA face and the web view when they
/// are bound, until a stop signal (or until one ends: then all stop).
async fn serve_faces<H: uoi::tcp::Handler>(
    server: Server<H>,
    face: Option<Face>,
    web: Option<web_view::WebFace>,
    stop: CancellationToken,
) -> std::io::Result<()> {
    let signal = stop.clone();
    let watch = tokio::spawn(async move {
        tokio::select! {
            () = shutdown_signal() => signal.cancel(),
            () = signal.cancelled() => {}
        }
    });
    let uoi = async {
        let end = server.run(stop.cancelled()).await;
        stop.cancel();
        end
    };
    let opcua = async {
        let Some(face) = face else { return Ok(()) };
        let end = face.run(stop.cancelled()).await;
        stop.cancel();
        end
    };
    let web = async {
        let Some(web) = web else { return Ok(()) };
        let end = web.run(stop.cancelled()).await;
        stop.cancel();
        end
    };
    let (uoi, opcua, web) = tokio::join!(uoi, opcua, web);
    watch.abort();
    uoi.and(opcua).and(web)
}

/// Runs `serve` until a stop signal (or prints the built-in settings);
/// the outcome says how it ended.
pub fn cmd_serve(args: &ServeArgs, print_default_config: bool) -> Outcome {
    if print_default_config {
        print!("{DEFAULT_CONFIG}");
        return Ok(());
    }
    let settings = serve_settings(args).map_err(Failure::trouble)?;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::trouble(format!("cannot start the runtime: {e}")))?;
    let addr = settings.server.listen;
    // The server logs its one start line (address, limits) once bound.
    let lock = settings._tools_lock;
    let realtime = settings.service.realtime().is_some();
    let server = rt
        .block_on(Server::bind(settings.server, settings.service))
        .map_err(|e| Failure::trouble(listen_error(addr, &e)))?;
    let face = match settings.opcua {
        Some(cfg) => {
            let at = cfg.listen;
            let mut table = emulator::opcua::table();
            table.machine = Some(emulator::opcua::machine(&settings.serial_number));
            let face = rt.block_on(Face::bind(cfg, table, server.core()));
            Some(face.map_err(|e| Failure::trouble(opcua_listen_error(at, &e)))?)
        }
        None => None,
    };
    let web = match settings.web {
        Some(mut cfg) => {
            cfg.opcua_connections = face.as_ref().map(Face::connections);
            let bound = rt.block_on(web_view::WebFace::bind(cfg, server.core()));
            Some(bound.map_err(|e| Failure::trouble(e.to_string()))?)
        }
        None => None,
    };
    let stop = CancellationToken::new();
    let clock = realtime.then(|| rt.spawn(tick_clock(server.core(), stop.clone())));
    let end = rt
        .block_on(serve_faces(server, face, web, stop))
        .map_err(Failure::failed);
    if let Some(c) = clock {
        c.abort();
    }
    // The emulator (and with it the tool writer, which compacts the
    // journal into the tool files) goes with the runtime; the lock after.
    drop(rt);
    drop(lock);
    end
}
