//! Why the machine cannot be shown: a NodeSet that does not load, or a
//! type or member of the model the face needs that is not there. The
//! face then runs without the machine and logs the reason.

/// Why the machine cannot be shown.
#[derive(Debug, thiserror::Error)]
pub(crate) enum ModelError {
    /// A NodeSet built into the program does not import.
    #[error("the built-in NodeSet {file}: {reason}")]
    NodeSet {
        /// Its file name.
        file: &'static str,
        /// What the library's import says.
        reason: String,
    },
    /// A namespace the model needs is not in the server's table.
    #[error("the namespace {0} is not loaded")]
    Namespace(&'static str),
    /// The server has no core node manager (namespace 0).
    #[error("the server has no core node manager")]
    NoCoreManager,
    /// A type the model needs is not in the loaded NodeSets.
    #[error("{0} is not in the loaded NodeSets")]
    Type(&'static str),
    /// A type or declaration lacks a member the model needs.
    #[error("{owner} has no {member}")]
    Member {
        /// The type or declaration.
        owner: &'static str,
        /// The member's BrowseName.
        member: &'static str,
    },
    /// A variable of a node table (`handles.rs`) is not in the instance
    /// planned from the NodeSets.
    #[error("the {instance} has no variable {path}")]
    Variable {
        /// The instance: `machine`, `tool`.
        instance: &'static str,
        /// The variable's browse path.
        path: &'static str,
    },
}
