//! Electronics: a projector, a speaker, a game console, a conference phone.
//!
//! Typical sizes: a projector 30 × 24 cm and 10 cm high; a bookshelf speaker 20 × 22 cm and
//! 32 cm high; a game console 30 × 22 cm and 6 cm high; a conference phone 28 cm across.

use super::finish::Material;
use super::mesh::{Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR_OR_ON, ON};

/// A projector: a body on feet, a lens at the front, vents and a button strip.
pub const PROJECTOR: Kind = Kind {
    name: "projector",
    family: "tech",
    phrases: &["projector", "video projector", "digital projector", "beamer", "lcd projector"],
    places: FLOOR_OR_ON,
    typical_m: [0.3, 0.1, 0.24],
    object_type: "Projector",
    thor: Thor::Pickup,
    mass_kg: 2.5,
    generator: projector,
};

fn projector(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Plastic);
    let dark = ctx.fixed(Material::Panel, [0.08, 0.08, 0.09]);
    let glass = ctx.fixed(Material::Glass, [0.35, 0.45, 0.55]);
    let mut b = Build::default();
    let feet = (h * 0.1).min(0.012);
    let lens_len = (d * 0.08).min(0.025);
    let bd = d - lens_len;
    b.add("body", body, Shape::cuboid([-w / 2.0, feet, -d / 2.0], [w, h - feet, bd]));
    for (x, z) in [
        (-w / 2.0 + 0.03, -d / 2.0 + 0.03),
        (w / 2.0 - 0.03, -d / 2.0 + 0.03),
        (0.0, -d / 2.0 + bd - 0.03),
    ] {
        b.add("foot", dark, Shape::cylinder(Axis::Y, [x, 0.0, z], feet, 0.012));
    }
    let r = ((h - feet) * 0.35).min(w * 0.15);
    let lx = -w * 0.22;
    let ly = feet + (h - feet) / 2.0;
    b.add("lens ring", dark, Shape::cylinder(Axis::Z, [lx, ly, -d / 2.0 + bd], lens_len, r));
    b.add(
        "lens",
        glass,
        Shape::cylinder(
            Axis::Z,
            [lx, ly, -d / 2.0 + bd + lens_len * 0.5],
            lens_len * 0.5,
            r * 0.75,
        ),
    );
    for i in 0..5 {
        let x = w * 0.1 + i as f64 * 0.015;
        b.add(
            "vent",
            dark,
            Shape::Cuboid {
                min: [x, feet + 0.015, -d / 2.0 + bd - 0.001],
                max: [x + 0.008, h - 0.02, -d / 2.0 + bd + 0.001],
            },
        );
    }
    b.add(
        "buttons",
        dark,
        Shape::Cuboid { min: [w * 0.05, h - 0.001, -0.03], max: [w * 0.4, h, 0.03] },
    );
    b
}

/// A speaker: a cabinet with a woofer, a tweeter and a port; floor-standing when tall.
pub const SPEAKER: Kind = Kind {
    name: "speaker",
    family: "tech",
    phrases: &[
        "speaker",
        "bookshelf speaker",
        "floor speaker",
        "loudspeaker",
        "bluetooth speaker",
        "smart speaker",
        "stereo speaker",
        "tower speaker",
    ],
    places: FLOOR_OR_ON,
    typical_m: [0.2, 0.32, 0.22],
    object_type: "Speaker",
    thor: Thor::Pickup,
    mass_kg: 5.0,
    generator: speaker,
};

fn speaker(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let cabinet = ctx.main(Material::Wood);
    let cone = ctx.fixed(Material::Panel, [0.07, 0.07, 0.08]);
    let rim = ctx.fixed(Material::Metal, [0.55, 0.56, 0.58]);
    let mut b = Build::default();
    let face = (d * 0.05).min(0.01);
    b.add("cabinet", cabinet, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, h, d - face]));
    let z = d / 2.0 - face;
    let rw = (w * 0.38).min(h * 0.22);
    let drivers = if h > 2.2 * w { 2 } else { 1 };
    ctx.note("woofers", drivers);
    for i in 0..drivers {
        let y = h * 0.35 - i as f64 * h * 0.2;
        let y = y.max(rw + 0.01);
        b.add("woofer rim", rim, Shape::tube(Axis::Z, [0.0, y, z], face, rw, 0.85));
        b.add(
            "woofer",
            cone,
            Shape::frustum(Axis::Z, [0.0, y, z], face * 0.9, rw * 0.85, rw * 0.3),
        );
    }
    let tr = rw * 0.35;
    b.add("tweeter", rim, Shape::tube(Axis::Z, [0.0, h * 0.78, z], face, tr, 0.6));
    b.add("tweeter", cone, Shape::cylinder(Axis::Z, [0.0, h * 0.78, z], face * 0.8, tr * 0.6));
    b.add(
        "port",
        cone,
        Shape::cylinder(Axis::Z, [0.0, h * 0.08 + 0.02, z], face * 0.5, (w * 0.08).min(0.02)),
    );
    b
}

/// A game console: a body with a disc slot, a power button and a light strip, on feet.
pub const GAME_CONSOLE: Kind = Kind {
    name: "game_console",
    family: "tech",
    phrases: &[
        "game console",
        "gaming console",
        "video game console",
        "games console",
        "playstation",
        "xbox",
        "nintendo switch",
    ],
    places: ON,
    typical_m: [0.3, 0.06, 0.22],
    object_type: "GameConsole",
    thor: Thor::Pickup,
    mass_kg: 3.0,
    generator: game_console,
};

fn game_console(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Plastic);
    let dark = ctx.fixed(Material::Panel, [0.06, 0.06, 0.07]);
    let light = ctx.fixed(Material::Plastic, [0.3, 0.6, 0.95]);
    let mut b = Build::default();
    let feet = (h * 0.1).min(0.006);
    b.add("body", body, Shape::cuboid([-w / 2.0, feet, -d / 2.0], [w, h - feet, d - 0.002]));
    b.add(
        "front",
        dark,
        Shape::Cuboid { min: [-w / 2.0, feet, d / 2.0 - 0.004], max: [w / 2.0, h * 0.45, d / 2.0] },
    );
    b.add(
        "slot",
        dark,
        Shape::Cuboid {
            min: [-w * 0.3, h * 0.6, d / 2.0 - 0.003],
            max: [w * 0.1, h * 0.68, d / 2.0],
        },
    );
    b.add(
        "light",
        light,
        Shape::Cuboid {
            min: [-w / 2.0, h - 0.004, d / 2.0 - 0.02],
            max: [w / 2.0, h, d / 2.0 - 0.012],
        },
    );
    b.add(
        "button",
        light,
        Shape::cylinder(Axis::Z, [w * 0.35, h * 0.6, d / 2.0 - 0.003], 0.003, 0.006),
    );
    for x in [-w / 2.0 + 0.02, w / 2.0 - 0.02] {
        for z in [-d / 2.0 + 0.02, d / 2.0 - 0.02] {
            b.add("foot", dark, Shape::cylinder(Axis::Y, [x, 0.0, z], feet, 0.008));
        }
    }
    b
}

/// A conference phone (a speakerphone): a round base, a speaker grille, a display and three
/// microphones.
pub const CONFERENCE_PHONE: Kind = Kind {
    name: "conference_phone",
    family: "tech",
    phrases: &[
        "conference phone",
        "speakerphone",
        "speaker phone",
        "conference speaker",
        "polycom",
        "conference speakerphone",
    ],
    places: ON,
    typical_m: [0.28, 0.06, 0.28],
    object_type: "ConferencePhone",
    thor: Thor::Pickup,
    mass_kg: 1.0,
    generator: conference_phone,
};

fn conference_phone(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Plastic);
    let grille = ctx.fixed(Material::Panel, [0.12, 0.12, 0.13]);
    let screen = ctx.fixed(Material::Glass, [0.2, 0.3, 0.35]);
    let mut b = Build::default();
    let r = w.min(d) / 2.0;
    b.add("base", body, Shape::frustum(Axis::Y, [0.0, 0.0, 0.0], h * 0.7, r, r * 0.8));
    b.add("grille", grille, Shape::cylinder(Axis::Y, [0.0, h * 0.7, 0.0], h * 0.3, r * 0.45));
    b.add(
        "display",
        screen,
        Shape::Cuboid {
            min: [-r * 0.3, h * 0.7 - 0.002, r * 0.5],
            max: [r * 0.3, h * 0.7 + 0.003, r * 0.72],
        },
    );
    for k in 0..3 {
        let a = std::f64::consts::TAU * f64::from(k) / 3.0 + 0.5;
        b.add(
            "microphone",
            grille,
            Shape::cylinder(
                Axis::Y,
                [a.sin() * r * 0.72, h * 0.5, a.cos() * r * 0.72],
                h * 0.25,
                0.008,
            ),
        );
    }
    b
}
