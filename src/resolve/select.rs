//! Choosing one asset per object instance, small object and ceiling object.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use super::catalog::{Catalog, PlacementKind};
use super::errors;
use super::index::{rank_top, Candidate, Query};
use super::standins;
use super::{kinds, objathor, receptacles, text};

/// Types the catalog has only as things on furniture that people also hang on a wall.
/// An alarm clock or a watch is not among them: the catalog's are desk clocks with a base and
/// wristwatches, and a wall clock made of one hangs a desk clock on the wall.
pub const WALL_MOUNTED: &[&str] = &["Television", "Microwave", "Painting", "Mirror", "LightSwitch"];
/// Types the catalog has only on the wall that people also stand on furniture (a framed
/// photograph on a shelf).
pub const ON_FURNITURE: &[&str] = &["Painting"];
/// Types the catalog has only as things on furniture that also stand on the floor.
pub const FLOOR_STANDING: &[&str] = &[
    "Vase",
    "Statue",
    "HousePlant",
    "Box",
    "GarbageCan",
    "LaundryHamper",
    "Dumbbell",
    "BasketBall",
    "Boots",
    "TeddyBear",
    "Pot",
    "WateringCan",
    "Bottle",
    "WineBottle",
    "Television",
    "Laptop",
];

/// A thing on top is rejected when its asset's longest side is more than this many times the
/// thing's size: its written size when the scene gives one, else the typical size of its type
/// on furniture ([`typical_on_object_m`]). Twice keeps every on-object asset of the embedded
/// catalog within its type but two outliers, and rules out a 0.53 m wall picture for a photo
/// frame.
pub const MAX_SIZE_RATIO: f64 = 2.0;

/// Typical longest sides, metres, of things people stand on furniture whose type the embedded
/// catalog has only on the wall: a framed photograph or picture on a shelf or a desk is 20 ×
/// 25 cm (8 × 10 in, the common frame), so 0.25 m.
pub const ON_FURNITURE_TYPICAL_M: &[(&str, f64)] = &[("Painting", 0.25)];

/// The typical longest side, metres, of a thing of `object_type` on furniture: the median
/// longest side of the catalog's on-object assets of that type, else the
/// [`ON_FURNITURE_TYPICAL_M`] table; `None` when neither knows the type.
pub fn typical_on_object_m(catalog: &Catalog, object_type: &str) -> Option<f64> {
    let mut sides: Vec<f64> = catalog
        .assets()
        .iter()
        .filter(|a| a.object_type == object_type && a.allows(PlacementKind::OnObject))
        .map(|a| a.bbox_m.iter().copied().fold(0.0, f64::max))
        .collect();
    if sides.is_empty() {
        return ON_FURNITURE_TYPICAL_M.iter().find(|(t, _)| *t == object_type).map(|(_, m)| *m);
    }
    sides.sort_by(f64::total_cmp);
    let n = sides.len();
    Some(if n % 2 == 1 { sides[n / 2] } else { f64::midpoint(sides[n / 2 - 1], sides[n / 2]) })
}

/// How many ranked candidates resolution looks at (enough for the largest varied group and
/// for avoiding assets used in other rooms).
const RANK_LIMIT: usize = 128;
use crate::check::{ObjectId, Pinned, Placement, RoomId, Scene, Variance};
use crate::diag::{Diagnostic, Outcome};
use crate::source::Span;

/// The chosen asset of one object, small object or ceiling object.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// The asset id.
    pub asset_id: String,
    /// Its object type.
    pub object_type: String,
    /// Its bounding box, metres (x width, y height, z depth).
    pub bbox_m: [f64; 3],
    /// Whether other objects can be put on it.
    pub receptacle: bool,
    /// Index of its catalog in [`Catalog::sources`].
    pub source: usize,
    /// Whether the file pinned it (then `parts` is `None`).
    pub pinned: bool,
    /// The parts of its score when it was ranked.
    pub parts: Option<Candidate>,
    /// The best other candidate, if any.
    pub runner_up: Option<Candidate>,
    /// When the asset stands in for a thing the catalog lacks: why a person accepts it.
    pub stand_in: Option<String>,
    /// When the thing is a kind of the asset's type that no catalog word names (a `chaise
    /// longue` is a sofa): the word that decided and where that came from.
    pub kind_of: Option<String>,
    /// When the asset is placed in another way than its catalog allows (a microwave hung on
    /// the wall): that way, in words.
    pub placed_as: Option<String>,
    /// For a stand-in or a thing placed otherwise, with a size asked: how far the asset's size
    /// is from it (`resolve::standins::size_ratio`; at most `MAX_STAND_IN_RATIO`).
    pub size_ratio: Option<f64>,
    /// When no catalog has the thing and holoc made it (`crate::make`): the made asset, whose
    /// uid is `asset_id`.
    pub made: Option<std::sync::Arc<crate::make::MadeAsset>>,
    /// Whether the asset breaks (an objathor asset whose secondary properties hold
    /// `CanBreak`): the original keeps such a small object kinematic, so physics does not
    /// break it when the house loads.
    pub breakable: bool,
}

impl Choice {
    /// The choice of an asset, with no ranking parts, runner-up, pin or stand-in yet.
    fn of(asset: &super::catalog::Asset) -> Choice {
        Choice {
            asset_id: asset.id.to_string(),
            object_type: asset.object_type.to_string(),
            bbox_m: asset.bbox_m,
            receptacle: asset.receptacle,
            source: asset.source,
            pinned: false,
            parts: None,
            runner_up: None,
            stand_in: None,
            kind_of: None,
            placed_as: None,
            size_ratio: None,
            made: None,
            breakable: false,
        }
    }

    /// The choice of a made asset.
    fn of_made(made: std::sync::Arc<crate::make::MadeAsset>, source: usize) -> Choice {
        Choice {
            asset_id: made.uid.clone(),
            object_type: made.object_type.to_string(),
            bbox_m: made.bbox_m(),
            receptacle: made.receptacle(),
            source,
            pinned: false,
            parts: None,
            runner_up: None,
            stand_in: None,
            kind_of: None,
            placed_as: None,
            size_ratio: None,
            made: Some(made),
            breakable: false,
        }
    }
}

/// Why nothing was chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct Unresolved {
    /// In words.
    pub reason: String,
    /// The nearest candidates (at most three), best first.
    pub nearest: Vec<Candidate>,
}

/// The outcome for one thing to resolve.
#[allow(
    clippy::large_enum_variant,
    reason = "a scene has few resolutions; boxing would burden every stage that matches on them"
)]
#[derive(Clone, Debug, PartialEq)]
pub enum Resolution {
    /// An asset was chosen.
    Chosen(Choice),
    /// Nothing was chosen; the thing is left out of the house and listed in the report.
    Unresolved(Unresolved),
}

impl Resolution {
    /// The choice, if any.
    pub fn choice(&self) -> Option<&Choice> {
        match self {
            Resolution::Chosen(c) => Some(c),
            Resolution::Unresolved(_) => None,
        }
    }
}

/// Every resolution of a scene.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Resolved {
    /// Per object instance, indexed by [`ObjectId`].
    pub objects: Vec<Resolution>,
    /// Per room with a ceiling object.
    pub ceilings: BTreeMap<RoomId, Resolution>,
    /// Rooms whose ceiling object is a light that no asset serves: the room's light of the
    /// house stands for it (its description is kept for the report).
    pub ceiling_lights: BTreeMap<RoomId, String>,
    /// Per object and `on top` line index: one resolution per small-object instance.
    pub small: BTreeMap<(ObjectId, usize), Vec<Resolution>>,
}

impl Resolved {
    /// Puts a room's resolution in its place: its objects' (by their ids in `room`), its small
    /// objects', its ceiling light's and its ceiling object's.
    pub fn put_room(&mut self, room: &crate::check::Room, done: &RoomResolution) {
        for (&id, res) in room.objects.iter().zip(&done.objects) {
            if let Some(slot) = self.objects.get_mut(id.0) {
                slot.clone_from(res);
            }
        }
        for ((i, k), list) in &done.small {
            if let Some(&id) = room.objects.get(*i) {
                self.small.insert((id, *k), list.clone());
            }
        }
        if let Some(light) = &done.ceiling_light {
            self.ceiling_lights.insert(room.id, light.clone());
        }
        if let Some(res) = &done.ceiling {
            self.ceilings.insert(room.id, res.clone());
        }
    }

    /// [`Resolved::put_room`], moving the room's resolutions out of `done` instead of copying
    /// them (its objects', small objects', ceiling object's and ceiling light's are left empty;
    /// its diagnostics and what it read and wrote stay).
    pub fn put_room_taken(&mut self, room: &crate::check::Room, done: &mut RoomResolution) {
        let objects = std::mem::take(&mut done.objects);
        for (&id, res) in room.objects.iter().zip(objects) {
            if let Some(slot) = self.objects.get_mut(id.0) {
                *slot = res;
            }
        }
        for ((i, k), list) in std::mem::take(&mut done.small) {
            if let Some(&id) = room.objects.get(i) {
                self.small.insert((id, k), list);
            }
        }
        if let Some(light) = done.ceiling_light.take() {
            self.ceiling_lights.insert(room.id, light);
        }
        if let Some(res) = done.ceiling.take() {
            self.ceilings.insert(room.id, res);
        }
    }

    /// Takes back into `done` what [`Resolved::put_room_taken`] put of a room that was room
    /// `room` with objects `ids`: its objects' resolutions (each left "not resolved"), its small
    /// objects', its ceiling object's and its ceiling light's (removed).
    pub fn take_room(&mut self, room: RoomId, ids: &[ObjectId], done: &mut RoomResolution) {
        done.objects = ids
            .iter()
            .map(|id| match self.objects.get_mut(id.0) {
                Some(slot) => std::mem::replace(slot, not_resolved()),
                None => not_resolved(),
            })
            .collect();
        done.small = Vec::new();
        for (i, &id) in ids.iter().enumerate() {
            let keys: Vec<(ObjectId, usize)> =
                self.small.range((id, 0)..=(id, usize::MAX)).map(|(key, _)| *key).collect();
            for key in keys {
                if let Some(list) = self.small.remove(&key) {
                    done.small.push(((i, key.1), list));
                }
            }
        }
        done.ceiling = self.ceilings.remove(&room);
        done.ceiling_light = self.ceiling_lights.remove(&room);
    }

    /// The chosen asset of an object, if any.
    pub fn object(&self, id: ObjectId) -> Option<&Choice> {
        self.objects.get(id.0).and_then(Resolution::choice)
    }

    /// A readable dump, one line per resolution, as `--emit resolved` and the snapshots show it.
    pub fn dump(&self, scene: &Scene, catalog: &Catalog) -> String {
        let mut out = String::new();
        for room in &scene.rooms {
            let _ = writeln!(out, "room {} \"{}\"", room.name, room.label);
            for &id in &room.objects {
                let obj = scene.object(id);
                let kind = if obj.is_floor() { "floor" } else { "wall" };
                if let Some(res) = self.objects.get(id.0) {
                    let _ =
                        writeln!(out, "  {} [{kind}] {}", obj.name, dump_resolution(res, catalog));
                }
                for (k, item) in obj.on_top.iter().enumerate() {
                    if let Some(list) = self.small.get(&(id, k)) {
                        for (i, res) in list.iter().enumerate() {
                            let _ = writeln!(
                                out,
                                "    on top {}#{i} [on-object] {}",
                                item.item,
                                dump_resolution(res, catalog)
                            );
                        }
                    }
                }
            }
            if self.ceiling_lights.contains_key(&room.id) {
                let _ = writeln!(out, "  ceiling [ceiling] the room's light (no ceiling asset)");
            } else if let Some(res) = self.ceilings.get(&room.id) {
                let _ = writeln!(out, "  ceiling [ceiling] {}", dump_resolution(res, catalog));
            }
        }
        out
    }
}

fn dump_resolution(res: &Resolution, catalog: &Catalog) -> String {
    match res {
        Resolution::Chosen(c) => {
            if let Some(m) = &c.made {
                let [w, h, d] = c.bbox_m;
                return format!(
                    "→ {} ({}, made by holoc) {w:.2}×{h:.2}×{d:.2} m, made: {} ({} parts, {} triangles)",
                    c.asset_id,
                    c.object_type,
                    m.kind.replace('_', " "),
                    m.parts.len(),
                    m.mesh.triangles.len() / 3
                );
            }
            let source = &catalog.sources()[c.source.min(catalog.sources().len() - 1)].name;
            let how = match &c.parts {
                _ if c.pinned => "pinned".to_string(),
                Some(p) => format!("score {}", parts_text(p)),
                None => match (&c.kind_of, &c.stand_in) {
                    (Some(k), _) => k.clone(),
                    (None, Some(reason)) => format!("stand-in: {reason}"),
                    (None, None) => String::new(),
                },
            };
            let how = match &c.placed_as {
                Some(way) => format!("{how}, placed {way}"),
                None => how,
            };
            let runner = c
                .runner_up
                .as_ref()
                .map(|r| format!("; runner-up {} {:.3}", r.asset_id, r.score))
                .unwrap_or_default();
            format!(
                "→ {} ({}, {}) {:.2}×{:.2}×{:.2} m, {how}{runner}",
                c.asset_id, c.object_type, source, c.bbox_m[0], c.bbox_m[1], c.bbox_m[2]
            )
        }
        Resolution::Unresolved(u) => {
            let nearest: Vec<String> =
                u.nearest.iter().map(|c| format!("{} {:.3}", c.asset_id, c.score)).collect();
            format!(
                "unresolved: {} (nearest: {})",
                u.reason,
                if nearest.is_empty() { "none".to_string() } else { nearest.join(", ") }
            )
        }
    }
}

/// The parts of a score in words: `7.512 = 10×0.936 − 10×0.185 m`.
pub(crate) fn parts_text(c: &Candidate) -> String {
    if let Some(f) = &c.features {
        let sbert = f.sbert.map(|s| format!(" + {s:.3} sbert")).unwrap_or_default();
        let size = c.size_diff_m.map(|d| format!(" − 10×{d:.3} m")).unwrap_or_default();
        return format!("{:.3} = {:.3} clip{sbert}{size}", c.score, f.clip);
    }
    match c.size_diff_m {
        Some(d) => format!("{:.3} = 10×{:.3} − 10×{d:.3} m", c.score, c.relevance),
        None => format!("{:.3} = 10×{:.3}", c.score, c.relevance),
    }
}

/// Resolves every object, small object and ceiling object of the scene against the catalog.
///
/// Pins win (an unknown pin or one of the wrong placement kind is an error). Otherwise the
/// best-ranked good-enough asset is chosen: a `same` group shares one asset, a `varied` group
/// takes different assets where there are enough, assets already used in another room are
/// avoided where an alternative exists, and objects with things on top prefer receptacles.
/// Exact ties are broken by the seed.
pub fn resolve(scene: &Scene, catalog: &Catalog, seed: u64) -> Outcome<Resolved> {
    resolve_with(scene, catalog, seed, &ResolveOptions::default())
}

/// How to resolve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResolveOptions {
    /// Whether an asset of another type that does the same job stands in for a thing the
    /// catalog lacks (the stand-in table of `resolve::standins`); on by default.
    pub stand_ins: bool,
    /// Whether holoc makes what no catalog has (`crate::make`), before a stand-in; on by
    /// default (`--no-make` turns it off, for houses of built-in assets only).
    pub make: bool,
}

impl Default for ResolveOptions {
    fn default() -> Self {
        ResolveOptions { stand_ins: true, make: true }
    }
}

/// [`resolve`] with options.
pub fn resolve_with(
    scene: &Scene,
    catalog: &Catalog,
    seed: u64,
    options: &ResolveOptions,
) -> Outcome<Resolved> {
    resolve_cached(scene, catalog, seed, options, &mut RankCache::default())
}

/// A ranking's query: category, description, size (each side's bits: the same size is the
/// same key) and placement kind.
type RankKey = (String, String, Option<[u64; 3]>, &'static str);

/// The size of a query as part of its [`RankKey`].
fn size_key(size_m: Option<[f64; 3]>) -> Option<[u64; 3]> {
    size_m.map(|s| s.map(f64::to_bits))
}

/// Rankings of earlier resolutions, kept by an editor between keystrokes: the ranking of a
/// query depends only on the catalog, the seed and the query, so a document resolved again
/// ranks only the descriptions that changed. It holds what the last resolution asked, no more.
#[derive(Debug, Default)]
pub struct RankCache {
    /// The catalog (by address and size) and seed the rankings were made with.
    made_with: Option<(usize, usize, u64)>,
    rankings: BTreeMap<RankKey, std::rc::Rc<Vec<Candidate>>>,
}

/// [`resolve_with`], reusing the rankings of `cache` (made with this catalog and seed).
pub fn resolve_cached(
    scene: &Scene,
    catalog: &Catalog,
    seed: u64,
    options: &ResolveOptions,
    cache: &mut RankCache,
) -> Outcome<Resolved> {
    let mut resolver = Resolver::new(catalog, seed, options, cache);
    let mut rooms = Vec::with_capacity(scene.rooms.len());
    for room in &scene.rooms {
        let done = resolver.room(scene, room);
        resolver.used_before(&done);
        rooms.push(done);
    }
    resolver.finish(cache);
    assemble(scene, &rooms)
}

/// What resolving one room made, and what it read of and added to the assets the rooms
/// before it used: the only thing a room's choices take from the rest of the scene (an asset
/// another room uses is avoided where an alternative exists). Given the same room, catalog,
/// seed and options, a room that reads the same answers makes the same choices and the same
/// diagnostics, which is what lets an editor keep a room's resolution while another changes.
#[derive(Clone, Debug)]
pub struct RoomResolution {
    /// Per object of the room, in the order of [`crate::check::Room::objects`].
    pub objects: Vec<Resolution>,
    /// Per object (its index in the room's list) and `on top` line: one per instance.
    pub small: Vec<((usize, usize), Vec<Resolution>)>,
    /// The ceiling object's resolution, if the room has one.
    pub ceiling: Option<Resolution>,
    /// The ceiling light's description when the room's light stands for it.
    pub ceiling_light: Option<String>,
    /// The room's diagnostics, in the order they were made.
    pub diagnostics: Vec<Diagnostic>,
    /// Each asset whose use by an earlier room was asked, with the answer: [`read`] of its
    /// place in the catalog and whether it was free (no earlier room used it).
    reads: Vec<u64>,
    /// The catalog and seed the room was resolved with (what its reads' places are places in).
    made_with: (usize, usize, u64),
    /// The assets the room uses.
    pub writes: BTreeSet<String>,
    /// The rankings the room asked for (kept alive in the [`RankCache`] while a room holds
    /// them).
    ranks: Vec<std::rc::Rc<Vec<Candidate>>>,
    /// Each object group's choice with what it read and gave, in the room's order: what the
    /// next resolution of the room takes again for a group whose input is the same.
    groups: Vec<GroupRun>,
    /// The assets the room's things on top and ceiling object use, and the rankings they
    /// asked for (with [`RoomResolution::groups`], what one group chosen again alone needs to
    /// make the room's `writes` and `ranks` again).
    rest_writes: Vec<String>,
    rest_asked: Vec<std::rc::Rc<Vec<Candidate>>>,
}

/// A span as the room's reported set keeps it: file, start, end.
type SpanKey = (u32, u32, u32);

/// One object group's choice in a room: its input, and everything the choice read of and
/// gave to the room's resolution.
#[derive(Clone, Debug)]
struct GroupRun {
    /// The subject, the query, the variance, the pins and whether it must hold things.
    what: Subject,
    query: Query,
    variance: Variance,
    pins: Vec<Option<Pinned>>,
    wants_receptacle: bool,
    /// The room's box when it was chosen (the objathor folder's size filters read it).
    room_box: Option<[f64; 3]>,
    /// The resolutions, one per instance.
    results: Vec<Resolution>,
    /// The diagnostics it made, and each span it asked to report with whether it was new.
    diagnostics: Vec<Diagnostic>,
    reports: Vec<(SpanKey, bool)>,
    /// The assets it asked about, with the answers, and those it used, in order.
    reads: Vec<u64>,
    writes: Vec<String>,
    /// The rankings it asked for.
    asked: Vec<std::rc::Rc<Vec<Candidate>>>,
}

impl RoomResolution {
    /// Lets go of the rankings the room asked for, so that the [`RankCache`] no longer keeps
    /// them for it (an editor keeps them only for the rooms being edited: with a description of
    /// its own per object group, every room's rankings held were most of its memory). The
    /// resolution itself does not change.
    pub fn release_rankings(&mut self) {
        self.ranks = Vec::new();
    }

    /// Calls `f` on every span the room's resolution holds (its diagnostics' and those its
    /// object groups' choices are kept by), so that an editor can move them with the text.
    /// (`diagnostic` is called on each diagnostic kept, to move its spans.)
    pub fn spans_mut(
        &mut self,
        f: &mut dyn FnMut(&mut Span),
        diagnostic: &mut dyn FnMut(&mut Diagnostic),
    ) {
        for group in &mut self.groups {
            f(&mut group.what.span);
            for pin in group.pins.iter_mut().flatten() {
                f(&mut pin.span);
            }
            for d in &mut group.diagnostics {
                diagnostic(d);
            }
            for (key, _) in &mut group.reports {
                let mut span =
                    Span { file: crate::source::FileId(key.0), start: key.1, end: key.2 };
                f(&mut span);
                *key = (span.file.0, span.start, span.end);
            }
        }
    }
}

impl RoomResolution {
    /// Whether the room would read the same answers from `used` (the assets of the rooms
    /// before it).
    fn reads_hold(&self, catalog: &Catalog, used: &rustc_hash::FxHashSet<String>) -> bool {
        self.reads.iter().all(|&r| {
            let (place, free) = unread(r);
            catalog.assets().get(place).is_some_and(|a| free != used.contains(a.id.as_ref()))
        })
    }
}

/// Resolves a scene room by room, in order: each room reads which assets the rooms before it
/// use ([`Resolver::used_before`] adds a room's), and nothing else of them.
pub struct Resolver<'a> {
    state: State<'a>,
}

impl<'a> Resolver<'a> {
    /// A resolver for a scene with `catalog` and `seed`, taking the rankings `cache` holds
    /// (when they were made with the same catalog and seed).
    pub fn new(
        catalog: &'a Catalog,
        seed: u64,
        options: &ResolveOptions,
        cache: &mut RankCache,
    ) -> Resolver<'a> {
        let made_with = (std::ptr::from_ref(catalog) as usize, catalog.assets().len(), seed);
        let earlier = if cache.made_with == Some(made_with) {
            std::mem::take(&mut cache.rankings)
        } else {
            BTreeMap::new()
        };
        let mut state = State::new(catalog, seed, *options);
        state.earlier = earlier;
        Resolver { state }
    }

    /// Resolves one room of `scene`, given the assets of the rooms before it.
    pub fn room(&mut self, scene: &Scene, room: &crate::check::Room) -> RoomResolution {
        resolve_room(scene, room, &mut self.state, None)
    }

    /// [`Resolver::room`], taking again from `last` (an earlier resolution of the same room,
    /// its spans moved to the current text) the choice of every object group whose input is
    /// the same and whose reads of the rooms before and of the room so far hold: the same
    /// result as [`Resolver::room`], with only the groups that changed chosen again.
    /// Without `last` (or with one whose groups' choices were not recorded) every group is
    /// chosen and recorded for the next time. The groups are taken out of `last`.
    pub fn room_again(
        &mut self,
        scene: &Scene,
        room: &crate::check::Room,
        last: Option<&mut RoomResolution>,
    ) -> RoomResolution {
        // Groups chosen with another catalog or seed are not taken again.
        let made_with = self.state.made_with();
        let groups = last
            .filter(|l| l.made_with == made_with)
            .map_or_else(Vec::new, |l| std::mem::take(&mut l.groups));
        resolve_room(scene, room, &mut self.state, Some(groups))
    }

    /// [`Resolver::room_again`] when one object group alone changed: the group of the room's
    /// objects at places `members` (the room's objects in the order of their ids, each group
    /// one run of them, none with things on top) is chosen again and put into `last` (an
    /// earlier resolution of the room whose groups' choices were recorded), whose every other
    /// group's choice, span and diagnostic `moved` moves to the current text: the room's
    /// resolution as [`Resolver::room`] makes it (but for the answers it read, which may be
    /// more). The group's new resolutions, and whether the room's assets changed; `None` when
    /// `last` cannot be used so (then it is left with some of its spans moved: to be thrown
    /// away).
    pub fn group_again(
        &mut self,
        scene: &Scene,
        room: &crate::check::Room,
        last: &mut RoomResolution,
        members: std::ops::Range<usize>,
        moved: &dyn Fn(Span) -> Option<Span>,
    ) -> Option<(Vec<Resolution>, bool)> {
        let state = &mut self.state;
        if last.made_with != state.made_with() || members.is_empty() {
            return None;
        }
        // The groups line up with the room's objects, in the order of their ids.
        let ids = &room.objects;
        if !ids.windows(2).all(|w| w[1].0 == w[0].0 + 1) {
            return None;
        }
        if last.groups.iter().map(|g| g.results.len()).sum::<usize>() != ids.len() {
            return None;
        }
        let mut at = 0;
        let gi = last.groups.iter().position(|g| {
            let here = at;
            at += g.results.len();
            here == members.start
        })?;
        let first = scene.object(*ids.get(members.start)?);
        if last.groups[gi].results.len() != members.len()
            || last.groups[gi].what.name != first.name
            || members
                .clone()
                .any(|i| ids.get(i).is_none_or(|&id| !scene.object(id).on_top.is_empty()))
        {
            return None;
        }
        let from: usize = last.groups[..gi].iter().map(|g| g.diagnostics.len()).sum();
        let to = from + last.groups[gi].diagnostics.len();
        if to > last.diagnostics.len() {
            return None;
        }
        // Every span but the group's moved to the current text.
        let mut ok = true;
        let mut move_span = |span: &mut Span| match moved(*span) {
            Some(m) => *span = m,
            None => ok = false,
        };
        for (j, g) in last.groups.iter_mut().enumerate() {
            if j == gi {
                continue;
            }
            move_span(&mut g.what.span);
            for pin in g.pins.iter_mut().flatten() {
                move_span(&mut pin.span);
            }
            for d in &mut g.diagnostics {
                move_diagnostic(d, &mut move_span);
            }
            for (key, _) in &mut g.reports {
                let mut span =
                    Span { file: crate::source::FileId(key.0), start: key.1, end: key.2 };
                move_span(&mut span);
                *key = (span.file.0, span.start, span.end);
            }
        }
        for (j, d) in last.diagnostics.iter_mut().enumerate() {
            if !(from..to).contains(&j) {
                move_diagnostic(d, &mut move_span);
            }
        }
        if !ok {
            return None;
        }
        // The room's state when the group was chosen: the spans the groups before reported.
        state.reported.clear();
        for g in &last.groups[..gi] {
            for (key, new) in &g.reports {
                if *new {
                    state.reported.insert(*key);
                }
            }
        }
        state.room_box = room_box(room, scene.wall_height_m);
        let kind = match first.placement {
            Placement::Floor { .. } => PlacementKind::Floor,
            Placement::Wall { .. } => PlacementKind::Wall,
        };
        let query = Query {
            category: first.category.clone(),
            description: first.description.clone(),
            size_m: first.size_m,
            kind: Some(kind),
        };
        let pins: Vec<Option<&Pinned>> =
            members.clone().map(|i| scene.object(ids[i]).asset.as_ref()).collect();
        let what = Subject {
            name: first.name.clone(),
            description: first.description.clone().unwrap_or_else(|| first.category.clone()),
            span: first.name_span,
        };
        state.diagnostics.clear();
        state.reads.clear();
        state.asked.clear();
        let writes_before = std::mem::take(&mut state.writes);
        let run = state.choose_recorded(what, query, first.variance, &pins, false);
        state.writes = writes_before;
        state.diagnostics.clear();
        state.room_box = None;
        // The spans the group reports are its own: no other group's choice reads them.
        let own: BTreeSet<SpanKey> =
            run.reports.iter().chain(&last.groups[gi].reports).map(|(key, _)| *key).collect();
        let shared = last
            .groups
            .iter()
            .enumerate()
            .any(|(j, g)| j != gi && g.reports.iter().any(|(key, _)| own.contains(key)));
        if shared || run.results.len() != members.len() {
            return None;
        }
        let mut results = run.results.clone();
        if let Some(obj) = state.catalog.objathor() {
            for res in &mut results {
                if let Resolution::Chosen(c) = res {
                    c.breakable = state
                        .catalog
                        .index_of(&c.asset_id)
                        .and_then(|i| obj.entry(i))
                        .is_some_and(|e| e.can_break);
                }
            }
        }
        let _ = last.diagnostics.splice(from..to, run.diagnostics.iter().cloned());
        let mut reads = std::mem::take(&mut last.reads);
        reads.extend(run.reads.iter().copied());
        reads.sort_unstable();
        reads.dedup();
        last.reads = reads;
        let writes_changed = sorted(&run.writes) != sorted(&last.groups[gi].writes);
        last.groups[gi] = run;
        if writes_changed {
            last.writes = last
                .groups
                .iter()
                .flat_map(|g| g.writes.iter())
                .chain(&last.rest_writes)
                .cloned()
                .collect();
        }
        if !last.ranks.is_empty() || !last.rest_asked.is_empty() || !last.groups.is_empty() {
            let mut seen: rustc_hash::FxHashSet<*const Vec<Candidate>> =
                rustc_hash::FxHashSet::default();
            let mut ranks = Vec::new();
            for list in last.groups.iter().flat_map(|g| g.asked.iter()).chain(&last.rest_asked) {
                if seen.insert(std::rc::Rc::as_ptr(list)) {
                    ranks.push(std::rc::Rc::clone(list));
                }
            }
            last.ranks = ranks;
        }
        self.state.groups_kept += last.groups.len() as u64 - 1;
        Some((results, writes_changed))
    }

    /// Whether `room` (an earlier resolution, with this resolver's catalog and seed) would read
    /// now what it read then: each asset it asked about is used or not by the rooms given to
    /// [`Resolver::used_before`] as it was by the rooms before it then.
    pub fn reads_hold(&self, room: &RoomResolution) -> bool {
        room.made_with == self.state.made_with()
            && room.reads_hold(self.state.catalog, &self.state.used)
    }

    /// Counts the assets of `room` as used by the rooms before the next one.
    pub fn used_before(&mut self, room: &RoomResolution) {
        self.state.used.extend(room.writes.iter().cloned());
    }

    /// Forgets the rankings computed so far that no room's resolution holds, once there are
    /// more than `max` of them: the rankings a scene's rooms share while they are resolved stay
    /// (a scene that repeats its descriptions asks fewer questions than that), and a scene
    /// whose every object group has a description of its own keeps at most about `max`
    /// rankings at a time instead of one per group. Choices do not change: a ranking forgotten
    /// is worked out again when it is asked again.
    pub fn bound_rankings(&mut self, max: usize) {
        if self.state.cache.len() > max {
            self.state.cache.retain(|_, list| std::rc::Rc::strong_count(list) > 1);
        }
    }

    /// How many object groups' choices [`Resolver::room_again`] took again so far.
    pub fn groups_kept(&self) -> u64 {
        self.state.groups_kept
    }

    /// The assets of the rooms given to [`Resolver::used_before`] so far.
    pub fn used(&self) -> &rustc_hash::FxHashSet<String> {
        &self.state.used
    }

    /// Gives the rankings back to `cache`: those asked now, and those of earlier resolutions
    /// that a room kept from an earlier resolution still holds.
    pub fn finish(mut self, cache: &mut RankCache) {
        let mut rankings = std::mem::take(&mut self.state.cache);
        for (key, list) in std::mem::take(&mut self.state.earlier) {
            // Held by a room kept from an earlier resolution (the cache holds one more).
            if std::rc::Rc::strong_count(&list) > 1 {
                rankings.insert(key, list);
            }
        }
        cache.made_with = Some(self.state.made_with());
        cache.rankings = rankings;
    }
}

/// The assets of a list, sorted, each once.
fn sorted(w: &[String]) -> Vec<&str> {
    let mut w: Vec<&str> = w.iter().map(String::as_str).collect();
    w.sort_unstable();
    w.dedup();
    w
}

/// Calls `f` on every span of a diagnostic (its labels' and fixes').
fn move_diagnostic(d: &mut Diagnostic, f: &mut dyn FnMut(&mut Span)) {
    if let Some(label) = &mut d.primary {
        f(&mut label.span);
    }
    for label in &mut d.secondary {
        f(&mut label.span);
    }
    for fix in &mut d.fixes {
        f(&mut fix.span);
    }
}

/// A read of whether an asset is free, kept in one word: its place in the catalog and the
/// answer. (A place is less than `isize::MAX`, the most elements a `Vec` holds: doubled, it
/// fits.)
fn read(place: usize, free: bool) -> u64 {
    ((place as u64) << 1) | u64::from(free)
}

/// The place of no asset in a [`read`].
const NO_PLACE: usize = usize::MAX >> 1;

/// The place and answer [`read`] kept.
fn unread(read: u64) -> (usize, bool) {
    ((read >> 1) as usize, read & 1 == 1)
}

/// What stands for a thing no resolution was made for.
fn not_resolved() -> Resolution {
    Resolution::Unresolved(Unresolved { reason: "not resolved".into(), nearest: Vec::new() })
}

/// The resolution of a scene from its rooms' (in the scene's room order).
pub fn assemble<'r>(
    scene: &Scene,
    rooms: impl IntoIterator<Item = &'r RoomResolution>,
) -> Outcome<Resolved> {
    let mut resolved =
        Resolved { objects: vec![not_resolved(); scene.objects.len()], ..Resolved::default() };
    let mut diagnostics = Vec::new();
    for (room, done) in scene.rooms.iter().zip(rooms) {
        resolved.put_room(room, done);
        diagnostics.extend(done.diagnostics.iter().cloned());
    }
    Outcome::new(resolved, diagnostics)
}

fn resolve_room(
    scene: &Scene,
    room: &crate::check::Room,
    state: &mut State<'_>,
    last: Option<Vec<GroupRun>>,
) -> RoomResolution {
    let mut done = RoomResolution {
        objects: Vec::with_capacity(room.objects.len()),
        small: Vec::new(),
        ceiling: None,
        ceiling_light: None,
        diagnostics: Vec::new(),
        reads: Vec::new(),
        made_with: state.made_with(),
        writes: BTreeSet::new(),
        ranks: Vec::new(),
        groups: Vec::new(),
        rest_writes: Vec::new(),
        rest_asked: Vec::new(),
    };
    // Without a last resolution (a room resolved for the first time) nothing is recorded:
    // only the rooms being edited keep their groups' choices.
    let record = last.is_some();
    // The last resolution's groups by where their first object is named.
    let mut last: Vec<Option<GroupRun>> = last.unwrap_or_default().into_iter().map(Some).collect();
    let by_place: rustc_hash::FxHashMap<(u32, u32, u32), usize> = last
        .iter()
        .enumerate()
        .filter_map(|(k, g)| g.as_ref().map(|g| (g.what.span, k)))
        .map(|(span, k)| ((span.file.0, span.start, span.end), k))
        .collect();
    state.reported.clear();
    state.room_box = room_box(room, scene.wall_height_m);
    // Object groups of the room, in order of first instance.
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    let mut group_index: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    for (i, &id) in room.objects.iter().enumerate() {
        let obj = scene.object(id);
        match group_index.get(obj.group.as_str()) {
            Some(&g) => groups[g].1.push(i),
            None => {
                group_index.insert(obj.group.as_str(), groups.len());
                groups.push((obj.group.clone(), vec![i]));
            }
        }
    }
    let mut objects: Vec<Option<Resolution>> = vec![None; room.objects.len()];
    for (_, members) in &groups {
        let first = scene.object(room.objects[members[0]]);
        let kind = match first.placement {
            Placement::Floor { .. } => PlacementKind::Floor,
            Placement::Wall { .. } => PlacementKind::Wall,
        };
        let query = Query {
            category: first.category.clone(),
            description: first.description.clone(),
            size_m: first.size_m,
            kind: Some(kind),
        };
        let wants_receptacle = !first.on_top.is_empty();
        let pins: Vec<Option<&Pinned>> =
            members.iter().map(|&i| scene.object(room.objects[i]).asset.as_ref()).collect();
        let what = Subject {
            name: first.name.clone(),
            description: first.description.clone().unwrap_or_else(|| first.category.clone()),
            span: first.name_span,
        };
        // The last resolution's group named at the same place is taken again when its input
        // is this one and what it read still reads the same.
        let same_input = |g: &GroupRun| {
            g.what == what
                && g.query == query
                && g.variance == first.variance
                && g.wants_receptacle == wants_receptacle
                && g.room_box == state.room_box
                && g.pins.len() == pins.len()
                && g.pins.iter().zip(&pins).all(|(a, b)| a.as_ref() == *b)
        };
        if !record {
            let results = state.choose(&what, &query, first.variance, &pins, wants_receptacle);
            for (&i, res) in members.iter().zip(results) {
                objects[i] = Some(res);
            }
            continue;
        }
        let place = (what.span.file.0, what.span.start, what.span.end);
        let kept = by_place
            .get(&place)
            .and_then(|&k| last.get_mut(k))
            .and_then(|g| g.take_if(|g| same_input(g) && state.reads_hold(g)));
        let run = match kept {
            Some(run) => {
                state.replay(&run);
                state.groups_kept += 1;
                run
            }
            None => state.choose_recorded(what, query, first.variance, &pins, wants_receptacle),
        };
        for (&i, res) in members.iter().zip(&run.results) {
            objects[i] = Some(res.clone());
        }
        done.groups.push(run);
    }
    done.objects = objects.into_iter().map(|res| res.unwrap_or_else(not_resolved)).collect();
    // What the things on top and the ceiling object use and ask, when the groups' choices are
    // recorded.
    let rest_asked_from = state.asked.len();
    if record {
        state.writes_made = Some(Vec::new());
    }
    // Small objects on top, per instance and line; each prefers assets that fit on the
    // top of its receptacle's asset, less the margin the layout keeps round its edge.
    for (i, &id) in room.objects.iter().enumerate() {
        let obj = scene.object(id);
        let choice = done.objects.get(i).and_then(Resolution::choice);
        state.top = choice.map(|c| {
            let (a, b) = (c.bbox_m[0], c.bbox_m[2]);
            let margin = 2.0 * crate::solve::SMALL_GAP_M;
            [a.min(b) - margin, a.max(b) - margin]
        });
        state.top_type = choice.map(|c| c.object_type.clone());
        for (k, item) in obj.on_top.iter().enumerate() {
            let query = Query {
                category: item.item.clone(),
                description: None,
                size_m: None,
                kind: Some(PlacementKind::OnObject),
            };
            let pins = vec![item.asset.as_ref(); item.count as usize];
            let what = Subject {
                name: format!("{} on {}", item.item, obj.name),
                description: item.item.clone(),
                span: item.span,
            };
            let results = state.choose(&what, &query, item.variance, &pins, false);
            done.small.push(((i, k), results));
        }
    }
    state.top = None;
    state.top_type = None;
    state.room_box = None;
    if let Some(ceiling) = &room.ceiling {
        let category =
            ceiling.description.rsplit(',').next().unwrap_or(&ceiling.description).to_string();
        let query = Query {
            category,
            description: Some(ceiling.description.clone()),
            size_m: None,
            kind: Some(PlacementKind::Ceiling),
        };
        let what = Subject {
            name: format!("ceiling of {}", room.name),
            description: ceiling.description.clone(),
            span: ceiling.span,
        };
        let reported = state.diagnostics.len();
        let mut results =
            state.choose(&what, &query, Variance::Same, &[ceiling.asset.as_ref()], false);
        if let Some(res) = results.pop() {
            // A ceiling light with no asset is not lost: the house's light of the room, at
            // the ceiling over the room, stands for it (AI2-THOR's own assets have no
            // ceiling lamps).
            if res.choice().is_none() && ceiling.asset.is_none() && is_light(&ceiling.description) {
                state.diagnostics.truncate(reported);
                done.ceiling_light = Some(ceiling.description.clone());
            }
            done.ceiling = Some(res);
        }
    }
    if record {
        done.rest_writes = state.writes_made.take().unwrap_or_default();
        done.rest_asked = state.asked[rest_asked_from..].to_vec();
    }
    done.diagnostics = std::mem::take(&mut state.diagnostics);
    // An asset asked about twice got the same answer (the rooms before do not change while
    // this one is resolved): each is kept once.
    let mut reads = std::mem::take(&mut state.reads);
    reads.sort_unstable();
    reads.dedup();
    reads.shrink_to_fit();
    done.reads = reads;
    done.writes = std::mem::take(&mut state.writes);
    done.ranks = std::mem::take(&mut state.asked);
    if let Some(obj) = state.catalog.objathor() {
        let breaks = |res: &mut Resolution| {
            if let Resolution::Chosen(c) = res {
                c.breakable = state
                    .catalog
                    .index_of(&c.asset_id)
                    .and_then(|i| obj.entry(i))
                    .is_some_and(|e| e.can_break);
            }
        };
        done.objects.iter_mut().for_each(breaks);
        done.small.iter_mut().flat_map(|(_, list)| list.iter_mut()).for_each(breaks);
        if let Some(c) = done.ceiling.as_mut() {
            breaks(c);
        }
    }
    done
}

/// Resolves one query as a build resolves an object declared with it (the words, then the
/// kind the thing is, then a stand-in, then another placement), as `holoc assets search`
/// shows it. The diagnostics are the build's (W0401, W0403, W0404), without a place in a file.
pub fn resolve_query(
    catalog: &Catalog,
    query: &Query,
    seed: u64,
    options: &ResolveOptions,
) -> Outcome<Resolution> {
    let mut state = State::new(catalog, seed, *options);
    let what = Subject {
        name: query.category.clone(),
        description: query.description.clone().unwrap_or_else(|| query.category.clone()),
        span: Span::default(),
    };
    let mut results = state.choose(&what, query, Variance::Same, &[None], false);
    let res = results.pop().unwrap_or_else(not_resolved);
    Outcome::new(res, state.diagnostics)
}

/// Words that make a ceiling object a light.
const LIGHT_WORDS: [&str; 14] = [
    "light",
    "lights",
    "lamp",
    "chandelier",
    "pendant",
    "lantern",
    "fixture",
    "sconce",
    "bulb",
    "led",
    "fluorescent",
    "spotlight",
    "downlight",
    "luminaire",
];

/// Whether a ceiling object's description names a light.
pub fn is_light(description: &str) -> bool {
    description
        .to_lowercase()
        .split(|c: char| !c.is_alphanumeric())
        .any(|w| LIGHT_WORDS.contains(&w))
}

/// What is being resolved, for messages.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Subject {
    pub(crate) name: String,
    pub(crate) description: String,
    pub(crate) span: Span,
}

struct State<'a> {
    catalog: &'a Catalog,
    seed: u64,
    options: ResolveOptions,
    /// The assets the rooms before the one being resolved use.
    /// (Looked up once per candidate and object, never iterated: a hash set.)
    used: rustc_hash::FxHashSet<String>,
    /// Which assets the room being resolved asked about, with the answers (free or not), as
    /// [`read`] makes them.
    reads: Vec<u64>,
    /// The assets the room being resolved uses.
    writes: BTreeSet<String>,
    /// The rankings the room being resolved asked for.
    asked: Vec<std::rc::Rc<Vec<Candidate>>>,
    diagnostics: Vec<Diagnostic>,
    /// While a group's choice is recorded ([`State::choose_recorded`]): each span it asked to
    /// report, with whether it was new, and each asset it used.
    reports: Option<Vec<(SpanKey, bool)>>,
    writes_made: Option<Vec<String>>,
    /// How many groups' choices were taken again ([`Resolver::groups_kept`]).
    groups_kept: u64,
    /// Spans already reported in the room being resolved (one cause, one diagnostic; every
    /// span of a room's diagnostics is in the room).
    reported: BTreeSet<(u32, u32, u32)>,
    /// Rankings already computed, by query text (shared, not copied, by every object that
    /// asks the same question).
    cache: BTreeMap<RankKey, std::rc::Rc<Vec<Candidate>>>,
    /// Rankings of an earlier resolution with the same catalog and seed, taken when asked.
    earlier: BTreeMap<RankKey, std::rc::Rc<Vec<Candidate>>>,
    /// While resolving things on top: the receptacle's top, `[short, long]` side in metres.
    top: Option<[f64; 2]>,
    /// While resolving things on top: the receptacle's asset type (`ShelvingUnit`).
    top_type: Option<String>,
    /// Typical on-object sizes by type, worked out once ([`typical_on_object_m`]).
    typical: BTreeMap<String, Option<f64>>,
    /// The last on-object asset rejected as too large in `choose`, for the warning.
    too_large: Option<String>,
    /// The nearest stand-in (or thing placed otherwise) refused in `choose` for its size: the
    /// asset and its size ratio, for the warning.
    refused: Option<(String, f64)>,
    /// While resolving a room's floor and wall objects: its `[long side, short side, wall
    /// height]`, metres, for the objathor size filters.
    room_box: Option<[f64; 3]>,
    /// Objathor rankings already computed, by query text.
    objathor_cache: BTreeMap<RankKey, std::rc::Rc<Vec<Candidate>>>,
}

impl<'a> State<'a> {
    fn new(catalog: &'a Catalog, seed: u64, options: ResolveOptions) -> State<'a> {
        State {
            catalog,
            seed,
            options,
            used: rustc_hash::FxHashSet::default(),
            reads: Vec::new(),
            writes: BTreeSet::new(),
            asked: Vec::new(),
            diagnostics: Vec::new(),
            reported: BTreeSet::new(),
            reports: None,
            writes_made: None,
            groups_kept: 0,
            cache: BTreeMap::new(),
            earlier: BTreeMap::new(),
            top: None,
            top_type: None,
            typical: BTreeMap::new(),
            too_large: None,
            refused: None,
            room_box: None,
            objathor_cache: BTreeMap::new(),
        }
    }

    /// The catalog (by address and size) and seed rankings are made with.
    fn made_with(&self) -> (usize, usize, u64) {
        (std::ptr::from_ref(self.catalog) as usize, self.catalog.assets().len(), self.seed)
    }

    /// Whether no room before this one uses the asset at `place` in the catalog, `asset` (the
    /// answer is remembered).
    fn is_free(&mut self, place: usize, asset: &str) -> bool {
        let free = !self.used.contains(asset);
        // A place that is not the asset's (no candidate has one) is kept as no place: a read
        // that never holds again.
        let known = self.catalog.assets().get(place).is_some_and(|a| a.id == asset);
        self.reads.push(read(if known { place } else { NO_PLACE }, free));
        free
    }

    /// Counts `asset` as used by the room being resolved.
    fn mark_used(&mut self, asset: &str) {
        if let Some(made) = &mut self.writes_made {
            made.push(asset.to_string());
        }
        if !self.writes.contains(asset) {
            self.writes.insert(asset.to_string());
        }
    }

    fn ranked(&mut self, query: &Query) -> std::rc::Rc<Vec<Candidate>> {
        let key = (
            query.category.clone(),
            query.description.clone().unwrap_or_default(),
            size_key(query.size_m),
            query.kind.map_or("", PlacementKind::as_str),
        );
        let list = if let Some(hit) = self.cache.get(&key) {
            std::rc::Rc::clone(hit)
        } else if let Some(hit) = self.earlier.remove(&key) {
            self.cache.insert(key, std::rc::Rc::clone(&hit));
            hit
        } else {
            let list = std::rc::Rc::new(rank_top(self.catalog, query, self.seed, RANK_LIMIT));
            self.cache.insert(key, std::rc::Rc::clone(&list));
            list
        };
        if !self.asked.iter().any(|l| std::rc::Rc::ptr_eq(l, &list)) {
            self.asked.push(std::rc::Rc::clone(&list));
        }
        list
    }

    fn objathor_ranked(&mut self, query: &Query) -> std::rc::Rc<Vec<Candidate>> {
        if self.catalog.objathor().is_none() {
            return std::rc::Rc::new(Vec::new());
        }
        let key = (
            query.category.clone(),
            query.description.clone().unwrap_or_default(),
            size_key(query.size_m),
            query.kind.map_or("", PlacementKind::as_str),
        );
        if let Some(hit) = self.objathor_cache.get(&key) {
            return std::rc::Rc::clone(hit);
        }
        let list = std::rc::Rc::new(objathor::rank(self.catalog, query, self.seed, RANK_LIMIT));
        self.objathor_cache.insert(key, std::rc::Rc::clone(&list));
        list
    }

    fn report_once(&mut self, span: Span, d: Diagnostic) {
        let key = (span.file.0, span.start, span.end);
        let new = self.reported.insert(key);
        if let Some(reports) = &mut self.reports {
            reports.push((key, new));
        }
        if new {
            self.diagnostics.push(d);
        }
    }

    /// [`State::choose`] for an object group, with what it read of and gave to the room's
    /// resolution recorded (see [`GroupRun`]).
    fn choose_recorded(
        &mut self,
        what: Subject,
        query: Query,
        variance: Variance,
        pins: &[Option<&Pinned>],
        wants_receptacle: bool,
    ) -> GroupRun {
        let (diagnostics, reads, asked) =
            (self.diagnostics.len(), self.reads.len(), self.asked.len());
        self.reports = Some(Vec::new());
        self.writes_made = Some(Vec::new());
        let results = self.choose(&what, &query, variance, pins, wants_receptacle);
        GroupRun {
            room_box: self.room_box,
            pins: pins.iter().map(|p| p.cloned()).collect(),
            what,
            query,
            variance,
            wants_receptacle,
            results,
            diagnostics: self.diagnostics[diagnostics..].to_vec(),
            reports: self.reports.take().unwrap_or_default(),
            reads: self.reads[reads..].to_vec(),
            writes: self.writes_made.take().unwrap_or_default(),
            asked: self.asked[asked..].to_vec(),
        }
    }

    /// Whether a group's choice would read now what it read then: the same answers about the
    /// rooms before, and the same spans reported or not in the room so far.
    fn reads_hold(&self, run: &GroupRun) -> bool {
        run.reads.iter().all(|&r| {
            let (place, free) = unread(r);
            let asset = self.catalog.assets().get(place);
            asset.is_some_and(|a| free != self.used.contains(a.id.as_ref()))
        }) && run.reports.iter().all(|(key, new)| *new != self.reported.contains(key))
    }

    /// Gives the room's resolution what a group's choice gave it when it was made.
    fn replay(&mut self, run: &GroupRun) {
        for (key, new) in &run.reports {
            if *new {
                self.reported.insert(*key);
            }
        }
        self.diagnostics.extend(run.diagnostics.iter().cloned());
        self.reads.extend(run.reads.iter().copied());
        for asset in &run.writes {
            self.mark_used(asset);
        }
        for list in &run.asked {
            if !self.asked.iter().any(|l| std::rc::Rc::ptr_eq(l, list)) {
                self.asked.push(std::rc::Rc::clone(list));
            }
        }
    }

    /// Resolutions for `pins.len()` instances of one thing.
    fn choose(
        &mut self,
        what: &Subject,
        query: &Query,
        variance: Variance,
        pins: &[Option<&Pinned>],
        wants_receptacle: bool,
    ) -> Vec<Resolution> {
        let kind = query.kind.unwrap_or(PlacementKind::Floor);
        let ranked = self.ranked(query);
        self.too_large = None;
        self.refused = None;
        let mut good: Vec<&Candidate> = Vec::new();
        for c in ranked.iter().filter(|c| c.is_good_enough()) {
            if kind == PlacementKind::OnObject && self.is_too_large(query, c.bbox_m, &c.object_type)
            {
                self.too_large.get_or_insert_with(|| c.asset_id.clone());
            } else {
                good.push(c);
            }
        }
        // The objathor folder's assets: for what the other catalogs have nothing good for, or
        // merged with theirs by lexical score.
        let objathor_ranked = self.objathor_ranked(query);
        if let Some(obj) = self.catalog.objathor() {
            let (mix, pick) = (obj.mix, obj.pick);
            let mut extra: Vec<&Candidate> = Vec::new();
            for c in objathor_ranked.iter().filter(|c| c.is_good_enough()) {
                if self.room_box.is_some_and(|r| objathor::fits_room(c.bbox_m, kind, r).is_err()) {
                    continue;
                }
                if kind == PlacementKind::OnObject
                    && self.is_too_large(query, c.bbox_m, &c.object_type)
                {
                    self.too_large.get_or_insert_with(|| c.asset_id.clone());
                    continue;
                }
                extra.push(c);
            }
            if pick == objathor::Pick::Seeded {
                let scores: Vec<f64> = extra.iter().map(|c| c.score).collect();
                let order = objathor::seeded_order(
                    &scores,
                    objathor::pick_pool(kind),
                    self.seed,
                    &what.name,
                );
                extra = order.into_iter().map(|i| extra[i]).collect();
            }
            match mix {
                objathor::Mix::ObjathorFirst => {
                    if !extra.is_empty() {
                        good = extra;
                    }
                }
                objathor::Mix::BuiltinFirst => {
                    // The built-in set first, unless its best is not the kind of thing the
                    // words name and holoc would make it (objathor's assets come before a
                    // made one).
                    let not_the_thing = self.options.make
                        && good.first().is_some_and(|c| {
                            crate::make::named(&query.category, kind)
                                .is_some_and(|k| !crate::make::builtin_is(k, &c.object_type))
                        });
                    if good.is_empty() || (not_the_thing && !extra.is_empty()) {
                        good = extra;
                    }
                }
                objathor::Mix::Score => {
                    let lexical =
                        |c: &Candidate| c.features.as_ref().map_or(c.score, |f| f.lexical_score);
                    let (mut a, mut b) =
                        (good.into_iter().peekable(), extra.into_iter().peekable());
                    let mut merged = Vec::new();
                    loop {
                        let take_a = match (a.peek(), b.peek()) {
                            (Some(x), Some(y)) => x.score >= lexical(y),
                            (Some(_), None) => true,
                            (None, Some(_)) => false,
                            (None, None) => break,
                        };
                        merged.extend(if take_a { a.next() } else { b.next() });
                    }
                    good = merged;
                }
            }
        }
        if wants_receptacle && good.iter().any(|c| self.catalog.asset_at(c.idx).receptacle) {
            // Stable: receptacles first, each part in rank order.
            good.sort_by_key(|c| !self.catalog.asset_at(c.idx).receptacle);
        }
        if let (Some(top), PlacementKind::OnObject) = (self.top, kind) {
            // Things that fit on the receptacle's top first (a 1.22 m television is not put
            // on a 1.20 m stand while narrower ones exist), each part in rank order.
            let fits = |c: &Candidate| {
                let (a, b) = (c.bbox_m[0], c.bbox_m[2]);
                a.min(b) <= top[0] + 1e-9 && a.max(b) <= top[1] + 1e-9
            };
            good.sort_by_key(|c| !fits(c));
        }
        if let (Some(receptacle), PlacementKind::OnObject) = (&self.top_type, kind) {
            // Things people put on this receptacle first (`resolve::receptacles`: a book on a
            // shelving unit, never a plant on a plant), each part in the order above.
            if receptacles::is_receptacle_type(receptacle) {
                good.sort_by_key(|c| !receptacles::allowed_on(&c.object_type, receptacle));
            }
        }
        // Avoid assets used in other rooms where an alternative exists.
        // Only the first `pins.len()` picks are ever taken (`pool[i]` with `i < pins.len()`),
        // so the scan stops once that many fresh assets are found: the pool's prefix is then
        // the same as with every candidate sorted.
        let need = pins.len().max(1);
        let (mut fresh, mut used) = (Vec::with_capacity(need), Vec::new());
        for c in &good {
            if fresh.len() == need {
                break;
            }
            if self.is_free(c.idx, &c.asset_id) {
                fresh.push(*c);
            } else {
                used.push(*c);
            }
        }
        let pool: Vec<&Candidate> = fresh.into_iter().chain(used).collect();
        // Words that name a kind holoc makes take the made asset before a built-in asset of
        // another type (a painting for `round mirror`); the scene's own catalogs and objathor
        // still come first.
        let made_first = self.options.make
            && pool.first().is_some_and(|c| {
                self.catalog.asset_at(c.idx).source == 0
                    && crate::make::named(&query.category, kind)
                        .is_some_and(|k| !crate::make::builtin_is(k, &c.object_type))
            });

        let mut out = Vec::with_capacity(pins.len());
        for (i, pin) in pins.iter().enumerate() {
            if let Some(pin) = pin {
                out.push(self.pinned(what, pin, kind, &ranked));
                continue;
            }
            if made_first {
                if let Some(res) = self.made(what, query, kind) {
                    out.push(res);
                    continue;
                }
            }
            if pool.is_empty() {
                if let Some(res) = self.kind_of(query, kind, wants_receptacle) {
                    out.push(res);
                    continue;
                }
                if let Some(res) = self.made(what, query, kind) {
                    out.push(res);
                    continue;
                }
                if let Some(res) = self.stand_in(what, query, kind, wants_receptacle) {
                    out.push(res);
                    continue;
                }
                if let Some(res) = self.placed_otherwise(what, query, kind) {
                    out.push(res);
                    continue;
                }
                let nearest: Vec<Candidate> = ranked.iter().take(3).cloned().collect();
                let mut d = errors::no_match(what, kind, &nearest, self.catalog);
                if let Some(id) = &self.too_large {
                    d = d.with_note(errors::too_large_note(self.catalog, id, query));
                }
                if let Some((id, ratio)) = &self.refused {
                    d = d.with_note(errors::refused_note(self.catalog, id, *ratio, query, kind));
                }
                self.report_once(what.span, d);
                out.push(Resolution::Unresolved(Unresolved {
                    reason: format!(
                        "no {} asset matches \"{}\" well enough",
                        kind.as_str(),
                        what.description
                    ),
                    nearest,
                }));
                continue;
            }
            let pick = match variance {
                Variance::Same => pool[0],
                Variance::Varied => pool[i % pool.len()],
            };
            let from = if self.catalog.objathor().is_some_and(|o| o.holds(pick.idx)) {
                &objathor_ranked
            } else {
                &ranked
            };
            let runner_up = from.iter().find(|c| c.asset_id != pick.asset_id).cloned();
            let asset = self.catalog.asset_at(pick.idx);
            self.mark_used(&asset.id);
            out.push(Resolution::Chosen(Choice {
                parts: Some(pick.clone()),
                runner_up,
                ..Choice::of(asset)
            }));
        }
        out
    }

    /// An asset of the type the thing is a kind of (`resolve::kinds`), read from its category's
    /// noun phrase, else from its description's; `None` when neither names a known kind or the
    /// catalog has no asset of those types for this placement.
    fn kind_of(
        &mut self,
        query: &Query,
        kind: PlacementKind,
        wants_receptacle: bool,
    ) -> Option<Resolution> {
        let (category, _) = text::split_phrase(&query.category);
        let description = query.description.as_deref().map(|d| text::split_phrase(d).0);
        let row =
            kinds::lookup(&category).or_else(|| description.as_deref().and_then(kinds::lookup))?;
        // When the object's words name a kind holoc makes, only a type that is that kind (a
        // dog bed for a cat bed) goes before the made asset: a `round mirror, brass frame` is
        // not a painting because its description ends in `frame`.
        if let Some(named) =
            self.options.make.then(|| crate::make::named(&query.category, kind)).flatten()
        {
            if !row.types.iter().any(|t| crate::make::builtin_is(named, t)) {
                return None;
            }
        }
        let types = self.holding_types(&row.types, wants_receptacle);
        let asset = standins::pick_of_types(self.catalog, &types, kind, query.size_m)?;
        if kind == PlacementKind::OnObject
            && self.is_too_large(query, asset.bbox_m, &asset.object_type)
        {
            self.too_large.get_or_insert_with(|| asset.id.to_string());
            return None;
        }
        self.mark_used(&asset.id);
        Some(Resolution::Chosen(Choice {
            kind_of: Some(format!(
                "`{}` is a kind of {} ({})",
                row.word, asset.object_type, row.source
            )),
            ..Choice::of(asset)
        }))
    }

    /// A thing asked for in a placement its type does not have in the catalog, placed the way
    /// people place it anyway: a television, microwave, clock or mirror hung on the wall, a
    /// vase, statue, plant or box stood on the floor, a framed picture stood on furniture
    /// (the smallest one; W0404). `None` for anything else.
    fn placed_otherwise(
        &mut self,
        what: &Subject,
        query: &Query,
        kind: PlacementKind,
    ) -> Option<Resolution> {
        let (allowed, from): (&[&str], PlacementKind) = match kind {
            PlacementKind::Wall => (WALL_MOUNTED, PlacementKind::OnObject),
            PlacementKind::Floor => (FLOOR_STANDING, PlacementKind::OnObject),
            PlacementKind::OnObject => (ON_FURNITURE, PlacementKind::Wall),
            PlacementKind::Ceiling => return None,
        };
        let tried = match kind {
            PlacementKind::Wall => vec![from, PlacementKind::Floor],
            _ => vec![from],
        };
        for other in tried {
            let other_query = Query { kind: Some(other), ..query.clone() };
            let ranked = self.ranked(&other_query);
            let by_words = ranked
                .iter()
                .find(|c| c.is_good_enough() && allowed.contains(&c.object_type.as_str()))
                .map(|c| self.catalog.asset_at(c.idx));
            let asset = by_words.or_else(|| {
                let (category, _) = text::split_phrase(&query.category);
                let row = kinds::lookup(&category)?;
                let types: Vec<&str> =
                    row.types.iter().copied().filter(|t| allowed.contains(t)).collect();
                standins::pick_of_types(self.catalog, &types, other, query.size_m)
            });
            if let Some(asset) = asset {
                if kind == PlacementKind::OnObject
                    && self.is_too_large(query, asset.bbox_m, &asset.object_type)
                {
                    // A wall picture is no photo frame on a shelf.
                    self.too_large.get_or_insert_with(|| asset.id.to_string());
                    continue;
                }
                let ratio = query.size_m.map(|want| standins::size_ratio(asset.bbox_m, want, kind));
                if let Some(r) = ratio.filter(|r| *r > standins::MAX_STAND_IN_RATIO + 1e-9) {
                    self.refused.get_or_insert_with(|| (asset.id.to_string(), r));
                    continue;
                }
                self.report_once(
                    what.span,
                    errors::placed_otherwise(what, asset, kind, ratio, query.size_m),
                );
                self.mark_used(&asset.id);
                return Some(Resolution::Chosen(Choice {
                    placed_as: Some(errors::kind_phrase(kind).to_string()),
                    size_ratio: ratio,
                    ..Choice::of(asset)
                }));
            }
        }
        None
    }

    /// An asset holoc makes (`crate::make`) when one of its generators makes this kind of
    /// thing placed this way; `None` when making is off or no kind is named. Made assets of
    /// one request are the same asset (one uid, one folder).
    fn made(&mut self, what: &Subject, query: &Query, kind: PlacementKind) -> Option<Resolution> {
        if !self.options.make {
            return None;
        }
        let description = query.description.as_deref().or(Some(what.description.as_str()));
        let made_kind = crate::make::recognise(&query.category, description, kind)
            .or_else(|| crate::make::recognise(&what.name.replace(['_', '-'], " "), None, kind))?;
        let request = crate::make::Request {
            kind: made_kind,
            size_m: query.size_m,
            description: query.description.clone().unwrap_or_else(|| query.category.clone()),
        };
        let made = crate::make::make(&request);
        let source = self.catalog.sources().len().saturating_sub(1);
        Some(Resolution::Chosen(Choice::of_made(made, source)))
    }

    /// An asset of another type that does the same job, from the stand-in table, with its
    /// warning (W0403, once per declaration); `None` when stand-ins are off or none fits.
    fn stand_in(
        &mut self,
        what: &Subject,
        query: &Query,
        kind: PlacementKind,
        wants_receptacle: bool,
    ) -> Option<Resolution> {
        if !self.options.stand_ins {
            return None;
        }
        let line = standins::lookup(&query.category).or_else(|| standins::lookup(&what.name))?;
        // A stand-in for a thing with things on top must itself hold things (no plant on a
        // plant).
        let types = self.holding_types(line.types, wants_receptacle);
        let (asset, ratio) = standins::pick_stand_in(self.catalog, &types, kind, query.size_m)?;
        if let Some(r) = ratio.filter(|r| *r > standins::MAX_STAND_IN_RATIO + 1e-9) {
            // Too far from the size asked: a 0.89 m dresser is no 2 m wardrobe.
            self.refused.get_or_insert_with(|| (asset.id.to_string(), r));
            return None;
        }
        if kind == PlacementKind::OnObject
            && self.is_too_large(query, asset.bbox_m, &asset.object_type)
        {
            self.too_large.get_or_insert_with(|| asset.id.to_string());
            return None;
        }
        self.report_once(what.span, errors::stand_in(what, asset, line, ratio, query.size_m));
        self.mark_used(&asset.id);
        Some(Resolution::Chosen(Choice {
            stand_in: Some(line.reason.to_owned()),
            size_ratio: ratio,
            ..Choice::of(asset)
        }))
    }

    /// Of `types`, those that can hold things when the thing has things on top: a type of
    /// the receptacle table or one the catalog has a receptacle asset of. All of them
    /// otherwise.
    fn holding_types<'t>(&self, types: &[&'t str], wants_receptacle: bool) -> Vec<&'t str> {
        types
            .iter()
            .copied()
            .filter(|t| {
                !wants_receptacle
                    || receptacles::is_receptacle_type(t)
                    || self.catalog.assets().iter().any(|a| a.object_type == *t && a.receptacle)
            })
            .collect()
    }

    /// Whether an asset is too large for a thing on top ([`MAX_SIZE_RATIO`] times its written
    /// size, else the typical size of the asset's type on furniture).
    fn is_too_large(&mut self, query: &Query, bbox_m: [f64; 3], object_type: &str) -> bool {
        let longest = |b: [f64; 3]| b.iter().copied().fold(0.0, f64::max);
        let want = match query.size_m {
            Some(size) => Some(longest(size)),
            None => *self
                .typical
                .entry(object_type.to_owned())
                .or_insert_with(|| typical_on_object_m(self.catalog, object_type)),
        };
        want.is_some_and(|w| longest(bbox_m) > MAX_SIZE_RATIO * w + 1e-9)
    }

    fn pinned(
        &mut self,
        what: &Subject,
        pin: &Pinned,
        kind: PlacementKind,
        ranked: &[Candidate],
    ) -> Resolution {
        let right_kind: Vec<Candidate> =
            ranked.iter().filter(|c| c.is_good_enough()).take(3).cloned().collect();
        match self.catalog.get(&pin.id) {
            None => {
                let d = errors::unknown_asset(pin, self.catalog, kind, &right_kind);
                self.report_once(pin.span, d);
                Resolution::Unresolved(Unresolved {
                    reason: format!("pinned asset `{}` is not in the catalog", pin.id),
                    nearest: right_kind,
                })
            }
            Some(asset) if !asset.allows(kind) => {
                let d = errors::wrong_kind(pin, asset, kind, &right_kind, &what.name);
                self.report_once(pin.span, d);
                Resolution::Unresolved(Unresolved {
                    reason: format!(
                        "pinned asset `{}` cannot be placed {}",
                        pin.id,
                        errors::kind_phrase(kind)
                    ),
                    nearest: right_kind,
                })
            }
            Some(asset) => {
                self.mark_used(&asset.id);
                Resolution::Chosen(Choice {
                    pinned: true,
                    runner_up: ranked.iter().find(|c| c.asset_id != asset.id).cloned(),
                    ..Choice::of(asset)
                })
            }
        }
    }
}

/// A room's `[long side, short side, wall height]`, metres: the sides of its corners' box.
pub fn room_box(room: &crate::check::Room, wall_height_m: f64) -> Option<[f64; 3]> {
    let first = room.corners.first()?;
    let (mut lo, mut hi) = (*first, *first);
    for c in &room.corners {
        lo = [lo[0].min(c[0]), lo[1].min(c[1])];
        hi = [hi[0].max(c[0]), hi[1].max(c[1])];
    }
    let (dx, dz) = (hi[0] - lo[0], hi[1] - lo[1]);
    Some([dx.max(dz), dx.min(dz), wall_height_m])
}
