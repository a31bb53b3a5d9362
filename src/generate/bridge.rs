//! The seam between `generate` and `import`: import one answer in the context of the earlier
//! ones, build the whole `.holo` from a transcript, and turn it into a [`Scene`].
//!
//! FIXME(issue 7): until `import::import_answer` and `import::import_transcript` land on main,
//! this file holds a small stand-in reader of the wire formats (strict: one answer line = one
//! statement, no tolerance beyond numbering and case). Only this file changes when they land.

use crate::check::{self, Scene, DEFAULT_WALL_HEIGHT_M};
use crate::diag::Outcome;
use crate::import::transcript::Transcript;
use crate::parse;
use crate::source::SourceMap;
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// What the importer found in one answer.
pub(crate) struct Problems {
    /// Every diagnostic (errors and warnings).
    pub count: usize,
    /// One line per error, for the repair prompt: `line 3: expected 4 fields, found 3 ...`.
    pub errors: Vec<String>,
}

/// The errors of one answer, in the context of the earlier exchanges of `context`.
pub(crate) fn answer_problems(
    stage: &str,
    room: Option<&str>,
    answer: &str,
    context: &Transcript,
) -> Problems {
    let mut transcript = context.clone();
    transcript.exchanges.retain(|e| !(e.stage == stage && e.room.as_deref() == room));
    transcript.exchanges.push(crate::import::Exchange {
        stage: stage.to_string(),
        room: room.map(str::to_string),
        answer: answer.to_string(),
        ..Default::default()
    });
    let mut reader = Reader::new(&transcript);
    reader.run();
    let errors: Vec<String> = reader
        .problems
        .iter()
        .filter(|(s, r, _)| s == stage && r.as_deref() == room)
        .map(|(_, _, p)| p.clone())
        .collect();
    Problems { count: errors.len(), errors }
}

/// The whole `.holo` text of a transcript, canonical, with the diagnostics of reading it.
pub(crate) fn build(transcript: &Transcript, sources: &mut SourceMap) -> Outcome<String> {
    let mut reader = Reader::new(transcript);
    reader.run();
    let text = reader.text();
    let file = sources.add("<generated>.holo", text);
    let parsed = parse::parse(sources, file);
    let mut diagnostics = parsed.diagnostics.clone();
    let canonical = crate::fmt::print(&parsed.value);
    diagnostics.extend(check::check(&parsed.value).diagnostics);
    Outcome::new(canonical, diagnostics)
}

/// The scene of a transcript (possibly partial); used to fill in the next prompts.
pub(crate) fn scene(transcript: &Transcript) -> Scene {
    let mut reader = Reader::new(transcript);
    reader.run();
    let parsed = parse::parse_str(&reader.text());
    check::check(&parsed.value).value
}

// ------------------------------------------------------------------------------------------------
// The stand-in reader.

#[derive(Default)]
struct ObjectPlan {
    key: String,
    name: String,
    wall: bool,
    description: Option<String>,
    size: Option<[f64; 3]>,
    count: u32,
    varied: bool,
    on_top: Vec<(String, u32, bool)>,
    /// Constraints per instance index.
    constraints: BTreeMap<u32, Vec<String>>,
    order: Option<usize>,
}

#[derive(Default)]
struct RoomPlan {
    id: String,
    label: String,
    floor: String,
    walls: String,
    corners: Vec<(f64, f64)>,
    windows: Vec<String>,
    objects: Vec<ObjectPlan>,
    ceiling: Option<String>,
}

struct Reader<'a> {
    transcript: &'a Transcript,
    wall_height: Option<f64>,
    rooms: Vec<RoomPlan>,
    doors: Vec<String>,
    problems: Vec<(String, Option<String>, String)>,
}

fn lines(answer: &str) -> Vec<(usize, Vec<String>)> {
    answer
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains('|'))
        .map(|(i, l)| {
            let mut l = l.trim().to_lowercase();
            let digits = l.chars().take_while(char::is_ascii_digit).count();
            if digits > 0 && matches!(l[digits..].chars().next(), Some('.' | ')')) {
                l = l[digits + 1..].to_string();
            } else if let Some(rest) = l.strip_prefix("- ") {
                l = rest.to_string();
            }
            let l = l.trim().trim_end_matches('.').to_string();
            (i + 1, l.split('|').map(|f| f.trim().replace('*', "")).collect())
        })
        .collect()
}

fn numbers(text: &str) -> Vec<f64> {
    let mut out = Vec::new();
    let mut current = String::new();
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit() || c == '.' || (c == '-' && current.is_empty()) {
            current.push(c);
        } else {
            if let Ok(v) = current.parse::<f64>() {
                if v.is_finite() {
                    out.push(v);
                }
            }
            current.clear();
        }
    }
    out
}

/// A `.holo` identifier from a label.
fn ident(label: &str) -> String {
    let mut id = String::new();
    for c in label.to_lowercase().chars() {
        if c.is_ascii_alphanumeric() {
            id.push(c);
        } else if !id.ends_with('_') {
            id.push('_');
        }
    }
    let id = id.trim_matches('_').to_string();
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        format!("r_{id}")
    } else {
        id
    }
}

fn quote(text: &str) -> String {
    format!("\"{}\"", parse::escape(text))
}

impl<'a> Reader<'a> {
    fn new(transcript: &'a Transcript) -> Reader<'a> {
        Reader {
            transcript,
            wall_height: None,
            rooms: Vec::new(),
            doors: Vec::new(),
            problems: Vec::new(),
        }
    }

    fn problem(&mut self, stage: &str, room: Option<&str>, line: usize, message: String) {
        self.problems.push((
            stage.to_string(),
            room.map(str::to_string),
            format!("line {line}: {message}"),
        ));
    }

    fn answer(&self, stage: &str, room: Option<&str>) -> Option<String> {
        self.transcript.latest(stage, room).map(|e| e.answer.clone())
    }

    fn room_id(&self, label: &str) -> Option<String> {
        if label == "exterior" {
            return Some("exterior".to_string());
        }
        self.rooms.iter().find(|r| r.label == label).map(|r| r.id.clone())
    }

    fn run(&mut self) {
        if let Some(answer) = self.answer("floor-plan", None) {
            self.floor_plan(&answer);
        }
        if let Some(answer) = self.answer("wall-height", None) {
            match answer.lines().next().map(numbers).and_then(|n| n.first().copied()) {
                Some(h) => self.wall_height = Some(h.clamp(2.0, 4.5)),
                None => self.problem(
                    "wall-height",
                    None,
                    1,
                    "expected a number of metres such as `2.8`".into(),
                ),
            }
        }
        if let Some(answer) = self.answer("doorways", None) {
            self.doorways(&answer);
        }
        if let Some(answer) = self.answer("windows", None) {
            self.windows(&answer);
        }
        let labels: Vec<String> = self.rooms.iter().map(|r| r.label.clone()).collect();
        for (index, label) in labels.iter().enumerate() {
            if let Some(answer) = self.answer("objects", Some(label)) {
                self.objects(index, label, &answer);
            }
            if let Some(answer) = self.answer("floor-constraints", Some(label)) {
                self.constraints(index, label, &answer, false);
            }
            if let Some(answer) = self.answer("wall-constraints", Some(label)) {
                self.constraints(index, label, &answer, true);
            }
            if let Some(answer) = self.answer("small-objects", Some(label)) {
                self.small_objects(index, label, &answer);
            }
        }
        if let Some(answer) = self.answer("ceiling", None) {
            for (line, fields) in lines(&answer) {
                let index = self.rooms.iter().position(|r| r.label == fields[0]);
                match (index, fields.len()) {
                    (Some(i), 2) => self.rooms[i].ceiling = Some(fields[1].clone()),
                    _ => self.problem(
                        "ceiling",
                        None,
                        line,
                        "expected `room | description` with a room of the plan".into(),
                    ),
                }
            }
        }
    }

    fn floor_plan(&mut self, answer: &str) {
        for (line, fields) in lines(answer) {
            if fields.len() != 4 {
                self.problem(
                    "floor-plan",
                    None,
                    line,
                    format!("expected 4 fields `room | floor design | wall design | [(x, y), ...]`, found {}", fields.len()),
                );
                continue;
            }
            let n = numbers(&fields[3]);
            if n.len() < 8 || n.len() % 2 != 0 {
                self.problem(
                    "floor-plan",
                    None,
                    line,
                    "expected a list of at least four (x, y) corners in metres".into(),
                );
                continue;
            }
            let label = fields[0].replace('\'', "");
            let mut id = ident(&label);
            let mut k = 2;
            while self.rooms.iter().any(|r| r.id == id) {
                id = format!("{}_{k}", ident(&label));
                k += 1;
            }
            self.rooms.push(RoomPlan {
                id,
                label,
                floor: fields[1].clone(),
                walls: fields[2].clone(),
                corners: n.chunks(2).map(|c| (c[0], c[1])).collect(),
                ..RoomPlan::default()
            });
        }
        if self.rooms.is_empty() {
            self.problem(
                "floor-plan",
                None,
                1,
                "no room line `room | floor design | wall design | [(x, y), ...]` found".into(),
            );
        }
    }

    fn doorways(&mut self, answer: &str) {
        for (line, f) in lines(answer) {
            if f.len() != 5 {
                self.problem(
                    "doorways",
                    None,
                    line,
                    format!(
                        "expected 5 fields `room 1 | room 2 | type | size | style`, found {}",
                        f.len()
                    ),
                );
                continue;
            }
            let (Some(a), Some(b)) = (self.room_id(&f[0]), self.room_id(&f[1])) else {
                self.problem(
                    "doorways",
                    None,
                    line,
                    format!("`{}` or `{}` is not a room of the plan", f[0], f[1]),
                );
                continue;
            };
            let kind = if a == "exterior" || b == "exterior" { "doorway" } else { f[2].as_str() };
            let text = match kind {
                "open" => format!("door {a} -- {b} : open"),
                "doorway" | "doorframe" => {
                    let size = if f[3] == "double" { "double" } else { "single" };
                    let style =
                        if f[4] == "n/a" { String::new() } else { format!(" {}", quote(&f[4])) };
                    format!("door {a} -- {b} : {kind} {size}{style}")
                }
                other => {
                    self.problem(
                        "doorways",
                        None,
                        line,
                        format!("unknown connection type `{other}`"),
                    );
                    continue;
                }
            };
            self.doors.push(text);
        }
    }

    fn windows(&mut self, answer: &str) {
        for (line, f) in lines(answer) {
            let index = self.rooms.iter().position(|r| r.label == f[0]);
            let size = f.get(3).map(|s| numbers(s)).unwrap_or_default();
            match (index, f.len(), size.as_slice()) {
                (Some(i), 6, [w, h]) => {
                    let count = numbers(&f[4]).first().copied().unwrap_or(1.0).max(1.0) as u32;
                    let sill = numbers(&f[5]).first().copied().unwrap_or(90.0);
                    let text = format!(
                        "window {} {} {w} cm x {h} cm, count {count}, sill {sill} cm",
                        f[1], f[2]
                    );
                    self.rooms[i].windows.push(text);
                }
                _ => self.problem("windows", None, line, "expected `room | side | type | (w, h) | count | base height` with a room of the plan".into()),
            }
        }
    }

    fn objects(&mut self, index: usize, label: &str, answer: &str) {
        let lower = answer.to_lowercase();
        let json = match (lower.find('{'), lower.rfind('}')) {
            (Some(a), Some(b)) if b > a => serde_json::from_str::<Value>(&lower[a..=b]).ok(),
            _ => None,
        };
        let Some(Value::Object(map)) = json else {
            self.problem(
                "objects",
                Some(label),
                1,
                "expected one JSON object keyed by object name".into(),
            );
            return;
        };
        for (name, record) in &map {
            let key = ident(&name.replace(' ', "_"));
            let get = |f: &str| record.get(f);
            let size = get("size").and_then(Value::as_array).and_then(|a| {
                let v: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
                (v.len() == 3 && v.iter().all(|x| *x > 0.0)).then(|| [v[0], v[1], v[2]])
            });
            let on_top = get("objects_on_top")
                .and_then(Value::as_array)
                .map(|a| {
                    a.iter()
                        .filter_map(|c| {
                            let name = c.get("object_name")?.as_str()?.to_string();
                            let n =
                                c.get("quantity").and_then(Value::as_u64).unwrap_or(1).clamp(1, 20)
                                    as u32;
                            let varied =
                                c.get("variance_type").and_then(Value::as_str) == Some("varied");
                            Some((name, n, varied))
                        })
                        .collect()
                })
                .unwrap_or_default();
            self.rooms[index].objects.push(ObjectPlan {
                key,
                name: name.clone(),
                wall: get("location").and_then(Value::as_str) == Some("wall"),
                description: get("description").and_then(Value::as_str).map(str::to_string),
                size,
                count: get("quantity").and_then(Value::as_u64).unwrap_or(1).clamp(1, 10) as u32,
                varied: get("variance_type").and_then(Value::as_str) == Some("varied"),
                on_top,
                ..ObjectPlan::default()
            });
        }
    }

    fn find(&self, index: usize, instance: &str) -> Option<(usize, u32)> {
        let (group, n) = instance.rsplit_once('-')?;
        let n: u32 = n.parse().ok()?;
        let o = self.rooms[index].objects.iter().position(|o| o.key == group && n < o.count)?;
        Some((o, n))
    }

    fn constraints(&mut self, index: usize, label: &str, answer: &str, wall: bool) {
        let stage = if wall { "wall-constraints" } else { "floor-constraints" };
        let mut order = 0;
        for (line, f) in lines(answer) {
            let Some((o, n)) =
                self.find(index, &f[0]).filter(|(o, _)| self.rooms[index].objects[*o].wall == wall)
            else {
                self.problem(
                    stage,
                    Some(label),
                    line,
                    format!("`{}` is not an object of the room", f[0]),
                );
                continue;
            };
            let mut list = Vec::new();
            if wall {
                if let Some(target) = f.get(1).and_then(|t| t.strip_prefix("above,")).map(str::trim)
                {
                    if self.find(index, target).is_some() {
                        list.push(format!("above {target}"));
                    }
                }
                if let Some(h) = f.get(2).map(|h| numbers(h)).and_then(|v| v.first().copied()) {
                    list.push(format!("height {h} cm"));
                }
            } else {
                for field in &f[1..] {
                    let (name, target) = match field.split_once(',') {
                        Some((a, b)) => (a.trim(), Some(b.trim())),
                        None => (field.trim(), None),
                    };
                    match (name, target) {
                        ("n/a", _) => {}
                        ("edge" | "middle", _) => list.push(name.to_string()),
                        (_, Some(t))
                            if self
                                .find(index, t)
                                .and_then(|(to, _)| self.rooms[index].objects[to].order)
                                .is_some()
                                || self.find(index, t) == Some((o, n)) =>
                        {
                            if self.find(index, t) != Some((o, n)) {
                                list.push(format!("{name} {t}"));
                            }
                        }
                        _ => {
                            self.problem(stage, Some(label), line, format!("cannot use `{field}`"))
                        }
                    }
                }
            }
            let object = &mut self.rooms[index].objects[o];
            if object.order.is_none() {
                object.order = Some(order);
                order += 1;
            }
            object.constraints.insert(n, list);
        }
        if !wall {
            // Objects in the order of the answer; the others after.
            self.rooms[index].objects.sort_by_key(|o| (o.wall, o.order.unwrap_or(usize::MAX)));
        }
    }

    fn small_objects(&mut self, index: usize, label: &str, answer: &str) {
        for (line, f) in lines(answer) {
            let receptacle = f[0].split('(').next().unwrap_or("").trim().to_string();
            let Some((o, _)) = self.find(index, &receptacle) else {
                self.problem(
                    "small-objects",
                    Some(label),
                    line,
                    format!("`{receptacle}` is not an object of the room"),
                );
                continue;
            };
            for item in &f[1..] {
                let parts: Vec<&str> = item.split(',').map(str::trim).collect();
                if parts.len() == 3 {
                    let n =
                        numbers(parts[1]).first().copied().unwrap_or(1.0).clamp(1.0, 20.0) as u32;
                    self.rooms[index].objects[o].on_top.push((
                        parts[0].to_string(),
                        n,
                        parts[2] == "varied",
                    ));
                } else {
                    self.problem(
                        "small-objects",
                        Some(label),
                        line,
                        format!("expected `item, number, same|varied`, found `{item}`"),
                    );
                }
            }
        }
    }

    fn text(&self) -> String {
        let mut out = String::new();
        let request = quote(&self.transcript.request);
        let height = self.wall_height.unwrap_or(DEFAULT_WALL_HEIGHT_M);
        let _ = writeln!(
            out,
            "scene {request} {{\n  wall height {height} m\n  seed {}\n}}\n",
            self.transcript.seed
        );
        for r in &self.rooms {
            let _ = writeln!(out, "room {} {} {{", r.id, quote(&r.label));
            let _ = writeln!(out, "  floor {}\n  walls {}", quote(&r.floor), quote(&r.walls));
            let corners: Vec<String> =
                r.corners.iter().map(|(x, z)| format!("({x}, {z})")).collect();
            let _ = writeln!(out, "  corners in m {}", corners.join(" "));
            for w in &r.windows {
                let _ = writeln!(out, "  {w}");
            }
            for o in &r.objects {
                let kw = if o.wall { "wall object" } else { "object" };
                let _ = writeln!(out, "  {kw} {} {} {{", o.key, quote(&o.name));
                if let Some(d) = &o.description {
                    let _ = writeln!(out, "    describe {}", quote(d));
                }
                if let Some([l, w, h]) = o.size {
                    let _ = writeln!(out, "    size {l} cm x {w} cm x {h} cm");
                }
                if o.count > 1 {
                    let _ = writeln!(
                        out,
                        "    count {} {}",
                        o.count,
                        if o.varied { "varied" } else { "same" }
                    );
                }
                for (item, n, varied) in &o.on_top {
                    let _ = writeln!(
                        out,
                        "    on top {} x{n} {}",
                        quote(item),
                        if *varied { "varied" } else { "same" }
                    );
                }
                for (n, list) in &o.constraints {
                    if o.count == 1 {
                        for c in list {
                            let _ = writeln!(out, "    {c}");
                        }
                    } else {
                        let _ = writeln!(out, "    instance {}-{n} {{", o.key);
                        for c in list {
                            let _ = writeln!(out, "      {c}");
                        }
                        let _ = writeln!(out, "    }}");
                    }
                }
                let _ = writeln!(out, "  }}");
            }
            if let Some(c) = &r.ceiling {
                let _ = writeln!(out, "  ceiling {}", quote(c));
            }
            let _ = writeln!(out, "}}\n");
        }
        for d in &self.doors {
            let _ = writeln!(out, "{d}");
        }
        out
    }
}
