//! An OPC UA client for the tests (async-opcua's), with its certificate
//! store in a temporary folder: connect, browse, read, write, watch.
//! Every wait is bounded by [`GUARD`], a hang guard far above any real
//! wait.

// Each test file uses only some of these; setups may stop loudly.
#![allow(dead_code, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::future::Future;
use std::sync::Arc;
use std::time::{Duration, Instant};

use opcua::client::{ClientBuilder, DataChangeCallback, EventCallback, IdentityToken, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    AttributeId, BrowseDescription, BrowseDescriptionResultMask, BrowseDirection,
    ContentFilterBuilder, DataValue, EndpointDescription, EventFilter, ExtensionObject,
    LiteralOperand, MessageSecurityMode, MonitoredItemCreateRequest, MonitoringMode,
    MonitoringParameters, NodeId, ObjectTypeId, ReadValueId, ReferenceDescription, ReferenceTypeId,
    SimpleAttributeOperand, StatusCode, TimestampsToReturn, Variant, WriteValue,
};
use tokio::sync::mpsc;

pub mod model;

/// The hang guard of every wait.
pub const GUARD: Duration = Duration::from_secs(30);

/// `f`, or a panic naming `what` after [`GUARD`].
pub async fn guarded<T>(what: &str, f: impl Future<Output = T>) -> T {
    tokio::time::timeout(GUARD, f)
        .await
        .unwrap_or_else(|_| panic!("{what}: no answer within {GUARD:?}"))
}

/// A connected session, and the namespace of the face.
pub struct Ua {
    pub session: Arc<Session>,
    pub ns: u16,
    event_loop: tokio::task::JoinHandle<StatusCode>,
    _pki: tempfile::TempDir,
}

/// How a client logs in.
pub enum Login<'a> {
    /// Anonymous, no security.
    Open,
    /// This user and password on the Basic256Sha256 Sign&Encrypt endpoint.
    Password(&'a str, &'a str),
    /// Anonymous on the server's first endpoint, changed by the function
    /// (as a client would that does not check what the server offers).
    Forged(fn(&mut EndpointDescription)),
}

impl Ua {
    /// Connects anonymously without security.
    pub async fn open(url: &str) -> Ua {
        Self::connect(url, Login::Open).await.expect("connect")
    }

    /// Connects as `login` says; the error of a refused session.
    pub async fn connect(url: &str, login: Login<'_>) -> Result<Ua, opcua::types::Error> {
        let pki = tempfile::tempdir().expect("pki dir");
        let secure = !matches!(login, Login::Open);
        let mut client = ClientBuilder::new()
            .application_name("addipos test client")
            .application_uri("urn:addipos-test-client")
            .pki_dir(pki.path())
            .create_sample_keypair(secure)
            .trust_server_certs(true)
            .session_retry_limit(0)
            .min_publish_interval(Duration::from_millis(10))
            .max_array_length(100_000)
            .max_chunk_count(64)
            .max_message_size(64 * 65_535)
            .client()
            .expect("client");
        let (session, event_loop) = match login {
            Login::Open => {
                let endpoint = (
                    url,
                    SecurityPolicy::None.to_str(),
                    MessageSecurityMode::None,
                );
                let anonymous = IdentityToken::Anonymous;
                guarded(
                    "connect",
                    client.connect_to_matching_endpoint(endpoint, anonymous),
                )
                .await?
            }
            Login::Password(user, pass) => {
                let policy = SecurityPolicy::Basic256Sha256.to_str();
                let endpoint = (url, policy, MessageSecurityMode::SignAndEncrypt);
                let identity = IdentityToken::new_user_name(user, pass);
                guarded(
                    "connect",
                    client.connect_to_matching_endpoint(endpoint, identity),
                )
                .await?
            }
            Login::Forged(change) => {
                let offered =
                    guarded("endpoints", client.get_server_endpoints_from_url(url)).await?;
                let mut endpoint = offered.into_iter().next().expect("an endpoint");
                change(&mut endpoint);
                client.connect_to_endpoint_directly(endpoint, IdentityToken::Anonymous)?
            }
        };
        let mut event_loop = event_loop.spawn();
        let connected = guarded("session", async {
            tokio::select! {
                up = session.wait_for_connection() => Ok(up),
                end = &mut event_loop => Err(end.expect("event loop")),
            }
        })
        .await;
        match connected {
            Ok(true) => {}
            Ok(false) => {
                return Err(opcua::types::Error::new(
                    StatusCode::BadDisconnect,
                    "no session",
                ))
            }
            Err(status) => return Err(opcua::types::Error::new(status, "session refused")),
        }
        let ns = namespace(&session).await;
        Ok(Ua {
            session,
            ns,
            event_loop,
            _pki: pki,
        })
    }

    /// The face's node `id` (`1300/1/2/6`).
    pub fn node(&self, id: &str) -> NodeId {
        NodeId::new(self.ns, id)
    }

    /// The Value of `id`.
    pub async fn read(&self, id: &str) -> DataValue {
        self.read_attr(&self.node(id), AttributeId::Value).await
    }

    /// The Values of `ids` in one Read.
    pub async fn read_many(&self, ids: &[NodeId]) -> Vec<DataValue> {
        let ids: Vec<ReadValueId> = ids
            .iter()
            .map(|n| ReadValueId::new_value(n.clone()))
            .collect();
        guarded(
            "read",
            self.session.read(&ids, TimestampsToReturn::Both, 0.0),
        )
        .await
        .expect("read")
    }

    /// Attribute `attr` of `node`.
    pub async fn read_attr(&self, node: &NodeId, attr: AttributeId) -> DataValue {
        let id = ReadValueId::new(node.clone(), attr);
        let mut v = guarded(
            "read",
            self.session.read(&[id], TimestampsToReturn::Both, 0.0),
        )
        .await
        .expect("read");
        v.pop().expect("one value")
    }

    /// Writes `value` to the Value of `id`: its status.
    pub async fn write(&self, id: &str, value: impl Into<Variant>) -> StatusCode {
        self.write_attr(&self.node(id), AttributeId::Value, value.into())
            .await
    }

    /// Writes attribute `attr` of `node`: its status.
    pub async fn write_attr(&self, node: &NodeId, attr: AttributeId, value: Variant) -> StatusCode {
        let w = WriteValue {
            node_id: node.clone(),
            attribute_id: attr as u32,
            value: DataValue::value_only(value),
            ..Default::default()
        };
        let mut s = guarded("write", self.session.write(&[w]))
            .await
            .expect("write");
        s.pop().expect("one status")
    }

    /// The BrowseNames of the nodes `node` organises or has as
    /// components or properties, in the order the server gives them.
    pub async fn children(&self, node: &NodeId) -> Vec<String> {
        let d = BrowseDescription {
            node_id: node.clone(),
            browse_direction: BrowseDirection::Forward,
            reference_type_id: ReferenceTypeId::HierarchicalReferences.into(),
            include_subtypes: true,
            node_class_mask: 0,
            result_mask: BrowseDescriptionResultMask::all().bits(),
        };
        let mut r = guarded("browse", self.session.browse(&[d], 0, None))
            .await
            .expect("browse");
        let r = r.pop().expect("one result");
        assert!(r.status_code.is_good(), "browse {node}: {}", r.status_code);
        r.references
            .unwrap_or_default()
            .into_iter()
            .map(|d| d.browse_name.name.to_string())
            .collect()
    }

    /// Every reference of `node` of type `kind` (and its subtypes) in
    /// `direction`, following continuation points.
    pub async fn browse(
        &self,
        node: &NodeId,
        kind: impl Into<NodeId>,
        direction: BrowseDirection,
    ) -> Vec<ReferenceDescription> {
        let d = BrowseDescription {
            node_id: node.clone(),
            browse_direction: direction,
            reference_type_id: kind.into(),
            include_subtypes: true,
            node_class_mask: 0,
            result_mask: BrowseDescriptionResultMask::all().bits(),
        };
        let mut r = guarded("browse", self.session.browse(&[d], 0, None))
            .await
            .expect("browse");
        let mut r = r.pop().expect("one result");
        assert!(r.status_code.is_good(), "browse {node}: {}", r.status_code);
        let mut all = r.references.take().unwrap_or_default();
        while !r.continuation_point.is_null() {
            let cp = [r.continuation_point.clone()];
            let mut next = guarded("browse next", self.session.browse_next(false, &cp))
                .await
                .expect("browse next");
            r = next.pop().expect("one result");
            all.extend(r.references.take().unwrap_or_default());
        }
        all
    }

    /// A subscription (publishing every 10 ms) with one monitored item on
    /// `id` sampled every `sampling_ms`: its notifications, each with the
    /// moment it arrived.
    pub async fn watch(
        &self,
        id: &str,
        sampling_ms: f64,
    ) -> mpsc::UnboundedReceiver<(DataValue, Instant)> {
        let (tx, rx) = mpsc::unbounded_channel();
        let callback = DataChangeCallback::new(move |dv, _item| {
            let _ = tx.send((dv, Instant::now()));
        });
        let sub = guarded(
            "subscribe",
            self.session.create_subscription(
                Duration::from_millis(10),
                3000,
                1000,
                0,
                0,
                true,
                callback,
            ),
        )
        .await
        .expect("subscription");
        let item = MonitoredItemCreateRequest::new(
            ReadValueId::new_value(self.node(id)),
            MonitoringMode::Reporting,
            MonitoringParameters {
                sampling_interval: sampling_ms,
                queue_size: 100,
                discard_oldest: true,
                ..Default::default()
            },
        );
        let created = guarded(
            "monitor",
            self.session
                .create_monitored_items(sub, TimestampsToReturn::Both, vec![item]),
        )
        .await
        .expect("monitored item");
        assert!(
            created[0].result.status_code.is_good(),
            "{:?}",
            created[0].result
        );
        rx
    }

    /// A subscription (publishing every 10 ms) to the events `node`
    /// notifies of type `event_type` (a where clause `OfType`): the values
    /// of the fields `fields` of each, named as OPC 10000-4 allows for any
    /// event type: by their BrowseName below BaseEventType.
    pub async fn events(
        &self,
        node: &NodeId,
        event_type: NodeId,
        fields: &[&str],
    ) -> mpsc::UnboundedReceiver<Vec<Variant>> {
        let (tx, rx) = mpsc::unbounded_channel();
        let callback = EventCallback::new(move |fields, _item| {
            let _ = tx.send(fields.unwrap_or_default());
        });
        let sub = guarded(
            "subscribe",
            self.session.create_subscription(
                Duration::from_millis(10),
                3000,
                1000,
                0,
                0,
                true,
                callback,
            ),
        )
        .await
        .expect("subscription");
        let select = fields
            .iter()
            .map(|f| SimpleAttributeOperand::new_value(ObjectTypeId::BaseEventType, f))
            .collect();
        let literal = LiteralOperand {
            value: Variant::from(event_type.clone()),
        };
        let filter = EventFilter {
            select_clauses: Some(select),
            where_clause: ContentFilterBuilder::new().of_type(literal).build(),
        };
        let item = MonitoredItemCreateRequest::new(
            ReadValueId {
                node_id: node.clone(),
                attribute_id: AttributeId::EventNotifier as u32,
                ..Default::default()
            },
            MonitoringMode::Reporting,
            MonitoringParameters {
                queue_size: 100,
                discard_oldest: true,
                filter: ExtensionObject::from_message(filter),
                ..Default::default()
            },
        );
        let created = guarded(
            "monitor",
            self.session
                .create_monitored_items(sub, TimestampsToReturn::Both, vec![item]),
        )
        .await
        .expect("monitored item");
        assert!(
            created[0].result.status_code.is_good(),
            "{:?}",
            created[0].result
        );
        rx
    }

    /// Closes the session.
    pub async fn close(self) {
        let _ = guarded("disconnect", self.session.disconnect()).await;
        let _ = guarded("event loop", self.event_loop).await;
    }
}

/// The index of the face's namespace in the server's namespace array.
async fn namespace(session: &Session) -> u16 {
    let array = ReadValueId::new_value(opcua::types::VariableId::Server_NamespaceArray.into());
    let v = guarded(
        "namespaces",
        session.read(&[array], TimestampsToReturn::Neither, 0.0),
    )
    .await
    .expect("namespaces");
    let Some(Variant::Array(a)) = &v[0].value else {
        panic!("namespace array: {v:?}")
    };
    let i = a
        .values
        .iter()
        .position(|u| matches!(u, Variant::String(s) if s.as_ref() == opcua_face::NAMESPACE))
        .expect("the face's namespace");
    u16::try_from(i).expect("index")
}

/// The next notification of `rx`, within the guard.
pub async fn next(rx: &mut mpsc::UnboundedReceiver<(DataValue, Instant)>) -> (DataValue, Instant) {
    guarded("notification", rx.recv())
        .await
        .expect("subscription open")
}

/// Waits for a notification of `rx` carrying `value`; gives the moment it
/// arrived.
pub async fn until(
    rx: &mut mpsc::UnboundedReceiver<(DataValue, Instant)>,
    value: &Variant,
) -> Instant {
    loop {
        let (dv, at) = next(rx).await;
        if dv.value.as_ref() == Some(value) {
            return at;
        }
    }
}
