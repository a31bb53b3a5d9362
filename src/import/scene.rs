//! Whole scenes: holoc transcripts and original Holodeck scene files.

use super::draft::{DObject, DOnTop};
use super::locate::{JsonText, Step};
use super::stages::{no_constraints_in_file, shown_names, unconstrained};
use super::transcript::Transcript;
use super::{import_answer, ImportContext, ImportOptions, Stage};
use crate::ast;
use crate::diag::{Code, Diagnostic, Outcome};
use crate::source::{FileId, SourceMap, Span};
use serde_json::Value;
use std::fmt::Write as _;

/// Imports the answers of one stage (and room) into the context; returns the file the answer
/// was added to `sources` as.
fn feed(
    ctx: &mut ImportContext,
    sources: &mut SourceMap,
    name: String,
    answer: String,
    stage: Stage,
    room: Option<&str>,
    diags: &mut Vec<Diagnostic>,
) -> FileId {
    let file = sources.add(name, answer);
    ctx.set_room(room);
    let out = import_answer(stage, sources, file, ctx);
    diags.extend(out.diagnostics);
    *ctx = out.value.context;
    ctx.set_room(None);
    file
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

/// Writes a room's object-selection record back as JSON text, one object a line, in the order
/// of the solved selection (the scene file's maps are unordered); with the keys in that order.
fn plan_text(
    plan: &serde_json::Map<String, Value>,
    selected: Option<&Value>,
) -> (String, Vec<String>) {
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
    (out, order.into_iter().map(str::to_owned).collect())
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
///
/// Each answer is added to `sources` so that diagnostics point into it; when the JSON is also a
/// file of `sources`, [`import_holodeck_scene_file`] points them at the file's lines instead.
pub fn import_holodeck_scene(
    scene: &Value,
    sources: &mut SourceMap,
    options: &ImportOptions,
) -> Outcome<ast::File> {
    holodeck_scene(scene, sources, None, options)
}

/// [`import_holodeck_scene`] of `scene`, read from `file` of `sources`: every diagnostic points
/// at the line of the file it is about (an object's entry in `object_selection_plan`, a room's
/// entry, the character of a raw answer, the entry of a solved object), not into the answers'
/// copies.
pub fn import_holodeck_scene_file(
    scene: &Value,
    sources: &mut SourceMap,
    file: FileId,
    options: &ImportOptions,
) -> Outcome<ast::File> {
    holodeck_scene(scene, sources, Some(file), options)
}

/// How the spans of one answer's copy map to the scene file.
enum Mapping {
    /// Every span to this span (a number read as an answer).
    Whole(Span),
    /// Offsets through the escapes of the string value whose `"` is at this offset.
    Literal(usize),
    /// The object selection of a room, written one object a line (see [`plan_text`]): a line
    /// to its object's entry, the others to the room's entry.
    Plan { room: Span, objects: Vec<Span> },
}

/// A span in an answer's copy, with the line of the copy it starts on.
struct CopySpan {
    span: Span,
    line_in_copy: usize,
}

impl Mapping {
    fn map(&self, json: &JsonText<'_>, file: FileId, at: CopySpan) -> Span {
        let CopySpan { span, line_in_copy } = at;
        match self {
            Mapping::Whole(to) => *to,
            Mapping::Literal(at) => {
                let start = json.string_offset(*at, span.start as usize);
                let end = json.string_offset(*at, span.end as usize);
                match (start, end) {
                    (Some(start), Some(end)) => Span::new(file, start, end.max(start)),
                    _ => Span::new(file, *at, *at + 1),
                }
            }
            Mapping::Plan { room, objects } => {
                // Line 0 is the `{`; line k the k-th object.
                line_in_copy.checked_sub(1).and_then(|k| objects.get(k)).copied().unwrap_or(*room)
            }
        }
    }
}

fn holodeck_scene(
    scene: &Value,
    sources: &mut SourceMap,
    origin: Option<FileId>,
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
    // The file's text, to point into (`None` without a file).
    let origin_text = origin.and_then(|f| sources.try_get(f)).map(|f| f.text.clone());
    let json = origin_text.as_deref().map(|t| JsonText::new(t));
    let whole_file = |at: Option<super::locate::Found>, key: bool| {
        let file = origin?;
        let (start, end) = if key { at?.key } else { at?.value };
        Some(Span::new(file, start, end))
    };
    let find = |path: &[Step<'_>]| json.as_ref().and_then(|j| j.find(path));
    let mut copies: Vec<(FileId, Mapping)> = Vec::new();
    let request = obj.get("query").and_then(Value::as_str).unwrap_or("").to_string();
    let mut ctx = ImportContext::new().with_request(request, 0);
    let text = |k: &str| obj.get(k).and_then(Value::as_str).map(str::to_string);
    if text("raw_floor_plan").is_none() {
        let mut d = Diagnostic::new(Code::E0709, "the scene file has no `raw_floor_plan`")
            .with_help(
                "only scenes generated by Holodeck carry their raw answers; ProcTHOR houses do not",
            );
        if let Some(file) = origin {
            d = d.with_primary(Span::new(file, 0, 0), "a scene without its raw answers");
        }
        diags.push(d);
    }
    if let Some(h) = num(obj.get("wall_height")) {
        let copy = feed(
            &mut ctx,
            sources,
            "scene:wall_height".into(),
            format!("{h}"),
            Stage::WallHeight,
            None,
            &mut diags,
        );
        if let Some(span) = whole_file(find(&[Step::Key("wall_height")]), false) {
            copies.push((copy, Mapping::Whole(span)));
        }
    }
    let literal = |key: &str| find(&[Step::Key(key)]).map(|f| Mapping::Literal(f.value.0));
    for (key, stage) in [
        ("raw_floor_plan", Stage::FloorPlan),
        ("raw_doorway_plan", Stage::Doorways),
        ("raw_window_plan", Stage::Windows),
    ] {
        if let Some(t) = text(key) {
            let copy = feed(&mut ctx, sources, format!("scene:{key}"), t, stage, None, &mut diags);
            if let Some(mapping) = literal(key) {
                copies.push((copy, mapping));
            }
        }
    }
    let selected = obj.get("selected_objects");
    // Each room's entry in the object selection, by its key, in the file (for W0705).
    let mut room_entries: Vec<(String, Span)> = Vec::new();
    if let Some(plan) = obj.get("object_selection_plan").and_then(Value::as_object) {
        for (room, rec) in plan {
            let Some(rec) = rec.as_object() else { continue };
            let (t, order) = plan_text(rec, selected.and_then(|s| s.get(room)));
            let copy = feed(
                &mut ctx,
                sources,
                format!("scene:object_selection_plan[{room}]"),
                t,
                Stage::Objects,
                Some(room),
                &mut diags,
            );
            let room_path = [Step::Key("object_selection_plan"), Step::Key(room)];
            if let Some(room_span) = whole_file(find(&room_path), true) {
                let objects = order
                    .iter()
                    .map(|key| {
                        let path = [room_path[0], room_path[1], Step::Key(key)];
                        whole_file(find(&path), true).unwrap_or(room_span)
                    })
                    .collect();
                copies.push((copy, Mapping::Plan { room: room_span, objects }));
                room_entries.push((room.clone(), room_span));
            }
        }
    }
    if let Some(t) = text("raw_ceiling_plan") {
        let copy = feed(
            &mut ctx,
            sources,
            "scene:raw_ceiling_plan".into(),
            t,
            Stage::Ceiling,
            None,
            &mut diags,
        );
        if let Some(mapping) = literal("raw_ceiling_plan") {
            copies.push((copy, mapping));
        }
    }
    if options.keep_layout {
        let entry = |key: &str, index: usize, member: &str| {
            let element = [Step::Key(key), Step::Index(index)];
            let named = [element[0], element[1], Step::Key(member)];
            whole_file(find(&named), true).or_else(|| whole_file(find(&element), false))
        };
        keep_layout(obj, &mut ctx, &entry, &mut diags);
    }
    let plan_span = whole_file(find(&[Step::Key("object_selection_plan")]), true);
    no_constraints_in_scene(
        &ctx,
        options.keep_layout,
        plan_span.unwrap_or(Span::new(FileId(0), 0, 0)),
        &room_entries,
        &mut diags,
    );
    if let (Some(json), Some(file)) = (&json, origin) {
        for d in &mut diags {
            point_into_file(d, json, file, sources, &copies);
        }
    }
    crate::diag::sort(&mut diags);
    Outcome::new(ctx.file(), diags)
}

/// Moves the labels of a diagnostic that point into an answer's copy to the scene file; its
/// fixes, edits of the copy, are dropped.
fn point_into_file(
    d: &mut Diagnostic,
    json: &JsonText<'_>,
    file: FileId,
    sources: &SourceMap,
    copies: &[(FileId, Mapping)],
) {
    let move_span = |span: Span| -> Span {
        let Some((_, mapping)) = copies.iter().find(|(f, _)| *f == span.file) else {
            return span;
        };
        let line_in_copy = sources
            .try_get(span.file)
            .map_or(0, |f| f.text[..(span.start as usize).min(f.text.len())].matches('\n').count());
        mapping.map(json, file, CopySpan { span, line_in_copy })
    };
    if let Some(p) = &mut d.primary {
        p.span = move_span(p.span);
    }
    for l in &mut d.secondary {
        l.span = move_span(l.span);
    }
    d.fixes.retain(|f| !copies.iter().any(|(c, _)| *c == f.span.file));
}

/// W0705 for an original scene file, which keeps no floor-constraint answer: one diagnostic
/// for the whole file (the same cause for every floor object), at its `object_selection_plan`,
/// with each room's entry (or, with `keep_layout`, each object left without a pose) labelled
/// and the objects named in notes.
fn no_constraints_in_scene(
    ctx: &ImportContext,
    keep_layout: bool,
    plan_span: Span,
    room_entries: &[(String, Span)],
    diags: &mut Vec<Diagnostic>,
) {
    let mut total = 0usize;
    let mut rooms = 0usize;
    let mut first_label = "";
    let mut secondary: Vec<(Span, String)> = Vec::new();
    let mut notes = Vec::new();
    for r in &ctx.draft.rooms {
        let objects = unconstrained(r);
        let names: Vec<String> = objects.iter().flat_map(|(_, n)| n.iter().cloned()).collect();
        if names.is_empty() {
            continue;
        }
        total += names.len();
        rooms += 1;
        if first_label.is_empty() {
            first_label = &r.label;
        }
        notes.push(format!("in `{}`: {}", r.label, shown_names(&names)));
        if keep_layout {
            for (o, names) in &objects {
                if let Some(span) = o.span {
                    secondary.push((span, format!("{}: no pose", names.join(", "))));
                }
            }
        } else {
            let entry = room_entries
                .iter()
                .find(|(key, _)| ctx.draft.find_room(key).is_some_and(|x| x.id == r.id));
            if let Some((_, span)) = entry {
                let n = names.len();
                secondary
                    .push((*span, format!("{n} floor object{}", if n == 1 { "" } else { "s" })));
            }
        }
    }
    if total == 0 {
        return;
    }
    let objects = if total == 1 { "object" } else { "objects" };
    let (verb, pronoun) = if total == 1 { ("has", "it") } else { ("have", "they") };
    let (of, within) = if rooms == 1 {
        (format!("of `{first_label}`"), format!("in `{first_label}`"))
    } else {
        (format!("of its {rooms} rooms"), format!("in {rooms} rooms"))
    };
    let (message, label, help) = if keep_layout {
        (
            format!(
                "{total} floor {objects} {within} {verb} no solved pose and no constraints; {pronoun} will be placed at an edge"
            ),
            "the original placed every other object selected here",
            "add constraints for them in the `.holo`",
        )
    } else {
        (
            format!(
                "the scene file keeps no floor-constraint answer: the {total} floor {objects} {of} {verb} no constraints; {pronoun} will be placed at an edge"
            ),
            "no constraints for the objects selected here",
            "import with `--keep-layout` to keep the original's positions, or add constraints in the `.holo`",
        )
    };
    let mut d =
        Diagnostic::new(Code::W0705, message).with_primary(plan_span, label).with_help(help);
    for (span, text) in secondary {
        d = d.with_secondary(span, text);
    }
    for note in notes {
        d = d.with_note(note);
    }
    diags.push(d);
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

/// Pins the solved poses of an original scene. `entry(list, index, member)` is where the file
/// holds the member of an element of one of its lists (`None` without a file).
fn keep_layout(
    obj: &serde_json::Map<String, Value>,
    ctx: &mut ImportContext,
    entry: &dyn Fn(&str, usize, &str) -> Option<Span>,
    diags: &mut Vec<Diagnostic>,
) {
    for (key, wall) in [("floor_objects", false), ("wall_objects", true)] {
        for (index, o) in obj.get(key).and_then(Value::as_array).into_iter().flatten().enumerate() {
            let room = o.get("roomId").and_then(Value::as_str).unwrap_or("");
            let name = o.get("object_name").and_then(Value::as_str).unwrap_or("");
            let asset = o.get("assetId").and_then(Value::as_str).map(str::to_string);
            let (Some((x, y, z, r)), Some((group, i))) =
                (pose(o), locate(ctx, room, name, Some(wall)))
            else {
                let mut d = Diagnostic::new(
                    Code::W0706,
                    format!("solved object `{name}` in `{room}` is not in the plan; its pose is not kept"),
                );
                if let Some(span) = entry(key, index, "object_name") {
                    d = d.with_primary(span, "not in the object selection");
                }
                diags.push(d);
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
    for (index, s) in small.into_iter().enumerate() {
        let id = s.get("id").and_then(Value::as_str).unwrap_or("");
        let Some((item, rest)) = id.split_once('|') else { continue };
        let Some((receptacle, room)) = split_id(rest) else { continue };
        let item = group_of(item).to_string();
        let asset = s.get("assetId").and_then(Value::as_str).map(str::to_string);
        let (Some((x, y, z, r)), Some((group, i))) = (pose(s), locate(ctx, room, receptacle, None))
        else {
            let mut d = Diagnostic::new(
                Code::W0706,
                format!("small object `{id}` sits on an object that is not in the plan; left out"),
            );
            if let Some(span) = entry("small_objects", index, "id") {
                d = d.with_primary(span, "its receptacle is not in the plan");
            }
            diags.push(d);
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
