//! The facts each prompt shows, computed from the scene built out of the earlier answers.
//!
//! Rooms are the rectilinear polygons of the floor plan; two rooms are neighbours when edges of
//! theirs overlap along a line, and the parts of a room's edges that no other room covers are its
//! outside walls. Lengths are printed in metres (room sizes) or whole centimetres (windows,
//! objects), trimmed of useless zeros, so the prompt text is the same on every platform.

use crate::check::{Object, Placement, Room, Scene};

/// Two lengths closer than this are equal, metres.
const EPS_M: f64 = 1e-6;

/// The shortest shared wall offered for a connection, metres (a single door is about 1 m wide).
pub(crate) const MIN_CONNECTION_M: f64 = 1.2;

/// The shortest outside wall offered for windows, metres.
pub(crate) const MIN_WINDOW_WALL_M: f64 = 1.0;

/// A length in metres, at most two decimals, without trailing zeros.
pub(crate) fn metres(value: f64) -> String {
    let text = format!("{value:.2}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}

/// A length in whole centimetres.
pub(crate) fn centimetres(value_m: f64) -> String {
    format!("{}", (value_m * 100.0).round() as i64)
}

fn edges(room: &Room) -> Vec<([f64; 2], [f64; 2])> {
    let n = room.corners.len();
    (0..n).map(|i| (room.corners[i], room.corners[(i + 1) % n])).collect()
}

fn bounds(room: &Room) -> Option<([f64; 2], [f64; 2])> {
    let first = *room.corners.first()?;
    let mut low = first;
    let mut high = first;
    for c in &room.corners {
        low = [low[0].min(c[0]), low[1].min(c[1])];
        high = [high[0].max(c[0]), high[1].max(c[1])];
    }
    Some((low, high))
}

/// Extent of the room's bounding box, `(dx, dz)` in metres.
pub(crate) fn extent(room: &Room) -> (f64, f64) {
    bounds(room).map_or((0.0, 0.0), |(low, high)| (high[0] - low[0], high[1] - low[1]))
}

/// Whether a point is inside a polygon (even-odd rule).
fn inside(corners: &[[f64; 2]], p: [f64; 2]) -> bool {
    let n = corners.len();
    let mut result = false;
    for i in 0..n {
        let a = corners[i];
        let b = corners[(i + 1) % n];
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                result = !result;
            }
        }
    }
    result
}

/// An axis-aligned edge as a line coordinate and an interval along it.
#[derive(Clone, Copy, Debug)]
struct Run {
    /// True for an edge of constant z (it runs along x).
    along_x: bool,
    /// The constant coordinate.
    at: f64,
    lo: f64,
    hi: f64,
}

fn run(edge: ([f64; 2], [f64; 2])) -> Option<Run> {
    let (a, b) = edge;
    if (a[1] - b[1]).abs() < EPS_M && (a[0] - b[0]).abs() > EPS_M {
        Some(Run { along_x: true, at: a[1], lo: a[0].min(b[0]), hi: a[0].max(b[0]) })
    } else if (a[0] - b[0]).abs() < EPS_M && (a[1] - b[1]).abs() > EPS_M {
        Some(Run { along_x: false, at: a[0], lo: a[1].min(b[1]), hi: a[1].max(b[1]) })
    } else {
        None
    }
}

fn overlap(a: Run, b: Run) -> f64 {
    if a.along_x != b.along_x || (a.at - b.at).abs() > EPS_M {
        return 0.0;
    }
    (a.hi.min(b.hi) - a.lo.max(b.lo)).max(0.0)
}

/// Length of the boundary two rooms share, metres.
pub(crate) fn shared_length(a: &Room, b: &Room) -> f64 {
    let runs_b: Vec<Run> = edges(b).into_iter().filter_map(run).collect();
    edges(a)
        .into_iter()
        .filter_map(run)
        .map(|ra| runs_b.iter().map(|&rb| overlap(ra, rb)).sum::<f64>())
        .sum()
}

/// The side of the room an edge lies on.
fn side(room: &Room, r: Run) -> &'static str {
    let mid = f64::midpoint(r.lo, r.hi);
    let probe = 0.01;
    if r.along_x {
        if inside(&room.corners, [mid, r.at - probe]) {
            "north"
        } else {
            "south"
        }
    } else if inside(&room.corners, [r.at - probe, mid]) {
        "east"
    } else {
        "west"
    }
}

/// The longest outside piece of wall per side of a room, in the order north, east, south, west.
pub(crate) fn outside_walls(scene: &Scene, room: &Room) -> Vec<(&'static str, f64)> {
    let others: Vec<Run> = scene
        .rooms
        .iter()
        .filter(|r| r.id != room.id)
        .flat_map(|r| edges(r).into_iter().filter_map(run))
        .collect();
    let mut best: Vec<(&'static str, f64)> = Vec::new();
    for r in edges(room).into_iter().filter_map(run) {
        // Subtract every interval covered by another room's collinear edge.
        let mut covered: Vec<(f64, f64)> = others
            .iter()
            .filter(|o| o.along_x == r.along_x && (o.at - r.at).abs() <= EPS_M)
            .map(|o| (o.lo.max(r.lo), o.hi.min(r.hi)))
            .filter(|(lo, hi)| hi > lo)
            .collect();
        covered.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut at = r.lo;
        let mut longest: f64 = 0.0;
        for (lo, hi) in covered {
            if lo > at {
                longest = longest.max(lo - at);
            }
            at = at.max(hi);
        }
        longest = longest.max(r.hi - at);
        if longest + EPS_M >= MIN_WINDOW_WALL_M {
            let s = side(room, r);
            match best.iter_mut().find(|(name, _)| *name == s) {
                Some(entry) => entry.1 = entry.1.max(longest),
                None => best.push((s, longest)),
            }
        }
    }
    let order = ["north", "east", "south", "west"];
    best.sort_by_key(|(name, _)| order.iter().position(|o| o == name));
    best
}

/// `living room, kitchen, bedroom`.
pub(crate) fn rooms(scene: &Scene) -> String {
    scene.rooms.iter().map(|r| r.label.as_str()).collect::<Vec<_>>().join(", ")
}

/// One line per room: `living room: 5 m x 8 m x 2.7 m`.
pub(crate) fn room_sizes(scene: &Scene) -> String {
    let h = metres(scene.wall_height_m);
    scene
        .rooms
        .iter()
        .map(|r| {
            let (dx, dz) = extent(r);
            format!("{}: {} m x {} m x {h} m", r.label, metres(dx), metres(dz))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// One line per pair of rooms that can be connected, with the shared length, then one line per
/// room with an outside wall.
pub(crate) fn room_pairs(scene: &Scene) -> String {
    let mut lines = Vec::new();
    for (i, a) in scene.rooms.iter().enumerate() {
        for b in &scene.rooms[i + 1..] {
            let shared = shared_length(a, b);
            if shared + EPS_M >= MIN_CONNECTION_M {
                lines.push(format!("{} | {} (shared wall {} m)", a.label, b.label, metres(shared)));
            }
        }
    }
    for r in &scene.rooms {
        if let Some(longest) = outside_walls(scene, r).iter().map(|w| w.1).reduce(f64::max) {
            if longest + EPS_M >= MIN_CONNECTION_M {
                lines.push(format!(
                    "exterior | {} (outside wall up to {} m)",
                    r.label,
                    metres(longest)
                ));
            }
        }
    }
    if lines.is_empty() {
        "(no pair of rooms shares a wall)".to_string()
    } else {
        lines.join("\n")
    }
}

/// One line per room with outside walls: `living room: north, 500 cm; west, 800 cm`.
pub(crate) fn window_walls(scene: &Scene) -> String {
    let entrance: Vec<usize> = scene
        .doors
        .iter()
        .filter_map(|d| match (d.from, d.to) {
            (crate::check::DoorSide::Exterior, crate::check::DoorSide::Room(r))
            | (crate::check::DoorSide::Room(r), crate::check::DoorSide::Exterior) => Some(r.0),
            _ => None,
        })
        .collect();
    let mut lines = Vec::new();
    for r in &scene.rooms {
        let walls = outside_walls(scene, r);
        if walls.is_empty() {
            continue;
        }
        let sides: Vec<String> =
            walls.iter().map(|(side, len)| format!("{side}, {} cm", centimetres(*len))).collect();
        let note = if entrance.contains(&r.id.0) {
            " (the entrance door is on one of these walls; keep one of them free of windows)"
        } else {
            ""
        };
        lines.push(format!("{}: {}{note}", r.label, sides.join("; ")));
    }
    if lines.is_empty() {
        "(no room has an outside wall)".to_string()
    } else {
        lines.join("\n")
    }
}

/// `500 cm x 800 cm, with walls 270 cm high`.
pub(crate) fn room_size_cm(scene: &Scene, room: &Room) -> String {
    let (dx, dz) = extent(room);
    format!(
        "{} cm x {} cm, with walls {} cm high",
        centimetres(dx),
        centimetres(dz),
        centimetres(scene.wall_height_m)
    )
}

fn names<'a>(objects: impl Iterator<Item = &'a Object>) -> String {
    let names: Vec<&str> = objects.map(|o| o.name.as_str()).collect();
    if names.is_empty() {
        "(none)".to_string()
    } else {
        names.join(", ")
    }
}

/// The floor objects of a room: `sofa-0, coffee_table-0`.
pub(crate) fn floor_objects(scene: &Scene, room: &Room) -> String {
    names(scene.room_objects(room.id).filter(|o| o.is_floor()))
}

/// The wall objects of a room.
pub(crate) fn wall_objects(scene: &Scene, room: &Room) -> String {
    names(scene.room_objects(room.id).filter(|o| matches!(o.placement, Placement::Wall { .. })))
}

/// Whether the room has wall objects.
pub(crate) fn has_wall_objects(scene: &Scene, room: &Room) -> bool {
    scene.room_objects(room.id).any(|o| !o.is_floor())
}

/// Whether the room has floor objects.
pub(crate) fn has_floor_objects(scene: &Scene, room: &Room) -> bool {
    scene.room_objects(room.id).any(Object::is_floor)
}

/// One line per floor object: `desk-0 (study) [already: desk lamp x1]`.
pub(crate) fn receptacles(scene: &Scene, room: &Room) -> String {
    let lines: Vec<String> = scene
        .room_objects(room.id)
        .filter(|o| o.is_floor())
        .map(|o| {
            let planned: Vec<String> =
                o.on_top.iter().map(|i| format!("{} x{}", i.item, i.count)).collect();
            let planned =
                if planned.is_empty() { "nothing yet".to_string() } else { planned.join(", ") };
            format!("{} ({}) [{planned}]", o.name, room.label)
        })
        .collect();
    if lines.is_empty() {
        "(none)".to_string()
    } else {
        lines.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::RoomId;
    use crate::source::{FileId, Span};

    fn room(id: usize, label: &str, corners: &[[f64; 2]]) -> Room {
        let span = Span::new(FileId(0), 0, 0);
        Room {
            id: RoomId(id),
            name: label.replace(' ', "_"),
            label: label.to_string(),
            floor_design: None,
            wall_design: None,
            floor_material: None,
            wall_material: None,
            corners: corners.to_vec(),
            corner_spans: vec![span; corners.len()],
            corners_unit_span: None,
            windows: Vec::new(),
            objects: Vec::new(),
            ceiling: None,
            name_span: span,
            decl_span: span,
        }
    }

    pub(crate) fn three_rooms() -> Scene {
        Scene {
            request: Some("test".into()),
            wall_height_m: 3.0,
            seed: 0,
            rooms: vec![
                room(0, "living room", &[[0.0, 0.0], [0.0, 8.0], [5.0, 8.0], [5.0, 0.0]]),
                room(1, "kitchen", &[[5.0, 0.0], [5.0, 5.0], [8.0, 5.0], [8.0, 0.0]]),
                room(2, "bedroom", &[[5.0, 5.0], [5.0, 8.0], [8.0, 8.0], [8.0, 5.0]]),
            ],
            doors: Vec::new(),
            objects: Vec::new(),
            ceiling_material: None,
            ceiling_design: None,
        }
    }

    #[test]
    fn numbers() {
        assert_eq!(metres(5.0), "5");
        assert_eq!(metres(4.5), "4.5");
        assert_eq!(metres(2.675), "2.67");
        assert_eq!(centimetres(4.5), "450");
    }

    #[test]
    fn sizes_pairs_and_walls() {
        let scene = three_rooms();
        assert_eq!(
            room_sizes(&scene),
            "living room: 5 m x 8 m x 3 m\nkitchen: 3 m x 5 m x 3 m\nbedroom: 3 m x 3 m x 3 m"
        );
        assert_eq!(
            room_pairs(&scene),
            "living room | kitchen (shared wall 5 m)\nliving room | bedroom (shared wall 3 m)\n\
             kitchen | bedroom (shared wall 3 m)\nexterior | living room (outside wall up to 8 m)\n\
             exterior | kitchen (outside wall up to 5 m)\nexterior | bedroom (outside wall up to 3 m)"
        );
        assert_eq!(
            window_walls(&scene),
            "living room: north, 500 cm; south, 500 cm; west, 800 cm\n\
             kitchen: east, 500 cm; south, 300 cm\nbedroom: north, 300 cm; east, 300 cm"
        );
    }
}
