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

/// One diagnostic's JSON object.
fn item_json(sources: &SourceMap, d: &Diagnostic) -> Value {
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
}

/// `{"version": 1, "diagnostics": [...]}`, pretty-printed, with a final newline. Each
/// diagnostic's object is written out as soon as it is made, indented as it stands in the
/// document, so that 130,000 diagnostics (a house of overlapping beds) never stand as a tree
/// of values all at once beside their text.
pub fn render_json(sources: &SourceMap, diagnostics: &[Diagnostic]) -> String {
    const HOLE: &str = "\"diagnostics\": []";
    let shell = json!({ "version": JSON_VERSION, "diagnostics": [] });
    let shell = serde_json::to_string_pretty(&shell).expect("a JSON value always serializes");
    let (before, after) = shell.split_once(HOLE).unwrap_or((shell.as_str(), ""));
    let mut text = String::from(before);
    text.push_str("\"diagnostics\": [");
    for (n, d) in diagnostics.iter().enumerate() {
        let item = serde_json::to_string_pretty(&item_json(sources, d))
            .expect("a JSON value always serializes");
        text.push_str(if n == 0 { "\n" } else { ",\n" });
        // JSON strings hold no raw line break: every line of the object is one to indent.
        for (i, line) in item.split('\n').enumerate() {
            if i > 0 {
                text.push('\n');
            }
            text.push_str("    ");
            text.push_str(line);
        }
    }
    if !diagnostics.is_empty() {
        text.push_str("\n  ");
    }
    text.push(']');
    text.push_str(after);
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::{Code, Fix};
    use crate::source::Span;

    /// The document written item by item is the document of the whole tree, to the byte:
    /// none, one and several diagnostics, with labels, help, notes, fixes, quotes and line
    /// breaks in their texts, and one with no place.
    #[test]
    fn the_document_written_item_by_item_is_the_whole_trees() {
        let mut sources = SourceMap::new();
        let file = sources.add("scene.holo", "room a {\n  bed \"x\\ny\"\n}\n".to_string());
        let all = [
            Diagnostic::new(Code::E0201, "unknown name `bde`\nsecond line \"quoted\"")
                .with_primary(Span::new(file, 11, 14), "here")
                .with_secondary(Span::new(file, 0, 4), "in this room")
                .with_help("did you mean `bed`?")
                .with_note("a note")
                .with_fix(Fix {
                    title: "rename".into(),
                    span: Span::new(file, 11, 14),
                    replacement: "bed".into(),
                }),
            Diagnostic::new(Code::W0608, "overlaps"),
            Diagnostic::new(Code::E0002, "internal").with_primary(Span::new(file, 0, 0), ""),
        ];
        for n in 0..=all.len() {
            let diagnostics = &all[..n];
            let items: Vec<Value> = diagnostics.iter().map(|d| item_json(&sources, d)).collect();
            let doc = json!({ "version": JSON_VERSION, "diagnostics": items });
            let whole = serde_json::to_string_pretty(&doc).expect("serializes") + "\n";
            assert_eq!(render_json(&sources, diagnostics), whole, "{n} diagnostics");
        }
    }
}
