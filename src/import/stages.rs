//! The readers of every stage's answer.

#![allow(
    clippy::single_match_else,
    reason = "a match with a `None` arm that reports and skips reads better than `if let … else`"
)]

use super::draft::{loose, object_id, DDoor, DInstance, DObject, DOnTop, DWindow};
use super::front::{self, norm, Field, Line, Num};
use super::{noise_diagnostics, ImportContext, Stage};
use crate::diag::suggest::{closest, did_you_mean};
use crate::diag::{Code, Diagnostic};
use crate::source::{FileId, Span};

type Diags = Vec<Diagnostic>;

/// Runs the reader of `stage` on `text`, updating the context.
pub(crate) fn run(stage: Stage, text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let whole = Span::new(file, 0, text.len());
    // A byte-order mark at the start is skipped: it becomes three spaces, so that every span
    // still points at the same bytes of the answer.
    let unmarked;
    let text = match text.strip_prefix('\u{FEFF}') {
        Some(rest) => {
            unmarked = format!("   {rest}");
            unmarked.as_str()
        }
        None => text,
    };
    if text.trim().is_empty() {
        d.push(
            Diagnostic::new(Code::E0708, format!("the {stage} answer is empty"))
                .with_primary(whole, "nothing here")
                .with_help("ask the model again"),
        );
        return;
    }
    if matches!(stage, Stage::Windows | Stage::SmallObjects | Stage::Ceiling) && says_none(text) {
        let what = match stage {
            Stage::Windows => "windows",
            Stage::SmallObjects => "small objects",
            _ => "ceiling objects",
        };
        d.push(
            Diagnostic::new(
                Code::W0706,
                format!("the {stage} answer says there are none: the scene gets no {what} from it"),
            )
            .with_primary(Span::new(file, 0, prefix_end(text, 200)), "read as “none”")
            .with_note(format!("an answer without any `|`-separated line that says “none” or “no {what}” means none")),
        );
        return;
    }
    match stage {
        Stage::WallHeight => wall_height(text, file, ctx, d),
        Stage::FloorPlan => floor_plan(text, file, ctx, d),
        Stage::Doorways => doorways(text, file, ctx, d),
        Stage::Windows => windows(text, file, ctx, d),
        Stage::Objects => objects_json(text, file, ctx, d),
        Stage::ObjectsPipe => objects_pipe(text, file, ctx, d),
        Stage::FloorConstraints => floor_constraints(text, file, ctx, d),
        Stage::WallConstraints => wall_constraints(text, file, ctx, d),
        Stage::SmallObjects => small_objects(text, file, ctx, d),
        Stage::Ceiling => ceiling(text, file, ctx, d),
        Stage::AbsoluteLayout => absolute_layout(text, file, ctx, d),
    }
}

// ---------------------------------------------------------------------------------------------
// Vocabularies and synonym tables (documented in book/src/reference/import.md).

/// Layout constraint names.
pub(crate) const CONSTRAINTS: &[&str] = &[
    "edge",
    "middle",
    "near",
    "far",
    "in front of",
    "behind",
    "side of",
    "left of",
    "right of",
    "around",
    "center aligned",
    "face to",
    "face same as",
];

/// Near-miss constraint names and what they mean. `beside` is `near`, never `behind`;
/// `next to` is `near`, never `face to`.
pub(crate) const CONSTRAINT_SYNONYMS: &[(&str, &str)] = &[
    ("next to", "near"),
    ("beside", "near"),
    ("close to", "near"),
    ("near to", "near"),
    ("nearby", "near"),
    ("adjacent to", "near"),
    ("far from", "far"),
    ("away from", "far"),
    ("facing", "face to"),
    ("faces", "face to"),
    ("face", "face to"),
    ("face towards", "face to"),
    ("face toward", "face to"),
    ("facing to", "face to"),
    ("facing towards", "face to"),
    ("in front", "in front of"),
    ("front of", "in front of"),
    ("in the front of", "in front of"),
    ("center alignment", "center aligned"),
    ("centre alignment", "center aligned"),
    ("centre aligned", "center aligned"),
    ("center-aligned", "center aligned"),
    ("center align", "center aligned"),
    ("aligned center", "center aligned"),
    ("aligned", "center aligned"),
    ("alignment", "center aligned"),
    ("aligned with", "center aligned"),
    ("align", "center aligned"),
    ("at the edge", "edge"),
    ("against the wall", "edge"),
    ("against wall", "edge"),
    ("along the wall", "edge"),
    ("center", "middle"),
    ("centre", "middle"),
    ("in the middle", "middle"),
    ("in the center", "middle"),
    ("surround", "around"),
    ("surrounding", "around"),
    ("left", "left of"),
    ("to the left of", "left of"),
    ("right", "right of"),
    ("to the right of", "right of"),
    ("to the side of", "side of"),
    ("on the side of", "side of"),
    ("in back of", "behind"),
    ("back of", "behind"),
    ("face same direction as", "face same as"),
    ("same direction as", "face same as"),
    ("facing same as", "face same as"),
];

const DOOR_KINDS: &[&str] = &["doorway", "doorframe", "open"];
const DOOR_SYNONYMS: &[(&str, &str)] = &[
    ("door", "doorway"),
    ("door way", "doorway"),
    ("door frame", "doorframe"),
    ("frame", "doorframe"),
    ("arch", "doorframe"),
    ("archway", "doorframe"),
    ("open connection", "open"),
    ("opening", "open"),
    ("no door", "open"),
];
const DOOR_SIZES: &[&str] = &["single", "double"];
const DOOR_SIZE_SYNONYMS: &[(&str, &str)] =
    &[("single door", "single"), ("double door", "double"), ("double-wide", "double")];
const WINDOW_TYPES: &[&str] = &["fixed", "hung", "slider"];
const WINDOW_SYNONYMS: &[(&str, &str)] = &[
    ("fixed window", "fixed"),
    ("hung window", "hung"),
    ("slider window", "slider"),
    ("double hung", "hung"),
    ("double-hung", "hung"),
    ("single hung", "hung"),
    ("single-hung", "hung"),
    ("sliding", "slider"),
    ("sliding window", "slider"),
];
const DIRECTIONS: &[&str] = &["north", "south", "east", "west"];
const DIRECTION_SYNONYMS: &[(&str, &str)] = &[
    ("n", "north"),
    ("s", "south"),
    ("e", "east"),
    ("w", "west"),
    ("north wall", "north"),
    ("south wall", "south"),
    ("east wall", "east"),
    ("west wall", "west"),
];
const VARIANCES: &[&str] = &["same", "varied"];
const VARIANCE_SYNONYMS: &[(&str, &str)] =
    &[("identical", "same"), ("different", "varied"), ("various", "varied"), ("vary", "varied")];
const LOCATIONS: &[&str] = &["floor", "wall"];
const LOCATION_SYNONYMS: &[(&str, &str)] = &[
    ("ground", "floor"),
    ("on the floor", "floor"),
    ("on the wall", "wall"),
    ("wall-mounted", "wall"),
];

enum Found {
    Exact(&'static str),
    Synonym(&'static str),
    Unknown(Vec<String>),
}

fn lookup(word: &str, vocab: &[&'static str], synonyms: &[(&'static str, &'static str)]) -> Found {
    let w = norm(word);
    if let Some(v) = vocab.iter().find(|v| **v == w) {
        return Found::Exact(v);
    }
    if let Some((_, v)) = synonyms.iter().find(|(s, _)| *s == w) {
        return Found::Synonym(v);
    }
    Found::Unknown(closest(&w, vocab.iter().copied()))
}

/// Looks a word up, reporting synonyms (W0702) and unknown words (E0705).
fn word(
    field: &Field,
    what: &str,
    vocab: &[&'static str],
    synonyms: &[(&'static str, &'static str)],
    d: &mut Diags,
) -> Option<&'static str> {
    match lookup(&field.text, vocab, synonyms) {
        Found::Exact(v) => Some(v),
        Found::Synonym(v) => {
            d.push(
                Diagnostic::new(Code::W0702, format!("read {what} `{}` as `{v}`", field.text))
                    .with_primary(field.span, format!("synonym of `{v}`")),
            );
            Some(v)
        }
        Found::Unknown(s) => {
            let expected = vocab.join("`, `");
            d.push(
                Diagnostic::new(Code::E0705, format!("unknown {what} `{}`", field.text))
                    .with_primary(field.span, format!("expected one of `{expected}`"))
                    .with_help_opt(did_you_mean(&s)),
            );
            None
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Shared helpers.

fn bad_line(line: &Line, message: String, expected: &str, d: &mut Diags) {
    d.push(
        Diagnostic::new(Code::E0701, message)
            .with_primary(line.span(), "this line is left out")
            .with_help(format!("expected `{expected}`")),
    );
}

fn bad_value(span: Span, message: String, label: &str, help: &str, d: &mut Diags) {
    d.push(
        Diagnostic::new(Code::E0702, message).with_primary(span, label.to_string()).with_help(help),
    );
}

/// Reports units and decimal commas that were converted.
fn converted(n: &Num, span: Span, to: &str, d: &mut Diags) {
    if n.comma || n.unit.is_some_and(|u| u != to) {
        let what = if n.comma { "decimal comma" } else { "unit" };
        d.push(
            Diagnostic::new(
                Code::W0703,
                format!("converted a value written with a {what} to {to}"),
            )
            .with_primary(span, "converted"),
        );
    }
}

/// A length in cm from a number written in cm (default), m or mm.
fn to_cm(n: &Num) -> f64 {
    match n.unit {
        Some("m") => n.value * 100.0,
        Some("mm") => n.value / 10.0,
        _ => n.value,
    }
}

/// The most list lines (or JSON entries) read from one answer.
const MAX_LINES: usize = 300;

fn start_lines(text: &str, file: FileId, d: &mut Diags, stage: Stage) -> Vec<Line> {
    let mut l = front::lines(text, file, true);
    noise_diagnostics(&l.noise, d);
    if l.lines.len() > MAX_LINES {
        let first = &l.lines[MAX_LINES];
        d.push(
            Diagnostic::new(
                Code::E0701,
                format!(
                    "the {stage} answer has {} list lines; only the first {MAX_LINES} are read",
                    l.lines.len()
                ),
            )
            .with_primary(first.span(), "not read from here on")
            .with_help("a scene answer needs far fewer lines; ask again"),
        );
        l.lines.truncate(MAX_LINES);
    }
    if l.lines.is_empty() {
        d.push(
            Diagnostic::new(Code::E0708, format!("the {stage} answer has no `|`-separated line"))
                .with_primary(Span::new(file, 0, prefix_end(text, 200)), "no list here")
                .with_help("answer with one `|`-separated line per item"),
        );
    }
    l.lines
}

/// Whether an answer with no list line says there is nothing to list ("none", "No windows.",
/// "There are no small objects", "N/A").
fn says_none(text: &str) -> bool {
    if text.contains('|') || text.contains('{') || text.contains('[') {
        return false;
    }
    let lower = text.to_lowercase();
    let words: Vec<&str> =
        lower.split(|c: char| !c.is_alphanumeric() && c != '/').filter(|w| !w.is_empty()).collect();
    !words.is_empty()
        && words.len() <= 40
        && words.iter().any(|w| matches!(*w, "none" | "no" | "nothing" | "n/a" | "without"))
}

/// Whether the floor plan has declared rooms (then names are checked against them).
fn has_plan(ctx: &ImportContext) -> bool {
    ctx.draft.rooms.iter().any(|r| !r.implicit)
}

/// Resolves a room named in a line; declares it when there is no floor plan to check against.
fn resolve_room(ctx: &mut ImportContext, field: &Field, d: &mut Diags) -> Option<String> {
    let name = field.text.trim_matches(['\'', '"']).trim();
    if let Some(r) = ctx.draft.find_room(name) {
        return Some(r.id.clone());
    }
    if has_plan(ctx) {
        let names = ctx.draft.room_names();
        d.push(
            Diagnostic::new(Code::E0703, format!("unknown room `{name}`"))
                .with_primary(field.span, "not a room of the floor plan")
                .with_help_opt(did_you_mean(&closest(name, names.iter().map(String::as_str))))
                .with_note(format!("rooms: {}", names.join(", "))),
        );
        return None;
    }
    if name.is_empty() {
        d.push(
            Diagnostic::new(Code::E0701, "a room name is empty")
                .with_primary(field.span, "empty")
                .with_help("write the room name as in the floor plan"),
        );
        return None;
    }
    Some(ctx.draft.implicit_room(name))
}

/// The room a per-room answer is about.
fn current_room(ctx: &mut ImportContext, file: FileId, d: &mut Diags) -> String {
    if let Some(label) = ctx.room.clone() {
        if let Some(r) = ctx.draft.find_room(&label) {
            return r.id.clone();
        }
        if has_plan(ctx) {
            let names = ctx.draft.room_names();
            d.push(
                Diagnostic::new(
                    Code::E0703,
                    format!("the answer is for room `{label}`, which the floor plan does not have"),
                )
                .with_primary(Span::new(file, 0, 0), "answer for this room")
                .with_help_opt(did_you_mean(&closest(&label, names.iter().map(String::as_str)))),
            );
        }
        return ctx.draft.implicit_room(&label);
    }
    if ctx.draft.rooms.len() == 1 {
        return ctx.draft.rooms[0].id.clone();
    }
    ctx.draft.implicit_room("room")
}

fn room_comment(ctx: &mut ImportContext, room: Option<&str>, comment: String) {
    match room.and_then(|r| ctx.draft.room_mut(r)) {
        Some(r) => r.comments.push(comment),
        None => ctx.draft.comments.push(comment),
    }
}

/// The extent, in cm, that a zero extent of an object's size is read as.
const THINNEST_CM: f64 = 1.0;

// ---------------------------------------------------------------------------------------------
// Wall height.

/// Words that, shortly before a number, say it is the wall height.
const HEIGHT_WORDS: [&str; 5] = ["height", "high", "tall", "ceiling", "ceilings"];

/// The wall height in a prose answer ("For a 1b1b apartment, a wall height of 2.7 m works
/// well."): of the numbers that are not part of a word (`1b1b`), the one with a length unit,
/// then the one after a word such as "height", then one that is a plausible height in metres;
/// the first such number wins a tie.
fn height_in_prose(text: &str) -> Option<(front::Num, usize, usize)> {
    front::numbers(text)
        .into_iter()
        .filter(|(_, _, _, glued)| !glued)
        .map(|(n, a, e, _)| {
            // The 30 characters before the number (spans are byte offsets into `text`).
            let from = text[..a].char_indices().rev().nth(29).map_or(0, |(i, _)| i);
            let before = text[from..a].to_lowercase();
            let metres = match n.unit {
                Some("cm") => n.value / 100.0,
                Some("mm") => n.value / 1000.0,
                _ => n.value,
            };
            let score = 4 * u8::from(matches!(n.unit, Some("m" | "cm" | "mm")))
                + 2 * u8::from(HEIGHT_WORDS.iter().any(|w| before.contains(w)))
                + u8::from((2.0..=6.0).contains(&metres));
            (score, n, a, e)
        })
        .fold(None, |best: Option<(u8, front::Num, usize, usize)>, c| match best {
            Some(b) if b.0 >= c.0 => Some(b),
            _ => Some(c),
        })
        .map(|(_, n, a, e)| (n, a, e))
}

fn wall_height(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let trimmed = text.trim();
    let lead = text.len() - text.trim_start().len();
    let (n, at, end) = if let Some(n) = front::number(trimmed.trim_end_matches('.')) {
        (n, lead, lead + trimmed.len())
    } else if let Some((n, a, e)) = height_in_prose(text) {
        d.push(
            Diagnostic::new(Code::W0701, "read the wall height from prose")
                .with_primary(Span::new(file, a, e), "the height the answer gives"),
        );
        (n, a, e)
    } else {
        d.push(
            Diagnostic::new(Code::E0702, "the wall-height answer holds no number")
                .with_primary(Span::new(file, 0, prefix_end(text, 200)), "no number here")
                .with_help("answer with a bare number of metres, e.g. `3.0`")
                .with_note(
                    "the original picks a random height in 2.5–4.5 m; holoc leaves it unset",
                ),
        );
        ctx.draft
            .comments
            .push(front::raw_comment("wall-height", trimmed.lines().next().unwrap_or("")));
        return;
    };
    let span = Span::new(file, at, end);
    let metres = match n.unit {
        Some("cm") => n.value / 100.0,
        Some("mm") => n.value / 1000.0,
        Some("m") => n.value,
        Some(_) => {
            bad_value(
                span,
                "the wall height is not a length".into(),
                "not metres",
                "write metres, e.g. `3.0`",
                d,
            );
            return;
        }
        None if n.value > 10.0 => {
            d.push(
                Diagnostic::new(Code::W0703, "read a wall height above 10 as centimetres")
                    .with_primary(span, "taken as cm"),
            );
            n.value / 100.0
        }
        None => n.value,
    };
    if n.unit.is_some_and(|u| u != "m") || n.comma {
        converted(&n, span, "m", d);
    }
    let clamped = metres.clamp(2.0, 4.5);
    if clamped != metres {
        d.push(
            Diagnostic::new(
                Code::W0707,
                format!("clamped the wall height {metres} m to {clamped} m"),
            )
            .with_primary(span, "outside 2.0–4.5 m"),
        );
    }
    ctx.draft.wall_height = Some(clamped);
}

// ---------------------------------------------------------------------------------------------
// Floor plan.

const FLOOR_SHAPE: &str = "room name | floor design | wall design | [(x, y), (x, y), ...]";

fn floor_plan(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "floor-plan";
    for line in start_lines(text, file, d, Stage::FloorPlan) {
        let fields = line.fields();
        if !line.content.chars().any(|c| c.is_ascii_digit()) {
            // A table header or prose with `|`: nothing to read.
            d.push(
                Diagnostic::new(
                    Code::W0701,
                    "ignored a `|` line without coordinates (a table header or prose)",
                )
                .with_primary(line.span(), "ignored"),
            );
            continue;
        }
        if fields.len() != 4 {
            bad_line(
                &line,
                format!("a floor-plan line has {} fields, not 4", fields.len()),
                FLOOR_SHAPE,
                d,
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        // The name as written (an apostrophe stays: `professor's office`); only quotes around
        // it and double quotes inside are removed. Its id comes from `draft::room_id`, the rule
        // every later answer's room names are matched with.
        let label: String =
            fields[0].text.trim().trim_matches(['\'', '"']).replace('"', "").trim().to_string();
        if label.is_empty() {
            bad_line(&line, "a floor-plan line has no room name".into(), FLOOR_SHAPE, d);
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        let (id, dup) = ctx.draft.fresh_room_id(&label);
        if dup {
            d.push(
                Diagnostic::new(
                    Code::W0704,
                    format!("room `{label}` is declared twice; this one is `{id}`"),
                )
                .with_primary(fields[0].span, format!("renamed `{id}`")),
            );
        }
        let mut room = super::draft::DRoom {
            id,
            label,
            span: Some(fields[0].span),
            ..super::draft::DRoom::default()
        };
        room.floor = (!fields[1].is_na()).then(|| fields[1].text.clone());
        room.walls = (!fields[2].is_na()).then(|| fields[2].text.clone());
        match front::vertex_list(&fields[3].text) {
            Some(points) if points.len() >= 3 => {
                let mut ok = true;
                for (x, z) in &points {
                    for n in [x, z] {
                        converted(n, fields[3].span, "m", d);
                        let m = to_cm(n) / 100.0;
                        let m = if n.unit.is_none() { n.value } else { m };
                        if m.abs() > 1000.0 {
                            ok = false;
                        }
                    }
                }
                if ok {
                    room.corners = points
                        .iter()
                        .map(|(x, z)| {
                            let m =
                                |n: &Num| if n.unit.is_none() { n.value } else { to_cm(n) / 100.0 };
                            (m(x), m(z))
                        })
                        .collect();
                } else {
                    bad_value(
                        fields[3].span,
                        "a corner is more than 1 km from the origin".into(),
                        "too large",
                        "coordinates are metres",
                        d,
                    );
                    room.comments.push(line.raw_comment(stage));
                }
            }
            Some(points) => {
                bad_value(
                    fields[3].span,
                    format!("a room needs at least 3 corners, this one has {}", points.len()),
                    "too few corners",
                    "list every corner, e.g. `[(0, 0), (0, 4), (5, 4), (5, 0)]`",
                    d,
                );
                room.comments.push(line.raw_comment(stage));
            }
            None => {
                bad_value(
                    fields[3].span,
                    "the vertex list cannot be read".into(),
                    "not a list of (x, y) pairs",
                    "write `[(0, 0), (0, 4), (5, 4), (5, 0)]` (metres)",
                    d,
                );
                room.comments.push(line.raw_comment(stage));
            }
        }
        ctx.draft.rooms.push(room);
    }
}

// ---------------------------------------------------------------------------------------------
// Doorways.

const DOOR_SHAPE: &str = "room 1 | room 2 | doorway/doorframe/open | single/double | door style";

fn door_side(ctx: &mut ImportContext, f: &Field, d: &mut Diags) -> Option<String> {
    let n = norm(&f.text);
    match n.as_str() {
        "exterior" => return Some("exterior".into()),
        "outside" | "outdoors" | "exterior door" | "entrance" => {
            d.push(
                Diagnostic::new(Code::W0702, format!("read `{}` as `exterior`", f.text))
                    .with_primary(f.span, "the outside"),
            );
            return Some("exterior".into());
        }
        _ => {}
    }
    resolve_room(ctx, f, d)
}

fn doorways(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "doorways";
    for line in start_lines(text, file, d, Stage::Doorways) {
        let fields = line.fields();
        if !(3..=5).contains(&fields.len()) {
            bad_line(
                &line,
                format!("a doorway line has {} fields, not 5", fields.len()),
                DOOR_SHAPE,
                d,
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        let a = door_side(ctx, &fields[0], d);
        let b = door_side(ctx, &fields[1], d);
        let kind = word(&fields[2], "connection type", DOOR_KINDS, DOOR_SYNONYMS, d);
        let (Some(a), Some(b), Some(mut kind)) = (a, b, kind) else {
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        };
        if fields.len() < 5 && kind != "open" {
            bad_line(
                &line,
                format!("a doorway line has {} fields, not 5", fields.len()),
                DOOR_SHAPE,
                d,
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        if a == b {
            d.push(
                Diagnostic::new(Code::E0702, "a connection joins a room to itself")
                    .with_primary(line.span(), "left out")
                    .with_help("name two different rooms"),
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        if (a == "exterior" || b == "exterior") && kind == "open" {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    "an open connection to the exterior was made a doorway",
                )
                .with_primary(fields[2].span, "read as `doorway`"),
            );
            kind = "doorway";
        }
        let mut size = None;
        if kind != "open" {
            match fields.get(3) {
                Some(f) if !f.is_na() => {
                    size =
                        word(f, "door size", DOOR_SIZES, DOOR_SIZE_SYNONYMS, d).map(str::to_string);
                    if size.is_none() {
                        ctx.draft.comments.push(line.raw_comment(stage));
                        continue;
                    }
                }
                other => {
                    let span = other.map_or(line.span(), |f| f.span);
                    d.push(
                        Diagnostic::new(
                            Code::W0707,
                            format!("a {kind} without a size was made `single`"),
                        )
                        .with_primary(span, "no size"),
                    );
                    size = Some("single".into());
                }
            }
        }
        let style = fields.get(4).filter(|f| !f.is_na() && kind != "open").map(|f| f.text.clone());
        let dup = ctx
            .draft
            .doors
            .iter()
            .any(|x| (x.from == a && x.to == b) || (x.from == b && x.to == a));
        if dup {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    format!("a second connection between `{a}` and `{b}` was ignored"),
                )
                .with_primary(line.span(), "duplicate"),
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        ctx.draft.doors.push(DDoor {
            from: a,
            to: b,
            kind: kind.to_string(),
            size,
            style,
            asset: None,
            comments: Vec::new(),
        });
    }
}

// ---------------------------------------------------------------------------------------------
// Windows.

const WINDOW_SHAPE: &str =
    "room | wall direction | fixed/hung/slider | (width, height) | quantity | base height cm";

fn windows(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "windows";
    for line in start_lines(text, file, d, Stage::Windows) {
        let fields = line.fields();
        if fields.len() != 6 {
            bad_line(
                &line,
                format!("a window line has {} fields, not 6", fields.len()),
                WINDOW_SHAPE,
                d,
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        let room = resolve_room(ctx, &fields[0], d);
        let dir = word(&fields[1], "wall direction", DIRECTIONS, DIRECTION_SYNONYMS, d);
        let kind = word(&fields[2], "window type", WINDOW_TYPES, WINDOW_SYNONYMS, d);
        let size = front::size_pair(&fields[3].text);
        if size.is_none() {
            bad_value(
                fields[3].span,
                "the window size cannot be read".into(),
                "not `(width, height)`",
                "write `(130, 130)` (cm)",
                d,
            );
        }
        let count = count_field(&fields[4], d);
        let sill = front::number(&fields[5].text).or_else(|| {
            let n = front::first_number(&fields[5].text).map(|x| x.0);
            if n.is_some() {
                d.push(
                    Diagnostic::new(Code::W0701, "read the base height from text")
                        .with_primary(fields[5].span, "first number"),
                );
            }
            n
        });
        let sill_cm = match sill {
            Some(n) if n.value >= 0.0 && to_cm(&n) < 1000.0 => {
                converted(&n, fields[5].span, "cm", d);
                Some(to_cm(&n))
            }
            Some(_) => {
                bad_value(
                    fields[5].span,
                    "the base height must be between 0 and 1000 cm".into(),
                    "out of range",
                    "write the height of the window's bottom in cm",
                    d,
                );
                None
            }
            None => {
                bad_value(
                    fields[5].span,
                    "the base height cannot be read".into(),
                    "not a number",
                    "write the height of the window's bottom in cm",
                    d,
                );
                None
            }
        };
        let mut dims = None;
        if let Some((w, h)) = size {
            let (w_cm, h_cm) = (to_cm(&w), to_cm(&h));
            if w_cm > 0.0 && h_cm > 0.0 && w_cm < 2000.0 && h_cm < 2000.0 {
                converted(&w, fields[3].span, "cm", d);
                dims = Some((w_cm, h_cm));
            } else {
                bad_value(
                    fields[3].span,
                    "the window size is not a positive size below 20 m".into(),
                    "out of range",
                    "write `(130, 130)` (cm)",
                    d,
                );
            }
        }
        let (Some(room), Some(dir), Some(kind), Some((w, h)), Some(count), Some(sill_cm)) =
            (room.clone(), dir, kind, dims, count, sill_cm)
        else {
            room_comment(ctx, room.as_deref(), line.raw_comment(stage));
            continue;
        };
        let win = DWindow {
            wall: dir.into(),
            kind: kind.into(),
            width_cm: w,
            height_cm: h,
            count,
            sill_cm,
        };
        let Some(r) = ctx.draft.room_mut(&room) else { continue };
        if r.windows.iter().any(|x| x.wall == win.wall) {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    format!("a second window row for the {dir} wall of `{room}` was ignored"),
                )
                .with_primary(line.span(), "duplicate"),
            );
            r.comments.push(line.raw_comment(stage));
            continue;
        }
        r.windows.push(win);
    }
}

/// A quantity field: a positive integer, tolerating words after it (`2 windows`).
fn count_field(f: &Field, d: &mut Diags) -> Option<u32> {
    let n = front::number(&f.text).or_else(|| {
        let n = front::first_number(&f.text).map(|x| x.0);
        if n.is_some() {
            d.push(
                Diagnostic::new(Code::W0701, "read the quantity from text")
                    .with_primary(f.span, "first number"),
            );
        }
        n
    });
    match n {
        Some(n) if (1.0..=100.0).contains(&n.value) && n.unit.is_none() => {
            if n.value.fract() != 0.0 {
                d.push(
                    Diagnostic::new(Code::W0707, "rounded a fractional quantity")
                        .with_primary(f.span, "rounded"),
                );
            }
            Some(n.value.round() as u32)
        }
        _ => {
            bad_value(
                f.span,
                format!("`{}` is not a quantity from 1 to 100", f.text),
                "not a quantity",
                "write a whole number, e.g. `2`",
                d,
            );
            None
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Object selection (JSON and pipe).

/// A JSON object with its keys in the order written.
struct Ordered(Vec<(String, serde_json::Value)>);

impl<'de> serde::Deserialize<'de> for Ordered {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Ordered, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Ordered;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Ordered, A::Error> {
                let mut out = Vec::new();
                while let Some((k, v)) = map.next_entry::<String, serde_json::Value>()? {
                    out.push((k, v));
                }
                Ok(Ordered(out))
            }
        }
        de.deserialize_map(V)
    }
}

/// Reads the JSON between the first `open` and the last `close`, as JSON then JSON5.
fn extract_json<T: serde::de::DeserializeOwned>(
    text: &str,
    file: FileId,
    open: char,
    close: char,
    stage: Stage,
    d: &mut Diags,
) -> Option<(T, Span)> {
    let (Some(a), Some(b)) = (text.find(open), text.rfind(close)) else {
        d.push(
            Diagnostic::new(
                Code::E0706,
                format!("the {stage} answer holds no JSON (no `{open}` … `{close}`)"),
            )
            .with_primary(Span::new(file, 0, prefix_end(text, 200)), "no JSON here")
            .with_help("answer with one JSON value; prose around it is fine"),
        );
        return None;
    };
    if b < a {
        d.push(
            Diagnostic::new(Code::E0706, format!("the {stage} answer's brackets are unbalanced"))
                .with_primary(Span::new(file, a, a + 1), "opened here")
                .with_help("answer with one complete JSON value"),
        );
        return None;
    }
    let span = Span::new(file, a, b + close.len_utf8());
    let body = &text[a..b + close.len_utf8()];
    if a > 0 && !text[..a].trim().is_empty() || !text[b + 1..].trim().is_empty() {
        d.push(
            Diagnostic::new(Code::W0701, "ignored prose around the JSON")
                .with_primary(span, "the JSON read"),
        );
    }
    // JSON5's reader recurses without a bound: a body nested deeper than strict JSON reads is
    // refused before either reader sees it.
    if let Some(at) = json_too_deep(body) {
        d.push(
            Diagnostic::new(
                Code::E0706,
                format!("the {stage} answer nests brackets deeper than {MAX_JSON_NESTING} levels"),
            )
            .with_primary(Span::new(file, a + at, a + at + 1), "too deep")
            .with_help("answer with one flat JSON value"),
        );
        return None;
    }
    match serde_json::from_str::<T>(body) {
        Ok(v) => Some((v, span)),
        Err(e1) => match json5::from_str::<T>(body) {
            Ok(v) => {
                d.push(
                    Diagnostic::new(
                        Code::W0701,
                        "read the answer as JSON5 (quotes or commas are not strict JSON)",
                    )
                    .with_primary(span, "lenient JSON"),
                );
                Some((v, span))
            }
            Err(_) => {
                let at = Span::new(file, a, b + close.len_utf8());
                d.push(
                    Diagnostic::new(
                        Code::E0706,
                        format!("the {stage} answer is not valid JSON: {e1}"),
                    )
                    .with_primary(at, "cannot be read")
                    .with_help("answer with one complete JSON value"),
                );
                None
            }
        },
    }
}

/// The deepest nesting of brackets an answer's JSON may have (serde_json's own limit).
pub const MAX_JSON_NESTING: usize = 128;

/// The offset of the first `{` or `[` nested deeper than [`MAX_JSON_NESTING`], outside strings
/// (double- or single-quoted, as JSON5 allows). One pass, no recursion.
fn json_too_deep(body: &str) -> Option<usize> {
    let bytes = body.as_bytes();
    let mut depth = 0usize;
    let mut quote: Option<u8> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match quote {
            Some(_) if b == b'\\' => i += 1,
            Some(q) if b == q => quote = None,
            Some(_) => {}
            None => match b {
                b'"' | b'\'' => quote = Some(b),
                b'{' | b'[' => {
                    depth += 1;
                    if depth > MAX_JSON_NESTING {
                        return Some(i);
                    }
                }
                b'}' | b']' => depth = depth.saturating_sub(1),
                _ => {}
            },
        }
        i += 1;
    }
    None
}

fn key_norm(k: &str) -> String {
    k.trim().to_lowercase().split_whitespace().collect::<Vec<_>>().join("_")
}

fn find_span(text: &str, file: FileId, needle: &str, fallback: Span) -> Span {
    text.find(needle).map_or(fallback, |a| Span::new(file, a, a + needle.len()))
}

fn json_number(v: &serde_json::Value) -> Option<f64> {
    match v {
        serde_json::Value::Number(n) => n.as_f64().filter(|x| x.is_finite()),
        serde_json::Value::String(s) => front::number(s).map(|n| to_cm(&n)),
        _ => None,
    }
}

fn json_word(
    v: Option<&serde_json::Value>,
    what: &str,
    vocab: &[&'static str],
    syn: &[(&'static str, &'static str)],
    default: &'static str,
    span: Span,
    d: &mut Diags,
) -> &'static str {
    let Some(s) = v.and_then(serde_json::Value::as_str) else {
        if v.is_some() {
            d.push(
                Diagnostic::new(Code::W0707, format!("{what} is not a string; `{default}` used"))
                    .with_primary(span, "defaulted"),
            );
        }
        return default;
    };
    match lookup(s, vocab, syn) {
        Found::Exact(w) => w,
        Found::Synonym(w) => {
            d.push(
                Diagnostic::new(Code::W0702, format!("read {what} `{s}` as `{w}`"))
                    .with_primary(span, "synonym"),
            );
            w
        }
        Found::Unknown(_) => {
            d.push(
                Diagnostic::new(Code::W0707, format!("unknown {what} `{s}`; `{default}` used"))
                    .with_primary(span, "defaulted"),
            );
            default
        }
    }
}

fn objects_json(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let room = current_room(ctx, file, d);
    let Some((Ordered(entries), whole)) =
        extract_json::<Ordered>(text, file, '{', '}', Stage::Objects, d)
    else {
        room_comment(
            ctx,
            Some(&room),
            front::raw_comment("objects", text.lines().next().unwrap_or("")),
        );
        return;
    };
    if entries.is_empty() {
        d.push(
            Diagnostic::new(Code::E0708, "the object selection is empty")
                .with_primary(whole, "no objects")
                .with_help("select at least one object"),
        );
    }
    let mut seen: Vec<String> = Vec::new();
    let mut entries = entries;
    if entries.len() > MAX_LINES {
        d.push(
            Diagnostic::new(
                Code::E0701,
                format!(
                    "the answer selects {} objects; only the first {MAX_LINES} are read",
                    entries.len()
                ),
            )
            .with_primary(whole, "too many objects")
            .with_help("a room needs far fewer objects; ask again"),
        );
        entries.truncate(MAX_LINES);
    }
    for (key, value) in entries {
        let span = find_span(text, file, &format!("\"{key}\""), whole);
        let serde_json::Value::Object(rec) = value else {
            d.push(
                Diagnostic::new(Code::E0702, format!("object `{key}` is not a record"))
                    .with_primary(span, "expected `{\"description\": …, \"location\": …, …}`")
                    .with_help("give each object a JSON object with description, location, size, quantity, variance_type, objects_on_top"),
            );
            room_comment(
                ctx,
                Some(&room),
                front::raw_comment("objects", &format!("{key}: {value}")),
            );
            continue;
        };
        let rec: Vec<(String, serde_json::Value)> =
            rec.into_iter().map(|(k, v)| (key_norm(&k), v)).collect();
        let get = |k: &str| rec.iter().find(|(n, _)| n == k).map(|(_, v)| v);
        let category = key.trim().to_string();
        let base = object_id(&key_norm(&key));
        let mut id = base.clone();
        let mut n = 2;
        while seen.contains(&id) {
            id = format!("{base}_{n}");
            n += 1;
        }
        if id != base {
            d.push(
                Diagnostic::new(
                    Code::W0704,
                    format!("object `{key}` is selected twice; this one is `{id}`"),
                )
                .with_primary(span, "renamed"),
            );
        }
        seen.push(id.clone());
        let mut o = DObject { id, category, count: 1, span: Some(span), ..DObject::default() };
        match get("description") {
            Some(serde_json::Value::String(s)) => o.describe = Some(s.clone()),
            _ => d.push(
                Diagnostic::new(Code::W0707, format!("object `{key}` has no description"))
                    .with_primary(span, "no description"),
            ),
        }
        o.wall =
            json_word(get("location"), "location", LOCATIONS, LOCATION_SYNONYMS, "floor", span, d)
                == "wall";
        if let Some(v) = get("size").filter(|v| !v.is_null()) {
            let nums: Option<Vec<f64>> =
                v.as_array().and_then(|a| a.iter().map(json_number).collect::<Option<Vec<_>>>());
            match nums.as_deref() {
                Some(&[l, w, h])
                    if [l, w, h].iter().all(|x| (0.0..10_000.0).contains(x) && *x != 0.0) =>
                {
                    o.size = Some([l, w, h]);
                }
                Some(&[l, w, h]) if [l, w, h].iter().all(|x| (0.0..10_000.0).contains(x)) => {
                    // A zero extent (a curtain or a poster written as `[200, 0, 250]`): the
                    // thinnest sensible size, 1 cm, as the original system placed it.
                    let thin = |x: f64| if x == 0.0 { THINNEST_CM } else { x };
                    o.size = Some([thin(l), thin(w), thin(h)]);
                    d.push(
                        Diagnostic::new(
                            Code::W0707,
                            format!(
                                "the size of `{key}` has a zero extent; it is read as {THINNEST_CM} cm"
                            ),
                        )
                        .with_primary(span, format!("read as {:?} cm", [thin(l), thin(w), thin(h)]))
                        .with_help("give every extent in cm, at least 1"),
                    );
                }
                Some(&[_, _, _]) => bad_value(
                    span,
                    format!("the size of `{key}` is not three positive numbers below 10000 cm"),
                    "size ignored",
                    "write `[length, width, height]` in cm",
                    d,
                ),
                _ => d.push(
                    Diagnostic::new(
                        Code::W0707,
                        format!("the size of `{key}` is not `[length, width, height]`; ignored"),
                    )
                    .with_primary(span, "size ignored"),
                ),
            }
        }
        o.count = json_quantity(get("quantity"), &key, span, d);
        o.variance = Some(
            json_word(
                get("variance_type"),
                "variance type",
                VARIANCES,
                VARIANCE_SYNONYMS,
                "same",
                span,
                d,
            )
            .to_string(),
        );
        if o.count <= 1 && o.variance.as_deref() == Some("same") {
            o.variance = None;
        }
        if let Some(tops) = get("objects_on_top") {
            match tops.as_array() {
                Some(list) => {
                    for child in list {
                        let name = child
                            .get("object_name")
                            .or_else(|| child.get("object name"))
                            .and_then(serde_json::Value::as_str);
                        let Some(name) = name.filter(|n| !n.trim().is_empty()) else {
                            bad_value(span, format!("a child of `{key}` has no `object_name`"), "child ignored", "write `{\"object_name\": \"book\", \"quantity\": 2, \"variance_type\": \"varied\"}`", d);
                            o.comments.push(front::raw_comment("objects", &child.to_string()));
                            continue;
                        };
                        let count = json_quantity(child.get("quantity"), name, span, d);
                        let variance = json_word(
                            child.get("variance_type"),
                            "variance type",
                            VARIANCES,
                            VARIANCE_SYNONYMS,
                            "same",
                            span,
                            d,
                        );
                        o.on_top.push(DOnTop {
                            item: name.trim().to_string(),
                            count,
                            variance: Some(variance.into()),
                            asset: None,
                            at: None,
                            facing: None,
                        });
                    }
                }
                None if tops.is_null() => {}
                None => d.push(
                    Diagnostic::new(
                        Code::W0707,
                        format!("`objects_on_top` of `{key}` is not a list; ignored"),
                    )
                    .with_primary(span, "ignored"),
                ),
            }
        }
        o.fit();
        let Some(r) = ctx.draft.room_mut(&room) else { continue };
        if let Some(old) = r.objects.iter_mut().find(|x| x.id == o.id) {
            *old = o;
        } else {
            r.objects.push(o);
        }
    }
}

fn json_quantity(v: Option<&serde_json::Value>, name: &str, span: Span, d: &mut Diags) -> u32 {
    let q = match v {
        None => {
            d.push(
                Diagnostic::new(Code::W0707, format!("`{name}` has no quantity; 1 used"))
                    .with_primary(span, "quantity 1"),
            );
            return 1;
        }
        Some(v) => json_number(v),
    };
    match q {
        Some(q) if q >= 1.0 => {
            let r = q.round().min(10.0);
            if r != q {
                d.push(
                    Diagnostic::new(
                        Code::W0707,
                        format!("quantity {q} of `{name}` became {r} (whole, at most 10)"),
                    )
                    .with_primary(span, "adjusted"),
                );
            }
            r as u32
        }
        _ => {
            d.push(
                Diagnostic::new(
                    Code::W0707,
                    format!("the quantity of `{name}` is not a positive number; 1 used"),
                )
                .with_primary(span, "quantity 1"),
            );
            1
        }
    }
}

const PIPE_SHAPE: &str = "room | floor/wall | category | description | quantity, same/varied";

fn objects_pipe(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "objects-pipe";
    for line in start_lines(text, file, d, Stage::ObjectsPipe) {
        let fields = line.fields();
        let (room_f, loc, cat, desc, qty) = match fields.as_slice() {
            [r, l, c, de, q] => (r, Some(l), c, de, q),
            [r, c, de, q] => (r, None, c, de, q),
            _ => {
                bad_line(
                    &line,
                    format!("an object line has {} fields, not 4 or 5", fields.len()),
                    PIPE_SHAPE,
                    d,
                );
                ctx.draft.comments.push(line.raw_comment(stage));
                continue;
            }
        };
        let Some(room) = resolve_room(ctx, room_f, d) else {
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        };
        let wall = match loc {
            Some(l) => match word(l, "location", LOCATIONS, LOCATION_SYNONYMS, d) {
                Some(w) => w == "wall",
                None => {
                    room_comment(ctx, Some(&room), line.raw_comment(stage));
                    continue;
                }
            },
            None => false,
        };
        let mut parts = qty.text.splitn(2, ',');
        let q_text = parts.next().unwrap_or("").trim();
        let q_field = Field { text: q_text.to_string(), span: qty.span };
        let Some(count) = count_field(&q_field, d) else {
            room_comment(ctx, Some(&room), line.raw_comment(stage));
            continue;
        };
        let variance = match parts.next().map(str::trim).filter(|v| !v.is_empty()) {
            Some(v) => word(
                &Field { text: v.to_string(), span: qty.span },
                "variance type",
                VARIANCES,
                VARIANCE_SYNONYMS,
                d,
            ),
            None => None,
        };
        let key = key_norm(&cat.text);
        let Some(r) = ctx.draft.room_mut(&room) else { continue };
        let base = object_id(&key);
        let mut id = base.clone();
        let mut n = 2;
        while r.objects.iter().any(|o| o.id == id) {
            id = format!("{base}_{n}");
            n += 1;
        }
        if id != base {
            d.push(
                Diagnostic::new(
                    Code::W0704,
                    format!("object `{}` is selected twice; this one is `{id}`", cat.text),
                )
                .with_primary(cat.span, "renamed"),
            );
        }
        let count = count.min(10);
        let mut o = DObject {
            id,
            category: cat.text.clone(),
            wall,
            describe: (!desc.is_na()).then(|| desc.text.clone()),
            count,
            variance: variance.filter(|v| count > 1 || *v != "same").map(str::to_string),
            span: Some(cat.span),
            ..DObject::default()
        };
        o.fit();
        r.objects.push(o);
    }
}

// ---------------------------------------------------------------------------------------------
// Instance lookup.

/// Where an instance is: (object index in the room, instance index).
type Inst = (usize, usize);

fn inst_norm(name: &str) -> String {
    name.trim()
        .trim_matches(['\'', '"'])
        .to_lowercase()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join("_")
}

fn find_inst(ctx: &ImportContext, room: &str, name: &str, wall: Option<bool>) -> Option<Inst> {
    let r = ctx.draft.room(room)?;
    let n = inst_norm(name);
    let ok = |o: &DObject| wall.is_none_or(|w| o.wall == w);
    for (oi, o) in r.objects.iter().enumerate().filter(|(_, o)| ok(o)) {
        for (ii, inst) in o.instance_names().iter().enumerate() {
            if *inst == n || loose(inst) == loose(&n) {
                return Some((oi, ii));
            }
        }
        if o.count <= 1 && (o.id == n || loose(&o.id) == loose(&n)) {
            return Some((oi, 0));
        }
    }
    None
}

fn all_insts(ctx: &ImportContext, room: &str, wall: Option<bool>) -> Vec<String> {
    ctx.draft
        .room(room)
        .map(|r| {
            r.objects
                .iter()
                .filter(|o| wall.is_none_or(|w| o.wall == w))
                .flat_map(DObject::instance_names)
                .collect()
        })
        .unwrap_or_default()
}

/// Declares an object from an instance name `<group>-<n>` (stand-alone imports).
fn declare_inst(ctx: &mut ImportContext, room: &str, name: &str, wall: bool) -> Option<Inst> {
    let n = inst_norm(name);
    let (group, index) = match n.rsplit_once('-') {
        Some((g, i)) if i.parse::<usize>().is_ok() => {
            (g.to_string(), i.parse::<usize>().unwrap_or(0))
        }
        _ => (n.clone(), 0),
    };
    if index > 50 {
        return None;
    }
    let id = object_id(&group);
    let r = ctx.draft.room_mut(room)?;
    let oi = match r.objects.iter().position(|o| o.id == id) {
        Some(oi) => oi,
        None => {
            r.objects.push(DObject {
                id: id.clone(),
                category: group.replace('_', " "),
                wall,
                count: 1,
                ..DObject::default()
            });
            r.objects.len() - 1
        }
    };
    let o = &mut r.objects[oi];
    if o.wall != wall {
        return None;
    }
    o.count = o.count.max(index as u32 + 1);
    o.fit();
    Some((oi, index))
}

fn inst_mut<'a>(
    ctx: &'a mut ImportContext,
    room: &str,
    (oi, ii): Inst,
) -> Option<&'a mut DInstance> {
    let o = ctx.draft.room_mut(room)?.objects.get_mut(oi)?;
    o.fit();
    o.instances.get_mut(ii)
}

fn inst_name(ctx: &ImportContext, room: &str, (oi, ii): Inst) -> String {
    ctx.draft
        .room(room)
        .and_then(|r| r.objects.get(oi))
        .map_or_else(String::new, |o| format!("{}-{ii}", o.id))
}

fn unknown_inst(
    ctx: &ImportContext,
    room: &str,
    f: &Field,
    wall: Option<bool>,
    what: &str,
    d: &mut Diags,
) {
    let names = all_insts(ctx, room, wall);
    let n = inst_norm(&f.text);
    d.push(
        Diagnostic::new(Code::E0704, format!("unknown {what} `{}`", f.text))
            .with_primary(f.span, format!("not a {what} of the room"))
            .with_help_opt(did_you_mean(&closest(&n, names.iter().map(String::as_str))))
            .with_note(if names.is_empty() {
                "the room has none".to_string()
            } else {
                format!("known: {}", names.join(", "))
            }),
    );
}

// ---------------------------------------------------------------------------------------------
// Floor constraints.

struct Pending {
    from: Inst,
    to: Inst,
    name: String,
    span: Span,
    raw: String,
}

fn split_constraint(text: &str) -> (String, Option<String>) {
    if let Some((a, b)) = text.split_once(',') {
        return (a.trim().to_string(), Some(b.trim().to_string()).filter(|t| !t.is_empty()));
    }
    if let Some((a, b)) = text.split_once(':') {
        return (a.trim().to_string(), Some(b.trim().to_string()).filter(|t| !t.is_empty()));
    }
    // `near sofa-0`: the longest known name that starts the field.
    let n = norm(text);
    let mut names: Vec<&str> =
        CONSTRAINTS.iter().copied().chain(CONSTRAINT_SYNONYMS.iter().map(|(s, _)| *s)).collect();
    names.sort_by_key(|s| std::cmp::Reverse(s.len()));
    for name in names {
        if let Some(rest) = n.strip_prefix(name) {
            if rest.starts_with(' ') {
                return (name.to_string(), Some(rest.trim().to_string()));
            }
        }
    }
    (text.trim().to_string(), None)
}

fn floor_constraints(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "floor-constraints";
    let room = current_room(ctx, file, d);
    let implicit = all_insts(ctx, &room, Some(false)).is_empty();
    let mut pending: Vec<Pending> = Vec::new();
    let mut seen: Vec<Inst> = Vec::new();
    let lines = start_lines(text, file, d, Stage::FloorConstraints);
    if implicit {
        // Names are resolved after the whole answer is read: every line's object is declared
        // first, so that a relation may name an object whose line comes later.
        for line in &lines {
            let head = &line.fields()[0];
            if find_inst(ctx, &room, &head.text, None).is_none() {
                declare_inst(ctx, &room, &head.text, false);
            }
        }
    }
    for (pos, line) in lines.into_iter().enumerate() {
        let fields = line.fields();
        let head = &fields[0];
        let found = find_inst(ctx, &room, &head.text, Some(false)).or_else(|| {
            if implicit {
                declare_inst(ctx, &room, &head.text, false)
            } else {
                None
            }
        });
        let Some(me) = found else {
            if find_inst(ctx, &room, &head.text, Some(true)).is_some() {
                d.push(
                    Diagnostic::new(
                        Code::E0704,
                        format!(
                            "`{}` is a wall object; floor constraints are for floor objects",
                            head.text
                        ),
                    )
                    .with_primary(head.span, "a wall object")
                    .with_help(
                        "give wall objects `above` and a height in the wall-constraint answer",
                    ),
                );
            } else if !norm(&head.text).chars().any(|c| c.is_ascii_digit())
                && fields.len() > 1
                && fields[1..].iter().all(|f| !f.text.contains(','))
                && !implicit
            {
                d.push(
                    Diagnostic::new(
                        Code::W0701,
                        "ignored a `|` line that names no object (a table header or prose)",
                    )
                    .with_primary(line.span(), "ignored"),
                );
                continue;
            } else {
                unknown_inst(ctx, &room, head, Some(false), "floor object", d);
            }
            room_comment(ctx, Some(&room), line.raw_comment(stage));
            continue;
        };
        if seen.contains(&me) {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    format!("a second line for `{}` replaces the first", head.text),
                )
                .with_primary(line.span(), "replaces the earlier line"),
            );
            pending.retain(|p| p.from != me);
        } else {
            seen.push(me);
        }
        let me_name = inst_name(ctx, &room, me);
        {
            let Some(r) = ctx.draft.room_mut(&room) else { continue };
            let o = &mut r.objects[me.0];
            o.order = Some(o.order.map_or(pos, |p| p.min(pos)));
            o.fit();
            o.instances[me.1].order = Some(pos);
            o.instances[me.1].constraints.clear();
            o.instances[me.1].comments.clear();
        }
        let mut has_global = false;
        for f in &fields[1..] {
            if f.is_na() {
                continue;
            }
            let (name, target) = split_constraint(&f.text);
            let name_field = Field { text: name.clone(), span: f.span };
            let Some(canon) = word(&name_field, "constraint", CONSTRAINTS, CONSTRAINT_SYNONYMS, d)
            else {
                if let Some(i) = inst_mut(ctx, &room, me) {
                    i.comments.push(front::raw_comment(stage, &f.text));
                }
                continue;
            };
            if matches!(canon, "edge" | "middle") {
                if has_global {
                    d.push(
                        Diagnostic::new(
                            Code::W0706,
                            format!("a second global constraint `{canon}` was ignored"),
                        )
                        .with_primary(f.span, "ignored")
                        .with_help("an object is at the `edge` or in the `middle`, not both"),
                    );
                    if let Some(i) = inst_mut(ctx, &room, me) {
                        i.comments.push(front::raw_comment(stage, &f.text));
                    }
                    continue;
                }
                has_global = true;
                if let Some(i) = inst_mut(ctx, &room, me) {
                    i.constraints.push((canon.to_string(), None));
                }
                continue;
            }
            let Some(target) = target else {
                d.push(
                    Diagnostic::new(Code::E0701, format!("constraint `{canon}` needs a target"))
                        .with_primary(f.span, "no target")
                        .with_help(format!("write `{canon}, sofa-0`")),
                );
                if let Some(i) = inst_mut(ctx, &room, me) {
                    i.comments.push(front::raw_comment(stage, &f.text));
                }
                continue;
            };
            let to = find_inst(ctx, &room, &target, Some(false));
            let problem = match to {
                None => {
                    let names = all_insts(ctx, &room, Some(false));
                    Some((
                        format!("constraint `{canon}` names unknown object `{target}`"),
                        did_you_mean(&closest(
                            &inst_norm(&target),
                            names.iter().map(String::as_str),
                        )),
                    ))
                }
                Some(t) if t == me => Some((
                    format!("`{me_name}` cannot be `{canon}` itself"),
                    Some("name another object".to_string()),
                )),
                Some(_) => None,
            };
            if let Some((msg, help)) = problem {
                d.push(
                    Diagnostic::new(Code::E0707, msg)
                        .with_primary(f.span, "dropped")
                        .with_help_opt(help),
                );
                if let Some(i) = inst_mut(ctx, &room, me) {
                    i.comments.push(front::raw_comment(stage, &f.text));
                }
                continue;
            }
            if let Some(to) = to {
                pending.push(Pending {
                    from: me,
                    to,
                    name: canon.to_string(),
                    span: f.span,
                    raw: f.text.clone(),
                });
            }
        }
    }
    keep_acyclic(ctx, &room, stage, pending, d);
    no_constraints(ctx, &room, Span::new(file, 0, 0), d);
}

/// Puts the answer's relations on their objects. A relation may name an object whose line comes
/// later (the checker places every object after the objects it names), unless it closes a
/// circle: objects are placed one after another, so of a circle the relation that names a later
/// line leaves the scene (W0708, kept as a `// raw` comment), as the original system drops every
/// relation to a later line. Relations to earlier lines are kept first, and the others in the
/// answer's order, each only when it closes no circle with those kept before it.
fn keep_acyclic(
    ctx: &mut ImportContext,
    room: &str,
    stage: &str,
    pending: Vec<Pending>,
    d: &mut Diags,
) {
    let key = |ctx: &ImportContext, (oi, ii): Inst| -> usize {
        let o = ctx.draft.room(room).and_then(|r| r.objects.get(oi));
        o.and_then(|o| o.instances.get(ii)).and_then(|i| i.order).unwrap_or(usize::MAX)
    };
    let backward: Vec<bool> = pending.iter().map(|p| key(ctx, p.to) < key(ctx, p.from)).collect();
    // The kept relations, as indices into `pending`.
    let mut kept: Vec<usize> = (0..pending.len()).filter(|&k| backward[k]).collect();
    let mut dropped: Vec<(usize, Vec<usize>)> = Vec::new();
    for k in (0..pending.len()).filter(|&k| !backward[k]) {
        match relation_path(&pending, &kept, pending[k].to, pending[k].from) {
            Some(path) => dropped.push((k, path)),
            None => kept.push(k),
        }
    }
    for (k, path) in &dropped {
        let p = &pending[*k];
        let me = inst_name(ctx, room, p.from);
        let target = inst_name(ctx, room, p.to);
        let mut diag = Diagnostic::new(
            Code::W0708,
            format!("constraint `{}` of `{me}` names `{target}`, which depends on `{me}`", p.name),
        )
        .with_primary(p.span, "dropped: closes a circle");
        for &j in path {
            let q = &pending[j];
            diag = diag.with_secondary(
                q.span,
                format!(
                    "`{}` names `{}` here",
                    inst_name(ctx, room, q.from),
                    inst_name(ctx, room, q.to)
                ),
            );
        }
        let help = if path.len() == 1 {
            format!(
                "objects are placed one after another; to keep it, remove the relation of \
                 `{target}` that names `{me}`"
            )
        } else {
            "objects are placed one after another; to keep it, remove one of the relations \
             labelled"
                .to_string()
        };
        d.push(diag.with_help(help).with_note("kept as a `// raw` comment"));
    }
    let dropped: Vec<usize> = dropped.into_iter().map(|(k, _)| k).collect();
    for (k, p) in pending.into_iter().enumerate() {
        if dropped.contains(&k) {
            if let Some(i) = inst_mut(ctx, room, p.from) {
                i.comments.push(front::raw_comment(stage, &p.raw));
            }
        } else {
            let target = inst_name(ctx, room, p.to);
            if let Some(i) = inst_mut(ctx, room, p.from) {
                i.constraints.push((p.name, Some(target)));
            }
        }
    }
}

/// A chain of kept relations (indices into `pending`) that leads from `from` to `to`, if any
/// (breadth first, so the shortest).
fn relation_path(pending: &[Pending], kept: &[usize], from: Inst, to: Inst) -> Option<Vec<usize>> {
    let mut came_by: Vec<(Inst, usize)> = Vec::new();
    let mut queue = std::collections::VecDeque::from([from]);
    let mut reached = vec![from];
    while let Some(at) = queue.pop_front() {
        if at == to {
            let mut path = Vec::new();
            let mut node = to;
            while node != from {
                let &(_, k) = came_by.iter().find(|(n, _)| *n == node)?;
                path.push(k);
                node = pending[k].from;
            }
            path.reverse();
            return Some(path);
        }
        for &k in kept.iter().filter(|&&k| pending[k].from == at) {
            let next = pending[k].to;
            if !reached.contains(&next) {
                reached.push(next);
                came_by.push((next, k));
                queue.push_back(next);
            }
        }
    }
    None
}

/// The instances of a room's floor objects that have no constraints and no pinned position:
/// per object, the object and its instance names.
pub(crate) fn unconstrained(r: &super::draft::DRoom) -> Vec<(&DObject, Vec<String>)> {
    let mut out = Vec::new();
    for o in r.objects.iter().filter(|o| !o.wall) {
        let names: Vec<String> = o
            .instances
            .iter()
            .enumerate()
            .take(o.count.max(1) as usize)
            .filter(|(_, inst)| inst.order.is_none() && inst.at.is_none())
            .map(|(i, _)| format!("{}-{i}", o.id))
            .collect();
        if !names.is_empty() {
            out.push((o, names));
        }
    }
    out
}

/// `a`, `a and b`, `a, b and c`, each in backticks.
pub(crate) fn name_list(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// W0705 for the floor objects the constraint answer (at `answer`) did not mention: one per
/// object, at the line of the object selection that declares it (at the answer when none
/// does), naming its instances.
pub(crate) fn no_constraints(ctx: &ImportContext, room: &str, answer: Span, d: &mut Diags) {
    let Some(r) = ctx.draft.room(room) else { return };
    for (o, names) in unconstrained(r) {
        let (verb, pronoun) = if names.len() == 1 { ("has", "it") } else { ("have", "they") };
        let message = format!(
            "{} in `{}` {verb} no constraints; {pronoun} will be placed at an edge",
            name_list(&names),
            r.label
        );
        let mut diagnostic = Diagnostic::new(Code::W0705, message);
        diagnostic = match o.span {
            Some(span) => diagnostic
                .with_primary(span, "declared here")
                .with_secondary(answer, "the constraint answer does not mention it"),
            None => diagnostic.with_primary(answer, "not mentioned by the constraint answer"),
        };
        d.push(diagnostic);
    }
}

/// One W0705 for a room of a transcript that has no constraint answer for it at all: its floor
/// objects without constraints, counted, with their names in a note (one line, not one per
/// object), at the room's line in the floor plan (at `fallback` when no line names it).
pub(crate) fn no_constraints_in_file(
    ctx: &ImportContext,
    room: &str,
    fallback: Span,
    d: &mut Diags,
) {
    let Some(r) = ctx.draft.room(room) else { return };
    let names: Vec<String> = unconstrained(r).into_iter().flat_map(|(_, names)| names).collect();
    if names.is_empty() {
        return;
    }
    let n = names.len();
    let (objects, verb, pronoun) =
        if n == 1 { ("object", "has", "it") } else { ("objects", "have", "they") };
    d.push(
        Diagnostic::new(
            Code::W0705,
            format!(
                "the {n} floor {objects} of `{}` {verb} no constraints; {pronoun} will be placed at an edge",
                r.label
            ),
        )
        .with_primary(r.span.unwrap_or(fallback), "no constraint answer for this room")
        .with_note(shown_names(&names)),
    );
}

/// The first 8 names, in backticks, and how many more there are.
pub(crate) fn shown_names(names: &[String]) -> String {
    let shown: Vec<String> = names.iter().take(8).map(|n| format!("`{n}`")).collect();
    let more =
        if names.len() > 8 { format!(" and {} more", names.len() - 8) } else { String::new() };
    format!("{}{more}", shown.join(", "))
}

// ---------------------------------------------------------------------------------------------
// Wall constraints.

const WALL_SHAPE: &str = "wall object-0 | above, floor object-0 | height cm";

fn wall_constraints(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "wall-constraints";
    let room = current_room(ctx, file, d);
    let implicit = all_insts(ctx, &room, Some(true)).is_empty();
    let implicit_floor = all_insts(ctx, &room, Some(false)).is_empty();
    let mut seen: Vec<Inst> = Vec::new();
    for line in start_lines(text, file, d, Stage::WallConstraints) {
        let fields = line.fields();
        if !(2..=3).contains(&fields.len()) {
            bad_line(
                &line,
                format!("a wall-constraint line has {} fields, not 3", fields.len()),
                WALL_SHAPE,
                d,
            );
            room_comment(ctx, Some(&room), line.raw_comment(stage));
            continue;
        }
        let head = &fields[0];
        let found = find_inst(ctx, &room, &head.text, Some(true)).or_else(|| {
            if implicit {
                declare_inst(ctx, &room, &head.text, true)
            } else {
                None
            }
        });
        let Some(me) = found else {
            unknown_inst(ctx, &room, head, Some(true), "wall object", d);
            room_comment(ctx, Some(&room), line.raw_comment(stage));
            continue;
        };
        if seen.contains(&me) {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    format!("a second line for `{}` replaces the first", head.text),
                )
                .with_primary(line.span(), "replaces"),
            );
        } else {
            seen.push(me);
        }
        let mut above = None;
        let loc = &fields[1];
        if !loc.is_na() {
            let n = norm(loc.text.trim_start_matches(['*', ' ']));
            let rest = ["above", "over", "on top of", "on the wall above"].iter().find_map(|w| {
                n.strip_prefix(w)
                    .map(|r| (*w, r.trim_start_matches([',', ':', ' ']).trim().to_string()))
            });
            match rest {
                Some((w, target)) if !target.is_empty() => {
                    if w != "above" {
                        d.push(
                            Diagnostic::new(Code::W0702, format!("read `{w}` as `above`"))
                                .with_primary(loc.span, "synonym of `above`"),
                        );
                    }
                    let to = find_inst(ctx, &room, &target, Some(false)).or_else(|| {
                        if implicit_floor {
                            declare_inst(ctx, &room, &target, false)
                        } else {
                            None
                        }
                    });
                    match to {
                        Some(t) => above = Some(inst_name(ctx, &room, t)),
                        None => {
                            let names = all_insts(ctx, &room, Some(false));
                            d.push(
                                Diagnostic::new(
                                    Code::E0707,
                                    format!("`above` names unknown floor object `{target}`"),
                                )
                                .with_primary(loc.span, "dropped")
                                .with_help_opt(did_you_mean(
                                    &closest(&inst_norm(&target), names.iter().map(String::as_str)),
                                )),
                            );
                            if let Some(i) = inst_mut(ctx, &room, me) {
                                i.comments.push(front::raw_comment(stage, &loc.text));
                            }
                        }
                    }
                }
                _ => {
                    d.push(
                        Diagnostic::new(
                            Code::E0705,
                            format!("unknown wall placement `{}`", loc.text),
                        )
                        .with_primary(loc.span, "expected `above, <floor object>` or `N/A`")
                        .with_help("only `above` is understood"),
                    );
                    if let Some(i) = inst_mut(ctx, &room, me) {
                        i.comments.push(front::raw_comment(stage, &loc.text));
                    }
                }
            }
        }
        let mut height = None;
        if let Some(h) = fields.get(2).filter(|f| !f.is_na()) {
            let n = front::number(&h.text).or_else(|| {
                let n = front::first_number(&h.text).map(|x| x.0);
                if n.is_some() {
                    d.push(
                        Diagnostic::new(Code::W0701, "read the height from text")
                            .with_primary(h.span, "first number"),
                    );
                }
                n
            });
            match n {
                Some(n) if n.value >= 0.0 && to_cm(&n) <= 1000.0 => {
                    converted(&n, h.span, "cm", d);
                    height = Some(to_cm(&n));
                }
                _ => bad_value(
                    h.span,
                    format!("the height `{}` is not a number of cm from 0 to 1000", h.text),
                    "height left out",
                    "write the height of the bottom of the object in cm, e.g. `160`",
                    d,
                ),
            }
        }
        if let Some(i) = inst_mut(ctx, &room, me) {
            i.above = above;
            i.height_cm = height;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Small objects.

const SMALL_SHAPE: &str = "receptacle-0 (room) | item, quantity, same/varied | ...";

fn small_objects(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "small-objects";
    // Whether each room named had no objects before this answer (then every receptacle the
    // answer names is declared, by the rule of the floor-constraint answer): decided once per
    // room, so that the receptacles declared by earlier lines do not make later ones unknown.
    let mut implicit_rooms: Vec<(String, bool)> = Vec::new();
    for line in start_lines(text, file, d, Stage::SmallObjects) {
        let fields = line.fields();
        if fields.len() < 2 {
            bad_line(&line, "a small-object line has no item".into(), SMALL_SHAPE, d);
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        let head = &fields[0];
        let (rec_name, room_name) = match (head.text.rfind('('), head.text.ends_with(')')) {
            (Some(a), true) => (
                head.text[..a].trim().to_string(),
                Some(head.text[a + 1..head.text.len() - 1].trim().to_string()),
            ),
            _ => (head.text.clone(), None),
        };
        let room = match room_name {
            Some(rn) => resolve_room(ctx, &Field { text: rn, span: head.span }, d),
            None => Some(current_room(ctx, file, d)),
        };
        let Some(room) = room else {
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        };
        let implicit = match implicit_rooms.iter().find(|(r, _)| *r == room) {
            Some(&(_, implicit)) => implicit,
            None => {
                let implicit = all_insts(ctx, &room, None).is_empty();
                implicit_rooms.push((room.clone(), implicit));
                implicit
            }
        };
        let found = find_inst(ctx, &room, &rec_name, None).or_else(|| {
            if implicit {
                declare_inst(ctx, &room, &rec_name, false)
            } else {
                None
            }
        });
        let Some(me) = found else {
            unknown_inst(
                ctx,
                &room,
                &Field { text: rec_name, span: head.span },
                None,
                "receptacle",
                d,
            );
            room_comment(ctx, Some(&room), line.raw_comment(stage));
            continue;
        };
        for f in &fields[1..] {
            if f.is_na() {
                continue;
            }
            let parts: Vec<&str> = f.text.split(',').map(str::trim).collect();
            let mut variance = None;
            let mut count = 1;
            let mut name_end = parts.len();
            if parts.len() >= 2 {
                let last = parts[parts.len() - 1];
                if let Found::Exact(v) | Found::Synonym(v) =
                    lookup(last, VARIANCES, VARIANCE_SYNONYMS)
                {
                    variance = Some(v.to_string());
                    name_end -= 1;
                }
            }
            if name_end >= 2 {
                let q = Field { text: parts[name_end - 1].to_string(), span: f.span };
                match count_field(&q, d) {
                    Some(c) => {
                        count = c.min(20);
                        name_end -= 1;
                    }
                    None => {
                        if let Some(i) = inst_mut(ctx, &room, me) {
                            i.comments.push(front::raw_comment(stage, &f.text));
                        }
                        continue;
                    }
                }
            }
            let name = parts[..name_end].join(", ");
            if name.is_empty() {
                bad_value(
                    f.span,
                    "a small object has no name".into(),
                    "no name",
                    "write `item, quantity, same`",
                    d,
                );
                continue;
            }
            if let Some(i) = inst_mut(ctx, &room, me) {
                i.on_top.push(DOnTop {
                    item: name,
                    count,
                    variance,
                    asset: None,
                    at: None,
                    facing: None,
                });
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Ceiling.

fn ceiling(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "ceiling";
    for line in start_lines(text, file, d, Stage::Ceiling) {
        let fields = line.fields();
        if fields.len() != 2 {
            bad_line(
                &line,
                format!("a ceiling line has {} fields, not 2", fields.len()),
                "room | ceiling object description",
                d,
            );
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        }
        let Some(room) = resolve_room(ctx, &fields[0], d) else {
            ctx.draft.comments.push(line.raw_comment(stage));
            continue;
        };
        if fields[1].is_na() {
            d.push(
                Diagnostic::new(Code::W0706, "a room without a ceiling object")
                    .with_primary(fields[1].span, "ignored"),
            );
            continue;
        }
        let Some(r) = ctx.draft.room_mut(&room) else { continue };
        if r.ceiling.is_some() {
            d.push(
                Diagnostic::new(
                    Code::W0706,
                    format!("a second ceiling object for `{}` was ignored", r.label),
                )
                .with_primary(line.span(), "the first line wins"),
            );
            r.comments.push(line.raw_comment(stage));
            continue;
        }
        r.ceiling = Some(fields[1].text.clone());
    }
}

// ---------------------------------------------------------------------------------------------
// Absolute layout.

fn absolute_layout(text: &str, file: FileId, ctx: &mut ImportContext, d: &mut Diags) {
    let stage = "absolute-layout";
    let room = current_room(ctx, file, d);
    let Some((list, whole)) =
        extract_json::<Vec<serde_json::Value>>(text, file, '[', ']', Stage::AbsoluteLayout, d)
    else {
        room_comment(
            ctx,
            Some(&room),
            front::raw_comment(stage, text.lines().next().unwrap_or("")),
        );
        return;
    };
    let (min_x, min_z) = ctx.draft.room(&room).map_or((0.0, 0.0), |r| {
        r.corners
            .iter()
            .fold((f64::INFINITY, f64::INFINITY), |(a, b), (x, z)| (a.min(*x), b.min(*z)))
    });
    let (min_x, min_z) = if min_x.is_finite() { (min_x, min_z) } else { (0.0, 0.0) };
    let implicit = all_insts(ctx, &room, Some(false)).is_empty();
    let mut list = list;
    if list.len() > MAX_LINES {
        d.push(
            Diagnostic::new(
                Code::E0701,
                format!(
                    "the layout has {} entries; only the first {MAX_LINES} are read",
                    list.len()
                ),
            )
            .with_primary(whole, "too many entries"),
        );
        list.truncate(MAX_LINES);
    }
    for entry in list {
        let get = |v: &serde_json::Value, k: &str| -> Option<serde_json::Value> {
            v.as_object()?.iter().find(|(n, _)| n.eq_ignore_ascii_case(k)).map(|(_, v)| v.clone())
        };
        let name = get(&entry, "object_name").and_then(|v| v.as_str().map(str::to_string));
        let Some(name) = name else {
            bad_value(whole, "a layout entry has no `object_name`".into(), "entry left out", "write `{\"object_name\": \"sofa-0\", \"position\": {\"X\": 100, \"Y\": 50}, \"rotation\": 0}`", d);
            room_comment(ctx, Some(&room), front::raw_comment(stage, &entry.to_string()));
            continue;
        };
        let span = find_span(text, file, &name, whole);
        let found = find_inst(ctx, &room, &name, Some(false)).or_else(|| {
            if implicit {
                declare_inst(ctx, &room, &name, false)
            } else {
                None
            }
        });
        let Some(me) = found else {
            unknown_inst(
                ctx,
                &room,
                &Field { text: name.clone(), span },
                Some(false),
                "floor object",
                d,
            );
            room_comment(ctx, Some(&room), front::raw_comment(stage, &entry.to_string()));
            continue;
        };
        let pos = get(&entry, "position");
        let x = pos.as_ref().and_then(|p| get(p, "x")).as_ref().and_then(json_number);
        let y = pos
            .as_ref()
            .and_then(|p| get(p, "y").or_else(|| get(p, "z")))
            .as_ref()
            .and_then(json_number);
        let rot = get(&entry, "rotation")
            .and_then(|r| json_number(&r).or_else(|| get(&r, "y").as_ref().and_then(json_number)));
        match (x, y) {
            (Some(x), Some(y)) if x.abs() < 100_000.0 && y.abs() < 100_000.0 => {
                let facing = rot.filter(|r| r.abs() < 100_000.0).map(|r| r.rem_euclid(360.0));
                if let Some(i) = inst_mut(ctx, &room, me) {
                    i.at = Some(vec![min_x + x / 100.0, min_z + y / 100.0]);
                    i.facing = facing;
                }
            }
            _ => {
                bad_value(
                    span,
                    format!("the position of `{name}` is not `{{\"X\": cm, \"Y\": cm}}`"),
                    "no position",
                    "write `\"position\": {\"X\": 100, \"Y\": 50}` (cm from the room's min corner)",
                    d,
                );
                room_comment(ctx, Some(&room), front::raw_comment(stage, &entry.to_string()));
            }
        }
    }
}

/// The end of the first `max` bytes of `text`, moved back to a character boundary (a span must
/// never end inside a character).
fn prefix_end(text: &str, max: usize) -> usize {
    let mut end = text.len().min(max);
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    end
}
