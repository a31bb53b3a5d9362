//! A human-readable dump of a checked scene (`holoc build --emit scene`, the check snapshots).

use super::scene::{DoorSide, Placement, Scene};
use std::fmt::Write as _;

/// Prints a number with at most 4 decimals, without trailing zeros.
fn num(v: f64) -> String {
    let r = (v * 10_000.0).round() / 10_000.0;
    crate::ast::format_number(if r == 0.0 { 0.0 } else { r })
}

/// Dumps a scene, one fact per line, in declaration order.
pub fn dump(scene: &Scene) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scene request={:?} wall_height={} m seed={}",
        scene.request.as_deref().unwrap_or(""),
        num(scene.wall_height_m),
        scene.seed
    );
    for room in &scene.rooms {
        let corners: Vec<String> =
            room.corners.iter().map(|[x, z]| format!("({}, {})", num(*x), num(*z))).collect();
        let _ = writeln!(out, "room #{} {} {:?}", room.id.0, room.name, room.label);
        let _ = writeln!(out, "  corners m {}", corners.join(" "));
        if let Some(f) = &room.floor_design {
            let _ = writeln!(out, "  floor {f:?}");
        }
        if let Some(w) = &room.wall_design {
            let _ = writeln!(out, "  walls {w:?}");
        }
        if let Some(p) = &room.floor_material {
            let _ = writeln!(out, "  floor material {:?}", p.id);
        }
        if let Some(p) = &room.wall_material {
            let _ = writeln!(out, "  wall material {:?}", p.id);
        }
        for w in &room.windows {
            let _ = writeln!(
                out,
                "  window {} {} {} x {} m count {} sill {} m{}",
                w.wall.as_str(),
                w.kind.as_str(),
                num(w.width_m),
                num(w.height_m),
                w.count,
                num(w.sill_m),
                w.asset.as_ref().map(|a| format!(" asset {:?}", a.id)).unwrap_or_default()
            );
        }
        for id in &room.objects {
            let o = scene.object(*id);
            let kind = if o.is_floor() { "floor" } else { "wall" };
            let mut line = format!("  #{} {kind} {} {:?}", o.id.0, o.name, o.category);
            if let Some(d) = &o.description {
                let _ = write!(line, " desc={d:?}");
            }
            if let Some([w, d, h]) = o.size_m {
                let _ = write!(line, " size={}x{}x{}", num(w), num(d), num(h));
            }
            if o.group_count > 1 {
                let _ = write!(line, " {}", o.variance.as_str());
            }
            if let Some(a) = &o.asset {
                let _ = write!(line, " asset={:?}", a.id);
            }
            if let Some([x, z]) = o.at {
                let _ = write!(line, " at=({}, {})", num(x), num(z));
            }
            if let Some(f) = o.facing_deg {
                let _ = write!(line, " facing={}", num(f));
            }
            let _ = writeln!(out, "{line}");
            match &o.placement {
                Placement::Floor { global, constraints } => {
                    let g = global.map_or("(none)", |g| match g.kind {
                        super::scene::GlobalKind::Edge => "edge",
                        super::scene::GlobalKind::Middle => "middle",
                    });
                    let cs: Vec<String> = constraints
                        .iter()
                        .map(|c| format!("{} {}", c.kind.as_str(), scene.object(c.target).name))
                        .collect();
                    let _ = writeln!(
                        out,
                        "    global {g}; {}",
                        if cs.is_empty() { "no relations".into() } else { cs.join(", ") }
                    );
                }
                Placement::Wall { above, height_m } => {
                    let _ = writeln!(
                        out,
                        "    above {} height {}",
                        above.map_or("(none)".to_string(), |(t, _)| scene.object(t).name.clone()),
                        height_m.map_or("(solver)".to_string(), |h| format!("{} m", num(h)))
                    );
                }
            }
            for item in &o.on_top {
                let _ = writeln!(
                    out,
                    "    on top {:?} x{} {}{}",
                    item.item,
                    item.count,
                    item.variance.as_str(),
                    item.asset.as_ref().map(|a| format!(" asset {:?}", a.id)).unwrap_or_default()
                );
            }
        }
        if let Some(c) = &room.ceiling {
            let _ = writeln!(
                out,
                "  ceiling {:?}{}",
                c.description,
                c.above
                    .map(|(t, _)| format!(" above {}", scene.object(t).name))
                    .unwrap_or_default()
            );
        }
    }
    for d in &scene.doors {
        let side = |s: DoorSide| match s {
            DoorSide::Exterior => "exterior".to_string(),
            DoorSide::Room(r) => scene.room(r).name.clone(),
        };
        let _ = writeln!(
            out,
            "door #{} {} -- {} {}{}{}",
            d.index,
            side(d.from),
            side(d.to),
            d.kind.as_str(),
            d.size.map(|s| format!(" {}", s.as_str())).unwrap_or_default(),
            d.style.as_ref().map(|s| format!(" {s:?}")).unwrap_or_default()
        );
    }
    out
}
