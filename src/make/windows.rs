//! What dresses a window: curtains (or drapes) on a rod, and blinds. Their back is at `-z`
//! against the wall; the solver hangs them over a window of their room and sizes them to it
//! (`solve::others`): curtains 30 cm wider than the window on each side, from 15 cm above it,
//! to the floor for drapes or to 20 cm under the sill for curtains; blinds the window's size.
//!
//! Typical sizes (when no window is there to size them): curtains 160 × 220 cm, blinds
//! 100 × 120 cm.

use super::finish::Material;
use super::mesh::{pleats, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, WALL};

/// Curtains or drapes: a rod with finials and two pleated panels drawn to the sides.
pub const CURTAINS: Kind = Kind {
    name: "curtains",
    family: "windows",
    phrases: &[
        "curtain",
        "drape",
        "drapery",
        "window curtain",
        "curtain panel",
        "sheer curtain",
        "blackout curtain",
    ],
    places: WALL,
    typical_m: [1.6, 2.2, 0.12],
    object_type: "Curtains",
    thor: Thor::Static,
    mass_kg: 4.0,
    generator: curtains,
};

fn curtains(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let cloth = ctx.main(Material::Fabric);
    let rod = ctx.accent(Material::Metal);
    let mut b = Build::default();
    let r = (d / 6.0).min(0.012);
    let rod_y = h - r;
    let z_rod = d / 2.0 - r * 2.2;
    b.add("rod", rod, Shape::cylinder(Axis::X, [-w / 2.0 + 0.03, rod_y - r, z_rod], w - 0.06, r));
    for x in [-w / 2.0, w / 2.0 - 0.03] {
        b.add("finial", rod, Shape::cylinder(Axis::X, [x, rod_y - r, z_rod], 0.03, r * 2.2));
    }
    // Brackets to the wall.
    for x in [-w / 2.0 + 0.08, w / 2.0 - 0.08] {
        b.add(
            "bracket",
            rod,
            Shape::Cuboid {
                min: [x - 0.008, rod_y - 3.0 * r, -d / 2.0],
                max: [x + 0.008, rod_y - r, z_rod],
            },
        );
    }
    // Two panels, each a third of the width, pleated every ~10 cm, hanging from just under the rod.
    let sheer = ctx.look.any(&["sheer", "voile", "lace"]);
    ctx.note("panels", 2);
    ctx.note("sheer", sheer);
    let panel = w / 3.0;
    let fold = (d * 0.35).min(0.05);
    let z = -d / 2.0 + 0.01;
    for side in [-1.0, 1.0] {
        let (x0, x1) =
            if side < 0.0 { (-w / 2.0, -w / 2.0 + panel) } else { (w / 2.0 - panel, w / 2.0) };
        b.add(
            "panel",
            cloth,
            Shape::Sheet {
                path: pleats(x0, x1, z, fold, 0.1),
                thickness: 0.006,
                y0: 0.0,
                y1: rod_y - 2.0 * r,
            },
        );
    }
    b
}

/// Blinds: a head rail, horizontal slats, a bottom rail and a cord.
pub const BLINDS: Kind = Kind {
    name: "blinds",
    family: "windows",
    phrases: &[
        "blind",
        "window blind",
        "venetian blind",
        "roller blind",
        "roman blind",
        "shade",
        "window shade",
        "roller shade",
    ],
    places: WALL,
    typical_m: [1.0, 1.2, 0.05],
    object_type: "Blinds",
    thor: Thor::Static,
    mass_kg: 2.0,
    generator: blinds,
};

fn blinds(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let slat = ctx.main(Material::Painted);
    let rail = ctx.accent(Material::Metal);
    let mut b = Build::default();
    let head = (0.04_f64).min(h / 8.0);
    b.add("head rail", rail, Shape::cuboid([-w / 2.0, h - head, -d / 2.0], [w, head, d]));
    let roller = ctx.look.any(&["roller", "roman", "shade"]);
    ctx.note("style", if roller { "roller" } else { "slats" });
    if roller {
        b.add(
            "shade",
            slat,
            Shape::Cuboid {
                min: [-w / 2.0 + 0.01, 0.02, -0.003],
                max: [w / 2.0 - 0.01, h - head, 0.003],
            },
        );
    } else {
        let pitch = 0.025;
        let n = (((h - head - 0.03) / pitch).floor() as usize).clamp(3, 120);
        ctx.note("slats", n);
        for i in 0..n {
            let y = 0.03 + i as f64 * pitch;
            b.add(
                "slat",
                slat,
                Shape::cuboid([-w / 2.0 + 0.01, y, -d / 2.0 + 0.005], [w - 0.02, 0.003, d * 0.7]),
            );
        }
    }
    b.add(
        "bottom rail",
        rail,
        Shape::cuboid([-w / 2.0 + 0.01, 0.0, -d / 2.0 + 0.004], [w - 0.02, 0.02, d * 0.75]),
    );
    b.add(
        "cord",
        rail,
        Shape::cylinder(Axis::Y, [w / 2.0 - 0.04, h * 0.35, d / 2.0 - 0.004], h * 0.6, 0.003),
    );
    b
}
