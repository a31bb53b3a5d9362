//! Kitchen things: a cutting board, a pitcher, a set of coasters, a range (stove and oven),
//! a kitchen island with a sink.
//!
//! Typical sizes: a cutting board 40 × 28 cm; a pitcher 24 cm tall; coasters 11 cm across; a
//! range 76 × 65 cm and 92 cm high (counter height); an island 180 × 90 cm.

use super::finish::Material;
use super::mesh::{frame, tray, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR, ON};

/// A cutting board with a handle and a juice groove.
pub const CUTTING_BOARD: Kind = Kind {
    name: "cutting_board",
    family: "kitchen",
    phrases: &[
        "cutting board",
        "chopping board",
        "bread board",
        "carving board",
        "serving board",
        "cheese board",
    ],
    places: ON,
    typical_m: [0.4, 0.02, 0.28],
    object_type: "CuttingBoard",
    thor: Thor::Pickup,
    mass_kg: 1.0,
    generator: cutting_board,
};

fn cutting_board(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let wood = ctx.main(Material::Wood);
    let groove = ctx.fixed(Material::Wood, [0.45, 0.32, 0.2]);
    let mut b = Build::default();
    let handle = (w * 0.15).min(0.08);
    b.add("board", wood, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w - handle, h, d]));
    b.add(
        "handle",
        wood,
        Shape::Cuboid { min: [w / 2.0 - handle, 0.0, -d * 0.15], max: [w / 2.0, h, d * 0.15] },
    );
    frame_groove(&mut b, groove, w - handle, h, d);
    b
}

fn frame_groove(b: &mut Build, swatch: usize, w: f64, h: f64, d: f64) {
    let inset = 0.02_f64.min(d / 6.0);
    let t = 0.004;
    let (x0, x1) = (-w / 2.0 + inset, w / 2.0 - inset);
    let (z0, z1) = (-d / 2.0 + inset, d / 2.0 - inset);
    super::mesh::frame_flat(b, "groove", swatch, [x0, x1], [z0, z1], [h - 0.0015, h + 0.0005], t);
}

/// A pitcher: a body open at the top, a spout and a handle.
pub const PITCHER: Kind = Kind {
    name: "pitcher",
    family: "kitchen",
    phrases: &["pitcher", "jug", "water pitcher", "water jug", "carafe", "milk jug", "creamer"],
    places: ON,
    typical_m: [0.14, 0.24, 0.18],
    object_type: "Pitcher",
    thor: Thor::Pickup,
    mass_kg: 0.8,
    generator: pitcher,
};

fn pitcher(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Ceramic);
    let mut b = Build::default();
    let r = w / 2.0;
    let cz = -d / 2.0 + r;
    b.add(
        "body",
        body,
        Shape::Round {
            axis: Axis::Y,
            from: [0.0, 0.0, cz],
            length: h,
            r0: r * 0.85,
            r1: r,
            inner: 0.9,
            segments: 24,
        },
    );
    b.add("bottom", body, Shape::cylinder(Axis::Y, [0.0, 0.0, cz], 0.01, r * 0.85));
    // The spout on the side away from the handle.
    b.add(
        "spout",
        body,
        Shape::Cuboid { min: [-r * 0.25, h * 0.85, -d / 2.0], max: [r * 0.25, h, cz - r * 0.6] },
    );
    // The handle on the other side.
    let back = cz + r;
    let hb = (d / 2.0 - back).max(0.015);
    b.add(
        "handle",
        body,
        Shape::Cuboid { min: [-0.008, h * 0.25, back], max: [0.008, h * 0.3, back + hb] },
    );
    b.add(
        "handle",
        body,
        Shape::Cuboid { min: [-0.008, h * 0.8, back], max: [0.008, h * 0.85, back + hb] },
    );
    b.add(
        "handle",
        body,
        Shape::Cuboid {
            min: [-0.008, h * 0.25, back + hb - 0.015],
            max: [0.008, h * 0.85, back + hb],
        },
    );
    b
}

/// A set of coasters in their holder.
pub const COASTERS: Kind = Kind {
    name: "coaster_set",
    family: "kitchen",
    phrases: &["coaster", "coaster set", "set of coasters", "drink coaster"],
    places: ON,
    typical_m: [0.11, 0.05, 0.11],
    object_type: "Coasters",
    thor: Thor::Pickup,
    mass_kg: 0.3,
    generator: coasters,
};

fn coasters(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let holder = ctx.accent(Material::Wood);
    let mut b = Build::default();
    let r = w.min(d) / 2.0;
    b.add("holder", holder, Shape::cylinder(Axis::Y, [0.0, 0.0, 0.0], 0.004, r));
    b.add("holder", holder, Shape::block(0.0, 0.0, -r * 0.9, [r * 0.6, h, 0.006]));
    let n = ((h / 0.008).floor() as usize).clamp(2, 8);
    ctx.note("coasters", n);
    for i in 0..n {
        let s = ctx.main(Material::Ceramic);
        b.add(
            "coaster",
            s,
            Shape::cylinder(
                Axis::Y,
                [0.0, 0.004 + i as f64 * (h - 0.004) / n as f64, 0.0],
                (h - 0.004) / n as f64 * 0.9,
                r * 0.92,
            ),
        );
    }
    b
}

/// A range: a body at counter height, a cooktop with four burners, knobs, and an oven door
/// with a window and a handle.
pub const RANGE: Kind = Kind {
    name: "range",
    family: "kitchen",
    phrases: &[
        "range",
        "stove",
        "cooker",
        "kitchen range",
        "gas range",
        "electric range",
        "oven range",
        "stove top",
        "cooktop",
        "gas stove",
    ],
    places: FLOOR,
    typical_m: [0.76, 0.92, 0.65],
    object_type: "Stove",
    thor: Thor::StaticReceptacle,
    mass_kg: 70.0,
    generator: range,
};

fn range(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Metal);
    let top = ctx.fixed(Material::Panel, [0.08, 0.08, 0.09]);
    let grate = ctx.fixed(Material::Metal, [0.2, 0.2, 0.21]);
    let glass = ctx.fixed(Material::Glass, [0.15, 0.15, 0.17]);
    let mut b = Build::default();
    let top_t = 0.02;
    let panel_h = (h * 0.12).min(0.12);
    b.add(
        "body",
        body,
        Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, h - panel_h - top_t, d - 0.02]),
    );
    b.add("cooktop", top, Shape::cuboid([-w / 2.0, h - panel_h - top_t, -d / 2.0], [w, top_t, d]));
    b.add("back panel", body, Shape::cuboid([-w / 2.0, h - panel_h, -d / 2.0], [w, panel_h, 0.05]));
    for (k, (fx, fz)) in
        [(-0.25, -0.15), (0.25, -0.15), (-0.25, 0.2), (0.25, 0.2)].into_iter().enumerate()
    {
        let r = if k % 3 == 0 { 0.09 } else { 0.07 };
        let r = r * (w / 0.76).min(1.2);
        let at = [fx * w, h - panel_h, fz * d];
        b.add("burner", grate, Shape::tube(Axis::Y, at, 0.015, r, 0.8).with_segments(12));
        b.add("burner", grate, Shape::cylinder(Axis::Y, at, 0.02, r * 0.35).with_segments(10));
    }
    for i in 0..4 {
        let x = -w * 0.3 + i as f64 * w * 0.2;
        b.add(
            "knob",
            grate,
            Shape::cylinder(Axis::Z, [x, h - panel_h * 0.5, -d / 2.0 + 0.05], 0.025, 0.018)
                .with_segments(10),
        );
    }
    // The oven door on the front with its window and handle.
    let door_top = h - panel_h - top_t - 0.06;
    let z = d / 2.0 - 0.02;
    frame(
        &mut b,
        "door",
        body,
        [-w / 2.0 + 0.01, w / 2.0 - 0.01],
        [0.1, door_top],
        [z, d / 2.0],
        0.08,
    );
    b.add(
        "window",
        glass,
        Shape::Cuboid {
            min: [-w / 2.0 + 0.09, 0.18, z],
            max: [w / 2.0 - 0.09, door_top - 0.08, d / 2.0 - 0.004],
        },
    );
    b.add(
        "handle",
        grate,
        Shape::cylinder(Axis::X, [-w * 0.4, door_top - 0.04, d / 2.0 - 0.002], w * 0.8, 0.01),
    );
    b.add(
        "drawer",
        top,
        Shape::Cuboid { min: [-w / 2.0 + 0.01, 0.01, z], max: [w / 2.0 - 0.01, 0.09, d / 2.0] },
    );
    b
}

/// A tall cabinet standing on the floor (a kitchen high cabinet, a pantry, a storage
/// cupboard): the wall cabinet's carcass, shelf, doors and handles at full height. A dresser
/// is no kitchen high cabinet.
pub const TALL_CABINET: Kind = Kind {
    name: "tall_cabinet",
    family: "kitchen",
    phrases: &[
        "tall cabinet",
        "high cabinet",
        "kitchen high cabinet",
        "pantry",
        "pantry cabinet",
        "storage cabinet",
        "kitchen cabinet",
        "cupboard",
        "linen cupboard",
        "broom cupboard",
        "utility cabinet",
    ],
    places: FLOOR,
    typical_m: [0.8, 2.0, 0.6],
    object_type: "Cabinet",
    thor: Thor::StaticReceptacle,
    mass_kg: 60.0,
    generator: super::wall::wall_cabinet,
};

/// A kitchen island: a cabinet body with doors, a stone top with an overhang, a sink and a
/// faucet.
pub const KITCHEN_ISLAND: Kind = Kind {
    name: "kitchen_island",
    family: "kitchen",
    phrases: &[
        "kitchen island",
        "island",
        "island counter",
        "kitchen island with sink",
        "island with sink",
    ],
    places: FLOOR,
    typical_m: [1.8, 0.92, 0.9],
    object_type: "CounterTop",
    thor: Thor::StaticReceptacle,
    mass_kg: 150.0,
    generator: kitchen_island,
};

fn kitchen_island(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let cabinet = ctx.main(Material::Painted);
    let stone = ctx.fixed(Material::Stone, [0.86, 0.85, 0.82]);
    let steel = ctx.fixed(Material::Metal, [0.75, 0.76, 0.78]);
    let mut b = Build::default();
    let top_t = 0.04;
    let over = (d * 0.2).min(0.25);
    // The body stands back from the overhang at the front (where stools go).
    b.add(
        "cabinet",
        cabinet,
        Shape::cuboid([-w / 2.0 + 0.05, 0.0, -d / 2.0], [w - 0.1, h - top_t, d - over]),
    );
    b.add(
        "plinth",
        stone,
        Shape::cuboid([-w / 2.0 + 0.07, 0.0, -d / 2.0 + 0.02], [w - 0.14, 0.08, d - over - 0.05]),
    );
    let doors = ((w / 0.45).floor() as usize).clamp(2, 6);
    ctx.note("doors", doors);
    let dw = (w - 0.1) / doors as f64;
    for i in 0..doors {
        let x0 = -w / 2.0 + 0.05 + i as f64 * dw + 0.003;
        b.add(
            "door",
            cabinet,
            Shape::Cuboid {
                min: [x0, 0.1, -d / 2.0 - 0.0],
                max: [x0 + dw - 0.006, h - top_t - 0.02, -d / 2.0 + 0.018],
            },
        );
        b.add(
            "handle",
            steel,
            Shape::Cuboid {
                min: [x0 + dw * 0.45, h - top_t - 0.1, -d / 2.0 - 0.0],
                max: [x0 + dw * 0.55, h - top_t - 0.09, -d / 2.0 + 0.001],
            },
        );
    }
    let with_sink = !ctx.look.any(&["without", "no"]) || ctx.look.has("sink");
    ctx.note("sink", with_sink);
    if with_sink {
        let (sw, sd) = ((w * 0.3).min(0.6), (d * 0.45).min(0.42));
        let sx = -w * 0.2;
        let sz = -d / 2.0 + (d - over) / 2.0;
        // The top round the sink's opening, the basin under it.
        b.add(
            "top",
            stone,
            Shape::Cuboid {
                min: [-w / 2.0, h - top_t, -d / 2.0],
                max: [sx - sw / 2.0, h, d / 2.0],
            },
        );
        b.add(
            "top",
            stone,
            Shape::Cuboid { min: [sx + sw / 2.0, h - top_t, -d / 2.0], max: [w / 2.0, h, d / 2.0] },
        );
        b.add(
            "top",
            stone,
            Shape::Cuboid {
                min: [sx - sw / 2.0, h - top_t, -d / 2.0],
                max: [sx + sw / 2.0, h, sz - sd / 2.0],
            },
        );
        b.add(
            "top",
            stone,
            Shape::Cuboid {
                min: [sx - sw / 2.0, h - top_t, sz + sd / 2.0],
                max: [sx + sw / 2.0, h, d / 2.0],
            },
        );
        tray(
            &mut b,
            "sink",
            steel,
            [sx - sw / 2.0, h - top_t - 0.2, sz - sd / 2.0],
            [sx + sw / 2.0, h - 0.001, sz + sd / 2.0],
            0.01,
        );
        b.add(
            "faucet",
            steel,
            Shape::cylinder(Axis::Y, [sx, h, sz - sd / 2.0 - 0.04], 0.0001, 0.02),
        );
    } else {
        b.add("top", stone, Shape::cuboid([-w / 2.0, h - top_t, -d / 2.0], [w, top_t, d]));
    }
    b
}
