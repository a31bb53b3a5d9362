//! From the solver's [`Layout`] to the objects of the house: one [`LoweredObject`] per placed
//! floor, wall, small and ceiling object that has an asset, with its AI2-THOR id, pose,
//! `kinematic` flag and, for an item on top of another object, the receptacle it is nested under.
//!
//! Floor, wall and ceiling objects are kinematic (they stay where the layout put them, as
//! ProcTHOR's furniture does); items on a floor receptacle are not (ProcTHOR leaves them to
//! physics, so an agent can pick them up); items on a wall object (a towel on its holder, a
//! plant on a wall shelf) are, so that they stay where they hang, and so are items that break
//! (objathor's `CanBreak`), as the original keeps them.

use super::LoweredObject;
use crate::check::scene::Scene;
use crate::plan::FloorPlan;
use crate::resolve::{Resolution, Resolved};
use crate::solve::Layout;
use std::collections::{BTreeMap, BTreeSet};

fn round6(v: f64) -> f64 {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn position(p: [f64; 3]) -> [f64; 3] {
    [round6(p[0]), round6(p[1]), round6(p[2])]
}

/// The objects of the house: floor, wall, small and ceiling objects, room by room.
pub fn objects(
    layout: &Layout,
    scene: &Scene,
    plan: &FloorPlan,
    resolved: &Resolved,
) -> Vec<LoweredObject> {
    let mut out = Vec::new();
    for solved in &layout.rooms {
        let label = &plan.room(solved.room).thor_id;
        // Floor and wall objects: the placed ones, matched to the scene by instance name.
        let floor_names: Vec<&str> = solved.problem.objects.iter().map(|o| o.id.as_str()).collect();
        let wall_names: Vec<&str> =
            solved.problem.wall_objects.iter().map(|o| o.id.as_str()).collect();
        for (placed_list, names, ids) in [
            (&solved.layout.floor_world, &floor_names, &solved.floor_ids),
            (&solved.layout.wall, &wall_names, &solved.wall_ids),
        ] {
            for placed in placed_list {
                let Some(index) = names.iter().position(|n| *n == placed.id) else { continue };
                let id = ids[index];
                let Some(choice) = resolved.object(id) else { continue };
                let name = &scene.object(id).name;
                out.push(LoweredObject {
                    id: format!("{name} ({label})"),
                    asset_id: choice.asset_id.clone(),
                    room: solved.room,
                    position_m: position(placed.position_m),
                    rotation_deg: [0.0, placed.rotation_deg, 0.0],
                    kinematic: true,
                    object_name: name.clone(),
                    parent: None,
                    source: super::Source::Object(id),
                    layout_id: placed.id.clone(),
                });
            }
        }
        // Small objects: the problem lists them in the order of `small_keys`; ids may repeat
        // (two `on top` lines naming the same item), so they are matched in order.
        let mut by_id: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
        for (i, s) in solved.problem.small_objects.iter().enumerate().rev() {
            by_id.entry(s.id.as_str()).or_default().push(i);
        }
        // A thing moved to another receptacle (W0506) is named by where it is; when that name
        // is taken by a thing declared there, it takes the next free number.
        let declared: BTreeSet<&str> = (solved.problem.small_objects.iter())
            .filter(|s| s.elsewhere.is_none() && s.absent.is_none())
            .map(|s| s.id.as_str())
            .collect();
        let mut taken: BTreeSet<String> = (solved.layout.small.iter())
            .filter(|p| declared.contains(p.id.as_str()))
            .map(|p| p.id.clone())
            .collect();
        for placed in &solved.layout.small {
            let Some(index) = by_id.get_mut(placed.id.as_str()).and_then(Vec::pop) else {
                continue;
            };
            let small = &solved.problem.small_objects[index];
            let (declared, line, copy) = solved.small_keys[index];
            let receptacle = declared;
            let Some(choice) = resolved
                .small
                .get(&(receptacle, line))
                .and_then(|v| v.get(copy as usize))
                .and_then(Resolution::choice)
            else {
                continue;
            };
            // The receptacle it stands on: the one declared, or the one it was moved to.
            let receptacle = match placed.on {
                Some(crate::solve::Holder::Floor(i)) => solved.floor_ids.get(i).copied(),
                Some(crate::solve::Holder::Wall(i)) => solved.wall_ids.get(i).copied(),
                None => None,
            }
            .unwrap_or(receptacle);
            let receptacle_name = &scene.object(receptacle).name;
            let mut name = placed.id.split('|').next().unwrap_or(&placed.id).to_string();
            if small.elsewhere.is_some() || small.absent.is_some() {
                let mut n = 0;
                while taken.contains(&format!("{name}|{receptacle_name}")) {
                    name = format!("{}-{n}", small.item);
                    n += 1;
                }
                taken.insert(format!("{name}|{receptacle_name}"));
            }
            out.push(LoweredObject {
                id: format!("{name}|{receptacle_name} ({label})"),
                asset_id: choice.asset_id.clone(),
                room: solved.room,
                position_m: position(placed.position_m),
                rotation_deg: [0.0, placed.rotation_deg, 0.0],
                // As ProcTHOR: what stands on a floor receptacle is left to physics; what hangs
                // on or stands on a wall object stays put (physics would drop a towel off its
                // bar); so does one that breaks (an objathor asset with `CanBreak`, as the
                // original keeps it).
                kinematic: matches!(placed.on, Some(crate::solve::Holder::Wall(_)))
                    || choice.breakable,
                object_name: name,
                parent: Some(format!("{receptacle_name} ({label})")),
                source: super::Source::Item(declared, line, copy),
                layout_id: placed.id.clone(),
            });
        }
        if let (Some(placed), Some(choice)) = (
            &solved.layout.ceiling,
            resolved.ceilings.get(&solved.room).and_then(Resolution::choice),
        ) {
            out.push(LoweredObject {
                id: format!("ceiling ({label})"),
                asset_id: choice.asset_id.clone(),
                room: solved.room,
                position_m: position(placed.position_m),
                rotation_deg: [0.0, placed.rotation_deg, 0.0],
                kinematic: true,
                object_name: "ceiling".to_string(),
                parent: None,
                source: super::Source::Ceiling(solved.room),
                layout_id: placed.id.clone(),
            });
        }
    }
    out
}
