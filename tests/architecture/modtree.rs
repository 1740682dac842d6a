//! A crate's module tree, found the way rustc finds it: the root file,
//! `mod x;` as `x.rs` or `x/mod.rs` in the folder of the declaring module
//! (`a.rs` declares its children in `a/`), and inline `mod x { }` blocks.
//! Test-only modules and items (`#[cfg(test)]`, `#[test]`) are left out,
//! and the files of test-only modules are remembered so that other checks
//! can skip them. `#[path]` attributes are not followed (none is used).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use syn::Item;

use crate::workspace::{is_test_only, item_attrs};

/// Reads a source file: from disk in the checks, from a map in the
/// checker's own tests. `None` when there is no such file.
pub type Reader<'a> = &'a dyn Fn(&Path) -> Option<String>;

/// One module of a crate.
pub struct Module {
    /// `crate`, or its path below the root (`correction::sink`).
    pub name: String,
    /// The enclosing module (`None` for the root).
    pub parent: Option<usize>,
    /// The modules it declares, by name.
    pub children: BTreeMap<String, usize>,
    /// The file that holds it.
    pub file: PathBuf,
    /// Its items, test-only ones left out.
    pub items: Vec<Item>,
}

/// A crate's modules; `modules[0]` is the root.
#[derive(Default)]
pub struct ModuleTree {
    /// Every module, parents before children.
    pub modules: Vec<Module>,
    /// Files and folders that hold test-only modules.
    pub test_paths: Vec<PathBuf>,
    /// Files that were declared but could not be found or parsed.
    pub problems: Vec<String>,
}

/// Where a module's children live.
struct Place {
    /// The file holding the module.
    file: PathBuf,
    /// The folder of its children's files.
    dir: PathBuf,
}

impl ModuleTree {
    /// The module tree of the crate whose root file is `root_file`.
    pub fn load(root_file: &Path, read: Reader<'_>) -> Self {
        let mut tree = Self::default();
        let items = tree.parse(root_file, read).unwrap_or_default();
        let place = Place {
            file: root_file.to_path_buf(),
            dir: root_file.parent().unwrap_or(Path::new("")).to_path_buf(),
        };
        tree.add(None, "crate".into(), place, items, read);
        tree
    }

    /// The module called `name` (`crate`, `a::b`), if there is one.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.modules.iter().position(|m| m.name == name)
    }

    /// Whether `path` is the file or lies in the folder of a test-only
    /// module.
    pub fn is_test_file(&self, path: &Path) -> bool {
        self.test_paths.iter().any(|t| path.starts_with(t))
    }

    /// Every file of the tree.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = self.modules.iter().map(|m| m.file.clone()).collect();
        files.sort();
        files.dedup();
        files
    }

    /// The items of `file`, or `None` with a note in `problems`.
    fn parse(&mut self, file: &Path, read: Reader<'_>) -> Option<Vec<Item>> {
        let Some(text) = read(file) else {
            self.problems.push(format!("{}: not found", file.display()));
            return None;
        };
        match syn::parse_file(&text) {
            Ok(f) => Some(f.items),
            Err(e) => {
                self.problems.push(format!("{}: {e}", file.display()));
                None
            }
        }
    }

    /// Adds module `name` holding `items`, then its children; returns its
    /// number.
    fn add(
        &mut self,
        parent: Option<usize>,
        name: String,
        place: Place,
        items: Vec<Item>,
        read: Reader<'_>,
    ) -> usize {
        let (kept, tests): (Vec<Item>, Vec<Item>) = items
            .into_iter()
            .partition(|i| !is_test_only(item_attrs(i)));
        for test in tests {
            if let Item::Mod(m) = test {
                let dir = place.dir.join(m.ident.to_string());
                self.test_paths.push(dir.with_extension("rs"));
                self.test_paths.push(dir);
            }
        }
        let id = self.modules.len();
        self.modules.push(Module {
            name,
            parent,
            children: BTreeMap::new(),
            file: place.file.clone(),
            items: kept.clone(),
        });
        for item in kept {
            if let Item::Mod(m) = item {
                self.add_child(id, &place, m, read);
            }
        }
        id
    }

    /// Adds the module declared by `m` inside module `parent`.
    fn add_child(&mut self, parent: usize, place: &Place, m: syn::ItemMod, read: Reader<'_>) {
        let ident = m.ident.to_string();
        let dir = place.dir.join(&ident);
        let (file, items) = match m.content {
            Some((_, items)) => (place.file.clone(), Some(items)),
            None => {
                let flat = dir.with_extension("rs");
                let file = if read(&flat).is_some() {
                    flat
                } else {
                    dir.join("mod.rs")
                };
                let items = self.parse(&file, read);
                (file, items)
            }
        };
        let name = match parent {
            0 => ident.clone(),
            _ => format!("{}::{ident}", self.modules[parent].name),
        };
        let place = Place { file, dir };
        let child = self.add(Some(parent), name, place, items.unwrap_or_default(), read);
        self.modules[parent].children.insert(ident, child);
    }
}
