//! Whole scenes: holoc transcripts and original Holodeck scene files.

use super::draft::{DObject, DOnTop};
use super::stages::no_constraints_in_file;
use super::transcript::Transcript;
use super::{import_answer, ImportContext, ImportOptions, Stage};
use crate::ast;
use crate::diag::{Code, Diagnostic, Outcome};
use crate::source::{FileId, SourceMap, Span};
use serde_json::Value;
use std::fmt::Write as _;

/// Imports the answers of one stage (and room) into the context.
fn feed(
    ctx: &mut ImportContext,
    sources: &mut SourceMap,
    name: String,
    answer: String,
    stage: Stage,
    room: Option<&str>,
    diags: &mut Vec<Diagnostic>,
) {
    let file = sources.add(name, answer);
    ctx.set_room(room);
    let out = import_answer(stage, sources, file, ctx);
    diags.extend(out.diagnostics);
    *ctx = out.value.context;
    ctx.set_room(None);
}

/// Rebuilds a scene from a holoc transcript: for every stage (in generation order) and room,
/// the exchange with the highest `attempt` is imported. Each answer is added to `sources` so
/// that diagnostics point into it.
pub fn import_transcript(
    transcript: &Transcript,
    sources: &mut SourceMap,
    _options: &ImportOptions,
) -> Outcome<ast::File> {
    let mut diags = Vec::new();
    let mut ctx = ImportContext::new().with_request(transcript.request.clone(), transcript.seed);
    for ex in &transcript.exchanges {
        if Stage::parse(&ex.stage).is_none() {
            diags.push(
                Diagnostic::new(Code::W0706, format!("transcript stage `{}` is not an import stage; ignored", ex.stage))
                    .with_note("stages: floor-plan, wall-height, doorways, windows, objects, objects-pipe, floor-constraints, wall-constraints, small-objects, ceiling, absolute-layout"),
            );
        }
    }
    let mut constrained: Vec<String> = Vec::new();
    for &stage in Stage::ALL {
        let mut rooms: Vec<Option<&str>> = Vec::new();
        for ex in transcript.exchanges.iter().filter(|e| Stage::parse(&e.stage) == Some(stage)) {
            if !rooms.contains(&ex.room.as_deref()) {
                rooms.push(ex.room.as_deref());
            }
        }
        for room in rooms {
            let Some(ex) = transcript
                .exchanges
                .iter()
                .filter(|e| Stage::parse(&e.stage) == Some(stage) && e.room.as_deref() == room)
                .fold(None::<&super::Exchange>, |best, e| match best {
                    Some(b) if b.attempt > e.attempt => Some(b),
                    _ => Some(e),
                })
            else {
                continue;
            };
            let name = match room {
                Some(r) => format!("{}[{r}]#{}", stage.as_str(), ex.attempt),
                None => format!("{}#{}", stage.as_str(), ex.attempt),
            };
            if stage == Stage::FloorConstraints {
                if let Some(r) = room {
                    constrained.push(r.to_string());
                }
            }
            feed(&mut ctx, sources, name, ex.answer.clone(), stage, room, &mut diags);
        }
    }
    let span = Span::new(FileId(0), 0, 0);
    let unconstrained: Vec<String> = ctx
        .draft
        .rooms
        .iter()
        .filter(|r| {
            !constrained.iter().any(|c| ctx.draft.find_room(c).is_some_and(|x| x.id == r.id))
        })
        .map(|r| r.id.clone())
        .collect();
    for r in unconstrained {
        no_constraints_in_file(&ctx, &r, span, &mut diags);
    }
    crate::diag::sort(&mut diags);
    Outcome::new(ctx.file(), diags)
}

/// The group key of an instance name: the text before its last `-<n>`.
fn group_of(instance: &str) -> &str {
    match instance.rsplit_once('-') {
        Some((g, n)) if n.chars().all(|c| c.is_ascii_digit()) && !n.is_empty() => g,
        _ => instance,
    }
}

/// Writes a room's object-selection record back as JSON text, in the order of the solved
/// selection (the scene file's maps are unordered).
fn plan_text(plan: &serde_json::Map<String, Value>, selected: Option<&Value>) -> String {
    let mut order: Vec<&str> = Vec::new();
    for kind in ["floor", "wall"] {
        let list = selected.and_then(|s| s.get(kind)).and_then(Value::as_array);
        for pair in list.into_iter().flatten() {
            if let Some(name) = pair.get(0).and_then(Value::as_str) {
                let g = group_of(name);
                if let Some((k, _)) = plan
                    .iter()
                    .find(|(k, _)| k.as_str() == g || k.replace(' ', "_") == g.replace(' ', "_"))
                {
                    if !order.contains(&k.as_str()) {
                        order.push(k.as_str());
                    }
                }
            }
        }
    }
    for k in plan.keys() {
        if !order.contains(&k.as_str()) {
            order.push(k.as_str());
        }
    }
    let mut out = String::from("{\n");
    for (i, k) in order.iter().enumerate() {
        let v = plan.get(*k).cloned().unwrap_or(Value::Null);
        let key = serde_json::to_string(k).unwrap_or_else(|_| "\"?\"".into());
        let comma = if i + 1 < order.len() { "," } else { "" };
        let _ = writeln!(out, "  {key}: {v}{comma}");
    }
    out.push('}');
    out
}

fn num(v: Option<&Value>) -> Option<f64> {
    v.and_then(Value::as_f64).filter(|x| x.is_finite())
}

fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// Rebuilds a scene from an original Holodeck scene JSON: the cached raw answers
/// (`raw_floor_plan`, `wall_height`, `raw_doorway_plan`, `raw_window_plan`,
/// `object_selection_plan`, `raw_ceiling_plan`) and, with `keep_layout`, the solved poses.
pub fn import_holodeck_scene(
    scene: &Value,
    sources: &mut SourceMap,
    options: &ImportOptions,
) -> Outcome<ast::File> {
    let mut diags = Vec::new();
    let Some(obj) = scene.as_object() else {
        diags.push(
            Diagnostic::new(Code::E0709, "the scene file is not a JSON object")
                .with_help("pass a Holodeck scene JSON"),
        );
        return Outcome::new(ImportContext::new().file(), diags);
    };
    let request = obj.get("query").and_then(Value::as_str).unwrap_or("").to_string();
    let mut ctx = ImportContext::new().with_request(request, 0);
    let text = |k: &str| obj.get(k).and_then(Value::as_str).map(str::to_string);
    if text("raw_floor_plan").is_none() {
        diags.push(
            Diagnostic::new(Code::E0709, "the scene file has no `raw_floor_plan`").with_help(
                "only scenes generated by Holodeck carry their raw answers; ProcTHOR houses do not",
            ),
        );
    }
    if let Some(h) = num(obj.get("wall_height")) {
        feed(
            &mut ctx,
            sources,
            "scene:wall_height".into(),
            format!("{h}"),
            Stage::WallHeight,
            None,
            &mut diags,
        );
    }
    for (key, stage) in [
        ("raw_floor_plan", Stage::FloorPlan),
        ("raw_doorway_plan", Stage::Doorways),
        ("raw_window_plan", Stage::Windows),
    ] {
        if let Some(t) = text(key) {
            feed(&mut ctx, sources, format!("scene:{key}"), t, stage, None, &mut diags);
        }
    }
    let selected = obj.get("selected_objects");
    if let Some(plan) = obj.get("object_selection_plan").and_then(Value::as_object) {
        for (room, rec) in plan {
            let Some(rec) = rec.as_object() else { continue };
            let t = plan_text(rec, selected.and_then(|s| s.get(room)));
            feed(
                &mut ctx,
                sources,
                format!("scene:object_selection_plan[{room}]"),
                t,
                Stage::Objects,
                Some(room),
                &mut diags,
            );
        }
    }
    if let Some(t) = text("raw_ceiling_plan") {
        feed(
            &mut ctx,
            sources,
            "scene:raw_ceiling_plan".into(),
            t,
            Stage::Ceiling,
            None,
            &mut diags,
        );
    }
    if options.keep_layout {
        keep_layout(obj, &mut ctx, &mut diags);
    }
    let span = Span::new(FileId(0), 0, 0);
    let ids: Vec<String> = ctx.draft.rooms.iter().map(|r| r.id.clone()).collect();
    for r in ids {
        no_constraints_in_file(&ctx, &r, span, &mut diags);
    }
    crate::diag::sort(&mut diags);
    Outcome::new(ctx.file(), diags)
}

/// `sofa-0 (living room)` → (`sofa-0`, `living room`).
fn split_id(id: &str) -> Option<(&str, &str)> {
    let a = id.rfind(" (")?;
    let inner = id[a + 2..].strip_suffix(')')?;
    Some((&id[..a], inner))
}

fn locate<'a>(
    ctx: &'a mut ImportContext,
    room: &str,
    instance: &str,
    wall: Option<bool>,
) -> Option<(&'a mut DObject, usize)> {
    let rid = ctx.draft.find_room(room)?.id.clone();
    let r = ctx.draft.room_mut(&rid)?;
    let key = super::draft::loose(instance);
    for o in &mut r.objects {
        if wall.is_some_and(|w| o.wall != w) {
            continue;
        }
        for (i, name) in o.instance_names().iter().enumerate() {
            if super::draft::loose(name) == key {
                o.fit();
                return Some((o, i));
            }
        }
    }
    None
}

fn pose(v: &Value) -> Option<(f64, f64, f64, f64)> {
    let p = v.get("position")?;
    let (x, y, z) = (num(p.get("x"))?, num(p.get("y"))?, num(p.get("z"))?);
    let r = num(v.get("rotation").and_then(|r| r.get("y"))).unwrap_or(0.0);
    Some((round3(x), round3(y), round3(z), round3(r.rem_euclid(360.0))))
}

fn keep_layout(
    obj: &serde_json::Map<String, Value>,
    ctx: &mut ImportContext,
    diags: &mut Vec<Diagnostic>,
) {
    for (key, wall) in [("floor_objects", false), ("wall_objects", true)] {
        for o in obj.get(key).and_then(Value::as_array).into_iter().flatten() {
            let room = o.get("roomId").and_then(Value::as_str).unwrap_or("");
            let name = o.get("object_name").and_then(Value::as_str).unwrap_or("");
            let asset = o.get("assetId").and_then(Value::as_str).map(str::to_string);
            let (Some((x, y, z, r)), Some((group, i))) =
                (pose(o), locate(ctx, room, name, Some(wall)))
            else {
                diags.push(Diagnostic::new(Code::W0706, format!("solved object `{name}` in `{room}` is not in the plan; its pose is not kept")));
                continue;
            };
            let size_h = group.size.map(|s| s[2]);
            let inst = &mut group.instances[i];
            inst.asset = asset;
            inst.at = Some(vec![x, z]);
            inst.facing = Some(r);
            if wall {
                // The record holds the centre; the bottom is half the planned height lower.
                let bottom = size_h.map_or(y * 100.0, |h| (y * 100.0 - h / 2.0).max(0.0));
                inst.height_cm = Some((bottom * 10.0).round() / 10.0);
            }
        }
    }
    let small: Vec<&Value> =
        obj.get("small_objects").and_then(Value::as_array).into_iter().flatten().collect();
    if small.is_empty() {
        return;
    }
    // The placed small objects replace the planned ones.
    for r in &mut ctx.draft.rooms {
        for o in &mut r.objects {
            for t in std::mem::take(&mut o.on_top) {
                let v = t.variance.clone().unwrap_or_else(|| "same".into());
                o.comments.push(format!(
                    "// planned: on top \"{}\" x{} {v} (replaced by the placed objects)",
                    t.item.replace('"', "'"),
                    t.count
                ));
            }
        }
    }
    for s in small {
        let id = s.get("id").and_then(Value::as_str).unwrap_or("");
        let Some((item, rest)) = id.split_once('|') else { continue };
        let Some((receptacle, room)) = split_id(rest) else { continue };
        let item = group_of(item).to_string();
        let asset = s.get("assetId").and_then(Value::as_str).map(str::to_string);
        let (Some((x, y, z, r)), Some((group, i))) = (pose(s), locate(ctx, room, receptacle, None))
        else {
            diags.push(Diagnostic::new(
                Code::W0706,
                format!("small object `{id}` sits on an object that is not in the plan; left out"),
            ));
            continue;
        };
        group.instances[i].on_top.push(DOnTop {
            item,
            count: 1,
            variance: None,
            asset,
            at: Some(vec![x, y, z]),
            facing: Some(r),
        });
    }
}
