//! The cycle checker tried on small crates written here: a cycle, a
//! re-export that is not one, `super::` from a child, a glob re-export,
//! test-only code, inline modules and 2018 paths through a child's name.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::cycles::{components, cycles};
use crate::graph::{module_graph, ModuleGraph};
use crate::modtree::ModuleTree;
use crate::resolve::{Resolver, Target};

/// The module graph of the crate made of `files` (`src/lib.rs` first).
fn graph(files: &[(&str, &str)]) -> (ModuleTree, ModuleGraph) {
    let sources: BTreeMap<PathBuf, String> = files
        .iter()
        .map(|(p, t)| (PathBuf::from(p), t.to_string()))
        .collect();
    let read = |p: &Path| sources.get(p).cloned();
    let tree = ModuleTree::load(Path::new("src/lib.rs"), &read);
    assert!(tree.problems.is_empty(), "{:?}", tree.problems);
    let g = module_graph(&tree);
    (tree, g)
}

/// The cycles of `files`, as `a -> b -> a`.
fn cycle_names(files: &[(&str, &str)]) -> Vec<String> {
    let (_, g) = graph(files);
    cycles(&g.adjacency())
        .iter()
        .map(|c| {
            let names: Vec<&str> = c.iter().map(|&m| g.names[m].as_str()).collect();
            names.join(" -> ")
        })
        .collect()
}

#[test]
fn two_modules_that_import_each_other_are_a_cycle_with_both_places() {
    let files = [
        ("src/lib.rs", "mod a;\nmod b;\n"),
        ("src/a.rs", "use crate::b::B;\npub struct A;\n"),
        (
            "src/b.rs",
            "pub struct B;\nfn f() {\n    let _ = crate::a::A;\n}\n",
        ),
    ];
    assert_eq!(cycle_names(&files), ["a -> b -> a"]);
    let (tree, g) = graph(&files);
    let (a, b) = (tree.find("a").unwrap(), tree.find("b").unwrap());
    assert_eq!(g.edges[&(a, b)].line, 1);
    assert_eq!(g.edges[&(b, a)].line, 3);
    assert_eq!(g.edges[&(b, a)].file, PathBuf::from("src/b.rs"));
}

#[test]
fn a_re_export_at_the_root_is_followed_to_the_defining_module() {
    let files = [
        (
            "src/lib.rs",
            "mod a;\nmod b;\npub use a::A;\npub use b::B;\n",
        ),
        ("src/a.rs", "pub struct A;\n"),
        ("src/b.rs", "use crate::A;\npub struct B(A);\n"),
    ];
    assert!(cycle_names(&files).is_empty());
    let (_, g) = graph(&files);
    let edges: Vec<String> = g.edge_names().into_iter().collect();
    assert_eq!(edges, ["b -> a", "crate -> a", "crate -> b"]);
}

#[test]
fn an_item_the_root_defines_makes_a_cycle_with_a_child_it_re_exports() {
    let files = [
        (
            "src/lib.rs",
            "mod a;\npub use a::A;\npub const N: u16 = 1;\n",
        ),
        ("src/a.rs", "pub struct A([u8; crate::N as usize]);\n"),
    ];
    assert_eq!(cycle_names(&files), ["crate -> a -> crate"]);
}

#[test]
fn super_from_a_child_is_a_cycle_only_if_the_parent_imports_the_child() {
    let child = ("src/p/c.rs", "use super::P;\npub fn g(_: P) {}\n");
    let tangled = [
        ("src/lib.rs", "mod p;\n"),
        (
            "src/p.rs",
            "mod c;\npub struct P;\npub fn f() {\n    c::g(P);\n}\n",
        ),
        child,
    ];
    assert_eq!(cycle_names(&tangled), ["p -> p::c -> p"]);
    let one_way = [
        ("src/lib.rs", "mod p;\n"),
        ("src/p/mod.rs", "mod c;\npub struct P;\n"),
        child,
    ];
    assert!(cycle_names(&one_way).is_empty());
    assert_eq!(graph(&one_way).1.edge_names().len(), 1);
}

#[test]
fn a_glob_re_export_is_followed_and_is_an_edge() {
    let files = [
        ("src/lib.rs", "mod a;\nmod b;\nmod c;\npub use b::*;\n"),
        ("src/a.rs", "pub struct A;\n"),
        ("src/b.rs", "pub use crate::a::*;\npub struct B;\n"),
        ("src/c.rs", "use crate::A;\n"),
    ];
    let (tree, g) = graph(&files);
    let resolver = Resolver::new(&tree);
    let path: Vec<String> = ["crate", "A"].map(String::from).to_vec();
    let a = tree.find("a").unwrap();
    let expected = Target {
        module: a,
        item: Some("A".into()),
    };
    assert_eq!(
        resolver.resolve(tree.find("c").unwrap(), &path),
        Some(expected)
    );
    assert!(g.edge_names().contains("b -> a"));
    assert!(g.edge_names().contains("c -> a"));
    assert!(cycle_names(&files).is_empty());
    let mut tangled = files;
    tangled[1] = ("src/a.rs", "pub struct A(crate::B);\n");
    assert_eq!(cycle_names(&tangled), ["a -> b -> a"]);
}

#[test]
fn test_only_code_and_modules_make_no_edge() {
    let files = [
        (
            "src/lib.rs",
            "mod a {\n    pub fn f() {\n        crate::b::g();\n    }\n}\n\
             mod b {\n    pub fn g() {}\n    #[cfg(test)]\n    mod tests {\n        use crate::a::f;\n    }\n\
             #[cfg(test)]\n    fn t() {\n        crate::a::f();\n    }\n}\n\
             #[cfg(test)]\nmod helpers;\n",
        ),
        ("src/helpers.rs", "use crate::a::f;\n"),
    ];
    let (tree, g) = graph(&files);
    assert_eq!(g.edge_names().into_iter().collect::<Vec<_>>(), ["a -> b"]);
    assert!(tree.find("b::tests").is_none());
    assert!(tree.is_test_file(Path::new("src/helpers.rs")));
}

#[test]
fn a_path_through_a_child_name_is_an_edge_and_a_local_name_is_not() {
    let files = [
        ("src/lib.rs", "mod a;\nmod b;\nuse a::A;\n"),
        ("src/a.rs", "pub struct A;\n"),
        ("src/b.rs", "mod c;\npub fn f(c: u8) -> u8 {\n    c\n}\n"),
        ("src/b/c.rs", "pub fn g() {}\n"),
    ];
    let edges: Vec<String> = graph(&files).1.edge_names().into_iter().collect();
    assert_eq!(edges, ["crate -> a"]);
}

#[test]
fn paths_inside_macro_calls_are_read() {
    let files = [
        ("src/lib.rs", "mod a;\nmod b;\n"),
        (
            "src/a.rs",
            "pub const X: u8 = 1;\npub fn f() {\n    let _ = crate::b::Y;\n}\n",
        ),
        (
            "src/b.rs",
            "pub const Y: u8 = 2;\nfn g() {\n    assert_eq!(crate::a::X, 1);\n}\n",
        ),
    ];
    assert_eq!(cycle_names(&files), ["a -> b -> a"]);
}

#[test]
fn tarjan_finds_every_component_and_a_cycle_through_every_edge() {
    // 0 -> 1 -> 2 -> 0 and 1 -> 0; 3 <-> 4; 5 alone, 4 -> 5.
    let adj = vec![vec![1], vec![2, 0], vec![0], vec![4], vec![3, 5], vec![]];
    let mut found = components(&adj);
    found.sort();
    assert_eq!(found, [vec![0, 1, 2], vec![3, 4], vec![5]]);
    assert_eq!(
        cycles(&adj),
        [vec![0, 1, 0], vec![0, 1, 2, 0], vec![3, 4, 3]]
    );
}
