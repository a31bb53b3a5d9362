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
        return Problems { count: 0, errors: Vec::new() };
    };
    let mut earlier = context.clone();
    earlier.exchanges.retain(|e| !(e.stage == stage && e.room.as_deref() == room));
    let mut sources = SourceMap::new();
    let mut ctx = context_of(&earlier, &mut sources);
    let file = sources.add("answer", answer);
    ctx.set_room(room);
    let outcome = import::import_answer(import_stage, &sources, file, &ctx);
    let source = sources.get(file);
    let errors = outcome
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
    Problems { count: outcome.diagnostics.len(), errors }
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
