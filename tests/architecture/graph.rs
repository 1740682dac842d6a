//! A crate's module graph. Its edges: from a module to the module that
//! defines what it names, for every leaf of every `use` tree and every
//! path in code that starts with `crate::`, `super::`, `self::`, the
//! name of one of the module's own children or a name it imports (a path
//! in code needs two segments or more: one segment is a local name). Paths inside macro
//! calls are read when the macro's arguments parse as expressions
//! (`format!`, `assert_eq!`, `vec![a, b]` ...). A re-export is itself an
//! edge to the defining module. Test-only items are not read; a module's
//! child modules are modules of their own.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};
use syn::{Expr, ImplItem, Item, Token};

use crate::modtree::ModuleTree;
use crate::resolve::{flatten_use, imported_names, Resolver, Target};
use crate::workspace::{impl_item_attrs, is_test_only, item_attrs, line_of};

/// Where in the sources something is written.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Location {
    /// The file.
    pub file: PathBuf,
    /// The line, 1-based.
    pub line: usize,
}

/// A path written in a module.
#[derive(Clone, Debug)]
pub struct Reference {
    /// The module it is written in.
    pub from: usize,
    /// Its segments (a glob import ends in `*`).
    pub path: Vec<String>,
    /// Where it is written.
    pub at: Location,
}

/// The modules of a crate and the imports between them.
pub struct ModuleGraph {
    /// Module names (`crate`, `a::b`), by number.
    pub names: Vec<String>,
    /// Each edge `(from, to)` with the first place that makes it.
    pub edges: BTreeMap<(usize, usize), Location>,
}

impl ModuleGraph {
    /// The modules each module imports, by number.
    pub fn adjacency(&self) -> Vec<Vec<usize>> {
        let mut adj = vec![Vec::new(); self.names.len()];
        for &(from, to) in self.edges.keys() {
            adj[from].push(to);
        }
        adj
    }

    /// The edges as `from -> to` names, for the checker's own tests.
    pub fn edge_names(&self) -> BTreeSet<String> {
        let name = |m: usize| self.names[m].clone();
        self.edges
            .keys()
            .map(|&(a, b)| format!("{} -> {}", name(a), name(b)))
            .collect()
    }
}

/// The module graph of `tree`.
pub fn module_graph(tree: &ModuleTree) -> ModuleGraph {
    let mut edges: BTreeMap<(usize, usize), Location> = BTreeMap::new();
    for (r, t) in resolved(tree) {
        if t.module == r.from {
            continue;
        }
        let at = edges
            .entry((r.from, t.module))
            .or_insert_with(|| r.at.clone());
        if r.at < *at {
            *at = r.at;
        }
    }
    ModuleGraph {
        names: tree.modules.iter().map(|m| m.name.clone()).collect(),
        edges,
    }
}

/// Every reference of `tree` that stays in the crate, with its target.
pub fn resolved(tree: &ModuleTree) -> Vec<(Reference, Target)> {
    let resolver = Resolver::new(tree);
    references(tree)
        .into_iter()
        .filter_map(|r| resolver.resolve(r.from, &r.path).map(|t| (r, t)))
        .collect()
}

/// Every `use` leaf and every path in code of every module of `tree`
/// that may name a module of the crate.
pub fn references(tree: &ModuleTree) -> Vec<Reference> {
    let mut out = Vec::new();
    for (id, module) in tree.modules.iter().enumerate() {
        let imported = imported_names(&module.items);
        let mut c = Collector {
            from: id,
            file: module.file.clone(),
            local: |s: &str| {
                matches!(s, "crate" | "self" | "super")
                    || module.children.contains_key(s)
                    || imported.contains(s)
            },
            out: Vec::new(),
        };
        for item in &module.items {
            c.visit_item(item);
        }
        out.extend(c.out);
    }
    out
}

/// Gathers the references of one module.
struct Collector<F: Fn(&str) -> bool> {
    from: usize,
    file: PathBuf,
    /// Whether a first segment may lead into the crate.
    local: F,
    out: Vec<Reference>,
}

impl<F: Fn(&str) -> bool> Collector<F> {
    fn push(&mut self, path: Vec<String>, line: usize) {
        if path.first().is_some_and(|s| (self.local)(s)) {
            self.out.push(Reference {
                from: self.from,
                path,
                at: Location {
                    file: self.file.clone(),
                    line,
                },
            });
        }
    }
}

impl<'ast, F: Fn(&str) -> bool> Visit<'ast> for Collector<F> {
    fn visit_item(&mut self, item: &'ast Item) {
        if is_test_only(item_attrs(item)) {
            return;
        }
        match item {
            Item::Mod(_) => {}
            Item::Use(u) => {
                let mut leaves = Vec::new();
                flatten_use(&u.tree, &mut Vec::new(), &mut leaves);
                for leaf in leaves {
                    self.push(leaf.path, leaf.line);
                }
            }
            _ => visit::visit_item(self, item),
        }
    }

    fn visit_impl_item(&mut self, item: &'ast ImplItem) {
        if !is_test_only(impl_item_attrs(item)) {
            visit::visit_impl_item(self, item);
        }
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        if path.leading_colon.is_none() && path.segments.len() >= 2 {
            let segs = path.segments.iter().map(|s| s.ident.to_string()).collect();
            self.push(segs, line_of(path.segments[0].ident.span()));
        }
        visit::visit_path(self, path);
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        visit::visit_macro(self, mac);
        if let Ok(args) = mac.parse_body_with(Punctuated::<Expr, Token![,]>::parse_terminated) {
            for arg in &args {
                self.visit_expr(arg);
            }
        }
    }
}
