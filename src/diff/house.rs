//! What the diff compares: a house (and, when there is one, its build report) read leniently
//! from JSON into plain values. Any AI2-THOR house is read — holoc's, ProcTHOR's, the original
//! Holodeck's — and a field that is missing reads as empty, so the diff of two houses never
//! fails on a field it does not need. Like `lower/validate.rs`, this reads the JSON by key
//! instead of through `lower::thor`'s strict types.

use serde_json::Value;

/// A room of a house.
#[derive(Clone, Debug, PartialEq)]
pub struct RoomView {
    /// The room's id.
    pub id: String,
    /// Its `roomType`.
    pub room_type: String,
    /// The floor outline (x, z), metres.
    pub outline: Vec<[f64; 2]>,
    /// The floor material's name.
    pub floor_material: String,
    /// The wall material's name (Holodeck's extra key; empty when absent).
    pub wall_material: String,
}

impl RoomView {
    /// The area of the outline, m².
    pub fn area_m2(&self) -> f64 {
        let n = self.outline.len();
        let mut twice = 0.0;
        for i in 0..n {
            let [x0, z0] = self.outline[i];
            let [x1, z1] = self.outline[(i + 1) % n];
            twice += x0 * z1 - x1 * z0;
        }
        (twice / 2.0).abs()
    }
}

/// A door or a window.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleView {
    /// Its id.
    pub id: String,
    /// Its asset.
    pub asset: String,
    /// The room it is listed under (a door's first side that is a room; a window's room).
    pub room: String,
    /// The two sides, sorted (a door's rooms, `exterior` included).
    pub sides: (String, String),
    /// The wall it is cut into (`wall0`).
    pub wall: String,
    /// Where along that wall the hole starts (the hole's first corner, wall-local x), metres.
    pub offset_m: f64,
}

/// An object of a house, or an item on top of one.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectView {
    /// Its id.
    pub id: String,
    /// What pairs it with an object of the other house when the ids differ: its name without
    /// the instance number (`chair` for `chair-2`), else its asset's type.
    pub category: String,
    /// Its asset.
    pub asset: String,
    /// The room it stands in.
    pub room: String,
    /// The centre of its box (x, y, z), metres.
    pub position: [f64; 3],
    /// Its turn about the vertical axis, degrees.
    pub rotation_deg: f64,
    /// The id of the receptacle it stands on, for an item on top.
    pub parent: Option<String>,
    /// Its AI2-THOR object type from the catalog (`Dresser`), when the catalog knows its asset.
    pub thor_type: Option<String>,
}

impl ObjectView {
    /// Its type: the catalog's AI2-THOR object type, else the asset id's prefix (`None` for an
    /// id without `_`, an Objaverse hash, which names no type).
    pub fn type_name(&self) -> Option<&str> {
        self.thor_type
            .as_deref()
            .or_else(|| self.asset.contains('_').then(|| asset_type(&self.asset)))
    }
}

/// A light.
#[derive(Clone, Debug, PartialEq)]
pub struct LightView {
    /// Its id.
    pub id: String,
    /// The room of a point light.
    pub room: Option<String>,
    /// Its position, metres.
    pub position: [f64; 3],
    /// Its intensity.
    pub intensity: f64,
    /// Its colour.
    pub rgb: [f64; 3],
    /// The range of a point light.
    pub range: Option<f64>,
}

/// The agent's start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseView {
    /// Position, metres.
    pub position: [f64; 3],
    /// Turn about the vertical axis, degrees.
    pub rotation_deg: f64,
    /// Camera pitch, degrees.
    pub horizon: f64,
}

/// One relation of the build report: an object's constraint, kept or not.
#[derive(Clone, Debug, PartialEq)]
pub struct RelationView {
    /// The room's label.
    pub room: String,
    /// The object, as the house names it (`chair-0 (living room)`).
    pub object: String,
    /// The constraint as written (`near sofa-0`).
    pub constraint: String,
    /// Whether the layout keeps it.
    pub kept: bool,
}

/// A house (and its report's relations), ready to compare.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HouseView {
    /// Rooms, in the file's order.
    pub rooms: Vec<RoomView>,
    /// Doors.
    pub doors: Vec<HoleView>,
    /// Windows.
    pub windows: Vec<HoleView>,
    /// Objects, each receptacle before the items on it.
    pub objects: Vec<ObjectView>,
    /// Lights.
    pub lights: Vec<LightView>,
    /// The agent's start.
    pub agent: Option<PoseView>,
    /// Other settings of the scene, as (name, value): skybox, schema, ceiling material, and the
    /// report's request and seed.
    pub metadata: Vec<(String, String)>,
    /// The relations of the build report, when one was given.
    pub relations: Option<Vec<RelationView>>,
}

fn text(v: &Value, key: &str) -> String {
    v.get(key).and_then(Value::as_str).unwrap_or_default().to_string()
}

fn num(v: &Value, key: &str) -> f64 {
    v.get(key).and_then(Value::as_f64).unwrap_or(0.0)
}

fn xyz(v: Option<&Value>) -> [f64; 3] {
    v.map_or([0.0; 3], |p| [num(p, "x"), num(p, "y"), num(p, "z")])
}

fn list<'a>(v: &'a Value, key: &str) -> &'a [Value] {
    v.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// A material's name: `{"name": …}` (schema 1.0.0) or a plain string (older houses).
fn material(v: Option<&Value>) -> String {
    match v {
        Some(Value::String(s)) => s.clone(),
        Some(m) => text(m, "name"),
        None => String::new(),
    }
}

/// The type of an asset: its id up to the first `_` (`Sofa` for `Sofa_201_1`).
pub fn asset_type(asset: &str) -> &str {
    asset.split('_').next().unwrap_or(asset)
}

/// The category of an object: its instance name without the number (`chair-2` → `chair`),
/// or, for a house without instance names, its asset's type in lower case.
fn category(object: &Value, asset: &str) -> String {
    let name = text(object, "object_name");
    if name.is_empty() {
        return asset_type(asset).to_lowercase();
    }
    match name.rsplit_once('-') {
        Some((head, n)) if !head.is_empty() && n.chars().all(|c| c.is_ascii_digit()) => {
            head.to_string()
        }
        _ => name,
    }
}

impl HouseView {
    /// Gives every object its AI2-THOR type from `catalog` (the embedded catalog and the user
    /// catalogs of `holoc.toml` or `--catalog`); an asset the catalog lacks keeps none.
    pub fn set_types(&mut self, catalog: &crate::resolve::Catalog) {
        for o in &mut self.objects {
            o.thor_type = catalog.get(&o.asset).map(|a| a.object_type.to_string());
        }
    }

    /// Reads a house. `Err` says why the value is not a house (not an object, no `rooms`).
    pub fn read(house: &Value) -> Result<HouseView, String> {
        let Some(top) = house.as_object() else {
            return Err("it is not a JSON object".into());
        };
        if !top.get("rooms").is_some_and(Value::is_array) {
            return Err("it has no `rooms` list, so it is not a house".into());
        }
        // A coordinate no house has (1e308) is refused as `holoc validate` refuses it: sums of
        // such numbers are infinite and areas `NaN`.
        if let Some((path, x)) = crate::lower::validate::absurd_numbers(house).first() {
            return Err(format!(
                "its coordinate at `{path}` is {x:e} m, beyond {:e} m, the largest holoc reads",
                crate::lower::validate::MAX_COORDINATE_M
            ));
        }
        let rooms = list(house, "rooms")
            .iter()
            .map(|r| RoomView {
                id: text(r, "id"),
                room_type: text(r, "roomType"),
                outline: list(r, "floorPolygon")
                    .iter()
                    .map(|p| [num(p, "x"), num(p, "z")])
                    .collect(),
                floor_material: material(r.get("floorMaterial")),
                wall_material: material(r.get("wallMaterial")),
            })
            .collect();
        let hole = |h: &Value, is_door: bool| {
            let (r0, r1) = (text(h, "room0"), text(h, "room1"));
            let room = if is_door {
                if r0 == "exterior" || r0.is_empty() {
                    r1.clone()
                } else {
                    r0.clone()
                }
            } else {
                let own = text(h, "roomId");
                if own.is_empty() {
                    r0.clone()
                } else {
                    own
                }
            };
            let sides = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
            HoleView {
                id: text(h, "id"),
                asset: text(h, "assetId"),
                room,
                sides,
                wall: text(h, "wall0"),
                offset_m: list(h, "holePolygon").first().map_or(0.0, |p| num(p, "x")),
            }
        };
        let doors = list(house, "doors").iter().map(|d| hole(d, true)).collect();
        let windows = list(house, "windows").iter().map(|w| hole(w, false)).collect();
        let embedded = crate::resolve::Catalog::embedded();
        let mut objects = Vec::new();
        let mut pending: Vec<(&Value, Option<String>, String)> =
            list(house, "objects").iter().rev().map(|o| (o, None, String::new())).collect();
        while let Some((o, parent, parent_room)) = pending.pop() {
            let asset = text(o, "assetId");
            let asset_id = asset.clone();
            let mut room = text(o, "roomId");
            if room.is_empty() {
                room = parent_room;
            }
            let id = text(o, "id");
            objects.push(ObjectView {
                category: category(o, &asset),
                id: id.clone(),
                asset,
                room: room.clone(),
                position: xyz(o.get("position")),
                rotation_deg: o.get("rotation").map_or(0.0, |r| num(r, "y")),
                parent,
                thor_type: embedded.get(&asset_id).map(|a| a.object_type.to_string()),
            });
            pending.extend(
                list(o, "children").iter().rev().map(|c| (c, Some(id.clone()), room.clone())),
            );
        }
        let params = house.get("proceduralParameters").cloned().unwrap_or(Value::Null);
        let lights = list(&params, "lights")
            .iter()
            .map(|l| {
                let c = l.get("rgb");
                LightView {
                    id: text(l, "id"),
                    room: l.get("roomId").and_then(Value::as_str).map(str::to_string),
                    position: xyz(l.get("position")),
                    intensity: num(l, "intensity"),
                    rgb: c.map_or([0.0; 3], |c| [num(c, "r"), num(c, "g"), num(c, "b")]),
                    range: l.get("range").and_then(Value::as_f64),
                }
            })
            .collect();
        let meta = house.get("metadata").cloned().unwrap_or(Value::Null);
        let agent = meta.get("agent").filter(|a| a.is_object()).map(|a| PoseView {
            position: xyz(a.get("position")),
            rotation_deg: a.get("rotation").map_or(0.0, |r| num(r, "y")),
            horizon: num(a, "horizon"),
        });
        let mut metadata = Vec::new();
        let mut field = |name: &str, value: String| {
            if !value.is_empty() {
                metadata.push((name.to_string(), value));
            }
        };
        field("schema", text(&meta, "schema"));
        field("room spec", text(&meta, "roomSpecId"));
        field("skybox", text(&params, "skyboxId"));
        field("ceiling material", material(params.get("ceilingMaterial")));
        Ok(HouseView { rooms, doors, windows, objects, lights, agent, metadata, relations: None })
    }

    /// Adds the relations, request and seed of a build report (`holoc build --report`).
    /// `Err` says why the value is not a build report.
    pub fn add_report(&mut self, report: &Value) -> Result<(), String> {
        let Some(layout) = report.get("layout").and_then(Value::as_array) else {
            return Err("it has no `layout` list, so it is not a build report".into());
        };
        let mut relations = Vec::new();
        for room in layout {
            let label = text(room, "label");
            for object in list(room, "floor_objects") {
                let name = format!("{} ({label})", text(object, "object"));
                for c in list(object, "constraints") {
                    relations.push(RelationView {
                        room: label.clone(),
                        object: name.clone(),
                        constraint: text(c, "constraint"),
                        kept: c.get("satisfied").and_then(Value::as_bool).unwrap_or(false),
                    });
                }
            }
        }
        self.relations = Some(relations);
        let request = text(report, "request");
        if !request.is_empty() {
            self.metadata.push(("request".into(), request));
        }
        if let Some(seed) = report.get("seed").filter(|s| !s.is_null()) {
            self.metadata.push(("seed".into(), seed.to_string()));
        }
        // Each catalog of the lock by its name: a new version (or the same version with other
        // bytes) is one `catalog …` setting changed, said as such.
        let lock = report.get("assets").filter(|a| a.get("catalogs").is_some()).unwrap_or(report);
        for c in list(lock, "catalogs") {
            let name = text(c, "name");
            if name.is_empty() {
                continue;
            }
            let version = c.get("version").map_or_else(String::new, |v| match v.as_str() {
                Some(s) => s.to_string(),
                None if v.is_null() => String::new(),
                None => v.to_string(),
            });
            let sha = text(c, "sha256");
            let short = sha.get(..12).unwrap_or(&sha);
            let value = match (version.is_empty(), short.is_empty()) {
                (false, false) => format!("version {version} (sha256 {short}…)"),
                (false, true) => format!("version {version}"),
                (true, false) => format!("sha256 {short}…"),
                (true, true) => continue,
            };
            self.metadata.push((format!("catalog {name}"), value));
        }
        Ok(())
    }
}
