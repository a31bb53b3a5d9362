//! Making a [`Drawing`] from a finished build.
//!
//! The objects drawn are the house's objects, at the house's positions: the plan shows exactly
//! what AI2-THOR loads. The layout supplies what the house does not say (footprint sizes, which
//! level an object stands on, the relations it keeps); the resolutions and the layout supply
//! what was left out and why.

use super::{
    DrawDoor, DrawObject, DrawRoom, DrawSegment, DrawViolation, Drawing, LeftOut, ObjectLevel,
};
use crate::check::scene::{DoorKind, DoorSize};
use crate::compile::Built;
use crate::resolve::structure::StructureCatalog;

/// What the layout knows of one object the house may hold.
struct Known {
    name: String,
    /// What the scene calls it (its category, the `on top` line's item, the ceiling's words).
    label: String,
    /// For a small object, the receptacle's name.
    on: Option<String>,
    /// The instance number of a floor or wall object.
    index: Option<u32>,
    size: [f64; 2],
    level: ObjectLevel,
    used: bool,
}

/// The drawing of a build: its plan, the house's objects and what the layout does not keep.
pub fn drawing(built: &Built) -> Drawing {
    let plan = &built.plan;
    let mut d =
        Drawing { title: built.scene.request.clone().unwrap_or_default(), ..Drawing::default() };
    for room in &plan.rooms {
        d.rooms.push(DrawRoom {
            label: built.scene.room(room.id).label.clone(),
            polygon: room.polygon.clone(),
        });
        d.keep_out.extend(room.door_keep_out.iter().cloned());
        d.keep_out.extend(room.open_boxes.iter().cloned());
    }
    for wall in &plan.walls {
        if !wall.empty {
            d.walls.push(DrawSegment { a: wall.start, b: wall.end });
        }
    }
    for door in &plan.doors {
        let (a, b) = door.segment;
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dz);
        // The leaf swings into the room on the right of the segment (the room of its wall).
        let swing = (door.kind == DoorKind::Doorway && len > 0.0).then(|| [dz / len, -dx / len]);
        // Double by its asset, else by the statement it comes from.
        let size = StructureCatalog::builtin().door(&door.asset_id).map(|a| a.size).or_else(|| {
            built.scene.doors.iter().find(|s| Some(s.span) == door.span).and_then(|s| s.size)
        });
        d.doors.push(DrawDoor {
            opening: DrawSegment { a, b },
            swing,
            double: size == Some(DoorSize::Double),
            label: door.kind.as_str().to_string(),
        });
    }
    for window in &plan.windows {
        d.windows.push(DrawSegment { a: window.segment.0, b: window.segment.1 });
    }

    // What the layout knows, room by room (by the house's room id).
    let mut known: Vec<(String, Vec<Known>)> = Vec::new();
    for solved in &built.layout.rooms {
        let problem = &solved.problem;
        let scene_object =
            |ids: &[crate::check::ObjectId], k: usize| ids.get(k).map(|id| built.scene.object(*id));
        let mut list = Vec::new();
        for placed in &solved.layout.floor {
            let o = &problem.objects[placed.index];
            let scene = scene_object(&solved.floor_ids, placed.index);
            list.push(Known {
                name: o.id.clone(),
                label: scene.map_or_else(|| o.id.clone(), |s| spoken(&s.category)),
                on: None,
                index: scene.map(|s| s.index),
                size: o.size,
                level: ObjectLevel::Floor,
                used: false,
            });
        }
        for p in &solved.layout.wall {
            let index = problem.wall_objects.iter().position(|w| w.id == p.id);
            let size = index
                .map(|k| &problem.wall_objects[k])
                .map_or([0.2, 0.2], |w| [w.size[0], w.size[1]]);
            let scene = index.and_then(|k| scene_object(&solved.wall_ids, k));
            list.push(Known {
                name: p.id.clone(),
                label: scene.map_or_else(|| p.id.clone(), |s| spoken(&s.category)),
                on: None,
                index: scene.map(|s| s.index),
                size,
                level: ObjectLevel::Wall,
                used: false,
            });
        }
        for p in &solved.layout.small {
            let small = problem.small_objects.iter().find(|s| s.id == p.id);
            let size = small.map_or([0.2, 0.2], |s| [s.size[0], s.size[1]]);
            let name = p.id.split('|').next().unwrap_or(&p.id).to_string();
            let on = p.on.or(small.map(|s| s.on)).map(|holder| match holder {
                crate::solve::Holder::Floor(k) => problem.objects.get(k).map(|o| o.id.clone()),
                crate::solve::Holder::Wall(k) => problem.wall_objects.get(k).map(|o| o.id.clone()),
            });
            list.push(Known {
                label: small.map_or_else(|| name.clone(), |s| spoken(&s.item)),
                name,
                on: on.flatten(),
                index: None,
                size,
                level: ObjectLevel::Small,
                used: false,
            });
        }
        if let (Some(_), Some(c)) = (&solved.layout.ceiling, &problem.ceiling) {
            let description =
                built.scene.room(solved.room).ceiling.as_ref().map(|c| c.description.as_str());
            list.push(Known {
                name: "ceiling".to_string(),
                label: description.map_or_else(|| "ceiling".to_string(), short_name),
                on: None,
                index: None,
                size: [c.size[0], c.size[1]],
                level: ObjectLevel::Ceiling,
                used: false,
            });
        }
        known.push((plan.room(solved.room).thor_id.clone(), list));
    }

    // The objects of each room, with the scene's names for their labels.
    let mut room_of: Vec<String> = Vec::new();
    let mut numbers: Vec<Option<u32>> = Vec::new();
    for object in built.house.all_objects() {
        let entry = known
            .iter_mut()
            .filter(|(room, _)| *room == object.room_id)
            .flat_map(|(_, list)| list.iter_mut())
            .find(|k| !k.used && k.name == object.object_name);
        let (size, level, label, on, index) = match entry {
            Some(k) => {
                k.used = true;
                (k.size, k.level, k.label.clone(), k.on.clone(), k.index)
            }
            // The house holds something the layout does not describe: drawn small, never
            // hidden.
            None => ([0.2, 0.2], ObjectLevel::Small, object.object_name.clone(), None, None),
        };
        d.objects.push(DrawObject {
            name: object.object_name.clone(),
            label,
            on,
            center: [object.position.x, object.position.z],
            size,
            facing_deg: object.rotation.y,
            level,
        });
        room_of.push(object.room_id.clone());
        numbers.push(index);
    }
    number_alike(&mut d.objects, &room_of, &numbers);

    for solved in &built.layout.rooms {
        let problem = &solved.problem;
        for placed in &solved.layout.floor {
            let o = &problem.objects[placed.index];
            if !d.objects.iter().any(|x| x.name == o.id) {
                continue;
            }
            // The first report is the global placement; the others follow the object's
            // relations in order.
            if let Some(global) = placed.constraints.first().filter(|g| !g.measure.satisfied) {
                d.violations.push(DrawViolation {
                    from: [placed.pose.x, placed.pose.z],
                    to: None,
                    text: format!("{}: {}", o.id, global.text),
                });
            }
            for (c, report) in o.constraints.iter().zip(placed.constraints.iter().skip(1)) {
                if report.measure.satisfied {
                    continue;
                }
                let target = solved.layout.floor.iter().find(|p| p.index == c.target);
                // A relation to an object left out has nothing to measure: say so, never
                // "NaN m".
                let measured = match (target, report.measure.value.is_finite()) {
                    (Some(_), true) => {
                        format!("{:.2} {}", report.measure.value, report.measure.unit)
                    }
                    (None, _) => format!(
                        "`{}` is left out",
                        problem.objects.get(c.target).map_or("its target", |t| t.id.as_str())
                    ),
                    (Some(_), false) => "not measured".to_string(),
                };
                d.violations.push(DrawViolation {
                    from: [placed.pose.x, placed.pose.z],
                    to: target.map(|t| [t.pose.x, t.pose.z]),
                    text: format!("{}: {} ({measured})", o.id, report.text),
                });
            }
        }
        for u in &solved.layout.unplaced {
            d.left_out.push(LeftOut {
                name: u.id.split('|').next().unwrap_or(&u.id).to_string(),
                reason: u.reason.clone(),
            });
        }
    }
    d
}

/// A name as people write it: `sectional_sofa` (a key of an imported answer) is `sectional sofa`.
fn spoken(name: &str) -> String {
    name.replace('_', " ")
}

/// A short name for a long description: its last two words (`round flush mount ceiling
/// light` → `ceiling light`), or all of it when it has no more.
fn short_name(description: &str) -> String {
    let words: Vec<&str> = description.split_whitespace().collect();
    words[words.len().saturating_sub(2)..].join(" ")
}

/// Gives the floor, wall and ceiling objects of a room that share a name their instance
/// number (`dining chair 0`, `dining chair 1`), and those still alike (two groups of one
/// category) their identifier; items on top keep their name (they are counted instead).
fn number_alike(objects: &mut [DrawObject], rooms: &[String], numbers: &[Option<u32>]) {
    let alike = |objects: &[DrawObject], i: usize| {
        objects.iter().enumerate().any(|(j, o)| {
            j != i
                && o.level != ObjectLevel::Small
                && rooms[j] == rooms[i]
                && o.label == objects[i].label
        })
    };
    let numbered: Vec<Option<String>> = (0..objects.len())
        .map(|i| {
            let o = &objects[i];
            (o.level != ObjectLevel::Small && alike(objects, i)).then(|| match numbers[i] {
                Some(n) => format!("{} {n}", o.label),
                None => o.name.clone(),
            })
        })
        .collect();
    for (o, label) in objects.iter_mut().zip(numbered) {
        if let Some(label) = label {
            o.label = label;
        }
    }
    let still: Vec<bool> = (0..objects.len())
        .map(|i| objects[i].level != ObjectLevel::Small && alike(objects, i))
        .collect();
    for (o, same) in objects.iter_mut().zip(still) {
        if same {
            o.label.clone_from(&o.name);
        }
    }
}
