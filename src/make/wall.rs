//! Things on walls: shelves, cabinets, mirrors, boards, a projector screen, a clock, picture
//! frames and hooks. Their back is at `-z` (against the wall), their front at `+z`.
//!
//! Typical sizes: a wall shelf 80 × 22 cm, 5 cm thick; a wall cabinet 80 × 60 × 30 cm; a
//! mirror 60 × 80 cm (a full-length one 50 × 150 cm); a whiteboard 180 × 120 cm; a pin board
//! 90 × 60 cm; a pull-down screen 200 × 160 cm; a wall clock 35 cm across; a picture frame
//! 50 × 40 cm; a rail of hooks 50 cm.

use super::finish::Material;
use super::mesh::{frame, Axis, Build, Shape};
use super::{Ctx, Kind, Thor, FLOOR_OR_WALL, WALL};

/// A shelf on the wall: a board, on brackets unless it is a floating shelf (then a hidden
/// rail) or too thin for them.
pub const WALL_SHELF: Kind = Kind {
    name: "wall_shelf",
    family: "wall",
    phrases: &[
        "wall shelf",
        "floating shelf",
        "shelf",
        "wall rack",
        "ledge",
        "picture ledge",
        "spice rack",
    ],
    places: WALL,
    typical_m: [0.8, 0.05, 0.22],
    object_type: "Shelf",
    thor: Thor::StaticReceptacle,
    mass_kg: 3.0,
    generator: wall_shelf,
};

fn wall_shelf(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let wood = ctx.main(Material::Wood);
    let metal = ctx.fixed(Material::Metal, [0.12, 0.12, 0.13]);
    let mut b = Build::default();
    let floating = ctx.look.has("floating") || h < 0.09;
    ctx.note("brackets", !floating);
    let board = if floating { h * 0.8 } else { (0.025_f64).min(h / 3.0) };
    b.add("board", wood, Shape::cuboid([-w / 2.0, h - board, -d / 2.0], [w, board, d]));
    if floating {
        // The rail it hangs on, behind and under the board.
        b.add(
            "rail",
            metal,
            Shape::cuboid([-w / 2.0 + 0.05, 0.0, -d / 2.0], [w - 0.1, h - board, 0.012]),
        );
    } else {
        for x in [-w / 2.0 + w * 0.15, w / 2.0 - w * 0.15] {
            b.add(
                "bracket",
                metal,
                Shape::block(x, 0.0, -d / 2.0 + 0.008, [0.02, h - board, 0.016]),
            );
            b.add(
                "bracket",
                metal,
                Shape::block(x, h - board - 0.012, -d / 2.0 + d * 0.4, [0.02, 0.012, d * 0.8]),
            );
        }
    }
    b
}

/// A wall cabinet: a carcass with an inner shelf and two doors with handles (a mirrored door
/// for a bathroom or medicine cabinet).
pub const WALL_CABINET: Kind = Kind {
    name: "wall_cabinet",
    family: "wall",
    phrases: &[
        "wall cabinet",
        "bathroom cabinet",
        "medicine cabinet",
        "wall cupboard",
        "hanging cabinet",
        "upper cabinet",
        "wall mounted cabinet",
        "mirror cabinet",
        "bathroom wall cabinet",
    ],
    places: WALL,
    typical_m: [0.8, 0.6, 0.3],
    object_type: "Cabinet",
    thor: Thor::StaticReceptacle,
    mass_kg: 15.0,
    generator: wall_cabinet,
};

pub(super) fn wall_cabinet(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let body = ctx.main(Material::Painted);
    let metal = ctx.fixed(Material::Metal, [0.7, 0.71, 0.72]);
    let mirrored = ctx.look.any(&["mirror", "mirrored", "medicine", "bathroom"]);
    ctx.note("mirrored doors", mirrored);
    let door_swatch = if mirrored { ctx.fixed(Material::Mirror, [0.86, 0.89, 0.92]) } else { body };
    let mut b = Build::default();
    let t = 0.018_f64.min(w / 10.0);
    let door_t = 0.018_f64.min(d / 5.0);
    let back = -d / 2.0;
    let front = d / 2.0 - door_t;
    b.add(
        "carcass",
        body,
        Shape::Cuboid { min: [-w / 2.0, 0.0, back], max: [-w / 2.0 + t, h, front] },
    );
    b.add(
        "carcass",
        body,
        Shape::Cuboid { min: [w / 2.0 - t, 0.0, back], max: [w / 2.0, h, front] },
    );
    b.add(
        "carcass",
        body,
        Shape::Cuboid { min: [-w / 2.0 + t, 0.0, back], max: [w / 2.0 - t, t, front] },
    );
    b.add(
        "carcass",
        body,
        Shape::Cuboid { min: [-w / 2.0 + t, h - t, back], max: [w / 2.0 - t, h, front] },
    );
    b.add(
        "carcass",
        body,
        Shape::Cuboid { min: [-w / 2.0 + t, t, back], max: [w / 2.0 - t, h - t, back + 0.008] },
    );
    b.add(
        "shelf",
        body,
        Shape::Cuboid {
            min: [-w / 2.0 + t, h / 2.0 - t / 2.0, back],
            max: [w / 2.0 - t, h / 2.0 + t / 2.0, front],
        },
    );
    let doors = if w > 0.5 { 2 } else { 1 };
    ctx.note("doors", doors);
    let gap = 0.003;
    let dw = w / doors as f64;
    for i in 0..doors {
        let x0 = -w / 2.0 + i as f64 * dw + gap;
        let x1 = x0 + dw - 2.0 * gap;
        b.add(
            "door",
            door_swatch,
            Shape::Cuboid { min: [x0, gap, front], max: [x1, h - gap, d / 2.0 - 0.01] },
        );
        if mirrored {
            // A thin painted edge round the mirror.
            b.add(
                "door edge",
                body,
                Shape::Cuboid { min: [x0, gap, d / 2.0 - 0.01], max: [x1, gap + 0.01, d / 2.0] },
            );
        }
        // The handle by the meeting edge (or the right edge of a single door).
        let hx = if doors == 2 && i == 0 {
            x1 - 0.03
        } else if doors == 2 {
            x0 + 0.03
        } else {
            x1 - 0.03
        };
        let hy = if h > 0.3 { h * 0.2 } else { h / 2.0 };
        b.add(
            "handle",
            metal,
            Shape::Cuboid {
                min: [hx - 0.006, hy - 0.05, d / 2.0 - 0.01],
                max: [hx + 0.006, hy + 0.05, d / 2.0],
            },
        );
    }
    b
}

/// A mirror: a frame and a pane, round, oval, rectangular or full length (standing when
/// placed on the floor: with a stand behind it).
pub const MIRROR: Kind = Kind {
    name: "mirror",
    family: "wall",
    phrases: &[
        "mirror",
        "wall mirror",
        "round mirror",
        "full length mirror",
        "floor mirror",
        "standing mirror",
        "vanity mirror",
        "bathroom mirror",
        "oval mirror",
        "dressing mirror",
    ],
    places: FLOOR_OR_WALL,
    typical_m: [0.6, 0.8, 0.03],
    object_type: "Mirror",
    thor: Thor::Static,
    mass_kg: 6.0,
    generator: mirror,
};

fn mirror(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let framing = ctx.main(Material::Wood);
    let pane = ctx.fixed(Material::Mirror, [0.86, 0.89, 0.92]);
    let mut b = Build::default();
    let round = ctx.look.any(&["round", "circular", "circle", "oval"]);
    let frameless = ctx.look.any(&["frameless", "unframed"]);
    let standing = h > 1.2 && d > 0.1;
    ctx.note("shape", if round { "round" } else { "rectangular" });
    ctx.note("standing", standing);
    let depth = if standing { 0.03_f64.min(d) } else { d };
    // The pane's plane: at the back unless it stands (then in front of its stand).
    let z0 = if standing { d / 2.0 - depth } else { -d / 2.0 };
    let bar = if frameless { 0.008 } else { (w.min(h) * 0.06).clamp(0.015, 0.06) };
    if round {
        let r = w.min(h) / 2.0;
        let cy = h - r;
        b.add(
            "frame",
            framing,
            Shape::Round {
                axis: Axis::Z,
                from: [0.0, cy, z0],
                length: depth,
                r0: r,
                r1: r,
                inner: 1.0 - bar / r,
                segments: 40,
            },
        );
        b.add(
            "pane",
            pane,
            Shape::Round {
                axis: Axis::Z,
                from: [0.0, cy, z0],
                length: depth * 0.6,
                r0: r - bar,
                r1: r - bar,
                inner: 0.0,
                segments: 40,
            },
        );
        // An oval or a narrow one: the frame fills the box with a second disc above.
        if h - 2.0 * r > 0.05 {
            let r2 = r;
            b.add(
                "frame",
                framing,
                Shape::Round {
                    axis: Axis::Z,
                    from: [0.0, r2, z0],
                    length: depth,
                    r0: r2,
                    r1: r2,
                    inner: 1.0 - bar / r2,
                    segments: 40,
                },
            );
            b.add(
                "pane",
                pane,
                Shape::Cuboid { min: [-r + bar, r2, z0], max: [r - bar, cy, z0 + depth * 0.6] },
            );
            b.add(
                "pane",
                pane,
                Shape::Round {
                    axis: Axis::Z,
                    from: [0.0, r2, z0],
                    length: depth * 0.6,
                    r0: r2 - bar,
                    r1: r2 - bar,
                    inner: 0.0,
                    segments: 40,
                },
            );
        }
    } else {
        frame(&mut b, "frame", framing, [-w / 2.0, w / 2.0], [0.0, h], [z0, z0 + depth], bar);
        b.add(
            "pane",
            pane,
            Shape::Cuboid {
                min: [-w / 2.0 + bar, bar, z0],
                max: [w / 2.0 - bar, h - bar, z0 + depth * 0.6],
            },
        );
    }
    if standing {
        // A stand leaning behind it.
        let leg = 0.025;
        for x in [-w / 2.0 + 0.06, w / 2.0 - 0.06] {
            b.add(
                "stand",
                framing,
                Shape::block(x, 0.0, -d / 2.0 + leg / 2.0, [leg, h * 0.75, leg]),
            );
        }
        b.add(
            "stand",
            framing,
            Shape::Cuboid {
                min: [-w / 2.0 + 0.06, h * 0.5, -d / 2.0],
                max: [w / 2.0 - 0.06, h * 0.5 + leg, d / 2.0 - depth],
            },
        );
    }
    b
}

/// A board on the wall with a frame and a tray: the shape shared by whiteboards, blackboards
/// and pin boards.
fn board(ctx: &mut Ctx<'_>, surface: Material, framing: Material, tray: bool) -> Build {
    let (w, h, d) = ctx.whd();
    let face = ctx.fixed(surface, super::finish::Look::of("").swatch(surface, false).rgb);
    let rim = ctx.main(framing);
    let mut b = Build::default();
    let bar = (w.min(h) * 0.025).clamp(0.012, 0.04);
    let tray_d = if tray { (d * 0.8).min(0.06).max(d - 0.02) } else { 0.0 };
    let board_d = if tray { (d - tray_d).clamp(0.01, 0.025) } else { d };
    let z0 = -d / 2.0;
    let tray_h = if tray { (h * 0.04).clamp(0.02, 0.04) } else { 0.0 };
    let y0 = tray_h;
    b.add(
        "board",
        face,
        Shape::Cuboid {
            min: [-w / 2.0 + bar, y0 + bar, z0],
            max: [w / 2.0 - bar, h - bar, z0 + board_d * 0.8],
        },
    );
    frame(&mut b, "frame", rim, [-w / 2.0, w / 2.0], [y0, h], [z0, z0 + board_d], bar);
    if tray {
        b.add(
            "tray",
            rim,
            Shape::Cuboid { min: [-w * 0.35, 0.0, z0], max: [w * 0.35, tray_h * 0.4, d / 2.0] },
        );
        b.add(
            "tray",
            rim,
            Shape::Cuboid {
                min: [-w * 0.35, 0.0, d / 2.0 - 0.006],
                max: [w * 0.35, tray_h, d / 2.0],
            },
        );
    }
    b
}

/// A whiteboard: an enamel board in an aluminium frame with a pen tray and markers.
pub const WHITEBOARD: Kind = Kind {
    name: "whiteboard",
    family: "wall",
    phrases: &["whiteboard", "white board", "dry erase board", "marker board", "wall whiteboard"],
    places: WALL,
    typical_m: [1.8, 1.2, 0.07],
    object_type: "Whiteboard",
    thor: Thor::Static,
    mass_kg: 14.0,
    generator: whiteboard,
};

fn whiteboard(ctx: &mut Ctx<'_>) -> Build {
    let mut b = board(ctx, Material::Whiteboard, Material::Metal, true);
    let (w, h, d) = ctx.whd();
    let tray_h = (h * 0.04).clamp(0.02, 0.04);
    let colours = [[0.1, 0.1, 0.12], [0.75, 0.1, 0.1], [0.1, 0.25, 0.7]];
    for (i, c) in colours.iter().enumerate() {
        let marker = ctx.fixed(Material::Plastic, *c);
        let x = -w * 0.2 + i as f64 * 0.05;
        b.add(
            "marker",
            marker,
            Shape::cylinder(Axis::X, [x, tray_h * 0.4 + 0.008, d / 2.0 - 0.025], 0.13, 0.008),
        );
    }
    b
}

/// A blackboard: slate in a wooden frame with a chalk tray.
pub const BLACKBOARD: Kind = Kind {
    name: "blackboard",
    family: "wall",
    phrases: &["blackboard", "chalkboard", "chalk board", "black board", "green board"],
    places: WALL,
    typical_m: [1.8, 1.2, 0.07],
    object_type: "Blackboard",
    thor: Thor::Static,
    mass_kg: 20.0,
    generator: blackboard,
};

fn blackboard(ctx: &mut Ctx<'_>) -> Build {
    let mut b = board(ctx, Material::Slate, Material::Wood, true);
    let (w, h, d) = ctx.whd();
    let tray_h = (h * 0.04).clamp(0.02, 0.04);
    let chalk = ctx.fixed(Material::Paper, [0.97, 0.97, 0.95]);
    for i in 0..3 {
        let x = w * 0.1 + i as f64 * 0.05;
        b.add(
            "chalk",
            chalk,
            Shape::cylinder(Axis::X, [x, tray_h * 0.4 + 0.006, d / 2.0 - 0.025], 0.08, 0.006),
        );
    }
    b
}

/// A pin board: cork in a wooden frame, with a few notes pinned on it.
pub const PIN_BOARD: Kind = Kind {
    name: "pin_board",
    family: "wall",
    phrases: &[
        "pin board",
        "pinboard",
        "cork board",
        "corkboard",
        "bulletin board",
        "notice board",
        "memo board",
    ],
    places: WALL,
    typical_m: [0.9, 0.6, 0.03],
    object_type: "PinBoard",
    thor: Thor::Static,
    mass_kg: 3.0,
    generator: pin_board,
};

fn pin_board(ctx: &mut Ctx<'_>) -> Build {
    let mut b = board(ctx, Material::Cork, Material::Wood, false);
    let (w, h, d) = ctx.whd();
    let notes = [[0.98, 0.94, 0.55], [0.96, 0.96, 0.94], [0.7, 0.86, 0.95], [0.98, 0.75, 0.8]];
    for (i, c) in notes.iter().enumerate() {
        let paper = ctx.fixed(Material::Paper, *c);
        let (fx, fy) = ([-0.3, 0.05, 0.25, -0.1][i], [0.6, 0.65, 0.35, 0.3][i]);
        let (nw, nh) = ((w * 0.16).min(0.15), (h * 0.2).min(0.15));
        b.add(
            "note",
            paper,
            Shape::Cuboid {
                min: [fx * w - nw / 2.0, fy * h - nh / 2.0, -d / 2.0 + 0.02],
                max: [fx * w + nw / 2.0, fy * h + nh / 2.0, -d / 2.0 + 0.022],
            },
        );
    }
    b
}

/// A pull-down projector screen: the case at the top, the matte screen with its black border,
/// the weighted bottom bar and its pull handle.
pub const PROJECTOR_SCREEN: Kind = Kind {
    name: "projector_screen",
    family: "wall",
    phrases: &[
        "projector screen",
        "projection screen",
        "pull down screen",
        "presentation screen",
        "screen for projector",
    ],
    places: WALL,
    typical_m: [2.0, 1.6, 0.09],
    object_type: "ProjectorScreen",
    thor: Thor::Static,
    mass_kg: 9.0,
    generator: projector_screen,
};

fn projector_screen(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let case = ctx.main(Material::Painted);
    let cloth = ctx.fixed(Material::Screen, [0.95, 0.95, 0.95]);
    let border = ctx.fixed(Material::Panel, [0.06, 0.06, 0.06]);
    let mut b = Build::default();
    let r = (d / 2.0).min(0.05);
    b.add("case", case, Shape::cylinder(Axis::X, [-w / 2.0, h - r, -d / 2.0 + r], w, r));
    let sw = w - 0.08;
    let z = -d / 2.0 + r;
    b.add(
        "border",
        border,
        Shape::Cuboid {
            min: [-sw / 2.0, 0.03, z - 0.003],
            max: [sw / 2.0, h - 2.0 * r, z + 0.002],
        },
    );
    b.add(
        "screen",
        cloth,
        Shape::Cuboid {
            min: [-sw / 2.0 + 0.04, 0.12, z + 0.002],
            max: [sw / 2.0 - 0.04, h - 2.0 * r - 0.08, z + 0.004],
        },
    );
    b.add("bar", case, Shape::cylinder(Axis::X, [-sw / 2.0, 0.03, z], sw, 0.012));
    b.add("handle", border, Shape::block(0.0, 0.0, z, [0.06, 0.03, 0.012]));
    b
}

/// A wall clock: a rim, a face with hour marks, hands and a centre cap; square when asked.
pub const WALL_CLOCK: Kind = Kind {
    name: "wall_clock",
    family: "wall",
    phrases: &[
        "wall clock",
        "clock",
        "round clock",
        "kitchen clock",
        "office clock",
        "analog clock",
    ],
    places: WALL,
    typical_m: [0.35, 0.35, 0.05],
    object_type: "WallClock",
    thor: Thor::Static,
    mass_kg: 1.0,
    generator: wall_clock,
};

fn wall_clock(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let rim = ctx.main(Material::Plastic);
    let face = ctx.fixed(Material::Paper, [0.97, 0.96, 0.93]);
    let ink = ctx.fixed(Material::Panel, [0.08, 0.08, 0.09]);
    let mut b = Build::default();
    let r = w.min(h) / 2.0;
    let (cy, z0) = (h / 2.0, -d / 2.0);
    let square = ctx.look.any(&["square", "rectangular"]);
    ctx.note("shape", if square { "square" } else { "round" });
    if square {
        frame(&mut b, "rim", rim, [-w / 2.0, w / 2.0], [0.0, h], [z0, d / 2.0], r * 0.1);
        b.add(
            "face",
            face,
            Shape::Cuboid {
                min: [-w / 2.0 + r * 0.1, r * 0.1, z0],
                max: [w / 2.0 - r * 0.1, h - r * 0.1, z0 + d * 0.5],
            },
        );
    } else {
        b.add(
            "rim",
            rim,
            Shape::Round {
                axis: Axis::Z,
                from: [0.0, cy, z0],
                length: d,
                r0: r,
                r1: r,
                inner: 0.88,
                segments: 36,
            },
        );
        b.add(
            "face",
            face,
            Shape::Round {
                axis: Axis::Z,
                from: [0.0, cy, z0],
                length: d * 0.5,
                r0: r * 0.9,
                r1: r * 0.9,
                inner: 0.0,
                segments: 36,
            },
        );
    }
    let zf = z0 + d * 0.5;
    for k in 0..12 {
        let a = std::f64::consts::TAU * f64::from(k) / 12.0;
        let (s, c) = (a.sin(), a.cos());
        let m = if k % 3 == 0 { 0.035 } else { 0.018 };
        let rr = r * 0.78;
        b.add(
            "marks",
            ink,
            Shape::block(
                s * rr,
                cy + c * rr - m * r / 0.35 / 2.0,
                zf + 0.001,
                [0.008 * r / 0.175, m * r / 0.175, 0.002],
            ),
        );
    }
    // Hands at ten past ten, as clocks are shown.
    b.add(
        "hands",
        ink,
        Shape::Cuboid { min: [-0.006, cy, zf + 0.003], max: [0.006, cy + r * 0.6, zf + 0.005] },
    );
    b.add(
        "hands",
        ink,
        Shape::Cuboid {
            min: [-r * 0.45, cy - 0.006, zf + 0.005],
            max: [0.0, cy + 0.006, zf + 0.007],
        },
    );
    b.add("cap", rim, Shape::cylinder(Axis::Z, [0.0, cy, zf], (d / 2.0 - zf).max(0.008), r * 0.05));
    b
}

/// A picture frame on the wall: the frame, a white mat and the picture.
pub const PICTURE_FRAME: Kind = Kind {
    name: "picture_frame",
    family: "wall",
    phrases: &[
        "picture frame",
        "photo frame",
        "framed photo",
        "framed print",
        "framed picture",
        "frame",
        "poster frame",
        "family photo",
    ],
    places: WALL,
    typical_m: [0.5, 0.4, 0.03],
    object_type: "PictureFrame",
    thor: Thor::Static,
    mass_kg: 1.2,
    generator: picture_frame,
};

fn picture_frame(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let framing = ctx.main(Material::Wood);
    let mut b = Build::default();
    let z0 = -d / 2.0;
    let bar = (w.min(h) * 0.07).clamp(0.01, 0.05);
    frame(&mut b, "frame", framing, [-w / 2.0, w / 2.0], [0.0, h], [z0, d / 2.0], bar);
    picture(ctx, &mut b, [-w / 2.0 + bar, w / 2.0 - bar], [bar, h - bar], z0 + d * 0.4);
    b
}

/// A mat and a picture inside a frame's opening, facing `+z` at depth `z`: the picture is a
/// landscape in four bands whose colours follow the description's hash (a photo differs from
/// frame to frame but the same frame is always the same).
pub(super) fn picture(
    ctx: &mut Ctx<'_>,
    b: &mut Build,
    [x0, x1]: [f64; 2],
    [y0, y1]: [f64; 2],
    z: f64,
) {
    let mat = ctx.fixed(Material::Paper, [0.97, 0.96, 0.93]);
    b.add("mat", mat, Shape::Cuboid { min: [x0, y0, z - 0.004], max: [x1, y1, z] });
    let inset = ((x1 - x0).min(y1 - y0) * 0.12).max(0.005);
    let (px0, px1, py0, py1) = (x0 + inset, x1 - inset, y0 + inset, y1 - inset);
    let hash =
        ctx.look.words.iter().fold(0u64, |h, w| {
            w.bytes().fold(h, |h, c| h.wrapping_mul(31).wrapping_add(u64::from(c)))
        });
    let scenes: [[[f64; 3]; 3]; 4] = [
        [[0.55, 0.72, 0.88], [0.35, 0.55, 0.3], [0.25, 0.4, 0.22]],
        [[0.95, 0.7, 0.45], [0.35, 0.42, 0.6], [0.15, 0.2, 0.3]],
        [[0.8, 0.85, 0.9], [0.6, 0.62, 0.66], [0.3, 0.32, 0.35]],
        [[0.6, 0.8, 0.95], [0.2, 0.45, 0.6], [0.85, 0.78, 0.6]],
    ];
    let scene = scenes[(hash % 4) as usize];
    ctx.note("picture", ["meadow", "sunset", "mountains", "seaside"][(hash % 4) as usize]);
    let bands = [0.55, 0.25, 0.2];
    let mut top = py1;
    for (band, rgb) in bands.iter().zip(scene) {
        let s = ctx.fixed(Material::Paper, rgb);
        let bottom = top - band * (py1 - py0);
        b.add("picture", s, Shape::Cuboid { min: [px0, bottom, z], max: [px1, top, z + 0.002] });
        top = bottom;
    }
}

/// A rail of hooks for coats or towels: a board with three to six hooks.
pub const COAT_HOOKS: Kind = Kind {
    name: "coat_hooks",
    family: "wall",
    phrases: &[
        "coat hook",
        "coat rack",
        "wall hook",
        "hook",
        "hook rail",
        "key hook",
        "hat hook",
        "entryway hook",
    ],
    places: WALL,
    typical_m: [0.5, 0.12, 0.07],
    object_type: "CoatHooks",
    thor: Thor::Static,
    mass_kg: 1.5,
    generator: hooks,
};

/// Towel hooks: hooks that towels hang from (AI2-THOR's towel holder: things on them hang).
pub const TOWEL_HOOKS: Kind = Kind {
    name: "towel_hooks",
    family: "wall",
    phrases: &["towel hook", "robe hook", "bathroom hook", "towel hooks"],
    places: WALL,
    typical_m: [0.4, 0.1, 0.06],
    object_type: "TowelHolder",
    thor: Thor::StaticReceptacle,
    mass_kg: 1.0,
    generator: hooks,
};

fn hooks(ctx: &mut Ctx<'_>) -> Build {
    let (w, h, d) = ctx.whd();
    let board = ctx.main(Material::Wood);
    let metal = ctx.accent(Material::Metal);
    let mut b = Build::default();
    let t = (0.018_f64).min(d / 3.0);
    b.add("board", board, Shape::cuboid([-w / 2.0, 0.0, -d / 2.0], [w, h, t]));
    let n = ((w / 0.12).floor() as usize).clamp(2, 8);
    ctx.note("hooks", n);
    for i in 0..n {
        let x = -w / 2.0 + w * (i as f64 + 0.5) / n as f64;
        let y = h * 0.35;
        b.add("hook", metal, Shape::cylinder(Axis::Z, [x, y, -d / 2.0 + t], d - t - 0.01, 0.006));
        b.add("hook", metal, Shape::cylinder(Axis::Y, [x, y, d / 2.0 - 0.012], h * 0.3, 0.006));
    }
    b
}
