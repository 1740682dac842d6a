//! Keeping the machine up to date: every [`POLL`] the face looks at the
//! machine (through the object server's handler, between two requests)
//! and brings the nodes in line. A tool that appears is added to the tool
//! list, one that goes is deleted, each time with a
//! GeneralModelChangeEvent from the tool list and a new `NodeVersion`
//! (OPC 10000-3, 9.32); a changed value (radius, wear, the channel's
//! state) is written to its variable, and subscribers see it.

use std::collections::BTreeMap;
use std::sync::{Arc, Weak};
use std::time::Duration;

use opcua::server::address_space::AddressSpace;
use opcua::server::node_manager::memory::InMemoryNodeManager;
use opcua::server::SubscriptionCache;
use opcua::types::{
    DataValue, DateTime, LocalizedText, ModelChangeStructureDataType, NodeId, ObjectTypeId,
    StatusCode, Variant,
};
use tokio::time::MissedTickBehavior;
use uoi::tcp::CoreHandle;

use super::event::{verb, ModelChange};
use super::handles::{MachineVar, NodeTable, RunningVar};
use super::instance::Template;
use super::model::{channel_code, mt, Spaces, MACHINE, TOOLS};
use super::tools::{self, ToolTemplates, LIFE, LIVE};
use super::view::{ChannelState, MachineSource, MachineTool, MachineView, ToolRecord};
use crate::manager::ObjectNodes;

/// How often the face looks at the machine: the longest a change takes
/// to show (the poll holds the handler for the time it takes to walk
/// the tool tables).
pub const POLL: Duration = Duration::from_millis(100);

/// Most tools the list shows: the first ones by table and number. Each
/// tool is 19 nodes, about 43 kB of server memory; the tables could hold
/// 32,768 tools, which one UOI client could write.
pub const MAX_TOOLS: usize = 1024;

/// The manager whose address space holds the machine.
pub(crate) type Manager = InMemoryNodeManager<ObjectNodes>;

/// A tool on show: its record and the nodes made for it.
struct Shown {
    record: ToolRecord,
    nodes: Vec<NodeId>,
    running: Vec<NodeId>,
}

/// The states of the active program's state machine this server uses:
/// name, NodeId, number.
pub(crate) type ProgramStates = Vec<(&'static str, NodeId, u32)>;

/// What the machine's nodes show now, and how to change them.
pub(crate) struct Live {
    at: Spaces,
    source: Arc<dyn MachineSource>,
    templates: ToolTemplates,
    program: ProgramStates,
    shown: BTreeMap<(u32, u32), Shown>,
    state: Option<ChannelState>,
    ran: bool,
    version: u64,
    events: u64,
    capped: bool,
}

/// What one look changes: model changes, values, and the list's own verb.
#[derive(Default)]
struct Changes {
    model: Vec<ModelChangeStructureDataType>,
    list: u8,
    values: Vec<(NodeId, Variant)>,
}

impl Live {
    /// The live state of `machine`, shown through `templates`.
    pub fn new(
        at: Spaces,
        machine: &MachineTool,
        templates: ToolTemplates,
        program: ProgramStates,
    ) -> Self {
        Self {
            at,
            source: Arc::clone(&machine.source),
            templates,
            program,
            shown: BTreeMap::new(),
            state: None,
            ran: false,
            version: 0,
            events: 0,
            capped: false,
        }
    }

    fn id(&self, base: &str, path: &str) -> NodeId {
        Template::id(self.at.own, base, path)
    }

    /// The running-wear entry of the tool at `base`.
    fn running_wear(&self, base: &str) -> NodeId {
        let below = format!("{LIFE}/{}", RunningVar::RunningWear.path());
        self.id(base, &below)
    }

    /// Brings the nodes of `manager` in line with `view`; subscribers of
    /// `subscriptions` see the changes.
    pub fn apply(
        &mut self,
        view: MachineView,
        manager: &Manager,
        subscriptions: &SubscriptionCache,
    ) {
        let mut tools = view.tools;
        tools.sort_by_key(|r| (r.group, r.number));
        tools.dedup_by_key(|r| (r.group, r.number));
        if tools.len() > MAX_TOOLS && !self.capped {
            tracing::warn!(
                tools = tools.len(),
                shown = MAX_TOOLS,
                "OPC UA: more tools than the tool list shows"
            );
        }
        self.capped = tools.len() > MAX_TOOLS;
        tools.truncate(MAX_TOOLS);
        let mut c = Changes::default();
        {
            let mut space = manager.address_space().write();
            self.remove_gone(&mut space, &tools, &mut c);
            for r in &tools {
                self.show(&mut space, r, &mut c);
            }
        }
        self.state_values(view.state, &mut c);
        if c.list != 0 {
            self.version += 1;
            c.values.push((
                self.at.machine_var(MachineVar::NodeVersion),
                self.version.to_string().into(),
            ));
        }
        write(manager, subscriptions, &c.values);
        if !c.model.is_empty() {
            self.notify(subscriptions, c);
        }
    }

    /// Deletes the tools no longer in `tools`.
    fn remove_gone(&mut self, space: &mut AddressSpace, tools: &[ToolRecord], c: &mut Changes) {
        let keep: std::collections::HashSet<(u32, u32)> =
            tools.iter().map(|r| (r.group, r.number)).collect();
        let gone: Vec<(u32, u32)> = self
            .shown
            .keys()
            .filter(|k| !keep.contains(k))
            .copied()
            .collect();
        for key in gone {
            let Some(s) = self.shown.remove(&key) else {
                continue;
            };
            for id in s.running.iter().chain(&s.nodes).rev() {
                space.delete(id, true);
            }
            c.model.push(change(
                self.id(&tools::base(key.0, key.1), ""),
                self.templates.tool_type.clone(),
                verb::NODE_DELETED | verb::REFERENCE_DELETED,
            ));
            c.list |= verb::REFERENCE_DELETED;
        }
    }

    /// Adds tool `r`, or brings it up to date.
    fn show(&mut self, space: &mut AddressSpace, r: &ToolRecord, c: &mut Changes) {
        let base = tools::base(r.group, r.number);
        let key = (r.group, r.number);
        let Some(old) = self.shown.get(&key).map(|s| s.record) else {
            let list = self.id(MACHINE, TOOLS);
            let tool = tools::of(&self.templates, r, self.at.own);
            let nodes = tool.place(space, self.at.own, &base, &list);
            let id = self.id(&base, "");
            let added = verb::NODE_ADDED | verb::REFERENCE_ADDED;
            c.model
                .push(change(id, self.templates.tool_type.clone(), added));
            c.list |= verb::REFERENCE_ADDED;
            let running = match r.running_wear {
                Some(_) => self.place_running(space, &base, r, c),
                None => Vec::new(),
            };
            let shown = Shown {
                record: *r,
                nodes,
                running,
            };
            self.shown.insert(key, shown);
            return;
        };
        for v in LIVE {
            let new = tools::value(r, v);
            if let Some(value) = new.filter(|n| Some(n) != tools::value(&old, v).as_ref()) {
                c.values.push((self.id(&base, v.path()), value));
            }
        }
        self.running(space, &base, &old, r, c);
        if let Some(s) = self.shown.get_mut(&key) {
            s.record = *r;
        }
    }

    /// The running-wear entry of a tool shown (`old` its record before,
    /// `r` now): placed, deleted or updated.
    fn running(
        &mut self,
        space: &mut AddressSpace,
        base: &str,
        old: &ToolRecord,
        r: &ToolRecord,
        c: &mut Changes,
    ) {
        let key = (r.group, r.number);
        match (old.running_wear, r.running_wear) {
            (None, Some(_)) => {
                let running = self.place_running(space, base, r, c);
                if let Some(s) = self.shown.get_mut(&key) {
                    s.running = running;
                }
            }
            (Some(_), None) => {
                let gone = self
                    .shown
                    .get_mut(&key)
                    .map(|s| std::mem::take(&mut s.running))
                    .unwrap_or_default();
                for id in gone.iter().rev() {
                    space.delete(id, true);
                }
                let (entry, life) = (self.running_wear(base), self.id(base, LIFE));
                let deleted = verb::NODE_DELETED | verb::REFERENCE_DELETED;
                c.model
                    .push(change(entry, self.templates.life_type.clone(), deleted));
                let base_object = ObjectTypeId::BaseObjectType.into();
                c.model
                    .push(change(life, base_object, verb::REFERENCE_DELETED));
            }
            (Some(a), Some(b)) if a != b => {
                c.values.push((self.running_wear(base), b.into()));
            }
            _ => {}
        }
    }

    /// Places the running-wear entry of tool `r` (at `base`).
    fn place_running(
        &self,
        space: &mut AddressSpace,
        base: &str,
        r: &ToolRecord,
        c: &mut Changes,
    ) -> Vec<NodeId> {
        let life = self.id(base, LIFE);
        let mut t = self.templates.running.clone();
        t.set(RunningVar::RunningWear, r.running_wear.unwrap_or(0.0));
        let made = t
            .template()
            .place(space, self.at.own, &format!("{base}/{LIFE}"), &life);
        c.model.push(change(
            self.running_wear(base),
            self.templates.life_type.clone(),
            verb::NODE_ADDED | verb::REFERENCE_ADDED,
        ));
        c.model.push(change(
            life,
            ObjectTypeId::BaseObjectType.into(),
            verb::REFERENCE_ADDED,
        ));
        made
    }

    /// The channel's state and the active program's, when they change.
    fn state_values(&mut self, state: ChannelState, c: &mut Changes) {
        if self.state == Some(state) {
            return;
        }
        self.state = Some(state);
        self.ran |= state == ChannelState::Running;
        c.values.push((
            self.at.machine_var(MachineVar::ChannelState),
            channel_code(state).into(),
        ));
        let name = match state {
            ChannelState::Running => "Running",
            ChannelState::Interrupted => "Interrupted",
            ChannelState::Idle if self.ran => "Ended",
            ChannelState::Idle => "Initializing",
        };
        if let Some((_, id, number)) = self.program.iter().find(|(n, _, _)| *n == name) {
            let var = |v| self.at.machine_var(v);
            c.values.extend([
                (
                    var(MachineVar::ProgramState),
                    LocalizedText::from(name).into(),
                ),
                (var(MachineVar::ProgramStateId), id.clone().into()),
                (var(MachineVar::ProgramStateNumber), (*number).into()),
            ]);
        }
    }

    /// Raises the GeneralModelChangeEvent of `c` from the tool list (which
    /// is among the nodes changed when a tool came or went).
    fn notify(&mut self, subscriptions: &SubscriptionCache, mut c: Changes) {
        let list = self.id(MACHINE, TOOLS);
        if c.list != 0 {
            c.model
                .push(change(list.clone(), self.at.mt(mt::TOOL_LIST_TYPE), c.list));
        }
        self.events += 1;
        let event = ModelChange::new(&list, "Tools", c.model, self.events);
        subscriptions.notify_events([(&event as &dyn opcua::nodes::Event, &list)].into_iter());
    }
}

/// One entry of a GeneralModelChangeEvent.
fn change(affected: NodeId, affected_type: NodeId, verb: u8) -> ModelChangeStructureDataType {
    ModelChangeStructureDataType {
        affected,
        affected_type,
        verb,
    }
}

/// Writes `values` to their variables, notifying subscribers.
fn write(manager: &Manager, subscriptions: &SubscriptionCache, values: &[(NodeId, Variant)]) {
    if values.is_empty() {
        return;
    }
    let now = DateTime::now();
    let stamped = values.iter().map(|(id, v)| {
        let dv = DataValue {
            value: Some(v.clone()),
            status: Some(StatusCode::Good),
            source_timestamp: Some(now),
            server_timestamp: Some(now),
            ..Default::default()
        };
        (id, None, dv)
    });
    if let Err(e) = manager.set_values(subscriptions, stamped) {
        tracing::warn!(status = %e, "OPC UA: a machine value could not be set");
    }
}

/// Looks at the machine every [`POLL`] and applies what it sees, until
/// the manager is gone.
pub(crate) async fn run(
    mut live: Live,
    core: CoreHandle,
    manager: Weak<Manager>,
    subscriptions: Arc<SubscriptionCache>,
) {
    let mut tick = tokio::time::interval(POLL);
    tick.set_missed_tick_behavior(MissedTickBehavior::Skip);
    let mut warned = false;
    loop {
        tick.tick().await;
        let source = Arc::clone(&live.source);
        let view = core.inspect(move |h| source.look(h)).await;
        let Some(manager) = manager.upgrade() else {
            return;
        };
        match view {
            Some(Some(view)) => live.apply(view, &manager, &subscriptions),
            Some(None) if !warned => {
                warned = true;
                tracing::warn!("OPC UA: the machine source does not know this server's handler");
            }
            Some(None) => {}
            None => return,
        }
    }
}
