//! The semantic diff of two houses (`holoc diff`, `holoc test`): what changed in the rooms,
//! doors, windows, objects (and the items on them), relations, agent start, lights and
//! metadata, within tolerances, rather than which lines of the JSON differ.
//!
//! Objects are paired by id, then, among those left, by category (the instance name without
//! its number) and nearest position, so a renamed or renumbered chair that moved is one chair
//! that moved, not one removed and one added. Rooms are paired by id, doors and windows by id
//! and then by their sides and nearest position along the wall. Relations come from the build
//! reports when both houses have one.
//!
//! **Invariants:** the diff is a pure function of the two houses and the options; the changes
//! come out in a fixed order (by room, most important first); `diff(a, a)` is empty and
//! `diff(b, a)` is `diff(a, b)` mirrored ([`Change::mirror`]). The work is linear in the size
//! of the houses, except the nearest-position pairing, which is quadratic in the number of
//! objects of one category that the ids do not pair (few in practice).

pub mod folder;
pub mod house;

pub use house::HouseView;

use house::{HoleView, ObjectView};
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

/// How far two values may differ and still count as the same.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Lengths, metres.
    pub metres: f64,
    /// Angles, degrees.
    pub degrees: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance { metres: 0.01, degrees: 1.0 }
    }
}

impl Tolerance {
    /// Reads `1cm,1deg` (lengths in `mm`, `cm` or `m`, angles in `deg` or `°`; either part
    /// alone, the other keeps its default).
    pub fn parse(text: &str) -> Result<Tolerance, String> {
        let mut t = Tolerance::default();
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let split =
                part.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(part.len());
            let (number, unit) = part.split_at(split);
            let value: f64 = number.parse().map_err(|_| {
                format!(
                    "`{part}` is not a tolerance: write a number and a unit, e.g. `1cm` or `1deg`"
                )
            })?;
            match unit.trim() {
                "mm" => t.metres = value / 1000.0,
                "cm" => t.metres = value / 100.0,
                "m" => t.metres = value,
                "deg" | "°" | "degrees" => t.degrees = value,
                other => {
                    return Err(format!(
                        "`{other}` is not a unit of a tolerance: use mm, cm or m for lengths and deg for angles"
                    ))
                }
            }
        }
        Ok(t)
    }
}

impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let cm = self.metres * 100.0;
        write!(f, "{} cm, {}°", trim(cm), trim(self.degrees))
    }
}

/// Groups of fields that `--ignore` leaves out of the comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Group {
    /// Rooms: added, removed, reshaped, their type.
    Rooms,
    /// Floor and wall materials.
    Materials,
    /// Doors.
    Doors,
    /// Windows.
    Windows,
    /// Objects (and the items on them).
    Objects,
    /// Items on top of other objects only.
    Items,
    /// The assets of objects, doors and windows (a changed asset is not a difference).
    Assets,
    /// Relations from the build reports.
    Relations,
    /// The agent's start.
    Agent,
    /// Lights.
    Lights,
    /// Skybox, schema, ceiling, request and seed.
    Metadata,
}

/// What the diff compares.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    /// The tolerances.
    pub tolerance: Tolerance,
    /// The groups left out.
    pub ignore: Vec<Group>,
}

impl Options {
    fn ignores(&self, g: Group) -> bool {
        self.ignore.contains(&g)
    }
}

/// The kinds of change, most important first (the order of the output).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A room is only in the second house.
    RoomAdded,
    /// A room is only in the first house.
    RoomRemoved,
    /// A room's outline changed.
    RoomReshaped,
    /// A room's type changed.
    RoomTypeChanged,
    /// A door is only in the second house.
    DoorAdded,
    /// A door is only in the first house.
    DoorRemoved,
    /// A door moved along its wall or to another wall.
    DoorMoved,
    /// A window is only in the second house.
    WindowAdded,
    /// A window is only in the first house.
    WindowRemoved,
    /// A window moved along its wall or to another wall.
    WindowMoved,
    /// An object is only in the second house.
    ObjectAdded,
    /// An object is only in the first house.
    ObjectRemoved,
    /// An object became an object of another type.
    TypeChanged,
    /// An object has another id, with the same asset at the same place.
    ObjectRenamed,
    /// An item stands on another receptacle (or on the floor).
    ReceptacleChanged,
    /// An object moved or turned.
    ObjectMoved,
    /// A relation the first layout keeps, the second does not.
    RelationBroken,
    /// A relation the first layout does not keep, the second does.
    RelationRestored,
    /// An object, door or window has another asset of the same type.
    AssetChanged,
    /// A floor or wall material changed.
    MaterialChanged,
    /// The agent starts elsewhere.
    AgentMoved,
    /// A light is only in the second house.
    LightAdded,
    /// A light is only in the first house.
    LightRemoved,
    /// A light moved or changed its intensity, colour or range.
    LightChanged,
    /// A setting of the scene changed (skybox, schema, ceiling, request, seed).
    MetadataChanged,
}

impl Kind {
    /// The change seen from the other side (`diff(b, a)`).
    #[must_use]
    pub fn mirror(self) -> Kind {
        match self {
            Kind::RoomAdded => Kind::RoomRemoved,
            Kind::RoomRemoved => Kind::RoomAdded,
            Kind::DoorAdded => Kind::DoorRemoved,
            Kind::DoorRemoved => Kind::DoorAdded,
            Kind::WindowAdded => Kind::WindowRemoved,
            Kind::WindowRemoved => Kind::WindowAdded,
            Kind::ObjectAdded => Kind::ObjectRemoved,
            Kind::ObjectRemoved => Kind::ObjectAdded,
            Kind::RelationBroken => Kind::RelationRestored,
            Kind::RelationRestored => Kind::RelationBroken,
            Kind::LightAdded => Kind::LightRemoved,
            Kind::LightRemoved => Kind::LightAdded,
            other => other,
        }
    }

    /// How the summary line counts it: (one, many).
    fn phrase(self) -> (&'static str, &'static str) {
        match self {
            Kind::RoomAdded => ("room added", "rooms added"),
            Kind::RoomRemoved => ("room removed", "rooms removed"),
            Kind::RoomReshaped => ("room reshaped", "rooms reshaped"),
            Kind::RoomTypeChanged => ("room type changed", "room types changed"),
            Kind::DoorAdded => ("door added", "doors added"),
            Kind::DoorRemoved => ("door removed", "doors removed"),
            Kind::DoorMoved => ("door moved", "doors moved"),
            Kind::WindowAdded => ("window added", "windows added"),
            Kind::WindowRemoved => ("window removed", "windows removed"),
            Kind::WindowMoved => ("window moved", "windows moved"),
            Kind::ObjectAdded => ("object added", "objects added"),
            Kind::ObjectRemoved => ("object removed", "objects removed"),
            Kind::TypeChanged => ("type changed", "types changed"),
            Kind::ObjectRenamed => ("object renamed", "objects renamed"),
            Kind::ReceptacleChanged => ("receptacle changed", "receptacles changed"),
            Kind::ObjectMoved => ("object moved", "objects moved"),
            Kind::RelationBroken => ("relation no longer kept", "relations no longer kept"),
            Kind::RelationRestored => ("relation now kept", "relations now kept"),
            Kind::AssetChanged => ("asset changed", "assets changed"),
            Kind::MaterialChanged => ("material changed", "materials changed"),
            Kind::AgentMoved => ("agent start moved", "agent starts moved"),
            Kind::LightAdded => ("light added", "lights added"),
            Kind::LightRemoved => ("light removed", "lights removed"),
            Kind::LightChanged => ("light changed", "lights changed"),
            Kind::MetadataChanged => ("setting changed", "settings changed"),
        }
    }
}

/// One difference between the two houses.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Change {
    /// What changed.
    pub kind: Kind,
    /// The room it is shown under (the second house's room; the first's for what was
    /// removed); empty for the house as a whole.
    pub room: String,
    /// The first house's room, when an object changed rooms.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from_room: Option<String>,
    /// What changed: an object's, door's, window's, light's or room's id, `floor` or `walls`
    /// for materials, `agent`, or a setting's name.
    pub subject: String,
    /// The first house's id of a paired object, door or window whose id changed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub was: Option<String>,
    /// The two types of a type change (the catalog's AI2-THOR types), `before → after`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub types: Option<(String, String)>,
    /// The value in the first house (an asset, material, type, receptacle, area…).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub before: Option<String>,
    /// The value in the second house.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub after: Option<String>,
    /// How far it moved, metres.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_m: Option<f64>,
    /// How far it turned, degrees (−180…180, counter-clockwise seen from above is positive).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turn_deg: Option<f64>,
    /// The relation, for a relation kept or no longer kept.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relation: Option<String>,
}

impl Change {
    fn new(kind: Kind, room: &str, subject: &str) -> Change {
        Change {
            kind,
            room: room.to_string(),
            from_room: None,
            subject: subject.to_string(),
            was: None,
            types: None,
            before: None,
            after: None,
            distance_m: None,
            turn_deg: None,
            relation: None,
        }
    }

    fn values(mut self, before: impl Into<String>, after: impl Into<String>) -> Change {
        self.before = Some(before.into());
        self.after = Some(after.into());
        self
    }

    /// The same change seen from the other side: added and removed swap, as do before and
    /// after, the two rooms and the two ids; a turn changes sign.
    #[must_use]
    pub fn mirror(&self) -> Change {
        let mut m = self.clone();
        m.kind = self.kind.mirror();
        std::mem::swap(&mut m.before, &mut m.after);
        m.types = self.types.clone().map(|(x, y)| (y, x));
        if let Some(from) = &self.from_room {
            m.room.clone_from(from);
            m.from_room = Some(self.room.clone());
        }
        if let Some(was) = &self.was {
            m.subject.clone_from(was);
            m.was = Some(self.subject.clone());
        }
        // A half turn stays +180° both ways (turns are in (−180, 180]).
        m.turn_deg = self.turn_deg.map(|t| if t == 0.0 || t == 180.0 { t } else { -t });
        m
    }

    /// The sigil of a line: `+` added, `-` removed, `!` no longer kept, `~` changed.
    fn sigil(&self) -> char {
        match self.kind {
            Kind::RoomAdded
            | Kind::DoorAdded
            | Kind::WindowAdded
            | Kind::ObjectAdded
            | Kind::LightAdded => '+',
            Kind::RoomRemoved
            | Kind::DoorRemoved
            | Kind::WindowRemoved
            | Kind::ObjectRemoved
            | Kind::LightRemoved => '-',
            Kind::RelationBroken => '!',
            _ => '~',
        }
    }

    /// The change as one line of text (without the sigil).
    pub fn text(&self) -> String {
        let b = self.before.as_deref().unwrap_or("");
        let a = self.after.as_deref().unwrap_or("");
        let s = &self.subject;
        let moved = || {
            let mut parts = Vec::new();
            if let Some(d) = self.distance_m {
                parts.push(format!("moved {}", metres(d)));
            }
            if let Some(t) = self.turn_deg {
                parts.push(format!("turned {}", degrees(t)));
            }
            if let Some(from) = &self.from_room {
                parts.push(format!("from {from}"));
            }
            parts.join(", ")
        };
        let was = self.was.as_ref().map(|w| format!(" (was {w})")).unwrap_or_default();
        match self.kind {
            Kind::RoomAdded => format!("room {s} added ({a})"),
            Kind::RoomRemoved => format!("room {s} removed ({b})"),
            Kind::RoomReshaped => format!("outline of {s} changed: {b} → {a}"),
            Kind::RoomTypeChanged => format!("type of {s}: {b} → {a}"),
            Kind::DoorAdded | Kind::WindowAdded | Kind::ObjectAdded => format!("{s} added ({a})"),
            Kind::DoorRemoved | Kind::WindowRemoved | Kind::ObjectRemoved => {
                format!("{s} removed ({b})")
            }
            Kind::DoorMoved | Kind::WindowMoved => {
                if b == a {
                    format!(
                        "{s}{was} moved {} along its wall",
                        metres(self.distance_m.unwrap_or(0.0))
                    )
                } else {
                    format!("{s}{was} moved from wall {b} to wall {a}")
                }
            }
            Kind::TypeChanged => {
                let (tb, ta) = self.types.clone().unwrap_or_default();
                format!("{s}{was} type {tb} → {ta} (asset {b} → {a})")
            }
            Kind::ObjectRenamed => format!(
                "{s} renamed (was {}; same asset and place)",
                self.was.as_deref().unwrap_or("")
            ),
            Kind::ReceptacleChanged => format!("{s}{was} stands on {a} (was on {b})"),
            Kind::ObjectMoved | Kind::AgentMoved => {
                let what = if self.kind == Kind::AgentMoved { "agent start" } else { s.as_str() };
                format!("{what}{was} {}", moved())
            }
            Kind::RelationBroken | Kind::RelationRestored => {
                let r = self.relation.as_deref().unwrap_or("");
                let state =
                    if self.kind == Kind::RelationBroken { "no longer kept" } else { "now kept" };
                format!("{s}: `{r}` {state}")
            }
            Kind::AssetChanged => format!("{s}{was} asset {b} → {a}"),
            Kind::MaterialChanged => format!("{s} material {b} → {a}"),
            Kind::LightAdded => format!("light {s} added"),
            Kind::LightRemoved => format!("light {s} removed"),
            Kind::LightChanged => {
                let mut parts = Vec::new();
                if let Some(d) = self.distance_m {
                    parts.push(format!("moved {}", metres(d)));
                }
                if b != a {
                    parts.push(format!("{b} → {a}"));
                }
                format!("light {s} {}", parts.join(", "))
            }
            Kind::MetadataChanged => format!("{s}: {b} → {a}"),
        }
    }
}

/// A number with at most two decimals, without trailing zeros.
fn trim(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn metres(v: f64) -> String {
    if v < 1.0 {
        format!("{} cm", trim(v * 100.0))
    } else {
        format!("{} m", trim(v))
    }
}

fn degrees(v: f64) -> String {
    format!("{}{}°", if v > 0.0 { "+" } else { "" }, trim(v))
}

/// A rounded value for the output (1e-4), so that noise below the tolerances never shows.
fn r4(v: f64) -> f64 {
    let r = (v * 10_000.0).round() / 10_000.0;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// The differences between two houses, in output order.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Diff {
    /// The changes, grouped by room (most important room first), most important first.
    pub changes: Vec<Change>,
}

impl Diff {
    /// Whether the houses are the same within the tolerances.
    pub fn is_empty(&self) -> bool {
        self.changes.is_empty()
    }

    /// How many changes of each kind, in the kinds' order.
    pub fn counts(&self) -> BTreeMap<Kind, usize> {
        let mut counts = BTreeMap::new();
        for c in &self.changes {
            *counts.entry(c.kind).or_insert(0) += 1;
        }
        counts
    }

    /// The one-line summary: `2 objects moved, 1 asset changed, 1 relation no longer kept`,
    /// or `no differences`.
    pub fn summary(&self) -> String {
        summary_of(&self.counts())
    }

    /// The changes grouped by room, as text: a heading per room (`house` for the house as a
    /// whole), one indented line per change.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let mut current: Option<&str> = None;
        for c in &self.changes {
            if current != Some(c.room.as_str()) {
                let heading = if c.room.is_empty() { "house" } else { c.room.as_str() };
                out.push_str(heading);
                out.push_str(":\n");
                current = Some(c.room.as_str());
            }
            let _ = writeln!(out, "  {} {}", c.sigil(), c.text());
        }
        out
    }
}

/// The summary line of counts by kind.
pub fn summary_of(counts: &BTreeMap<Kind, usize>) -> String {
    let parts: Vec<String> = counts
        .iter()
        .filter(|(_, n)| **n > 0)
        .map(|(k, n)| {
            let (one, many) = k.phrase();
            format!("{n} {}", if *n == 1 { one } else { many })
        })
        .collect();
    if parts.is_empty() {
        "no differences".to_string()
    } else {
        parts.join(", ")
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The turn from `a` to `b`, degrees, in (−180, 180] (rounded first, so that a half turn is
/// +180° both ways).
fn turn(a: f64, b: f64) -> f64 {
    let d = r4((b - a).rem_euclid(360.0)) % 360.0;
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

fn pos_text(p: [f64; 3]) -> String {
    format!("{}, {}, {}", trim(p[0]), trim(p[1]), trim(p[2]))
}

/// Pairs the items of two lists by equal `id` (the first of each id). Returns the pairs
/// (indices) and the unpaired indices of each side.
fn pair_by_id<T>(
    a: &[T],
    b: &[T],
    id: impl Fn(&T) -> &str,
) -> (Vec<(usize, usize)>, Vec<usize>, Vec<usize>) {
    let mut by_id: HashMap<&str, usize> = HashMap::with_capacity(a.len());
    for (i, x) in a.iter().enumerate() {
        by_id.entry(id(x)).or_insert(i);
    }
    let mut used_a = vec![false; a.len()];
    let mut pairs = Vec::new();
    let mut left_b = Vec::new();
    for (j, y) in b.iter().enumerate() {
        match by_id.get(id(y)) {
            Some(&i) if !used_a[i] => {
                used_a[i] = true;
                pairs.push((i, j));
            }
            _ => left_b.push(j),
        }
    }
    let left_a = (0..a.len()).filter(|&i| !used_a[i]).collect();
    (pairs, left_a, left_b)
}

/// Pairs the items of two lists: first by equal `id`, then, among those left, within equal
/// `group` by smallest `distance` (ties broken by the two ids, the same way whichever list
/// comes first). Returns the pairs (indices) and the unpaired indices of each side.
fn pair<T>(
    a: &[T],
    b: &[T],
    id: impl Fn(&T) -> &str,
    group: impl Fn(&T) -> String,
    distance: impl Fn(&T, &T) -> f64,
) -> (Vec<(usize, usize)>, Vec<usize>, Vec<usize>) {
    let (mut pairs, left_a, left_b) = pair_by_id(a, b, &id);
    if left_a.is_empty() || left_b.is_empty() {
        return (pairs, left_a, left_b);
    }
    let mut groups: BTreeMap<String, (Vec<usize>, Vec<usize>)> = BTreeMap::new();
    for &i in &left_a {
        groups.entry(group(&a[i])).or_default().0.push(i);
    }
    for &j in &left_b {
        groups.entry(group(&b[j])).or_default().1.push(j);
    }
    let mut taken_a = vec![false; a.len()];
    let mut taken_b = vec![false; b.len()];
    for (ga, gb) in groups.values() {
        if ga.is_empty() || gb.is_empty() {
            continue;
        }
        let mut candidates: Vec<(f64, &str, &str, usize, usize)> = Vec::new();
        for &i in ga {
            for &j in gb {
                let (x, y) = (id(&a[i]), id(&b[j]));
                let (lo, hi) = if x <= y { (x, y) } else { (y, x) };
                candidates.push((distance(&a[i], &b[j]), lo, hi, i, j));
            }
        }
        candidates.sort_by(|p, q| {
            p.0.total_cmp(&q.0).then_with(|| p.1.cmp(q.1)).then_with(|| p.2.cmp(q.2))
        });
        for (_, _, _, i, j) in candidates {
            if !taken_a[i] && !taken_b[j] {
                taken_a[i] = true;
                taken_b[j] = true;
                pairs.push((i, j));
            }
        }
    }
    let left_a = left_a.into_iter().filter(|&i| !taken_a[i]).collect();
    let left_b = left_b.into_iter().filter(|&j| !taken_b[j]).collect();
    (pairs, left_a, left_b)
}

/// Whether two outlines are the same within `tol` metres, whatever corner each starts at.
fn same_outline(a: &[[f64; 2]], b: &[[f64; 2]], tol: f64) -> bool {
    if a.len() != b.len() {
        return false;
    }
    if a.is_empty() {
        return true;
    }
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) <= tol;
    (0..b.len()).any(|shift| (0..a.len()).all(|i| close(a[i], b[(i + shift) % b.len()])))
}

/// Compares two houses.
pub fn diff(a: &HouseView, b: &HouseView, options: &Options) -> Diff {
    let tol = options.tolerance;
    let mut out: Vec<Change> = Vec::new();
    if !options.ignores(Group::Rooms) || !options.ignores(Group::Materials) {
        rooms(a, b, options, &mut out);
    }
    if !options.ignores(Group::Doors) {
        holes(&a.doors, &b.doors, true, options, &mut out);
    }
    if !options.ignores(Group::Windows) {
        holes(&a.windows, &b.windows, false, options, &mut out);
    }
    if !options.ignores(Group::Objects) {
        objects(a, b, options, &mut out);
    }
    if !options.ignores(Group::Relations) {
        if let (Some(ra), Some(rb)) = (&a.relations, &b.relations) {
            let before: HashMap<(&str, &str), bool> =
                ra.iter().map(|r| ((r.object.as_str(), r.constraint.as_str()), r.kept)).collect();
            for r in rb {
                if let Some(&was) = before.get(&(r.object.as_str(), r.constraint.as_str())) {
                    if was != r.kept {
                        let kind =
                            if r.kept { Kind::RelationRestored } else { Kind::RelationBroken };
                        let mut c = Change::new(kind, &r.room, &r.object);
                        c.relation = Some(r.constraint.clone());
                        out.push(c);
                    }
                }
            }
        }
    }
    if !options.ignores(Group::Agent) {
        if let (Some(pa), Some(pb)) = (a.agent, b.agent) {
            let d = dist(pa.position, pb.position);
            let t = turn(pa.rotation_deg, pb.rotation_deg);
            if d > tol.metres
                || t.abs() > tol.degrees
                || (pa.horizon - pb.horizon).abs() > tol.degrees
            {
                let mut c = Change::new(Kind::AgentMoved, "", "agent")
                    .values(pos_text(pa.position), pos_text(pb.position));
                c.distance_m = (d > tol.metres).then(|| r4(d));
                c.turn_deg = (t.abs() > tol.degrees).then(|| r4(t));
                out.push(c);
            }
        }
    }
    if !options.ignores(Group::Lights) {
        lights(a, b, tol, &mut out);
    }
    if !options.ignores(Group::Metadata) {
        let before: HashMap<&str, &str> =
            a.metadata.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        let after: HashMap<&str, &str> =
            b.metadata.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        let mut keys: Vec<&str> = before.keys().chain(after.keys()).copied().collect();
        keys.sort_unstable();
        keys.dedup();
        for k in keys {
            // A setting only one side has (a report on one side only) is not compared.
            if let (Some(x), Some(y)) = (before.get(k), after.get(k)) {
                if x != y {
                    out.push(Change::new(Kind::MetadataChanged, "", k).values(*x, *y));
                }
            }
        }
    }
    order(&mut out);
    Diff { changes: out }
}

/// Sorts changes by room (the room of the most important change first), then by kind and
/// subject.
fn order(changes: &mut [Change]) {
    let mut rank: HashMap<String, Kind> = HashMap::new();
    for c in changes.iter() {
        let e = rank.entry(c.room.clone()).or_insert(c.kind);
        if c.kind < *e {
            *e = c.kind;
        }
    }
    changes.sort_by(|x, y| {
        rank[&x.room]
            .cmp(&rank[&y.room])
            .then_with(|| x.room.cmp(&y.room))
            .then_with(|| x.kind.cmp(&y.kind))
            .then_with(|| x.subject.cmp(&y.subject))
            .then_with(|| x.relation.cmp(&y.relation))
            .then_with(|| x.was.cmp(&y.was))
    });
}

fn rooms(a: &HouseView, b: &HouseView, options: &Options, out: &mut Vec<Change>) {
    let area = |r: &house::RoomView| format!("{} m²", trim(r.area_m2()));
    // Rooms pair by id only: a nearest-room pairing would call a renamed room a moved one.
    let (pairs, left_a, left_b) = pair_by_id(&a.rooms, &b.rooms, |r| r.id.as_str());
    if !options.ignores(Group::Rooms) {
        for i in left_a {
            let r = &a.rooms[i];
            out.push(
                Change::new(Kind::RoomRemoved, &r.id, &r.id)
                    .values(format!("{}, {}", r.room_type, area(r)), ""),
            );
        }
        for j in left_b {
            let r = &b.rooms[j];
            out.push(
                Change::new(Kind::RoomAdded, &r.id, &r.id)
                    .values("", format!("{}, {}", r.room_type, area(r))),
            );
        }
    }
    for (i, j) in pairs {
        let (x, y) = (&a.rooms[i], &b.rooms[j]);
        if !options.ignores(Group::Rooms) {
            if !same_outline(&x.outline, &y.outline, options.tolerance.metres) {
                out.push(Change::new(Kind::RoomReshaped, &y.id, &y.id).values(area(x), area(y)));
            }
            if x.room_type != y.room_type {
                out.push(
                    Change::new(Kind::RoomTypeChanged, &y.id, &y.id)
                        .values(&x.room_type, &y.room_type),
                );
            }
        }
        if !options.ignores(Group::Materials) {
            if x.floor_material != y.floor_material {
                out.push(
                    Change::new(Kind::MaterialChanged, &y.id, "floor")
                        .values(&x.floor_material, &y.floor_material),
                );
            }
            if x.wall_material != y.wall_material {
                out.push(
                    Change::new(Kind::MaterialChanged, &y.id, "walls")
                        .values(&x.wall_material, &y.wall_material),
                );
            }
        }
    }
}

fn holes(a: &[HoleView], b: &[HoleView], doors: bool, options: &Options, out: &mut Vec<Change>) {
    let (added, removed, moved) = if doors {
        (Kind::DoorAdded, Kind::DoorRemoved, Kind::DoorMoved)
    } else {
        (Kind::WindowAdded, Kind::WindowRemoved, Kind::WindowMoved)
    };
    let (pairs, left_a, left_b) = pair(
        a,
        b,
        |h| h.id.as_str(),
        |h| format!("{}|{}", h.sides.0, h.sides.1),
        |x, y| if x.wall == y.wall { (x.offset_m - y.offset_m).abs() } else { 1e6 },
    );
    for i in left_a {
        out.push(Change::new(removed, &a[i].room, &a[i].id).values(&a[i].asset, ""));
    }
    for j in left_b {
        out.push(Change::new(added, &b[j].room, &b[j].id).values("", &b[j].asset));
    }
    for (i, j) in pairs {
        let (x, y) = (&a[i], &b[j]);
        let was = (x.id != y.id).then(|| x.id.clone());
        let from_room = (x.room != y.room).then(|| x.room.clone());
        let d = (x.offset_m - y.offset_m).abs();
        if x.wall != y.wall || d > options.tolerance.metres {
            let mut c = Change::new(moved, &y.room, &y.id).values(&x.wall, &y.wall);
            c.distance_m = (x.wall == y.wall).then(|| r4(d));
            c.was.clone_from(&was);
            c.from_room.clone_from(&from_room);
            out.push(c);
        }
        if x.asset != y.asset && !options.ignores(Group::Assets) {
            let mut c = Change::new(Kind::AssetChanged, &y.room, &y.id).values(&x.asset, &y.asset);
            c.was = was;
            c.from_room = from_room;
            out.push(c);
        }
    }
}

fn objects(a: &HouseView, b: &HouseView, options: &Options, out: &mut Vec<Change>) {
    let tol = options.tolerance;
    let items = !options.ignores(Group::Items);
    let keep = |o: &&ObjectView| items || o.parent.is_none();
    let xs: Vec<&ObjectView> = a.objects.iter().filter(keep).collect();
    let ys: Vec<&ObjectView> = b.objects.iter().filter(keep).collect();
    let (mut pairs, left_a, left_b) = pair(
        &xs,
        &ys,
        |o| o.id.as_str(),
        |o| format!("{}|{}", o.category, u8::from(o.parent.is_some())),
        |x, y| dist(x.position, y.position),
    );
    // A renamed object (another name, so another category): the same asset at the same place,
    // paired one to one, nearest first.
    let (left_a, left_b) = renames(&xs, &ys, left_a, left_b, tol, &mut pairs);
    // The second house's id of each paired object of the first, for receptacles.
    let renamed: HashMap<&str, &str> =
        pairs.iter().map(|&(i, j)| (xs[i].id.as_str(), ys[j].id.as_str())).collect();
    let on = |o: &ObjectView| o.parent.clone().unwrap_or_else(|| "the floor".to_string());
    for i in left_a {
        let o = xs[i];
        let mut c = Change::new(Kind::ObjectRemoved, &o.room, &o.id).values(&o.asset, "");
        if let Some(p) = &o.parent {
            c.before = Some(format!("{}, on {p}", o.asset));
        }
        out.push(c);
    }
    for j in left_b {
        let o = ys[j];
        let mut c = Change::new(Kind::ObjectAdded, &o.room, &o.id).values("", &o.asset);
        if let Some(p) = &o.parent {
            c.after = Some(format!("{}, on {p}", o.asset));
        }
        out.push(c);
    }
    for (i, j) in pairs {
        let (x, y) = (xs[i], ys[j]);
        let before = out.len();
        let was = (x.id != y.id).then(|| x.id.clone());
        let from_room = (x.room != y.room).then(|| x.room.clone());
        let d = dist(x.position, y.position);
        let t = turn(x.rotation_deg, y.rotation_deg);
        if d > tol.metres || t.abs() > tol.degrees || from_room.is_some() {
            let mut c = Change::new(Kind::ObjectMoved, &y.room, &y.id)
                .values(pos_text(x.position), pos_text(y.position));
            c.distance_m = (d > tol.metres).then(|| r4(d));
            c.turn_deg = (t.abs() > tol.degrees).then(|| r4(t));
            c.from_room.clone_from(&from_room);
            c.was.clone_from(&was);
            out.push(c);
        }
        let parent_then = x.parent.as_deref().map(|p| renamed.get(p).copied().unwrap_or(p));
        if parent_then != y.parent.as_deref() {
            let mut c = Change::new(Kind::ReceptacleChanged, &y.room, &y.id).values(on(x), on(y));
            c.was.clone_from(&was);
            c.from_room.clone_from(&from_room);
            out.push(c);
        }
        if x.asset != y.asset && !options.ignores(Group::Assets) {
            // The types are the catalog's (a Dresser is a Dresser whatever its asset's id
            // begins with); an asset no catalog knows and whose id names no type (an
            // Objaverse hash) only changed its asset.
            let kind = match (x.type_name(), y.type_name()) {
                (Some(p), Some(q)) if p != q => Kind::TypeChanged,
                _ => Kind::AssetChanged,
            };
            let mut c = Change::new(kind, &y.room, &y.id).values(&x.asset, &y.asset);
            if kind == Kind::TypeChanged {
                c.types = Some((
                    x.type_name().unwrap_or_default().to_string(),
                    y.type_name().unwrap_or_default().to_string(),
                ));
            }
            c.was.clone_from(&was);
            c.from_room.clone_from(&from_room);
            out.push(c);
        }
        // A rename with nothing else changed is one line of its own.
        if out.len() == before {
            if let Some(was) = was {
                let mut c = Change::new(Kind::ObjectRenamed, &y.room, &y.id);
                c.was = Some(was);
                out.push(c);
            }
        }
    }
}

/// Pairs the objects the ids and categories left unpaired that have the same asset and stand
/// at the same place within the tolerances (nearest first, ties by the ids); returns those
/// still unpaired.
fn renames(
    xs: &[&ObjectView],
    ys: &[&ObjectView],
    left_a: Vec<usize>,
    left_b: Vec<usize>,
    tol: Tolerance,
    pairs: &mut Vec<(usize, usize)>,
) -> (Vec<usize>, Vec<usize>) {
    let mut candidates: Vec<(f64, &str, &str, usize, usize)> = Vec::new();
    let mut by_asset: HashMap<&str, Vec<usize>> = HashMap::new();
    for &j in &left_b {
        by_asset.entry(ys[j].asset.as_str()).or_default().push(j);
    }
    for &i in &left_a {
        for &j in by_asset.get(xs[i].asset.as_str()).into_iter().flatten() {
            let (x, y) = (xs[i], ys[j]);
            let d = dist(x.position, y.position);
            if d <= tol.metres
                && turn(x.rotation_deg, y.rotation_deg).abs() <= tol.degrees
                && x.parent.is_some() == y.parent.is_some()
            {
                // Ties broken the same way whichever house comes first.
                let (lo, hi) = if x.id <= y.id { (&x.id, &y.id) } else { (&y.id, &x.id) };
                candidates.push((d, lo.as_str(), hi.as_str(), i, j));
            }
        }
    }
    candidates
        .sort_by(|p, q| p.0.total_cmp(&q.0).then_with(|| p.1.cmp(q.1)).then_with(|| p.2.cmp(q.2)));
    let mut taken_a = vec![false; xs.len()];
    let mut taken_b = vec![false; ys.len()];
    for (_, _, _, i, j) in candidates {
        if !taken_a[i] && !taken_b[j] {
            taken_a[i] = true;
            taken_b[j] = true;
            pairs.push((i, j));
        }
    }
    (
        left_a.into_iter().filter(|&i| !taken_a[i]).collect(),
        left_b.into_iter().filter(|&j| !taken_b[j]).collect(),
    )
}

fn lights(a: &HouseView, b: &HouseView, tol: Tolerance, out: &mut Vec<Change>) {
    let room = |l: &house::LightView| l.room.clone().unwrap_or_default();
    let (pairs, unpaired_a, unpaired_b) = pair_by_id(&a.lights, &b.lights, |l| l.id.as_str());
    for &(i, j) in &pairs {
        let (x, y) = (&a.lights[i], &b.lights[j]);
        let d = dist(x.position, y.position);
        let mut dx = Vec::new();
        let mut dy = Vec::new();
        if (x.intensity - y.intensity).abs() > 1e-3 {
            dx.push(format!("intensity {}", trim(x.intensity)));
            dy.push(format!("intensity {}", trim(y.intensity)));
        }
        if x.rgb.iter().zip(&y.rgb).any(|(p, q)| (p - q).abs() > 1e-3) {
            let rgb = |c: [f64; 3]| format!("colour {} {} {}", trim(c[0]), trim(c[1]), trim(c[2]));
            dx.push(rgb(x.rgb));
            dy.push(rgb(y.rgb));
        }
        if x.range.unwrap_or(0.0) != y.range.unwrap_or(0.0) {
            let range = |r: Option<f64>| {
                r.map_or_else(|| "no range".to_string(), |r| format!("range {}", trim(r)))
            };
            dx.push(range(x.range));
            dy.push(range(y.range));
        }
        let (dx, dy) = (dx.join(", "), dy.join(", "));
        if d > tol.metres || dx != dy {
            let mut c = Change::new(Kind::LightChanged, &room(y), &y.id).values(dx, dy);
            c.distance_m = (d > tol.metres).then(|| r4(d));
            out.push(c);
        }
    }
    for i in unpaired_a {
        out.push(Change::new(Kind::LightRemoved, &room(&a.lights[i]), &a.lights[i].id));
    }
    for j in unpaired_b {
        out.push(Change::new(Kind::LightAdded, &room(&b.lights[j]), &b.lights[j].id));
    }
}

/// The diff as JSON for tools: `{"version": 1, "same": …, "summary": …, "changes": […]}`.
pub fn to_json(d: &Diff) -> serde_json::Value {
    serde_json::json!({
        "version": 1,
        "same": d.is_empty(),
        "summary": d.summary(),
        "counts": d.counts().iter().map(|(k, n)| (serde_json::to_value(k).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default(), *n)).collect::<BTreeMap<String, usize>>(),
        "changes": d.changes,
    })
}
