//! The resolve stage's diagnostics, built in one place.

use super::catalog::{Asset, Catalog, PlacementKind};
use super::index::Candidate;
use super::select::{parts_text, Subject};
use crate::check::Pinned;
use crate::diag::{suggest, Code, Diagnostic};

/// `on the floor`, `on a wall`, … for messages.
pub(crate) fn kind_phrase(kind: PlacementKind) -> &'static str {
    match kind {
        PlacementKind::Floor => "on the floor",
        PlacementKind::Wall => "on a wall",
        PlacementKind::OnObject => "on top of an object",
        PlacementKind::Ceiling => "on the ceiling",
    }
}

fn ids(candidates: &[Candidate]) -> Vec<String> {
    candidates.iter().map(|c| c.asset_id.clone()).collect()
}

/// E0401: a pin names no asset of any catalog.
pub(crate) fn unknown_asset(
    pin: &Pinned,
    catalog: &Catalog,
    kind: PlacementKind,
    ranked: &[Candidate],
) -> Diagnostic {
    let close: Vec<String> = suggest::closest(
        &pin.id,
        catalog.assets().iter().filter(|a| a.allows(kind)).map(|a| &*a.id),
    );
    let help = suggest::did_you_mean(&close).or_else(|| {
        suggest::did_you_mean(&ids(ranked))
            .map(|h| format!("{h} (the best matches of the description)"))
    });
    Diagnostic::new(Code::E0401, format!("unknown asset `{}`", pin.id))
        .with_primary(pin.span, "no catalog has this asset")
        .with_help_opt(help.or_else(|| Some("list assets with `holoc assets list`".into())))
        .with_fixes(suggest::quoted_replacements(pin.span, &close))
}

/// E0402: a pinned asset cannot be placed the way the object is.
pub(crate) fn wrong_kind(
    pin: &Pinned,
    asset: &Asset,
    kind: PlacementKind,
    ranked: &[Candidate],
    name: &str,
) -> Diagnostic {
    let can: Vec<&str> = PlacementKind::ALL
        .into_iter()
        .filter(|k| asset.allows(*k))
        .map(PlacementKind::as_str)
        .collect();
    let can = if can.is_empty() { "nowhere".to_string() } else { can.join(", ") };
    Diagnostic::new(
        Code::E0402,
        format!("asset `{}` cannot be placed {} (`{name}`)", pin.id, kind_phrase(kind)),
    )
    .with_primary(pin.span, format!("a {} asset; it can go: {can}", asset.object_type))
    .with_help_opt(
        suggest::did_you_mean(&ids(ranked))
            .or_else(|| Some(format!("pin an asset that can be placed {}", kind_phrase(kind)))),
    )
}

/// W0403: an asset of another type stands in for a thing the catalog lacks.
pub(crate) fn stand_in(
    what: &Subject,
    asset: &Asset,
    line: &super::standins::StandIn,
    ratio: Option<f64>,
    asked_m: Option<[f64; 3]>,
) -> Diagnostic {
    let off = ratio.map_or(String::new(), |r| format!(", size ratio {r:.2}"));
    let mut d = Diagnostic::new(
        Code::W0403,
        format!(
            "no asset of its own for `{}` (\"{}\"); {} {} (`{}`) stands in{off}",
            what.name,
            what.description,
            article(&asset.object_type),
            asset.object_type,
            asset.id
        ),
    )
    .with_primary(
        what.span,
        format!("{} {} stands in", article(&asset.object_type), asset.object_type),
    )
    .with_note(format!(
        "{} {} for {} {}: {}",
        article(&asset.object_type),
        asset.object_type,
        article(line.key),
        line.key,
        line.reason
    ));
    if let (Some(r), Some(asked)) = (ratio, asked_m) {
        d = d.with_note(size_note(asset, asked, r));
    }
    d.with_help("pin an asset with `asset \"…\"`, add a catalog that has one with `--catalog`, or build with `--no-stand-ins` to leave it out")
}

/// `w × d × h cm`, rounded to whole centimetres.
fn cm3(w: f64, d: f64, h: f64) -> String {
    let cm = |m: f64| format!("{:.0}", m * 100.0);
    format!("{} × {} × {} cm", cm(w), cm(d), cm(h))
}

/// The note that compares an asset's size with the size asked.
fn size_note(asset: &Asset, asked_m: [f64; 3], ratio: f64) -> String {
    let [x, y, z] = asset.bbox_m;
    format!(
        "`{}` is {} (width × depth × height) for {} asked: size ratio {ratio:.2}, at most {} is accepted",
        asset.id,
        cm3(x, z, y),
        cm3(asked_m[0], asked_m[1], asked_m[2]),
        super::standins::MAX_STAND_IN_RATIO
    )
}

/// The note of a thing whose nearest stand-in (or placement otherwise) was refused for its
/// size.
pub(crate) fn refused_note(
    catalog: &Catalog,
    asset_id: &str,
    ratio: f64,
    query: &super::index::Query,
    kind: PlacementKind,
) -> String {
    let Some(asset) = catalog.get(asset_id) else { return String::new() };
    let asked =
        query.size_m.map_or(String::new(), |a| format!(" for {} asked", cm3(a[0], a[1], a[2])));
    let [x, y, z] = asset.bbox_m;
    format!(
        "{} {} could be used {} (`{}`, {}{asked}), but its size ratio {ratio:.2} is more than {}",
        article(&asset.object_type),
        asset.object_type,
        kind_phrase(kind),
        asset.id,
        cm3(x, z, y),
        super::standins::MAX_STAND_IN_RATIO
    )
}

/// W0404: a thing placed in a way its catalog type does not list (a microwave on the wall).
pub(crate) fn placed_otherwise(
    what: &Subject,
    asset: &Asset,
    kind: PlacementKind,
    ratio: Option<f64>,
    asked_m: Option<[f64; 3]>,
) -> Diagnostic {
    let d = Diagnostic::new(
        Code::W0404,
        format!(
            "no asset for `{}` (\"{}\") can be placed {}; {} (`{}`) is placed {} anyway",
            what.name,
            what.description,
            kind_phrase(kind),
            with_article(&asset.object_type),
            asset.id,
            kind_phrase(kind)
        ),
    )
    .with_primary(
        what.span,
        format!("{} placed {}", with_article(&asset.object_type), kind_phrase(kind)),
    )
    .with_note(format!(
        "the catalog places `{}` only {}; people place {} {} too",
        asset.id,
        placements_phrase(asset.placements),
        with_article(&asset.object_type),
        kind_phrase(kind)
    ))
    .with_help("declare it where the catalog places it (e.g. `on top` of furniture), or pin an asset with `asset \"…\"`");
    match (ratio, asked_m) {
        (Some(r), Some(asked)) => d.with_note(size_note(asset, asked, r)),
        _ => d,
    }
}

/// `a Sofa`, `an AlarmClock`.
fn with_article(word: &str) -> String {
    let vowel = word.chars().next().is_some_and(|c| "AEIOUaeiou".contains(c));
    format!("{} {word}", if vowel { "an" } else { "a" })
}

/// The placements an asset allows, in words (`on the floor or on furniture`).
fn placements_phrase(p: super::catalog::Placements) -> String {
    let words: Vec<&str> = [
        (p.on_floor, "on the floor"),
        (p.on_wall, "on a wall"),
        (p.on_object, "on furniture"),
        (p.on_ceiling, "on the ceiling"),
    ]
    .into_iter()
    .filter_map(|(on, w)| on.then_some(w))
    .collect();
    if words.is_empty() {
        "nowhere".to_string()
    } else {
        words.join(" or ")
    }
}

/// W0401: nothing in the catalog is good enough.
/// The note of a thing on top whose only asset was too large for it.
pub(crate) fn too_large_note(
    catalog: &Catalog,
    asset_id: &str,
    query: &super::index::Query,
) -> String {
    let Some(asset) = catalog.get(asset_id) else { return String::new() };
    let longest = asset.bbox_m.iter().copied().fold(0.0, f64::max);
    let (what, size) = match query.size_m {
        Some(s) => ("its written size".to_owned(), s.iter().copied().fold(0.0, f64::max)),
        None => (
            format!("a typical {} on furniture", asset.object_type),
            super::select::typical_on_object_m(catalog, &asset.object_type).unwrap_or(0.0),
        ),
    };
    format!(
        "`{}` ({}, {longest:.2} m) is more than {} times {what} ({size:.2} m): too large to stand on furniture",
        asset.id,
        asset.object_type,
        super::select::MAX_SIZE_RATIO
    )
}

pub(crate) fn no_match(
    what: &Subject,
    kind: PlacementKind,
    nearest: &[Candidate],
    catalog: &Catalog,
) -> Diagnostic {
    let mut d = Diagnostic::new(
        Code::W0401,
        format!(
            "no {} asset matches `{}` (\"{}\"); it is left out",
            kind.as_str(),
            what.name,
            what.description
        ),
    )
    .with_primary(what.span, "nothing in the catalog is close enough");
    if nearest.is_empty() {
        d = d.with_note("no asset of this placement kind shares a word with the description");
    }
    for c in nearest {
        d = d.with_note(format!(
            "candidate `{}` ({}): score {}",
            c.asset_id,
            c.object_type,
            parts_text(c)
        ));
    }
    let has_kind = catalog.assets().iter().any(|a| a.allows(kind));
    let help = if has_kind {
        "describe it with words the catalog uses, pin an asset with `asset \"…\"`, or add a catalog with `--catalog` (the original Holodeck's assets with `--objathor`)".to_string()
    } else {
        format!(
            "the catalogs have no asset that can be placed {}; add one with `--catalog` (the original Holodeck's assets with `--objathor`)",
            kind_phrase(kind)
        )
    };
    d.with_help(help)
}

/// `a` or `an` before a word, by its first letter (`an Ottoman`, `a DogBed`).
fn article(word: &str) -> &'static str {
    match word.chars().next().map(|c| c.to_ascii_lowercase()) {
        Some('a' | 'e' | 'i' | 'o' | 'u') => "an",
        _ => "a",
    }
}
