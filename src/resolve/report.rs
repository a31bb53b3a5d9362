//! The resolve part of the build report, as JSON (internal types are not `Serialize`).

use serde_json::{json, Map, Value};

use super::catalog::Catalog;
use super::index::Candidate;
use super::select::{Resolution, Resolved};
use crate::check::Scene;

/// Rounds to 4 decimals so that reports stay short and stable.
fn r4(v: f64) -> Value {
    let rounded = (v * 10_000.0).round() / 10_000.0;
    serde_json::Number::from_f64(rounded).map_or(Value::Null, Value::Number)
}

fn candidate(c: &Candidate, catalog: &Catalog) -> Value {
    let source = catalog.assets().get(c.idx).map(|a| catalog.source_of(a).name.clone());
    json!({
        "assetId": c.asset_id,
        "objectType": c.object_type,
        "catalog": source,
        "score": r4(c.score),
        "relevance": r4(c.relevance),
        "headMatch": c.head_match,
        "text": r4(c.text),
        "sizeDiffM": c.size_diff_m.map(r4),
        "bboxM": [r4(c.bbox_m[0]), r4(c.bbox_m[1]), r4(c.bbox_m[2])],
    })
}

/// One candidate as JSON (the `holoc assets search --format json` item).
pub fn candidate_json(c: &Candidate, catalog: &Catalog) -> Value {
    candidate(c, catalog)
}

fn resolution(res: &Resolution, catalog: &Catalog, mut head: Map<String, Value>) -> Value {
    match res {
        Resolution::Chosen(c) => {
            let source = &catalog.sources()[c.source.min(catalog.sources().len() - 1)];
            let status = if c.pinned {
                "pinned"
            } else if c.made.is_some() {
                "made"
            } else if c.stand_in.is_some() {
                "stand-in"
            } else {
                "chosen"
            };
            head.insert("status".into(), json!(status));
            if let Some(reason) = &c.stand_in {
                head.insert("standIn".into(), json!(reason));
            }
            if let Some(why) = &c.kind_of {
                head.insert("kindOf".into(), json!(why));
            }
            if let Some(way) = &c.placed_as {
                head.insert("placedAs".into(), json!(way));
            }
            if let Some(ratio) = c.size_ratio {
                head.insert("sizeRatio".into(), json!(r4(ratio)));
            }
            head.insert("assetId".into(), json!(c.asset_id));
            head.insert("objectType".into(), json!(c.object_type));
            match &c.made {
                Some(m) => {
                    head.insert("catalog".into(), json!("made by holoc"));
                    head.insert("madeKind".into(), json!(m.kind));
                }
                None => {
                    head.insert("catalog".into(), json!(source.name));
                }
            }
            head.insert("bboxM".into(), json!([r4(c.bbox_m[0]), r4(c.bbox_m[1]), r4(c.bbox_m[2])]));
            head.insert(
                "score".into(),
                c.parts.as_ref().map_or(Value::Null, |p| candidate(p, catalog)["score"].clone()),
            );
            head.insert(
                "scoreParts".into(),
                c.parts.as_ref().map_or(Value::Null, |p| {
                    let mut parts = json!({
                        "relevance": r4(p.relevance),
                        "headMatch": p.head_match,
                        "text": r4(p.text),
                        "sizeDiffM": p.size_diff_m.map(r4),
                    });
                    if let (Some(f), Some(map)) = (&p.features, parts.as_object_mut()) {
                        map.insert("clip".into(), r4(f.clip));
                        map.insert("sbert".into(), f.sbert.map_or(Value::Null, r4));
                        // An image-to-image CLIP part is not held against a threshold.
                        map.insert(
                            "clipThreshold".into(),
                            if f.text_space { r4(f.threshold) } else { Value::Null },
                        );
                        map.insert("lexicalScore".into(), r4(f.lexical_score));
                    }
                    parts
                }),
            );
            head.insert(
                "runnerUp".into(),
                c.runner_up.as_ref().map_or(Value::Null, |r| candidate(r, catalog)),
            );
        }
        Resolution::Unresolved(u) => {
            head.insert("status".into(), json!("unresolved"));
            head.insert("reason".into(), json!(u.reason));
            head.insert(
                "nearest".into(),
                Value::Array(u.nearest.iter().map(|c| candidate(c, catalog)).collect()),
            );
        }
    }
    Value::Object(head)
}

/// The resolve fragment of the build report: the catalog lock (name, version, sha256 of every
/// catalog), then per object, small object and ceiling object the chosen asset with its score
/// parts and runner-up, or why it is unresolved; and the list of everything left out. `placed`
/// gives the fields the layout adds to an entry (its id in the house, where a moved thing went).
pub fn report(
    scene: &Scene,
    catalog: &Catalog,
    resolved: &Resolved,
    placed: &dyn Fn(crate::lower::Source) -> Map<String, Value>,
) -> Value {
    use crate::lower::Source;
    let objathor = catalog.objathor();
    let catalogs: Vec<Value> = catalog
        .sources()
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let mut entry = json!({
                "name": s.name,
                "version": s.version,
                "sha256": s.sha256,
                "path": s.path,
                "assets": s.n_assets,
            });
            if let (Some(o), Some(map)) =
                (objathor.filter(|o| o.source == i), entry.as_object_mut())
            {
                map.insert("folder".into(), json!(o.root.display().to_string()));
                map.insert("scoring".into(), json!(o.scoring.as_str()));
                map.insert(
                    "scoringAsked".into(),
                    json!(o.scoring_asked.map(super::objathor::Scoring::as_str)),
                );
                map.insert("pseudoQuery".into(), json!(o.pseudo_query_space()));
                map.insert("mix".into(), json!(o.mix.as_str()));
                map.insert("pick".into(), json!(o.pick.as_str()));
                map.insert("assetsFolder".into(), json!(o.assets_dir.is_some()));
                map.insert(
                    "files".into(),
                    Value::Array(
                        o.files
                            .iter()
                            .map(|(path, sha)| json!({"path": path, "sha256": sha}))
                            .collect(),
                    ),
                );
            }
            entry
        })
        .collect();
    let mut objects = Vec::new();
    let mut small = Vec::new();
    let mut ceilings = Vec::new();
    let mut unresolved = Vec::new();
    for room in &scene.rooms {
        for &id in &room.objects {
            let obj = scene.object(id);
            let mut head = Map::new();
            head.insert("object".into(), json!(obj.name));
            head.insert("room".into(), json!(room.name));
            head.insert("kind".into(), json!(if obj.is_floor() { "floor" } else { "wall" }));
            head.insert(
                "description".into(),
                json!(obj.description.as_deref().unwrap_or(&obj.category)),
            );
            head.extend(placed(Source::Object(id)));
            if let Some(res) = resolved.objects.get(id.0) {
                let v = resolution(res, catalog, head);
                if matches!(res, Resolution::Unresolved(_)) {
                    unresolved.push(v.clone());
                }
                objects.push(v);
            }
            for (k, item) in obj.on_top.iter().enumerate() {
                for (i, res) in resolved.small.get(&(id, k)).into_iter().flatten().enumerate() {
                    let mut head = Map::new();
                    head.insert("object".into(), json!(format!("{}#{i}", item.item)));
                    head.insert("on".into(), json!(obj.name));
                    head.insert("room".into(), json!(room.name));
                    head.insert("kind".into(), json!("on-object"));
                    head.insert("description".into(), json!(item.item));
                    head.extend(placed(Source::Item(id, k, i as u32)));
                    let v = resolution(res, catalog, head);
                    if matches!(res, Resolution::Unresolved(_)) {
                        unresolved.push(v.clone());
                    }
                    small.push(v);
                }
            }
        }
        if let (Some(res), Some(ceiling)) = (resolved.ceilings.get(&room.id), &room.ceiling) {
            let mut head = Map::new();
            head.insert("object".into(), json!(format!("ceiling ({})", room.name)));
            head.insert("room".into(), json!(room.name));
            head.insert("kind".into(), json!("ceiling"));
            head.insert("description".into(), json!(ceiling.description));
            head.extend(placed(Source::Ceiling(room.id)));
            let v = resolution(res, catalog, head);
            if matches!(res, Resolution::Unresolved(_)) {
                unresolved.push(v.clone());
            }
            ceilings.push(v);
        }
    }
    let mut out = json!({
        "catalogs": catalogs,
        "objects": objects,
        "smallObjects": small,
        "ceilings": ceilings,
        "unresolved": unresolved,
    });
    if let (Some(o), Some(map)) = (objathor, out.as_object_mut()) {
        map.insert("attributions".into(), attributions(scene, catalog, resolved, o));
    }
    out
}

/// The objathor assets the scene uses, by uid, each with its licence, creator and page and the
/// objects that use it: what the house owes its creators (Objaverse assets are mostly CC-BY).
fn attributions(
    scene: &Scene,
    catalog: &Catalog,
    resolved: &Resolved,
    objathor: &super::objathor::Objathor,
) -> Value {
    let mut used: std::collections::BTreeMap<String, Vec<String>> =
        std::collections::BTreeMap::new();
    let mut note = |res: &Resolution, what: String| {
        if let Some(c) = res.choice() {
            if catalog.index_of(&c.asset_id).is_some_and(|i| objathor.holds(i)) {
                used.entry(c.asset_id.clone()).or_default().push(what);
            }
        }
    };
    for room in &scene.rooms {
        for &id in &room.objects {
            let obj = scene.object(id);
            if let Some(res) = resolved.objects.get(id.0) {
                note(res, obj.name.clone());
            }
            for (k, item) in obj.on_top.iter().enumerate() {
                for (i, res) in resolved.small.get(&(id, k)).into_iter().flatten().enumerate() {
                    note(res, format!("{}#{i} on {}", item.item, obj.name));
                }
            }
        }
        if let Some(res) = resolved.ceilings.get(&room.id) {
            note(res, format!("ceiling ({})", room.name));
        }
    }
    Value::Array(
        used.into_iter()
            .map(|(uid, objects)| {
                let license = catalog.index_of(&uid).and_then(|i| objathor.license(i));
                let field = |f: fn(&super::objathor::annotations::License) -> &Option<String>| {
                    license.and_then(|l| f(l).clone())
                };
                json!({
                    "assetId": uid,
                    "objects": objects,
                    "license": field(|l| &l.license),
                    "creator": field(|l| &l.creator_display_name).or_else(|| field(|l| &l.creator_username)),
                    "creatorProfileUrl": field(|l| &l.creator_profile_url),
                    "uri": field(|l| &l.uri),
                })
            })
            .collect(),
    )
}
