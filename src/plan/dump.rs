//! The human-readable plan dump (`holoc build --emit plan`, snapshots).

use std::fmt::Write as _;

use super::{FloorPlan, HoleKind};
use crate::check::scene::Scene;
use crate::geometry::Point;

fn f(v: f64) -> String {
    let s = format!("{v:.3}");
    if s == "-0.000" {
        "0.000".to_owned()
    } else {
        s
    }
}

fn p(pt: Point) -> String {
    format!("({}, {})", f(pt[0]), f(pt[1]))
}

fn poly(points: &[Point]) -> String {
    points.iter().map(|&q| p(q)).collect::<Vec<_>>().join(" ")
}

pub(crate) fn dump(plan: &FloorPlan, scene: &Scene) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "plan: {} room{}, wall height {} m, seed {}",
        plan.rooms.len(),
        if plan.rooms.len() == 1 { "" } else { "s" },
        f(plan.wall_height_m),
        plan.seed
    );
    for r in &plan.rooms {
        let name = scene.rooms.get(r.id.0).map_or("?", |s| s.name.as_str());
        let _ = writeln!(out, "room {name} id `{}` layer Procedural{}", r.thor_id, r.layer);
        let _ = writeln!(out, "  corners  {}", poly(&r.corners));
        let _ = writeln!(out, "  polygon  {}", poly(&r.polygon));
        let _ = writeln!(out, "  area {} m², centroid {}", f(r.area_m2), p(r.centroid));
        let tint = |t: &Option<crate::resolve::colors::Color>| {
            t.as_ref().map(|c| format!(" tinted {} {}", c.phrase, c.hex())).unwrap_or_default()
        };
        let _ = writeln!(
            out,
            "  floor `{}`{}, walls `{}`{}",
            r.floor_material,
            tint(&r.floor_tint),
            r.wall_material,
            tint(&r.wall_tint)
        );
        for b in &r.door_keep_out {
            let _ = writeln!(out, "  door keep-out  {}", poly(b));
        }
        for b in &r.open_boxes {
            let _ = writeln!(out, "  open keep-out  {}", poly(b));
        }
        for (a, b) in &r.window_segments {
            let _ = writeln!(out, "  window  {} → {}", p(*a), p(*b));
        }
    }
    let _ = writeln!(out, "walls:");
    for w in &plan.walls {
        let mut line = format!("  {}  {} → {}  {} m", w.id, p(w.start), p(w.end), f(w.width_m));
        match &w.neighbour {
            Some((_, other)) => {
                let _ = write!(line, "  shared with {other}");
            }
            None => line.push_str("  exterior"),
        }
        if w.empty {
            line.push_str("  empty");
        }
        if let Some(h) = &w.hole {
            let kind = match h.kind {
                HoleKind::Door => "door",
                HoleKind::Window => "window",
            };
            let _ = write!(
                line,
                "  {kind} hole {}–{} × {}–{}",
                f(h.start_m),
                f(h.end_m),
                f(h.bottom_m),
                f(h.top_m)
            );
        }
        let _ = writeln!(out, "{line}");
    }
    let _ = writeln!(out, "doors:");
    for d in &plan.doors {
        let _ = writeln!(
            out,
            "  {}  {} {}  {} / {}  hole {}–{}  asset at {}  openable {}",
            d.id,
            d.kind.as_str(),
            d.asset_id,
            d.wall0,
            d.wall1,
            p(d.hole_min),
            p(d.hole_max),
            p(d.asset_position),
            d.openable
        );
    }
    let _ = writeln!(out, "windows:");
    for w in &plan.windows {
        let _ = writeln!(
            out,
            "  {}  {}  hole {}–{}  asset at {}",
            w.id,
            w.asset_id,
            p(w.hole_min),
            p(w.hole_max),
            p(w.asset_position)
        );
    }
    let _ = writeln!(out, "open connections:");
    for o in &plan.open_connections {
        let a = plan.rooms.get(o.rooms.0 .0).map_or("?", |r| r.thor_id.as_str());
        let b = plan.rooms.get(o.rooms.1 .0).map_or("?", |r| r.thor_id.as_str());
        let segs: Vec<String> =
            o.segments.iter().map(|(s, e)| format!("{} → {}", p(*s), p(*e))).collect();
        let _ = writeln!(out, "  {a} -- {b}  {}", segs.join(", "));
    }
    let _ = writeln!(
        out,
        "skybox {} ({}), ceiling `{}`",
        plan.skybox, plan.time_of_day, plan.ceiling_material
    );
    let agent_room = plan.rooms.get(plan.agent.room.0).map_or("?", |r| r.thor_id.as_str());
    let _ = writeln!(
        out,
        "agent in `{agent_room}` at {}, facing {}°",
        p(plan.agent.position),
        f(plan.agent.rotation_deg)
    );
    out
}
