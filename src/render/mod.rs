//! The SVG plan: a top-down drawing of a built scene.
//!
//! [`render_svg`] draws a [`Drawing`]: rooms with their labels, walls, doors with their swing,
//! windows, every object's footprint with its name and a mark on its front, the keep-out zones
//! in front of doors, and violated constraints as red lines between the objects involved.
//! [`drawing`] makes the drawing from a finished build (its floor plan and layout);
//! [`render_svg`] itself knows nothing of the stages. Neither does I/O.
//!
//! **Invariant:** the output depends only on the drawing: numbers are printed with two decimals,
//! elements in the drawing's order.

mod scene;

pub use scene::drawing;

use std::fmt::Write as _;
use svg::node::element::{Circle, Group, Line, Path, Polygon, Rectangle, Text, Title};
use svg::node::Text as TextNode;
use svg::Document;

/// Pixels per metre.
const SCALE: f64 = 100.0;
/// Margin around the plan, metres.
const MARGIN_M: f64 = 0.8;

/// What the plan shows.
#[derive(Clone, Debug, Default)]
pub struct Drawing {
    /// The title, e.g. the scene's request.
    pub title: String,
    /// Room floors.
    pub rooms: Vec<DrawRoom>,
    /// Wall segments (one per wall, interior and exterior copies merged by the caller).
    pub walls: Vec<DrawSegment>,
    /// Doors.
    pub doors: Vec<DrawDoor>,
    /// Windows.
    pub windows: Vec<DrawSegment>,
    /// Keep-out zones in front of doors and open connections.
    pub keep_out: Vec<Vec<[f64; 2]>>,
    /// Placed objects.
    pub objects: Vec<DrawObject>,
    /// Violated constraints.
    pub violations: Vec<DrawViolation>,
    /// Objects that could not be placed, with the reason, listed under the plan.
    pub unplaced: Vec<String>,
}

/// A room's floor.
#[derive(Clone, Debug)]
pub struct DrawRoom {
    /// The label shown at its centre.
    pub label: String,
    /// The outline, metres, `(x, z)`.
    pub polygon: Vec<[f64; 2]>,
}

/// A straight piece of wall or window, metres.
#[derive(Clone, Copy, Debug)]
pub struct DrawSegment {
    /// One end.
    pub a: [f64; 2],
    /// The other end.
    pub b: [f64; 2],
}

/// A door: its opening on the wall and the side its leaf swings into.
#[derive(Clone, Debug)]
pub struct DrawDoor {
    /// The opening, from hinge side to the other side.
    pub opening: DrawSegment,
    /// A unit vector, perpendicular to the wall, towards the side the leaf swings into
    /// (`None` for frames and open connections, which have no leaf).
    pub swing: Option<[f64; 2]>,
    /// A short label (e.g. `doorway`).
    pub label: String,
}

/// Where an object sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObjectLevel {
    /// On the floor.
    Floor,
    /// On a wall.
    Wall,
    /// On top of another object.
    Small,
    /// At the ceiling.
    Ceiling,
}

/// An object's footprint.
#[derive(Clone, Debug)]
pub struct DrawObject {
    /// Its name, e.g. `sofa-0`.
    pub name: String,
    /// Centre of the footprint, metres.
    pub center: [f64; 2],
    /// Width (x at facing 0) and depth, metres.
    pub size: [f64; 2],
    /// Facing, degrees (0 = +z, 90 = +x).
    pub facing_deg: f64,
    /// Floor, wall, small or ceiling.
    pub level: ObjectLevel,
}

/// A constraint that the layout does not keep.
#[derive(Clone, Debug)]
pub struct DrawViolation {
    /// The constrained object's centre.
    pub from: [f64; 2],
    /// The target's centre.
    pub to: [f64; 2],
    /// What is violated, e.g. `near sofa-0 (1.9 m)`.
    pub text: String,
}

fn n(v: f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    let mut s = format!("{r:.2}");
    if s == "-0.00" {
        s = "0.00".to_string();
    }
    s
}

/// A line between two drawing points.
fn line(a: (f64, f64), b: (f64, f64)) -> Line {
    Line::new().set("x1", n(a.0)).set("y1", n(a.1)).set("x2", n(b.0)).set("y2", n(b.1))
}

/// Converts a plan point (metres, z north) to drawing coordinates (pixels, y down).
fn px(p: [f64; 2], min: [f64; 2], max_z: f64) -> (f64, f64) {
    ((p[0] - min[0] + MARGIN_M) * SCALE, (max_z - p[1] + MARGIN_M) * SCALE)
}

fn points(poly: &[[f64; 2]], min: [f64; 2], max_z: f64) -> String {
    let mut out = String::new();
    for (i, p) in poly.iter().enumerate() {
        let (x, y) = px(*p, min, max_z);
        if i > 0 {
            out.push(' ');
        }
        let _ = write!(out, "{},{}", n(x), n(y));
    }
    out
}

/// Rotates the offset `(dx, dz)` by a facing angle (clockwise seen from above, as AI2-THOR).
fn rotate(d: [f64; 2], facing_deg: f64) -> [f64; 2] {
    let quarter = (facing_deg / 90.0).round();
    if (facing_deg - quarter * 90.0).abs() < 1e-9 {
        // Multiples of 90° are exact.
        match (quarter as i64).rem_euclid(4) {
            0 => d,
            1 => [d[1], -d[0]],
            2 => [-d[0], -d[1]],
            _ => [-d[1], d[0]],
        }
    } else {
        let (s, c) = facing_deg.to_radians().sin_cos();
        [d[0] * c + d[1] * s, -d[0] * s + d[1] * c]
    }
}

/// Draws the plan as an SVG document.
pub fn render_svg(drawing: &Drawing) -> String {
    let mut xs: Vec<f64> = Vec::new();
    let mut zs: Vec<f64> = Vec::new();
    for r in &drawing.rooms {
        for p in &r.polygon {
            xs.push(p[0]);
            zs.push(p[1]);
        }
    }
    let fold = |v: &[f64], f: fn(f64, f64) -> f64, init: f64| v.iter().copied().fold(init, f);
    let (min_x, max_x) = if xs.is_empty() {
        (0.0, 1.0)
    } else {
        (fold(&xs, f64::min, f64::INFINITY), fold(&xs, f64::max, f64::NEG_INFINITY))
    };
    let (min_z, max_z) = if zs.is_empty() {
        (0.0, 1.0)
    } else {
        (fold(&zs, f64::min, f64::INFINITY), fold(&zs, f64::max, f64::NEG_INFINITY))
    };
    let min = [min_x, min_z];
    let legend_lines = drawing.unplaced.len() + drawing.violations.len();
    let width = (max_x - min_x + 2.0 * MARGIN_M) * SCALE;
    let height = (max_z - min_z + 2.0 * MARGIN_M) * SCALE + 20.0 * (legend_lines as f64 + 1.0);

    let mut doc = Document::new()
        .set("xmlns", "http://www.w3.org/2000/svg")
        .set("width", n(width))
        .set("height", n(height))
        .set("viewBox", format!("0 0 {} {}", n(width), n(height)))
        .set("font-family", "sans-serif")
        .add(Title::new(drawing.title.clone()))
        .add(Rectangle::new().set("width", "100%").set("height", "100%").set("fill", "#ffffff"));

    let mut floors = Group::new().set("id", "rooms");
    for r in &drawing.rooms {
        floors = floors.add(
            Polygon::new()
                .set("points", points(&r.polygon, min, max_z))
                .set("fill", "#f4efe6")
                .set("stroke", "#b8ad9a")
                .set("stroke-width", 1),
        );
    }
    doc = doc.add(floors);

    let mut zones = Group::new().set("id", "keep-out");
    for z in &drawing.keep_out {
        zones = zones.add(
            Polygon::new()
                .set("points", points(z, min, max_z))
                .set("fill", "#f6c6c6")
                .set("fill-opacity", "0.45")
                .set("stroke", "#d98080")
                .set("stroke-dasharray", "4 3"),
        );
    }
    doc = doc.add(zones);

    let mut walls = Group::new().set("id", "walls");
    for w in &drawing.walls {
        let (x1, y1) = px(w.a, min, max_z);
        let (x2, y2) = px(w.b, min, max_z);
        walls = walls.add(
            line((x1, y1), (x2, y2))
                .set("stroke", "#333333")
                .set("stroke-width", 6)
                .set("stroke-linecap", "square"),
        );
    }
    doc = doc.add(walls);

    let mut windows = Group::new().set("id", "windows");
    for w in &drawing.windows {
        let (x1, y1) = px(w.a, min, max_z);
        let (x2, y2) = px(w.b, min, max_z);
        windows =
            windows.add(line((x1, y1), (x2, y2)).set("stroke", "#6fb7e9").set("stroke-width", 6));
    }
    doc = doc.add(windows);

    let mut doors = Group::new().set("id", "doors");
    for d in &drawing.doors {
        let (x1, y1) = px(d.opening.a, min, max_z);
        let (x2, y2) = px(d.opening.b, min, max_z);
        doors = doors.add(line((x1, y1), (x2, y2)).set("stroke", "#ffffff").set("stroke-width", 8));
        if let Some(s) = d.swing {
            // The leaf, opened at 90° from the hinge (end a), and its swing arc.
            let len = (d.opening.b[0] - d.opening.a[0]).hypot(d.opening.b[1] - d.opening.a[1]);
            let tip = [d.opening.a[0] + s[0] * len, d.opening.a[1] + s[1] * len];
            let (tx, ty) = px(tip, min, max_z);
            let r = len * SCALE;
            // The arc goes from the open leaf's tip back to the closed position around the
            // hinge; in SVG (y down) a positive cross product turns clockwise (sweep 1).
            let cross = (tx - x1) * (y2 - y1) - (ty - y1) * (x2 - x1);
            let sweep = u8::from(cross > 0.0);
            doors = doors
                .add(line((x1, y1), (tx, ty)).set("stroke", "#8a5a2b").set("stroke-width", 2))
                .add(
                    Path::new()
                        .set(
                            "d",
                            format!(
                                "M {} {} A {} {} 0 0 {sweep} {} {}",
                                n(tx),
                                n(ty),
                                n(r),
                                n(r),
                                n(x2),
                                n(y2)
                            ),
                        )
                        .set("fill", "none")
                        .set("stroke", "#8a5a2b")
                        .set("stroke-dasharray", "3 3"),
                );
        }
        let label_at = px(
            [
                f64::midpoint(d.opening.a[0], d.opening.b[0]),
                f64::midpoint(d.opening.a[1], d.opening.b[1]),
            ],
            min,
            max_z,
        );
        doors = doors.add(
            Text::new("")
                .set("x", n(label_at.0))
                .set("y", n(label_at.1 - 6.0))
                .set("font-size", 9)
                .set("fill", "#8a5a2b")
                .set("text-anchor", "middle")
                .add(TextNode::new(d.label.clone())),
        );
    }
    doc = doc.add(doors);

    let mut objects = Group::new().set("id", "objects");
    for o in &drawing.objects {
        let half = [o.size[0] / 2.0, o.size[1] / 2.0];
        let corners: Vec<[f64; 2]> =
            [[-half[0], -half[1]], [-half[0], half[1]], [half[0], half[1]], [half[0], -half[1]]]
                .iter()
                .map(|d| {
                    let r = rotate(*d, o.facing_deg);
                    [o.center[0] + r[0], o.center[1] + r[1]]
                })
                .collect();
        let (fill, stroke, dash) = match o.level {
            ObjectLevel::Floor => ("#cfe0c3", "#4d7a35", "none"),
            ObjectLevel::Wall => ("#e3d3f0", "#7a4d9a", "none"),
            ObjectLevel::Small => ("#fbe7a8", "#a8842a", "none"),
            ObjectLevel::Ceiling => ("none", "#888888", "5 3"),
        };
        let front = rotate([0.0, half[1]], o.facing_deg);
        let front_pt = [o.center[0] + front[0], o.center[1] + front[1]];
        let (fx, fy) = px(front_pt, min, max_z);
        let (cx, cy) = px(o.center, min, max_z);
        let mut g = Group::new().set("class", "object").add(Title::new(o.name.clone())).add(
            Polygon::new()
                .set("points", points(&corners, min, max_z))
                .set("fill", fill)
                .set("fill-opacity", "0.8")
                .set("stroke", stroke)
                .set("stroke-width", 1.5)
                .set("stroke-dasharray", dash),
        );
        if o.level != ObjectLevel::Ceiling {
            g = g.add(
                Circle::new().set("cx", n(fx)).set("cy", n(fy)).set("r", 3).set("fill", stroke),
            );
        }
        g = g.add(
            Text::new("")
                .set("x", n(cx))
                .set("y", n(cy + 3.0))
                .set("font-size", 9)
                .set("text-anchor", "middle")
                .set("fill", "#222222")
                .add(TextNode::new(o.name.clone())),
        );
        objects = objects.add(g);
    }
    doc = doc.add(objects);

    let mut labels = Group::new().set("id", "room-labels");
    for r in &drawing.rooms {
        if r.polygon.is_empty() {
            continue;
        }
        let count = r.polygon.len() as f64;
        let c = [
            r.polygon.iter().map(|p| p[0]).sum::<f64>() / count,
            r.polygon.iter().map(|p| p[1]).sum::<f64>() / count,
        ];
        let (x, y) = px(c, min, max_z);
        labels = labels.add(
            Text::new("")
                .set("x", n(x))
                .set("y", n(y))
                .set("font-size", 16)
                .set("font-weight", "bold")
                .set("fill", "#9c8f78")
                .set("fill-opacity", "0.8")
                .set("text-anchor", "middle")
                .add(TextNode::new(r.label.clone())),
        );
    }
    doc = doc.add(labels);

    let mut bad = Group::new().set("id", "violations");
    for v in &drawing.violations {
        let (x1, y1) = px(v.from, min, max_z);
        let (x2, y2) = px(v.to, min, max_z);
        bad = bad.add(
            line((x1, y1), (x2, y2))
                .set("stroke", "#d62728")
                .set("stroke-width", 2)
                .set("stroke-dasharray", "6 3")
                .add(Title::new(v.text.clone())),
        );
    }
    doc = doc.add(bad);

    let mut legend = Group::new().set("id", "legend");
    let mut y = (max_z - min_z + 2.0 * MARGIN_M) * SCALE + 14.0;
    for v in &drawing.violations {
        legend = legend.add(
            Text::new("")
                .set("x", 10)
                .set("y", n(y))
                .set("font-size", 11)
                .set("fill", "#d62728")
                .add(TextNode::new(format!("violated: {}", v.text))),
        );
        y += 20.0;
    }
    for u in &drawing.unplaced {
        legend = legend.add(
            Text::new("")
                .set("x", 10)
                .set("y", n(y))
                .set("font-size", 11)
                .set("fill", "#d62728")
                .add(TextNode::new(format!("not placed: {u}"))),
        );
        y += 20.0;
    }
    doc = doc.add(legend);
    let mut out = doc.to_string();
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_every_part_deterministically() {
        let drawing = Drawing {
            title: "t".into(),
            rooms: vec![DrawRoom {
                label: "living room".into(),
                polygon: vec![[0.0, 0.0], [0.0, 4.0], [5.0, 4.0], [5.0, 0.0]],
            }],
            walls: vec![DrawSegment { a: [0.0, 0.0], b: [0.0, 4.0] }],
            doors: vec![DrawDoor {
                opening: DrawSegment { a: [2.0, 0.0], b: [3.0, 0.0] },
                swing: Some([0.0, 1.0]),
                label: "doorway".into(),
            }],
            windows: vec![DrawSegment { a: [5.0, 1.0], b: [5.0, 2.5] }],
            keep_out: vec![vec![[2.0, 0.0], [2.0, 1.0], [3.0, 1.0], [3.0, 0.0]]],
            objects: vec![DrawObject {
                name: "sofa-0".into(),
                center: [1.0, 2.0],
                size: [2.0, 0.9],
                facing_deg: 90.0,
                level: ObjectLevel::Floor,
            }],
            violations: vec![DrawViolation {
                from: [1.0, 2.0],
                to: [3.0, 3.0],
                text: "near tv-0 (2.1 m)".into(),
            }],
            unplaced: vec!["lamp-0: no free spot by the wall".into()],
        };
        let a = render_svg(&drawing);
        assert_eq!(a, render_svg(&drawing));
        for needle in [
            "living room",
            "sofa-0",
            "doorway",
            "violated: near tv-0",
            "not placed: lamp-0",
            "<circle",
        ] {
            assert!(a.contains(needle), "the drawing lacks {needle}");
        }
        // A sofa facing east (90°) is 0.9 m wide along x: its polygon spans x from 0.55 to 1.45 m.
        assert!(a.contains("135.00,"), "{a}");
    }
}
