//! Putting the machine into the face's address space once the server
//! knows every type (OPC UA's own in the core node manager, the
//! companion NodeSets in the face's), and starting its live updates.

use std::sync::Arc;

use opcua::server::address_space::{DefaultTypeTree, EventNotifier, NodeType};
use opcua::server::node_manager::ServerContext;
use tokio_util::sync::{CancellationToken, DropGuard};
use uoi::tcp::CoreHandle;

use super::error::ModelError;
use super::instance::Template;
use super::live::{self, Live, Manager, ProgramStates};
use super::model::{self, mt, Spaces, MACHINE, TOOLS};
use super::nodesets::{MACHINERY, MACHINE_TOOL};
use super::tools;
use super::types::Types;
use super::view::MachineTool;
use crate::capped::Capped;

/// The states of the active program the face shows.
const PROGRAM_STATES: [&str; 4] = ["Initializing", "Running", "Interrupted", "Ended"];

/// Builds `machine` into `manager`'s address space (namespace `own`)
/// and starts its live updates through `core`; they stop when the
/// guard is dropped.
pub(crate) fn start(
    manager: &Arc<Manager>,
    tree: &DefaultTypeTree,
    context: &ServerContext,
    own: u16,
    machine: &MachineTool,
    core: CoreHandle,
) -> Result<DropGuard, ModelError> {
    let index = |uri: &'static str| {
        tree.namespaces()
            .get_index(uri)
            .ok_or(ModelError::Namespace(uri))
    };
    let at = Spaces {
        own,
        mt: index(MACHINE_TOOL)?,
        machinery: index(MACHINERY)?,
    };
    let core_nodes = context
        .node_managers
        .get_of_type::<Capped>()
        .ok_or(ModelError::NoCoreManager)?;
    let core_space = core_nodes.inner().address_space().read();
    let mut space = manager.address_space().write();
    let (plan, templates, program) = {
        let types = Types::new(vec![&*space, &*core_space], tree);
        let plan = model::machine(&types, at, machine)?;
        let templates = tools::templates(&types, at, &machine.tool_kinds)?;
        let states = at.mt(mt::PROGRAM_STATE_MACHINE);
        let program: ProgramStates = PROGRAM_STATES
            .iter()
            .filter_map(|&name| types.state(&states, name).map(|(id, n)| (name, id, n)))
            .collect();
        (plan, templates, program)
    };
    plan.place(&mut space, own, MACHINE, &at.machines());
    if let Some(NodeType::Object(list)) = space.find_mut(&Template::id(own, MACHINE, TOOLS)) {
        list.set_event_notifier(EventNotifier::SUBSCRIBE_TO_EVENTS);
    }
    drop(space);
    drop(core_space);
    let stop = CancellationToken::new();
    let live = Live::new(at, machine, templates, program);
    let run = live::run(
        live,
        core,
        Arc::downgrade(manager),
        context.subscriptions.clone(),
    );
    let token = stop.clone();
    tokio::spawn(async move {
        tokio::select! {
            () = token.cancelled() => {}
            () = run => {}
        }
    });
    Ok(stop.drop_guard())
}
