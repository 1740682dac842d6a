//! The root package is the command line and nothing else. The rule, kept
//! simple enough to check by machine:
//!
//! * no library: no `src/lib.rs`, no `[lib]` in `Cargo.toml`, and every
//!   `[[bin]]` is `src/main.rs`;
//! * `src/` holds `main.rs` and `src/cli/**` only, every file a module of
//!   the binary (no stray file), and `main.rs` declares the one module
//!   `cli`;
//! * every item declared `pub` (or `pub(..)`) in the binary is a clap
//!   argument type (derives `Parser`, `Args`, `Subcommand` or
//!   `ValueEnum`), a `cmd_*` function, a module, or named by another
//!   module of the binary, or named in the signature of an item that is
//!   (a result type, a field's type: the compiler wants those `pub`
//!   too). In a binary `pub` only lets a sibling module in, so a `pub` item nobody else names is an API without a user: the
//!   sign of a library hiding in the command line. `pub use` lines are
//!   re-exports, not declarations, and are not counted.

use std::collections::BTreeSet;
use std::path::Path;

use syn::visit::{self, Visit};
use syn::{Item, Visibility};

use crate::graph::resolved;
use crate::modtree::ModuleTree;
use crate::workspace::{item_attrs, line_of, read_disk, read_manifest, rust_files, shown};

/// Derives that make a clap argument type.
const CLAP_DERIVES: [&str; 4] = ["Parser", "Args", "Subcommand", "ValueEnum"];

/// What keeps the root package at `root` from being only the command
/// line, one line each.
pub fn problems(root: &Path) -> Vec<String> {
    let mut out = manifest_problems(root);
    let main = root.join("src/main.rs");
    let tree = ModuleTree::load(&main, &read_disk);
    out.extend(tree.problems.iter().cloned());
    out.extend(file_problems(root, &tree));
    out.extend(pub_problems(&tree));
    out
}

/// No library target, and the binary is `src/main.rs`.
fn manifest_problems(root: &Path) -> Vec<String> {
    let mut out = Vec::new();
    if root.join("src/lib.rs").exists() {
        out.push("src/lib.rs exists: the root package has a library".to_string());
    }
    let manifest = read_manifest(&root.join("Cargo.toml"));
    if manifest.contains_key("lib") {
        out.push("Cargo.toml has a [lib] section".to_string());
    }
    let bins = manifest.get("bin").and_then(|b| b.as_array());
    for bin in bins.into_iter().flatten() {
        let path = bin
            .get("path")
            .and_then(|p| p.as_str())
            .unwrap_or("src/main.rs");
        if path != "src/main.rs" {
            out.push(format!("Cargo.toml: a [[bin]] at {path}, not src/main.rs"));
        }
    }
    out
}

/// Every file under `src/` is `main.rs` or under `cli/`, and a module of
/// the binary; `main.rs` declares `cli` and no other module.
fn file_problems(root: &Path, tree: &ModuleTree) -> Vec<String> {
    let mut out = Vec::new();
    let src = root.join("src");
    let modules: BTreeSet<_> = tree.files().into_iter().collect();
    for file in rust_files(&src) {
        let shown_file = shown(&file);
        if file != src.join("main.rs") && !file.starts_with(src.join("cli")) {
            out.push(format!("{shown_file}: outside src/cli"));
        }
        if !modules.contains(&file) && !tree.is_test_file(&file) {
            out.push(format!("{shown_file}: not a module of the binary"));
        }
    }
    let root_modules: Vec<&String> = tree.modules[0].children.keys().collect();
    if root_modules != ["cli"] {
        out.push(format!(
            "src/main.rs declares the modules {root_modules:?}, not only `cli`"
        ));
    }
    out
}

/// `pub` items that are neither clap types, commands, modules, nor named
/// by another module or by the signature of an item that is.
fn pub_problems(tree: &ModuleTree) -> Vec<String> {
    let used: BTreeSet<(usize, String)> = resolved(tree)
        .into_iter()
        .filter(|(r, t)| r.from != t.module)
        .filter_map(|(_, t)| Some((t.module, t.item?)))
        .collect();
    let mut out = Vec::new();
    for (id, module) in tree.modules.iter().enumerate() {
        let used_here = |name: &str| used.contains(&(id, name.to_string()));
        for ident in unjustified_pub(&module.items, used_here) {
            out.push(format!(
                "{}:{}: pub `{ident}`: no clap type, no cmd_* function, and no other module names it",
                shown(&module.file),
                line_of(ident.span())
            ));
        }
    }
    out
}

/// The `pub` items among `items` that are no clap type, no `cmd_*`
/// function, not `used` by another module, and not named in the signature
/// of an item that is one of those.
fn unjustified_pub(items: &[Item], used: impl Fn(&str) -> bool) -> Vec<&syn::Ident> {
    let decls: Vec<(&Item, &syn::Ident)> = items
        .iter()
        .filter_map(|i| declared(i).map(|(ident, vis)| (i, ident, vis)))
        .filter(|(_, _, vis)| !matches!(vis, Visibility::Inherited))
        .map(|(i, ident, _)| (i, ident))
        .collect();
    let mut allowed: BTreeSet<String> = decls
        .iter()
        .filter(|(item, ident)| {
            let name = ident.to_string();
            is_clap_type(item)
                || matches!(item, Item::Fn(_)) && name.starts_with("cmd_")
                || used(&name)
        })
        .map(|(_, ident)| ident.to_string())
        .collect();
    // What the signature of an allowed item names must be pub too.
    loop {
        let before = allowed.len();
        for (item, ident) in &decls {
            if allowed.contains(&ident.to_string()) {
                allowed.extend(signature_types(item));
            }
        }
        if allowed.len() == before {
            break;
        }
    }
    decls
        .into_iter()
        .map(|(_, ident)| ident)
        .filter(|ident| !allowed.contains(&ident.to_string()))
        .collect()
}

/// The last segments of the type paths in an item's signature: a
/// function's arguments and result, the fields of a struct or an enum,
/// a type alias, the type of a constant.
fn signature_types(item: &Item) -> BTreeSet<String> {
    struct Types(BTreeSet<String>);
    impl<'ast> Visit<'ast> for Types {
        fn visit_type_path(&mut self, t: &'ast syn::TypePath) {
            if let Some(last) = t.path.segments.last() {
                self.0.insert(last.ident.to_string());
            }
            visit::visit_type_path(self, t);
        }
    }
    let mut types = Types(BTreeSet::new());
    match item {
        Item::Fn(f) => types.visit_signature(&f.sig),
        Item::Struct(s) => types.visit_fields(&s.fields),
        Item::Enum(e) => e
            .variants
            .iter()
            .for_each(|v| types.visit_fields(&v.fields)),
        Item::Type(t) => types.visit_type(&t.ty),
        Item::Const(c) => types.visit_type(&c.ty),
        Item::Static(s) => types.visit_type(&s.ty),
        _ => {}
    }
    types.0
}

/// The name and visibility of an item declaration (not a module, not a
/// `use`).
fn declared(item: &Item) -> Option<(&syn::Ident, &Visibility)> {
    match item {
        Item::Const(i) => Some((&i.ident, &i.vis)),
        Item::Enum(i) => Some((&i.ident, &i.vis)),
        Item::Fn(i) => Some((&i.sig.ident, &i.vis)),
        Item::Static(i) => Some((&i.ident, &i.vis)),
        Item::Struct(i) => Some((&i.ident, &i.vis)),
        Item::Trait(i) => Some((&i.ident, &i.vis)),
        Item::Type(i) => Some((&i.ident, &i.vis)),
        Item::Union(i) => Some((&i.ident, &i.vis)),
        _ => None,
    }
}

/// Whether `item` derives one of clap's argument traits.
fn is_clap_type(item: &Item) -> bool {
    item_attrs(item)
        .iter()
        .filter(|a| a.path().is_ident("derive"))
        .any(|a| {
            let mut clap = false;
            let _ = a.parse_nested_meta(|m| {
                clap |= m
                    .path
                    .segments
                    .last()
                    .is_some_and(|s| CLAP_DERIVES.iter().any(|d| s.ident == d));
                Ok(())
            });
            clap
        })
}

#[test]
fn a_pub_item_needs_a_clap_derive_a_cmd_name_a_user_or_a_signature_that_has_one() {
    let file: syn::File = syn::parse_str(
        "#[derive(clap::Args)]\npub struct A {\n    pub x: u8,\n}\n\
         pub fn cmd_a(a: &A) -> Outcome {\n    todo!()\n}\npub struct Outcome;\n\
         pub fn helper() {}\npub fn used() {}\npub const LONELY: u8 = 1;\nfn private() {}\n",
    )
    .unwrap();
    let names: Vec<String> = unjustified_pub(&file.items, |n| n == "used")
        .iter()
        .map(|i| i.to_string())
        .collect();
    assert_eq!(names, ["helper", "LONELY"]);
}
