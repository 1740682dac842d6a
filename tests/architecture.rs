//! Architecture checks (docs/architecture.md, "Architecture checks"), run on the tree as it is when the test
//! runs:
//!
//! 1. no module of any crate imports a module that imports it back;
//! 2. no bus-1300 address is written outside the object table
//!    (`objects/src`);
//! 3. the root package is the command line only;
//! 4. no comment cites a tracker's issue number (a clone has none);
//! 5. no public API reports its errors as `Result<_, String>`.
//!
//! Each reads the sources with `syn` (use trees, paths, literals and
//! `#[cfg(test)]` read as the compiler reads them, not guessed by a text
//! search). The rules are in the doc comments of the modules below; the
//! checker's own tests (`graph_tests`, `literal_tests`) try each rule on
//! small sources written in the test.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[path = "architecture/citations.rs"]
mod citations;
#[path = "architecture/cli_root.rs"]
mod cli_root;
#[path = "architecture/cycles.rs"]
mod cycles;
#[path = "architecture/graph.rs"]
mod graph;
#[path = "architecture/graph_tests.rs"]
mod graph_tests;
#[path = "architecture/literal_tests.rs"]
mod literal_tests;
#[path = "architecture/literals.rs"]
mod literals;
#[path = "architecture/modtree.rs"]
mod modtree;
#[path = "architecture/resolve.rs"]
mod resolve;
#[path = "architecture/string_errors.rs"]
mod string_errors;
#[path = "architecture/workspace.rs"]
mod workspace;

use modtree::ModuleTree;
use workspace::{crate_roots, package_dirs, read_disk, root, rust_files, shown};

/// The folder of the object table, the one place addresses are written.
const TABLE_DIR: &str = "objects/src";

#[test]
fn no_module_imports_a_module_that_imports_it_back() {
    let mut report = Vec::new();
    let mut problems = Vec::new();
    for krate in crate_roots(&root()) {
        let tree = ModuleTree::load(&krate.root_file, &read_disk);
        problems.extend(tree.problems.iter().cloned());
        let graph = graph::module_graph(&tree);
        for cycle in cycles::cycles(&graph.adjacency()) {
            report.push(cycles::describe(&krate.name, &graph, &cycle));
        }
    }
    assert!(
        problems.is_empty(),
        "unreadable modules:\n{}",
        problems.join("\n")
    );
    assert!(
        report.is_empty(),
        "{} module import cycle(s), each edge with one place that makes it:\n{}",
        report.len(),
        report.join("\n")
    );
}

#[test]
fn no_bus_1300_address_is_written_outside_the_table() {
    let root = root();
    let table = root.join(TABLE_DIR);
    let mut found = Vec::new();
    for krate in crate_roots(&root) {
        let tree = ModuleTree::load(&krate.root_file, &read_disk);
        let src = krate.dir.join("src");
        for file in rust_files(&src) {
            if file.starts_with(&table) || tree.is_test_file(&file) {
                continue;
            }
            found.extend(scanned(&file, literals::scan));
        }
    }
    assert_no_address(found, &format!("outside {TABLE_DIR}"));
}

/// The findings of `scan` in `file`, one line each (or its parse error).
fn scanned(
    file: &std::path::Path,
    scan: fn(&std::path::Path, &str) -> Result<Vec<literals::Finding>, literals::ScanError>,
) -> Vec<String> {
    let text = read_disk(file).unwrap_or_default();
    match scan(file, &text) {
        Ok(findings) => findings
            .iter()
            .map(|f| format!("{}:{}: {}", shown(&f.file), f.line, f.what))
            .collect(),
        Err(e) => vec![e.to_string()],
    }
}

/// Fails with every address `found`, written `place`.
fn assert_no_address(mut found: Vec<String>, place: &str) {
    found.sort();
    found.dedup();
    assert!(
        found.is_empty(),
        "{} bus-1300 address(es) written {place} (name them through tc_objects' keys):\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The checker's own tests, which write addresses on purpose to show that
/// each rule finds them.
const CHECKER_DIR: &str = "tests/architecture";

/// Every Rust file of a package outside its shipped code: test modules
/// under `src/`, and the files under `tests/`, `benches/` and `examples/`.
fn every_rust_file(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    ["src", "tests", "benches", "examples"]
        .iter()
        .flat_map(|sub| rust_files(&dir.join(sub)))
        .collect()
}

#[test]
fn no_bus_1300_address_is_written_in_tests_benches_or_examples() {
    let root = root();
    let table = root.join("objects");
    let checker = root.join(CHECKER_DIR);
    let mut found = Vec::new();
    for dir in package_dirs(&root) {
        for file in every_rust_file(&dir) {
            if file.starts_with(&table) || file.starts_with(&checker) {
                continue;
            }
            found.extend(scanned(&file, literals::scan_everything));
        }
    }
    assert_no_address(found, "in tests, benches or examples");
}

#[test]
fn the_root_package_is_the_command_line() {
    let problems = cli_root::problems(&root());
    assert!(
        problems.is_empty(),
        "the root package is more than the command line:\n{}",
        problems.join("\n")
    );
}

#[test]
fn every_workspace_member_is_read() {
    let dirs = package_dirs(&root());
    assert!(dirs.len() > 1, "no workspace members found");
    let roots = crate_roots(&root());
    for dir in dirs {
        assert!(
            roots.iter().any(|c| c.dir == dir),
            "{}: no src/lib.rs or src/main.rs",
            shown(&dir)
        );
    }
}

#[test]
fn no_comment_cites_an_issue_number() {
    let root = root();
    let mut found = Vec::new();
    for dir in package_dirs(&root) {
        for file in every_rust_file(&dir) {
            if file.starts_with(root.join(CHECKER_DIR)) {
                continue;
            }
            let text = read_disk(&file).unwrap_or_default();
            for line in citations::issue_citations(&text) {
                found.push(format!("{}:{line}", shown(&file)));
            }
        }
    }
    assert!(
        found.is_empty(),
        "{} comment(s) cite an issue number; cite docs/ or a decision instead:\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn no_public_api_reports_errors_as_strings() {
    let mut found = Vec::new();
    for krate in crate_roots(&root()) {
        let tree = ModuleTree::load(&krate.root_file, &read_disk);
        for file in rust_files(&krate.dir.join("src")) {
            if tree.is_test_file(&file) {
                continue;
            }
            let text = read_disk(&file).unwrap_or_default();
            match string_errors::string_errors(&text) {
                Ok(items) => found.extend(
                    items
                        .into_iter()
                        .map(|(line, name)| format!("{}:{line}: {name}", shown(&file))),
                ),
                Err(e) => found.push(format!("{}: {e}", shown(&file))),
            }
        }
    }
    assert!(
        found.is_empty(),
        "{} public item(s) report errors as strings (give them a typed error):\n{}",
        found.len(),
        found.join("\n")
    );
}
