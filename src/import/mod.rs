//! The `import` stage: raw model answers → a `.holo` syntax tree.
//!
//! Three entry points share one tolerant reader:
//! - [`import_answer`] reads one answer of one [`Stage`] in the context of the answers read
//!   before it (the `generate` driver uses it to get diagnostics for repair prompts);
//! - [`import_transcript`] rebuilds a whole scene from a holoc [`Transcript`];
//! - [`import_holodeck_scene`] rebuilds one from an original Holodeck scene JSON, optionally
//!   pinning the solved layout ([`ImportOptions::keep_layout`]); [`import_holodeck_scene_file`]
//!   does the same for a scene read from a file and points its diagnostics at the file's lines.
//!
//! Every unusable line becomes an `E07xx` error with a span into the answer and is kept in the
//! output as a `// raw <stage>: …` comment; tolerated noise becomes a `W07xx` warning that says
//! what was done. Nothing panics on any input. The formats, tolerances, synonym tables and the
//! id rule are documented in `book/src/reference/import.md`.

mod draft;
mod front;
mod grammar;
mod locate;
mod scene;
mod stages;
pub mod transcript;

pub use scene::{import_holodeck_scene, import_holodeck_scene_file, import_transcript};
pub use stages::MAX_JSON_NESTING;
pub use transcript::{Exchange, ModelInfo, Totals, Transcript, Usage};

use crate::ast;
use crate::diag::{Code, Diagnostic, Outcome};
use crate::source::{FileId, SourceMap, Span};
use draft::Draft;

/// One kind of model answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// `name | floor design | wall design | [(x, y), …]` per room.
    FloorPlan,
    /// A bare number of metres.
    WallHeight,
    /// `room 1 | room 2 | doorway/doorframe/open | single/double | style`.
    Doorways,
    /// `room | direction | type | (w, h) | quantity | sill cm`.
    Windows,
    /// The JSON object selection of one room.
    Objects,
    /// The pipe-format object selection (`room | location | category | description | n, same`).
    ObjectsPipe,
    /// `object-0 | edge | near, sofa-0 | …` for one room.
    FloorConstraints,
    /// `painting-0 | above, sofa-0 | 160` for one room.
    WallConstraints,
    /// `receptacle-0 (room) | item, quantity, same | …`.
    SmallObjects,
    /// `room | ceiling object description`.
    Ceiling,
    /// A JSON list of `{object_name, position {X, Y} cm, rotation}` for one room.
    AbsoluteLayout,
}

impl Stage {
    /// Every stage, in the order a scene is generated.
    pub const ALL: &'static [Stage] = &[
        Stage::WallHeight,
        Stage::FloorPlan,
        Stage::Doorways,
        Stage::Windows,
        Stage::Objects,
        Stage::ObjectsPipe,
        Stage::FloorConstraints,
        Stage::WallConstraints,
        Stage::SmallObjects,
        Stage::Ceiling,
        Stage::AbsoluteLayout,
    ];

    /// The stage's name, as used on the command line and in transcripts.
    pub fn as_str(self) -> &'static str {
        match self {
            Stage::FloorPlan => "floor-plan",
            Stage::WallHeight => "wall-height",
            Stage::Doorways => "doorways",
            Stage::Windows => "windows",
            Stage::Objects => "objects",
            Stage::ObjectsPipe => "objects-pipe",
            Stage::FloorConstraints => "floor-constraints",
            Stage::WallConstraints => "wall-constraints",
            Stage::SmallObjects => "small-objects",
            Stage::Ceiling => "ceiling",
            Stage::AbsoluteLayout => "absolute-layout",
        }
    }

    /// Reads a stage name (case-insensitive; `_` and `-` are the same).
    pub fn parse(text: &str) -> Option<Stage> {
        let t = text.trim().to_ascii_lowercase().replace('_', "-");
        Stage::ALL.iter().copied().find(|s| s.as_str() == t)
    }

    /// Whether the stage's answer is about one room (the exchange's `room`).
    pub fn per_room(self) -> bool {
        matches!(
            self,
            Stage::Objects
                | Stage::FloorConstraints
                | Stage::WallConstraints
                | Stage::AbsoluteLayout
        )
    }
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Options of a whole-scene import.
#[derive(Clone, Debug, Default)]
pub struct ImportOptions {
    /// Pin the solved poses of an original scene (`asset`, `at`, `facing`).
    pub keep_layout: bool,
}

/// What the answers read so far say: rooms, doors, objects. Feed it to the next
/// [`import_answer`] so that names can be checked against the earlier answers.
#[derive(Clone, Debug, Default)]
pub struct ImportContext {
    draft: Draft,
    room: Option<String>,
}

impl ImportContext {
    /// An empty context: every name a stage mentions is accepted and declared on the fly.
    pub fn new() -> ImportContext {
        ImportContext::default()
    }

    /// Sets the English request and the seed written in the `scene` block.
    #[must_use]
    pub fn with_request(mut self, request: impl Into<String>, seed: u64) -> ImportContext {
        self.draft.request = Some(request.into());
        self.draft.seed = seed;
        self
    }

    /// Sets the room (its label as in the floor plan) that per-room answers are about.
    pub fn set_room(&mut self, label: Option<&str>) {
        self.room = label.map(str::to_string);
    }

    /// The room labels declared so far, in order.
    pub fn room_labels(&self) -> Vec<String> {
        self.draft.room_names()
    }

    /// The floor instance names of a room (`sofa-0`, `chair-1`, …), in declaration order.
    pub fn floor_instances(&self, room_label: &str) -> Vec<String> {
        self.instances(room_label, false)
    }

    /// The wall instance names of a room.
    pub fn wall_instances(&self, room_label: &str) -> Vec<String> {
        self.instances(room_label, true)
    }

    fn instances(&self, room_label: &str, wall: bool) -> Vec<String> {
        self.draft
            .find_room(room_label)
            .map(|r| {
                r.objects
                    .iter()
                    .filter(|o| o.wall == wall)
                    .flat_map(draft::DObject::instance_names)
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The scene so far as a `.holo` syntax tree (print it with `fmt::print`).
    pub fn file(&self) -> ast::File {
        self.draft.to_ast(Span::new(FileId(0), 0, 0))
    }
}

/// The result of importing one answer.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The `.holo` the context holds after this answer (for a stand-alone import, only what
    /// this answer says).
    pub fragment: ast::File,
    /// The context to give to the next answer.
    pub context: ImportContext,
}

/// Imports one answer of `stage` (the text of `file`) in the context of the earlier answers.
/// Always returns a value; problems are diagnostics with spans into `file`.
pub fn import_answer(
    stage: Stage,
    sources: &SourceMap,
    file: FileId,
    context: &ImportContext,
) -> Outcome<Imported> {
    let mut ctx = context.clone();
    let text = sources.try_get(file).map_or("", |f| f.text.as_str());
    let mut diags = Vec::new();
    stages::run(stage, text, file, &mut ctx, &mut diags);
    let fragment = ctx.draft.to_ast(Span::new(file, 0, 0));
    crate::diag::sort(&mut diags);
    Outcome::new(Imported { fragment, context: ctx }, diags)
}

/// The kinds of decoration the front removes; each becomes one W0701 per answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Noise {
    Numbering,
    Bullet,
    Bold,
    CodeFence,
    Prose,
    Heading,
    TrailingPeriod,
}

impl Noise {
    fn what(self) -> &'static str {
        match self {
            Noise::Numbering => "removed line numbering (`1.`, `2)`)",
            Noise::Bullet => "removed list bullets",
            Noise::Bold => "removed `*` and backtick markup",
            Noise::CodeFence => "ignored code fences",
            Noise::Prose => "ignored prose lines that are not part of the list",
            Noise::Heading => "removed Markdown headings",
            Noise::TrailingPeriod => "removed trailing periods",
        }
    }
}

/// The W0701 warnings for the noise of one answer.
pub(crate) fn noise_diagnostics(noise: &[(Noise, Span, usize)], out: &mut Vec<Diagnostic>) {
    for (n, span, count) in noise {
        let mut d = Diagnostic::new(Code::W0701, format!("{} ", n.what()).trim_end().to_string())
            .with_primary(*span, "first seen here");
        if *count > 1 {
            d = d.with_note(format!("{count} lines"));
        }
        out.push(d);
    }
}
