//! The NodeSets of OPC 40501-1 "OPC UA for Machine Tools" and of the
//! models it builds on (Devices, Industrial Automation, Machinery, its Jobs
//! and ISA-95 job control), as the OPC Foundation publishes them
//! (`opcua-face/nodesets/README.md`), built into the program and imported
//! into the face's address space in the order they depend on each other.

use opcua::nodes::{ImportedItem, NodeSet2Import, NodeSetImport, NodeSetNamespaceMapper};
use opcua::server::address_space::AddressSpace;
use opcua::types::NamespaceMap;

use super::error::ModelError;

/// The namespace of OPC UA itself (namespace 0).
const UA: &str = "http://opcfoundation.org/UA/";

/// The namespace of OPC 40501-1 (MachineToolType, ToolType, ...).
pub const MACHINE_TOOL: &str = "http://opcfoundation.org/UA/MachineTool/";

/// The namespace of OPC 40001-1 Machinery (the `Machines` folder).
pub const MACHINERY: &str = "http://opcfoundation.org/UA/Machinery/";

/// The NodeSet files, each after those it needs.
const FILES: [(&str, &str); 6] = [
    (
        "Opc.Ua.Di.NodeSet2.xml",
        include_str!("../../nodesets/Opc.Ua.Di.NodeSet2.xml"),
    ),
    (
        "Opc.Ua.IA.NodeSet2.xml",
        include_str!("../../nodesets/Opc.Ua.IA.NodeSet2.xml"),
    ),
    (
        "Opc.Ua.Machinery.NodeSet2.xml",
        include_str!("../../nodesets/Opc.Ua.Machinery.NodeSet2.xml"),
    ),
    (
        "opc.ua.isa95-jobcontrol.nodeset2.xml",
        include_str!("../../nodesets/opc.ua.isa95-jobcontrol.nodeset2.xml"),
    ),
    (
        "Opc.Ua.Machinery.Jobs.Nodeset2.xml",
        include_str!("../../nodesets/Opc.Ua.Machinery.Jobs.Nodeset2.xml"),
    ),
    (
        "Opc.Ua.MachineTool.NodeSet2.xml",
        include_str!("../../nodesets/Opc.Ua.MachineTool.NodeSet2.xml"),
    ),
];

/// A NodeSet import that registers its namespaces without a word on
/// standard output (the library's own import prints a line for each).
struct Quiet(NodeSet2Import);

impl NodeSetImport for Quiet {
    /// The file's namespace table, index 1 onward (as the library does;
    /// namespace 0 is OPC UA's own and keeps its index).
    fn register_namespaces(&self, namespaces: &mut NodeSetNamespaceMapper) {
        let mut offset = 1;
        for (i, uri) in self.0.get_own_namespaces().iter().enumerate() {
            if uri == UA {
                offset = 0;
                continue;
            }
            // A NodeSet names a handful of namespaces.
            let index = u16::try_from(i).unwrap_or(u16::MAX).saturating_add(offset);
            namespaces.add_namespace(uri, index);
        }
    }

    fn get_own_namespaces(&self) -> Vec<String> {
        self.0.get_own_namespaces()
    }

    fn load<'a>(
        &'a self,
        namespaces: &'a NodeSetNamespaceMapper,
    ) -> Box<dyn Iterator<Item = ImportedItem> + 'a> {
        self.0.load(namespaces)
    }
}

/// Imports every NodeSet into `space`, its namespaces added to
/// `namespaces` (the server's table) after those already there; gives
/// them with their indexes, in the order the files name them.
pub(crate) fn import(
    space: &mut AddressSpace,
    namespaces: &mut NamespaceMap,
) -> Result<Vec<(String, u16)>, ModelError> {
    let mut loaded: Vec<(String, u16)> = Vec::new();
    for (name, xml) in FILES {
        let set =
            NodeSet2Import::new_str("en", &compact_byte_strings(xml), Vec::new()).map_err(|e| {
                ModelError::NodeSet {
                    file: name,
                    reason: e.to_string(),
                }
            })?;
        for uri in set.get_own_namespaces() {
            if loaded.iter().all(|(u, _)| *u != uri) {
                loaded.push((uri, 0));
            }
        }
        space.import_node_set(&Quiet(set), namespaces);
    }
    let known = namespaces.known_namespaces();
    loaded.retain_mut(|(uri, index)| match known.get(uri.as_str()) {
        Some(i) => {
            *index = *i;
            true
        }
        None => false,
    });
    Ok(loaded)
}

/// The NodeSet with the line breaks and indentation taken out of its
/// `ByteString` values (base64 in several lines, as XML allows; the
/// library's decoder takes one line only).
fn compact_byte_strings(xml: &str) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some((body, len)) = next_byte_string(rest) {
        out.push_str(&rest[..body]);
        out.extend(
            rest[body..body + len]
                .chars()
                .filter(|c| !c.is_whitespace()),
        );
        rest = &rest[body + len..];
    }
    out.push_str(rest);
    out
}

/// Where the text of the next `ByteString` element (any prefix, any
/// attributes) starts in `xml`, and how long it is.
fn next_byte_string(xml: &str) -> Option<(usize, usize)> {
    const NAME: &str = "ByteString";
    let mut from = 0;
    loop {
        let at = from + xml[from..].find(NAME)?;
        from = at + NAME.len();
        let Some(open) = xml[..at].rfind('<') else {
            continue;
        };
        let prefix = &xml[open + 1..at];
        let tag_name = prefix.chars().all(|c| c.is_alphanumeric() || c == ':');
        let name_ends = xml[from..].starts_with(|c: char| c == '>' || c.is_whitespace());
        if !tag_name || !name_ends {
            continue;
        }
        let close = from + xml[from..].find('>')?;
        if xml[..close].ends_with('/') {
            continue;
        }
        let body = close + 1;
        return Some((body, xml[body..].find("</")?));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_strings_lose_their_line_breaks_and_nothing_else() {
        let xml = "<V DataType=\"ByteString\"> x </V><u:ByteString xmlns:u=\"t\">QUJD\n  REVG\n\
                   </u:ByteString><b>\n</b><ByteString/><ByteString>R0\tg=</ByteString>";
        assert_eq!(
            compact_byte_strings(xml),
            "<V DataType=\"ByteString\"> x </V><u:ByteString xmlns:u=\"t\">QUJDREVG\
             </u:ByteString><b>\n</b><ByteString/><ByteString>R0g=</ByteString>"
        );
    }

    #[test]
    fn every_nodeset_imports_with_its_namespaces() {
        let mut space = AddressSpace::new();
        let mut namespaces = NamespaceMap::new();
        namespaces.add_namespace("urn:before");
        let loaded = import(&mut space, &mut namespaces).expect("import");
        let uris: Vec<&str> = loaded.iter().map(|(u, _)| u.as_str()).collect();
        assert!(
            uris.contains(&MACHINE_TOOL) && uris.contains(&MACHINERY),
            "{uris:?}"
        );
        assert_eq!(namespaces.get_index("urn:before"), Some(1));
        for (uri, index) in &loaded {
            assert!(*index > 1, "{uri} at {index}");
        }
    }
}
