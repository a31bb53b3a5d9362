//! The build report (`holoc build --report report.json`): for every object, the chosen asset
//! with its score parts and runner-up, its pose, each constraint satisfied or violated with the
//! measured value, and every object that was left out with the reason.
//!
//! **Invariant:** the report is built from the stages' values with `serde_json::json!`; the
//! internal types are not `Serialize`. Object order is the scene's; numbers are rounded to
//! 1e-4 so that the report is stable.

pub mod pins;

use crate::compile::Built;
use crate::lower::{LoweredObject, Source};
use crate::resolve::Catalog;
use serde_json::{json, Map, Value};
use std::collections::{BTreeMap, VecDeque};

/// The version of the report's format; raised on any change to it.
pub const REPORT_VERSION: u32 = 3;

fn r4(v: f64) -> f64 {
    let r = (v * 10_000.0).round() / 10_000.0;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// Builds the report of a build.
pub fn report(built: &Built, catalog: &Catalog) -> Value {
    // Every object of the house by what of the scene it is, and by its id in the layout (in
    // the layout's order: two things of one id in one room are met in the same order).
    let house_of: BTreeMap<Source, &LoweredObject> =
        built.objects.iter().map(|o| (o.source, o)).collect();
    let mut by_layout_id: BTreeMap<
        (crate::check::scene::RoomId, String),
        VecDeque<&LoweredObject>,
    > = BTreeMap::new();
    for o in &built.objects {
        by_layout_id.entry((o.room, o.layout_id.clone())).or_default().push_back(o);
    }
    // Every thing moved to another receptacle (W0506): where from, where to, the `p` of the
    // pair.
    let mut moved: BTreeMap<Source, Value> = BTreeMap::new();
    for solved in &built.layout.rooms {
        let p = &solved.problem;
        for m in &solved.layout.moved {
            let Some(&(declared, line, copy)) = solved.small_keys.get(m.small) else { continue };
            let source = Source::Item(declared, line, copy);
            let from = m.absent.clone().unwrap_or_else(|| p.holder_name(m.from).to_string());
            moved.insert(
                source,
                json!({
                    "from": from,
                    "to": p.holder_name(m.to),
                    "toHouseId": house_of.get(&source).and_then(|o| o.parent.clone()),
                    "p": m.p.map(r4),
                    "code": crate::diag::Code::W0506.as_str(),
                }),
            );
        }
    }
    // The fields the layout adds to an entry of the assets: its id in the house and in the
    // layout, and for a thing on top the receptacle it is on and, when moved, the move.
    let placed = |source: Source| -> Map<String, Value> {
        let mut m = Map::new();
        let house = house_of.get(&source);
        m.insert("houseId".into(), json!(house.map(|o| o.id.clone())));
        let layout_id = match (house, source) {
            (Some(o), _) => Some(o.layout_id.clone()),
            (None, Source::Item(id, line, copy)) => crate::solve::item_ids(built.scene.object(id))
                .into_iter()
                .find(|(_, l, c)| *l == line && *c == copy)
                .map(|(name, ..)| name),
            (None, Source::Object(id)) => Some(built.scene.object(id).name.clone()),
            (None, Source::Ceiling(_)) => None,
        };
        m.insert("layoutId".into(), json!(layout_id));
        if let Source::Item(..) = source {
            m.insert("placedOn".into(), json!(house.and_then(|o| o.parent.clone())));
            m.insert("moved".into(), moved.get(&source).cloned().unwrap_or(Value::Null));
        }
        m
    };
    let assets = crate::resolve::report(&built.scene, catalog, &built.resolved, &placed);
    let mut rooms = Vec::new();
    for solved in &built.layout.rooms {
        let room = built.scene.room(solved.room);
        // The id in the house of an object of the layout, met in the layout's order.
        let mut house_id = |layout_id: &str| -> Option<&LoweredObject> {
            by_layout_id
                .get_mut(&(solved.room, layout_id.to_string()))
                .and_then(VecDeque::pop_front)
        };
        let mut floor = Vec::new();
        for placed in &solved.layout.floor {
            let object = &solved.problem.objects[placed.index];
            let constraints: Vec<Value> = placed
                .constraints
                .iter()
                .map(|c| {
                    json!({
                        "constraint": c.text,
                        "satisfied": c.measure.satisfied,
                        "measured": r4(c.measure.value),
                        "unit": c.measure.unit,
                        "score": r4(c.measure.score),
                        "range": c.range.map(|(lo, hi)| json!([r4(lo), hi.is_finite().then(|| r4(hi))])),
                    })
                })
                .collect();
            floor.push(json!({
                "object": object.id,
                "house_id": house_id(&object.id).map(|o| o.id.clone()),
                "position": {"x": r4(placed.pose.x), "z": r4(placed.pose.z)},
                "rotation": placed.pose.rot.deg(),
                "footprint": {
                    "min_x": r4(placed.footprint.min_x), "min_z": r4(placed.footprint.min_z),
                    "max_x": r4(placed.footprint.max_x), "max_z": r4(placed.footprint.max_z),
                },
                "score": r4(placed.score),
                "placed_by": placed.by,
                "constraints": constraints,
            }));
        }
        let mut others = |list: &[crate::solve::PlacedObject]| -> Vec<Value> {
            list.iter()
                .map(|p| {
                    let house = house_id(&p.id);
                    let mut entry = json!({
                        "object": p.id,
                        "house_id": house.map(|o| o.id.clone()),
                        "position": {"x": r4(p.position_m[0]), "y": r4(p.position_m[1]), "z": r4(p.position_m[2])},
                        "rotation": r4(p.rotation_deg),
                    });
                    if let (Some(o), Some(map)) = (house, entry.as_object_mut()) {
                        if o.parent.is_some() {
                            map.insert("on".into(), json!(o.parent));
                            map.insert(
                                "moved".into(),
                                moved.get(&o.source).cloned().unwrap_or(Value::Null),
                            );
                        }
                    }
                    entry
                })
                .collect()
        };
        let unplaced: Vec<Value> = solved
            .layout
            .unplaced
            .iter()
            .map(|u| {
                json!({
                    "object": u.id,
                    "kind": u.kind,
                    "code": u.code.as_str(),
                    "rule": u.rule.map(crate::solve::HardRule::describe),
                    "reason": u.reason,
                })
            })
            .collect();
        let wall_objects = others(&solved.layout.wall);
        let small_objects = others(&solved.layout.small);
        let ceiling = solved.layout.ceiling.as_ref().map(|c| others(std::slice::from_ref(c)));
        let (satisfied, total) = solved.layout.constraint_tally(&solved.problem);
        let planned = built.plan.room(solved.room);
        let structure = crate::resolve::structure::StructureCatalog::builtin();
        let material = |pin: &Option<crate::check::Pinned>, design: &Option<String>, name: &str| {
            json!({
                "design": design,
                "pinned": pin.is_some(),
                "material": name,
                "words": design.as_deref().map_or_else(Vec::new, |d| structure.deciding_words(d, name)),
            })
        };
        rooms.push(json!({
            "room": room.name,
            "label": room.label,
            "materials": {
                "floor": material(&room.floor_material, &room.floor_design, &planned.floor_material),
                "walls": material(&room.wall_material, &room.wall_design, &planned.wall_material),
            },
            "floor_objects": floor,
            "wall_objects": wall_objects,
            "small_objects": small_objects,
            "ceiling": ceiling,
            "not_placed": unplaced,
            "relations_given_up": solved.given_up.iter().map(|g| json!({
                "object": g.object,
                "relation": g.relation,
                "reason": g.reason,
            })).collect::<Vec<Value>>(),
            "ceiling_light": built.resolved.ceiling_lights.get(&solved.room).map(|d| json!({
                "description": d,
                "served_by": format!("light|{}", built.plan.room(solved.room).thor_id),
            })),
            "constraints_satisfied": satisfied,
            "constraints_total": total,
            "search_nodes": solved.layout.nodes,
        }));
    }
    let mut report = json!({
        "version": REPORT_VERSION,
        "request": built.scene.request,
        "seed": built.scene.seed,
        "assets": assets,
        "layout": rooms,
    });
    let made = made_assets(built);
    if let (false, Some(map)) = (made.is_empty(), report.as_object_mut()) {
        map.insert("madeAssets".into(), Value::Array(made));
    }
    report
}

/// The assets the build made (`crate::make`), by uid: the house objects that use each, its
/// kind and generator, its size, parameters, parts and AI2-THOR properties.
fn made_assets(built: &Built) -> Vec<Value> {
    let made =
        crate::make::used_in(&built.resolved, built.objects.iter().map(|o| o.asset_id.as_str()));
    made.iter()
        .map(|m| {
            let objects: Vec<&str> = built
                .objects
                .iter()
                .filter(|o| o.asset_id == m.uid)
                .map(|o| o.id.as_str())
                .collect();
            let [w, h, d] = m.bbox_m();
            json!({
                "uid": m.uid,
                "objects": objects,
                "kind": m.kind,
                "generator": format!("make::{}::{}", m.family, m.kind),
                "objectType": m.object_type,
                "sizeM": {"width": r4(w), "depth": r4(d), "height": r4(h)},
                "parameters": m.params,
                "parts": m.parts.iter().map(|(name, swatch)| json!({
                    "part": name,
                    "material": m.palette[*swatch].material.name(),
                    "color": m.palette[*swatch].hex(),
                })).collect::<Vec<_>>(),
                "primaryProperty": m.thor.primary(),
                "secondaryProperties": m.thor.secondary(),
                "triangles": m.mesh.triangles.len() / 3,
            })
        })
        .collect()
}

/// Adds the folder the made assets were written to (`<folder>/<uid>/`) to each entry of a
/// report's `madeAssets`, or `null` when they were not written.
pub fn add_made_folder(report: &mut Value, folder: Option<&std::path::Path>) {
    let Some(list) = report.get_mut("madeAssets").and_then(Value::as_array_mut) else { return };
    for entry in list {
        let uid = entry.get("uid").and_then(Value::as_str).unwrap_or_default().to_string();
        if let Some(map) = entry.as_object_mut() {
            map.insert(
                "folder".into(),
                folder.map_or(Value::Null, |f| json!(f.join(&uid).display().to_string())),
            );
        }
    }
}

/// What a build made, in the counts `holoc build` prints on its last line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Summary {
    /// Rooms in the house.
    pub rooms: usize,
    /// Objects the scene asks for: floor and wall objects, items on top, ceiling objects.
    pub asked: usize,
    /// Objects in the house.
    pub placed: usize,
    /// Relations (and global placements) the layout keeps.
    pub relations_kept: usize,
    /// Relations (and global placements) of every placed floor object.
    pub relations_total: usize,
    /// Ceiling lights without an asset that the rooms' lights stand for.
    pub lights: usize,
}

impl Summary {
    /// Counts a finished build.
    pub fn of(built: &Built) -> Summary {
        let resolved = &built.resolved;
        let lights = resolved.ceiling_lights.len();
        let asked = resolved.objects.len()
            + resolved.ceilings.len()
            + resolved.small.values().map(Vec::len).sum::<usize>()
            - lights;
        let (relations_kept, relations_total) = built
            .layout
            .rooms
            .iter()
            .map(|r| r.layout.constraint_tally(&r.problem))
            .fold((0, 0), |(a, b), (c, d)| (a + c, b + d));
        Summary {
            rooms: built.house.house.rooms.len(),
            asked,
            placed: built.house.object_count(),
            relations_kept,
            relations_total,
            lights,
        }
    }

    /// Objects asked for that are not in the house.
    pub fn left_out(&self) -> usize {
        self.asked.saturating_sub(self.placed)
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plural =
            |n: usize, one: &'static str, many: &'static str| if n == 1 { one } else { many };
        write!(
            f,
            "{} {}, {} of {} objects placed",
            self.rooms,
            plural(self.rooms, "room", "rooms"),
            self.placed,
            self.asked
        )?;
        if self.left_out() > 0 {
            write!(f, " ({} left out)", self.left_out())?;
        }
        write!(f, ", {} of {} relations kept", self.relations_kept, self.relations_total)?;
        match self.lights {
            0 => Ok(()),
            1 => write!(f, ", 1 ceiling light as its room's light"),
            n => write!(f, ", {n} ceiling lights as their rooms' lights"),
        }
    }
}

/// Makes the paths a report holds portable (a golden report is committed and compared on other
/// machines): every catalog's `path` and `folder`, an objathor folder's `files`, and each made
/// asset's `folder` become relative to `base` (the folder of `holoc.toml`, else the current
/// folder) when they are inside it, else their last component.
pub fn portable_paths(report: &mut Value, base: &std::path::Path) {
    portable_catalog_paths(report, base);
    if let Some(list) = report.get_mut("madeAssets").and_then(Value::as_array_mut) {
        for m in list {
            if let Some(v) = m.get_mut("folder") {
                portable(v, base);
            }
        }
    }
}

/// The catalog paths of [`portable_paths`] alone (what `holoc build --report` writes: the made
/// assets' folder stays where the house's assets are).
pub fn portable_catalog_paths(report: &mut Value, base: &std::path::Path) {
    let lock = match report.get("assets").and_then(|a| a.get("catalogs")) {
        Some(_) => report.get_mut("assets").and_then(|a| a.get_mut("catalogs")),
        None => report.get_mut("catalogs"),
    };
    for c in lock.and_then(Value::as_array_mut).into_iter().flatten() {
        for key in ["path", "folder"] {
            if let Some(v) = c.get_mut(key) {
                portable(v, base);
            }
        }
        for f in c.get_mut("files").and_then(Value::as_array_mut).into_iter().flatten() {
            if let Some(v) = f.get_mut("path") {
                portable(v, base);
            }
        }
    }
}

/// `v` (a path, or not a string) relative to `base` when inside it, else its last component.
fn portable(v: &mut Value, base: &std::path::Path) {
    let Some(text) = v.as_str() else { return };
    let path = std::path::Path::new(text);
    let rel = if path.is_absolute() {
        match path.strip_prefix(base) {
            Ok(rel) => rel.to_path_buf(),
            Err(_) => path.file_name().map(std::path::PathBuf::from).unwrap_or_default(),
        }
    } else {
        path.strip_prefix(".").unwrap_or(path).to_path_buf()
    };
    *v = json!(rel.display().to_string().replace('\\', "/"));
}

#[cfg(test)]
mod portable_tests {
    use super::portable_paths;
    use serde_json::json;

    #[test]
    fn paths_inside_the_project_become_relative_and_others_their_file_name() {
        let mut report = json!({"assets": {
            "catalogs": [
                {"name": "holoc", "path": null},
                {"name": "mine", "path": "/home/me/project/catalogs/mine.json"},
                {"name": "theirs", "path": "/opt/shared/theirs.json.gz"},
                {"name": "local", "path": "./here.json"}
            ]},
            "madeAssets": [{"uid": "a", "folder": "/home/me/project/out/house.assets/a"}]
        });
        portable_paths(&mut report, std::path::Path::new("/home/me/project"));
        let lock = &report["assets"]["catalogs"];
        assert_eq!(lock[0]["path"], json!(null));
        assert_eq!(lock[1]["path"], "catalogs/mine.json");
        assert_eq!(lock[2]["path"], "theirs.json.gz");
        assert_eq!(lock[3]["path"], "here.json");
        assert_eq!(report["madeAssets"][0]["folder"], "out/house.assets/a");
    }
}
