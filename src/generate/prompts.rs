//! The prompt templates: one per question, embedded at build time and overridable from a folder.
//!
//! A template is plain text with placeholders written `{{name}}`. Each template has a fixed set
//! of placeholders its stage fills in; a template that uses any other name, or leaves out one
//! the stage needs, is reported before any request is sent.

use crate::diag::{suggest, Code, Diagnostic, Outcome};
use crate::source::{FileId, SourceMap, Span};
use std::collections::BTreeMap;

/// One question of the pipeline (plus the repair wrapper), i.e. one template file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Template {
    /// Rooms with designs and corners.
    FloorPlan,
    /// One number in metres.
    WallHeight,
    /// Connections between rooms.
    Doorways,
    /// Windows per room and wall.
    Windows,
    /// Object selection of one room (JSON).
    Objects,
    /// Floor-object constraints of one room.
    FloorConstraints,
    /// Wall-object placement of one room.
    WallConstraints,
    /// Small objects on the receptacles of one room.
    SmallObjects,
    /// One ceiling object per room.
    Ceiling,
    /// The wrapper that asks a question again with the problems of the previous answer.
    Repair,
}

impl Template {
    /// Every template, in pipeline order.
    pub const ALL: [Template; 10] = [
        Template::FloorPlan,
        Template::WallHeight,
        Template::Doorways,
        Template::Windows,
        Template::Objects,
        Template::FloorConstraints,
        Template::WallConstraints,
        Template::SmallObjects,
        Template::Ceiling,
        Template::Repair,
    ];

    /// The file name in `prompts/` and in a `--prompts` folder.
    pub fn file_name(self) -> &'static str {
        match self {
            Template::FloorPlan => "floor_plan.txt",
            Template::WallHeight => "wall_height.txt",
            Template::Doorways => "doorways.txt",
            Template::Windows => "windows.txt",
            Template::Objects => "objects.txt",
            Template::FloorConstraints => "floor_constraints.txt",
            Template::WallConstraints => "wall_constraints.txt",
            Template::SmallObjects => "small_objects.txt",
            Template::Ceiling => "ceiling.txt",
            Template::Repair => "repair.txt",
        }
    }

    /// The embedded default text.
    pub fn embedded(self) -> &'static str {
        match self {
            Template::FloorPlan => include_str!("../../prompts/floor_plan.txt"),
            Template::WallHeight => include_str!("../../prompts/wall_height.txt"),
            Template::Doorways => include_str!("../../prompts/doorways.txt"),
            Template::Windows => include_str!("../../prompts/windows.txt"),
            Template::Objects => include_str!("../../prompts/objects.txt"),
            Template::FloorConstraints => include_str!("../../prompts/floor_constraints.txt"),
            Template::WallConstraints => include_str!("../../prompts/wall_constraints.txt"),
            Template::SmallObjects => include_str!("../../prompts/small_objects.txt"),
            Template::Ceiling => include_str!("../../prompts/ceiling.txt"),
            Template::Repair => include_str!("../../prompts/repair.txt"),
        }
    }

    /// The placeholders the stage fills in; a template may use only these.
    pub fn placeholders(self) -> &'static [&'static str] {
        match self {
            Template::FloorPlan => &["request", "requirements"],
            Template::WallHeight => &["request"],
            Template::Doorways => &["request", "rooms", "room_sizes", "room_pairs", "requirements"],
            Template::Windows => &["request", "walls", "wall_height_cm", "requirements"],
            Template::Objects => &["request", "room", "room_size", "requirements"],
            Template::FloorConstraints => &["request", "room", "room_size", "objects"],
            Template::WallConstraints => {
                &["request", "room", "wall_height_cm", "floor_objects", "wall_objects"]
            }
            Template::SmallObjects => &["request", "room", "receptacles", "requirements"],
            Template::Ceiling => &["request", "rooms", "requirements"],
            Template::Repair => &["prompt", "answer", "problems"],
        }
    }

    /// The placeholders a template must use, because the answer cannot be right without them.
    pub fn required(self) -> &'static [&'static str] {
        match self {
            Template::FloorPlan | Template::WallHeight => &["request"],
            Template::Doorways => &["rooms", "room_pairs"],
            Template::Windows => &["walls"],
            Template::Objects => &["room"],
            Template::FloorConstraints => &["objects"],
            Template::WallConstraints => &["floor_objects", "wall_objects"],
            Template::SmallObjects => &["receptacles"],
            Template::Ceiling => &["rooms"],
            Template::Repair => &["prompt", "answer", "problems"],
        }
    }
}

/// One placeholder occurrence in a template.
#[derive(Clone, Debug)]
struct Slot {
    /// Byte range of `{{name}}` in the text.
    start: usize,
    end: usize,
    name: String,
}

/// A checked set of templates, one per [`Template`], each a file of a [`SourceMap`].
#[derive(Clone, Debug)]
pub struct Prompts {
    texts: BTreeMap<Template, (String, Vec<Slot>)>,
}

/// Finds every `{{name}}` in a text. An opening `{{` without a closing `}}` on the same line is
/// returned as a slot with an empty name spanning the rest of the line.
fn scan(text: &str) -> Vec<Slot> {
    let mut slots = Vec::new();
    let mut from = 0;
    while let Some(found) = text[from..].find("{{") {
        let start = from + found;
        let line_end = text[start..].find('\n').map_or(text.len(), |n| start + n);
        match text[start + 2..line_end].find("}}") {
            Some(close) => {
                let end = start + 2 + close + 2;
                let name = text[start + 2..start + 2 + close].trim().to_string();
                slots.push(Slot { start, end, name });
                from = end;
            }
            None => {
                slots.push(Slot { start, end: line_end, name: String::new() });
                from = line_end;
            }
        }
    }
    slots
}

impl Prompts {
    /// Checks the templates: the embedded default for each, unless `overrides` holds a file of
    /// `sources` for it (read by the caller from a `--prompts` folder).
    pub fn load(
        sources: &mut SourceMap,
        overrides: &BTreeMap<Template, FileId>,
    ) -> Outcome<Prompts> {
        let mut diagnostics = Vec::new();
        let mut texts = BTreeMap::new();
        for template in Template::ALL {
            let file = match overrides.get(&template) {
                Some(&file) if sources.try_get(file).is_some() => file,
                _ => {
                    sources.add(format!("<prompts>/{}", template.file_name()), template.embedded())
                }
            };
            let text = sources.get(file).text.to_string();
            let slots = scan(&text);
            let allowed = template.placeholders();
            for slot in &slots {
                let span = Span::new(file, slot.start, slot.end);
                if slot.name.is_empty() {
                    diagnostics.push(
                        Diagnostic::new(
                            Code::E0801,
                            format!(
                                "placeholder without a name or closing `}}}}` in `{}`",
                                template.file_name()
                            ),
                        )
                        .with_primary(span, "not a `{{name}}` placeholder")
                        .with_help(format!("write one of {}", list(allowed))),
                    );
                } else if !allowed.contains(&slot.name.as_str()) {
                    let help = suggest::did_you_mean(&suggest::closest(
                        &slot.name,
                        allowed.iter().copied(),
                    ))
                    .unwrap_or_else(|| format!("this template can use {}", list(allowed)));
                    diagnostics.push(
                        Diagnostic::new(
                            Code::E0801,
                            format!(
                                "unknown placeholder `{}` in `{}`",
                                slot.name,
                                template.file_name()
                            ),
                        )
                        .with_primary(span, "the stage does not fill this in")
                        .with_help(help),
                    );
                }
            }
            for needed in template.required() {
                if !slots.iter().any(|s| s.name == *needed) {
                    let end = text.len();
                    diagnostics.push(
                        Diagnostic::new(
                            Code::E0802,
                            format!("template `{}` does not use `{{{{{needed}}}}}`", template.file_name()),
                        )
                        .with_primary(Span::new(file, 0, end.min(1)), "in this template")
                        .with_help(format!(
                            "add `{{{{{needed}}}}}` where the model should see it; the answer cannot be right without it"
                        )),
                    );
                }
            }
            texts.insert(template, (text, slots));
        }
        Outcome::new(Prompts { texts }, diagnostics)
    }

    /// The embedded defaults, checked (they always pass; a test says so).
    pub fn embedded() -> Prompts {
        let mut sources = SourceMap::new();
        Prompts::load(&mut sources, &BTreeMap::new()).value
    }

    /// Fills a template in. A placeholder without a value becomes an empty string (the checks of
    /// [`Prompts::load`] make sure the stage provides every allowed name).
    pub fn render(&self, template: Template, values: &BTreeMap<&str, String>) -> String {
        let Some((text, slots)) = self.texts.get(&template) else {
            return String::new();
        };
        let mut out = String::with_capacity(text.len() + 256);
        let mut at = 0;
        for slot in slots {
            out.push_str(&text[at..slot.start]);
            match values.get(slot.name.as_str()) {
                Some(value) => out.push_str(value),
                None if slot.name.is_empty() => out.push_str(&text[slot.start..slot.end]),
                None => {}
            }
            at = slot.end;
        }
        out.push_str(&text[at..]);
        out
    }
}

/// `` `a`, `b` or `c` ``.
fn list(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{{{{{n}}}}}`")).collect();
    match quoted.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_templates_are_clean() {
        let mut sources = SourceMap::new();
        let outcome = Prompts::load(&mut sources, &BTreeMap::new());
        assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    }

    #[test]
    fn unknown_and_missing_placeholders() {
        let mut sources = SourceMap::new();
        let file = sources.add("mine/floor_plan.txt", "Plan {{reqest}} and {{oops");
        let overrides = BTreeMap::from([(Template::FloorPlan, file)]);
        let outcome = Prompts::load(&mut sources, &overrides);
        let codes: Vec<Code> = outcome.diagnostics.iter().map(|d| d.code).collect();
        assert_eq!(codes, vec![Code::E0801, Code::E0801, Code::E0802]);
        assert_eq!(outcome.diagnostics[0].help.as_deref(), Some("did you mean `request`?"));
    }

    #[test]
    fn render_fills_values() {
        let prompts = Prompts::embedded();
        let values = BTreeMap::from([("request", "a tiny flat".to_string())]);
        let text = prompts.render(Template::WallHeight, &values);
        assert!(text.contains("\"a tiny flat\""));
        assert!(!text.contains("{{"));
    }
}
