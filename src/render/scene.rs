//! Making a [`Drawing`] from a finished build.

use super::{DrawDoor, DrawObject, DrawRoom, DrawSegment, DrawViolation, Drawing, ObjectLevel};
use crate::check::scene::DoorKind;
use crate::compile::Built;

/// The drawing of a build: its plan, its layout and what the layout does not keep.
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
    for solved in &built.layout.rooms {
        let problem = &solved.problem;
        for placed in &solved.layout.floor {
            let o = &problem.objects[placed.index];
            d.objects.push(DrawObject {
                name: o.id.clone(),
                center: [placed.pose.x, placed.pose.z],
                size: o.size,
                facing_deg: placed.pose.rot.deg(),
                level: ObjectLevel::Floor,
            });
            // The first report is the global constraint; the others follow the object's
            // relations in order.
            for (c, report) in o.constraints.iter().zip(placed.constraints.iter().skip(1)) {
                if report.measure.satisfied {
                    continue;
                }
                if let Some(target) = solved.layout.floor.iter().find(|p| p.index == c.target) {
                    d.violations.push(DrawViolation {
                        from: [placed.pose.x, placed.pose.z],
                        to: [target.pose.x, target.pose.z],
                        text: format!(
                            "{}: {} ({:.2} {})",
                            o.id, report.text, report.measure.value, report.measure.unit
                        ),
                    });
                }
            }
            if let Some(global) = placed.constraints.first().filter(|g| !g.measure.satisfied) {
                d.unplaced.push(format!("{} does not keep `{}`", o.id, global.text));
            }
        }
        for (list, sizes, level) in [
            (
                &solved.layout.wall,
                problem
                    .wall_objects
                    .iter()
                    .map(|w| (w.id.as_str(), [w.size[0], w.size[1]]))
                    .collect::<Vec<_>>(),
                ObjectLevel::Wall,
            ),
            (
                &solved.layout.small,
                problem
                    .small_objects
                    .iter()
                    .map(|s| (s.id.as_str(), [s.size[0], s.size[1]]))
                    .collect(),
                ObjectLevel::Small,
            ),
        ] {
            for p in list {
                let size = sizes.iter().find(|(id, _)| *id == p.id).map_or([0.2, 0.2], |(_, s)| *s);
                d.objects.push(DrawObject {
                    name: p.id.split('|').next().unwrap_or(&p.id).to_string(),
                    center: [p.position_m[0], p.position_m[2]],
                    size,
                    facing_deg: p.rotation_deg,
                    level,
                });
            }
        }
        if let (Some(p), Some(c)) = (&solved.layout.ceiling, &problem.ceiling) {
            d.objects.push(DrawObject {
                name: "ceiling".to_string(),
                center: [p.position_m[0], p.position_m[2]],
                size: [c.size[0], c.size[1]],
                facing_deg: p.rotation_deg,
                level: ObjectLevel::Ceiling,
            });
        }
        for u in &solved.layout.unplaced {
            d.unplaced.push(format!("{} `{}`: {}", u.kind, u.id, u.reason));
        }
    }
    d
}
