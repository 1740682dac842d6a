//! The OPC UA face of the emulator with a real OPC UA client
//! (async-opcua's) on loopback, beside the UOI face: the tree, reads and
//! writes of every device, every refusal status, subscriptions seeing the
//! UOI face's writes, the executor and the correction, and `addipos serve
//! --opcua` itself (open, and guarded by the access token). And the
//! emulator as a machine of OPC 40501-1: tools from its tool
//! tables, the wear of OTC in their ToolLife, every mandatory node.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;
#[path = "../opcua-face/tests/ua/mod.rs"]
mod ua;

use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::process::{Child, Command, Stdio};
use std::time::Instant;

use emulator::EmulatorService;
use opcua::types::{ObjectId, StatusCode, Variant};
use opcua_face::{Face, FaceConfig};
use tc_module::CycleTime;
use tc_objects::{OtcObject, TcObject, DEVICES, GROUPS};
use tc_request::text::parse_request;
use tc_request::Reply;
use tokio::task::JoinHandle;
use tokio_util::sync::CancellationToken;
use ua::{guarded, until, Login, Ua};
use uoi::tcp::{Client, ClientOptions, Handler, Server, ServerConfig};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

/// The emulator served by UOI and OPC UA faces in this process.
struct Rig {
    uoi: SocketAddr,
    url: String,
    _data: tempfile::TempDir,
    stop: CancellationToken,
    tasks: Vec<JoinHandle<()>>,
}

impl Rig {
    /// Both faces of a fresh emulator.
    async fn start() -> Rig {
        Self::with(EmulatorService::new([0.0; 8], CycleTime::DEFAULT)).await
    }

    /// Both faces of a fresh emulator, the machine of the Machine Tools
    /// model shown.
    async fn machine() -> Rig {
        let mut table = emulator::opcua::table();
        table.machine = Some(emulator::opcua::machine("T-7"));
        Self::serve(EmulatorService::new([0.0; 8], CycleTime::DEFAULT), table).await
    }

    /// Both faces of `service`.
    async fn with<H: Handler>(service: H) -> Rig {
        Self::serve(service, emulator::opcua::table()).await
    }

    /// Both faces of `service`, the face showing `table`.
    async fn serve<H: Handler>(service: H, table: opcua_face::Table) -> Rig {
        let data = tempfile::tempdir().expect("data dir");
        let cfg = ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        };
        let server = Server::bind(cfg, service).await.expect("bind");
        let uoi = server.local_addr().unwrap();
        let face_cfg = FaceConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            allow_remote: false,
            token: None,
            pki_dir: data.path().join("opcua"),
            host_names: None,
            subject: Default::default(),
        };
        let face = Face::bind(face_cfg, table, server.core())
            .await
            .expect("face");
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
            _data: data,
            stop,
            tasks,
        }
    }

    async fn client(&self) -> Client {
        guarded("uoi", Client::connect(self.uoi))
            .await
            .expect("uoi")
    }

    async fn stop(mut self) {
        self.stop.cancel();
        for t in self.tasks.drain(..) {
            guarded("stop", t).await.expect("task");
        }
    }
}

/// The NodeId string of the address after `a`'s subindex, which no object
/// holds (after RADIUS, `1/g/7`, comes WKZINDEX at 8).
fn no_object_after(a: ObjectAddress) -> String {
    ObjectAddress {
        sub: a.sub + 1,
        ..a
    }
    .to_string()
}

/// The NodeId string of index 0, subindex 0 of the device one past the
/// last of the table (docs/decisions.md, decision 522).
fn past_the_devices() -> String {
    format!("{}/{}/0/0", emulator::opcua::table().bus, DEVICES.len())
}

/// The NodeId string of the folder of `a`'s device.
fn device_folder(a: ObjectAddress) -> String {
    format!("{}/{}", a.bus, a.device)
}

/// The NodeId string of the folder of `a`'s group or axis (device 1 to 4).
fn instance_folder(a: ObjectAddress) -> String {
    format!("{}/{}/{}", a.bus, a.device, a.index)
}

/// Sends the trace request `line` over the UOI face: its reply.
async fn send(uoi: &mut Client, line: &str) -> Reply {
    let req = parse_request(line).expect("request");
    let answer = guarded(line, uoi.call(&req.to_wire()))
        .await
        .expect("answer");
    Reply::from_wire(req.wire_op(), &answer).expect("a reply")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_tree_of_bus_1300() {
    let rig = Rig::start().await;
    let ua = Ua::open(&rig.url).await;
    let objects = ObjectId::ObjectsFolder.into();
    assert!(ua.children(&objects).await.contains(&"Bus1300".to_string()));
    let devices = [
        "Device0",
        "Device1",
        "Device2",
        "Device3",
        "Device4",
        "Dashboard",
    ];
    assert_eq!(ua.children(&ua.node("1300")).await, devices);
    let groups: Vec<String> = (1..=32).map(|g| format!("Group{g}")).collect();
    let per_group = [
        TcObject::Radius.of(1),
        TcObject::TransitionMode.of(1),
        OtcObject::OtcOn.of(1),
    ];
    for device in per_group.map(device_folder) {
        assert_eq!(ua.children(&ua.node(&device)).await, groups);
    }
    let axes: Vec<String> = (0..8).map(|a| format!("Axis{a}")).collect();
    let device4 = device_folder(OtcObject::AxisOffsetCommand.of(0));
    assert_eq!(ua.children(&ua.node(&device4)).await, axes);
    let device0 = ua
        .children(&ua.node(&device_folder(TcObject::Clean.address())))
        .await;
    assert_eq!(
        device0[..5],
        ["Clean", "AxisNr[0]", "AxisNr[1]", "AxisNr[2]", "TcPlane"]
    );
    let group = ua
        .children(&ua.node(&instance_folder(TcObject::Error.of(7))))
        .await;
    assert_eq!(group[..4], ["ERROR", "RESET", "STATUS", "XAxis"]);
    assert_eq!(group.len(), 11);
    let otc = ua
        .children(&ua.node(&instance_folder(OtcObject::WearAxis.of(32))))
        .await;
    assert!(otc.contains(&"WearAxis[7]".to_string()), "{otc:?}");
    let axis = ua
        .children(&ua.node(&instance_folder(OtcObject::AxisOffsetCommand.of(7))))
        .await;
    assert_eq!(
        axis,
        [
            "OffsetCommand",
            "OffsetEnable",
            "OffsetRequest",
            "OffsetState"
        ]
    );
    let dash = ua.children(&ua.node("dashboard")).await;
    assert_eq!(dash, ["ExecutedPosition", "QueueLength", "Groups"]);
    let position = ua.children(&ua.node("dashboard/ExecutedPosition")).await;
    assert_eq!(position, ["X", "Y", "Z", "A", "B", "C", "U", "V"]);
    let dash_group = ua.children(&ua.node("dashboard/Groups/Group32")).await;
    assert_eq!(dash_group, ["STATUS", "ERROR"]);
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_device_read_and_written_through_either_face() {
    let rig = Rig::start().await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = rig.client().await;
    // OPC UA writes, the UOI face reads (devices 0 to 4).
    let writes: [(ObjectAddress, Value); 5] = [
        (TcObject::RotAngle.address(), Value::F64(12.5)),
        (TcObject::Radius.of(3), Value::F64(2.5)),
        (TcObject::TransitionMode.of(4), Value::I32(1)),
        (OtcObject::WearConst.of(5), Value::F64(3.25)),
        (OtcObject::AxisOffsetCommand.of(6), Value::I32(-70)),
    ];
    for (addr, v) in writes {
        let variant = match v {
            Value::I32(i) => Variant::Int32(i),
            Value::F64(d) => Variant::Double(d),
        };
        assert_eq!(
            ua.write(&addr.to_string(), variant).await,
            StatusCode::Good,
            "{addr}"
        );
        assert_eq!(
            uoi.read(addr, v.value_type()).await.expect("read"),
            v,
            "{addr}"
        );
    }
    // The UOI face writes, OPC UA reads.
    uoi.write(TcObject::WkzIndex.of(3), Value::I32(5))
        .await
        .unwrap();
    assert_eq!(
        ua.read(&TcObject::WkzIndex.of(3).to_string()).await.value,
        Some(Variant::Int32(5))
    );
    // RADIUS is the entry's at WKZINDEX: entry 5 has none yet.
    assert_eq!(
        ua.read(&TcObject::Radius.of(3).to_string()).await.value,
        Some(Variant::Double(0.0))
    );
    uoi.write(TcObject::AxisNr.sub(1), Value::I32(3))
        .await
        .unwrap();
    assert_eq!(
        ua.read(&TcObject::AxisNr.sub(1).to_string()).await.value,
        Some(Variant::Int32(3))
    );
    // Read-only objects and the dashboard.
    assert_eq!(
        ua.read(&OtcObject::WearAxis.sub_of(1, 0).to_string())
            .await
            .value,
        Some(Variant::Double(0.0))
    );
    assert_eq!(
        ua.read(&OtcObject::AxisOffsetState.of(0).to_string())
            .await
            .value,
        Some(Variant::Int32(0))
    );
    assert_eq!(
        ua.read("dashboard/queue").await.value,
        Some(Variant::Int32(0))
    );
    assert_eq!(
        ua.read("dashboard/group/3/STATUS").await.value,
        Some(Variant::Int32(0))
    );
    // One Read of many objects of every device.
    let nodes: Vec<_> = [
        TcObject::TcPlane.address().to_string(),
        TcObject::WkzIndex.of(3).to_string(),
        TcObject::TransitionMode.of(4).to_string(),
        OtcObject::WearConst.of(5).to_string(),
        OtcObject::AxisOffsetCommand.of(6).to_string(),
    ]
    .iter()
    .map(|s| ua.node(s))
    .collect();
    let values: Vec<_> = ua
        .read_many(&nodes)
        .await
        .into_iter()
        .map(|v| v.value)
        .collect();
    let expected = [
        Variant::Int32(17),
        Variant::Int32(5),
        Variant::Int32(1),
        Variant::Double(3.25),
        Variant::Int32(-70),
    ];
    assert_eq!(values, expected.map(Some));
    ua.close().await;
    rig.stop().await;
}

/// Every object of the table and every reading, as NodeId strings.
fn every_variable() -> Vec<String> {
    let table = emulator::opcua::table();
    let objects = table.rows.iter().flat_map(|r| {
        r.index.clone().flat_map(move |i| {
            r.sub
                .clone()
                .map(move |s| ObjectAddress::new(table.bus, r.device, i, s).to_string())
        })
    });
    let readings = table.readings.iter().map(|r| r.id.clone());
    objects.chain(readings).collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_read_of_every_variable() {
    let rig = Rig::start().await;
    let ua = Ua::open(&rig.url).await;
    let all: Vec<_> = every_variable().iter().map(|s| ua.node(s)).collect();
    assert!(all.len() > 1_400, "{}", all.len());
    let values = ua.read_many(&all).await;
    assert_eq!(values.len(), all.len());
    for (node, v) in all.iter().zip(&values) {
        let s = v.status();
        assert!(
            s.is_good() || s == StatusCode::BadNotReadable,
            "{node}: {s}"
        );
    }
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_refusal_has_its_status_and_changes_nothing() {
    let rig = Rig::start().await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = rig.client().await;
    let radius = TcObject::Radius.of(1).to_string();
    assert_eq!(ua.write(&radius, 2.0).await, StatusCode::Good);
    // Range, a non-finite double included.
    for bad in [2e9, -2e9, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            ua.write(&radius, bad).await,
            StatusCode::BadOutOfRange,
            "{bad}"
        );
    }
    assert_eq!(
        ua.write(&TcObject::WkzIndex.of(1).to_string(), 1024).await,
        StatusCode::BadOutOfRange
    );
    assert_eq!(
        ua.write(&TcObject::TcPlane.address().to_string(), 20).await,
        StatusCode::BadOutOfRange
    );
    // ReadOnly, WriteOnly, TypeMismatch, no such object.
    assert_eq!(
        ua.write(&OtcObject::WearRadius.of(1).to_string(), 1.0)
            .await,
        StatusCode::BadNotWritable
    );
    assert_eq!(
        ua.write("dashboard/position/X", 1.0).await,
        StatusCode::BadNotWritable
    );
    assert_eq!(
        ua.read(&TcObject::GroupReset.of(1).to_string())
            .await
            .status(),
        StatusCode::BadNotReadable
    );
    assert_eq!(
        ua.read(&TcObject::Clean.address().to_string())
            .await
            .status(),
        StatusCode::BadNotReadable
    );
    assert_eq!(ua.write(&radius, 3).await, StatusCode::BadTypeMismatch);
    assert_eq!(
        ua.write(&TcObject::WkzIndex.of(1).to_string(), 3.0).await,
        StatusCode::BadTypeMismatch
    );
    assert_eq!(
        ua.read(&TcObject::Radius.of(*GROUPS.end() + 1).to_string())
            .await
            .status(),
        StatusCode::BadNodeIdUnknown
    );
    assert_eq!(
        ua.write(&no_object_after(TcObject::Radius.of(1)), 1.0)
            .await,
        StatusCode::BadNodeIdUnknown
    );
    assert_eq!(
        ua.write(&past_the_devices(), 1).await,
        StatusCode::BadNodeIdUnknown
    );
    // State: ReInit while OTC is on without AllowPosReq.
    assert_eq!(
        ua.write(&OtcObject::ToolType.of(1).to_string(), 2).await,
        StatusCode::Good
    );
    assert_eq!(
        ua.write(&OtcObject::OtcOn.of(1).to_string(), 1).await,
        StatusCode::Good
    );
    assert_eq!(
        ua.write(&TcObject::ReInit.address().to_string(), 1).await,
        StatusCode::BadInvalidState
    );
    // Nothing changed.
    assert_eq!(
        uoi.read(TcObject::Radius.of(1), ValueType::F64)
            .await
            .unwrap(),
        Value::F64(2.0)
    );
    assert_eq!(
        uoi.read(TcObject::WkzIndex.of(1), ValueType::I32)
            .await
            .unwrap(),
        Value::I32(0)
    );
    assert_eq!(
        uoi.read(TcObject::TcPlane.address(), ValueType::I32)
            .await
            .unwrap(),
        Value::I32(17)
    );
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_value_the_disk_refuses_is_a_device_failure_and_nothing_changes() {
    use emulator::tools::durable::Durable;
    use tool_store::Writer;
    use tool_store::{FaultKind, FaultyStorage, MemStorage, Op, Strictness, ToolStore};
    // The second journal append fails: the first write is kept, the second refused.
    let storage = FaultyStorage::new(MemStorage::default()).fail_at(Op::Append, 2, FaultKind::Fail);
    let (store, _) = ToolStore::open(storage, Strictness::Strict).expect("store");
    let mut service = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    service.set_tools(Box::new(Durable::new(
        Writer::start(store).expect("writer"),
    )));
    let rig = Rig::with(service).await;
    let ua = Ua::open(&rig.url).await;
    let mut radius = ua.watch(&TcObject::Radius.of(1).to_string(), 10.0).await;
    until(&mut radius, &Variant::Double(0.0)).await;
    assert_eq!(
        ua.write(&TcObject::Radius.of(1).to_string(), 1.5).await,
        StatusCode::Good
    );
    until(&mut radius, &Variant::Double(1.5)).await;
    assert_eq!(
        ua.write(&TcObject::Radius.of(1).to_string(), 2.5).await,
        StatusCode::BadDeviceFailure
    );
    assert_eq!(
        ua.read(&TcObject::Radius.of(1).to_string()).await.value,
        Some(Variant::Double(1.5))
    );
    // The refused value was never notified: the next change is the next write.
    assert_eq!(
        ua.write(&TcObject::Radius.of(1).to_string(), 3.5).await,
        StatusCode::Good
    );
    let (next, _) = ua::next(&mut radius).await;
    assert_eq!(next.value, Some(Variant::Double(3.5)));
    ua.close().await;
    rig.stop().await;
}

/// Median, lowest and highest of `ms`.
fn spread(ms: &mut [f64]) -> String {
    ms.sort_by(f64::total_cmp);
    format!(
        "median {:.1} ms (min {:.1}, max {:.1}, n {})",
        ms[ms.len() / 2],
        ms[0],
        ms[ms.len() - 1],
        ms.len()
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subscriptions_see_the_uoi_face_the_executor_and_the_correction() {
    let rig = Rig::start().await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = rig.client().await;
    // A UOI-side write reaches a monitored item sampled every 10 ms.
    let mut radius = ua.watch(&TcObject::Radius.of(1).to_string(), 10.0).await;
    until(&mut radius, &Variant::Double(0.0)).await;
    let mut latency = Vec::new();
    for k in 1..=20 {
        let v = f64::from(k) * 0.5;
        uoi.write(TcObject::Radius.of(1), Value::F64(v))
            .await
            .unwrap();
        let written = Instant::now();
        let seen = until(&mut radius, &Variant::Double(v)).await;
        latency.push(seen.saturating_duration_since(written).as_secs_f64() * 1e3);
    }
    // Measured, not asserted: the figure for docs/opcua.md.
    eprintln!("UOI write to OPC UA notification: {}", spread(&mut latency));
    // The executor moves the machine: the executed position follows.
    let mut x = ua.watch("dashboard/position/X", 10.0).await;
    until(&mut x, &Variant::Double(0.0)).await;
    let mut queue = ua.watch("dashboard/queue", 10.0).await;
    until(&mut queue, &Variant::Int32(0)).await;
    assert_eq!(send(&mut uoi, "LIN X10 F60000").await, Reply::Ok);
    until(&mut queue, &Variant::Int32(1)).await;
    assert_eq!(send(&mut uoi, "EXEC").await, Reply::Ok);
    let executed = Instant::now();
    let seen = until(&mut x, &Variant::Double(10.0)).await;
    until(&mut queue, &Variant::Int32(0)).await;
    eprintln!(
        "EXEC to position notification: {:.1} ms",
        seen.saturating_duration_since(executed).as_secs_f64() * 1e3
    );
    // The correction sets ERROR bits (CalcError: the offset arc vanishes).
    let mut error = ua.watch("dashboard/group/1/ERROR", 10.0).await;
    until(&mut error, &Variant::Int32(0)).await;
    for line in [
        "W 1300/1/1/8 i 1",
        "W 1300/1/1/6 d 2",
        "W 1300/1/1/9 i 0",
        "W 1300/1/1/3 i 1",
        "LIN X20 Y0",
        "CIR CCW X20 Y2 I0 J1",
    ] {
        assert_eq!(send(&mut uoi, line).await, Reply::Ok, "{line}");
    }
    let refused = Instant::now();
    let seen = until(&mut error, &Variant::Int32(4)).await;
    eprintln!(
        "correction error to ERROR notification: {:.1} ms",
        seen.saturating_duration_since(refused).as_secs_f64() * 1e3
    );
    // The fault refuses further motion until ERROR is written.
    assert_eq!(
        send(&mut uoi, "LIN X0").await,
        Reply::Access(AccessError::State)
    );
    assert_eq!(
        ua.write(&TcObject::Error.of(1).to_string(), 0).await,
        StatusCode::Good
    );
    until(&mut error, &Variant::Int32(0)).await;
    ua.close().await;
    rig.stop().await;
}

/// A running `addipos serve` with the OPC UA face, in its own working
/// directory; killed when dropped.
struct Serve {
    child: Child,
    uoi: String,
    url: String,
    dir: tempfile::TempDir,
}

impl Serve {
    /// `addipos serve ARGS --opcua 127.0.0.1:0` on free ports, its data in
    /// `data/` of a fresh working directory; waits for both start lines.
    fn start(args: &[&str]) -> Serve {
        let dir = tempfile::tempdir().expect("dir");
        let mut child = common::bin()
            .current_dir(dir.path())
            .args([
                "serve",
                "--listen",
                "127.0.0.1:0",
                "--opcua",
                "127.0.0.1:0",
                "--data-dir",
                "data",
                "--no-persist",
            ])
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("serve");
        let mut err = BufReader::new(child.stderr.take().expect("stderr"));
        let (mut uoi, mut url) = (None, None);
        let mut line = String::new();
        while uoi.is_none() || url.is_none() {
            line.clear();
            assert!(err.read_line(&mut line).expect("log") > 0, "serve ended");
            let field = |key: &str| {
                line.split_whitespace()
                    .find_map(|w| w.strip_prefix(key))
                    .map(str::to_string)
            };
            uoi = uoi.or_else(|| field("listen="));
            url = url.or_else(|| field("endpoint="));
        }
        // The rest of the log is not read: keep the pipe from filling.
        std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));
        Serve {
            child,
            uoi: uoi.unwrap(),
            url: url.unwrap(),
            dir,
        }
    }
}

impl Serve {
    /// Stops the server gracefully (SIGTERM); its exit status, within the
    /// hang guard.
    fn terminate(&mut self) -> std::process::ExitStatus {
        let pid = self.child.id().to_string();
        let term = Command::new("kill")
            .args(["-TERM", &pid])
            .status()
            .expect("kill");
        assert!(term.success());
        let t0 = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                return status;
            }
            assert!(t0.elapsed() < ua::GUARD, "serve did not stop on SIGTERM");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    }
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn serve_opcua_shares_the_emulator_with_the_uoi_face() {
    let mut serve = Serve::start(&[]);
    let ua = Ua::open(&serve.url).await;
    let mut uoi = guarded("uoi", Client::connect(serve.uoi.as_str()))
        .await
        .expect("uoi");
    // An OPC UA write is what the UOI face reads.
    assert_eq!(
        ua.write(&TcObject::Radius.of(2).to_string(), 6.25).await,
        StatusCode::Good
    );
    assert_eq!(
        uoi.read(TcObject::Radius.of(2), ValueType::F64)
            .await
            .unwrap(),
        Value::F64(6.25)
    );
    // A UOI write is what a subscription sees.
    let mut len = ua.watch(&TcObject::WkzLen.of(2).to_string(), 10.0).await;
    until(&mut len, &Variant::Double(0.0)).await;
    uoi.write(TcObject::WkzLen.of(2), Value::F64(-4.5))
        .await
        .unwrap();
    until(&mut len, &Variant::Double(-4.5)).await;
    // A stop signal ends both faces, with an OPC UA session open.
    assert!(serve.terminate().success());
    drop(ua);
    // The certificate store is in the data directory, nowhere else.
    assert!(serve
        .dir
        .path()
        .join("data/opcua")
        .join(opcua_face::OWN_CERT)
        .is_file());
    assert!(!serve.dir.path().join("pki").exists());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn with_allow_remote_the_face_wants_the_access_token() {
    let serve = Serve::start(&["--allow-remote"]);
    let token = std::fs::read_to_string(serve.dir.path().join("data/access-token")).expect("token");
    let token = token.trim();
    let refused = Ua::connect(&serve.url, Login::Password("maint", "not-the-token-at-all")).await;
    assert_eq!(
        refused.err().map(|e| e.status()),
        Some(StatusCode::BadUserAccessDenied)
    );
    let ua = Ua::connect(&serve.url, Login::Password("maint", token))
        .await
        .expect("login");
    assert_eq!(
        ua.write(&TcObject::Radius.of(1).to_string(), 1.25).await,
        StatusCode::Good
    );
    ua.close().await;
    // The UOI face asks other machines for the same token (not loopback).
    let opts = ClientOptions {
        token: Some(uoi::tcp::AccessToken::new(token).unwrap()),
        ..ClientOptions::default()
    };
    let mut uoi = guarded("uoi", Client::connect_with(serve.uoi.as_str(), &opts))
        .await
        .expect("uoi");
    assert_eq!(
        uoi.read(TcObject::Radius.of(1), ValueType::F64)
            .await
            .unwrap(),
        Value::F64(1.25)
    );
}

#[test]
fn an_opcua_address_of_another_machine_needs_allow_remote() {
    let dir = tempfile::tempdir().expect("dir");
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .current_dir(dir.path())
        .args([
            "serve",
            "--listen",
            "127.0.0.1:0",
            "--opcua",
            "0.0.0.0:0",
            "--no-persist",
        ])
        .output()
        .expect("serve");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("OPC UA") && err.contains("--allow-remote"),
        "{err}"
    );
}

/// Waits until the Value of `id` is `want`.
async fn shows(ua: &Ua, id: &str, want: Variant) {
    guarded(id, async {
        while ua.read(id).await.value != Some(want.clone()) {
            tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        }
    })
    .await;
}

/// The Double a variable holds.
async fn double(ua: &Ua, id: &str) -> f64 {
    match ua.read(id).await.value {
        Some(Variant::Double(v)) => v,
        other => panic!("{id}: {other:?}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_tool_tables_and_the_wear_of_otc_as_a_machine_tool() {
    let rig = Rig::machine().await;
    let ua = Ua::open(&rig.url).await;
    let mut uoi = rig.client().await;
    // A radius written to an empty entry makes a tool of it.
    for line in ["W 1300/1/2/8 i 5", "W 1300/1/2/6 d 2.5"] {
        assert_eq!(send(&mut uoi, line).await, Reply::Ok, "{line}");
    }
    shows(&ua, "machine/tool/2/5/Radius", Variant::from(2.5)).await;
    assert_eq!(
        ua.read("machine/tool/2/5/ControlIdentifier1").await.value,
        Some(Variant::from(5u32))
    );
    assert_eq!(
        ua.read("machine/tool/2/5/ControlIdentifier2").await.value,
        Some(Variant::from(2u32))
    );
    // The grinding disc of the OTC manual in entry 1 of group 1, and the
    // general example's motion (docs/otc.md), run 1000 cycles of the way:
    // through the approach and into the corrected profile that wears.
    for line in [
        "W 1300/1/1/8 i 1",
        "W 1300/3/1/30 i 2",
        "W 1300/1/1/6 d 30",
        "W 1300/3/1/31 d 100000",
        "RAP X0 Y0 Z0 F10000",
        "W 1300/3/1/2 i 0",
        "W 1300/3/1/3 i 2",
        "EXEC",
        "W 1300/3/1/1 i 1",
        "W 1300/1/1/9 i 1",
        "W 1300/1/1/3 i 1",
        "LIN X50",
        "LIN X1000",
        "W 1300/1/1/3 i 0",
        "LIN X50",
        "EXEC 1000",
    ] {
        assert_eq!(send(&mut uoi, line).await, Reply::Ok, "{line}");
    }
    // While OTC runs, the disc's ToolLife has the wear not yet booked, and
    // the channel is active (motion is waiting).
    let running = "machine/tool/1/1/ToolLife/RunningWear";
    let started = guarded("running wear", async {
        loop {
            match ua.read(running).await.value {
                Some(Variant::Double(w)) if w > 0.0 => return w,
                _ => {}
            }
            tokio::time::sleep(std::time::Duration::from_millis(20)).await;
        }
    })
    .await;
    shows(
        &ua,
        "machine/Monitoring/Channel1/ChannelState",
        Variant::from(0i32),
    )
    .await;
    for line in ["EXEC", "W 1300/3/1/1 i 0"] {
        assert_eq!(send(&mut uoi, line).await, Reply::Ok, "{line}");
    }
    // Switched off: the wear is booked (WearRadius) and the running entry
    // gone; the disc's radius is smaller by it.
    let booked = match send(&mut uoi, "R 1300/3/1/10 d").await {
        Reply::Value(Value::F64(w)) => w,
        other => panic!("{other:?}"),
    };
    assert!(booked > started, "{booked} after {started}");
    shows(
        &ua,
        "machine/tool/1/1/ToolLife/WearRadius",
        Variant::from(booked),
    )
    .await;
    assert_eq!(
        ua.read(running).await.status,
        Some(StatusCode::BadNodeIdUnknown)
    );
    assert_eq!(double(&ua, "machine/tool/1/1/Radius").await, 30.0 - booked);
    shows(
        &ua,
        "machine/Monitoring/Channel1/ChannelState",
        Variant::from(2i32),
    )
    .await;
    // Every mandatory node of every type, as the server's type model has it.
    let machine = ua.node("machine");
    let report = ua::model::Walk::check(&ua, &machine, "machine").await;
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    assert!(report
        .checked
        .iter()
        .any(|c| c.ends_with("G1 T1/ToolLife/WearRadius")));
    let serial = ua.read("machine/Identification/SerialNumber").await.value;
    assert_eq!(serial, Some(Variant::from("T-7")));
    ua.close().await;
    rig.stop().await;
}

/// The TCP ports process `pid` listens on: its sockets (the inodes of
/// `/proc/PID/fd`) in state LISTEN in `/proc/net/tcp` and `tcp6`.
fn listening_ports(pid: u32) -> Vec<u16> {
    let mut inodes = std::collections::HashSet::new();
    for fd in std::fs::read_dir(format!("/proc/{pid}/fd")).expect("fds") {
        let target = std::fs::read_link(fd.expect("fd").path()).unwrap_or_default();
        let target = target.to_string_lossy();
        if let Some(inode) = target
            .strip_prefix("socket:[")
            .and_then(|s| s.strip_suffix(']'))
        {
            inodes.insert(inode.to_string());
        }
    }
    let mut ports = Vec::new();
    for table in ["/proc/net/tcp", "/proc/net/tcp6"] {
        let text = std::fs::read_to_string(table).unwrap_or_default();
        for row in text.lines().skip(1) {
            let cols: Vec<&str> = row.split_whitespace().collect();
            // local address, state (0A: LISTEN), inode.
            let (local, state, inode) = (cols[1], cols[3], cols[9]);
            if state == "0A" && inodes.contains(inode) {
                let port = local.rsplit(':').next().expect("port");
                ports.push(u16::from_str_radix(port, 16).expect("hex port"));
            }
        }
    }
    ports.sort_unstable();
    ports
}

/// The port of a `HOST:PORT` or an `opc.tcp://HOST:PORT/` URL.
fn port_of(addr: &str) -> u16 {
    let tail = addr.trim_end_matches('/').rsplit(':').next().expect("port");
    tail.parse().expect("port number")
}

/// The OPC UA library listens on no port of its own: a client on this
/// machine cannot go round the door (its connection cap, activation
/// deadline and chunk check). With a session open, the server listens on
/// the configured UOI and OPC UA ports only.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn serve_opcua_listens_on_the_configured_ports_only() {
    let serve = Serve::start(&[]);
    let ua = Ua::open(&serve.url).await;
    assert_eq!(
        ua.write(&TcObject::Radius.of(2).to_string(), 1.5).await,
        StatusCode::Good
    );
    let mut want = vec![port_of(&serve.uoi), port_of(&serve.url)];
    want.sort_unstable();
    assert_eq!(listening_ports(serve.child.id()), want);
    ua.close().await;
}
