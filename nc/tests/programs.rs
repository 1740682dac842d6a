//! Every NC program printed in the manuals, typed in, parses.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use nc::{parse_program, Item, NcError};

fn parse_file(name: &str) -> (Vec<nc::Block>, Vec<NcError>) {
    let path = format!("{}/../tests/nc/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    parse_program(&text)
}

#[test]
fn seed_programs_parse_without_errors() {
    let clean = [
        ("wzkg25.nc", 37),
        ("wzkg26.nc", 37),
        ("tool_data_change.nc", 15),
        ("dynamic_radius.nc", 13),
        ("otc_general.nc", 11),
        ("wr_quad_disc.nc", 14),
        ("otc_length.nc", 5),
        ("otc_tool_dir.nc", 13),
        ("otc_surf_norm_dir.nc", 32),
    ];
    for (name, blocks) in clean {
        let (parsed, errors) = parse_file(name);
        assert!(errors.is_empty(), "{name}: {errors:?}");
        assert_eq!(parsed.len(), blocks, "{name}");
        let last = parsed.last().unwrap();
        assert!(!last.items.is_empty(), "{name}");
    }
}

/// The ToolParam samples write `Y` without a value in N60: a misprint of the
/// manual that the parser reports, exactly there, and nothing else.
#[test]
fn tool_param_samples_report_only_the_bare_y() {
    for name in ["toolparam_set.nc", "toolparam_get.nc"] {
        let (parsed, errors) = parse_file(name);
        assert_eq!(parsed.len(), 5, "{name}");
        assert_eq!(errors.len(), 1, "{name}: {errors:?}");
        let e = &errors[0];
        assert_eq!((e.line, e.block_number, e.column), (6, Some(60), 14));
        assert!(e.message.contains("`Y`"), "{}", e.message);
        let commands = parsed[3].items.iter();
        let tool_params = commands
            .filter(|i| matches!(i, Item::SetToolParam { .. } | Item::GetToolParam { .. }))
            .count();
        assert_eq!(tool_params, 2, "{name}: two commands in N40");
    }
}
