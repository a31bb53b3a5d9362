//! The seam between `generate` and `import`: import one answer in the context of the earlier
//! ones, build the whole `.holo` from a transcript, and turn it into a [`Scene`].
//!
//! The context of an answer is rebuilt the way `import::import_transcript` reads a transcript
//! (stages in import order, rooms in first-appearance order, the highest attempt of each), so
//! that the diagnostics a repair prompt lists are the ones `holoc import` would report.

use crate::check::{self, Scene};
use crate::diag::Outcome;
use crate::import::{self, ImportContext, ImportOptions, Stage, Transcript};
use crate::parse;
use crate::source::SourceMap;

/// What the importer found in one answer.
pub(crate) struct Problems {
    /// Every diagnostic (errors and warnings).
    pub count: usize,
    /// One line per error, for the repair prompt: `line 3: expected 4 fields ... (help: ...)`.
    pub errors: Vec<String>,
    /// How many of the errors the floor plan built so far has (overlapping rooms, a door
    /// between rooms that share no wall, a window that cannot be placed…): a plan that fails
    /// will never build, so the run stops when they remain after the repair rounds.
    pub plan_errors: usize,
}

/// The import context after every answer of `transcript`.
fn context_of(transcript: &Transcript, sources: &mut SourceMap) -> ImportContext {
    let mut ctx = ImportContext::new().with_request(transcript.request.clone(), transcript.seed);
    for &stage in Stage::ALL {
        let mut rooms: Vec<Option<&str>> = Vec::new();
        for e in transcript.exchanges.iter().filter(|e| Stage::parse(&e.stage) == Some(stage)) {
            if !rooms.contains(&e.room.as_deref()) {
                rooms.push(e.room.as_deref());
            }
        }
        for room in rooms {
            let Some(exchange) = transcript.latest(stage.as_str(), room) else { continue };
            let file = sources.add(stage.as_str(), exchange.answer.clone());
            ctx.set_room(room);
            ctx = import::import_answer(stage, sources, file, &ctx).value.context;
            ctx.set_room(None);
        }
    }
    ctx
}

/// The errors of one answer, in the context of the exchanges of `context` (other than earlier
/// attempts of the same question).
pub(crate) fn answer_problems(
    stage: &str,
    room: Option<&str>,
    answer: &str,
    context: &Transcript,
) -> Problems {
    let Some(import_stage) = Stage::parse(stage) else {
        return Problems { count: 0, errors: Vec::new(), plan_errors: 0 };
    };
    let mut earlier = context.clone();
    earlier.exchanges.retain(|e| !(e.stage == stage && e.room.as_deref() == room));
    let mut sources = SourceMap::new();
    let mut ctx = context_of(&earlier, &mut sources);
    let file = sources.add("answer", answer);
    ctx.set_room(room);
    let outcome = import::import_answer(import_stage, &sources, file, &ctx);
    let source = sources.get(file);
    let mut errors: Vec<String> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| {
            let place = d
                .primary
                .as_ref()
                .map(|l| format!("line {}: ", source.line_col(l.span.start as usize).line))
                .unwrap_or_default();
            let help = d.help.as_ref().map(|h| format!(" ({h})")).unwrap_or_default();
            format!("{place}{}{help}", d.message)
        })
        .collect();
    let mut plan_errors = 0;
    if errors.is_empty()
        && matches!(import_stage, Stage::FloorPlan | Stage::Doorways | Stage::Windows)
    {
        for d in plan_problems(import_stage, room, answer, &earlier) {
            let help = d.help.as_ref().map(|h| format!(" ({h})")).unwrap_or_default();
            errors.push(format!("in the floor plan this gives: {}{help}", d.message));
            plan_errors += 1;
        }
    }
    Problems { count: outcome.diagnostics.len() + plan_errors, errors, plan_errors }
}

/// The errors of the plan stage on the scene so far with this answer: what `holoc build` would
/// stop on. After the floor-plan answer alone every room is still closed off, so doors and
/// reachability (E0314, E0315) are only judged from the doorways answer on.
fn plan_problems(
    stage: Stage,
    room: Option<&str>,
    answer: &str,
    earlier: &Transcript,
) -> Vec<crate::diag::Diagnostic> {
    let mut with = earlier.clone();
    with.exchanges.push(crate::import::transcript::Exchange {
        stage: stage.as_str().to_string(),
        room: room.map(str::to_string),
        attempt: 0,
        prompt: String::new(),
        answer: answer.to_string(),
        parameters: None,
        started_ms: 0,
        duration_ms: 0,
        usage: None,
        diagnostics: 0,
    });
    let scene = scene(&with);
    if scene.rooms.is_empty() {
        return Vec::new();
    }
    let planned = crate::plan::plan_with(
        &scene,
        crate::resolve::structure::StructureCatalog::builtin(),
        crate::plan::PlanOptions::default(),
    );
    planned
        .diagnostics
        .into_iter()
        .filter(crate::diag::Diagnostic::is_error)
        .filter(|d| {
            stage != Stage::FloorPlan
                || !matches!(d.code, crate::diag::Code::E0314 | crate::diag::Code::E0315)
        })
        .collect()
}

/// The prompt of an exchange that records a local geometric repair (no model was asked); the
/// cost summary counts these apart from model calls.
pub(crate) const LOCAL_REPAIR_PROMPT: &str = "holoc: geometric repair (W0307)";

/// Whether an exchange records a local geometric repair rather than a model's answer.
pub(crate) fn is_local_repair(exchange: &crate::import::transcript::Exchange) -> bool {
    exchange.prompt.starts_with(LOCAL_REPAIR_PROMPT)
}

/// The plan errors of an answer of `stage` (floor plan, doorways or windows) that the geometric
/// repair (`plan::repair`) fixes, seeing every room, door and window known so far with this
/// answer: the floor-plan answer in the paper's format with the repaired corners, and what
/// moved; `None` when the repair cannot make the plan build. After the doorways answer, a door
/// between rooms drawn apart pulls them together.
pub(crate) fn repair_floor_plan(
    stage: Stage,
    answer: &str,
    earlier: &Transcript,
) -> Option<(String, Vec<String>)> {
    let mut with = earlier.clone();
    with.exchanges.retain(|e| e.stage != stage.as_str());
    with.exchanges.push(crate::import::transcript::Exchange {
        stage: stage.as_str().to_string(),
        room: None,
        attempt: 0,
        prompt: String::new(),
        answer: answer.to_string(),
        parameters: None,
        started_ms: 0,
        duration_ms: 0,
        usage: None,
        diagnostics: 0,
    });
    let scene = scene(&with);
    repair_scene(&scene, stage == Stage::FloorPlan)
}

/// A plan that builds but leaves gaps between rooms that face each other (W0308), joined by
/// the geometric repair with every door and window of the transcript known: the floor-plan
/// answer with the repaired corners, and what moved; `None` when there is no gap or the repair
/// cannot join them without an error.
pub(crate) fn join_gaps(transcript: &Transcript) -> Option<(String, Vec<String>)> {
    let scene = scene(transcript);
    if scene.rooms.is_empty() {
        return None;
    }
    let catalog = crate::resolve::structure::StructureCatalog::builtin();
    let planned = crate::plan::plan(&scene, catalog).diagnostics;
    if planned.iter().any(crate::diag::Diagnostic::is_error)
        || !planned.iter().any(|d| d.code == crate::diag::Code::W0308)
    {
        return None;
    }
    repair_scene(&scene, false)
}

/// The scene's floor plan repaired by geometry, as a floor-plan answer, when the repaired plan
/// has no error (`closed_off`: after the floor plan alone, where every room is still closed off,
/// a missing exterior door or an unreachable room does not count).
fn repair_scene(scene: &Scene, closed_off: bool) -> Option<(String, Vec<String>)> {
    if scene.rooms.is_empty() {
        return None;
    }
    let catalog = crate::resolve::structure::StructureCatalog::builtin();
    let repaired = crate::plan::repair::repair(scene, catalog);
    if !repaired.value.changed {
        return None;
    }
    let after = crate::plan::repair::apply(scene, &repaired.value);
    // After the floor plan alone every room is closed off: doors are judged from the doorways
    // answer on.
    let still = crate::plan::plan(&after, catalog).diagnostics.into_iter().any(|d| {
        d.is_error()
            && (!closed_off
                || !matches!(d.code, crate::diag::Code::E0314 | crate::diag::Code::E0315))
    });
    if still {
        return None;
    }
    let num = |v: f64| {
        let r = (v * 1000.0).round() / 1000.0;
        format!("{}", if r == 0.0 { 0.0 } else { r })
    };
    let lines: Vec<String> = after
        .rooms
        .iter()
        .map(|r| {
            let corners: Vec<String> =
                r.corners.iter().map(|p| format!("({}, {})", num(p[0]), num(p[1]))).collect();
            format!(
                "{} | {} | {} | [{}]",
                r.label,
                r.floor_design.as_deref().unwrap_or("light oak wood floor"),
                r.wall_design.as_deref().unwrap_or("white drywall"),
                corners.join(", ")
            )
        })
        .collect();
    let notes = repaired.diagnostics.iter().map(|d| d.message.clone()).collect();
    Some((lines.join("\n"), notes))
}

/// The whole `.holo` text of a transcript, canonical, with the diagnostics of importing and
/// checking it. The answers and the `.holo` text are added to `sources`.
pub(crate) fn build(transcript: &Transcript, sources: &mut SourceMap) -> Outcome<String> {
    let imported = import::import_transcript(transcript, sources, &ImportOptions::default());
    let text = crate::fmt::print(&imported.value);
    let mut diagnostics = imported.diagnostics;
    let file = sources.add("<generated>.holo", text.clone());
    let parsed = parse::parse(sources, file);
    diagnostics.extend(parsed.diagnostics);
    diagnostics.extend(check::check(&parsed.value).diagnostics);
    Outcome::new(text, diagnostics)
}

/// The scene of a transcript (possibly partial); used to fill in the next prompts.
pub(crate) fn scene(transcript: &Transcript) -> Scene {
    let mut sources = SourceMap::new();
    let imported = import::import_transcript(transcript, &mut sources, &ImportOptions::default());
    let parsed = parse::parse_str(&crate::fmt::print(&imported.value));
    check::check(&parsed.value).value
}
