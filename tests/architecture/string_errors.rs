//! A public API reports errors as types, not as strings: no `pub`
//! function, method or trait method of a library returns `Result<_,
//! String>` (or `Result<_, &str>`), and no `pub` type alias stands for
//! one. A caller can match a typed error; it can only print a string.
//! Test-only items are not read; private and `pub(crate)` items are
//! free (they are not an API).

use syn::visit::{self, Visit};
use syn::{GenericArgument, PathArguments, ReturnType, Type, Visibility};

use crate::workspace::{impl_item_attrs, is_test_only, item_attrs, line_of};

/// The lines of public items in the source `text` whose error type is a
/// string, each with the item's name.
pub fn string_errors(text: &str) -> Result<Vec<(usize, String)>, String> {
    let file = syn::parse_file(text).map_err(|e| e.to_string())?;
    let mut finder = Finder::default();
    for item in &file.items {
        finder.visit_item(item);
    }
    Ok(finder.found)
}

/// Walks a file; `public` tells whether the enclosing trait or impl is
/// public (a trait's methods are as public as the trait).
#[derive(Default)]
struct Finder {
    found: Vec<(usize, String)>,
    in_pub_trait: bool,
}

impl Finder {
    fn check(&mut self, ident: &syn::Ident, output: &ReturnType) {
        if let ReturnType::Type(_, ty) = output {
            if is_string_result(ty) {
                self.found.push((line_of(ident.span()), ident.to_string()));
            }
        }
    }
}

impl<'ast> Visit<'ast> for Finder {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        if is_test_only(item_attrs(item)) {
            return;
        }
        match item {
            syn::Item::Fn(f) if is_pub(&f.vis) => self.check(&f.sig.ident, &f.sig.output),
            syn::Item::Type(t) if is_pub(&t.vis) && is_string_result(&t.ty) => {
                self.found
                    .push((line_of(t.ident.span()), t.ident.to_string()));
            }
            syn::Item::Trait(t) => {
                let outer = std::mem::replace(&mut self.in_pub_trait, is_pub(&t.vis));
                visit::visit_item_trait(self, t);
                self.in_pub_trait = outer;
                return;
            }
            _ => {}
        }
        visit::visit_item(self, item);
    }

    fn visit_impl_item(&mut self, item: &'ast syn::ImplItem) {
        if is_test_only(impl_item_attrs(item)) {
            return;
        }
        if let syn::ImplItem::Fn(f) = item {
            if is_pub(&f.vis) {
                self.check(&f.sig.ident, &f.sig.output);
            }
        }
        visit::visit_impl_item(self, item);
    }

    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if self.in_pub_trait {
            self.check(&f.sig.ident, &f.sig.output);
        }
        visit::visit_trait_item_fn(self, f);
    }
}

/// `pub` alone: `pub(crate)`, `pub(super)` and `pub(in ..)` are no API.
fn is_pub(vis: &Visibility) -> bool {
    matches!(vis, Visibility::Public(_))
}

/// `Result<T, String>` or `Result<T, &str>` (any path ending in
/// `Result`, through references).
fn is_string_result(ty: &Type) -> bool {
    let Type::Path(p) = ty else { return false };
    let Some(last) = p.path.segments.last() else {
        return false;
    };
    if last.ident != "Result" {
        return false;
    }
    let PathArguments::AngleBracketed(args) = &last.arguments else {
        return false;
    };
    let types: Vec<&Type> = args
        .args
        .iter()
        .filter_map(|a| match a {
            GenericArgument::Type(t) => Some(t),
            _ => None,
        })
        .collect();
    types.len() == 2 && is_string(types[1])
}

fn is_string(ty: &Type) -> bool {
    match ty {
        Type::Path(p) => p
            .path
            .segments
            .last()
            .is_some_and(|s| s.ident == "String" || s.ident == "str"),
        Type::Reference(r) => is_string(&r.elem),
        _ => false,
    }
}

#[test]
fn public_string_errors_are_found() {
    let src = "pub fn a() -> Result<u8, String> { todo!() }\n\
               pub type R<T> = std::result::Result<T, String>;\n\
               pub trait T {\n    fn run(&mut self) -> Result<(), &'static str>;\n}\n\
               pub struct S;\nimpl S {\n    pub fn b(&self) -> Result<(), String> { todo!() }\n}\n";
    let lines: Vec<usize> = string_errors(src)
        .unwrap()
        .into_iter()
        .map(|f| f.0)
        .collect();
    assert_eq!(lines, [1, 2, 4, 8]);
}

#[test]
fn private_typed_and_test_items_are_left_alone() {
    let src = "fn a() -> Result<u8, String> { todo!() }\n\
               pub(crate) fn b() -> Result<u8, String> { todo!() }\n\
               pub fn c() -> Result<u8, Error> { todo!() }\n\
               trait T {\n    fn run(&mut self) -> Result<(), String>;\n}\n\
               #[cfg(test)]\nmod tests {\n    pub fn d() -> Result<(), String> { todo!() }\n}\n\
               pub fn e() -> Result<String, Error> { todo!() }\n";
    assert!(string_errors(src).unwrap().is_empty());
}
