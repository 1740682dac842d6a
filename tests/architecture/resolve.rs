//! Which module DEFINES what a path names. A path is resolved from the
//! module it is written in: `crate::`, `super::`, `self::`, the name of
//! one of that module's own children (a 2018 "uniform" path), or the name
//! under which it imports a module of the crate (`use super::token;`)
//! starts it; other paths lead out of the crate and are not followed. The segments
//! are walked while they name modules; the first that does not is an item
//! of the last module. If that module does not define the item but
//! imports it (`pub use path::Item`, `use path::Item as Name`, or a glob
//! `pub use path::*` that provides it), the import is followed to the
//! defining module, recursively; an import from another crate
//! (`pub use tc_request::motion`) leaves the crate.

use std::collections::BTreeSet;

use syn::{Item, UseTree};

use crate::modtree::ModuleTree;
use crate::workspace::line_of;

/// How deep re-exports are followed before giving up (a re-export loop
/// is a compile error, so this only guards against a misread).
const MAX_HOPS: usize = 32;

/// One leaf of a `use` tree.
#[derive(Clone, Debug)]
pub struct Import {
    /// The name it brings into scope; `None` for a glob.
    pub name: Option<String>,
    /// The path it imports (a glob ends in `*`).
    pub path: Vec<String>,
    /// Line of the leaf.
    pub line: usize,
}

/// What a path resolves to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Target {
    /// The defining module (for a path to a module: that module).
    pub module: usize,
    /// The item's name; `None` when the path names a module or a glob.
    pub item: Option<String>,
}

/// The names a module has: what it defines and what it imports.
#[derive(Default)]
struct Names {
    defined: BTreeSet<String>,
    imports: Vec<Import>,
}

/// Resolves paths within one crate.
pub struct Resolver<'t> {
    tree: &'t ModuleTree,
    names: Vec<Names>,
}

impl<'t> Resolver<'t> {
    /// A resolver over `tree`.
    pub fn new(tree: &'t ModuleTree) -> Self {
        let names = tree.modules.iter().map(|m| names_of(&m.items)).collect();
        Self { tree, names }
    }

    /// The target of `path` written in module `from`; `None` for a path
    /// that leaves the crate (another crate, `std`, a local name).
    pub fn resolve(&self, from: usize, path: &[String]) -> Option<Target> {
        self.resolve_hops(from, path, 0)
    }

    fn resolve_hops(&self, from: usize, path: &[String], hops: usize) -> Option<Target> {
        let (start, rest) = self.start(from, path, hops)?;
        self.walk(start, rest, hops)
    }

    /// The module a path starts from and the segments after it.
    fn start<'p>(
        &self,
        from: usize,
        path: &'p [String],
        hops: usize,
    ) -> Option<(usize, &'p [String])> {
        let first = path.first()?;
        match first.as_str() {
            "crate" => Some((0, &path[1..])),
            "self" => Some((from, &path[1..])),
            "super" => {
                let ups = path.iter().take_while(|s| *s == "super").count();
                let mut m = from;
                for _ in 0..ups {
                    m = self.tree.modules[m].parent?;
                }
                Some((m, &path[ups..]))
            }
            name if self.tree.modules[from].children.contains_key(name) => Some((from, path)),
            name => self
                .imported_module(from, name, hops)
                .map(|m| (m, &path[1..])),
        }
    }

    /// The module of the crate that module `from` imports as `name`
    /// (`use super::token;` then `token::load()`), if any.
    fn imported_module(&self, from: usize, name: &str, hops: usize) -> Option<usize> {
        if hops > MAX_HOPS {
            return None;
        }
        let imp = self.names[from]
            .imports
            .iter()
            .find(|i| i.name.as_deref() == Some(name))?;
        let t = self.resolve_hops(from, &imp.path, hops + 1)?;
        t.item.is_none().then_some(t.module)
    }

    /// Walks `rest` from module `m`; `None` when it leaves the crate.
    fn walk(&self, mut m: usize, rest: &[String], hops: usize) -> Option<Target> {
        for (i, seg) in rest.iter().enumerate() {
            if seg == "*" {
                break;
            }
            let t = self.follow(m, seg, hops)?;
            if t.item.is_some() || i + 1 == rest.len() {
                return Some(t);
            }
            m = t.module;
        }
        Some(Target {
            module: m,
            item: None,
        })
    }

    /// The defining module of `name` as seen in module `m`; `None` when
    /// `m` imports it from another crate (`pub use tc_request::motion`).
    fn follow(&self, m: usize, name: &str, hops: usize) -> Option<Target> {
        let here = Target {
            module: m,
            item: Some(name.to_string()),
        };
        if let Some(&child) = self.tree.modules[m].children.get(name) {
            return Some(Target {
                module: child,
                item: None,
            });
        }
        if hops > MAX_HOPS || self.names[m].defined.contains(name) {
            return Some(here);
        }
        let names = &self.names[m];
        if let Some(imp) = names
            .imports
            .iter()
            .find(|i| i.name.as_deref() == Some(name))
        {
            return self.resolve_hops(m, &imp.path, hops + 1);
        }
        for glob in names.imports.iter().filter(|i| i.name.is_none()) {
            let Some(g) = self.resolve_hops(m, &glob.path, hops + 1) else {
                continue;
            };
            if g.item.is_none() && g.module != m && self.provides(g.module, name, hops + 1) {
                return self.follow(g.module, name, hops + 1);
            }
        }
        Some(here)
    }

    /// Whether module `m` has `name` in its namespace (defined, a child,
    /// imported by name or through a glob).
    fn provides(&self, m: usize, name: &str, hops: usize) -> bool {
        let names = &self.names[m];
        if names.defined.contains(name)
            || self.tree.modules[m].children.contains_key(name)
            || names
                .imports
                .iter()
                .any(|i| i.name.as_deref() == Some(name))
        {
            return true;
        }
        hops <= MAX_HOPS
            && names
                .imports
                .iter()
                .filter(|i| i.name.is_none())
                .any(|glob| match self.resolve_hops(m, &glob.path, hops + 1) {
                    Some(g) if g.item.is_none() && g.module != m => {
                        self.provides(g.module, name, hops + 1)
                    }
                    _ => false,
                })
    }
}

/// The names defined and imported by `items` (modules are children, not
/// names).
fn names_of(items: &[Item]) -> Names {
    let mut names = Names::default();
    for item in items {
        let ident = match item {
            Item::Use(u) => {
                flatten_use(&u.tree, &mut Vec::new(), &mut names.imports);
                None
            }
            Item::Const(i) => Some(&i.ident),
            Item::Enum(i) => Some(&i.ident),
            Item::Fn(i) => Some(&i.sig.ident),
            Item::Macro(i) => i.ident.as_ref(),
            Item::Static(i) => Some(&i.ident),
            Item::Struct(i) => Some(&i.ident),
            Item::Trait(i) => Some(&i.ident),
            Item::TraitAlias(i) => Some(&i.ident),
            Item::Type(i) => Some(&i.ident),
            Item::Union(i) => Some(&i.ident),
            _ => None,
        };
        if let Some(ident) = ident {
            names.defined.insert(ident.to_string());
        }
    }
    names
}

/// The names the `use` items among `items` bring into scope.
pub fn imported_names(items: &[Item]) -> BTreeSet<String> {
    let mut imports = Vec::new();
    for item in items {
        if let Item::Use(u) = item {
            flatten_use(&u.tree, &mut Vec::new(), &mut imports);
        }
    }
    imports.into_iter().filter_map(|i| i.name).collect()
}

/// The leaves of a `use` tree, each with its whole path.
pub fn flatten_use(tree: &UseTree, prefix: &mut Vec<String>, out: &mut Vec<Import>) {
    match tree {
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten_use(&p.tree, prefix, out);
            prefix.pop();
        }
        UseTree::Name(n) if n.ident == "self" => out.push(Import {
            name: prefix.last().cloned(),
            path: prefix.clone(),
            line: line_of(n.ident.span()),
        }),
        UseTree::Name(n) => out.push(leaf(prefix, &n.ident, &n.ident)),
        UseTree::Rename(r) => out.push(leaf(prefix, &r.ident, &r.rename)),
        UseTree::Glob(g) => {
            let mut path = prefix.clone();
            path.push("*".into());
            out.push(Import {
                name: None,
                path,
                line: line_of(g.star_token.spans[0]),
            });
        }
        UseTree::Group(g) => {
            for t in &g.items {
                flatten_use(t, prefix, out);
            }
        }
    }
}

/// The import of `prefix::ident` under the name `as_name`.
fn leaf(prefix: &[String], ident: &syn::Ident, as_name: &syn::Ident) -> Import {
    let mut path = prefix.to_vec();
    path.push(ident.to_string());
    Import {
        name: Some(as_name.to_string()),
        path,
        line: line_of(ident.span()),
    }
}
