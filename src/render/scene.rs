//! Making a [`Drawing`] from a finished build.
//!
//! The objects drawn are the house's objects, at the house's positions: the plan shows exactly
//! what AI2-THOR loads. The layout supplies what the house does not say (footprint sizes, which
//! level an object stands on, the relations it keeps); the resolutions and the layout supply
//! what was left out and why.

use super::{
    DrawDoor, DrawObject, DrawRoom, DrawSegment, DrawViolation, Drawing, LeftOut, ObjectLevel,
};
use crate::check::scene::DoorKind;
use crate::compile::Built;

/// What the layout knows of one object the house may hold.
struct Known {
    name: String,
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
        d.doors.push(DrawDoor {
            opening: DrawSegment { a, b },
            swing,
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
        let mut list = Vec::new();
        for placed in &solved.layout.floor {
            let o = &problem.objects[placed.index];
            list.push(Known {
                name: o.id.clone(),
                size: o.size,
                level: ObjectLevel::Floor,
                used: false,
            });
        }
        for p in &solved.layout.wall {
            let size = problem
                .wall_objects
                .iter()
                .find(|w| w.id == p.id)
                .map_or([0.2, 0.2], |w| [w.size[0], w.size[1]]);
            list.push(Known { name: p.id.clone(), size, level: ObjectLevel::Wall, used: false });
        }
        for p in &solved.layout.small {
            let size = problem
                .small_objects
                .iter()
                .find(|s| s.id == p.id)
                .map_or([0.2, 0.2], |s| [s.size[0], s.size[1]]);
            list.push(Known {
                name: p.id.split('|').next().unwrap_or(&p.id).to_string(),
                size,
                level: ObjectLevel::Small,
                used: false,
            });
        }
        if let (Some(_), Some(c)) = (&solved.layout.ceiling, &problem.ceiling) {
            list.push(Known {
                name: "ceiling".to_string(),
                size: [c.size[0], c.size[1]],
                level: ObjectLevel::Ceiling,
                used: false,
            });
        }
        known.push((plan.room(solved.room).thor_id.clone(), list));
    }

    for object in built.house.all_objects() {
        let entry = known
            .iter_mut()
            .filter(|(room, _)| *room == object.room_id)
            .flat_map(|(_, list)| list.iter_mut())
            .find(|k| !k.used && k.name == object.object_name);
        let (size, level) = match entry {
            Some(k) => {
                k.used = true;
                (k.size, k.level)
            }
            // The house holds something the layout does not describe: drawn small, never
            // hidden.
            None => ([0.2, 0.2], ObjectLevel::Small),
        };
        d.objects.push(DrawObject {
            name: object.object_name.clone(),
            center: [object.position.x, object.position.z],
            size,
            facing_deg: object.rotation.y,
            level,
        });
    }

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
                d.violations.push(DrawViolation {
                    from: [placed.pose.x, placed.pose.z],
                    to: target.map(|t| [t.pose.x, t.pose.z]),
                    text: format!(
                        "{}: {} ({:.2} {})",
                        o.id, report.text, report.measure.value, report.measure.unit
                    ),
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
