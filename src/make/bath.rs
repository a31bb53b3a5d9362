//! Bathroom things: a shower stall and a bath caddy.
//!
//! Typical sizes: a shower stall 90 × 90 cm and 2 m tall; a bath caddy 30 × 15 cm.

use super::finish::Material;
use super::mesh::{tray, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR, ON};

/// A shower stall: a tray, a back and side wall, glass panels and door on a metal frame, and
/// a shower head on its riser.
pub const SHOWER_STALL: Kind = Kind {
    name: "shower_stall",
    family: "bath",
    phrases: &[
        "shower stall",
        "shower",
        "shower cubicle",
        "shower enclosure",
        "walk in shower",
        "shower cabin",
        "shower booth",
    ],
    places: FLOOR,
    typical_m: [0.9, 2.0, 0.9],
    object_type: "ShowerStall",
    thor: Thor::Static,
    mass_kg: 60.0,
    generator: shower_stall,
};

fn shower_stall(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let tile = ctx.main(Material::Ceramic);
    let glass = ctx.fixed(Material::Glass, [0.78, 0.86, 0.88]);
    let metal = ctx.fixed(Material::Metal, [0.8, 0.81, 0.83]);
    let mut b = Build::default();
    let tray_h = (0.08_f64).min(h / 10.0);
    tray(&mut b, "tray", tile, [-w / 2.0, 0.0, -d / 2.0], [w / 2.0, tray_h, d / 2.0], 0.04);
    b.add("drain", metal, Shape::cylinder(Axis::Y, [0.0, 0.01, 0.0], tray_h - 0.01, 0.04));
    let t = 0.02;
    // Tiled back and left walls (the stall stands in a corner or against a wall).
    b.add(
        "wall",
        tile,
        Shape::Cuboid { min: [-w / 2.0, tray_h, -d / 2.0], max: [w / 2.0, h, -d / 2.0 + t] },
    );
    b.add(
        "wall",
        tile,
        Shape::Cuboid { min: [-w / 2.0, tray_h, -d / 2.0 + t], max: [-w / 2.0 + t, h, d / 2.0] },
    );
    // A glass side and a glass front with a door, in a metal frame.
    let g = 0.008;
    b.add(
        "glass",
        glass,
        Shape::Cuboid {
            min: [w / 2.0 - g, tray_h, -d / 2.0 + t],
            max: [w / 2.0, h - 0.05, d / 2.0 - 0.02],
        },
    );
    b.add(
        "glass",
        glass,
        Shape::Cuboid {
            min: [-w / 2.0 + t, tray_h, d / 2.0 - g],
            max: [-w / 2.0 + w * 0.45, h - 0.05, d / 2.0],
        },
    );
    b.add(
        "door",
        glass,
        Shape::Cuboid {
            min: [-w / 2.0 + w * 0.45, tray_h, d / 2.0 - 2.5 * g],
            max: [w / 2.0 - 0.02, h - 0.05, d / 2.0 - 1.5 * g],
        },
    );
    for (x, z) in [(w / 2.0 - 0.01, d / 2.0 - 0.01), (w / 2.0 - 0.01, -d / 2.0 + 0.03)] {
        b.add("frame", metal, Shape::block(x, tray_h, z, [0.02, h - tray_h, 0.02]));
    }
    b.add(
        "frame",
        metal,
        Shape::Cuboid {
            min: [-w / 2.0 + t, h - 0.05, d / 2.0 - 0.02],
            max: [w / 2.0, h - 0.03, d / 2.0],
        },
    );
    b.add("handle", metal, Shape::block(w * 0.15, h * 0.45, d / 2.0 - 0.02, [0.015, 0.3, 0.015]));
    // The riser and head on the back wall, the mixer under it.
    let riser_x = 0.0;
    b.add(
        "riser",
        metal,
        Shape::cylinder(Axis::Y, [riser_x, h * 0.45, -d / 2.0 + t + 0.03], h * 0.5, 0.012),
    );
    b.add("head", metal, Shape::cylinder(Axis::Z, [riser_x, h * 0.93, -d / 2.0 + t], 0.2, 0.012));
    b.add(
        "head",
        metal,
        Shape::cylinder(Axis::Y, [riser_x, h * 0.91, -d / 2.0 + t + 0.2], 0.03, 0.1),
    );
    b.add("mixer", metal, Shape::block(riser_x, h * 0.42, -d / 2.0 + t + 0.02, [0.16, 0.06, 0.04]));
    b
}

/// A bath caddy: a tray with low rails and a soap dish.
pub const BATH_CADDY: Kind = Kind {
    name: "bath_caddy",
    family: "bath",
    phrases: &[
        "bath caddy",
        "shower caddy",
        "bathtub caddy",
        "bath tray",
        "bathtub tray",
        "toiletry caddy",
    ],
    places: ON,
    typical_m: [0.3, 0.12, 0.15],
    object_type: "BathCaddy",
    thor: Thor::Pickup,
    mass_kg: 0.8,
    generator: bath_caddy,
};

fn bath_caddy(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Wood);
    let handle = ctx.accent(Material::Metal);
    let mut b = Build::default();
    let wall_h = h * 0.45;
    tray(&mut b, "tray", body, [-w / 2.0, 0.0, -d / 2.0], [w / 2.0, wall_h, d / 2.0], 0.01);
    b.add(
        "divider",
        body,
        Shape::Cuboid { min: [-0.005, 0.0, -d / 2.0], max: [0.005, wall_h, d / 2.0] },
    );
    // A carrying handle over the middle.
    b.add(
        "handle",
        handle,
        Shape::Cuboid { min: [-0.005, wall_h, -0.008], max: [0.005, h - 0.01, 0.008] },
    );
    b.add(
        "handle",
        handle,
        Shape::Cuboid { min: [-w * 0.25, h - 0.012, -0.008], max: [w * 0.25, h, 0.008] },
    );
    b
}
