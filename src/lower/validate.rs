//! `holoc validate`: checks a house JSON file against the house schema
//! (`data/house.schema.json`) and the geometric rules AI2-THOR relies on.
//!
//! Rules: ids are unique and every reference names an existing room or wall; each door or
//! window hole lies inside its wall and no wall has two holes; each room's floor polygon is a
//! closed outline with an area; objects stand inside their room; the footprints of floor
//! objects (their asset's box from the object catalog, turned by their rotation) stay inside
//! their room and do not overlap (warnings: AI2-THOR loads such houses); asset ids that are
//! not built-in AI2-THOR assets get a warning. Diagnostics point at the id in the file where one can be found.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use serde_json::Value;

use crate::diag::suggest;
use crate::diag::{Code, Diagnostic, Outcome};
use crate::geometry::{self as geo, Aabb, Point};
use crate::resolve::structure::{Material, StructureCatalog};
use crate::resolve::Catalog;
use crate::source::{FileId, SourceMap, Span};
use nalgebra::{Isometry2, Point2, Vector2};
use parry2d::query::intersection_test;
use parry2d::shape::{Cuboid, Segment};

/// Whether this holoc checks houses against the JSON Schema (its `schema` feature, on by
/// default); without it, `validate` checks everything else and says so.
pub const SCHEMA_CHECKED: bool = cfg!(feature = "schema");

/// The house schema, compiled once a process (compiling it, with the meta-schemas jsonschema
/// checks it against, costs more than building a house).
#[cfg(feature = "schema")]
fn schema_validator() -> Result<&'static jsonschema::Validator, String> {
    static VALIDATOR: std::sync::OnceLock<Result<jsonschema::Validator, String>> =
        std::sync::OnceLock::new();
    VALIDATOR
        .get_or_init(|| {
            let schema: Value = serde_json::from_str(HOUSE_SCHEMA)
                .map_err(|e| format!("the embedded schema: {e}"))?;
            jsonschema::validator_for(&schema).map_err(|e| e.to_string())
        })
        .as_ref()
        .map_err(Clone::clone)
}

/// The first 20 places where `value` does not follow the house schema, as messages. A house
/// in holoc's own form (see [`in_holocs_own_form`]) follows it by construction: the schema is
/// not compiled for it.
#[cfg(feature = "schema")]
fn schema_errors(value: &Value) -> Result<Vec<String>, String> {
    if in_holocs_own_form(value) {
        return Ok(Vec::new());
    }
    Ok(schema_validator()?
        .iter_errors(value)
        .map(|e| {
            let path = e.instance_path.to_string();
            if path.is_empty() {
                format!("at the top level: {e}")
            } else {
                format!("at `{path}`: {e}")
            }
        })
        .take(20)
        .collect())
}

/// Whether `value` is a house exactly as holoc writes it: it reads into holoc's own house
/// type and writes back to the same JSON, and keeps the few bounds of the schema a value of
/// that type could break (colour channels in 0…1, a hole polygon of two corners, a wall
/// polygon of four or more). Such a house follows the schema by construction, which is what
/// lets `holoc export` of a built house skip compiling the schema (issue 54: export cost
/// 3× a build). Anything else — another tool's house, an edited one, a number written as an
/// integer — is checked against the schema. A unit test pins the schema's bounds, so a new one
/// is added here too.
#[cfg(feature = "schema")]
pub(crate) fn in_holocs_own_form(value: &Value) -> bool {
    fn bounds_kept(v: &Value, key: Option<&str>) -> bool {
        match v {
            Value::Object(map) => {
                if key == Some("color") {
                    let channel_ok = |c: &str| {
                        map.get(c)
                            .is_none_or(|x| x.as_f64().is_some_and(|x| (0.0..=1.0).contains(&x)))
                    };
                    if !["r", "g", "b", "a"].into_iter().all(channel_ok) {
                        return false;
                    }
                }
                map.iter().all(|(k, x)| bounds_kept(x, Some(k)))
            }
            Value::Array(items) => {
                (key != Some("holePolygon") || items.len() == 2)
                    && items.iter().all(|x| bounds_kept(x, None))
            }
            _ => true,
        }
    }
    let walls_closed = value.get("walls").and_then(Value::as_array).is_none_or(|walls| {
        walls
            .iter()
            .all(|w| w.get("polygon").and_then(Value::as_array).is_none_or(|p| p.len() >= 4))
    });
    // The house is read from the tree without copying it, and written back as text compared
    // with the tree as it is read (`Same`): neither a copy of the tree nor the tree written
    // back is ever held beside it (issue 51: the two took 600 MB for a 32 MiB house).
    walls_closed
        && bounds_kept(value, None)
        && serde::Deserialize::deserialize(value)
            .ok()
            .and_then(|house: crate::lower::thor::House| serde_json::to_vec(&house).ok())
            .is_some_and(|back| same_json(&back, value))
}

/// Whether the JSON text `text` is the value `value` (as `serde_json::from_slice::<Value>(text)
/// == Ok(value)` would say), read without building its tree.
#[cfg(feature = "schema")]
pub(crate) fn same_json(text: &[u8], value: &Value) -> bool {
    use serde::de::DeserializeSeed as _;
    let mut de = serde_json::Deserializer::from_slice(text);
    Same(value).deserialize(&mut de).is_ok() && de.end().is_ok()
}

/// A seed that reads a JSON value and fails (with a custom error) as soon as it differs from the
/// value it holds. Numbers compare as `serde_json::Value`s do: an unsigned, a negative and a
/// floating-point number are never equal to each other.
#[cfg(feature = "schema")]
struct Same<'v>(&'v Value);

#[cfg(feature = "schema")]
impl<'de> serde::de::DeserializeSeed<'de> for Same<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

#[cfg(feature = "schema")]
impl<'de> serde::de::Visitor<'de> for Same<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "the value {}", self.0)
    }
    fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<(), E> {
        check(self.0.as_bool() == Some(v))
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<(), E> {
        check(self.0.is_u64() && self.0.as_u64() == Some(v))
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<(), E> {
        match u64::try_from(v) {
            Ok(v) => self.visit_u64(v),
            Err(_) => check(self.0.is_i64() && self.0.as_i64() == Some(v)),
        }
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<(), E> {
        check(self.0.is_f64() && self.0.as_f64() == Some(v))
    }
    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<(), E> {
        check(self.0.as_str() == Some(v))
    }
    fn visit_unit<E: serde::de::Error>(self) -> Result<(), E> {
        check(self.0.is_null())
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let Value::Array(items) = self.0 else { return check(false) };
        let mut n = 0;
        while let Some(item) = items.get(n) {
            if seq.next_element_seed(Same(item))?.is_none() {
                return check(false);
            }
            n += 1;
        }
        check(seq.next_element::<serde::de::IgnoredAny>()?.is_none())
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let Value::Object(object) = self.0 else { return check(false) };
        let mut seen = std::collections::BTreeSet::new();
        while let Some(key) = map.next_key::<std::borrow::Cow<'de, str>>()? {
            let Some((key, expected)) = object.get_key_value(key.as_ref()) else {
                return check(false);
            };
            map.next_value_seed(Same(expected))?;
            seen.insert(key);
        }
        check(seen.len() == object.len())
    }
}

/// `Ok` when `same`, else the error that stops [`Same`].
#[cfg(feature = "schema")]
fn check<E: serde::de::Error>(same: bool) -> Result<(), E> {
    if same {
        Ok(())
    } else {
        Err(E::custom("differs"))
    }
}

/// Without the `schema` feature there is no schema check (see [`SCHEMA_CHECKED`]).
#[cfg(not(feature = "schema"))]
#[allow(clippy::unnecessary_wraps)]
fn schema_errors(_value: &Value) -> Result<Vec<String>, String> {
    Ok(Vec::new())
}

/// The house schema, embedded.
pub const HOUSE_SCHEMA: &str = include_str!("../../data/house.schema.json");

/// Tolerance of hole and object containment checks, metres.
pub const VALIDATE_TOLERANCE_M: f64 = 0.02;

/// What a valid house holds.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ValidationReport {
    /// Number of rooms.
    pub rooms: usize,
    /// Number of walls.
    pub walls: usize,
    /// Number of doors.
    pub doors: usize,
    /// Number of windows.
    pub windows: usize,
    /// Number of top-level objects.
    pub objects: usize,
}

struct Ctx<'a> {
    text: &'a str,
    file: FileId,
    diags: Vec<Diagnostic>,
    /// Where each `"key": "value"` pair of string literals stands, as written (quotes
    /// included), built on the first look-up: every look-up after it is constant time, so
    /// a house with many diagnostics is not read again for each.
    pairs: std::cell::OnceCell<HashMap<(&'a str, &'a str), Vec<usize>>>,
}

/// The end (one past the closing quote) of the JSON string starting at `at`.
fn string_end(bytes: &[u8], at: usize) -> Option<usize> {
    let mut i = at + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => return Some(i + 1),
            _ => i += 1,
        }
    }
    None
}

/// Every `"key": "value"` pair of string literals of a JSON text, by their raw text (key
/// without quotes, value with them), with the value's offsets. One pass.
fn string_pairs(text: &str) -> HashMap<(&str, &str), Vec<usize>> {
    let bytes = text.as_bytes();
    let mut pairs: HashMap<(&str, &str), Vec<usize>> = HashMap::new();
    let skip_ws = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        i
    };
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'"' {
            i += 1;
            continue;
        }
        let Some(key_end) = string_end(bytes, i) else { break };
        let colon = skip_ws(key_end);
        if bytes.get(colon) == Some(&b':') {
            let v = skip_ws(colon + 1);
            if bytes.get(v) == Some(&b'"') {
                let Some(v_end) = string_end(bytes, v) else { break };
                pairs.entry((&text[i + 1..key_end - 1], &text[v..v_end])).or_default().push(v);
                i = v_end;
                continue;
            }
        }
        i = key_end;
    }
    pairs
}

impl Ctx<'_> {
    /// The span of the `nth` occurrence of `"key": "value"` in the file (whole file start if not
    /// found).
    fn span_of(&self, key: &str, value: &str, nth: usize) -> Span {
        let quoted = serde_json::to_string(value).unwrap_or_default();
        let pairs = self.pairs.get_or_init(|| string_pairs(self.text));
        match pairs.get(&(key, quoted.as_str())).and_then(|at| at.get(nth)) {
            Some(&at) => Span::new(self.file, at, at + quoted.len()),
            None => Span::new(self.file, 0, self.text.len().min(1)),
        }
    }

    /// The span of the first `"key"` of the file (whole file start if not found).
    fn span_of_key(&self, key: &str) -> Span {
        let quoted = format!("\"{key}\"");
        self.text.find(&quoted).map_or_else(
            || Span::new(self.file, 0, self.text.len().min(1)),
            |at| Span::new(self.file, at, at + quoted.len()),
        )
    }

    fn push(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }
}

fn s<'v>(v: &'v Value, key: &str) -> Option<&'v str> {
    v.get(key).and_then(Value::as_str)
}

fn num(v: &Value, key: &str) -> Option<f64> {
    v.get(key).and_then(Value::as_f64)
}

fn floor_point(v: &Value) -> Option<Point> {
    Some([num(v, "x")?, num(v, "z")?])
}

fn arr<'v>(v: &'v Value, key: &str) -> &'v [Value] {
    v.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// `(width, height)` of a wall from its polygon.
fn wall_size(wall: &Value) -> Option<(f64, f64)> {
    let pts = arr(wall, "polygon");
    let ys: Vec<f64> = pts.iter().filter_map(|p| num(p, "y")).collect();
    let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let base: Vec<Point> = pts
        .iter()
        .filter(|p| num(p, "y").is_some_and(|y| geo::near(y, lo)))
        .filter_map(floor_point)
        .collect();
    let mut width: f64 = 0.0;
    for a in &base {
        for b in &base {
            width = width.max(geo::distance(*a, *b));
        }
    }
    (hi.is_finite() && lo.is_finite()).then_some((width, hi - lo))
}

/// `(min, max)` hole corners `(along, up)` of a door or window.
fn hole(v: &Value) -> Option<([f64; 2], [f64; 2])> {
    if let Some(poly) = v.get("holePolygon").and_then(Value::as_array) {
        let a = poly.first()?;
        let b = poly.get(1)?;
        return Some(([num(a, "x")?, num(a, "y")?], [num(b, "x")?, num(b, "y")?]));
    }
    let bb = v.get("boundingBox")?;
    let (a, b) = (bb.get("min")?, bb.get("max")?);
    Some(([num(a, "x")?, num(a, "y")?], [num(b, "x")?, num(b, "y")?]))
}

/// The largest coordinate (`x`, `y`, `z` anywhere in the house) validate reads, metres.
pub const MAX_COORDINATE_M: f64 = 1e5;

/// The places (JSON pointers) of the coordinates beyond [`MAX_COORDINATE_M`], at most 20, in
/// document order. Walks the value without recursion.
pub(crate) fn absurd_numbers(value: &Value) -> Vec<(String, f64)> {
    let mut found = Vec::new();
    let mut pending: Vec<(String, &Value)> = vec![(String::new(), value)];
    while let Some((path, v)) = pending.pop() {
        match v {
            Value::Object(map) => {
                for (k, x) in map.iter().rev() {
                    pending.push((format!("{path}/{k}"), x));
                }
            }
            Value::Array(list) => {
                for (i, x) in list.iter().enumerate().rev() {
                    pending.push((format!("{path}/{i}"), x));
                }
            }
            Value::Number(n) => {
                let key = path.rsplit('/').next().unwrap_or_default();
                if matches!(key, "x" | "y" | "z") {
                    let x = n.as_f64().unwrap_or(f64::INFINITY);
                    if !x.is_finite() || x.abs() > MAX_COORDINATE_M {
                        found.push((path, x));
                        if found.len() == 20 {
                            break;
                        }
                    }
                }
            }
            _ => {}
        }
    }
    found
}

/// Validates the house JSON in `file`.
pub fn validate(
    sources: &SourceMap,
    file: FileId,
    catalog: &StructureCatalog,
    objects_catalog: &Catalog,
) -> Outcome<ValidationReport> {
    let text = sources.get(file).text.as_str();
    let mut ctx = Ctx { text, file, diags: Vec::new(), pairs: std::cell::OnceCell::new() };
    let value: Value = match serde_json::from_str(text) {
        Ok(v) => v,
        Err(e) => {
            let mut offset = byte_offset(text, e.line(), e.column());
            while offset > 0 && !text.is_char_boundary(offset) {
                offset -= 1;
            }
            let d = Diagnostic::new(Code::E0601, format!("the file is not valid JSON: {e}"))
                .with_primary(
                    Span::new(
                        file,
                        offset,
                        text[offset..].chars().next().map_or(offset, |c| offset + c.len_utf8()),
                    ),
                    "here",
                )
                .with_help("fix the JSON syntax");
            return Outcome::new(ValidationReport::default(), vec![d]);
        }
    };
    let schema_errors = match schema_errors(&value) {
        Ok(errors) => errors,
        Err(e) => {
            return Outcome::new(
                ValidationReport::default(),
                vec![Diagnostic::internal(format!("house schema: {e}"))],
            );
        }
    };
    if !schema_errors.is_empty() {
        for msg in schema_errors {
            ctx.push(
                Diagnostic::new(Code::E0601, format!("the house does not follow the schema {msg}"))
                    .with_primary(Span::new(file, 0, text.len().min(1)), "in this file")
                    .with_help("see `data/house.schema.json` for the expected fields"),
            );
        }
        return Outcome::new(ValidationReport::default(), ctx.diags);
    }
    // A coordinate no house has (1e308, or beyond a hundred kilometres) is an error before any
    // geometry is computed with it.
    let absurd = absurd_numbers(&value);
    if !absurd.is_empty() {
        for (path, x) in absurd {
            let key = path.rsplit('/').next().unwrap_or_default().to_string();
            ctx.push(
                Diagnostic::new(
                    Code::E0601,
                    format!(
                        "the house does not follow the schema at `{path}`: {x:e} is beyond \
                         {MAX_COORDINATE_M:e} m, the largest coordinate holoc reads"
                    ),
                )
                .with_primary(ctx.span_of_key(&key), "this value")
                .with_help("coordinates are metres from the house's origin; fix the number"),
            );
        }
        return Outcome::new(ValidationReport::default(), ctx.diags);
    }
    let rooms = arr(&value, "rooms");
    let walls = arr(&value, "walls");
    let doors = arr(&value, "doors");
    let windows = arr(&value, "windows");
    let top_objects = arr(&value, "objects");
    // Every object, receptacles before the items nested in their `children`.
    let mut objects: Vec<&Value> = Vec::new();
    let mut pending: Vec<&Value> = top_objects.iter().rev().collect();
    while let Some(o) = pending.pop() {
        objects.push(o);
        pending.extend(arr(o, "children").iter().rev());
    }

    // Unique ids, per kind.
    let mut seen_ids: BTreeMap<String, usize> = BTreeMap::new();
    let mut all: Vec<&Value> = rooms.iter().chain(walls).chain(doors).chain(windows).collect();
    all.extend(objects.iter().copied());
    for v in &all {
        if let Some(id) = s(v, "id") {
            let n = seen_ids.entry(id.to_owned()).or_insert(0);
            *n += 1;
            if *n == 2 {
                let first = ctx.span_of("id", id, 0);
                let second = ctx.span_of("id", id, 1);
                ctx.push(
                    Diagnostic::new(Code::E0602, format!("the id `{id}` is used twice"))
                        .with_primary(second, "used again here")
                        .with_secondary(first, "first used here")
                        .with_help("give every entity its own id"),
                );
            }
        }
    }
    let room_ids: BTreeSet<&str> = rooms.iter().filter_map(|r| s(r, "id")).collect();
    let wall_by_id: BTreeMap<&str, &Value> =
        walls.iter().filter_map(|w| Some((s(w, "id")?, w))).collect();
    for w in walls {
        if let Some(r) = s(w, "roomId") {
            if r != "exterior" && !room_ids.contains(r) {
                let span = ctx.span_of("roomId", r, 0);
                ctx.push(
                    Diagnostic::new(
                        Code::E0603,
                        format!(
                            "wall `{}` names the unknown room `{r}`",
                            s(w, "id").unwrap_or("?")
                        ),
                    )
                    .with_primary(span, "no room has this id")
                    .with_help("refer to an existing room id"),
                );
            }
        }
    }
    // Doors and windows: references, holes inside walls, one hole per wall.
    let mut holes_per_wall: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (kind, list) in [("door", doors), ("window", windows)] {
        for d in list {
            let id = s(d, "id").unwrap_or("?");
            for key in ["room0", "room1"] {
                if let Some(r) = s(d, key) {
                    if r != "exterior" && !room_ids.contains(r) {
                        let span = ctx.span_of(key, r, 0);
                        ctx.push(
                            Diagnostic::new(
                                Code::E0603,
                                format!("{kind} `{id}` names the unknown room `{r}`"),
                            )
                            .with_primary(span, "no room has this id")
                            .with_help("refer to an existing room id"),
                        );
                    }
                }
            }
            let mut own_walls = BTreeSet::new();
            for key in ["wall0", "wall1"] {
                let Some(wid) = s(d, key) else { continue };
                if !wall_by_id.contains_key(wid) {
                    let span = ctx.span_of(key, wid, 0);
                    ctx.push(
                        Diagnostic::new(
                            Code::E0603,
                            format!("{kind} `{id}` names the unknown wall `{wid}`"),
                        )
                        .with_primary(span, "no wall has this id")
                        .with_help("refer to an existing wall id"),
                    );
                } else if own_walls.insert(wid) {
                    holes_per_wall.entry(wid).or_default().push(id);
                }
            }
            if let (Some((lo, hi)), Some(w0)) =
                (hole(d), s(d, "wall0").and_then(|w| wall_by_id.get(w)))
            {
                if let Some((width, height)) = wall_size(w0) {
                    let t = VALIDATE_TOLERANCE_M;
                    if lo[0] < -t
                        || hi[0] > width + t
                        || lo[1] < -t
                        || hi[1] > height + t
                        || hi[0] < lo[0]
                        || hi[1] < lo[1]
                    {
                        let span = ctx.span_of("id", id, 0);
                        ctx.push(
                            Diagnostic::new(
                                Code::E0604,
                                format!(
                                    "the hole of {kind} `{id}` ({:.3}–{:.3} m along, {:.3}–{:.3} m up) is not inside its {:.3} m × {:.3} m wall",
                                    lo[0], hi[0], lo[1], hi[1], width, height
                                ),
                            )
                            .with_primary(span, "hole outside its wall")
                            .with_help("move the hole inside the wall"),
                        );
                    }
                }
            }
        }
    }
    for (wall, users) in &holes_per_wall {
        if users.len() > 1 {
            let span = ctx.span_of("id", wall, 0);
            ctx.push(
                Diagnostic::new(Code::E0605, format!("wall `{wall}` has {} holes", users.len()))
                    .with_primary(span, "AI2-THOR builds one hole per wall")
                    .with_note(format!(
                        "used by {}",
                        users.iter().map(|u| format!("`{u}`")).collect::<Vec<_>>().join(", ")
                    ))
                    .with_help("move one of the openings to another wall"),
            );
        }
    }
    // Rooms closed.
    let mut polygons: BTreeMap<&str, Vec<Point>> = BTreeMap::new();
    for r in rooms {
        let id = s(r, "id").unwrap_or("?");
        let poly: Vec<Point> = arr(r, "floorPolygon").iter().filter_map(floor_point).collect();
        if poly.len() < 3 || geo::signed_area(&poly).abs() <= geo::EPS_M {
            let span = ctx.span_of("id", id, 0);
            ctx.push(
                Diagnostic::new(Code::E0606, format!("room `{id}` has no closed floor polygon"))
                    .with_primary(span, format!("{} points, no area", poly.len()))
                    .with_help("give the room at least three corners enclosing some floor"),
            );
        } else {
            polygons.insert(id, poly);
        }
    }
    // Objects inside rooms; floor footprints inside their room and not overlapping.
    let nested_items: std::collections::BTreeSet<*const Value> =
        objects.iter().flat_map(|o| arr(o, "children").iter().map(std::ptr::from_ref)).collect();
    let mut footprints: Vec<Footprint<'_>> = Vec::new();
    for &o in &objects {
        let id = s(o, "id").unwrap_or("?");
        let Some(pos) = o.get("position").and_then(floor_point) else { continue };
        let inside = |poly: &Vec<Point>| {
            geo::point_in_or_on_polygon(pos, poly)
                || (0..poly.len()).any(|i| {
                    geo::distance_to_segment(pos, poly[i], poly[(i + 1) % poly.len()])
                        <= VALIDATE_TOLERANCE_M
                })
        };
        let room_poly = s(o, "roomId").and_then(|r| polygons.get(r));
        let ok = match room_poly {
            Some(poly) => inside(poly),
            None => polygons.values().any(inside),
        };
        if !ok {
            let span = ctx.span_of("id", id, 0);
            let where_ =
                s(o, "roomId").map_or_else(|| "any room".to_owned(), |r| format!("room `{r}`"));
            ctx.push(
                Diagnostic::new(
                    Code::E0607,
                    format!("object `{id}` at ({:.3}, {:.3}) is outside {where_}", pos[0], pos[1]),
                )
                .with_primary(span, "outside its room")
                .with_help("move the object into the room"),
            );
            continue;
        }
        // Objects of unknown size (E0614 below) have no footprint to check; an item nested on
        // a receptacle stands on it, even on a bottom shelf just above the floor.
        let nested = nested_items.contains(&std::ptr::from_ref(o));
        if let Some(fp) = floor_footprint(o, pos, objects_catalog).filter(|_| !nested) {
            footprints.push(Footprint { id, room: s(o, "roomId"), ..fp });
        }
    }
    // A footprint reaching through a wall of its room.
    for fp in &footprints {
        let Some(poly) = fp.room.and_then(|r| polygons.get(r)) else { continue };
        let (iso, shape) = fp.shape();
        let crosses = (0..poly.len()).any(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let seg = Segment::new(
                Point2::new(a[0] as f32, a[1] as f32),
                Point2::new(b[0] as f32, b[1] as f32),
            );
            intersection_test(&iso, &shape, &Isometry2::identity(), &seg).unwrap_or(false)
        });
        if crosses {
            let span = ctx.span_of("id", fp.id, 0);
            ctx.push(
                Diagnostic::new(
                    Code::W0609,
                    format!("floor object `{}` reaches through a wall of its room", fp.id),
                )
                .with_primary(
                    span,
                    format!(
                        "its {:.2} m × {:.2} m footprint crosses the room's outline",
                        2.0 * fp.half[0],
                        2.0 * fp.half[1]
                    ),
                )
                .with_help("move or turn the object so that its footprint stays inside the room"),
            );
        }
    }
    // Pairs of footprints that overlap: candidates by a sweep over their bounds along x
    // (near-linear unless many overlap), then the exact test.
    let bounds: Vec<Aabb> = footprints.iter().map(Footprint::bounds).collect();
    let mut by_x: Vec<usize> = (0..footprints.len()).collect();
    by_x.sort_by(|&i, &j| bounds[i].min[0].total_cmp(&bounds[j].min[0]).then(i.cmp(&j)));
    // The pairs are kept only while they may be reported one by one (up to
    // `PAIR_DETAIL_LIMIT`); past that each object keeps its number of overlaps and its three
    // first partners (by place in the file), which is all the per-object diagnostics say:
    // 150,000 objects on one spot made 9.6 million pairs (420 MB, issue 51).
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    let mut n_pairs = 0usize;
    let mut partners: Vec<Partners> = vec![Partners::default(); footprints.len()];
    // An object's overlaps are worked out up to `OVERLAPS_COUNTED_PER_OBJECT` as the sweep
    // meets them: thousands of objects on one spot cost a bounded number of tests each.
    let mut capped = false;
    for (k, &i) in by_x.iter().enumerate() {
        let mut hits = 0usize;
        for &j in &by_x[k + 1..] {
            if bounds[j].min[0] > bounds[i].max[0] + VALIDATE_TOLERANCE_M {
                break;
            }
            let (lo, hi) = (i.min(j), i.max(j));
            let (a, b) = (&footprints[lo], &footprints[hi]);
            if a.room != b.room
                || bounds[j].min[1] > bounds[i].max[1] + VALIDATE_TOLERANCE_M
                || bounds[i].min[1] > bounds[j].max[1] + VALIDATE_TOLERANCE_M
            {
                continue;
            }
            let ((ia, sa), (ib, sb)) = (a.shape(), b.shape());
            if intersection_test(&ia, &sa, &ib, &sb).unwrap_or(false) {
                if n_pairs <= crate::diag::PAIR_DETAIL_LIMIT {
                    pairs.push((lo, hi));
                }
                n_pairs += 1;
                partners[lo].add(hi);
                partners[hi].add(lo);
                hits += 1;
                if hits >= OVERLAPS_COUNTED_PER_OBJECT {
                    capped = true;
                    break;
                }
            }
        }
    }
    pairs.sort_unstable();
    if n_pairs <= crate::diag::PAIR_DETAIL_LIMIT {
        for &(i, j) in &pairs {
            let (a, b) = (&footprints[i], &footprints[j]);
            let (ba, bb) = (&bounds[i], &bounds[j]);
            let overlap_x = ba.max[0].min(bb.max[0]) - ba.min[0].max(bb.min[0]);
            let overlap_z = ba.max[1].min(bb.max[1]) - ba.min[1].max(bb.min[1]);
            let span = ctx.span_of("id", b.id, 0);
            let other = ctx.span_of("id", a.id, 0);
            ctx.push(
                Diagnostic::new(
                    Code::W0608,
                    format!("floor objects `{}` and `{}` overlap", a.id, b.id),
                )
                .with_primary(
                    span,
                    if a.square() && b.square() {
                        format!("overlaps `{}` by {overlap_x:.2} m × {overlap_z:.2} m", a.id)
                    } else {
                        format!(
                            "overlaps `{}` (turned boxes whose bounds share {overlap_x:.2} m × {overlap_z:.2} m)",
                            a.id
                        )
                    },
                )
                .with_secondary(other, "this one")
                .with_note("AI2-THOR loads overlapping objects (ProcTHOR tucks chairs under tables), but holoc's layouts never overlap")
                .with_help("move one of them"),
            );
        }
    } else {
        // Many pairs: one diagnostic per object that overlaps others, with their number.
        for (i, list) in partners.iter().enumerate().filter(|(_, l)| l.count > 0) {
            let fp = &footprints[i];
            let named: Vec<String> =
                list.first().map(|j| format!("`{}`", footprints[j].id)).collect();
            let more = if list.count > 3 { ", …" } else { "" };
            let span = ctx.span_of("id", fp.id, 0);
            ctx.push(
                Diagnostic::new(
                    Code::W0608,
                    format!(
                        "floor object `{}` overlaps {}{} floor object{}",
                        fp.id,
                        if capped { "at least " } else { "" },
                        list.count,
                        if list.count == 1 { "" } else { "s" }
                    ),
                )
                .with_primary(span, format!("overlaps {}{more}", named.join(", ")))
                .with_note(format!(
                    "{}{} pairs of floor objects overlap in this house; past {} they are \
                     counted per object{}",
                    if capped { "at least " } else { "" },
                    n_pairs,
                    crate::diag::PAIR_DETAIL_LIMIT,
                    if capped {
                        format!(", and each object's count stops at {OVERLAPS_COUNTED_PER_OBJECT}")
                    } else {
                        String::new()
                    }
                ))
                .with_help("move the objects apart"),
            );
        }
    }
    // Assets: every door, window and object asset must be one AI2-THOR can spawn, a built-in
    // one or one of a catalog given with `--catalog` (CreateHouse fails on any other).
    let known = |a: &str| catalog.is_thor_asset(a) || objects_catalog.get(a).is_some();
    for (kind, list) in [("door", doors), ("window", windows)] {
        for v in list {
            if let Some(a) = s(v, "assetId").filter(|a| !known(a)) {
                ctx.push(
                    Diagnostic::new(Code::E0614, format!("the {kind} asset `{a}` is not an AI2-THOR asset"))
                        .with_primary(ctx.span_of("assetId", a, 0), format!("unknown {kind} asset"))
                        .with_help(format!("use one of the {kind} assets of `holoc assets list`, or give the catalog that has it with `--catalog`")),
                );
            }
        }
    }
    let mut unknown: BTreeMap<&str, usize> = BTreeMap::new();
    for &v in &objects {
        if let Some(a) = s(v, "assetId").filter(|a| !known(a)) {
            *unknown.entry(a).or_insert(0) += 1;
        }
    }
    if !unknown.is_empty() {
        let first = unknown.keys().next().copied().unwrap_or_default();
        let span = ctx.span_of("assetId", first, 0);
        let list: Vec<String> = unknown.keys().take(5).map(|a| format!("`{a}`")).collect();
        ctx.push(
            Diagnostic::new(
                Code::E0614,
                if unknown.len() == 1 {
                    "1 object asset is not an AI2-THOR asset".to_owned()
                } else {
                    format!("{} object assets are not AI2-THOR assets", unknown.len())
                },
            )
            .with_primary(span, "unknown object asset")
            .with_note(format!("for example {}", list.join(", ")))
            .with_note(format!(
                "{} objects use them; CreateHouse cannot spawn them unless they are installed",
                unknown.values().sum::<usize>()
            ))
            .with_help("give the catalog they come from with `--catalog` (e.g. the objathor annotations of Objaverse assets) if they are installed where the house is loaded"),
        );
        if let Some(made) = unknown.keys().find(|a| crate::make::is_made_id(a)) {
            if let Some(last) = ctx.diags.last_mut() {
                *last = last.clone().with_note(format!(
                    "`{made}` is an asset holoc made: its folder `<house stem>.assets/{made}/` is missing or unreadable; build the scene again, or name the folder with `--assets-dir`"
                ));
            }
        }
    }
    procthor_checks(&mut ctx, &value, catalog);
    resting_checks(&mut ctx, top_objects, objects_catalog, &value);
    let report = ValidationReport {
        rooms: rooms.len(),
        walls: walls.len(),
        doors: doors.len(),
        windows: windows.len(),
        objects: objects.len(),
    };
    Outcome::new(report, ctx.diags)
}

/// The checks of what CreateHouse reads beyond the schema: the schema version, materials as
/// `{"name": …}` objects with known names, a known skybox, and doors to the outside oriented
/// from their room.
fn procthor_checks(ctx: &mut Ctx<'_>, value: &Value, catalog: &StructureCatalog) {
    let schema = value.get("metadata").and_then(|m| s(m, "schema"));
    if schema != Some(super::SCHEMA_VERSION) {
        let (span, what) = match schema {
            Some(v) => (ctx.span_of("schema", v, 0), format!("`{v}`")),
            None => (Span::new(ctx.file, 0, ctx.text.len().min(1)), "missing".to_owned()),
        };
        ctx.push(
            Diagnostic::new(
                Code::E0610,
                format!(
                    "the house's `metadata.schema` is {what}; AI2-THOR reads schema {}",
                    super::SCHEMA_VERSION
                ),
            )
            .with_primary(span, "schema version")
            .with_help(format!(
                "write houses of schema {} (ProcTHOR's house upgrader turns older ones into it)",
                super::SCHEMA_VERSION
            )),
        );
    }
    let mut materials: Vec<(&str, &Value)> = Vec::new();
    for r in arr(value, "rooms") {
        for key in ["floorMaterial", "wallMaterial"] {
            if let Some(m) = r.get(key) {
                materials.push((key, m));
            }
        }
    }
    for w in arr(value, "walls") {
        if let Some(m) = w.get("material") {
            materials.push(("material", m));
        }
    }
    if let Some(m) = value.get("proceduralParameters").and_then(|p| p.get("ceilingMaterial")) {
        materials.push(("ceilingMaterial", m));
    }
    let mut plain = 0usize;
    let mut first_plain: Option<(&str, &str)> = None;
    let mut unknown: BTreeMap<&str, &str> = BTreeMap::new();
    for (key, m) in materials {
        let name = match m {
            Value::String(name) => {
                plain += 1;
                first_plain.get_or_insert((key, name.as_str()));
                name.as_str()
            }
            Value::Object(_) => match s(m, "name") {
                Some(name) => name,
                None => continue,
            },
            _ => continue,
        };
        if catalog.material(name).is_none() {
            unknown.entry(name).or_insert(key);
        }
    }
    if let Some((key, name)) = first_plain {
        ctx.push(
            Diagnostic::new(
                Code::E0611,
                format!("{plain} material(s) are plain strings; AI2-THOR reads a material as an object `{{\"name\": …}}`"),
            )
            .with_primary(ctx.span_of(key, name, 0), "a string, not an object")
            .with_help(format!("write `\"{key}\": {{\"name\": \"{name}\"}}`")),
        );
    }
    for (name, key) in unknown {
        let near = suggest::did_you_mean(&suggest::closest(
            name,
            catalog.materials.iter().map(Material::name),
        ));
        ctx.push(
            Diagnostic::new(
                Code::E0612,
                format!("the material `{name}` is not an AI2-THOR material"),
            )
            .with_primary(ctx.span_of("name", name, 0), format!("unknown material (in `{key}`)"))
            .with_help(near.unwrap_or_else(|| {
                "use a material of the ProcTHOR material database (`data/catalog/materials.tsv`)"
                    .to_owned()
            })),
        );
    }
    if let Some(sky) = value.get("proceduralParameters").and_then(|p| s(p, "skyboxId")) {
        if !catalog.skyboxes.iter().any(|k| k.name == sky) {
            let near = suggest::did_you_mean(&suggest::closest(
                sky,
                catalog.skyboxes.iter().map(|k| k.name),
            ));
            ctx.push(
                Diagnostic::new(
                    Code::E0613,
                    format!("the skybox `{sky}` is not an AI2-THOR skybox"),
                )
                .with_primary(ctx.span_of("skyboxId", sky, 0), "unknown skybox")
                .with_help(
                    near.unwrap_or_else(|| {
                        "use a skybox of `data/catalog/skyboxes.tsv`".to_owned()
                    }),
                ),
            );
        }
    }
    for d in arr(value, "doors") {
        let (Some(id), Some(wall0)) = (s(d, "id"), s(d, "wall0")) else { continue };
        if wall0.ends_with("|exterior") || s(d, "room0") == Some("exterior") {
            ctx.push(
                Diagnostic::new(Code::W0610, format!("the door `{id}` to the outside is written from outside its room"))
                    .with_primary(ctx.span_of("wall0", wall0, 0), "the exterior side")
                    .with_note("AI2-THOR places the door and opens it from `wall0`/`room0`; ProcTHOR writes the room's own wall there and the room as both `room0` and `room1`")
                    .with_help("swap `wall0` and `wall1`, and name the room in `room0`"),
            );
        }
    }
}

/// Whether objects stand where they can: floor objects not sunk into the floor, items nested on
/// a receptacle resting on its top, the agent not inside a footprint.
fn resting_checks(ctx: &mut Ctx<'_>, top: &[Value], objects_catalog: &Catalog, value: &Value) {
    // The catalog's box is the asset upright; an object tipped about x or z (a bat lying on its
    // side) has another height, so it is not checked.
    let upright = |o: &Value| {
        let r = o.get("rotation");
        ["x", "z"].iter().all(|k| r.and_then(|r| num(r, k)).is_none_or(|a| a.abs() < 1.0))
    };
    let size = |o: &Value| {
        s(o, "assetId")
            .and_then(|a| objects_catalog.get(a))
            .map(|a| a.bbox_m)
            .filter(|_| upright(o))
    };
    let y_of = |o: &Value| o.get("position").and_then(|p| num(p, "y"));
    let mut floor_boxes: Vec<(Point, [f64; 2], f64)> = Vec::new();
    for o in top {
        let (Some([w, h, d]), Some(y), Some(id)) = (size(o), y_of(o), s(o, "id")) else { continue };
        let bottom = y - h / 2.0;
        if bottom < -FLOOR_TOLERANCE_M {
            ctx.push(
                Diagnostic::new(
                    Code::W0611,
                    format!("object `{id}` is sunk {:.2} m into the floor", -bottom),
                )
                .with_primary(ctx.span_of("id", id, 0), "its bottom is under the floor")
                .with_help(format!("raise it to y = {:.3} (half its height)", h / 2.0)),
            );
        }
        if bottom.abs() <= FLOOR_TOLERANCE_M {
            if let Some(p) = o.get("position").and_then(floor_point) {
                let angle = o.get("rotation").and_then(|r| num(r, "y")).unwrap_or(0.0);
                floor_boxes.push((p, [w / 2.0, d / 2.0], angle));
            }
        }
        // A towel holder's towels hang from its bar: their top at the holder's top.
        let bar = s(o, "assetId")
            .and_then(|a| objects_catalog.get(a))
            .is_some_and(|a| crate::solve::surfaces::has_bar(&a.object_type));
        for c in arr(o, "children") {
            let (Some([_, ch, _]), Some(cy), Some(cid)) = (size(c), y_of(c), s(c, "id")) else {
                continue;
            };
            if bar && (cy + ch / 2.0 - (y + h / 2.0)).abs() <= FLOAT_TOLERANCE_M {
                continue;
            }
            // An item stands on the receptacle's top or on a surface inside it (a shelf, a
            // drawer): its bottom between the receptacle's bottom and a little above its top.
            let bottom_item = cy - ch / 2.0;
            let above = bottom_item - (y + h / 2.0);
            let below = (y - h / 2.0) - bottom_item;
            if above > FLOAT_TOLERANCE_M || below > RESTING_TOLERANCE_M {
                let (what, by) = if above > 0.0 {
                    ("floats", format!("{above:.2} m above the top of"))
                } else {
                    ("hangs", format!("{below:.2} m below the bottom of"))
                };
                ctx.push(
                    Diagnostic::new(
                        Code::W0612,
                        format!("`{cid}` {what} {by} `{id}`, the receptacle it is nested on"),
                    )
                    .with_primary(ctx.span_of("id", cid, 0), "not resting on its receptacle")
                    .with_help(format!("put its centre at y = {:.3}", y + h / 2.0 + ch / 2.0)),
                );
            }
        }
    }
    let agent = value
        .get("metadata")
        .and_then(|m| m.get("agent"))
        .and_then(|a| a.get("position"))
        .and_then(floor_point);
    if let Some(p) = agent {
        let inside = floor_boxes.iter().find(|(c, half, angle)| {
            // The agent's centre in the box's frame.
            let (sn, cs) = angle.to_radians().sin_cos();
            let (dx, dz) = (p[0] - c[0], p[1] - c[1]);
            let lx = dx * cs - dz * sn;
            let lz = dx * sn + dz * cs;
            let ox = (lx.abs() - half[0]).max(0.0);
            let oz = (lz.abs() - half[1]).max(0.0);
            ox.hypot(oz) < super::AGENT_RADIUS_M - VALIDATE_TOLERANCE_M
        });
        if inside.is_some() {
            ctx.push(
                Diagnostic::new(Code::W0613, "the agent starts inside or against a floor object")
                    .with_primary(
                        ctx.span_of_key("agent"),
                        format!("starts at ({:.2}, {:.2})", p[0], p[1]),
                    )
                    .with_note(format!("the agent's radius is {} m", super::AGENT_RADIUS_M))
                    .with_help("move `metadata.agent` and `agentPoses` to free floor"),
            );
        }
    }
}

/// The most overlaps of one floor object worked out exactly, as the sweep meets them; past it
/// the counts are lower bounds.
const OVERLAPS_COUNTED_PER_OBJECT: usize = 64;
/// How far (metres) an item nested on a receptacle may reach under the receptacle's bottom.
const RESTING_TOLERANCE_M: f64 = 0.05;
/// How far (metres) an item nested on a receptacle may hover over its top (physics drops it).
const FLOAT_TOLERANCE_M: f64 = 0.1;

/// How far above the floor (metres) the bottom of an object may be and still count as standing
/// on the floor.
const FLOOR_TOLERANCE_M: f64 = 0.05;

/// The footprint of a floor object: its box seen from above.
struct Footprint<'v> {
    id: &'v str,
    room: Option<&'v str>,
    centre: Point,
    /// Half width and half depth before the rotation.
    half: [f64; 2],
    /// The rotation about the vertical axis, degrees (AI2-THOR: clockwise seen from above).
    angle_deg: f64,
}

impl Footprint<'_> {
    /// The footprint as a parry2d box, shrunk by half the tolerance on every side so that
    /// touching footprints and overlaps within [`VALIDATE_TOLERANCE_M`] do not count.
    fn shape(&self) -> (Isometry2<f32>, Cuboid) {
        let shrink = VALIDATE_TOLERANCE_M / 2.0;
        let half = Vector2::new(
            (self.half[0] - shrink).max(1e-3) as f32,
            (self.half[1] - shrink).max(1e-3) as f32,
        );
        // Clockwise seen from above is a negative angle in the (x, z) plane.
        let iso = Isometry2::new(
            Vector2::new(self.centre[0] as f32, self.centre[1] as f32),
            (-self.angle_deg.to_radians()) as f32,
        );
        (iso, Cuboid::new(half))
    }

    /// Whether the footprint is turned by a multiple of 90° (its bounds are the footprint).
    fn square(&self) -> bool {
        let r = self.angle_deg.rem_euclid(90.0);
        r < 1e-6 || 90.0 - r < 1e-6
    }

    /// The axis-aligned bounds of the (rotated) footprint.
    fn bounds(&self) -> Aabb {
        let (sin, cos) = self.angle_deg.to_radians().sin_cos();
        let corners: Vec<Point> = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .iter()
            .map(|[sx, sz]| {
                let (x, z) = (sx * self.half[0], sz * self.half[1]);
                [self.centre[0] + x * cos + z * sin, self.centre[1] - x * sin + z * cos]
            })
            .collect();
        Aabb::of(&corners)
    }
}

/// The overlaps of one floor object past `PAIR_DETAIL_LIMIT` pairs: how many, and its three
/// partners of least place (the first three of its partners in the file's order).
#[derive(Clone, Copy, Default)]
struct Partners {
    count: usize,
    /// The least places, ascending; `usize::MAX` where there are fewer than three.
    least: [usize; 3],
}

impl Partners {
    fn add(&mut self, j: usize) {
        if self.count == 0 {
            self.least = [usize::MAX; 3];
        }
        self.count += 1;
        let mut j = j;
        for slot in &mut self.least {
            if j < *slot {
                std::mem::swap(slot, &mut j);
            }
        }
    }

    /// The least partners, ascending.
    fn first(&self) -> impl Iterator<Item = usize> + '_ {
        self.least.iter().copied().filter(|j| *j != usize::MAX)
    }
}

/// The footprint of a top-level object that stands on the floor, from its asset's size in the
/// catalog; `None` for objects off the floor (on walls, hanging) and assets of unknown size.
fn floor_footprint<'v>(o: &'v Value, centre: Point, catalog: &Catalog) -> Option<Footprint<'v>> {
    let asset = catalog.get(s(o, "assetId")?)?;
    let [w, h, d] = asset.bbox_m;
    let y = o.get("position").and_then(|p| num(p, "y"))?;
    if (y - h / 2.0).abs() > FLOOR_TOLERANCE_M {
        return None;
    }
    let angle_deg = o.get("rotation").and_then(|r| num(r, "y")).unwrap_or(0.0);
    Some(Footprint { id: "", room: None, centre, half: [w / 2.0, d / 2.0], angle_deg })
}

fn byte_offset(text: &str, line: usize, column: usize) -> usize {
    let mut offset = 0;
    for (i, l) in text.split_inclusive('\n').enumerate() {
        if i + 1 == line {
            return (offset + column.saturating_sub(1)).min(text.len());
        }
        offset += l.len();
    }
    text.len()
}

#[cfg(all(test, feature = "schema"))]
mod own_form_tests {
    use super::*;

    /// The house of every example, as `holoc build` writes it.
    fn example_houses() -> Vec<(String, Value)> {
        let catalog = Catalog::embedded();
        let mut paths: Vec<_> = std::fs::read_dir("examples")
            .expect("the examples")
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "holo"))
            .collect();
        paths.sort();
        assert!(paths.len() >= 10, "{paths:?}");
        paths
            .into_iter()
            .map(|p| {
                let mut sources = SourceMap::new();
                let id = sources
                    .add(p.display().to_string(), std::fs::read_to_string(&p).expect("readable"));
                let built = crate::compile::build(
                    &sources,
                    id,
                    &crate::compile::BuildOptions::new(&catalog),
                );
                let house = built.value.expect("every example builds").house;
                let text = house.to_json_string();
                (p.display().to_string(), serde_json::from_str(&text).expect("JSON"))
            })
            .collect()
    }

    fn schema_check(value: &Value) -> Vec<String> {
        schema_validator()
            .expect("the schema compiles")
            .iter_errors(value)
            .map(|e| e.to_string())
            .collect()
    }

    #[test]
    fn same_json_says_what_comparing_the_trees_says() {
        let texts = [
            "null",
            "true",
            "false",
            "0",
            "1",
            "-1",
            "1.0",
            "-0.0",
            "0.1",
            "1e300",
            "18446744073709551615",
            "-9223372036854775808",
            "\"a\"",
            "\"\"",
            "[]",
            "[1]",
            "[1, 2]",
            "[2, 1]",
            "{}",
            "{\"a\": 1}",
            "{\"a\": 1.0}",
            "{\"a\": 1, \"b\": [true, null]}",
            "{\"b\": [true, null], \"a\": 1}",
            "{\"a\": {\"b\": {}}}",
            "{\"a\": {\"b\": []}}",
            "[[], {}]",
            "[{}, []]",
        ];
        for a in texts {
            for b in texts {
                let (x, y): (Value, Value) =
                    (serde_json::from_str(a).expect(a), serde_json::from_str(b).expect(b));
                assert_eq!(same_json(a.as_bytes(), &y), x == y, "{a} against {b}");
            }
        }
        assert!(!same_json(b"[1", &serde_json::json!([1])));
        assert!(!same_json(b"1 2", &serde_json::json!(1)));
    }

    #[test]
    fn every_built_house_is_in_holocs_own_form_and_follows_the_schema() {
        for (name, house) in example_houses() {
            assert!(in_holocs_own_form(&house), "{name}");
            assert_eq!(schema_check(&house), Vec::<String>::new(), "{name}");
        }
    }

    #[test]
    fn a_house_out_of_the_schemas_bounds_is_checked_against_it() {
        let (_, house) = example_houses().swap_remove(0);
        let mut breaks: Vec<(&str, Value)> = Vec::new();
        let mut v = house.clone();
        v["walls"][0]["polygon"].as_array_mut().expect("a polygon").truncate(3);
        breaks.push(("a wall of three corners", v));
        let mut v = house.clone();
        v["rooms"][0]["floorMaterial"]["color"] = serde_json::json!({"r": 1.5, "g": 0, "b": 0});
        breaks.push(("a colour channel above 1", v));
        let door = house["doors"].as_array().and_then(|d| d.first()).cloned();
        if let Some(mut door) = door {
            let corner = door["holePolygon"][0].clone();
            door["holePolygon"].as_array_mut().expect("a hole").push(corner);
            let mut v = house.clone();
            v["doors"][0] = door;
            breaks.push(("a hole of three corners", v));
        }
        let mut v = house.clone();
        v.as_object_mut().expect("an object").remove("metadata");
        breaks.push(("no metadata", v));
        assert_eq!(breaks.len(), 4, "the first example has a door");
        for (what, v) in breaks {
            assert!(!in_holocs_own_form(&v), "{what}");
            assert!(!schema_check(&v).is_empty(), "{what}: the schema finds it");
            let errors = schema_errors(&v).expect("checked");
            assert!(!errors.is_empty(), "{what}");
        }
        // Written by another tool: an integer where holoc writes a float is read against the
        // schema (and follows it).
        let mut v = house;
        v["walls"][0]["polygon"][0]["y"] = serde_json::json!(0);
        assert!(!in_holocs_own_form(&v));
        assert_eq!(schema_errors(&v).expect("checked"), Vec::<String>::new());
    }

    /// The bounds of the schema that a value of holoc's house type could break: each one is
    /// checked by [`in_holocs_own_form`]. A new bound in the schema fails this test, so that
    /// it is added there too.
    #[test]
    fn the_schemas_bounds_are_the_ones_the_own_form_check_keeps() {
        fn walk(v: &Value, path: &str, out: &mut Vec<String>) {
            const BOUNDS: [&str; 16] = [
                "minimum",
                "maximum",
                "exclusiveMinimum",
                "exclusiveMaximum",
                "multipleOf",
                "minItems",
                "maxItems",
                "uniqueItems",
                "minLength",
                "maxLength",
                "pattern",
                "enum",
                "const",
                "not",
                "minProperties",
                "if",
            ];
            match v {
                Value::Object(map) => {
                    for (k, x) in map {
                        if BOUNDS.contains(&k.as_str()) {
                            out.push(format!("{path}/{k}"));
                        }
                        walk(x, &format!("{path}/{k}"), out);
                    }
                }
                Value::Array(items) => {
                    for (i, x) in items.iter().enumerate() {
                        walk(x, &format!("{path}/{i}"), out);
                    }
                }
                _ => {}
            }
        }
        let schema: Value = serde_json::from_str(HOUSE_SCHEMA).expect("the schema");
        let mut bounds = Vec::new();
        walk(&schema, "", &mut bounds);
        bounds.sort();
        let kept: Vec<String> = ["a", "b", "g", "r"]
            .iter()
            .flat_map(|c| {
                ["maximum", "minimum"].map(|k| format!("/definitions/color/properties/{c}/{k}"))
            })
            .chain([
                "/definitions/hole/anyOf/0/properties/holePolygon/maxItems".to_string(),
                "/definitions/hole/anyOf/0/properties/holePolygon/minItems".to_string(),
                "/properties/walls/items/properties/polygon/minItems".to_string(),
            ])
            .collect();
        assert_eq!(bounds, kept, "a new bound of the schema: keep it in `in_holocs_own_form`");
    }
}
