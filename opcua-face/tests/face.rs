//! The face over a small demo bus served by a UOI server on loopback,
//! with async-opcua's client: the tree in the order of the table, every
//! attribute of a write-only variable, reads and writes and their
//! refusals, a subscription seeing the UOI face's write, the loopback
//! rule, the token-guarded endpoint, and the certificate store in its
//! folder.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod ua;

use std::sync::Arc;

use opcua::crypto::{CertificateStore, X509Data};
use opcua::types::{
    ApplicationDescription, AttributeId, DataTypeId, EndpointDescription, MessageSecurityMode,
    StatusCode, UserTokenPolicy, UserTokenType, Variant,
};
use opcua_face::{answer_value, Device, Face, FaceConfig, IndexKind, Reading, Row, Table};
use tokio::task::JoinHandle;
use tokio_util::sync::CancellationToken;
use ua::{until, Login, Ua};
use uoi::tcp::{AccessToken, Client, CoreHandle, Handler, Server, ServerConfig, Slice};
use uoi::wire::{Answer, Request};
use uoi::{
    Access, AccessError, Bus, Meaning, ObjectAddress, ObjectDesc, ObjectServer, Value, ValueRange,
    ValueType,
};

/// The demo bus: a command, a speed, a count of commands, per station a
/// mode and three slots.
#[derive(Default)]
struct Demo {
    speed: f64,
    count: i32,
    mode: [i32; 2],
    slots: [[i32; 3]; 2],
}

#[derive(Debug, Clone, Copy)]
enum Key {
    Go,
    Speed,
    Count,
    Mode,
    Slot,
}

impl Meaning for Key {
    fn meaning(&self) -> &'static str {
        match self {
            Key::Go => "Any value: counts one more",
            Key::Speed => "The speed",
            Key::Count => "Commands so far",
            Key::Mode => "The station's mode",
            Key::Slot => "A slot of the station",
        }
    }
}

const BUS: u16 = 7;

static OBJECTS: [ObjectDesc<Key>; 5] = [
    ObjectDesc::int(
        Key::Go,
        "Go",
        0,
        1..=1,
        0,
        Access::WriteOnly,
        ValueRange::AnyInt,
    ),
    ObjectDesc::double(
        Key::Speed,
        "Speed",
        0,
        2..=2,
        0,
        Access::ReadWrite,
        ValueRange::Finite {
            min: 0.0,
            max: 100.0,
        },
    ),
    ObjectDesc::int(
        Key::Count,
        "Count",
        0,
        3..=3,
        0,
        Access::ReadOnly,
        ValueRange::AnyInt,
    ),
    ObjectDesc::int(
        Key::Mode,
        "Mode",
        1,
        1..=2,
        1,
        Access::ReadWrite,
        ValueRange::Int { min: 0, max: 3 },
    ),
    ObjectDesc::int(
        Key::Slot,
        "Slot",
        1,
        1..=2,
        2,
        Access::ReadWrite,
        ValueRange::AnyInt,
    )
    .subs(2, 4),
];

impl Bus for Demo {
    type Key = Key;
    fn number(&self) -> u16 {
        BUS
    }
    fn objects(&self) -> &[ObjectDesc<Key>] {
        &OBJECTS
    }
    fn read(&mut self, key: Key, a: ObjectAddress) -> Result<Value, AccessError> {
        let station = usize::from(a.index.saturating_sub(1));
        Ok(match key {
            Key::Speed => Value::F64(self.speed),
            Key::Count => Value::I32(self.count),
            Key::Mode => Value::I32(self.mode[station]),
            Key::Slot => Value::I32(self.slots[station][usize::from(a.sub - 2)]),
            Key::Go => return Err(AccessError::WriteOnly),
        })
    }
    fn write(&mut self, key: Key, a: ObjectAddress, v: Value) -> Result<(), AccessError> {
        let station = usize::from(a.index.saturating_sub(1));
        match (key, v) {
            (Key::Go, _) => self.count += 1,
            (Key::Speed, Value::F64(s)) => self.speed = s,
            // Station 2 takes no mode while station 1 is in mode 3.
            (Key::Mode, Value::I32(_)) if station == 1 && self.mode[0] == 3 => {
                return Err(AccessError::State)
            }
            (Key::Mode, Value::I32(m)) => self.mode[station] = m,
            (Key::Slot, Value::I32(s)) => self.slots[station][usize::from(a.sub - 2)] = s,
            _ => return Err(AccessError::TypeMismatch),
        }
        Ok(())
    }
}

/// The object server of the demo bus as the UOI server's handler.
struct Objects(ObjectServer);

impl Handler for Objects {
    type Session = ();
    type Rest = Request;
    fn open_session(&mut self) {}
    fn serve(&mut self, req: Request) -> Slice {
        Slice::Done(match req {
            Request::Read(a, ty) => self
                .0
                .read(a, ty)
                .map_or_else(Answer::Access, Answer::Value),
            Request::Write(a, v) => self
                .0
                .write(a, v)
                .map_or_else(Answer::Access, |()| Answer::Ok),
            _ => Answer::Access(AccessError::NoObject),
        })
    }
}

fn table() -> Table {
    Table {
        bus: BUS,
        devices: vec![
            Device {
                number: 0,
                title: "Globals".into(),
                index: IndexKind::Object,
            },
            Device {
                number: 1,
                title: "Stations".into(),
                index: IndexKind::Instance {
                    name: "Station".into(),
                    note: "Station {}".into(),
                },
            },
        ],
        rows: OBJECTS.iter().map(Row::from_desc).collect(),
        readings: vec![Reading {
            id: "dashboard/count".into(),
            path: vec![],
            name: "Commands".into(),
            doc: "Commands so far".into(),
            ty: ValueType::I32,
            request: Request::Read(ObjectAddress::new(BUS, 0, 3, 0), ValueType::I32),
            pick: Arc::new(answer_value),
        }],
        machine: None,
    }
}

/// A UOI server of the demo bus with the face beside it, on loopback.
struct Rig {
    uoi: std::net::SocketAddr,
    url: String,
    pki: tempfile::TempDir,
    stop: CancellationToken,
    tasks: Vec<JoinHandle<()>>,
}

impl Rig {
    async fn start(token: Option<&str>) -> Rig {
        let pki = tempfile::tempdir().expect("pki");
        let mut objects = ObjectServer::new();
        objects.register(Demo::default()).expect("bus");
        let cfg = ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        };
        let server = Server::bind(cfg, Objects(objects)).await.expect("bind");
        let uoi = server.local_addr().unwrap();
        let face = bind_face(
            &pki,
            token.map(|t| AccessToken::new(t).unwrap()),
            server.core(),
        )
        .await;
        let url = face.endpoint_url().to_string();
        let stop = CancellationToken::new();
        let (a, b) = (stop.clone(), stop.clone());
        let tasks = vec![
            tokio::spawn(async move { server.run(a.cancelled_owned()).await.expect("uoi") }),
            tokio::spawn(async move { face.run(b.cancelled_owned()).await.expect("face") }),
        ];
        Rig {
            uoi,
            url,
            pki,
            stop,
            tasks,
        }
    }

    async fn stop(mut self) {
        self.stop.cancel();
        for t in self.tasks.drain(..) {
            ua::guarded("stop", t).await.expect("task");
        }
    }
}

async fn bind_face(pki: &tempfile::TempDir, token: Option<AccessToken>, core: CoreHandle) -> Face {
    let cfg = FaceConfig {
        listen: "127.0.0.1:0".parse().unwrap(),
        allow_remote: false,
        token,
        pki_dir: pki.path().join("opcua"),
        host_names: None,
        subject: Default::default(),
    };
    Face::bind(cfg, table(), core).await.expect("face")
}

fn demo(device: u16, index: u16, sub: u16) -> String {
    ObjectAddress::new(BUS, device, index, sub).to_string()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_tree_in_the_order_of_the_table() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let objects = opcua::types::ObjectId::ObjectsFolder.into();
    assert!(ua.children(&objects).await.contains(&"Bus7".to_string()));
    assert_eq!(
        ua.children(&ua.node("7")).await,
        ["Device0", "Device1", "Dashboard"]
    );
    assert_eq!(ua.children(&ua.node("7/0")).await, ["Go", "Speed", "Count"]);
    assert_eq!(ua.children(&ua.node("7/1")).await, ["Station1", "Station2"]);
    assert_eq!(
        ua.children(&ua.node("7/1/2")).await,
        ["Mode", "Slot[0]", "Slot[1]", "Slot[2]"]
    );
    assert_eq!(ua.children(&ua.node("dashboard")).await, ["Commands"]);
    // A range that is one interval is an EURange property.
    assert_eq!(ua.children(&ua.node(&demo(1, 2, 1))).await, ["EURange"]);
    let eu = ua.read(&format!("{}/EURange", demo(1, 2, 1))).await;
    let Some(Variant::ExtensionObject(eu)) = eu.value else {
        panic!("{eu:?}")
    };
    let eu = eu.inner_as::<opcua::types::Range>().expect("a Range");
    assert_eq!((eu.low, eu.high), (0.0, 3.0));
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_write_only_variable_shows_every_attribute_but_its_value() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let go = ua.node(&demo(0, 1, 0));
    let name = ua.read_attr(&go, AttributeId::BrowseName).await;
    assert_eq!(name.status(), StatusCode::Good, "{name:?}");
    let Some(Variant::QualifiedName(q)) = name.value else {
        panic!("{name:?}")
    };
    assert_eq!(q.name.as_ref(), "Go");
    let ty = ua.read_attr(&go, AttributeId::DataType).await;
    assert_eq!(
        ty.value,
        Some(Variant::from(opcua::types::NodeId::from(DataTypeId::Int32)))
    );
    let doc = ua.read_attr(&go, AttributeId::Description).await;
    let Some(Variant::LocalizedText(doc)) = doc.value else {
        panic!("{doc:?}")
    };
    assert_eq!(
        doc.text.as_ref(),
        "7/0/1/0 (i, w, any): Any value: counts one more"
    );
    // AccessLevel CurrentWrite only (2).
    assert_eq!(
        ua.read_attr(&go, AttributeId::AccessLevel).await.value,
        Some(Variant::Byte(2))
    );
    assert_eq!(
        ua.read_attr(&go, AttributeId::UserAccessLevel).await.value,
        Some(Variant::Byte(2))
    );
    assert_eq!(
        ua.read_attr(&go, AttributeId::Value).await.status(),
        StatusCode::BadNotReadable
    );
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reads_and_writes_reach_the_table_and_every_refusal_has_its_status() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = Client::connect(rig.uoi).await.expect("uoi");
    let speed = demo(0, 2, 0);
    assert_eq!(ua.write(&speed, 12.5).await, StatusCode::Good);
    let speed_addr = ObjectAddress::new(BUS, 0, 2, 0);
    assert_eq!(
        uoi.read(speed_addr, ValueType::F64).await.unwrap(),
        Value::F64(12.5)
    );
    assert_eq!(ua.write(&demo(1, 2, 3), 42).await, StatusCode::Good);
    assert_eq!(
        ua.read(&demo(1, 2, 3)).await.value,
        Some(Variant::Int32(42))
    );
    assert_eq!(ua.write(&demo(0, 1, 0), 1).await, StatusCode::Good);
    assert_eq!(
        ua.read("dashboard/count").await.value,
        Some(Variant::Int32(1))
    );
    // Refusals; none changes the value.
    for bad in [100.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            ua.write(&speed, bad).await,
            StatusCode::BadOutOfRange,
            "{bad}"
        );
    }
    assert_eq!(ua.write(&demo(1, 1, 1), 4).await, StatusCode::BadOutOfRange);
    assert_eq!(ua.write(&speed, 3).await, StatusCode::BadTypeMismatch);
    assert_eq!(ua.write(&speed, 3.0f32).await, StatusCode::BadTypeMismatch);
    assert_eq!(ua.write(&speed, "3").await, StatusCode::BadTypeMismatch);
    assert_eq!(
        ua.write(&demo(0, 3, 0), 5).await,
        StatusCode::BadNotWritable
    );
    assert_eq!(
        ua.write("dashboard/count", 5).await,
        StatusCode::BadNotWritable
    );
    assert_eq!(
        ua.read(&demo(0, 1, 0)).await.status(),
        StatusCode::BadNotReadable
    );
    assert_eq!(
        ua.read("7/0/9/0").await.status(),
        StatusCode::BadNodeIdUnknown
    );
    assert_eq!(ua.write("7/0/9/0", 1).await, StatusCode::BadNodeIdUnknown);
    assert_eq!(ua.write(&demo(1, 1, 1), 3).await, StatusCode::Good);
    assert_eq!(
        ua.write(&demo(1, 2, 1), 1).await,
        StatusCode::BadInvalidState
    );
    assert_eq!(ua.read(&demo(1, 2, 1)).await.value, Some(Variant::Int32(0)));
    let name = Variant::from(opcua::types::QualifiedName::new(0, "x"));
    let status = ua
        .write_attr(&ua.node(&speed), AttributeId::BrowseName, name)
        .await;
    assert_eq!(status, StatusCode::BadNotWritable);
    assert_eq!(ua.read(&speed).await.value, Some(Variant::Double(12.5)));
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_subscription_sees_the_uoi_faces_write_and_nothing_of_a_refused_one() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = Client::connect(rig.uoi).await.expect("uoi");
    let mut speed = ua.watch(&demo(0, 2, 0), 10.0).await;
    until(&mut speed, &Variant::Double(0.0)).await;
    let addr = ObjectAddress::new(BUS, 0, 2, 0);
    uoi.write(addr, Value::F64(7.0)).await.unwrap();
    until(&mut speed, &Variant::Double(7.0)).await;
    // A refused write (through either face) notifies no one: the next
    // notification is the next accepted write's.
    assert!(uoi.write(addr, Value::F64(-1.0)).await.is_err());
    assert_eq!(
        ua.write(&demo(0, 2, 0), 500.0).await,
        StatusCode::BadOutOfRange
    );
    uoi.write(addr, Value::F64(8.0)).await.unwrap();
    let (next, _) = ua::next(&mut speed).await;
    assert_eq!(next.value, Some(Variant::Double(8.0)));
    // The dashboard follows what the bus does by itself.
    let mut count = ua.watch("dashboard/count", 10.0).await;
    until(&mut count, &Variant::Int32(0)).await;
    uoi.write(ObjectAddress::new(BUS, 0, 1, 0), Value::I32(1))
        .await
        .unwrap();
    until(&mut count, &Variant::Int32(1)).await;
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_machines_address_needs_allow_remote_and_the_token() {
    let pki = tempfile::tempdir().unwrap();
    let server = Server::bind(
        ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        },
        Objects(ObjectServer::new()),
    )
    .await
    .unwrap();
    let mut cfg = FaceConfig {
        listen: "0.0.0.0:0".parse().unwrap(),
        allow_remote: false,
        token: None,
        pki_dir: pki.path().join("opcua"),
        host_names: None,
        subject: Default::default(),
    };
    let refused = |r: std::io::Result<Face>| match r {
        Ok(_) => panic!("bound"),
        Err(e) => {
            assert_eq!(e.kind(), std::io::ErrorKind::PermissionDenied);
            e.to_string()
        }
    };
    let e = refused(Face::bind(cfg.clone(), table(), server.core()).await);
    assert!(e.contains("--allow-remote"), "{e}");
    cfg.allow_remote = true;
    let e = refused(Face::bind(cfg.clone(), table(), server.core()).await);
    assert!(e.contains("access token"), "{e}");
    // Nothing was made for a face that did not start.
    assert!(!pki.path().join("opcua").exists());
}

const TOKEN: &str = "0123456789abcdef0123";

/// The endpoint as if it took anonymous users.
fn offer_anonymous(e: &mut EndpointDescription) {
    e.user_identity_tokens = Some(vec![UserTokenPolicy {
        policy_id: "anonymous".into(),
        token_type: UserTokenType::Anonymous,
        ..Default::default()
    }]);
}

/// The endpoint as if it were one without security, for anonymous users.
fn no_security(e: &mut EndpointDescription) {
    offer_anonymous(e);
    e.security_mode = MessageSecurityMode::None;
    e.security_policy_uri = opcua::crypto::SecurityPolicy::None.to_uri().into();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_guarded_face_wants_the_token_as_password_over_an_encrypted_endpoint() {
    let rig = Rig::start(Some(TOKEN)).await;
    // Only the encrypted endpoint is offered, for a user name and password.
    let client = opcua::client::ClientBuilder::new()
        .application_name("addipos test client")
        .application_uri("urn:addipos-test-client")
        .pki_dir(rig.pki.path().join("client"))
        .create_sample_keypair(false)
        .client()
        .unwrap();
    let endpoints = ua::guarded(
        "endpoints",
        client.get_server_endpoints_from_url(rig.url.as_str()),
    )
    .await
    .expect("endpoints");
    // One endpoint, described once for each host name the server answers
    // to (the address asked with first).
    let urls: std::collections::HashSet<_> =
        endpoints.iter().map(|e| e.endpoint_url.as_ref()).collect();
    assert_eq!(urls.len(), endpoints.len(), "{urls:?}");
    assert_eq!(endpoints[0].endpoint_url.as_ref(), rig.url, "{urls:?}");
    assert!(urls.iter().any(|u| u.starts_with("opc.tcp://localhost:")));
    let same = |e: &opcua::types::EndpointDescription| {
        (
            e.security_mode,
            e.security_policy_uri.clone(),
            e.user_identity_tokens.clone(),
        )
    };
    assert!(endpoints.iter().all(|e| same(e) == same(&endpoints[0])));
    let e = &endpoints[0];
    assert_eq!(
        e.security_policy_uri.as_ref(),
        opcua::crypto::SecurityPolicy::Basic256Sha256.to_uri()
    );
    assert_eq!(
        e.security_mode,
        opcua::types::MessageSecurityMode::SignAndEncrypt
    );
    let tokens: Vec<_> = e
        .user_identity_tokens
        .iter()
        .flatten()
        .map(|t| t.token_type)
        .collect();
    assert_eq!(tokens, [opcua::types::UserTokenType::UserName]);
    // No anonymous user, no wrong token, no unencrypted channel.
    let refused = |r: Result<Ua, opcua::types::Error>| match r {
        Ok(_) => panic!("let in"),
        Err(e) => e.status(),
    };
    // A client that offers what the server does not take anyway.
    let anonymous = refused(Ua::connect(&rig.url, Login::Forged(offer_anonymous)).await);
    let open = refused(Ua::connect(&rig.url, Login::Forged(no_security)).await);
    let wrong = refused(Ua::connect(&rig.url, Login::Password("maint", "wrong-token-123")).await);
    assert_eq!(anonymous, StatusCode::BadIdentityTokenInvalid);
    // No endpoint without security to open a session on.
    assert!(open.is_bad(), "{open}");
    assert_eq!(wrong, StatusCode::BadUserAccessDenied);
    let ua = Ua::connect(&rig.url, Login::Password("maint", TOKEN))
        .await
        .expect("logged in");
    assert_eq!(ua.write(&demo(0, 2, 0), 3.5).await, StatusCode::Good);
    assert_eq!(
        ua.read(&demo(0, 2, 0)).await.value,
        Some(Variant::Double(3.5))
    );
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_certificate_store_is_in_its_folder_and_the_key_private() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    ua.close().await;
    let store = rig.pki.path().join("opcua");
    assert!(store.join(opcua_face::OWN_CERT).is_file());
    let key = store.join(opcua_face::OWN_KEY);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&key), 0o600);
        assert_eq!(mode(key.parent().unwrap()), 0o700);
    }
    // Neither the server nor a client made a store where nobody asked.
    assert!(!std::path::Path::new("pki").exists());
    assert!(!std::path::Path::new("pki-client").exists());
    rig.stop().await;
}

/// The same certificate serves the next start, until a month before it
/// expires.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_certificate_is_made_once_and_again_before_it_expires() {
    let pki = tempfile::tempdir().unwrap();
    let server = Server::bind(
        ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        },
        Objects(ObjectServer::new()),
    )
    .await
    .unwrap();
    drop(bind_face(&pki, None, server.core()).await);
    let cert = pki.path().join("opcua").join(opcua_face::OWN_CERT);
    let first = std::fs::read(&cert).unwrap();
    drop(bind_face(&pki, None, server.core()).await);
    assert_eq!(std::fs::read(&cert).unwrap(), first);
    // A certificate with less than a month to go is made anew.
    let key = pki.path().join("opcua").join(opcua_face::OWN_KEY);
    let mut short: X509Data = ApplicationDescription {
        application_name: "short".into(),
        application_uri: "urn:short".into(),
        ..Default::default()
    }
    .into();
    short.certificate_duration_days = u32::try_from(opcua_face::RENEW_DAYS - 1).unwrap();
    CertificateStore::create_certificate_and_key(&short, true, &cert, &key).unwrap();
    let expiring = std::fs::read(&cert).unwrap();
    drop(bind_face(&pki, None, server.core()).await);
    let renewed = std::fs::read(&cert).unwrap();
    assert_ne!(renewed, expiring);
    let end = CertificateStore::read_cert(&cert)
        .unwrap()
        .not_after()
        .unwrap();
    let now = opcua::types::DateTime::now().as_chrono();
    assert!((end - now).num_days() > 300, "valid until {end}");
}

/// Two items on one variable, sampled every 10 and every 200 ms: each
/// gets every change that stays, the slow one at its own pace too (the
/// library holds back a value that comes sooner than an item's interval
/// after the last one, and sends it only on a further change).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slower_item_still_gets_the_last_change() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = Client::connect(rig.uoi).await.expect("uoi");
    let speed = demo(0, 2, 0);
    let mut fast = ua.watch(&speed, 10.0).await;
    let mut slow = ua.watch(&speed, 200.0).await;
    until(&mut fast, &Variant::Double(0.0)).await;
    until(&mut slow, &Variant::Double(0.0)).await;
    let addr = ObjectAddress::new(BUS, 0, 2, 0);
    for v in [1.0, 2.0, 3.0] {
        uoi.write(addr, Value::F64(v)).await.unwrap();
        until(&mut fast, &Variant::Double(v)).await;
    }
    // 3 stays: the slow item gets it.
    until(&mut slow, &Variant::Double(3.0)).await;
    ua.close().await;
    rig.stop().await;
}

/// A Read whose values could not fit in one response is refused value by
/// value before they are copied: 5,000 times namespace 0's binary type
/// dictionary (about 200 kB) would be about a gigabyte, which the library
/// alone builds before it fails the whole service. Small values in any
/// number still read.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_read_too_large_for_a_response_is_refused_before_it_is_built() {
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let dictionary: opcua::types::NodeId = opcua::types::VariableId::OpcUa_BinarySchema.into();
    let many = ua.read_many(&vec![dictionary; 5000]).await;
    assert_eq!(many.len(), 5000);
    assert!(
        many.iter()
            .all(|v| v.status() == StatusCode::BadResponseTooLarge),
        "{:?}",
        many[0].status
    );
    let state: opcua::types::NodeId = opcua::types::VariableId::Server_ServerStatus_State.into();
    let mut small = vec![state; 5000];
    small.push(ua.node(&demo(0, 2, 0)));
    let read = ua.read_many(&small).await;
    assert!(read.iter().all(|v| v.status() == StatusCode::Good));
    ua.close().await;
    rig.stop().await;
}

/// A publishing interval of 1e12 ms (or an endless
/// one) is revised to the door's bound on a channel without security; an
/// ordinary one is kept. The client connects to the endpoint GetEndpoints
/// describes: the revision shows that its session went through the door
/// (the library advertised its inner port before, so such a client went
/// round the door).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_endless_publishing_interval_is_revised_to_a_bound() {
    use opcua::client::DataChangeCallback;
    use std::time::Duration;
    let rig = Rig::start(None).await;
    let ua = Ua::open(&rig.url).await;
    let mut revised = Vec::new();
    for asked in [
        Duration::from_secs(1_000_000_000),
        Duration::from_millis(250),
    ] {
        let id = ua
            .session
            .create_subscription(
                asked,
                3000,
                10,
                0,
                0,
                true,
                DataChangeCallback::new(|_, _| {}),
            )
            .await
            .expect("subscription");
        let state = ua.session.subscription_state().lock();
        revised.push(state.get(id).expect("kept").publishing_interval());
    }
    assert_eq!(
        revised,
        [Duration::from_secs(600), Duration::from_millis(250)]
    );
    ua.close().await;
    rig.stop().await;
}
