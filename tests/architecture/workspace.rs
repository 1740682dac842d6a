//! The workspace as the checks see it: its packages and their crates, the
//! source files under each `src/`, and small helpers on syntax (test-only
//! items, line numbers, paths relative to the workspace root).

use std::fs;
use std::path::{Path, PathBuf};

use syn::{Attribute, ImplItem, Item};

/// One crate of a package: its library or its binary.
pub struct CrateRoot {
    /// The package name, with ` (bin)` for a binary next to a library.
    pub name: String,
    /// The package folder.
    pub dir: PathBuf,
    /// `src/lib.rs` or `src/main.rs`.
    pub root_file: PathBuf,
}

/// The workspace root: this package's folder.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The folders of the root package and of every workspace member, in the
/// order of the root `Cargo.toml` (the fuzz package is outside the
/// workspace and is not read).
pub fn package_dirs(root: &Path) -> Vec<PathBuf> {
    let manifest = read_manifest(&root.join("Cargo.toml"));
    let members = manifest
        .get("workspace")
        .and_then(|w| w.get("members"))
        .and_then(|m| m.as_array())
        .cloned()
        .unwrap_or_default();
    let mut dirs = vec![root.to_path_buf()];
    dirs.extend(
        members
            .iter()
            .filter_map(|m| m.as_str())
            .map(|m| root.join(m)),
    );
    dirs
}

/// The crates of every package: `src/lib.rs` and `src/main.rs` where
/// they exist.
pub fn crate_roots(root: &Path) -> Vec<CrateRoot> {
    let mut out = Vec::new();
    for dir in package_dirs(root) {
        let name = package_name(&dir);
        let lib = dir.join("src/lib.rs");
        let main = dir.join("src/main.rs");
        if lib.is_file() {
            out.push(CrateRoot {
                name: name.clone(),
                dir: dir.clone(),
                root_file: lib.clone(),
            });
        }
        if main.is_file() {
            let name = if lib.is_file() {
                format!("{name} (bin)")
            } else {
                name
            };
            out.push(CrateRoot {
                name,
                dir,
                root_file: main,
            });
        }
    }
    out
}

/// The parsed manifest at `path`.
pub fn read_manifest(path: &Path) -> toml::Table {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `package.name` of the manifest in `dir`.
fn package_name(dir: &Path) -> String {
    read_manifest(&dir.join("Cargo.toml"))
        .get("package")
        .and_then(|p| p.get("name"))
        .and_then(|n| n.as_str())
        .unwrap_or("?")
        .to_string()
}

/// Every `.rs` file under `dir`, sorted.
pub fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = walkdir::WalkDir::new(dir)
        .into_iter()
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_file())
        .map(|e| e.into_path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    files.sort();
    files
}

/// Reads a file from disk (the reader of the real checks).
pub fn read_disk(path: &Path) -> Option<String> {
    fs::read_to_string(path).ok()
}

/// `path` relative to the workspace root, for messages.
pub fn shown(path: &Path) -> String {
    let root = root();
    path.strip_prefix(&root)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// The line a syntax node starts on (1-based; needs proc-macro2's
/// `span-locations`).
pub fn line_of(span: proc_macro2::Span) -> usize {
    span.start().line
}

/// Whether `attrs` make an item exist only in tests: `#[test]`, or a
/// `#[cfg(..)]` that names `test` and no `not` (`cfg(test)`,
/// `cfg(all(test, feature = ".."))`).
pub fn is_test_only(attrs: &[Attribute]) -> bool {
    attrs.iter().any(|a| {
        if a.path().is_ident("test") {
            return true;
        }
        if !a.path().is_ident("cfg") {
            return false;
        }
        let words = token_idents(a.meta.require_list().map(|l| l.tokens.clone()).ok());
        words.iter().any(|w| w == "test") && !words.iter().any(|w| w == "not")
    })
}

/// Every identifier in `tokens`, groups included.
fn token_idents(tokens: Option<proc_macro2::TokenStream>) -> Vec<String> {
    let mut out = Vec::new();
    for t in tokens.into_iter().flatten() {
        match t {
            proc_macro2::TokenTree::Ident(i) => out.push(i.to_string()),
            proc_macro2::TokenTree::Group(g) => out.extend(token_idents(Some(g.stream()))),
            _ => {}
        }
    }
    out
}

/// The attributes of an item.
pub fn item_attrs(item: &Item) -> &[Attribute] {
    match item {
        Item::Const(i) => &i.attrs,
        Item::Enum(i) => &i.attrs,
        Item::ExternCrate(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        Item::ForeignMod(i) => &i.attrs,
        Item::Impl(i) => &i.attrs,
        Item::Macro(i) => &i.attrs,
        Item::Mod(i) => &i.attrs,
        Item::Static(i) => &i.attrs,
        Item::Struct(i) => &i.attrs,
        Item::Trait(i) => &i.attrs,
        Item::TraitAlias(i) => &i.attrs,
        Item::Type(i) => &i.attrs,
        Item::Union(i) => &i.attrs,
        Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

/// The attributes of an item of an `impl` block.
pub fn impl_item_attrs(item: &ImplItem) -> &[Attribute] {
    match item {
        ImplItem::Const(i) => &i.attrs,
        ImplItem::Fn(i) => &i.attrs,
        ImplItem::Type(i) => &i.attrs,
        ImplItem::Macro(i) => &i.attrs,
        _ => &[],
    }
}
