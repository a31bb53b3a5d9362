//! Textiles: a bath mat, a rug, a folded throw.
//!
//! Typical sizes: a bath mat 80 × 50 cm, a rug 200 × 140 cm, a folded throw 50 × 35 cm and
//! 6 cm high.

use super::finish::Material;
use super::mesh::{Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR, ON};

/// A bath mat: a rubber backing, a pile and a border.
pub const BATH_MAT: Kind = Kind {
    name: "bath_mat",
    family: "textiles",
    phrases: &["bath mat", "bathmat", "bath rug", "shower mat", "bathroom mat", "bathroom rug"],
    places: FLOOR,
    typical_m: [0.8, 0.015, 0.5],
    object_type: "BathMat",
    thor: Thor::Static,
    mass_kg: 0.8,
    generator: bath_mat,
};

fn bath_mat(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let pile = ctx.main(Material::Fabric);
    let backing = ctx.fixed(Material::Rubber, [0.2, 0.2, 0.2]);
    let border = ctx.accent(Material::Fabric);
    let mut b = Build::default();
    let back = h * 0.2;
    b.add("backing", backing, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, back, d]));
    let band = (w.min(d) * 0.06).min(0.04);
    b.add(
        "pile",
        pile,
        Shape::cuboid(
            [-w / 2.0 + band, back, -d / 2.0 + band],
            [w - 2.0 * band, h - back, d - 2.0 * band],
        ),
    );
    super::mesh::frame_flat(
        &mut b,
        "border",
        border,
        [-w / 2.0, w / 2.0],
        [-d / 2.0, d / 2.0],
        [back, h * 0.9],
        band,
    );
    b
}

/// A rug: a body with a border band, rectangular with fringes at its ends, or round.
pub const RUG: Kind = Kind {
    name: "rug",
    family: "textiles",
    phrases: &[
        "rug",
        "area rug",
        "carpet",
        "round rug",
        "runner",
        "runner rug",
        "floor rug",
        "kilim",
    ],
    places: FLOOR,
    typical_m: [2.0, 0.012, 1.4],
    object_type: "Rug",
    thor: Thor::Static,
    mass_kg: 6.0,
    generator: rug,
};

fn rug(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Fabric);
    let border = ctx.accent(Material::Carpet);
    let mut b = Build::default();
    let round = ctx.look.any(&["round", "circular", "circle", "oval"]);
    ctx.note("shape", if round { "round" } else { "rectangular" });
    if round {
        let r = w.min(d) / 2.0;
        b.add("border", border, Shape::tube(Axis::Y, [0.0, 0.0, 0.0], h, r, 0.88));
        b.add(
            "body",
            body,
            Shape::Round {
                axis: Axis::Y,
                from: [0.0, 0.0, 0.0],
                length: h * 0.95,
                r0: r * 0.88,
                r1: r * 0.88,
                inner: 0.0,
                segments: 40,
            },
        );
        return b;
    }
    let fringe = (w * 0.03).min(0.06);
    let (x0, x1) = (-w / 2.0 + fringe, w / 2.0 - fringe);
    let band = (d * 0.08).min(0.12);
    b.add(
        "body",
        body,
        Shape::Cuboid {
            min: [x0 + band, 0.0, -d / 2.0 + band],
            max: [x1 - band, h, d / 2.0 - band],
        },
    );
    super::mesh::frame_flat(
        &mut b,
        "border",
        border,
        [x0, x1],
        [-d / 2.0, d / 2.0],
        [0.0, h],
        band,
    );
    // Fringes: tassels along both short ends.
    let n = ((d / 0.04).floor() as usize).clamp(4, 60);
    let tassel = ctx.fixed(Material::Fabric, [0.92, 0.9, 0.84]);
    for i in 0..n {
        let z = -d / 2.0 + d * (i as f64 + 0.5) / n as f64;
        for (a, bx) in [(-w / 2.0, x0), (x1, w / 2.0)] {
            b.add(
                "fringe",
                tassel,
                Shape::Cuboid { min: [a, 0.0, z - 0.004], max: [bx, h * 0.4, z + 0.004] },
            );
        }
    }
    b
}

/// A folded throw or blanket: folded layers, offset a little, with a fringe at the folded
/// edge's ends.
pub const THROW: Kind = Kind {
    name: "throw",
    family: "textiles",
    phrases: &[
        "throw",
        "throw blanket",
        "blanket",
        "folded blanket",
        "knit throw",
        "afghan",
        "quilt",
        "plaid",
    ],
    places: ON,
    typical_m: [0.5, 0.06, 0.35],
    object_type: "Blanket",
    thor: Thor::Pickup,
    mass_kg: 1.0,
    generator: throw,
};

fn throw(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let cloth = ctx.main(Material::Fabric);
    let stripe = ctx.accent(Material::Fabric);
    let mut b = Build::default();
    let layers = ((h / 0.015).round() as usize).clamp(2, 6);
    ctx.note("layers", layers);
    let lh = h / layers as f64;
    for i in 0..layers {
        let shrink = 0.012 * (i % 2) as f64;
        b.add(
            "layer",
            cloth,
            Shape::cuboid(
                [-w / 2.0 + shrink, i as f64 * lh, -d / 2.0 + shrink],
                [w - 0.03 - shrink, lh * 0.92, d - 2.0 * shrink],
            ),
        );
    }
    // The rounded fold at the right side and a woven stripe across the top.
    b.add(
        "fold",
        cloth,
        Shape::cylinder(Axis::Z, [w / 2.0 - h / 2.0, h / 2.0, -d / 2.0], d, h / 2.0),
    );
    b.add(
        "stripe",
        stripe,
        Shape::cuboid([-w * 0.3, h * 0.999 - 0.002, -d / 2.0 + 0.01], [w * 0.08, 0.002, d - 0.02]),
    );
    b
}
