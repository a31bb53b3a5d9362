//! The scenes in the shape users write (issue 53), generated: shared by `benches/lsp_bench.rs`
//! and the property tests that hold the language server's incremental analysis to a check from
//! scratch (`tests/properties.rs`).

use std::fmt::Write as _;

/// A scene in the shape users write (issue 53): every object group with a description of its
/// own (multi-byte text: `é`, `ü`, `°`, `—`), every third group counted with an `instance` block
/// for one of its instances, relations to the group before, and wall objects above floor
/// objects. With `one_room`, one 20 m × 20 m room of 834 floor groups and 104 wall objects
/// (about 6,200 lines, whatever `lines` says); else rooms of 5 m × 5 m with 22 floor groups and
/// 3 wall objects each (about 184 lines a room) until the text has about `lines` lines.
pub fn user_scene(lines: usize, one_room: bool) -> String {
    let kinds = [
        ("sofa", "sofa", "200 cm x 90 cm x 80 cm"),
        ("armchair", "armchair", "80 cm x 80 cm x 90 cm"),
        ("bookshelf", "bookshelf", "90 cm x 30 cm x 190 cm"),
        ("table", "dining table", "120 cm x 120 cm x 75 cm"),
        ("chair", "dining chair", "45 cm x 50 cm x 90 cm"),
        ("desk", "writing desk", "120 cm x 60 cm x 75 cm"),
        ("cabinet", "storage cabinet", "100 cm x 45 cm x 80 cm"),
        ("plant", "potted plant", "40 cm x 40 cm x 90 cm"),
    ];
    let materials = [
        "oak",
        "walnut",
        "crème lacquer",
        "brushed steel",
        "rattan",
        "bouclé fabric",
        "pine",
        "marble",
    ];
    let colours = [
        "warm grey",
        "café brown",
        "off-white",
        "navy blue",
        "sage green",
        "ochre",
        "charcoal",
        "terracotta",
    ];
    let styles = [
        "mid-century",
        "Scandinavian",
        "Japandi",
        "art déco",
        "industrial",
        "Bauhaus",
        "rustic",
        "minimalist",
    ];
    let (floor_groups, wall_groups, side) = if one_room { (834, 104, 20.0) } else { (22, 3, 5.0) };
    let mut text = String::from(
        "scene \"a house as its owners describe it\" {\n  wall height 2.7 m\n  seed 7\n}\n",
    );
    let mut room = 0;
    let mut count = text.lines().count();
    let mut n = 0usize;
    while count < lines || room == 0 {
        let (gx, gz) = (room % 4, room / 4);
        let (x0, z0) = (gx as f64 * side, gz as f64 * side);
        let _ = writeln!(
            text,
            "\nroom r{room} \"salle {room} — séjour\" {{\n  floor \"light oak parquet, matte\"\n  walls \"crème plaster, smooth\"\n  corners in m ({x0}, {z0}) ({x0}, {}) ({}, {}) ({}, {z0})",
            z0 + side,
            x0 + side,
            z0 + side,
            x0 + side
        );
        for k in 0..floor_groups {
            let (id, category, size) = kinds[k % kinds.len()];
            n += 1;
            let description = format!(
                "{} {} {category} in {}, nº {n}, 30° back",
                styles[n % styles.len()],
                colours[(n / 8) % colours.len()],
                materials[(n / 64) % materials.len()]
            );
            let _ = writeln!(
                text,
                "  object {id}_{k} \"{category}\" {{\n    describe \"{description}\"\n    size {size}"
            );
            if k % 3 == 1 {
                text.push_str("    count 2 varied\n");
            }
            text.push_str("    edge\n");
            if k > 0 {
                let (before, _, _) = kinds[(k - 1) % kinds.len()];
                let _ = writeln!(text, "    near {before}_{}-0", k - 1);
            }
            if k % 3 == 1 {
                let _ = writeln!(text, "    instance {id}_{k}-1 {{\n      far {id}_{k}-0\n    }}");
            }
            text.push_str("  }\n");
        }
        for w in 0..wall_groups {
            let target = (w * 8) % floor_groups;
            let (id, _, _) = kinds[target % kinds.len()];
            n += 1;
            let _ = writeln!(
                text,
                "  wall object painting_{w} \"painting\" {{\n    describe \"{} framed print nº {n}, {} — gallery style\"\n    size 60 cm x 3 cm x 80 cm\n    above {id}_{target}-0\n    height 150 cm\n  }}",
                styles[n % styles.len()],
                colours[n % colours.len()]
            );
        }
        text.push_str("}\n");
        room += 1;
        // Every piece ends with a line break: the lines add up.
        count = text.lines().count();
        if one_room {
            break;
        }
    }
    for r in 0..room {
        let from = if r == 0 { "exterior".to_string() } else { format!("r{}", r - 1) };
        let from = if r % 4 == 0 && r > 0 { format!("r{}", r - 4) } else { from };
        let _ = writeln!(text, "door {from} -- r{r} : doorway single");
    }
    text
}
