//! The OPC UA server of the face: its settings, the listening socket (on
//! loopback unless remote access is allowed), the certificate store, the
//! one endpoint, and its run until a stop signal.

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use opcua::crypto::X509Data;
use opcua::server::address_space::{add_namespaces, AddressSpace};
use opcua::server::diagnostics::DiagnosticsNodeManagerBuilder;
use opcua::server::node_manager::memory::InMemoryNodeManagerBuilder;
use opcua::server::node_manager::ServerContext;
use opcua::server::{Server, ServerBuilder, ServerHandle};
use opcua::types::NodeId;
use tokio::net::TcpListener;
use uoi::tcp::{AccessToken, CoreHandle};

use crate::capped::CappedCore;
use crate::front::FrontBuilder;
use crate::guard::{self, Limits};
use crate::layout::Table;
use crate::machine::nodesets;
use crate::manager::{ObjectNodes, NAMESPACE};
use crate::pki::{self, CertSubject};
use crate::points::Points;
use crate::sampler::TICK;
use crate::security::{endpoint, TokenGate, ENDPOINT_PATH};
use crate::{nodes, space};
use uoi::tcp::Places;

/// The application's name, as OPC UA clients list it.
pub const APPLICATION_NAME: &str = "addipos TC emulator";
/// The application's URI (also in its certificate).
pub const APPLICATION_URI: &str = "urn:addipos-tc:server";
/// The product's URI.
const PRODUCT_URI: &str = "urn:addipos-tc";

/// Most nodes one request may name (the library's own limit of a Read).
const MAX_NODES_PER_REQUEST: usize = 10_000;

/// Clients the door may have handed over that the library has not yet
/// taken.
const HANDOVER_QUEUE: usize = 16;

/// Most chunks of one message: room for a Read of that many nodes.
const MAX_CHUNKS: usize = 64;

/// Settings of the face.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FaceConfig {
    /// Where OPC UA clients connect.
    pub listen: SocketAddr,
    /// Allow a non-loopback listen address (it also needs a token).
    pub allow_remote: bool,
    /// `Some`: guarded — no anonymous user; the token is the password,
    /// on a Basic256Sha256 Sign&Encrypt endpoint only. `None`: open —
    /// anonymous, no security (loopback only).
    pub token: Option<AccessToken>,
    /// The certificate store's folder (the data directory's `opcua`).
    pub pki_dir: PathBuf,
    /// The host names clients may connect with, besides the listen
    /// address: each endpoint is described with each of them, and the
    /// certificate names them. `None`: `localhost` and this machine's
    /// name.
    pub host_names: Option<Vec<String>>,
    /// The subject of the server's certificate.
    pub subject: CertSubject,
}

/// A bound face, ready to run.
pub struct Face {
    server: Server,
    handle: ServerHandle,
    listener: TcpListener,
    endpoint_url: String,
    guarded: bool,
    limits: Limits,
    places: Arc<Places>,
}

/// Sets the library's limits the face needs (the sampling and publishing
/// tick, arrays as long as the table, messages of `MAX_CHUNKS` chunks);
/// the door's limits and the largest message.
fn set_limits(builder: &mut ServerBuilder) -> (Limits, usize) {
    let fastest = TICK.as_secs_f64() * 1e3;
    let limits = builder.limits_mut();
    limits.subscriptions.min_sampling_interval_ms = fastest;
    limits.subscriptions.min_publishing_interval_ms = fastest;
    // One Read (or Write, or CreateMonitoredItems) may name every
    // object of the table: the library's arrays stop at 1,000.
    limits.max_array_length = MAX_NODES_PER_REQUEST;
    limits.max_chunk_count = MAX_CHUNKS;
    limits.max_message_size = limits.receive_buffer_size * MAX_CHUNKS;
    let door = Limits::new(u32::try_from(limits.receive_buffer_size).unwrap_or(u32::MAX));
    (door, limits.max_message_size)
}

impl Face {
    /// Binds the listen address and prepares the server of `table`, whose
    /// values it reads and writes through `core`. A non-loopback address
    /// is refused unless remote access is allowed and a token is given.
    pub async fn bind(cfg: FaceConfig, table: Table, core: CoreHandle) -> io::Result<Self> {
        check_listen(&cfg)?;
        let listener = TcpListener::bind(cfg.listen).await?;
        let addr = listener.local_addr()?;
        let host = endpoint_host(addr);
        let endpoint_url = format!("opc.tcp://{host}:{}{ENDPOINT_PATH}", addr.port());
        let hosts = host_names(&host, cfg.host_names.as_deref());
        let discovery = hosts
            .iter()
            .map(|h| format!("opc.tcp://{h}:{}{ENDPOINT_PATH}", addr.port()));
        let guarded = cfg.token.is_some();
        let mut builder = ServerBuilder::new()
            .application_name(APPLICATION_NAME)
            .application_uri(APPLICATION_URI)
            .product_uri(PRODUCT_URI)
            .create_sample_keypair(false)
            .pki_dir(cfg.pki_dir.clone())
            // The token decides who gets in, not a list of client
            // certificates.
            .trust_client_certs(guarded)
            .host(host)
            .host_names(hosts[1..].to_vec())
            .port(addr.port())
            .discovery_urls(discovery.collect())
            .subscription_poll_interval_ms(TICK.as_millis() as u64)
            .with_authenticator(Arc::new(TokenGate::new(cfg.token.clone())));
        let (id, ep) = endpoint(guarded);
        builder = builder.add_endpoint(id, ep);
        let (door, largest) = set_limits(&mut builder);
        ensure_certificate(&cfg, &hosts)?;
        // The library's own node managers (namespace 0 behind the size
        // check of `capped.rs`, diagnostics), then the face's.
        let builder = builder
            .without_node_managers()
            .with_node_manager(CappedCore { limit: largest })
            .with_node_manager(DiagnosticsNodeManagerBuilder)
            .with_node_manager(FrontBuilder {
                inner: InMemoryNodeManagerBuilder::new(
                    move |context: ServerContext, space: &mut AddressSpace| {
                        object_nodes(context, space, table, core)
                    },
                ),
                largest,
            });
        let (server, handle) = builder.build().map_err(io::Error::other)?;
        let places = guard::places(&door);
        Ok(Self {
            server,
            handle,
            listener,
            endpoint_url,
            guarded,
            limits: door,
            places,
        })
    }

    /// The door's count of OPC UA client connections open now (`open()`),
    /// for a dashboard such as the web view.
    pub fn connections(&self) -> Arc<Places> {
        Arc::clone(&self.places)
    }

    /// The endpoint URL clients connect to.
    pub fn endpoint_url(&self) -> &str {
        &self.endpoint_url
    }

    /// Serves until `shutdown` completes, then closes every session.
    /// Clients come in through the door (`guard.rs`) on the listen
    /// address, which hands each to the library inside the process: the
    /// library listens on no port of its own.
    pub async fn run(self, shutdown: impl Future<Output = ()>) -> io::Result<()> {
        let security = if self.guarded {
            "Basic256Sha256 Sign&Encrypt, access token as password"
        } else {
            "None, anonymous"
        };
        tracing::info!(endpoint = %self.endpoint_url, security, "serving OPC UA");
        let Face {
            server,
            handle,
            listener,
            limits,
            places,
            ..
        } = self;
        let (handover, handed) = tokio::sync::mpsc::channel(HANDOVER_QUEUE);
        let door = tokio::spawn(guard::serve(listener, handover, limits, places));
        let _close_door = DropAbort(door);
        let run = server.run_with_connections(handed);
        tokio::pin!(run);
        tokio::pin!(shutdown);
        let end = tokio::select! {
            end = &mut run => end,
            () = &mut shutdown => {
                handle.cancel();
                run.await
            }
        };
        end.map_err(io::Error::other)
    }
}

/// Stops the door's task when the face stops.
struct DropAbort(tokio::task::JoinHandle<()>);

impl Drop for DropAbort {
    fn drop(&mut self) {
        self.0.abort();
    }
}

/// The loopback rule of the UOI face: another machine's address needs
/// remote access allowed and the access token.
fn check_listen(cfg: &FaceConfig) -> io::Result<()> {
    let refused = |why: &str| {
        Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            format!("{} is not a loopback address: {why}", cfg.listen),
        ))
    };
    if cfg.listen.ip().is_loopback() {
        Ok(())
    } else if !cfg.allow_remote {
        refused("serving OPC UA there needs --allow-remote")
    } else if cfg.token.is_none() {
        refused("serving OPC UA there needs the access token")
    } else {
        Ok(())
    }
}

/// The host named in endpoint URLs: the address listened on, or for "any
/// address" this machine's name.
fn endpoint_host(addr: SocketAddr) -> String {
    match addr {
        SocketAddr::V4(a) if !a.ip().is_unspecified() => a.ip().to_string(),
        SocketAddr::V6(a) if !a.ip().is_unspecified() => format!("[{}]", a.ip()),
        _ => X509Data::computer_hostnames()
            .into_iter()
            .next()
            .unwrap_or_else(|| "localhost".into()),
    }
}

/// Makes the server's certificate, naming `hosts`, unless the store keeps
/// one still valid.
fn ensure_certificate(cfg: &FaceConfig, hosts: &[String]) -> io::Result<()> {
    let names = pki::Names {
        application_name: APPLICATION_NAME,
        application_uri: APPLICATION_URI,
        hosts,
        subject: &cfg.subject,
    };
    if pki::ensure_keypair(&cfg.pki_dir, &names)? {
        let cert = pki::cert_path(&cfg.pki_dir);
        tracing::info!("made the OPC UA server certificate {}", cert.display());
    }
    Ok(())
}

/// The host names the face answers to: `listen` (the listen address, or
/// this machine's name), then `extra` (by default `localhost` and this
/// machine's name), each once.
fn host_names(listen: &str, extra: Option<&[String]>) -> Vec<String> {
    let default;
    let extra = match extra {
        Some(given) => given,
        None => {
            default = std::iter::once("localhost".to_string())
                .chain(X509Data::computer_hostnames())
                .collect::<Vec<_>>();
            &default
        }
    };
    let mut hosts: Vec<String> = vec![listen.to_string()];
    for h in extra {
        if !h.is_empty() && !hosts.iter().any(|k| k.eq_ignore_ascii_case(h)) {
            hosts.push(h.clone());
        }
    }
    hosts
}

/// The face's node manager: its namespace, its nodes from `table`, and
/// with a machine to show the companion NodeSets (their namespaces after
/// the face's own, so it keeps its index).
fn object_nodes(
    context: ServerContext,
    space: &mut AddressSpace,
    table: Table,
    core: CoreHandle,
) -> ObjectNodes {
    let ns = add_namespaces(&context, space, &[NAMESPACE])
        .first()
        .copied()
        .unwrap_or_default();
    let plan = space::plan(&table);
    let map = nodes::insert(space, ns, &plan);
    let order = plan.order.iter().enumerate();
    let order = order
        .map(|(i, id)| (NodeId::new(ns, id.as_str()), i))
        .collect();
    let mut companions = Vec::new();
    let machine = table.machine.filter(|_| {
        let mut tree = context.type_tree.write();
        match nodesets::import(space, tree.namespaces_mut()) {
            Ok(loaded) => {
                companions = loaded;
                true
            }
            Err(e) => {
                tracing::error!("OPC UA: the machine is not shown: {e}");
                false
            }
        }
    });
    let points = Points::new(map, table.readings, core.clone());
    let machine = machine.map(|m| (m, core, companions));
    ObjectNodes::new(ns, points, order, machine)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_listen_address_first_then_each_other_name_once() {
        let given = ["LOCALHOST".to_string(), "cell-7".into(), "".into()];
        let hosts = host_names("localhost", Some(&given));
        assert_eq!(hosts, ["localhost", "cell-7"]);
        let hosts = host_names("127.0.0.1", None);
        assert_eq!(hosts[..2], ["127.0.0.1", "localhost"]);
        let mut lower: Vec<_> = hosts.iter().map(|h| h.to_lowercase()).collect();
        lower.dedup();
        assert_eq!(lower.len(), hosts.len(), "{hosts:?}");
    }
}
