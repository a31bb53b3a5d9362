//! Things for cats: a cat tree, a cat bed, a litter box, a scratching post, a cat wall shelf,
//! a pet bowl.
//!
//! Typical sizes are those of common retail products: a cat tree 60 × 50 cm and 1.5 m tall
//! (three levels), a cat bed 50 cm across, a litter box 50 × 40 cm, a scratching post 80 cm
//! on a 40 cm base, a cat wall shelf 60 × 25 cm.

use super::finish::Material;
use super::mesh::{tray, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR, FLOOR_OR_ON, WALL};

/// A cat tree: a carpeted base, sisal posts, platforms at rising heights, a hideaway box on
/// the first level and a round perch on top.
pub const CAT_TREE: Kind = Kind {
    name: "cat_tree",
    family: "pets",
    phrases: &["cat tree", "cat tower", "cat condo", "cat climber", "cat climbing tree", "cat gym"],
    places: FLOOR,
    typical_m: [0.6, 1.5, 0.5],
    object_type: "CatTree",
    thor: Thor::StaticReceptacle,
    mass_kg: 18.0,
    generator: cat_tree,
};

fn cat_tree(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let carpet = ctx.main(Material::Carpet);
    let sisal = ctx.accent(Material::Sisal);
    let mut b = Build::default();
    let board = (0.04_f64).min(h / 12.0);
    b.add("base", carpet, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, board, d]));
    // Levels: one every ~45 cm, at least two.
    let levels = ((h / 0.45).floor() as usize).clamp(2, 5);
    ctx.note("levels", levels);
    let post_r = (0.045_f64).min(w / 10.0).min(d / 10.0);
    let pw = w * 0.55;
    let pd = d * 0.6;
    let mut top_of_prev = board;
    for i in 1..=levels {
        let y = h * i as f64 / levels as f64;
        let last = i == levels;
        // Platforms alternate sides; the top one is a round perch over the middle.
        let side = if i % 2 == 1 { -1.0 } else { 1.0 };
        let cx = if last { 0.0 } else { side * (w - pw) / 2.0 };
        let cz = if last { 0.0 } else { -side * (d - pd) / 4.0 };
        // The post up to this level, under the platform's centre.
        let post_top = if last { y - 0.12_f64.min(h / 10.0) } else { y - board };
        b.add(
            "post",
            sisal,
            Shape::Round {
                axis: Axis::Y,
                from: [cx, top_of_prev, cz],
                length: post_top - top_of_prev,
                r0: post_r,
                r1: post_r,
                inner: 0.0,
                segments: 12,
            },
        );
        if last {
            let r = (w.min(d) / 2.0) * 0.8;
            let rim_h = (y - post_top).max(0.02);
            b.add("perch", carpet, Shape::cylinder(Axis::Y, [0.0, post_top, 0.0], rim_h * 0.4, r));
            b.add("perch rim", carpet, Shape::tube(Axis::Y, [0.0, post_top, 0.0], rim_h, r, 0.75));
        } else if i == 1 {
            // The hideaway: a box with an opening in its front, standing on the first level.
            let hw = pw.min(0.42);
            let hh = (h / levels as f64 * 0.7).min(0.34);
            let y0 = y - board;
            b.add("platform", carpet, Shape::block(cx, y0, cz, [pw, board, pd]));
            let (x0, x1) = (cx - hw / 2.0, cx + hw / 2.0);
            let (z0, z1) = (cz - pd / 2.0, cz + pd / 2.0);
            let t = 0.018;
            let yb = y;
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [x0, yb, z0], max: [x0 + t, yb + hh, z1] },
            );
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [x1 - t, yb, z0], max: [x1, yb + hh, z1] },
            );
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [x0, yb + hh - t, z0], max: [x1, yb + hh, z1] },
            );
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [x0, yb, z0], max: [x1, yb + hh, z0 + t] },
            );
            // The front: two jambs and a lintel round a cat-sized door.
            let door = (hw * 0.55).min(0.2);
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [x0, yb, z1 - t], max: [cx - door / 2.0, yb + hh, z1] },
            );
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid { min: [cx + door / 2.0, yb, z1 - t], max: [x1, yb + hh, z1] },
            );
            b.add(
                "hideaway",
                carpet,
                Shape::Cuboid {
                    min: [cx - door / 2.0, yb + hh * 0.7, z1 - t],
                    max: [cx + door / 2.0, yb + hh, z1],
                },
            );
        } else {
            b.add("platform", carpet, Shape::block(cx, y - board, cz, [pw, board, pd]));
        }
        top_of_prev = if last { post_top } else { y };
        // The next post starts where this platform is.
        if !last {
            top_of_prev = y;
        }
    }
    // A second post from the base to the first platform, for stability.
    let first_y = h / levels as f64 - board;
    b.add(
        "post",
        sisal,
        Shape::Round {
            axis: Axis::Y,
            from: [w / 2.0 - post_r * 2.0, board, d / 2.0 - post_r * 2.0],
            length: first_y - board,
            r0: post_r,
            r1: post_r,
            inner: 0.0,
            segments: 12,
        },
    );
    b
}

/// A round cat bed: a cushion inside a raised rim.
pub const CAT_BED: Kind = Kind {
    name: "cat_bed",
    family: "pets",
    phrases: &["cat bed", "pet bed", "cat cushion", "cat basket", "donut bed", "pet cushion"],
    places: FLOOR_OR_ON,
    typical_m: [0.5, 0.18, 0.5],
    object_type: "PetBed",
    thor: Thor::Static,
    mass_kg: 1.2,
    generator: cat_bed,
};

fn cat_bed(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let rim = ctx.main(Material::Fabric);
    let cushion = ctx.accent(Material::Carpet);
    let mut b = Build::default();
    let r = w.min(d) / 2.0;
    b.add("rim", rim, Shape::tube(Axis::Y, [0.0, 0.0, 0.0], h, r, 0.72));
    b.add("cushion", cushion, Shape::cylinder(Axis::Y, [0.0, 0.0, 0.0], h * 0.45, r * 0.74));
    // Stretch to an oval bed when asked longer than wide: a second rim beside the first.
    if (w - d).abs() > 0.05 {
        let long = (w - d).abs() / 2.0;
        let (dx, dz) = if w > d { (long, 0.0) } else { (0.0, long) };
        b.add("rim", rim, Shape::tube(Axis::Y, [dx, 0.0, dz], h, r, 0.72));
        b.add("rim", rim, Shape::tube(Axis::Y, [-dx, 0.0, -dz], h, r, 0.72));
        b.add("cushion", cushion, Shape::block(0.0, 0.0, 0.0, [w - 0.1, h * 0.45, d - 0.1]));
    }
    b
}

/// A litter box: a tray with litter in it, hooded when asked (or tall enough) with an
/// entrance in its front.
pub const LITTER_BOX: Kind = Kind {
    name: "litter_box",
    family: "pets",
    phrases: &["litter box", "litter tray", "cat litter box", "litter pan", "cat toilet"],
    places: FLOOR,
    typical_m: [0.5, 0.4, 0.4],
    object_type: "LitterBox",
    thor: Thor::Static,
    mass_kg: 6.0,
    generator: litter_box,
};

fn litter_box(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let shell = ctx.main(Material::Plastic);
    let litter = ctx.fixed(Material::Litter, [0.8, 0.76, 0.68]);
    let mut b = Build::default();
    let hooded = ctx.look.any(&["hooded", "covered", "enclosed", "closed"]) || h > 0.28;
    let pan_h = if hooded { (h * 0.38).min(0.16) } else { h };
    ctx.note("hooded", hooded);
    tray(&mut b, "pan", shell, [-w / 2.0, 0.0, -d / 2.0], [w / 2.0, pan_h, d / 2.0], 0.012);
    b.add("litter", litter, Shape::block(0.0, 0.012, 0.0, [w - 0.03, pan_h * 0.55, d - 0.03]));
    if hooded {
        let t = 0.01;
        let (y0, y1) = (pan_h, h);
        let hood = ctx.accent(Material::Plastic);
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [-w / 2.0, y1 - t, -d / 2.0], max: [w / 2.0, y1, d / 2.0] },
        );
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [-w / 2.0, y0, -d / 2.0], max: [-w / 2.0 + t, y1, d / 2.0] },
        );
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [w / 2.0 - t, y0, -d / 2.0], max: [w / 2.0, y1, d / 2.0] },
        );
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [-w / 2.0, y0, -d / 2.0], max: [w / 2.0, y1, -d / 2.0 + t] },
        );
        // The front with an entrance.
        let door = (w * 0.45).min(0.2);
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [-w / 2.0, y0, d / 2.0 - t], max: [-door / 2.0, y1, d / 2.0] },
        );
        b.add(
            "hood",
            hood,
            Shape::Cuboid { min: [door / 2.0, y0, d / 2.0 - t], max: [w / 2.0, y1, d / 2.0] },
        );
        b.add(
            "hood",
            hood,
            Shape::Cuboid {
                min: [-door / 2.0, y0 + (y1 - y0) * 0.75, d / 2.0 - t],
                max: [door / 2.0, y1, d / 2.0],
            },
        );
    }
    b
}

/// A scratching post: a weighted base, a sisal-wrapped post and a carpeted top.
pub const SCRATCHING_POST: Kind = Kind {
    name: "scratching_post",
    family: "pets",
    phrases: &["scratching post", "scratch post", "cat scratcher", "scratcher", "scratching pole"],
    places: FLOOR,
    typical_m: [0.4, 0.8, 0.4],
    object_type: "ScratchingPost",
    thor: Thor::Static,
    mass_kg: 4.0,
    generator: scratching_post,
};

fn scratching_post(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let carpet = ctx.main(Material::Carpet);
    let sisal = ctx.accent(Material::Sisal);
    let mut b = Build::default();
    let base_h = (0.04_f64).min(h / 6.0);
    let top_h = (0.03_f64).min(h / 8.0);
    let r = (w.min(d) / 5.0).min(0.06);
    b.add("base", carpet, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, base_h, d]));
    b.add("post", sisal, Shape::cylinder(Axis::Y, [0.0, base_h, 0.0], h - base_h - top_h, r));
    let top = (w.min(d) * 0.6).max(2.0 * r + 0.02);
    b.add("top", carpet, Shape::block(0.0, h - top_h, 0.0, [top, top_h, top]));
    b
}

/// A wall shelf for cats: a board on two brackets with a carpet pad.
pub const CAT_WALL_SHELF: Kind = Kind {
    name: "cat_wall_shelf",
    family: "pets",
    phrases: &[
        "cat shelf",
        "cat wall shelf",
        "cat wall step",
        "cat step",
        "cat perch",
        "cat wall perch",
    ],
    places: WALL,
    typical_m: [0.6, 0.2, 0.25],
    object_type: "Shelf",
    thor: Thor::StaticReceptacle,
    mass_kg: 3.0,
    generator: cat_wall_shelf,
};

fn cat_wall_shelf(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let wood = ctx.main(Material::Wood);
    let pad = ctx.accent(Material::Carpet);
    let metal = ctx.fixed(Material::Metal, [0.15, 0.15, 0.16]);
    let mut b = Build::default();
    let board = (0.025_f64).min(h / 4.0);
    let pad_h = (0.012_f64).min(h / 8.0);
    let top = h - pad_h;
    b.add("board", wood, Shape::cuboid([-w / 2.0, top - board, -d / 2.0], [w, board, d]));
    b.add("pad", pad, Shape::block(0.0, top, 0.0, [w - 0.04, pad_h, d - 0.03]));
    // Two L brackets under it, on the wall.
    for x in [-w / 3.0, w / 3.0] {
        b.add("bracket", metal, Shape::block(x, 0.0, -d / 2.0 + 0.01, [0.025, top - board, 0.02]));
        b.add("bracket", metal, Shape::block(x, top - board - 0.012, 0.0, [0.025, 0.012, d * 0.8]));
    }
    b
}

/// A pet bowl on a stand.
pub const PET_BOWL: Kind = Kind {
    name: "pet_bowl",
    family: "pets",
    phrases: &["pet bowl", "cat bowl", "food bowl", "water bowl", "feeding bowl", "cat feeder"],
    places: FLOOR_OR_ON,
    typical_m: [0.16, 0.07, 0.16],
    object_type: "PetBowl",
    thor: Thor::Pickup,
    mass_kg: 0.4,
    generator: pet_bowl,
};

fn pet_bowl(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let bowl = ctx.main(Material::Ceramic);
    let food = ctx.fixed(Material::Litter, [0.52, 0.33, 0.2]);
    let mut b = Build::default();
    let r = w.min(d) / 2.0;
    b.add(
        "bowl",
        bowl,
        Shape::Round {
            axis: Axis::Y,
            from: [0.0, 0.0, 0.0],
            length: h,
            r0: r * 0.75,
            r1: r,
            inner: 0.82,
            segments: 20,
        },
    );
    b.add("base", bowl, Shape::cylinder(Axis::Y, [0.0, 0.0, 0.0], h * 0.15, r * 0.75));
    b.add("food", food, Shape::cylinder(Axis::Y, [0.0, h * 0.15, 0.0], h * 0.45, r * 0.7));
    b
}
