//! The machine of the OPC UA for Machine Tools model (OPC 40501-1) over a
//! bench handler whose tools the tests change directly (through the
//! server's core handle, as the emulator's own tables change), with
//! async-opcua's client: every mandatory node of every type instantiated,
//! checked against the type model the server loaded from the NodeSets; the
//! tool list following the tools with model-change events and its
//! NodeVersion; values, running wear and the channel's state following the
//! machine.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod ua;

use std::any::Any;
use std::sync::Arc;
use std::time::Duration;

use opcua::types::{
    BrowseDirection, EUInformation, LocalizedText, NodeId, ObjectTypeId, ReferenceTypeId, Variant,
};
use opcua_face::{
    ChannelState, Face, FaceConfig, Identity, MachineSource, MachineTool, MachineView, Table,
    ToolRecord, MACHINERY, MACHINE_TOOL,
};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;
use tokio_util::sync::CancellationToken;
use ua::model::Walk;
use ua::{guarded, until, Ua};
use uoi::tcp::{CoreHandle, Handler, Server, ServerConfig, Slice};
use uoi::wire::{Answer, Request};
use uoi::AccessError;

/// A handler that only holds what the machine looks like.
struct Bench(MachineView);

impl Handler for Bench {
    type Session = ();
    type Rest = Request;
    fn open_session(&mut self) {}
    fn serve(&mut self, _req: Request) -> Slice {
        Slice::Done(Answer::Access(AccessError::NoObject))
    }
}

/// The bench's machine, as the face looks at it.
struct BenchSource;

impl MachineSource for BenchSource {
    fn look(&self, handler: &mut dyn Any) -> Option<MachineView> {
        handler.downcast_mut::<Bench>().map(|b| b.0.clone())
    }
}

fn tool(group: u32, number: u32, radius: f64) -> ToolRecord {
    ToolRecord {
        group,
        number,
        radius,
        length: 40.0,
        kind: 2,
        wear: 0.0,
        running_wear: None,
    }
}

fn machine() -> MachineTool {
    MachineTool {
        name: "bench".into(),
        identity: Identity {
            manufacturer: "maker".into(),
            model: "model".into(),
            software_revision: "1.2.3".into(),
            serial_number: "S-1".into(),
            product_instance_uri: "urn:maker:S-1".into(),
        },
        tool_kinds: ["a", "b", "c"].map(String::from).to_vec(),
        source: Arc::new(BenchSource),
    }
}

/// The bench served with the face.
struct Rig {
    url: String,
    core: CoreHandle,
    _pki: tempfile::TempDir,
    stop: CancellationToken,
    tasks: Vec<JoinHandle<()>>,
}

impl Rig {
    async fn start(tools: Vec<ToolRecord>) -> Rig {
        let pki = tempfile::tempdir().expect("pki");
        let cfg = ServerConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            ..ServerConfig::default()
        };
        let view = MachineView {
            state: ChannelState::Idle,
            tools,
        };
        let server = Server::bind(cfg, Bench(view)).await.expect("bind");
        let core = server.core();
        let table = Table {
            bus: 9,
            devices: Vec::new(),
            rows: Vec::new(),
            readings: Vec::new(),
            machine: Some(machine()),
        };
        let face_cfg = FaceConfig {
            listen: "127.0.0.1:0".parse().unwrap(),
            allow_remote: false,
            token: None,
            pki_dir: pki.path().join("opcua"),
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
            url,
            core,
            _pki: pki,
            stop,
            tasks,
        }
    }

    /// Changes the bench's machine.
    async fn change(&self, f: impl FnOnce(&mut MachineView) + Send + 'static) {
        self.core
            .inspect(move |h| f(&mut h.downcast_mut::<Bench>().expect("bench").0))
            .await
            .expect("served");
    }

    async fn stop(mut self) {
        self.stop.cancel();
        for t in self.tasks.drain(..) {
            guarded("stop", t).await.expect("task");
        }
    }
}

/// The index of namespace `uri`.
async fn ns(ua: &Ua, uri: &str) -> u16 {
    let array = ua
        .read_attr(
            &opcua::types::VariableId::Server_NamespaceArray.into(),
            opcua::types::AttributeId::Value,
        )
        .await;
    let Some(Variant::Array(a)) = array.value else {
        panic!("{array:?}")
    };
    let i = a
        .values
        .iter()
        .position(|u| matches!(u, Variant::String(s) if s.as_ref() == uri))
        .unwrap_or_else(|| panic!("{uri} not served"));
    u16::try_from(i).unwrap()
}

/// The machines in the Machines folder: (NodeId, TypeDefinition).
async fn machines(ua: &Ua) -> Vec<(NodeId, NodeId)> {
    let folder = NodeId::new(ns(ua, MACHINERY).await, 1001u32);
    ua.browse(
        &folder,
        ReferenceTypeId::Organizes,
        BrowseDirection::Forward,
    )
    .await
    .into_iter()
    .map(|r| (r.node_id.node_id, r.type_definition.node_id))
    .collect()
}

/// Waits until the value of `id` is `want`.
async fn shows(ua: &Ua, id: &str, want: Variant) {
    guarded(id, async {
        loop {
            if ua.read(id).await.value == Some(want.clone()) {
                return;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    })
    .await;
}

/// Waits for the next model-change event of `rx`, from `list` (the
/// fields asked for: EventType, SourceNode).
///
/// The `Changes` of the event are not asked for here: async-opcua's client
/// does not deliver an event whose fields hold an array of structures
/// (tests/opcua_machine.py reads them with Python asyncua).
async fn model_change(rx: &mut mpsc::UnboundedReceiver<Vec<Variant>>, list: &NodeId) {
    let fields = guarded("model change", rx.recv()).await.expect("open");
    let gmce: NodeId = ObjectTypeId::GeneralModelChangeEventType.into();
    assert_eq!(fields, [Variant::from(gmce), Variant::from(list.clone())]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_mandatory_node_of_every_type_instantiated() {
    let mut running = tool(1, 7, 3.0);
    running.running_wear = Some(0.25);
    let rig = Rig::start(vec![tool(1, 5, 2.5), running, tool(3, 0, 1.0)]).await;
    let ua = Ua::open(&rig.url).await;
    let found = machines(&ua).await;
    let mt = ns(&ua, MACHINE_TOOL).await;
    assert_eq!(found.len(), 1, "{found:?}");
    let (machine, ty) = &found[0];
    assert_eq!(*ty, NodeId::new(mt, 13u32), "MachineToolType");
    shows(
        &ua,
        "machine/Equipment/Tools/NodeVersion",
        Variant::from("1"),
    )
    .await;
    let report = Walk::check(&ua, machine, "bench").await;
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    // The walk went down every tool to each ToolLife entry.
    for path in [
        "bench/Equipment/Tools/G1 T5/ToolLife/WearRadius",
        "bench/Equipment/Tools/G1 T7/ToolLife/RunningWear",
        "bench/Equipment/Tools/G3 T0/Locked/ReasonForLocking",
        "bench/Equipment/Tools/G3 T0/Radius/EngineeringUnits",
        "bench/Equipment/Tools/G3 T0/ToolKind/EnumStrings",
    ] {
        assert!(
            report.checked.iter().any(|c| c == path),
            "{path} not checked"
        );
    }
    // The walk finds what is missing: the tool list is no machine.
    let list = ua.node("machine/Equipment/Tools");
    let wrong = Walk::check_as(&ua, &list, "list", &NodeId::new(mt, 13u32)).await;
    assert!(
        wrong
            .problems
            .iter()
            .any(|p| p == "list/Identification: missing"),
        "{:?}",
        wrong.problems
    );
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tools_come_and_go_with_model_change_events() {
    let rig = Rig::start(vec![tool(1, 5, 2.5)]).await;
    let ua = Ua::open(&rig.url).await;
    let mt = ns(&ua, MACHINE_TOOL).await;
    let list = ua.node("machine/Equipment/Tools");
    shows(&ua, "machine/tool/1/5/Radius", Variant::from(2.5)).await;
    let version = ua.read("machine/Equipment/Tools/NodeVersion").await.value;
    let mut events = ua
        .events(
            &list,
            ObjectTypeId::GeneralModelChangeEventType.into(),
            &["EventType", "SourceNode"],
        )
        .await;
    let mut radius = ua.watch("machine/tool/1/5/Radius", 10.0).await;
    rig.change(|m| m.tools.push(tool(2, 9, 4.0))).await;
    model_change(&mut events, &list).await;
    let tools = ua
        .browse(
            &list,
            ReferenceTypeId::HasComponent,
            BrowseDirection::Forward,
        )
        .await;
    let tool_id = ua.node("machine/tool/2/9");
    let added = tools
        .iter()
        .find(|r| r.node_id.node_id == tool_id)
        .expect("G2 T9 listed");
    assert_eq!(
        added.type_definition.node_id,
        NodeId::new(mt, 50u32),
        "ToolType"
    );
    assert_eq!(added.browse_name.name.as_ref(), "G2 T9");
    assert_eq!(
        ua.read("machine/tool/2/9/Radius").await.value,
        Some(Variant::from(4.0))
    );
    let name = ua.read("machine/tool/2/9/Name").await.value;
    assert_eq!(name, Some(Variant::from("G2 T9")));
    assert_ne!(
        ua.read("machine/Equipment/Tools/NodeVersion").await.value,
        version
    );
    // A value that changes is a data change, not a model change.
    rig.change(|m| m.tools[0].radius = 2.25).await;
    until(&mut radius, &Variant::from(2.25)).await;
    // A compensation starts and stops on a tool: its RunningWear comes
    // and goes.
    let life = ua.node("machine/tool/1/5/ToolLife");
    assert_eq!(ua.children(&life).await, ["WearRadius"]);
    rig.change(|m| m.tools[0].running_wear = Some(0.5)).await;
    model_change(&mut events, &list).await;
    assert_eq!(ua.children(&life).await, ["RunningWear", "WearRadius"]);
    assert_eq!(
        ua.read("machine/tool/1/5/ToolLife/RunningWear").await.value,
        Some(Variant::from(0.5))
    );
    rig.change(|m| {
        m.tools[0].running_wear = None;
        m.tools[0].wear = 0.5;
    })
    .await;
    model_change(&mut events, &list).await;
    assert_eq!(ua.children(&life).await, ["WearRadius"]);
    shows(
        &ua,
        "machine/tool/1/5/ToolLife/WearRadius",
        Variant::from(0.5),
    )
    .await;
    let before = ua.read("machine/Equipment/Tools/NodeVersion").await.value;
    rig.change(|m| m.tools.retain(|t| t.number != 9)).await;
    model_change(&mut events, &list).await;
    assert_eq!(ua.children(&list).await, ["G1 T5", "NodeVersion"]);
    assert_ne!(
        ua.read("machine/Equipment/Tools/NodeVersion").await.value,
        before
    );
    ua.close().await;
    rig.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_channel_and_the_program_follow_the_machine() {
    let rig = Rig::start(Vec::new()).await;
    let ua = Ua::open(&rig.url).await;
    let state = "machine/Monitoring/Channel1/ChannelState";
    let program = "machine/Production/ActiveProgram/State/CurrentState";
    shows(&ua, state, Variant::from(2i32)).await;
    assert_eq!(
        ua.read(program).await.value,
        Some(Variant::from(LocalizedText::from("Initializing")))
    );
    rig.change(|m| m.state = ChannelState::Running).await;
    shows(&ua, state, Variant::from(0i32)).await;
    assert_eq!(
        ua.read(program).await.value,
        Some(Variant::from(LocalizedText::from("Running")))
    );
    rig.change(|m| m.state = ChannelState::Interrupted).await;
    shows(&ua, state, Variant::from(1i32)).await;
    rig.change(|m| m.state = ChannelState::Idle).await;
    shows(&ua, state, Variant::from(2i32)).await;
    assert_eq!(
        ua.read(program).await.value,
        Some(Variant::from(LocalizedText::from("Ended")))
    );
    let ident = ua.read("machine/Identification/SerialNumber").await.value;
    assert_eq!(ident, Some(Variant::from("S-1")));
    // Read-only, and a node the server does not have is still unknown.
    let write = ua.write("machine/Identification/SerialNumber", "S-2").await;
    assert_eq!(write, opcua::types::StatusCode::BadNotWritable);
    let nowhere = ua.write("machine/Identification/Nothing", "S-2").await;
    assert_eq!(nowhere, opcua::types::StatusCode::BadNodeIdUnknown);
    let unit = ua
        .read("machine/Monitoring/Channel1/FeedOverride/EngineeringUnits")
        .await;
    let Some(Variant::ExtensionObject(eu)) = unit.value else {
        panic!("{unit:?}")
    };
    let eu = eu.inner_as::<EUInformation>().expect("EUInformation");
    assert_eq!(eu.display_name.text.as_ref(), "%");
    ua.close().await;
    rig.stop().await;
}
