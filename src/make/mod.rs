//! The `make` stage: assets no catalog has, made from parameters.
//!
//! AI2-THOR's built-in set has no cat tree, whiteboard, mirror or curtains, and the original's
//! Objaverse assets are a 50 GB download. When no catalog has a good enough asset for an object
//! and one of holoc's generators makes that kind of thing, the resolve stage asks this module
//! to make it: [`recognise`] reads the kind from the object's words, [`make`] builds it from
//! real parts (a cat tree's base, posts, platforms and hideaway), sized as the scene asks (or
//! at the kind's typical size), in the colours and materials its description names
//! ([`finish`]), front to `+z`. The house names it by a uid, as Holodeck's houses name
//! Objaverse assets, and [`runtime`] writes the folder AI2-THOR's run-time asset hook loads
//! (`<uid>/<uid>.json`, its textures and `thor_metadata.json`).
//!
//! Each family of generators is a file: `pets`, `wall`, `windows`, `bath`, `textiles`,
//! `tech`, `kitchen`, `desk`. The table of kinds ([`KINDS`]) says for each
//! the words that name it, where it may stand, its typical size, its AI2-THOR object type and
//! properties, and its generator.
//!
//! **Invariant:** a made asset is a pure function of its kind, size and description: the same
//! request makes the same bytes, and its uid is a hash of them.

mod bath;
mod desk;
pub mod finish;
mod kitchen;
pub mod mesh;
mod pets;
pub mod runtime;
mod tech;
mod textiles;
mod wall;
mod windows;

use std::collections::BTreeMap;
use std::sync::Arc;

use finish::{Look, Material, Swatch};
use mesh::{Build, Mesh};

use crate::resolve::PlacementKind;

/// The version of the generators: part of every uid, so that a changed generator never
/// reuses an older asset's folder.
pub const GENERATOR_VERSION: u32 = 1;

/// Where a kind of thing may be placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Places {
    /// On the floor.
    pub floor: bool,
    /// On a wall.
    pub wall: bool,
    /// On another object.
    pub on_object: bool,
}

const FLOOR: Places = Places { floor: true, wall: false, on_object: false };
const WALL: Places = Places { floor: false, wall: true, on_object: false };
const ON: Places = Places { floor: false, wall: false, on_object: true };
const FLOOR_OR_ON: Places = Places { floor: true, wall: false, on_object: true };
const FLOOR_OR_WALL: Places = Places { floor: true, wall: true, on_object: false };

impl Places {
    /// Whether a thing placed this way may be of the kind.
    pub fn allows(self, kind: PlacementKind) -> bool {
        match kind {
            PlacementKind::Floor => self.floor,
            PlacementKind::Wall => self.wall,
            PlacementKind::OnObject => self.on_object,
            PlacementKind::Ceiling => false,
        }
    }
}

/// How AI2-THOR treats a made asset (`thor_metadata.json`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Thor {
    /// Furniture: `Static`.
    Static,
    /// Furniture that holds things: `Static` with `Receptacle`.
    StaticReceptacle,
    /// A small thing an agent can pick up: `CanPickup`.
    Pickup,
}

impl Thor {
    /// `primaryProperty`.
    pub fn primary(self) -> &'static str {
        match self {
            Thor::Static | Thor::StaticReceptacle => "Static",
            Thor::Pickup => "CanPickup",
        }
    }

    /// `secondaryProperties`.
    pub fn secondary(self) -> &'static [&'static str] {
        match self {
            Thor::StaticReceptacle => &["Receptacle"],
            _ => &[],
        }
    }
}

/// A generator: builds the parts of one kind in the box `ctx.size`.
pub type Generator = fn(&mut Ctx<'_>) -> Build;

/// One kind of thing holoc makes.
#[derive(Clone, Copy, Debug)]
pub struct Kind {
    /// Its name (`cat_tree`): in uids, reports and the book.
    pub name: &'static str,
    /// The family file its generator is in.
    pub family: &'static str,
    /// The phrases that name it, singular, lower case (`cat tree`, `cat tower`).
    pub phrases: &'static [&'static str],
    /// Where it may be placed.
    pub places: Places,
    /// Its typical size `[width, height, depth]`, metres, when the scene asks none.
    pub typical_m: [f64; 3],
    /// The AI2-THOR object type it is reported as (a real one where one fits: `Mirror`,
    /// `Shelf`; else a name of its own). Its surfaces follow the type (`solve::surfaces`).
    pub object_type: &'static str,
    /// How AI2-THOR treats it.
    pub thor: Thor,
    /// Its mass, kilograms, at its typical size (scaled with its volume).
    pub mass_kg: f64,
    /// The generator.
    pub generator: Generator,
}

impl std::fmt::Debug for Ctx<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ctx").field("size", &self.size).finish_non_exhaustive()
    }
}

impl Kind {
    /// Whether other things may stand on it.
    pub fn receptacle(&self) -> bool {
        self.thor == Thor::StaticReceptacle
    }
}

/// Every kind holoc makes, by family.
pub const KINDS: &[Kind] = &[
    pets::CAT_TREE,
    pets::CAT_BED,
    pets::LITTER_BOX,
    pets::SCRATCHING_POST,
    pets::CAT_WALL_SHELF,
    pets::PET_BOWL,
    wall::WALL_SHELF,
    wall::WALL_CABINET,
    wall::MIRROR,
    wall::WHITEBOARD,
    wall::BLACKBOARD,
    wall::PIN_BOARD,
    wall::PROJECTOR_SCREEN,
    wall::WALL_CLOCK,
    wall::PICTURE_FRAME,
    wall::COAT_HOOKS,
    wall::TOWEL_HOOKS,
    windows::CURTAINS,
    windows::BLINDS,
    bath::SHOWER_STALL,
    bath::BATH_CADDY,
    textiles::BATH_MAT,
    textiles::RUG,
    textiles::THROW,
    tech::PROJECTOR,
    tech::SPEAKER,
    tech::GAME_CONSOLE,
    tech::CONFERENCE_PHONE,
    kitchen::CUTTING_BOARD,
    kitchen::PITCHER,
    kitchen::COASTERS,
    kitchen::RANGE,
    kitchen::KITCHEN_ISLAND,
    kitchen::TALL_CABINET,
    desk::PHOTO_FRAME,
    desk::PEN_HOLDER,
];

/// A kind by name.
pub fn kind(name: &str) -> Option<&'static Kind> {
    KINDS.iter().find(|k| k.name == name)
}

/// The words of a text, lower case and singular (`curtains` → `curtain`, `boxes` → `box`).
fn words(text: &str) -> Vec<String> {
    text.split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(|w| singular(&w.to_lowercase()))
        .collect()
}

/// A plural noun's singular, by the common English endings (enough for the phrases of
/// [`KINDS`]; a word that is not a plural comes back as it is).
fn singular(word: &str) -> String {
    let n = word.len();
    if n > 4 && (word.ends_with("xes") || word.ends_with("ches") || word.ends_with("shes")) {
        return word[..n - 2].to_string();
    }
    if n > 3 && word.ends_with('s') && !word.ends_with("ss") && !word.ends_with("us") {
        return word[..n - 1].to_string();
    }
    word.to_string()
}

/// Whether `phrase` (already singular words) occurs in `words` as a run of whole words, and
/// where it ends.
fn find_phrase(words: &[String], phrase: &str) -> Option<usize> {
    let p: Vec<&str> = phrase.split(' ').collect();
    if p.len() > words.len() {
        return None;
    }
    (0..=words.len() - p.len())
        .rev()
        .find(|&s| p.iter().zip(&words[s..]).all(|(a, b)| *a == b))
        .map(|s| s + p.len())
}

/// Categories that end in a phrase of [`KINDS`] but are other things, which AI2-THOR has or
/// which holoc does not make (`shower curtain` is no window curtain).
const NOT_MADE: &[&str] =
    &["shower curtain", "curtain rod", "shower head", "alarm clock", "clock radio"];

/// The kind an object is, read from its category (a phrase of the table ending at the
/// category's last word, the longest winning), else from its description (a phrase of two
/// words or more anywhere in it); `None` when no kind placed this way is named.
pub fn recognise(
    category: &str,
    description: Option<&str>,
    placement: PlacementKind,
) -> Option<&'static Kind> {
    let cat = words(category);
    if NOT_MADE.iter().any(|p| find_phrase(&cat, p).is_some()) {
        return None;
    }
    let best = |ws: &[String], anchored: bool| {
        let mut best: Option<(usize, &'static Kind)> = None;
        for k in KINDS.iter().filter(|k| k.places.allows(placement)) {
            for phrase in k.phrases {
                let n = phrase.split(' ').count();
                if !anchored && n < 2 {
                    continue;
                }
                let Some(end) = find_phrase(ws, phrase) else { continue };
                if anchored && end != ws.len() {
                    continue;
                }
                if best.is_none_or(|(m, _)| n > m) {
                    best = Some((n, k));
                }
            }
        }
        best.map(|(_, k)| k)
    };
    best(&cat, true).or_else(|| description.and_then(|d| best(&words(d), false)))
}

/// The AI2-THOR types whose built-in assets are truly this kind of thing (a dog bed for a cat
/// bed, a counter top for a kitchen island): when the words of an object name a kind holoc
/// makes, a built-in asset ranked first is taken only if it is of one of these types; any
/// other (a painting for `round mirror`) gives way to the made asset.
const BUILTIN_TYPES: &[(&str, &[&str])] = &[
    ("cat_bed", &["DogBed"]),
    ("pet_bowl", &["Bowl"]),
    ("kitchen_island", &["CounterTop"]),
    ("wall_shelf", &["ShelvingUnit"]),
    ("curtains", &["ShowerCurtain"]),
    ("picture_frame", &["Painting"]),
    ("towel_hooks", &["TowelHolder", "HandTowelHolder"]),
];

/// Whether a built-in asset of `object_type` is this kind of thing (the table `BUILTIN_TYPES`:
/// a dog bed for a cat bed, a counter top for a kitchen island, a painting for a picture frame,
/// a towel holder for towel hooks, a bowl for a pet bowl, a shelving unit for a wall shelf).
pub fn builtin_is(kind: &Kind, object_type: &str) -> bool {
    BUILTIN_TYPES
        .iter()
        .find(|(k, _)| *k == kind.name)
        .is_some_and(|(_, types)| types.contains(&object_type))
}

/// The kind an object's own name or category names (a phrase of the table ending at its last
/// word), without reading its description: what decides whether a made asset goes before a
/// built-in asset of another type.
pub fn named(category: &str, placement: PlacementKind) -> Option<&'static Kind> {
    recognise(category, None, placement)
}

/// What a generator is given: the box to fill and the description's look.
pub struct Ctx<'a> {
    /// The box to fill, `[width, height, depth]`, metres.
    pub size: [f64; 3],
    /// The description's look.
    pub look: &'a Look,
    /// The palette so far.
    palette: Vec<Swatch>,
    /// The parameters it chose (for the report), by name.
    params: BTreeMap<&'static str, String>,
}

impl Ctx<'_> {
    /// The width (x), height (y) and depth (z).
    pub fn whd(&self) -> (f64, f64, f64) {
        (self.size[0], self.size[1], self.size[2])
    }

    /// The swatch of the main part, in `material` unless the description names another of its
    /// family, in the description's colour.
    pub fn main(&mut self, material: Material) -> usize {
        self.push(self.look.swatch(material, true))
    }

    /// The swatch of an accent part in `material` (the description's second colour, if any).
    pub fn accent(&mut self, material: Material) -> usize {
        self.push(self.look.swatch(material, false))
    }

    /// A swatch of exactly this material and colour.
    pub fn fixed(&mut self, material: Material, rgb: [f64; 3]) -> usize {
        let mut s = self.look.swatch(material, false);
        s.material = material;
        s.rgb = rgb;
        self.push(s)
    }

    fn push(&mut self, s: Swatch) -> usize {
        if let Some(i) = self.palette.iter().position(|p| *p == s) {
            return i;
        }
        self.palette.push(s);
        self.palette.len() - 1
    }

    /// Records a parameter the generator chose (a count, a variant), for the report.
    pub fn note(&mut self, name: &'static str, value: impl std::fmt::Display) {
        self.params.insert(name, value.to_string());
    }
}

/// A thing to make.
#[derive(Clone, Debug)]
pub struct Request<'k> {
    /// Its kind.
    pub kind: &'k Kind,
    /// The size asked, `[width, depth, height]` as the scene writes it, metres.
    pub size_m: Option<[f64; 3]>,
    /// Its description (for colours, materials and variants).
    pub description: String,
}

/// A made asset.
#[derive(Clone, PartialEq)]
pub struct MadeAsset {
    /// Its id in the house and the name of its folder: `holoc_<kind>_<hash>`.
    pub uid: String,
    /// Its kind.
    pub kind: &'static str,
    /// The family its generator is in.
    pub family: &'static str,
    /// Its AI2-THOR object type.
    pub object_type: &'static str,
    /// How AI2-THOR treats it.
    pub thor: Thor,
    /// Its mass, kilograms.
    pub mass_kg: f64,
    /// The box its generator filled, `[width, height, depth]`, metres.
    pub size_m: [f64; 3],
    /// The parameters: the size, the description it read, and what its generator chose.
    pub params: BTreeMap<String, String>,
    /// Its parts' names, swatch by part.
    pub parts: Vec<(&'static str, usize)>,
    /// The colours and finishes of its parts.
    pub palette: Vec<Swatch>,
    /// Its triangle mesh, centred on its bounding box.
    pub mesh: Mesh,
}

impl std::fmt::Debug for MadeAsset {
    /// Its uid, kind, size and how many triangles: the mesh itself is too long to read.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MadeAsset")
            .field("uid", &self.uid)
            .field("kind", &self.kind)
            .field("size_m", &self.size_m)
            .field("triangles", &(self.mesh.triangles.len() / 3))
            .finish_non_exhaustive()
    }
}

impl MadeAsset {
    /// Its bounding box `[x, y, z]`, metres (the mesh's).
    pub fn bbox_m(&self) -> [f64; 3] {
        self.mesh.size
    }

    /// Whether things may be put on it.
    pub fn receptacle(&self) -> bool {
        self.thor == Thor::StaticReceptacle
    }

    /// "made by holoc: cat tree, 60 × 150 × 50 cm" (the language server's hover and the
    /// build's notes).
    pub fn summary(&self) -> String {
        let [w, h, d] = self.bbox_m();
        format!(
            "made by holoc: {}, {:.0} × {:.0} × {:.0} cm",
            self.kind.replace('_', " "),
            w * 100.0,
            d * 100.0,
            h * 100.0
        )
    }
}

/// The smallest side a made asset gets, metres: a size asked thinner than this is raised to it
/// (a 1 mm rug would make degenerate faces).
const MIN_SIDE_M: f64 = 0.005;

/// Makes an asset. The size asked (scene order: width, depth, height) is the box the
/// generator fills; without one, the kind's typical size.
pub fn make(request: &Request<'_>) -> Arc<MadeAsset> {
    let kind = request.kind;
    let size = request.size_m.map_or(kind.typical_m, |[w, d, h]| [w, h, d]).map(|v| {
        if v.is_finite() {
            v.max(MIN_SIDE_M)
        } else {
            MIN_SIDE_M
        }
    });
    let look = Look::of(&request.description);
    let mut ctx = Ctx { size, look: &look, palette: Vec::new(), params: BTreeMap::new() };
    let build = (kind.generator)(&mut ctx);
    let palette = ctx.palette;
    let cells = palette.len().max(1);
    let mesh = build.finish(|s| runtime::cell_uv(s, cells));
    let mut params: BTreeMap<String, String> =
        ctx.params.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
    params
        .insert("size".to_string(), format!("{:.3} x {:.3} x {:.3} m", size[0], size[2], size[1]));
    params.insert("description".to_string(), request.description.clone());
    let volume = |s: [f64; 3]| s[0] * s[1] * s[2];
    let mass_kg =
        (kind.mass_kg * volume(size) / volume(kind.typical_m).max(1e-9)).clamp(0.05, 500.0);
    let parts = build.parts.iter().map(|p| (p.name, p.swatch)).collect();
    let uid = uid_of(kind, size, &palette, &params, &mesh);
    Arc::new(MadeAsset {
        uid,
        kind: kind.name,
        family: kind.family,
        object_type: kind.object_type,
        thor: kind.thor,
        mass_kg: (mass_kg * 100.0).round() / 100.0,
        size_m: size,
        params,
        parts,
        palette,
        mesh,
    })
}

/// `holoc_<kind>_<12 hex digits>`: a hash of the generator version, the kind, the size, the
/// palette, the parameters and the mesh's size.
fn uid_of(
    kind: &Kind,
    size: [f64; 3],
    palette: &[Swatch],
    params: &BTreeMap<String, String>,
    mesh: &Mesh,
) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    h.update(GENERATOR_VERSION.to_le_bytes());
    h.update(kind.name.as_bytes());
    for v in size.iter().chain(&mesh.size) {
        h.update(((v * 10_000.0).round() as i64).to_le_bytes());
    }
    for s in palette {
        h.update(s.hex().as_bytes());
        h.update(s.material.name().as_bytes());
    }
    for (k, v) in params {
        h.update(k.as_bytes());
        h.update([0]);
        h.update(v.as_bytes());
        h.update([0]);
    }
    h.update((mesh.triangles.len() as u64).to_le_bytes());
    let digest = h.finalize();
    let hex = digest.iter().take(6).fold(String::new(), |mut s, b| {
        use std::fmt::Write as _;
        let _ = write!(s, "{b:02x}");
        s
    });
    format!("holoc_{}_{hex}", kind.name)
}

/// Whether an asset id is one holoc makes (`holoc_<kind>_<hash>`).
pub fn is_made_id(id: &str) -> bool {
    id.strip_prefix("holoc_").is_some_and(|rest| {
        rest.rsplit_once('_').is_some_and(|(k, h)| {
            kind(k).is_some() && h.len() == 12 && h.bytes().all(|b| b.is_ascii_hexdigit())
        })
    })
}

/// The made assets a house uses: every made choice of `resolved` whose uid is one of the
/// house's asset ids, once each, by uid.
pub fn used_in<'a>(
    resolved: &crate::resolve::Resolved,
    asset_ids: impl IntoIterator<Item = &'a str>,
) -> Vec<Arc<MadeAsset>> {
    let ids: std::collections::BTreeSet<&str> = asset_ids.into_iter().collect();
    let mut found: BTreeMap<String, Arc<MadeAsset>> = BTreeMap::new();
    let choices = resolved
        .objects
        .iter()
        .chain(resolved.ceilings.values())
        .chain(resolved.small.values().flatten())
        .filter_map(crate::resolve::Resolution::choice);
    for c in choices {
        if let Some(m) = &c.made {
            if ids.contains(m.uid.as_str()) {
                found.entry(m.uid.clone()).or_insert_with(|| Arc::clone(m));
            }
        }
    }
    found.into_values().collect()
}

/// The default folder of a house's made assets: `<house stem>.assets/` beside it.
pub fn folder_beside(house: &std::path::Path) -> std::path::PathBuf {
    let stem =
        house.file_stem().map_or_else(|| "house".into(), |s| s.to_string_lossy().into_owned());
    house.with_file_name(format!("{stem}.assets"))
}

/// A made asset as a catalog asset (for `validate`, `export`, `view` and `diff`, which look
/// assets up by id): its uid, its type, its kind's words, its box and where it may stand.
pub fn catalog_asset(
    uid: &str,
    kind: &Kind,
    bbox_m: [f64; 3],
    receptacle: bool,
) -> crate::resolve::Asset {
    crate::resolve::Asset {
        id: uid.to_string().into(),
        object_type: kind.object_type.into(),
        category: kind.phrases[0].into(),
        description: format!("made by holoc: {}", kind.phrases[0]).into(),
        bbox_m,
        placements: crate::resolve::Placements {
            on_floor: kind.places.floor,
            on_wall: kind.places.wall,
            on_object: kind.places.on_object,
            on_ceiling: false,
        },
        receptacle,
        source: 0,
    }
}

/// The made assets of a build as catalog assets.
pub fn catalog_assets(made: &[Arc<MadeAsset>]) -> Vec<crate::resolve::Asset> {
    made.iter()
        .filter_map(|m| {
            let k = kind(m.kind)?;
            Some(catalog_asset(&m.uid, k, m.bbox_m(), m.receptacle()))
        })
        .collect()
}

/// The made assets in a folder of asset folders (`<dir>/<uid>/<uid>.json`, for every uid holoc
/// makes), as catalog assets, with the problems of the folders that could not be read
/// (`(uid, why)`). A folder that does not exist holds none.
pub fn read_folder(dir: &std::path::Path) -> (Vec<crate::resolve::Asset>, Vec<(String, String)>) {
    let (assets, problems, _) = read_folder_assets(dir);
    (assets, problems)
}

/// What the made assets of their folders read by [`read_folder`] are, each with what was
/// read of it (its mesh and colours), so that `export` and `view` draw them without reading
/// the folder again.
#[allow(clippy::type_complexity)]
pub fn read_folder_assets(
    dir: &std::path::Path,
) -> (Vec<crate::resolve::Asset>, Vec<(String, String)>, Vec<(String, runtime::ReadAsset)>) {
    let mut reads = Vec::new();
    let mut assets = Vec::new();
    let mut problems = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else { return (assets, problems, reads) };
    let mut names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|n| is_made_id(n))
        .collect();
    names.sort();
    names.truncate(MAX_FOLDER_ASSETS);
    for uid in names {
        let Some(k) =
            uid.strip_prefix("holoc_").and_then(|r| r.rsplit_once('_')).and_then(|(k, _)| kind(k))
        else {
            continue;
        };
        match runtime::read_asset(dir, &uid) {
            Ok(read) => {
                assets.push(catalog_asset(&uid, k, read.size, read.receptacle));
                reads.push((uid, read));
            }
            Err(e) => problems.push((uid, e.to_string())),
        }
    }
    (assets, problems, reads)
}

/// The most asset folders [`read_folder`] reads from one folder.
pub const MAX_FOLDER_ASSETS: usize = 10_000;

/// Makes again, at the size the layout gave them, the made assets the layout sized (curtains
/// and blinds to the window they dress: `solve::PlacedObject::sized_m`), so that the house's
/// asset is the size it hangs at.
pub fn fit_to_layout(layout: &crate::solve::Layout, resolved: &mut crate::resolve::Resolved) {
    for solved in &layout.rooms {
        for placed in &solved.layout.wall {
            let Some(size) = placed.sized_m else { continue };
            let Some(index) = solved.problem.wall_objects.iter().position(|o| o.id == placed.id)
            else {
                continue;
            };
            let Some(id) = solved.wall_ids.get(index) else { continue };
            let Some(crate::resolve::Resolution::Chosen(choice)) = resolved.objects.get_mut(id.0)
            else {
                continue;
            };
            let Some(made) = &choice.made else { continue };
            let Some(k) = kind(made.kind) else { continue };
            let description = made.params.get("description").cloned().unwrap_or_default();
            let remade = make(&Request { kind: k, size_m: Some(size), description });
            choice.asset_id.clone_from(&remade.uid);
            choice.bbox_m = remade.bbox_m();
            choice.made = Some(remade);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_recognised_by_their_head_phrase() {
        let k = |c: &str, p| recognise(c, None, p).map(|k| k.name);
        assert_eq!(k("cat tree", PlacementKind::Floor), Some("cat_tree"));
        assert_eq!(k("large cat towers", PlacementKind::Floor), Some("cat_tree"));
        assert_eq!(k("cat wall shelf", PlacementKind::Wall), Some("cat_wall_shelf"));
        assert_eq!(k("wall shelf", PlacementKind::Wall), Some("wall_shelf"));
        assert_eq!(k("linen curtains", PlacementKind::Wall), Some("curtains"));
        assert_eq!(k("round mirror", PlacementKind::Wall), Some("mirror"));
        assert_eq!(k("mirror", PlacementKind::Ceiling), None);
        assert_eq!(k("tree", PlacementKind::Floor), None);
        assert_eq!(k("litter boxes", PlacementKind::Floor), Some("litter_box"));
        // From the description when the category names nothing.
        assert_eq!(
            recognise(
                "cat furniture",
                Some("a tall cat tree with platforms"),
                PlacementKind::Floor
            )
            .map(|k| k.name),
            Some("cat_tree")
        );
    }

    #[test]
    fn every_kind_makes_real_parts_at_its_size_the_same_way_twice() {
        let mut wrong = Vec::new();
        for kind in KINDS {
            let request =
                Request { kind, size_m: None, description: format!("a {}", kind.phrases[0]) };
            let a = make(&request);
            let b = make(&request);
            assert_eq!(a, b, "{}", kind.name);
            let distinct: std::collections::BTreeSet<&str> =
                a.parts.iter().map(|(n, _)| *n).collect();
            assert!(distinct.len() >= 2, "{} has parts {:?}", kind.name, a.parts);
            for i in 0..3 {
                let (got, want) = (a.bbox_m()[i], kind.typical_m[i]);
                if (got - want).abs() > 0.15 * want + 1e-9 {
                    wrong.push(format!("{}: side {i} is {got}, typical {want}", kind.name));
                }
            }
            assert!(is_made_id(&a.uid), "{}", a.uid);
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    #[test]
    fn every_kind_is_at_most_200_kb_on_disk() {
        for kind in KINDS {
            let made = make(&Request { kind, size_m: None, description: kind.phrases[0].into() });
            let bytes: usize = runtime::files(&made).iter().map(|(_, b)| b.len()).sum();
            assert!(bytes <= 200 * 1024, "{}: {bytes} bytes", kind.name);
        }
    }

    #[test]
    fn an_asked_size_is_the_box_filled() {
        let kind = kind("wall_shelf").expect("a wall shelf kind");
        let made = make(&Request {
            kind,
            size_m: Some([1.2, 0.25, 0.04]),
            description: "floating wall shelf".to_string(),
        });
        let [w, h, d] = made.bbox_m();
        assert!((w - 1.2).abs() < 0.18 && (d - 0.25).abs() < 0.04 && (h - 0.04).abs() < 0.01);
    }
}
