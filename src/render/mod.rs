//! The SVG plan: a top-down drawing of a built scene.
//!
//! [`render_svg`] draws a [`Drawing`]: rooms with their label and area, walls, doors with their
//! swing, windows, every object's footprint with its name (or a number and a key where names
//! would overlap) and a mark on its front, the keep-out zones in front of doors, violated
//! relations as red lines between the objects involved, a scale bar and a north arrow; a panel
//! beside the plan holds the legend, the key, the objects left out and the relations not kept.
//! [`drawing`] makes the drawing from a finished build (the house's objects, sized by the
//! layout); [`render_svg`] itself knows nothing of the stages. Neither does I/O.
//!
//! **Invariant:** the output depends only on the drawing: numbers are printed with two decimals,
//! elements in the drawing's order, labels placed by a fixed greedy order.

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
    /// Violated relations and placements.
    pub violations: Vec<DrawViolation>,
    /// Objects the scene asks for that are not in the house, with the reason.
    pub left_out: Vec<LeftOut>,
}

/// An object the scene asks for that is not in the house.
#[derive(Clone, Debug)]
pub struct LeftOut {
    /// Its name, e.g. `piano-0` or `book on shelf-0`.
    pub name: String,
    /// Why, in words.
    pub reason: String,
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
    /// Whether it has two leaves, hinged at both ends of the opening (a double door).
    pub double: bool,
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
    /// Its identifier, e.g. `sofa-0` (the footprint's title).
    pub name: String,
    /// What the plan calls it: its name in the scene (`sofa`, `dining chair 1`, `book`).
    pub label: String,
    /// For an item on top of another object, that object's identifier: the items of one name
    /// on one object get one label, with their count (`book ×3`).
    pub on: Option<String>,
    /// Centre of the footprint, metres.
    pub center: [f64; 2],
    /// Width (x at facing 0) and depth, metres.
    pub size: [f64; 2],
    /// Facing, degrees (0 = +z, 90 = +x).
    pub facing_deg: f64,
    /// Floor, wall, small or ceiling.
    pub level: ObjectLevel,
}

/// A relation (or global placement) that the layout does not keep.
#[derive(Clone, Debug)]
pub struct DrawViolation {
    /// The constrained object's centre.
    pub from: [f64; 2],
    /// The target's centre (`None` for a global placement such as `edge`).
    pub to: Option<[f64; 2]>,
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

/// Width of the panel beside the plan (legend, key, left-out objects), pixels.
const PANEL_W: f64 = 330.0;
/// Font size of object labels, pixels.
const LABEL_FONT: f64 = 9.0;
/// The average advance of a sans-serif character, as a fraction of the font size (an estimate
/// that errs wide, so that labels estimated apart are apart).
const CHAR_EM: f64 = 0.58;
/// How many characters a line of the panel holds.
const PANEL_CHARS: usize = 52;
/// Height of a line of the panel, pixels.
const PANEL_LINE: f64 = 15.0;

/// How many steps the search for a room label's place makes along each side of the room.
const LABEL_GRID_STEPS: usize = 24;

/// A box on the drawing, pixels.
#[derive(Clone, Copy, Debug)]
struct PxBox {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl PxBox {
    /// The box of a text centred at `x` with its baseline at `y`.
    fn text(x: f64, y: f64, text: &str, font: f64) -> PxBox {
        let half = text.chars().count() as f64 * font * CHAR_EM / 2.0;
        PxBox { x0: x - half, y0: y - font * 0.85, x1: x + half, y1: y + font * 0.25 }
    }

    fn overlaps(&self, other: &PxBox) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
}

/// The point inside a room where its label reads best: the grid point farthest from its walls
/// (the area centroid of an L-shaped room may lie outside it).
fn label_point(poly: &[[f64; 2]]) -> [f64; 2] {
    let count = poly.len().max(1) as f64;
    let average = [
        poly.iter().map(|p| p[0]).sum::<f64>() / count,
        poly.iter().map(|p| p[1]).sum::<f64>() / count,
    ];
    if poly.len() < 3 {
        return average;
    }
    let aabb = crate::geometry::Aabb::of(poly);
    let centroid = crate::geometry::area_centroid(poly);
    let clearance = |p: [f64; 2]| {
        (0..poly.len())
            .map(|i| crate::geometry::distance_to_segment(p, poly[i], poly[(i + 1) % poly.len()]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut best: Option<([f64; 2], f64)> = None;
    if crate::geometry::point_in_polygon(centroid, poly) {
        best = Some((centroid, clearance(centroid)));
    }
    for i in 1..LABEL_GRID_STEPS {
        for j in 1..LABEL_GRID_STEPS {
            let p = [
                aabb.min[0] + aabb.width() * i as f64 / LABEL_GRID_STEPS as f64,
                aabb.min[1] + aabb.depth() * j as f64 / LABEL_GRID_STEPS as f64,
            ];
            if !crate::geometry::point_in_polygon(p, poly) {
                continue;
            }
            let c = clearance(p);
            // The centroid keeps its place unless a point is clearly better.
            if best.is_none_or(|(_, b)| c > b * 1.25 + 1e-9) {
                best = Some((p, c));
            }
        }
    }
    best.map_or(average, |(p, _)| p)
}

/// Splits a text into lines of at most `width` characters, at spaces where it can.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let needed = line.chars().count() + usize::from(!line.is_empty()) + word.chars().count();
        if !line.is_empty() && needed > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
        while line.chars().count() > width {
            let cut: String = line.chars().take(width).collect();
            let rest: String = line.chars().skip(width).collect();
            lines.push(cut);
            line = rest;
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

fn text(x: f64, y: f64, size: f64, fill: &str, content: impl Into<String>) -> Text {
    Text::new("")
        .set("x", n(x))
        .set("y", n(y))
        .set("font-size", n(size))
        .set("fill", fill.to_string())
        .add(TextNode::new(content.into()))
}

/// The fill, stroke and dash pattern of an object's footprint.
fn object_style(level: ObjectLevel) -> (&'static str, &'static str, &'static str) {
    match level {
        ObjectLevel::Floor => ("#cfe0c3", "#4d7a35", "none"),
        ObjectLevel::Wall => ("#e3d3f0", "#7a4d9a", "none"),
        ObjectLevel::Small => ("#fbe7a8", "#a8842a", "none"),
        ObjectLevel::Ceiling => ("none", "#888888", "5 3"),
    }
}

/// The length of the scale bar: a round number of metres near a fifth of the plan's width.
fn scale_bar_m(plan_width_m: f64) -> f64 {
    [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
        .into_iter()
        .rev()
        .find(|&l| l <= plan_width_m / 4.0)
        .unwrap_or(0.5)
}

/// What one object label says and where it may go: the centre of what it names, and the top
/// and bottom of its footprints (pixels).
struct LabelJob {
    text: String,
    center: (f64, f64),
    top: f64,
    bottom: f64,
    /// For items on top: the receptacle and the item's name, and how many there are.
    items: Option<(String, String, usize)>,
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
    // A door leaf that swings out of the house stays on the drawing.
    for d in &drawing.doors {
        if let Some(s) = d.swing {
            let len = (d.opening.b[0] - d.opening.a[0]).hypot(d.opening.b[1] - d.opening.a[1]);
            for end in [d.opening.a, d.opening.b] {
                xs.push(end[0] + s[0] * len);
                zs.push(end[1] + s[1] * len);
            }
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
    let plan_w = (max_x - min_x + 2.0 * MARGIN_M) * SCALE;
    let plan_h = (max_z - min_z + 2.0 * MARGIN_M) * SCALE;

    // Labels first (they decide the key), then the panel (it decides the height).
    let mut taken: Vec<PxBox> = Vec::new();
    let mut room_labels = Group::new().set("id", "room-labels");
    for r in &drawing.rooms {
        if r.polygon.is_empty() {
            continue;
        }
        let (x, y) = px(label_point(&r.polygon), min, max_z);
        let area = crate::geometry::signed_area(&r.polygon).abs();
        let area_text = format!("{area:.1} m²");
        taken.push(PxBox::text(x, y, &r.label, 16.0));
        taken.push(PxBox::text(x, y + 15.0, &area_text, 11.0));
        room_labels = room_labels
            .add(
                text(x, y, 16.0, "#9c8f78", r.label.clone())
                    .set("font-weight", "bold")
                    .set("text-anchor", "middle"),
            )
            .add(text(x, y + 15.0, 11.0, "#9c8f78", area_text).set("text-anchor", "middle"));
    }

    let mut key: Vec<(usize, String)> = Vec::new();
    let mut objects = Group::new().set("id", "objects");
    let mut jobs: Vec<LabelJob> = Vec::new();
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
        let (fill, stroke, dash) = object_style(o.level);
        let front = rotate([0.0, half[1]], o.facing_deg);
        let (fx, fy) = px([o.center[0] + front[0], o.center[1] + front[1]], min, max_z);
        let (cx, cy) = px(o.center, min, max_z);
        let mut g = Group::new()
            .set("class", "object")
            .set("data-name", o.name.clone())
            .set("data-level", format!("{:?}", o.level).to_lowercase())
            .add(Title::new(o.name.clone()))
            .add(
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
        objects = objects.add(g);
        let ys: Vec<f64> = corners.iter().map(|c| px(*c, min, max_z).1).collect();
        let top = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let bottom = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        // Items of one name on one object share a label: at their middle, with their count.
        if let (ObjectLevel::Small, Some(on)) = (o.level, &o.on) {
            let same = jobs
                .iter_mut()
                .find(|j| j.items.as_ref().is_some_and(|(r, item, _)| r == on && *item == o.label));
            if let Some(job) = same {
                let count = job.items.as_ref().map_or(1, |(_, _, k)| *k);
                let weight = count as f64;
                job.center = (
                    (job.center.0 * weight + cx) / (weight + 1.0),
                    (job.center.1 * weight + cy) / (weight + 1.0),
                );
                job.top = job.top.min(top);
                job.bottom = job.bottom.max(bottom);
                if let Some((_, _, k)) = &mut job.items {
                    *k += 1;
                }
                continue;
            }
            jobs.push(LabelJob {
                text: o.label.clone(),
                center: (cx, cy),
                top,
                bottom,
                items: Some((on.clone(), o.label.clone(), 1)),
            });
            continue;
        }
        jobs.push(LabelJob { text: o.label.clone(), center: (cx, cy), top, bottom, items: None });
    }
    // Names go above every footprint, so that no later footprint covers them: at the centre,
    // or just above or below the footprint; where all three would cover another label, a
    // number that the key beside the plan explains.
    let mut names = Group::new().set("id", "object-labels");
    for job in jobs {
        let label = match &job.items {
            Some((_, item, count)) if *count > 1 => format!("{item} ×{count}"),
            _ => job.text,
        };
        let (cx, cy) = job.center;
        let spots = [cy + 3.0, job.top - 3.0, job.bottom + LABEL_FONT + 1.0];
        let free = spots
            .iter()
            .map(|&y| (y, PxBox::text(cx, y, &label, LABEL_FONT)))
            .find(|(_, b)| !taken.iter().any(|t| t.overlaps(b)));
        match free {
            Some((y, b)) => {
                taken.push(b);
                names = names
                    .add(text(cx, y, LABEL_FONT, "#222222", label).set("text-anchor", "middle"));
            }
            None => {
                let number = key.len() + 1;
                key.push((number, label));
                let mark = number.to_string();
                taken.push(PxBox::text(cx, cy + 3.0, &mark, LABEL_FONT));
                names = names.add(
                    text(cx, cy + 3.0, LABEL_FONT, "#222222", mark)
                        .set("text-anchor", "middle")
                        .set("font-weight", "bold"),
                );
            }
        }
    }

    // The panel: title, legend, key, left-out objects, relations not kept.
    let x0 = plan_w + 12.0;
    let mut panel = Group::new().set("id", "panel");
    let mut y = 22.0;
    let title = if drawing.title.is_empty() { "plan".to_string() } else { drawing.title.clone() };
    for line in wrap(&title, 34) {
        panel = panel.add(text(x0, y, 14.0, "#222222", line).set("font-weight", "bold"));
        y += 18.0;
    }
    y += 6.0;
    panel = panel.add(text(x0, y, 12.0, "#222222", "Legend").set("font-weight", "bold"));
    y += 8.0;
    let mut legend = Group::new().set("id", "legend");
    // Only what the plan draws.
    let drawn = |level: ObjectLevel| drawing.objects.iter().any(|o| o.level == level);
    let swatches = [
        (
            drawn(ObjectLevel::Floor),
            object_style(ObjectLevel::Floor),
            "floor object (dot: its front)",
        ),
        (drawn(ObjectLevel::Wall), object_style(ObjectLevel::Wall), "wall object"),
        (
            drawn(ObjectLevel::Small),
            object_style(ObjectLevel::Small),
            "item on top of another object",
        ),
        (drawn(ObjectLevel::Ceiling), object_style(ObjectLevel::Ceiling), "ceiling object"),
        (
            !drawing.keep_out.is_empty(),
            ("#f6c6c6", "#d98080", "4 3"),
            "keep-out zone (door, open connection)",
        ),
    ];
    for (_, (fill, stroke, dash), what) in swatches.into_iter().filter(|s| s.0) {
        legend = legend
            .add(
                Rectangle::new()
                    .set("x", n(x0))
                    .set("y", n(y))
                    .set("width", 22)
                    .set("height", 11)
                    .set("fill", fill)
                    .set("stroke", stroke)
                    .set("stroke-dasharray", dash),
            )
            .add(text(x0 + 30.0, y + 10.0, 11.0, "#222222", what));
        y += PANEL_LINE;
    }
    let leaves = drawing.doors.iter().any(|d| d.swing.is_some());
    let strokes = [
        (!drawing.walls.is_empty(), "#333333", 6.0, "none", "wall"),
        (!drawing.windows.is_empty(), "#6fb7e9", 6.0, "none", "window"),
        (leaves, "#8a5a2b", 2.0, "3 3", "door: leaf and swing"),
        (!drawing.violations.is_empty(), "#d62728", 2.0, "6 3", "relation not kept"),
    ];
    for (_, stroke, width, dash, what) in strokes.into_iter().filter(|s| s.0) {
        legend = legend
            .add(
                line((x0, y + 6.0), (x0 + 22.0, y + 6.0))
                    .set("stroke", stroke)
                    .set("stroke-width", n(width))
                    .set("stroke-dasharray", dash),
            )
            .add(text(x0 + 30.0, y + 10.0, 11.0, "#222222", what));
        y += PANEL_LINE;
    }
    panel = panel.add(legend);
    let list = |panel: Group, y: &mut f64, heading: String, items: Vec<String>, fill: &str| {
        let mut g = panel;
        if items.is_empty() {
            return g;
        }
        *y += 10.0;
        g = g.add(text(x0, *y, 12.0, "#222222", heading).set("font-weight", "bold"));
        *y += PANEL_LINE;
        for item in items {
            for (i, line) in wrap(&item, PANEL_CHARS).into_iter().enumerate() {
                let indent = if i == 0 { 0.0 } else { 12.0 };
                g = g.add(text(x0 + indent, *y, 10.5, fill, line));
                *y += PANEL_LINE - 1.0;
            }
        }
        g
    };
    panel = list(
        panel,
        &mut y,
        "Key".to_string(),
        key.iter().map(|(k, name)| format!("{k}  {name}")).collect(),
        "#222222",
    );
    panel = list(
        panel,
        &mut y,
        format!("Left out ({})", drawing.left_out.len()),
        left_out_lines(&drawing.left_out),
        "#d62728",
    );
    panel = list(
        panel,
        &mut y,
        format!("Not kept ({})", drawing.violations.len()),
        drawing.violations.iter().map(|v| v.text.clone()).collect(),
        "#d62728",
    );
    let width = plan_w + PANEL_W;
    let height = plan_h.max(y + 10.0);

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
            // Each leaf opened at 90° from its hinge, and its swing arc back to where it closes:
            // one leaf hinged at end a, or two leaves of half the width hinged at both ends.
            let leaves: Vec<([f64; 2], [f64; 2])> = if d.double {
                let mid = [
                    f64::midpoint(d.opening.a[0], d.opening.b[0]),
                    f64::midpoint(d.opening.a[1], d.opening.b[1]),
                ];
                vec![(d.opening.a, mid), (d.opening.b, mid)]
            } else {
                vec![(d.opening.a, d.opening.b)]
            };
            for (hinge, closed) in leaves {
                doors = door_leaf(doors, hinge, closed, s, min, max_z);
            }
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
            text(label_at.0, label_at.1 - 6.0, 9.0, "#8a5a2b", d.label.clone())
                .set("text-anchor", "middle"),
        );
    }
    doc = doc.add(doors);
    doc = doc.add(objects);
    doc = doc.add(room_labels);
    doc = doc.add(names);

    let mut bad = Group::new().set("id", "violations");
    for v in &drawing.violations {
        let (x1, y1) = px(v.from, min, max_z);
        let mark = match v.to {
            Some(to) => {
                let (x2, y2) = px(to, min, max_z);
                line((x1, y1), (x2, y2))
                    .set("stroke", "#d62728")
                    .set("stroke-width", 2)
                    .set("stroke-dasharray", "6 3")
                    .add(Title::new(v.text.clone()))
            }
            // A placement not kept: a short red cross on the object.
            None => line((x1 - 6.0, y1 - 6.0), (x1 + 6.0, y1 + 6.0))
                .set("stroke", "#d62728")
                .set("stroke-width", 2)
                .add(Title::new(v.text.clone())),
        };
        bad = bad.add(mark);
    }
    doc = doc.add(bad);

    // The scale bar (bottom left) and the north arrow (top left), in the margin.
    let bar_m = scale_bar_m(max_x - min_x);
    let bar_px = bar_m * SCALE;
    let (bx, by) = (MARGIN_M * SCALE, plan_h - MARGIN_M * SCALE / 2.0);
    let bar_label =
        if bar_m < 1.0 { format!("{} cm", bar_m * 100.0) } else { format!("{bar_m} m") };
    let scale = Group::new()
        .set("id", "scale-bar")
        .add(line((bx, by), (bx + bar_px, by)).set("stroke", "#222222").set("stroke-width", 2))
        .add(line((bx, by - 5.0), (bx, by + 5.0)).set("stroke", "#222222").set("stroke-width", 2))
        .add(
            line((bx + bar_px, by - 5.0), (bx + bar_px, by + 5.0))
                .set("stroke", "#222222")
                .set("stroke-width", 2),
        )
        .add(text(bx, by - 8.0, 10.0, "#222222", "0").set("text-anchor", "middle"))
        .add(text(bx + bar_px, by - 8.0, 10.0, "#222222", bar_label).set("text-anchor", "middle"));
    doc = doc.add(scale);
    let (nx, ny) = (MARGIN_M * SCALE / 2.0, MARGIN_M * SCALE / 2.0 + 8.0);
    let north = Group::new()
        .set("id", "north-arrow")
        .add(
            Polygon::new()
                .set(
                    "points",
                    format!(
                        "{},{} {},{} {},{}",
                        n(nx),
                        n(ny - 22.0),
                        n(nx - 7.0),
                        n(ny),
                        n(nx + 7.0),
                        n(ny)
                    ),
                )
                .set("fill", "#222222"),
        )
        .add(
            text(nx, ny + 13.0, 12.0, "#222222", "N")
                .set("text-anchor", "middle")
                .set("font-weight", "bold"),
        )
        .add(Title::new("north is +z"));
    doc = doc.add(north);
    doc = doc.add(panel);

    let mut out = xml_chars(doc.to_string());
    out.push('\n');
    out
}

/// The lines of the left-out list: things of one name left out for one reason share a line,
/// with their count (`book ×10: its receptacle `wall_shelf-0` is left out`), in the order of
/// their first.
fn left_out_lines(left_out: &[LeftOut]) -> Vec<String> {
    // `book-3` → `book`; a name without an instance number stays as it is.
    let base = |name: &str| match name.rsplit_once('-') {
        Some((head, n)) if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) => {
            head.to_string()
        }
        _ => name.to_string(),
    };
    let mut groups: Vec<(String, &str, Vec<&str>)> = Vec::new();
    for l in left_out {
        let key = base(&l.name);
        match groups.iter_mut().find(|(k, reason, _)| *k == key && *reason == l.reason) {
            Some((_, _, names)) => names.push(&l.name),
            None => groups.push((key, &l.reason, vec![&l.name])),
        }
    }
    groups
        .into_iter()
        .map(|(key, reason, names)| match names.as_slice() {
            [one] => format!("{one}: {reason}"),
            _ => format!("{key} ×{}: {reason}", names.len()),
        })
        .collect()
}

/// Adds a door leaf hinged at `hinge`, closed towards `closed`, opened at 90° towards `swing`,
/// and its swing arc.
fn door_leaf(
    doors: Group,
    hinge: [f64; 2],
    closed: [f64; 2],
    swing: [f64; 2],
    min: [f64; 2],
    max_z: f64,
) -> Group {
    let len = (closed[0] - hinge[0]).hypot(closed[1] - hinge[1]);
    let tip = [hinge[0] + swing[0] * len, hinge[1] + swing[1] * len];
    let (x1, y1) = px(hinge, min, max_z);
    let (x2, y2) = px(closed, min, max_z);
    let (tx, ty) = px(tip, min, max_z);
    let r = len * SCALE;
    // The arc goes from the open leaf's tip back to the closed position around the hinge; in
    // SVG (y down) a positive cross product turns clockwise (sweep 1).
    let cross = (tx - x1) * (y2 - y1) - (ty - y1) * (x2 - x1);
    let sweep = u8::from(cross > 0.0);
    doors.add(line((x1, y1), (tx, ty)).set("stroke", "#8a5a2b").set("stroke-width", 2)).add(
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
    )
}

/// The document with every character XML 1.0 does not allow (C0 controls other than tab and
/// line breaks, U+FFFE, U+FFFF) replaced by U+FFFD. The `svg` crate escapes `<`, `>`, `&` and
/// quotes; a name read from a file may still hold a control character, and one such character
/// makes the whole document not well-formed. holoc's own markup holds none, so only text
/// taken from the scene is changed.
fn xml_chars(svg: String) -> String {
    let allowed = |c: char| {
        matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}')
    };
    if svg.chars().all(allowed) {
        return svg;
    }
    svg.chars().map(|c| if allowed(c) { c } else { '\u{FFFD}' }).collect()
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
                double: false,
                label: "doorway".into(),
            }],
            windows: vec![DrawSegment { a: [5.0, 1.0], b: [5.0, 2.5] }],
            keep_out: vec![vec![[2.0, 0.0], [2.0, 1.0], [3.0, 1.0], [3.0, 0.0]]],
            objects: vec![DrawObject {
                name: "sofa-0".into(),
                label: "sofa".into(),
                on: None,
                center: [1.0, 2.0],
                size: [2.0, 0.9],
                facing_deg: 90.0,
                level: ObjectLevel::Floor,
            }],
            violations: vec![
                DrawViolation {
                    from: [1.0, 2.0],
                    to: Some([3.0, 3.0]),
                    text: "sofa-0: near tv-0 (2.1 m)".into(),
                },
                DrawViolation { from: [1.0, 2.0], to: None, text: "sofa-0: edge".into() },
            ],
            left_out: vec![LeftOut {
                name: "lamp-0".into(),
                reason: "no free spot by the wall".into(),
            }],
        };
        let a = render_svg(&drawing);
        assert_eq!(a, render_svg(&drawing));
        for needle in [
            "living room",
            "sofa-0",
            "doorway",
            "sofa-0: near tv-0",
            "sofa-0: edge",
            "Left out (1)",
            "lamp-0: no free spot by the wall",
            "Legend",
            "20.0 m²",
            "id=\"scale-bar\"",
            "id=\"north-arrow\"",
            "<circle",
        ] {
            assert!(a.contains(needle), "the drawing lacks {needle}");
        }
        // A sofa facing east (90°) is 0.9 m wide along x: its polygon spans x from 0.55 to 1.45 m.
        assert!(a.contains("135.00,"), "{a}");
    }

    fn object(name: &str, label: &str, on: Option<&str>, center: [f64; 2]) -> DrawObject {
        DrawObject {
            name: name.into(),
            label: label.into(),
            on: on.map(str::to_owned),
            center,
            size: [0.2, 0.2],
            facing_deg: 0.0,
            level: if on.is_some() { ObjectLevel::Small } else { ObjectLevel::Floor },
        }
    }

    /// The texts of the object labels.
    fn labels(svg: &str) -> Vec<String> {
        let group = svg.split("id=\"object-labels\"").nth(1).unwrap_or("");
        let group = group.split("</g>").next().unwrap_or("");
        group
            .split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .map(str::trim)
            .filter(|t| !t.is_empty())
            .map(str::to_owned)
            .collect()
    }

    #[test]
    fn items_of_one_name_on_one_receptacle_get_one_label_with_their_count() {
        let room = DrawRoom {
            label: "study".into(),
            polygon: vec![[0.0, 0.0], [0.0, 6.0], [6.0, 6.0], [6.0, 0.0]],
        };
        let drawing = Drawing {
            rooms: vec![room],
            objects: vec![
                object("shelf-0", "bookshelf", None, [1.0, 1.0]),
                object("desk-0", "desk", None, [4.0, 4.0]),
                object("book-0", "book", Some("shelf-0"), [0.8, 1.0]),
                object("book-1", "book", Some("shelf-0"), [1.0, 1.0]),
                object("book-2", "book", Some("shelf-0"), [1.2, 1.0]),
                object("book-0", "book", Some("desk-0"), [4.0, 4.0]),
                object("lamp-0", "lamp", Some("desk-0"), [4.2, 4.0]),
            ],
            ..Drawing::default()
        };
        let svg = render_svg(&drawing);
        let mut got = labels(&svg);
        got.sort();
        assert_eq!(got, ["book", "book ×3", "bookshelf", "desk", "lamp"], "{svg}");
        // Every footprint is still drawn, each with its identifier.
        assert_eq!(svg.matches("class=\"object\"").count(), 7);
        assert!(svg.contains("data-name=\"book-2\""));
    }

    #[test]
    fn the_legend_lists_only_what_is_drawn() {
        let drawing = Drawing {
            rooms: vec![DrawRoom {
                label: "a".into(),
                polygon: vec![[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]],
            }],
            walls: vec![DrawSegment { a: [0.0, 0.0], b: [0.0, 4.0] }],
            objects: vec![object("sofa-0", "sofa", None, [1.0, 1.0])],
            ..Drawing::default()
        };
        let svg = render_svg(&drawing);
        let legend = svg.split("id=\"legend\"").nth(1).expect("a legend");
        let legend = legend.split("</g>").next().expect("its group");
        let entries: Vec<&str> = legend
            .split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .map(str::trim)
            .filter(|t| !t.is_empty())
            .collect();
        assert_eq!(entries, ["floor object (dot: its front)", "wall"]);
    }

    #[test]
    fn things_left_out_for_one_reason_share_a_line() {
        let left = |name: &str, reason: &str| LeftOut { name: name.into(), reason: reason.into() };
        let lines = left_out_lines(&[
            left("book-0", "its receptacle `shelf-0` is left out"),
            left("lamp-0", "no free spot"),
            left("book-1", "its receptacle `shelf-0` is left out"),
            left("book-2", "the top of `desk-0` is full"),
        ]);
        assert_eq!(
            lines,
            [
                "book ×2: its receptacle `shelf-0` is left out",
                "lamp-0: no free spot",
                "book-2: the top of `desk-0` is full"
            ]
        );
    }

    #[test]
    fn a_double_door_has_two_leaves() {
        let door = |double: bool| DrawDoor {
            opening: DrawSegment { a: [1.0, 0.0], b: [3.0, 0.0] },
            swing: Some([0.0, 1.0]),
            double,
            label: "doorway".into(),
        };
        let leaves = |double: bool| {
            let drawing = Drawing { doors: vec![door(double)], ..Drawing::default() };
            let svg = render_svg(&drawing);
            let doors = svg.split("id=\"doors\"").nth(1).expect("doors");
            let doors = doors.split("</g>").next().expect("their group").to_string();
            (doors.matches("<path").count(), doors)
        };
        assert_eq!(leaves(false).0, 1);
        let (arcs, doors) = leaves(true);
        assert_eq!(arcs, 2, "{doors}");
        // Each leaf is half the opening (1 m, 100 px) and closes at the middle (x = 2 m).
        assert!(doors.contains(" A 100.00 100.00 "), "{doors}");
    }
}
