//! Things on a desk or a shelf: a standing photo frame and a pen holder.
//!
//! Typical sizes: a photo frame 15 × 20 cm (a 10 × 15 cm photo) leaning on its easel back 10 cm
//! deep; a pen holder 8 cm across and 11 cm high with its pens.

use super::finish::Material;
use super::mesh::{frame, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, ON};

/// A photo frame that stands on its easel back.
pub const PHOTO_FRAME: Kind = Kind {
    name: "photo_frame",
    family: "desk",
    phrases: &[
        "photo frame",
        "picture frame",
        "frame",
        "photo",
        "framed photo",
        "family photo",
        "small photo frame",
        "photograph",
    ],
    places: ON,
    typical_m: [0.15, 0.2, 0.1],
    object_type: "PhotoFrame",
    thor: Thor::Pickup,
    mass_kg: 0.4,
    generator: photo_frame,
};

fn photo_frame(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let framing = ctx.main(Material::Wood);
    let mut b = Build::default();
    let t = (d * 0.15).min(0.015);
    let z0 = d / 2.0 - t;
    let bar = (w.min(h) * 0.08).clamp(0.006, 0.03);
    frame(&mut b, "frame", framing, [-w / 2.0, w / 2.0], [0.0, h], [z0, d / 2.0], bar);
    super::wall::picture(
        ctx,
        &mut b,
        [-w / 2.0 + bar, w / 2.0 - bar],
        [bar, h - bar],
        z0 + t * 0.4,
    );
    b.add(
        "back",
        framing,
        Shape::Cuboid { min: [-w / 2.0 + bar, bar, z0], max: [w / 2.0 - bar, h - bar, z0 + 0.002] },
    );
    // The easel leg from the back's middle to the table behind it.
    b.add(
        "easel",
        framing,
        Shape::Cuboid { min: [-0.01, 0.0, -d / 2.0], max: [0.01, h * 0.08, z0] },
    );
    b.add(
        "easel",
        framing,
        Shape::Cuboid { min: [-0.01, 0.0, z0 - 0.01], max: [0.01, h * 0.6, z0] },
    );
    b
}

/// A pen holder: a cup with pens and pencils in it.
pub const PEN_HOLDER: Kind = Kind {
    name: "pen_holder",
    family: "desk",
    phrases: &[
        "pen holder",
        "pencil holder",
        "pen cup",
        "pencil cup",
        "desk organizer",
        "pen pot",
        "stationery holder",
    ],
    places: ON,
    typical_m: [0.08, 0.11, 0.08],
    object_type: "PenHolder",
    thor: Thor::Pickup,
    mass_kg: 0.3,
    generator: pen_holder,
};

fn pen_holder(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let cup = ctx.main(Material::Metal);
    let mut b = Build::default();
    let r = w.min(d) / 2.0;
    let cup_h = h * 0.65;
    b.add("cup", cup, Shape::tube(Axis::Y, [0.0, 0.0, 0.0], cup_h, r, 0.9));
    b.add("cup", cup, Shape::cylinder(Axis::Y, [0.0, 0.0, 0.0], 0.004, r * 0.9));
    let pens = [[0.1, 0.2, 0.7], [0.1, 0.1, 0.1], [0.85, 0.15, 0.1], [0.95, 0.78, 0.2]];
    ctx.note("pens", pens.len());
    for (i, c) in pens.iter().enumerate() {
        let s = ctx.fixed(Material::Plastic, *c);
        let a = std::f64::consts::TAU * i as f64 / pens.len() as f64;
        let (x, z) = (a.sin() * r * 0.45, a.cos() * r * 0.45);
        let len = h - 0.004 - (i as f64) * (h * 0.06);
        b.add("pen", s, Shape::cylinder(Axis::Y, [x, 0.004, z], len, (r * 0.1).min(0.005)));
    }
    b
}
