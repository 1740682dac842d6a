//! Bus-1300 addresses written outside the object table (`objects/src`).
//! The rules, each precise enough to leave unrelated numbers alone (a
//! port 1300, a plane code 17, a bus other than 1300):
//!
//! 1. `ObjectAddress::new(bus, ..)` or `ObjectAddress { bus, .. }` with
//!    `bus` = `1300` or a `TC_BUS` path: an address built from its parts
//!    (this also catches a `tc(d, i, s)`-style helper, whose body builds
//!    one); `ObjectAddress { .. }` as a pattern (or as an expression
//!    without `bus`, as in `matches!`) with an integer literal in it.
//! 2. A string literal with `1300/` followed by a digit or a `{` (and
//!    not after a digit), or `{TC_BUS}/`: an address in text
//!    (`"1300/1/1/6".parse()`, `format!("1300/{d}/{i}/{s}")`,
//!    `format!("{TC_BUS}/1/{g}/8")`). Doc comments are not read.
//! 3. A list (call or method arguments, tuple, array, tuple or slice
//!    pattern) holding `1300` or `TC_BUS` and an integer literal:
//!    `(1300, 1, 1, 6)`, `addr(TC_BUS, 0, 3, 0)`.
//! 4. An integer literal matched or compared against an address's
//!    `.device` or `.sub`: `match (a.device, a.sub) { (1, 2) => .. }`,
//!    `a.sub == 6`.
//! 5. A constant or static named as a bus, device or subindex number
//!    (a word `BUS`, `DEVICE(S)`, `SUB(S)`, `SUBINDEX` in its name) whose
//!    value holds an integer literal that fits a `u16` (an address part):
//!    `const ERROR_SUB: u16 = 1;`, but not `const E_NO_SUBINDEX: u32 =
//!    0x06090011;`.
//!
//! In shipped code, test-only items and modules are skipped. Test code
//! (`scan_everything`: test modules, `tests/`, `benches/`, `examples/`)
//! is read under rules 1 to 3, except an address in trace text (after a
//! verb `R` or `W`, as a trace or `addipos call` writes it).

use std::path::{Path, PathBuf};

use proc_macro2::{TokenStream, TokenTree};
use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};
use syn::{Expr, ImplItem, Item, Lit, Member, Pat, Token};

use crate::workspace::{impl_item_attrs, is_test_only, item_attrs, line_of};

/// One address written by hand.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Finding {
    /// The file.
    pub file: PathBuf,
    /// The line, 1-based.
    pub line: usize,
    /// Which rule, in words.
    pub what: &'static str,
}

/// The bus-1300 addresses written in the source `text` of `file`, or the
/// parse error.
pub fn scan(file: &Path, text: &str) -> Result<Vec<Finding>, ScanError> {
    scan_in(file, text, Reach::ShippedCode)
}

/// The bus-1300 addresses written anywhere in `text` of `file`, test
/// code included (the files under `tests/`, `benches/` and `examples/`).
pub fn scan_everything(file: &Path, text: &str) -> Result<Vec<Finding>, ScanError> {
    scan_in(file, text, Reach::AllCode)
}

/// What a scan reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reach {
    /// Test-only items and modules are skipped.
    ShippedCode,
    /// Everything.
    AllCode,
}

/// A file the checker cannot read as Rust.
#[derive(Debug)]
pub struct ScanError(pub String);

impl std::fmt::Display for ScanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn scan_in(file: &Path, text: &str, reach: Reach) -> Result<Vec<Finding>, ScanError> {
    let syntax =
        syn::parse_file(text).map_err(|e| ScanError(format!("{}: {e}", file.display())))?;
    let mut finder = Finder {
        file: file.to_path_buf(),
        found: Vec::new(),
        reach,
    };
    for item in &syntax.items {
        finder.visit_item(item);
    }
    finder.found.sort();
    finder
        .found
        .dedup_by(|a, b| a.line == b.line && a.file == b.file);
    Ok(finder.found)
}

const BUILT: &str = "a bus-1300 ObjectAddress built from its parts";
const PATTERN: &str = "an ObjectAddress pattern with a number in it";
const TEXT: &str = "a bus-1300 address in a string";
const BESIDE: &str = "integer literals beside bus 1300";
const FIELD: &str = "a number matched against an address's device or subindex";
const CONSTANT: &str = "a constant giving a bus, device or subindex number";

/// Walks a file and notes the findings.
struct Finder {
    file: PathBuf,
    found: Vec<Finding>,
    reach: Reach,
}

impl Finder {
    fn note(&mut self, span: proc_macro2::Span, what: &'static str) {
        self.found.push(Finding {
            file: self.file.clone(),
            line: line_of(span),
            what,
        });
    }

    /// Rules 4 and 5 guess at an address from a number alone (no bus in
    /// sight): they are read in shipped code only. Test code of the
    /// generic layers (`uoi`, `opcua-face`) serves buses of its own
    /// and matches their parts freely.
    fn note_guess(&mut self, span: proc_macro2::Span, what: &'static str) {
        if self.reach == Reach::ShippedCode {
            self.note(span, what);
        }
    }

    /// Rule 5 for a constant named `ident` with value `expr`.
    fn named_number(&mut self, ident: &syn::Ident, expr: &Expr) {
        const WORDS: [&str; 6] = ["BUS", "DEVICE", "DEVICES", "SUB", "SUBS", "SUBINDEX"];
        let name = ident.to_string();
        if name.split('_').any(|w| WORDS.contains(&w)) && holds_int(expr) {
            self.note_guess(ident.span(), CONSTANT);
        }
    }

    /// Rule 2 for the string literals among `tokens` (macro bodies that
    /// are not expressions, attributes).
    fn token_strings(&mut self, tokens: TokenStream) {
        for t in tokens {
            match t {
                TokenTree::Group(g) => self.token_strings(g.stream()),
                TokenTree::Literal(l) => {
                    if let Ok(Lit::Str(s)) = syn::parse2::<Lit>(TokenTree::Literal(l).into()) {
                        self.visit_lit_str(&s);
                    }
                }
                _ => {}
            }
        }
    }
}

impl<'ast> Visit<'ast> for Finder {
    fn visit_item(&mut self, item: &'ast Item) {
        if self.reach == Reach::ShippedCode && is_test_only(item_attrs(item)) {
            return;
        }
        match item {
            Item::Const(c) => self.named_number(&c.ident, &c.expr),
            Item::Static(s) => self.named_number(&s.ident, &s.expr),
            _ => {}
        }
        visit::visit_item(self, item);
    }

    fn visit_impl_item(&mut self, item: &'ast ImplItem) {
        if self.reach == Reach::ShippedCode && is_test_only(impl_item_attrs(item)) {
            return;
        }
        if let ImplItem::Const(c) = item {
            self.named_number(&c.ident, &c.expr);
        }
        visit::visit_impl_item(self, item);
    }

    fn visit_attribute(&mut self, attr: &'ast syn::Attribute) {
        match &attr.meta {
            _ if attr.path().is_ident("doc") => {}
            syn::Meta::List(list) => self.token_strings(list.tokens.clone()),
            syn::Meta::NameValue(nv) => self.visit_expr(&nv.value),
            syn::Meta::Path(_) => {}
        }
    }

    fn visit_expr_call(&mut self, call: &'ast syn::ExprCall) {
        if ends_with(&call.func, &["ObjectAddress", "new"]) {
            if call.args.first().is_some_and(is_bus) {
                self.note(span_of(&call.func), BUILT);
            }
        } else {
            self.list(call.args.iter(), span_of(&call.func));
        }
        visit::visit_expr_call(self, call);
    }

    fn visit_expr_method_call(&mut self, call: &'ast syn::ExprMethodCall) {
        self.list(call.args.iter(), call.method.span());
        visit::visit_expr_method_call(self, call);
    }

    fn visit_expr_tuple(&mut self, t: &'ast syn::ExprTuple) {
        self.list(t.elems.iter(), t.paren_token.span.open());
        visit::visit_expr_tuple(self, t);
    }

    fn visit_expr_array(&mut self, a: &'ast syn::ExprArray) {
        self.list(a.elems.iter(), a.bracket_token.span.open());
        visit::visit_expr_array(self, a);
    }

    fn visit_expr_struct(&mut self, s: &'ast syn::ExprStruct) {
        // Without a `bus` field it is a pattern in an expression's clothes
        // (`matches!(a, ObjectAddress { device: 1, .. })`).
        let bus = s.fields.iter().find(|f| member_is(&f.member, "bus"));
        let by_hand = bus.map_or_else(
            || s.fields.iter().any(|f| is_int(&f.expr)),
            |f| is_bus(&f.expr),
        );
        if last_is(&s.path, "ObjectAddress") && by_hand {
            self.note(s.path.segments[0].ident.span(), BUILT);
        }
        visit::visit_expr_struct(self, s);
    }

    fn visit_pat_struct(&mut self, p: &'ast syn::PatStruct) {
        if last_is(&p.path, "ObjectAddress") && p.fields.iter().any(|f| pat_has_int(&f.pat)) {
            self.note(p.path.segments[0].ident.span(), PATTERN);
        }
        visit::visit_pat_struct(self, p);
    }

    fn visit_pat_tuple(&mut self, p: &'ast syn::PatTuple) {
        self.pattern_list(p.elems.iter(), p.paren_token.span.open());
        visit::visit_pat_tuple(self, p);
    }

    fn visit_pat_slice(&mut self, p: &'ast syn::PatSlice) {
        self.pattern_list(p.elems.iter(), p.bracket_token.span.open());
        visit::visit_pat_slice(self, p);
    }

    fn visit_pat_tuple_struct(&mut self, p: &'ast syn::PatTupleStruct) {
        self.pattern_list(p.elems.iter(), p.paren_token.span.open());
        visit::visit_pat_tuple_struct(self, p);
    }

    fn visit_expr_match(&mut self, m: &'ast syn::ExprMatch) {
        if names_address_part(&m.expr) {
            for arm in m.arms.iter().filter(|a| pat_has_int(&a.pat)) {
                self.note_guess(span_of_pat(&arm.pat), FIELD);
            }
        }
        visit::visit_expr_match(self, m);
    }

    fn visit_expr_binary(&mut self, b: &'ast syn::ExprBinary) {
        let part_vs_int = |x: &Expr, y: &Expr| names_address_part(x) && is_int(y);
        if part_vs_int(&b.left, &b.right) || part_vs_int(&b.right, &b.left) {
            self.note_guess(span_of(&b.left), FIELD);
        }
        visit::visit_expr_binary(self, b);
    }

    fn visit_lit_str(&mut self, s: &'ast syn::LitStr) {
        let text = s.value();
        let trace_text = self.reach == Reach::AllCode && is_trace_text(&text);
        if address_in_text(&text) && !trace_text {
            self.note(s.span(), TEXT);
        }
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        match mac.parse_body_with(Punctuated::<Expr, Token![,]>::parse_terminated) {
            Ok(args) => {
                self.list(args.iter(), mac.path.segments[0].ident.span());
                for arg in &args {
                    self.visit_expr(arg);
                }
            }
            Err(_) => self.token_strings(mac.tokens.clone()),
        }
    }
}

impl Finder {
    /// Rule 3 for expressions.
    fn list<'e>(&mut self, elems: impl Iterator<Item = &'e Expr> + Clone, at: proc_macro2::Span) {
        let bus = elems.clone().position(is_bus);
        if let Some(b) = bus {
            if elems.enumerate().any(|(i, e)| i != b && is_int(e)) {
                self.note(at, BESIDE);
            }
        }
    }

    /// Rule 3 for patterns.
    fn pattern_list<'p>(
        &mut self,
        elems: impl Iterator<Item = &'p Pat> + Clone,
        at: proc_macro2::Span,
    ) {
        let bus = elems.clone().position(is_bus_pat);
        if let Some(b) = bus {
            if elems.enumerate().any(|(i, p)| i != b && pat_has_int(p)) {
                self.note(at, BESIDE);
            }
        }
    }
}

/// Whether `text` holds a bus-1300 address (rule 2).
pub fn address_in_text(text: &str) -> bool {
    let after_digit = |i: usize| text[..i].ends_with(|c: char| c.is_ascii_digit());
    let digit_at = |i: usize| text[i..].starts_with(|c: char| c.is_ascii_digit() || c == '{');
    text.contains("{TC_BUS}/")
        || text
            .match_indices("1300/")
            .any(|(i, m)| !after_digit(i) && digit_at(i + m.len()))
}

/// Whether every bus-1300 address in `text` stands where a trace or
/// `addipos call` puts it: right after the verb `R` or `W` (any case),
/// as in `"W 1300/1/1/6 d 2.5"`. That is the trace syntax, the user's
/// language, which tests write as a user does (traces/ is written the
/// same way); read in test code only (decision 520).
pub fn is_trace_text(text: &str) -> bool {
    let after_verb = |i: usize| {
        let head = text[..i].trim_end_matches(' ');
        let spaced = head.len() < i;
        let verb = head.ends_with(['R', 'W', 'r', 'w']);
        let alone =
            head.len() < 2 || !head[..head.len() - 1].ends_with(|c: char| c.is_alphanumeric());
        spaced && verb && alone
    };
    !text.contains("{TC_BUS}/") && text.match_indices("1300/").all(|(i, _)| after_verb(i))
}

/// `1300`, or a path ending in `TC_BUS` (through parentheses and casts).
fn is_bus(e: &Expr) -> bool {
    match e {
        Expr::Lit(l) => int_value(&l.lit) == Some(1300),
        Expr::Path(p) => last_is(&p.path, "TC_BUS"),
        Expr::Paren(p) => is_bus(&p.expr),
        Expr::Group(g) => is_bus(&g.expr),
        Expr::Cast(c) => is_bus(&c.expr),
        _ => false,
    }
}

/// The pattern `1300` or `TC_BUS`.
fn is_bus_pat(p: &Pat) -> bool {
    match p {
        Pat::Lit(l) => int_value(&l.lit) == Some(1300),
        Pat::Ident(i) => i.ident == "TC_BUS",
        Pat::Path(p) => last_is(&p.path, "TC_BUS"),
        _ => false,
    }
}

/// An integer literal, maybe negated or in parentheses.
fn is_int(e: &Expr) -> bool {
    match e {
        Expr::Lit(l) => matches!(l.lit, Lit::Int(_)),
        Expr::Unary(u) => matches!(u.op, syn::UnOp::Neg(_)) && is_int(&u.expr),
        Expr::Paren(p) => is_int(&p.expr),
        Expr::Group(g) => is_int(&g.expr),
        _ => false,
    }
}

/// Whether `e` holds an integer literal anywhere.
fn holds_int(e: &Expr) -> bool {
    let mut ints = Ints(false);
    ints.visit_expr(e);
    ints.0
}

/// Whether the pattern `p` holds an integer literal anywhere.
fn pat_has_int(p: &Pat) -> bool {
    let mut ints = Ints(false);
    ints.visit_pat(p);
    ints.0
}

/// Notes whether an integer literal was seen.
struct Ints(bool);

impl<'ast> Visit<'ast> for Ints {
    /// Only a number an address part can hold (bus, device and subindex
    /// are `u16`): a 32-bit error code such as `0x06090011` is no address.
    fn visit_lit_int(&mut self, lit: &'ast syn::LitInt) {
        if lit
            .base10_parse::<u64>()
            .is_ok_and(|n| n <= u64::from(u16::MAX))
        {
            self.0 = true;
        }
    }
}

/// Whether `e` is, or is a tuple holding, a field `.device` or `.sub`.
fn names_address_part(e: &Expr) -> bool {
    match e {
        Expr::Field(f) => member_is(&f.member, "device") || member_is(&f.member, "sub"),
        Expr::Tuple(t) => t.elems.iter().any(names_address_part),
        Expr::Paren(p) => names_address_part(&p.expr),
        Expr::Reference(r) => names_address_part(&r.expr),
        _ => false,
    }
}

fn member_is(m: &Member, name: &str) -> bool {
    matches!(m, Member::Named(i) if i == name)
}

fn int_value(lit: &Lit) -> Option<u64> {
    match lit {
        Lit::Int(i) => i.base10_parse().ok(),
        _ => None,
    }
}

fn last_is(path: &syn::Path, name: &str) -> bool {
    path.segments.last().is_some_and(|s| s.ident == name)
}

/// Whether `e` is a path ending in `tail`.
fn ends_with(e: &Expr, tail: &[&str]) -> bool {
    let Expr::Path(p) = e else { return false };
    let segs: Vec<String> = p
        .path
        .segments
        .iter()
        .map(|s| s.ident.to_string())
        .collect();
    segs.len() >= tail.len()
        && segs[segs.len() - tail.len()..]
            .iter()
            .zip(tail)
            .all(|(a, b)| a == b)
}

fn span_of(e: &Expr) -> proc_macro2::Span {
    syn::spanned::Spanned::span(e)
}

fn span_of_pat(p: &Pat) -> proc_macro2::Span {
    syn::spanned::Spanned::span(p)
}
