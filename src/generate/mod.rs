//! The `generate` stage: English request → the model's answers → `.holo` text.
//!
//! [`generate`] asks the questions of the pipeline in order (floor plan, wall height, doorways,
//! windows; then, for every room in parallel, objects, floor constraints, wall constraints and
//! small objects; then ceiling objects). Each prompt is filled from the scene built out of the
//! earlier answers. Each answer is imported at once; when the importer finds errors, the
//! question is asked again with the problems listed (a repair round). Every exchange is recorded
//! in a [`Transcript`], from which `holoc import` rebuilds the same `.holo` without any network.
//!
//! **Invariant:** the `.holo` text depends only on the answers, never on timing: exchanges are
//! recorded in pipeline order (rooms in plan order) whatever order they finished in. Timings
//! exist only in the transcript and the accounting.
//!
//! **Invariant:** the model is reached only through the [`Llm`] trait; replaying a transcript
//! is just another implementation of it ([`ReplayLlm`]).

mod bridge;
pub mod client;
mod context;
pub mod prompts;

pub use client::{
    HttpLlm, HttpOptions, Llm, LlmAnswer, LlmError, LlmRequest, ModelInfo, RecordedAnswer,
    ReplayLlm, Usage,
};
pub use prompts::{Prompts, Template};

use crate::check::Scene;
use crate::diag::{Code, Diagnostic, Outcome};
use crate::import::transcript::{self, Exchange, Totals, Transcript};
use crate::source::{FileId, SourceMap};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The questions, in pipeline order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// Rooms, designs and corners.
    FloorPlan,
    /// Wall height in metres.
    WallHeight,
    /// Connections.
    Doorways,
    /// Windows.
    Windows,
    /// Object selection, per room.
    Objects,
    /// Floor-object constraints, per room.
    FloorConstraints,
    /// Wall-object placement, per room.
    WallConstraints,
    /// Small objects on receptacles, per room.
    SmallObjects,
    /// Ceiling objects.
    Ceiling,
}

impl Stage {
    /// Every stage, in pipeline order.
    pub const ALL: [Stage; 9] = [
        Stage::FloorPlan,
        Stage::WallHeight,
        Stage::Doorways,
        Stage::Windows,
        Stage::Objects,
        Stage::FloorConstraints,
        Stage::WallConstraints,
        Stage::SmallObjects,
        Stage::Ceiling,
    ];

    /// The name used in transcripts and on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            Stage::FloorPlan => "floor-plan",
            Stage::WallHeight => "wall-height",
            Stage::Doorways => "doorways",
            Stage::Windows => "windows",
            Stage::Objects => "objects",
            Stage::FloorConstraints => "floor-constraints",
            Stage::WallConstraints => "wall-constraints",
            Stage::SmallObjects => "small-objects",
            Stage::Ceiling => "ceiling",
        }
    }

    /// The template of the stage's question.
    pub fn template(self) -> Template {
        match self {
            Stage::FloorPlan => Template::FloorPlan,
            Stage::WallHeight => Template::WallHeight,
            Stage::Doorways => Template::Doorways,
            Stage::Windows => Template::Windows,
            Stage::Objects => Template::Objects,
            Stage::FloorConstraints => Template::FloorConstraints,
            Stage::WallConstraints => Template::WallConstraints,
            Stage::SmallObjects => Template::SmallObjects,
            Stage::Ceiling => Template::Ceiling,
        }
    }

    /// Whether the stage asks one question per room.
    pub fn per_room(self) -> bool {
        matches!(
            self,
            Stage::Objects | Stage::FloorConstraints | Stage::WallConstraints | Stage::SmallObjects
        )
    }

    /// Looks a stage up by its name.
    pub fn parse(name: &str) -> Option<Stage> {
        Stage::ALL.into_iter().find(|s| s.as_str() == name.trim())
    }
}

/// What to generate.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The English request, e.g. "a 1b1b apartment of a researcher who has a cat".
    pub text: String,
    /// The seed written into the scene (and passed to the model).
    pub seed: u64,
}

/// Something told about the progress of a run (the CLI draws it; tests may record it).
#[derive(Clone, Debug, PartialEq)]
pub enum ProgressEvent {
    /// A stage starts; `rooms` is the number of questions it will ask.
    StageStarted {
        /// The stage.
        stage: Stage,
        /// How many questions (1, or one per room).
        questions: usize,
    },
    /// A question is being sent.
    Asking {
        /// The stage.
        stage: Stage,
        /// The room, for per-room stages.
        room: Option<String>,
        /// 0, or the repair round.
        attempt: u32,
    },
    /// An answer arrived and was imported.
    Answered {
        /// The stage.
        stage: Stage,
        /// The room, for per-room stages.
        room: Option<String>,
        /// 0, or the repair round.
        attempt: u32,
        /// Errors the importer found in it.
        errors: usize,
    },
    /// A stage is done.
    StageFinished {
        /// The stage.
        stage: Stage,
    },
}

/// Receives progress events, possibly from several threads.
pub trait Progress: Sync {
    /// Called for every event.
    fn event(&self, event: &ProgressEvent);
}

/// How to run the pipeline.
#[derive(Clone)]
pub struct GenerateOptions {
    /// How many per-room questions may be in flight at once (at least 1).
    pub jobs: usize,
    /// How many times an answer with errors is asked again.
    pub repair_rounds: u32,
    /// Template texts that replace the embedded ones: name shown in diagnostics and text.
    pub prompt_overrides: BTreeMap<Template, (String, String)>,
    /// Ask for a plan of one room only.
    pub single_room: bool,
    /// Ask the small-objects question.
    pub small_objects: bool,
    /// Ask the ceiling question.
    pub ceiling: bool,
    /// Where progress events go (the CLI draws them on stderr); `None` for silence.
    pub progress: Option<Arc<dyn Progress + Send>>,
}

impl std::fmt::Debug for GenerateOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GenerateOptions")
            .field("jobs", &self.jobs)
            .field("repair_rounds", &self.repair_rounds)
            .field("prompt_overrides", &self.prompt_overrides.keys().collect::<Vec<_>>())
            .field("single_room", &self.single_room)
            .field("small_objects", &self.small_objects)
            .field("ceiling", &self.ceiling)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl Default for GenerateOptions {
    fn default() -> Self {
        GenerateOptions {
            jobs: 4,
            repair_rounds: 2,
            prompt_overrides: BTreeMap::new(),
            single_room: false,
            small_objects: true,
            ceiling: true,
            progress: None,
        }
    }
}

/// Calls, tokens and time spent on one stage.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageCost {
    /// The stage name.
    pub stage: String,
    /// Requests the model answered.
    pub calls: u64,
    /// Local geometric repairs recorded under the stage (no model asked).
    pub repairs: u64,
    /// Prompt tokens.
    pub prompt_tokens: u64,
    /// Answer tokens.
    pub completion_tokens: u64,
    /// Seconds spent waiting for the model (summed over parallel calls).
    pub seconds: f64,
}

/// The result of a run: the `.holo` text, the transcript and the accounting. With errors, the
/// text may be empty or partial, but the transcript holds every exchange that happened.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The scene, canonical `.holo` text.
    pub holo: String,
    /// Every exchange with the model.
    pub transcript: Transcript,
    /// The files diagnostics point into (templates, answers, the `.holo` text).
    pub sources: SourceMap,
    /// Cost per stage, in pipeline order (stages that asked nothing are left out).
    pub costs: Vec<StageCost>,
    /// The questions (stage, room) whose last answer still had errors after every repair
    /// round: a batch job that resumes asks them again instead of reusing their answers.
    pub failed_questions: Vec<(String, Option<String>)>,
}

/// Runs the whole pipeline against a model.
pub fn generate(request: &Request, llm: &dyn Llm, options: &GenerateOptions) -> Outcome<Generated> {
    let mut sources = SourceMap::new();
    let overrides: BTreeMap<Template, FileId> = options
        .prompt_overrides
        .iter()
        .map(|(t, (name, text))| (*t, sources.add(name.clone(), text.clone())))
        .collect();
    let prompts = Prompts::load(&mut sources, &overrides);
    let info = llm.info();
    let mut run = Run {
        request,
        llm,
        options,
        progress: options.progress.as_deref().map(|p| p as &dyn Progress),
        prompts: prompts.value,
        clock: Instant::now(),
        cancelled: AtomicBool::new(false),
        transcript: Transcript {
            request: request.text.clone(),
            seed: request.seed,
            model: Some(transcript::ModelInfo {
                base_url: info.base_url.clone(),
                model: info.model.clone(),
                temperature: info.temperature,
            }),
            ..Transcript::default()
        },
        parameters: info.parameters,
        diagnostics: prompts.diagnostics,
        failed_questions: Vec::new(),
    };
    if run.diagnostics.iter().any(Diagnostic::is_error) {
        return run.finish(sources);
    }
    run.pipeline();
    run.finish(sources)
}

/// The state of one run.
struct Run<'a> {
    request: &'a Request,
    llm: &'a dyn Llm,
    options: &'a GenerateOptions,
    progress: Option<&'a dyn Progress>,
    prompts: Prompts,
    clock: Instant,
    cancelled: AtomicBool,
    transcript: Transcript,
    parameters: BTreeMap<String, Value>,
    diagnostics: Vec<Diagnostic>,
    failed_questions: Vec<(String, Option<String>)>,
}

/// The exchanges of one question (first try and repairs) and how it ended.
struct Asked {
    exchanges: Vec<Exchange>,
    diagnostics: Vec<Diagnostic>,
    failed: bool,
    /// The last answer still had errors after every repair round.
    gave_up: bool,
}

impl Run<'_> {
    fn tell(&self, event: &ProgressEvent) {
        if let Some(p) = self.progress {
            p.event(event);
        }
    }

    fn requirements(&self, stage: Stage) -> String {
        match stage {
            Stage::FloorPlan if self.options.single_room => "only one room is needed".to_string(),
            Stage::Windows => "only one wall of each room should have windows".to_string(),
            _ => "none".to_string(),
        }
    }

    /// The scene built from the exchanges so far (plus `extra`).
    fn scene(&self, extra: &[Exchange]) -> Scene {
        let mut transcript = self.transcript.clone();
        transcript.exchanges.extend_from_slice(extra);
        bridge::scene(&transcript)
    }

    /// The values of every placeholder of a stage's template.
    fn values(
        &self,
        stage: Stage,
        scene: &Scene,
        room: Option<&crate::check::Room>,
    ) -> BTreeMap<&'static str, String> {
        let mut values = BTreeMap::new();
        values.insert("request", self.request.text.clone());
        values.insert("requirements", self.requirements(stage));
        values.insert("rooms", context::rooms(scene));
        values.insert("room_sizes", context::room_sizes(scene));
        values.insert("room_pairs", context::room_pairs(scene));
        values.insert("walls", context::window_walls(scene));
        values.insert("wall_height_cm", context::centimetres(scene.wall_height_m));
        if let Some(room) = room {
            values.insert("room", room.label.clone());
            values.insert("room_size", context::room_size_cm(scene, room));
            values.insert("objects", context::floor_objects(scene, room));
            values.insert("floor_objects", context::floor_objects(scene, room));
            values.insert("wall_objects", context::wall_objects(scene, room));
            values.insert("receptacles", context::receptacles(scene, room));
        }
        values
    }

    /// Asks one question, with repair rounds. `base` is the transcript the answer is imported
    /// against (with the room's own earlier exchanges for per-room stages).
    fn ask(
        &self,
        stage: Stage,
        room: Option<&str>,
        values: &BTreeMap<&'static str, String>,
        base: &[Exchange],
    ) -> Asked {
        let prompt = self.prompts.render(stage.template(), values);
        let used: BTreeMap<&str, &String> = values
            .iter()
            .filter(|(name, _)| stage.template().placeholders().contains(name))
            .map(|(name, value)| (*name, value))
            .collect();
        let parameters: Value = json!({
            "template": stage.template().file_name(),
            "values": used,
            "sampling": self.parameters,
        });
        let mut asked =
            Asked { exchanges: Vec::new(), diagnostics: Vec::new(), failed: false, gave_up: false };
        let mut previous: Option<(String, Vec<String>)> = None;
        for attempt in 0..=self.options.repair_rounds {
            if self.cancelled.load(Ordering::SeqCst) {
                asked.failed = true;
                return asked;
            }
            let text = match &previous {
                None => prompt.clone(),
                Some((answer, problems)) => {
                    let repair = BTreeMap::from([
                        ("prompt", prompt.trim_end().to_string()),
                        ("answer", answer.trim().to_string()),
                        (
                            "problems",
                            problems
                                .iter()
                                .map(|p| format!("- {p}"))
                                .collect::<Vec<_>>()
                                .join("\n"),
                        ),
                    ]);
                    self.prompts.render(Template::Repair, &repair)
                }
            };
            self.tell(&ProgressEvent::Asking { stage, room: room.map(str::to_string), attempt });
            let started = self.clock.elapsed();
            let result = self.llm.complete(&LlmRequest {
                stage: stage.as_str(),
                room,
                attempt,
                prompt: &text,
            });
            let duration = self.clock.elapsed().saturating_sub(started);
            let answer = match result {
                Ok(answer) => answer,
                Err(error) => {
                    self.cancelled.store(true, Ordering::SeqCst);
                    let mut d = error.to_diagnostic();
                    let room_note = room.map(|r| format!(", room `{r}`")).unwrap_or_default();
                    let which = if attempt == 0 {
                        "its first ask".to_string()
                    } else {
                        format!("repair round {attempt}")
                    };
                    d = d.with_note(format!(
                        "while asking stage `{}`{room_note}, {which}",
                        stage.as_str()
                    ));
                    asked.diagnostics.push(d);
                    asked.failed = true;
                    return asked;
                }
            };
            let mut exchange = Exchange {
                stage: stage.as_str().to_string(),
                room: room.map(str::to_string),
                attempt,
                prompt: text,
                answer: answer.text.clone(),
                parameters: Some(parameters.clone()),
                started_ms: started.as_millis() as u64,
                duration_ms: duration.as_millis() as u64,
                usage: Some(transcript::Usage {
                    prompt_tokens: answer.usage.prompt_tokens,
                    completion_tokens: answer.usage.completion_tokens,
                }),
                diagnostics: 0,
            };
            let mut context = self.transcript.clone();
            context.exchanges.extend_from_slice(base);
            context.exchanges.extend(asked.exchanges.iter().cloned());
            let found = bridge::answer_problems(stage.as_str(), room, &answer.text, &context);
            exchange.diagnostics = found.count as u32;
            asked.exchanges.push(exchange);
            self.tell(&ProgressEvent::Answered {
                stage,
                room: room.map(str::to_string),
                attempt,
                errors: found.errors.len(),
            });
            let what = match room {
                Some(r) => format!("the {} answer for room `{r}`", stage.as_str()),
                None => format!("the {} answer", stage.as_str()),
            };
            // A plan that only fails on its geometry is repaired by moving corners (no second
            // request). The floor plan is repaired on its own answer; a doorways or windows
            // answer whose doors need rooms that share a wall is repaired with every room, door
            // and window known, so that a door pulls its rooms together. The repaired floor
            // plan is recorded as the next attempt of the floor-plan question.
            if matches!(stage, Stage::FloorPlan | Stage::Doorways | Stage::Windows)
                && found.plan_errors > 0
                && found.plan_errors == found.errors.len()
            {
                let started_ms = exchange_started(&asked.exchanges);
                if let Some(repaired) =
                    Self::repair_locally(stage, &answer.text, &context, attempt, started_ms)
                {
                    let mut d = Diagnostic::new(
                        Code::W0307,
                        if stage == Stage::FloorPlan {
                            format!("{what} overlapped or left gaps; its corners were moved so that it builds")
                        } else {
                            format!("{what} needs rooms the floor plan drew apart; the floor plan's corners were moved so that it builds")
                        },
                    )
                    .with_help("review the corners in the `.holo` file");
                    for m in repaired.1 {
                        d = d.with_note(m);
                    }
                    asked.exchanges.push(repaired.0);
                    asked.diagnostics.push(d);
                    return asked;
                }
            }
            if found.errors.is_empty() {
                if attempt > 0 {
                    asked.diagnostics.push(Diagnostic::new(
                        Code::W0801,
                        format!("{what} had errors; repair round {attempt} fixed it"),
                    ));
                }
                return asked;
            }
            if attempt == self.options.repair_rounds {
                let n = found.errors.len();
                let mut d = Diagnostic::new(
                    Code::E0809,
                    format!(
                        "{what} still has {n} error{} after {attempt} repair round{}",
                        if n == 1 { "" } else { "s" },
                        if attempt == 1 { "" } else { "s" }
                    ),
                )
                .with_help("raise `--repair-rounds`, try a stronger model, or edit the `.holo` file by hand");
                for problem in found.errors.iter().take(5) {
                    d = d.with_note(problem.clone());
                }
                asked.diagnostics.push(d);
                asked.gave_up = true;
                // A floor plan that cannot be read, or a plan that fails, will never build:
                // no later question is asked.
                if found.plan_errors > 0 || stage == Stage::FloorPlan {
                    asked.failed = true;
                }
                return asked;
            }
            previous = Some((answer.text, found.errors));
        }
        asked
    }

    /// The floor plan repaired by geometry for an answer of `stage` whose only errors are the
    /// plan's: the exchange that records it (the next attempt of the floor-plan question, no
    /// model asked) and what moved.
    fn repair_locally(
        stage: Stage,
        answer: &str,
        context: &Transcript,
        attempt: u32,
        started_ms: u64,
    ) -> Option<(Exchange, Vec<String>)> {
        let import_stage = crate::import::Stage::parse(stage.as_str())?;
        let (text, moves) = bridge::repair_floor_plan(import_stage, answer, context)?;
        let latest = context.latest(Stage::FloorPlan.as_str(), None);
        let next = if stage == Stage::FloorPlan {
            attempt + 1
        } else {
            latest.map_or(0, |e| e.attempt + 1)
        };
        let from = if stage == Stage::FloorPlan {
            format!("of attempt {attempt}")
        } else {
            format!("with the {} answer (attempt {attempt})", stage.as_str())
        };
        let exchange = Exchange {
            stage: Stage::FloorPlan.as_str().to_string(),
            room: None,
            attempt: next,
            prompt: format!("{} {from}; no model was asked", bridge::LOCAL_REPAIR_PROMPT),
            answer: text,
            parameters: None,
            started_ms,
            duration_ms: 0,
            usage: None,
            diagnostics: 0,
        };
        Some((exchange, moves))
    }

    /// Once the doorways and windows are known: a floor plan that builds but leaves gaps
    /// between rooms that face each other (W0308) has them joined by the geometric repair,
    /// recorded as the next floor-plan attempt like any local repair (no model is asked).
    fn join_gaps(&mut self) {
        let Some((text, moves)) = bridge::join_gaps(&self.transcript) else { return };
        let latest = self.transcript.latest(Stage::FloorPlan.as_str(), None);
        let exchange = Exchange {
            stage: Stage::FloorPlan.as_str().to_string(),
            room: None,
            attempt: latest.map_or(0, |e| e.attempt + 1),
            prompt: format!(
                "{} joining rooms that faced each other across a gap (W0308); no model was asked",
                bridge::LOCAL_REPAIR_PROMPT
            ),
            answer: text,
            parameters: None,
            started_ms: exchange_started(&self.transcript.exchanges),
            duration_ms: 0,
            usage: None,
            diagnostics: 0,
        };
        self.transcript.exchanges.push(exchange);
        let mut d = Diagnostic::new(
            Code::W0307,
            "the floor plan left gaps between rooms that face each other; their walls were joined",
        )
        .with_help("review the corners in the `.holo` file");
        for m in moves {
            d = d.with_note(m);
        }
        self.diagnostics.push(d);
    }

    /// Records a finished question in the transcript and the diagnostics.
    fn record(&mut self, asked: Asked) -> bool {
        if asked.gave_up {
            if let Some(last) = asked.exchanges.last() {
                self.failed_questions.push((last.stage.clone(), last.room.clone()));
            }
        }
        self.transcript.exchanges.extend(asked.exchanges);
        self.diagnostics.extend(asked.diagnostics);
        !asked.failed
    }

    fn global(&mut self, stage: Stage) -> bool {
        self.tell(&ProgressEvent::StageStarted { stage, questions: 1 });
        let scene = self.scene(&[]);
        let values = self.values(stage, &scene, None);
        let asked = self.ask(stage, None, &values, &[]);
        let ok = self.record(asked);
        self.tell(&ProgressEvent::StageFinished { stage });
        ok
    }

    fn pipeline(&mut self) {
        for stage in [Stage::FloorPlan, Stage::WallHeight, Stage::Doorways, Stage::Windows] {
            if !self.global(stage) {
                return;
            }
        }
        self.join_gaps();
        if !self.rooms() {
            return;
        }
        if self.options.ceiling {
            self.global(Stage::Ceiling);
        }
    }

    /// The per-room stages: each room runs its own chain of questions; up to `jobs` rooms at
    /// once. Results are recorded in room order.
    fn rooms(&mut self) -> bool {
        let scene = self.scene(&[]);
        let labels: Vec<String> = scene.rooms.iter().map(|r| r.label.clone()).collect();
        let mut stages = vec![Stage::Objects, Stage::FloorConstraints, Stage::WallConstraints];
        if self.options.small_objects {
            stages.push(Stage::SmallObjects);
        }
        for &stage in &stages {
            self.tell(&ProgressEvent::StageStarted { stage, questions: labels.len() });
        }
        let next = AtomicUsize::new(0);
        let results: Mutex<BTreeMap<usize, Vec<Asked>>> = Mutex::new(BTreeMap::new());
        let jobs = self.options.jobs.clamp(1, labels.len().max(1));
        let this = &*self;
        std::thread::scope(|scope| {
            for _ in 0..jobs {
                scope.spawn(|| loop {
                    let index = next.fetch_add(1, Ordering::SeqCst);
                    let Some(label) = labels.get(index) else { break };
                    let done = this.room_chain(label, &stages);
                    if let Ok(mut map) = results.lock() {
                        map.insert(index, done);
                    }
                });
            }
        });
        let results = match results.into_inner() {
            Ok(map) => map,
            Err(poisoned) => poisoned.into_inner(),
        };
        let mut ok = true;
        for (_, asked) in results {
            for a in asked {
                ok &= self.record(a);
            }
        }
        for &stage in &stages {
            self.tell(&ProgressEvent::StageFinished { stage });
        }
        ok
    }

    fn room_chain(&self, label: &str, stages: &[Stage]) -> Vec<Asked> {
        let mut done: Vec<Asked> = Vec::new();
        let mut own: Vec<Exchange> = Vec::new();
        for &stage in stages {
            let scene = self.scene(&own);
            let Some(room) = scene.rooms.iter().find(|r| r.label == label) else { break };
            let skip = match stage {
                Stage::FloorConstraints | Stage::SmallObjects => {
                    !context::has_floor_objects(&scene, room)
                }
                Stage::WallConstraints => !context::has_wall_objects(&scene, room),
                _ => false,
            };
            if skip {
                continue;
            }
            let values = self.values(stage, &scene, Some(room));
            let asked = self.ask(stage, Some(label), &values, &own);
            own.extend(latest_only(&asked.exchanges));
            let failed = asked.failed;
            done.push(asked);
            if failed {
                break;
            }
        }
        done
    }

    fn finish(mut self, mut sources: SourceMap) -> Outcome<Generated> {
        let costs = costs(&self.transcript.exchanges);
        self.transcript.totals = Some(Totals {
            calls: costs.iter().map(|c| c.calls).sum(),
            prompt_tokens: costs.iter().map(|c| c.prompt_tokens).sum(),
            completion_tokens: costs.iter().map(|c| c.completion_tokens).sum(),
            seconds: round3(costs.iter().map(|c| c.seconds).sum()),
        });
        let mut holo = String::new();
        if !self.transcript.exchanges.is_empty() && !self.diagnostics.iter().any(|d| fatal(d.code))
        {
            let built = bridge::build(&self.transcript, &mut sources);
            holo = built.value;
            self.diagnostics.extend(built.diagnostics);
        }
        Outcome::new(
            Generated {
                holo,
                transcript: self.transcript,
                sources,
                costs,
                failed_questions: self.failed_questions,
            },
            self.diagnostics,
        )
    }
}

/// Whether a diagnostic means the run stopped before every question was answered.
fn fatal(code: Code) -> bool {
    matches!(
        code,
        Code::E0801
            | Code::E0802
            | Code::E0803
            | Code::E0804
            | Code::E0805
            | Code::E0806
            | Code::E0807
            | Code::E0808
            | Code::E0810
    )
}

/// When the last exchange of a question started, milliseconds into the run.
fn exchange_started(exchanges: &[Exchange]) -> u64 {
    exchanges.last().map_or(0, |e| e.started_ms)
}

/// Keeps the last attempt of a question (the one the importer uses).
fn latest_only(exchanges: &[Exchange]) -> Option<Exchange> {
    exchanges.last().cloned()
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Cost per stage, in pipeline order.
fn costs(exchanges: &[Exchange]) -> Vec<StageCost> {
    let mut out: Vec<StageCost> = Vec::new();
    for stage in Stage::ALL {
        let mut cost = StageCost { stage: stage.as_str().to_string(), ..StageCost::default() };
        for e in exchanges.iter().filter(|e| e.stage == stage.as_str()) {
            if bridge::is_local_repair(e) {
                cost.repairs += 1;
                continue;
            }
            cost.calls += 1;
            if let Some(u) = e.usage {
                cost.prompt_tokens += u.prompt_tokens;
                cost.completion_tokens += u.completion_tokens;
            }
            cost.seconds += e.duration_ms as f64 / 1000.0;
        }
        if cost.calls + cost.repairs > 0 {
            cost.seconds = round3(cost.seconds);
            out.push(cost);
        }
    }
    out
}

/// The answers of a transcript, for [`ReplayLlm`].
pub fn recorded_answers(transcript: &Transcript) -> Vec<RecordedAnswer> {
    transcript
        .exchanges
        .iter()
        .map(|e| RecordedAnswer {
            stage: e.stage.clone(),
            room: e.room.clone(),
            attempt: e.attempt,
            answer: e.answer.clone(),
            usage: e.usage.map_or(Usage::default(), |u| Usage {
                prompt_tokens: u.prompt_tokens,
                completion_tokens: u.completion_tokens,
            }),
        })
        .collect()
}
