//! The modules of `uoi::tcp` import one another one way only: the handler
//! contract (`handler.rs`) imports nothing of the rest of `tcp`, and no
//! module imports one that imports it back, however indirectly. Read from
//! the sources' `use super::…` lines (the only way the modules of `tcp`
//! name one another).

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// Module name → the sibling modules it imports, from `src/tcp/*.rs`.
fn imports() -> BTreeMap<String, BTreeSet<String>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/tcp");
    let mut graph = BTreeMap::new();
    for entry in fs::read_dir(&dir).expect("src/tcp") {
        let path = entry.expect("entry").path();
        let Some(name) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs") || name == "mod" {
            continue;
        }
        let text = fs::read_to_string(&path).expect("source");
        // Unit tests at the end may reach anywhere.
        let code = text.split("#[cfg(test)]").next().unwrap_or_default();
        let used = code
            .lines()
            .filter_map(|l| l.trim().strip_prefix("use super::"))
            .flat_map(|rest| rest.trim_start_matches('{').split(','))
            .filter_map(|item| item.trim().split("::").next())
            .map(|m| m.trim_end_matches([';', '}']).to_owned())
            .filter(|m| !m.is_empty())
            .collect();
        graph.insert(name.to_owned(), used);
    }
    graph
}

/// Whether `to` is reachable from `from`.
fn reaches(graph: &BTreeMap<String, BTreeSet<String>>, from: &str, to: &str) -> bool {
    let mut seen = BTreeSet::new();
    let mut todo = vec![from.to_owned()];
    while let Some(m) = todo.pop() {
        for next in graph.get(&m).into_iter().flatten() {
            if next == to {
                return true;
            }
            if seen.insert(next.clone()) {
                todo.push(next.clone());
            }
        }
    }
    false
}

#[test]
fn the_handler_contract_is_a_leaf() {
    let graph = imports();
    assert!(graph.len() >= 10, "{graph:?}");
    assert_eq!(graph["handler"], BTreeSet::new());
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let graph = imports();
    for (module, used) in &graph {
        for other in used {
            assert!(
                !reaches(&graph, other, module),
                "{module} imports {other}, which imports {module} back"
            );
        }
    }
}
