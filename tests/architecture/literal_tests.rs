//! The address-literal rules tried on small sources written here: each
//! way of writing a bus-1300 address by hand is found, on its line, and
//! the numbers that are no address are left alone.

use std::path::Path;

use crate::literals::{address_in_text, scan};

/// The lines `source` is flagged on, with the rule.
fn flagged(source: &str) -> Vec<(usize, &'static str)> {
    scan(Path::new("src/x.rs"), source)
        .unwrap()
        .into_iter()
        .map(|f| (f.line, f.what))
        .collect()
}

/// The lines only.
fn lines(source: &str) -> Vec<usize> {
    flagged(source).into_iter().map(|(l, _)| l).collect()
}

#[test]
fn object_address_new_on_bus_1300_is_found() {
    let src = "fn f() -> ObjectAddress {\n    ObjectAddress::new(1300, 1, 1, 6)\n}\n";
    assert_eq!(lines(src), [2]);
    let src = "fn f(g: u16) -> A {\n    uoi::ObjectAddress::new(tc_objects::TC_BUS, 1, g, 8)\n}\n";
    assert_eq!(lines(src), [2]);
}

#[test]
fn a_tc_helper_is_found_in_its_body() {
    let src = "fn tc(d: u16, i: u16, s: u16) -> ObjectAddress {\n    \
               ObjectAddress::new(TC_BUS, d, i, s)\n}\n\
               fn g() -> ObjectAddress {\n    tc(1, 1, 6)\n}\n";
    assert_eq!(lines(src), [2]);
    let src = "fn tc(d: u16, i: u16, s: u16) -> ObjectAddress {\n    \
               format!(\"1300/{d}/{i}/{s}\").parse().unwrap()\n}\n";
    assert_eq!(lines(src), [2]);
}

#[test]
fn an_address_in_a_string_is_found() {
    let src = "fn f() {\n    let a: ObjectAddress = \"1300/1/1/6\".parse().unwrap();\n}\n";
    assert_eq!(lines(src), [2]);
    let src = "fn f(g: u16) -> String {\n    format!(\"{TC_BUS}/1/{g}/8\")\n}\n";
    assert_eq!(lines(src), [2]);
    let src =
        "#[derive(Debug, thiserror::Error)]\n#[error(\"write 1300/0/1/0 first\")]\nstruct E;\n";
    assert_eq!(lines(src), [2]);
    let src = "fn f() {\n    let r = parse_request(\"R 1300/0/3/0 i\");\n}\n";
    assert_eq!(lines(src), [2]);
}

#[test]
fn an_address_struct_or_pattern_is_found() {
    let src = "const A: ObjectAddress = ObjectAddress {\n    bus: TC_BUS,\n    \
               device: 1,\n    index: 1,\n    sub: 6,\n};\n";
    assert_eq!(lines(src), [1]);
    let src = "fn f(a: ObjectAddress) -> bool {\n    \
               matches!(a, ObjectAddress { device: 1, sub: 6, .. })\n}\n";
    assert_eq!(lines(src), [2]);
}

#[test]
fn integers_beside_the_bus_are_found() {
    let src = "const A: (u16, u16, u16, u16) = (1300, 1, 1, 6);\nconst B: [u16; 4] = [TC_BUS, 0, 3, 0];\n";
    assert_eq!(lines(src), [1, 2]);
    let src = "fn f(a: (u16, u16, u16)) -> bool {\n    match a {\n        (1300, 1, 6) => true,\n        _ => false,\n    }\n}\n";
    assert_eq!(lines(src), [3]);
}

#[test]
fn numbers_matched_against_device_or_subindex_are_found() {
    let src = "fn f(addr: ObjectAddress) -> bool {\n    match (addr.device, addr.sub) {\n        \
               (1, 2) => true,\n        (3, 1) => true,\n        _ => false,\n    }\n}\n";
    assert_eq!(lines(src), [3, 4]);
    let src = "fn f(addr: ObjectAddress) -> bool {\n    addr.sub == 6\n}\n";
    assert_eq!(lines(src), [2]);
}

#[test]
fn constants_named_as_address_parts_are_found() {
    let src = "/// ERROR.\nconst ERROR_SUB: u16 = 1;\npub const DEVICES: [(u16, &str); 1] = [(0, \"Device 0\")];\n";
    assert_eq!(lines(src), [2, 3]);
}

#[test]
fn error_codes_named_after_a_subindex_are_no_address() {
    let src = "/// Missing subindex.\npub const E_NO_SUBINDEX: u32 = 0x06090011;\n\
               /// Its subindex.\nconst LIMIT_SUB: u16 = 0x11;\n";
    assert_eq!(lines(src), [4]);
}

#[test]
fn numbers_that_are_no_address_are_left_alone() {
    let src = "\
//! `R 1300/0/3/0 i` in a doc comment, and a doc test:
//! ```
//! let a: ObjectAddress = \"1300/1/1/6\".parse().unwrap();
//! ```
/// Plane code 17.
pub const PLANE_XY: i32 = 17;
const LISTEN: &str = \"127.0.0.1:1300\";
fn f(g: u16, table: &Table, d: u16, i: u16, s: u16) {
    let _ = TcObject::Radius.of(1);
    let _ = SocketAddr::from(([127, 0, 0, 1], 1300));
    let _ = ObjectAddress::new(7, 1, 1, 3);
    let _ = ObjectAddress::new(table.bus, d, i, s);
    let _ = entry.index == 3;
    let _ = \"13000/1\";
    let _ = (TC_BUS, g);
}
#[cfg(test)]
mod tests {
    fn t() {
        let _ = ObjectAddress::new(1300, 1, 1, 6);
        let _ = \"1300/1/1/6\";
    }
}
#[test]
fn t() {
    let _ = (1300, 1, 1, 6);
}
";
    assert_eq!(flagged(src), []);
}

#[test]
fn the_text_rule_wants_a_digit_after_the_bus_and_none_before() {
    assert!(address_in_text("1300/1"));
    assert!(address_in_text("W 1300/1/1/8 i 5"));
    assert!(address_in_text("{TC_BUS}/{d}"));
    assert!(address_in_text("1300/{d}/{i}/{s}"));
    assert!(!address_in_text("13000/1"));
    assert!(!address_in_text("1300/"));
    assert!(!address_in_text("port 1300"));
    assert!(!address_in_text("21300/4"));
}

#[test]
fn trace_text_is_the_users_language_in_test_code_only() {
    use crate::literals::{is_trace_text, scan_everything};
    assert!(is_trace_text("W 1300/1/1/6 d 2.5\nR 1300/1/1/6 d => 2.5\n"));
    assert!(is_trace_text("r 1300/0/3/0 i"));
    assert!(!is_trace_text("1300/1/1/6"));
    assert!(!is_trace_text("PWR 1300/1/1/6"));
    assert!(!is_trace_text("W 1300/1/1/6 then 1300/1/1/8"));
    assert!(!is_trace_text("W {TC_BUS}/1/1/6 d 2"));
    let trace = "fn f() {\n    run(\"W 1300/1/1/6 d 2.5\");\n}\n";
    let bare = "fn f() {\n    read(\"1300/1/1/6\");\n}\n";
    let test = "#[test]\nfn t() {\n    read(\"1300/1/1/6\");\n}\n";
    let every = |s: &str| {
        scan_everything(Path::new("tests/x.rs"), s)
            .unwrap()
            .into_iter()
            .map(|f| f.line)
            .collect::<Vec<_>>()
    };
    assert_eq!(every(trace), Vec::<usize>::new());
    assert_eq!(lines(trace), [2], "shipped code writes no trace text");
    assert_eq!(every(bare), [2]);
    assert_eq!(every(test), [3], "test functions are read too");
    assert_eq!(lines(test), Vec::<usize>::new());
}

#[test]
fn guesses_from_numbers_alone_are_for_shipped_code() {
    use crate::literals::scan_everything;
    let src = "fn f(a: ObjectAddress) -> bool {\n    a.sub == 6\n}\nconst TEST_BUS: u16 = 7;\n";
    assert_eq!(lines(src), [2, 4]);
    let every = scan_everything(Path::new("tests/x.rs"), src).unwrap();
    assert!(every.is_empty(), "{every:?}");
}
