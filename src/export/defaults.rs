//! AI2-THOR's defaults for what a house may leave out.
//!
//! `holoc validate` accepts houses that ProcTHOR, Holodeck and other tools write, and AI2-THOR
//! loads them: it fills what they leave out with its own defaults. `export` and `view` read a
//! house into holoc's own house type, which names every field, so before that the members AI2-THOR
//! does not need are filled here the way AI2-THOR fills them: a window's room is its `room0`,
//! layers are `Procedural0`, a door is openable and closed, an object is not kinematic, a room's
//! walls are drawn with the material of its first wall, the agent stands where the house's
//! `default` agent pose puts it (else at the origin), and so on. What cannot be filled (a room
//! without a floor polygon, a wall without a polygon) is left as it is, and the reader then says
//! which member is missing.

use serde_json::{json, Map, Value};
use std::collections::BTreeSet;

/// Fills the members AI2-THOR does not need with its defaults; returns the members filled, as
/// `doors[].openable`, in order.
pub fn fill(house: &mut Value) -> Vec<String> {
    let mut filled = BTreeSet::new();
    let Some(top) = house.as_object_mut() else { return Vec::new() };
    let walls_of: Vec<(String, Value)> = top
        .get("walls")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|w| {
            let room = w.get("roomId")?.as_str()?.to_string();
            Some((room, w.get("material")?.clone()))
        })
        .collect();
    for key in ["rooms", "walls", "doors", "windows", "objects"] {
        if !top.contains_key(key) {
            top.insert(key.into(), json!([]));
            filled.insert(key.to_string());
        }
    }
    for room in list(top, "rooms") {
        let id = room.get("id").and_then(Value::as_str).unwrap_or_default().to_string();
        let material = walls_of
            .iter()
            .find(|(r, _)| *r == id)
            .map_or_else(|| json!({"name": "PureWhite"}), |(_, m)| m.clone());
        put(room, "rooms[]", "ceilings", json!([]), &mut filled);
        put(room, "rooms[]", "children", json!([]), &mut filled);
        put(room, "rooms[]", "layer", json!("Procedural0"), &mut filled);
        put(room, "rooms[]", "roomType", json!(""), &mut filled);
        put(room, "rooms[]", "wallMaterial", material, &mut filled);
    }
    for wall in list(top, "walls") {
        put(wall, "walls[]", "layer", json!("Procedural0"), &mut filled);
        put(wall, "walls[]", "material", json!({"name": "PureWhite"}), &mut filled);
    }
    for door in list(top, "doors") {
        put(door, "doors[]", "openable", json!(true), &mut filled);
        put(door, "doors[]", "openness", json!(0.0), &mut filled);
        let position = hole_centre(door);
        put(door, "doors[]", "assetPosition", position, &mut filled);
        for key in ["room0", "room1", "wall0", "wall1"] {
            put(door, "doors[]", key, json!(""), &mut filled);
        }
    }
    for window in list(top, "windows") {
        let room0 = window.get("room0").cloned().unwrap_or_else(|| json!(""));
        let position = hole_centre(window);
        put(window, "windows[]", "assetPosition", position, &mut filled);
        put(window, "windows[]", "roomId", room0, &mut filled);
        put(window, "windows[]", "layer", json!("Procedural0"), &mut filled);
        for key in ["room0", "room1", "wall0", "wall1"] {
            put(window, "windows[]", key, json!(""), &mut filled);
        }
    }
    if let Some(objects) = top.get_mut("objects").and_then(Value::as_array_mut) {
        for object in objects {
            fill_object(object, "objects[]", &mut filled);
        }
    }
    let pp = top.entry("proceduralParameters").or_insert_with(|| {
        filled.insert("proceduralParameters".to_string());
        json!({})
    });
    if let Some(pp) = pp.as_object_mut() {
        let p = "proceduralParameters";
        put(pp, p, "ceilingColor", json!({"r": 1.0, "g": 1.0, "b": 1.0}), &mut filled);
        put(pp, p, "ceilingMaterial", json!({"name": "PureWhite"}), &mut filled);
        put(pp, p, "floorColliderThickness", json!(1.0), &mut filled);
        put(pp, p, "receptacleHeight", json!(0.7), &mut filled);
        put(pp, p, "reflections", json!([]), &mut filled);
        put(pp, p, "skyboxId", json!("Sky1"), &mut filled);
        put(pp, p, "lights", json!([]), &mut filled);
        if let Some(lights) = pp.get_mut("lights").and_then(Value::as_array_mut) {
            for light in lights.iter_mut().filter_map(Value::as_object_mut) {
                let l = "proceduralParameters.lights[]";
                put(light, l, "id", json!("light"), &mut filled);
                put(light, l, "type", json!("point"), &mut filled);
                put(light, l, "position", json!({"x": 0.0, "y": 0.0, "z": 0.0}), &mut filled);
                put(light, l, "intensity", json!(1.0), &mut filled);
                put(light, l, "rgb", json!({"r": 1.0, "g": 1.0, "b": 1.0}), &mut filled);
                let shadow = json!({"type": "Soft", "strength": 1.0, "normalBias": 0.0,
                    "bias": 0.05, "nearPlane": 0.2, "resolution": "FromQualitySettings"});
                put(light, l, "shadow", shadow, &mut filled);
            }
        }
    }
    let metadata = top.entry("metadata").or_insert_with(|| {
        filled.insert("metadata".to_string());
        json!({})
    });
    if let Some(md) = metadata.as_object_mut() {
        let m = "metadata";
        let default_pose = md
            .get("agentPoses")
            .and_then(|p| p.get("default"))
            .cloned()
            .filter(Value::is_object)
            .unwrap_or_else(|| {
                json!({"horizon": 30.0, "position": {"x": 0.0, "y": 0.95, "z": 0.0},
                    "rotation": {"x": 0.0, "y": 0.0, "z": 0.0}, "standing": true})
            });
        put(md, m, "agent", default_pose, &mut filled);
        put(md, m, "agentPoses", json!({}), &mut filled);
        put(md, m, "roomSpecId", json!(""), &mut filled);
        put(md, m, "schema", json!("1.0.0"), &mut filled);
        put(md, m, "warnings", json!({}), &mut filled);
        if let Some(agent) = md.get_mut("agent").and_then(Value::as_object_mut) {
            put(agent, "metadata.agent", "horizon", json!(30.0), &mut filled);
            put(
                agent,
                "metadata.agent",
                "rotation",
                json!({"x": 0.0, "y": 0.0, "z": 0.0}),
                &mut filled,
            );
        }
    }
    filled.into_iter().collect()
}

fn fill_object(object: &mut Value, path: &str, filled: &mut BTreeSet<String>) {
    let Some(o) = object.as_object_mut() else { return };
    let id = o.get("id").cloned().unwrap_or_else(|| json!(""));
    put(o, path, "kinematic", json!(false), filled);
    put(o, path, "layer", json!("Procedural0"), filled);
    put(o, path, "roomId", json!(""), filled);
    put(o, path, "object_name", id, filled);
    put(o, path, "rotation", json!({"x": 0.0, "y": 0.0, "z": 0.0}), filled);
    if let Some(children) = o.get_mut("children").and_then(Value::as_array_mut) {
        let inner = format!("{path}.children[]");
        for child in children {
            fill_object(child, &inner, filled);
        }
    }
}

/// The elements of the list `key` that are objects.
fn list<'a>(
    top: &'a mut Map<String, Value>,
    key: &str,
) -> impl Iterator<Item = &'a mut Map<String, Value>> {
    top.get_mut(key)
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
        .filter_map(Value::as_object_mut)
}

/// Puts `value` as member `key` when it is absent or null, noting `path.key`.
fn put(
    map: &mut Map<String, Value>,
    path: &str,
    key: &str,
    value: Value,
    filled: &mut BTreeSet<String>,
) {
    if map.get(key).is_none_or(Value::is_null) {
        map.insert(key.to_string(), value);
        filled.insert(format!("{path}.{key}"));
    }
}

/// The centre of a door's or window's hole, in its wall's frame (where AI2-THOR puts the asset
/// when no position is given).
fn hole_centre(hole: &Map<String, Value>) -> Value {
    let points: Vec<[f64; 3]> = hole
        .get("holePolygon")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|p| {
            let n = |k: &str| p.get(k).and_then(Value::as_f64);
            Some([n("x")?, n("y")?, n("z")?])
        })
        .collect();
    if points.is_empty() {
        return json!({"x": 0.0, "y": 0.0, "z": 0.0});
    }
    let mid = |i: usize| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[i]), hi.max(p[i])));
        f64::midpoint(lo, hi)
    };
    json!({"x": mid(0), "y": mid(1), "z": mid(2)})
}

#[cfg(test)]
mod tests {
    use super::fill;
    use serde_json::json;

    #[test]
    fn a_procthor_house_without_agent_and_layers_becomes_a_house() {
        let mut house = json!({
            "rooms": [{"id": "room|2", "roomType": "Bedroom",
                "floorPolygon": [{"x": 0, "y": 0, "z": 0}, {"x": 0, "y": 0, "z": 4},
                    {"x": 4, "y": 0, "z": 4}, {"x": 4, "y": 0, "z": 0}],
                "floorMaterial": {"name": "OakFloor"}, "ceilings": [], "children": []}],
            "walls": [{"id": "wall|2|0|0|0|4", "roomId": "room|2", "material": {"name": "BlueWall"},
                "polygon": [{"x": 0, "y": 0, "z": 0}, {"x": 0, "y": 0, "z": 4},
                    {"x": 0, "y": 2.5, "z": 0}, {"x": 0, "y": 2.5, "z": 4}]}],
            "doors": [],
            "windows": [{"id": "window|1", "assetId": "Window_1", "room0": "room|2",
                "room1": "room|2", "wall0": "wall|2|0|0|0|4", "wall1": "wall|exterior",
                "holePolygon": [{"x": 1, "y": 1, "z": 0}, {"x": 2, "y": 2, "z": 0}],
                "assetPosition": {"x": 1.5, "y": 1.5, "z": 0}}],
            "objects": [{"id": "Bed|1", "assetId": "Bed_1", "kinematic": false,
                "position": {"x": 2, "y": 0.5, "z": 2}, "rotation": {"x": 0, "y": 90, "z": 0},
                "children": [{"id": "Pillow|1", "assetId": "Pillow_1",
                    "position": {"x": 2, "y": 1, "z": 2}, "rotation": {"x": 0, "y": 0, "z": 0}}]}],
            "proceduralParameters": {"ceilingMaterial": {"name": "PureWhite"},
                "floorColliderThickness": 1.0, "lights": [], "receptacleHeight": 0.7,
                "reflections": [], "skyboxId": "Sky1"},
            "metadata": {"roomSpecId": "bedroom", "schema": "1.0.0"}
        });
        let filled = fill(&mut house);
        assert!(filled.contains(&"metadata.agent".to_string()), "{filled:?}");
        assert!(filled.contains(&"objects[].children[].kinematic".to_string()), "{filled:?}");
        assert_eq!(house["rooms"][0]["wallMaterial"]["name"], "BlueWall");
        assert_eq!(house["windows"][0]["roomId"], "room|2");
        let read: crate::lower::thor::House =
            serde_json::from_value(house.clone()).expect("a house");
        assert_eq!(read.objects[0].children[0].object_name, "Pillow|1");
        // Filling a filled house changes nothing.
        let again = house.clone();
        assert!(fill(&mut house).is_empty());
        assert_eq!(house, again);
    }
}
