use super::place;
use crate::diag::{Diagnostic, Label};
use crate::source::SourceMap;
use serde_json::{json, Value};

/// The version of the JSON diagnostics schema; raised on any change to it.
pub const JSON_VERSION: u32 = 1;

fn label_json(sources: &SourceMap, label: &Label, primary: bool) -> Value {
    let p = place(sources, label.span);
    json!({
        "file": p.as_ref().map(|p| p.file),
        "start": label.span.start,
        "end": label.span.end,
        "line": p.as_ref().map(|p| p.line),
        "column": p.as_ref().map(|p| p.column),
        "end_line": p.as_ref().map(|p| p.end_line),
        "end_column": p.as_ref().map(|p| p.end_column),
        "text": label.text,
        "primary": primary,
    })
}

/// `{"version": 1, "diagnostics": [...]}`, pretty-printed, with a final newline.
pub fn render_json(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    let items: Vec<Value> = diagnostics
        .iter()
        .map(|d| {
            let p = d.primary.as_ref().and_then(|l| place(sources, l.span));
            let mut labels = Vec::new();
            if let Some(l) = &d.primary {
                labels.push(label_json(sources, l, true));
            }
            labels.extend(d.secondary.iter().map(|l| label_json(sources, l, false)));
            let mut item = json!({
                "code": d.code.as_str(),
                "name": d.code.name(),
                "severity": d.severity.as_str(),
                "message": d.message,
                "file": p.as_ref().map(|p| p.file),
                "start": d.primary.as_ref().map(|l| l.span.start),
                "end": d.primary.as_ref().map(|l| l.span.end),
                "line": p.as_ref().map(|p| p.line),
                "column": p.as_ref().map(|p| p.column),
                "end_line": p.as_ref().map(|p| p.end_line),
                "end_column": p.as_ref().map(|p| p.end_column),
                "labels": labels,
                "help": d.help,
                "notes": d.notes,
                "url": d.code.url(),
            });
            if !d.fixes.is_empty() {
                item["fixes"] = Value::Array(
                    d.fixes
                        .iter()
                        .map(|f| {
                            json!({
                                "title": f.title,
                                "start": f.span.start,
                                "end": f.span.end,
                                "replacement": f.replacement,
                            })
                        })
                        .collect(),
                );
            }
            item
        })
        .collect();
    let doc = json!({ "version": JSON_VERSION, "diagnostics": items });
    let mut text = serde_json::to_string_pretty(&doc).expect("a JSON value always serializes");
    text.push('\n');
    text
}
