//! The answers to the editor's requests, computed from one [`Analysis`]: diagnostics, hover,
//! definitions, references, rename, symbols, completion, formatting and code actions.
//!
//! Each function is pure (no I/O), so the in-memory tests call the server and these are what
//! they see.

use super::document::{Analysis, Solved};
use super::index::{self, SymbolKind as HoloSymbol};
use crate::check::scene::RelationKind;
use crate::diag::{Diagnostic, Fix};
use crate::resolve::Resolution;
use crate::source::Span;
use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, CompletionItem, CompletionItemKind,
    DocumentSymbol, Hover, HoverContents, Location, MarkupContent, MarkupKind, Position,
    PrepareRenameResponse, Range, SymbolKind, TextEdit, Uri, WorkspaceEdit,
};
use std::collections::HashMap;
use std::fmt::Write as _;

/// The document's diagnostics as LSP diagnostics: every stage before the solver, and the
/// background solve's when it ran on this version, sorted as `holoc check` sorts them, then
/// the hints on relations that do not hold; at most `max`, closed by one that counts the rest
/// ([`capped`]). Only those shown are made in full: a keystroke in a scene with thousands of
/// warnings does not copy and convert them all.
pub fn diagnostics(
    analysis: &Analysis,
    solved: Option<&Solved>,
    max: usize,
) -> Vec<lsp_types::Diagnostic> {
    let name = analysis.source().name.as_str();
    let here = |d: &&Diagnostic| {
        d.primary.as_ref().is_some_and(|l| {
            l.span.file == analysis.file
                || analysis.sources.try_get(l.span.file).is_some_and(|f| f.name == name)
        })
    };
    let mut mine: Vec<&Diagnostic> = analysis
        .analysed
        .diagnostics
        .iter()
        .chain(solved.into_iter().flat_map(|s| s.diagnostics.iter()))
        .filter(here)
        .collect();
    // As `crate::diag::sort` (a stable sort on the same key).
    mine.sort_by_key(|d| d.primary.as_ref().map(|l| (l.span.file, l.span.start, l.span.end)));
    let shown: Vec<Diagnostic> = mine.iter().take(max).map(|&d| d.clone()).collect();
    let mut out: Vec<lsp_types::Diagnostic> =
        to_lsp(analysis, &shown).into_iter().map(|(_, d)| d).collect();
    // Those left out: `capped` reads only their severities and the first one's place.
    out.extend(mine.iter().skip(max).enumerate().map(|(k, d)| lsp_types::Diagnostic {
        range: match d.primary.as_ref() {
            Some(l) if k == 0 => analysis.range(l.span),
            _ => Range::default(),
        },
        severity: Some(match d.severity {
            crate::diag::Severity::Error => lsp_types::DiagnosticSeverity::ERROR,
            crate::diag::Severity::Warning => lsp_types::DiagnosticSeverity::WARNING,
            crate::diag::Severity::Note => lsp_types::DiagnosticSeverity::INFORMATION,
        }),
        ..Default::default()
    }));
    if let Some(solved) = solved {
        out.extend(relation_hints(analysis, solved));
    }
    capped(out, max)
}

/// The first `max` of a document's diagnostics and, when there are more, one closing
/// diagnostic that says how many are left out, of which severities, and where to see them all
/// (`holoc check --format json`): an editor is never shown a silently shortened list. The
/// closing one stands where the first one left out does, with the severity of the most severe
/// one left out, so that an editor's count of errors still says there are errors.
pub fn capped(
    mut diagnostics: Vec<lsp_types::Diagnostic>,
    max: usize,
) -> Vec<lsp_types::Diagnostic> {
    use lsp_types::DiagnosticSeverity as S;
    if diagnostics.len() <= max {
        return diagnostics;
    }
    let hidden = diagnostics.split_off(max);
    let count = |severity: S| hidden.iter().filter(|d| d.severity == Some(severity)).count();
    let kinds: Vec<String> = [
        (S::ERROR, "error(s)"),
        (S::WARNING, "warning(s)"),
        (S::INFORMATION, "note(s)"),
        (S::HINT, "hint(s)"),
    ]
    .into_iter()
    .filter_map(|(severity, word)| {
        let n = count(severity);
        (n > 0).then(|| format!("{n} {word}"))
    })
    .collect();
    // ERROR is 1 and HINT 4: the smallest is the most severe.
    let severity = hidden.iter().filter_map(|d| d.severity).min().unwrap_or(S::INFORMATION);
    let first = hidden.first().map(|d| d.range).unwrap_or_default();
    diagnostics.push(lsp_types::Diagnostic {
        range: first,
        severity: Some(severity),
        source: Some("holoc".to_string()),
        message: format!(
            "and {} more diagnostic(s) from here on not shown ({}): the editor is sent at most {max} per file; `holoc check --format json` on the file lists them all",
            hidden.len(),
            kinds.join(", "),
        ),
        ..Default::default()
    });
    diagnostics
}

/// Diagnostics in the LSP form, with the server's links: the document's own URI for places in
/// it (as the editor named it: a `file:` URI, or `untitled:1`), and absolute links to the
/// codes' pages.
fn to_lsp(analysis: &Analysis, all: &[Diagnostic]) -> Vec<(String, lsp_types::Diagnostic)> {
    let name = analysis.source().name.as_str();
    let uri = |file: &str| {
        if file == name {
            analysis.uri.clone()
        } else {
            crate::diag::lsp::file_uri(file)
        }
    };
    let links = crate::diag::lsp::Links { uri: &uri, href: &code_href };
    crate::diag::lsp::to_lsp_with(&analysis.sources, all, &links)
}

/// The absolute `file:` URI of a code's page in the holoc sources the server was built from,
/// when they are there (`holoc explain CODE` prints the same page).
pub fn code_href(code: crate::diag::Code) -> Option<Uri> {
    crate::diag::lsp::page_uri(code)
}

/// One hint per relation of a placed object that does not hold in the last solve (every
/// instance of a counted group is measured on its own), at the relation as written.
fn relation_hints(analysis: &Analysis, solved: &Solved) -> Vec<lsp_types::Diagnostic> {
    solved
        .relations
        .iter()
        .filter(|r| !r.satisfied && r.value.is_finite() && r.span.file == analysis.file)
        .map(|r| lsp_types::Diagnostic {
            range: analysis.range(r.span),
            severity: Some(lsp_types::DiagnosticSeverity::HINT),
            source: Some("holoc".to_string()),
            message: format!(
                "`{}` {} does not hold in the last solve: {}",
                r.object,
                r.text,
                measured(r)
            ),
            ..Default::default()
        })
        .collect()
}

/// `measured 2.10 m (range 0.10-1.50 m)`.
fn measured(outcome: &super::document::RelationOutcome) -> String {
    let mut text = format!("measured {:.2} {}", outcome.value, outcome.unit);
    match outcome.range {
        Some((lo, hi)) if hi.is_finite() => {
            let _ = write!(text, " (range {lo:.2}-{hi:.2} m)");
        }
        Some((lo, _)) => {
            let _ = write!(text, " (at least {lo:.2} m)");
        }
        None => {}
    }
    text
}

/// What a relation means, in one sentence (the definitions of the layout semantics).
pub fn relation_meaning(kind: RelationKind) -> &'static str {
    match kind {
        RelationKind::Near => {
            "close to the target: the gap between the footprints is within the pair's range (0.1-1.5 m for most pairs)"
        }
        RelationKind::Far => "away from the target: a gap of at least 1.5 m",
        RelationKind::InFrontOf => {
            "beyond the target's front side, within the pair's range, facing it where the pair calls for it"
        }
        RelationKind::Behind => "beyond the target's back side, within the pair's range",
        RelationKind::SideOf => "beyond the target's left or right side, within the pair's range",
        RelationKind::LeftOf => {
            "beyond the target's left side, from the target's own point of view"
        }
        RelationKind::RightOf => {
            "beyond the target's right side, from the target's own point of view"
        }
        RelationKind::Around => "within 0.6 m of the target and facing it (chairs around a table)",
        RelationKind::CenterAligned => "the centres differ by at most 5 cm on x or on z",
        RelationKind::FaceTo => "facing the target: the ray ahead of the object meets its footprint",
        RelationKind::FaceSameAs => "the same rotation as the target",
    }
}

fn global_meaning(words: &str) -> Option<&'static str> {
    match words {
        "edge" => Some("against a wall: the back centre at most 2 cm from a wall of the room"),
        "middle" => Some(
            "away from the walls: the footprint grown by 40 cm on every side stays in the room",
        ),
        _ => None,
    }
}

fn markdown(value: String) -> Hover {
    Hover {
        contents: HoverContents::Markup(MarkupContent { kind: MarkupKind::Markdown, value }),
        range: None,
    }
}

/// Hover: an object's resolved asset, size and score, and where the solve put it; a
/// relation's meaning and whether it holds after the last solve; a room's label and area.
/// `solving`: whether the server solves on save, and whether a solve of this version is
/// running. `solved` may hold some rooms only: in a room not solved yet, while the solve runs,
/// the hover says that the room is being solved.
pub fn hover(
    analysis: &Analysis,
    solved: Option<&Solved>,
    solving: (bool, bool),
    position: Position,
) -> Option<Hover> {
    let offset = analysis.offset(position);
    if let Some(relation) = analysis.index().relation_at(offset) {
        let words = relation.words.to_lowercase();
        let mut text = format!("**`{}`**", relation.words);
        if let Some(kind) = RelationKind::from_words(&words) {
            let _ = write!(text, " (relation): {}", relation_meaning(kind));
        } else if let Some(meaning) = global_meaning(&words) {
            let _ = write!(text, " (global constraint): {meaning}");
        } else {
            text.push_str(": not a relation of the language");
        }
        // Every instance of a counted group has its own outcome for the one relation written.
        let outcomes: Vec<&super::document::RelationOutcome> = solved
            .map(|s| s.relations.iter().filter(|r| r.span == relation.span).collect())
            .unwrap_or_default();
        let verdict = |o: &super::document::RelationOutcome| {
            let verdict = if o.satisfied { "holds" } else { "does not hold" };
            format!("`{}` {} {verdict}: {}", o.object, o.text, measured(o))
        };
        // The room the relation is written in, and whether the solve has reached it.
        let room = room_at(analysis, relation.span.start as usize);
        let reached = solved.is_some_and(|s| room.is_none_or(|r| s.room(r).is_some()));
        match outcomes.as_slice() {
            [one] => {
                let _ = write!(text, "\n\nAfter the last solve: {}", verdict(one));
            }
            [] if !reached && solving.1 => {
                let _ = write!(
                    text,
                    "\n\nThe layout of {} is being solved; hover again to see whether it holds.",
                    room.map_or_else(|| "this version".to_string(), |r| format!("room `{r}`"))
                );
            }
            [] if solved.is_none() && solving.0 => {
                text.push_str("\n\nSave the file to solve the layout and see whether it holds.");
            }
            [] => {}
            several => {
                let held = several.iter().filter(|o| o.satisfied).count();
                let _ = write!(
                    text,
                    "\n\nAfter the last solve: holds for {held} of {} instances",
                    several.len()
                );
                for o in several {
                    let _ = write!(text, "\n- {}", verdict(o));
                }
            }
        }
        let mut hover = markdown(text);
        hover.range = Some(analysis.range(relation.words_span));
        return Some(hover);
    }
    let occurrence = analysis.index().occurrence_at(offset)?;
    let symbol = &analysis.index().symbols[occurrence.symbol];
    let text = match symbol.kind {
        HoloSymbol::Room => room_hover(analysis, &symbol.name),
        HoloSymbol::Object | HoloSymbol::WallObject => {
            let mut text = object_hover(analysis, symbol, occurrence.instance);
            let room = symbol.room.map(|r| analysis.index().symbols[r].name.as_str());
            text.push_str(&solve_text(
                analysis,
                symbol,
                occurrence.instance,
                room,
                solved,
                solving,
            ));
            text
        }
    };
    let mut hover = markdown(text);
    hover.range = Some(analysis.range(occurrence.span));
    Some(hover)
}

/// The name of the room whose declaration holds byte `offset`.
pub fn room_at(analysis: &Analysis, offset: usize) -> Option<&str> {
    analysis
        .index()
        .symbols
        .iter()
        .filter(|s| s.kind == HoloSymbol::Room)
        .find(|s| (s.decl_span.start as usize) <= offset && offset <= (s.decl_span.end as usize))
        .map(|s| s.name.as_str())
}

fn room_hover(analysis: &Analysis, name: &str) -> String {
    let mut text = format!("**room** `{name}`");
    let Some(scene) = &analysis.analysed.scene else {
        text.push_str("\n\n(the file has errors; fix them to see the room's area)");
        return text;
    };
    let Some(room) = scene.rooms.iter().find(|r| r.name == name) else { return text };
    let _ = write!(text, " \"{}\"", room.label);
    let area = analysis
        .analysed
        .plan
        .as_ref()
        .and_then(|p| p.rooms.iter().find(|r| r.id == room.id))
        .map_or_else(|| crate::geometry::signed_area(&room.corners).abs(), |r| r.area_m2);
    let _ = write!(
        text,
        "\n\narea {area:.2} m², {} corners, {} objects, {} window line(s)",
        room.corners.len(),
        room.objects.len(),
        room.windows.len()
    );
    text
}

fn object_hover(analysis: &Analysis, symbol: &index::Symbol, instance: Option<u32>) -> String {
    let kind = if symbol.kind == HoloSymbol::WallObject { "wall object" } else { "object" };
    let mut text = match instance {
        Some(n) => format!("**{kind}** `{}-{n}` (instance {n} of `{}`)", symbol.name, symbol.name),
        None => format!("**{kind}** `{}`", symbol.name),
    };
    if let Some(category) = &symbol.detail {
        let _ = write!(text, " \"{category}\"");
    }
    let Some(scene) = &analysis.analysed.scene else {
        text.push_str("\n\n(the file has errors; fix them to see the chosen asset)");
        return text;
    };
    let room_name = symbol.room.map(|r| analysis.index().symbols[r].name.as_str());
    let members: Vec<&crate::check::Object> = scene
        .objects
        .iter()
        .filter(|o| o.group == symbol.name)
        .filter(|o| room_name.is_none_or(|r| scene.room(o.room).name == r))
        .filter(|o| instance.is_none_or(|n| o.index == n))
        .collect();
    if let Some(first) = members.first() {
        if let Some(d) = &first.description {
            let _ = write!(text, "\n\n{d}");
        }
        let _ = write!(text, "\n\n{} instance(s), {}", first.group_count, first.variance.as_str());
        if let Some([w, d, h]) = first.size_m {
            let _ = write!(text, "; size written {w:.2} × {d:.2} × {h:.2} m");
        }
    }
    match &analysis.analysed.resolved {
        None => text.push_str("\n\n(assets are chosen once the floor plan has no errors)"),
        Some(resolved) => {
            text.push('\n');
            for o in &members {
                let _ = write!(text, "\n- `{}`: ", o.name);
                text.push_str(&resolution_text(resolved.objects.get(o.id.0)));
            }
        }
    }
    text
}

/// Where the solve put an object's instances, once its room is solved; that its room is being
/// solved while it is not; nothing else.
fn solve_text(
    analysis: &Analysis,
    symbol: &index::Symbol,
    instance: Option<u32>,
    room: Option<&str>,
    solved: Option<&Solved>,
    solving: (bool, bool),
) -> String {
    let Some(room) = room else { return String::new() };
    let Some(found) = solved.and_then(|s| s.room(room)) else {
        if solving.1 {
            return format!(
                "\n\nThe layout of room `{room}` is being solved; hover again to see where it stands."
            );
        }
        return String::new();
    };
    let Some(scene) = &analysis.analysed.scene else { return String::new() };
    let mut text = String::from("\n\nAfter the last solve:");
    let members = scene
        .objects
        .iter()
        .filter(|o| o.group == symbol.name && scene.room(o.room).name == room)
        .filter(|o| instance.is_none_or(|n| o.index == n));
    for o in members {
        let outcome = found.objects.get(&o.name).map_or("not in the layout", String::as_str);
        let _ = write!(text, "\n- `{}`: {outcome}", o.name);
    }
    text
}

fn resolution_text(resolution: Option<&Resolution>) -> String {
    match resolution {
        Some(Resolution::Chosen(c)) => {
            if let Some(made) = &c.made {
                return format!("`{}`, {}", c.asset_id, made.summary());
            }
            let [x, y, z] = c.bbox_m;
            let how = if c.pinned {
                "pinned".to_string()
            } else if let Some(p) = &c.parts {
                format!("score {}", crate::resolve::parts_text(p))
            } else if let Some(reason) = &c.stand_in {
                format!("stand-in: {reason}")
            } else if let Some(k) = &c.kind_of {
                k.clone()
            } else {
                String::new()
            };
            format!("`{}` ({}), {x:.2} × {z:.2} × {y:.2} m, {how}", c.asset_id, c.object_type)
        }
        Some(Resolution::Unresolved(u)) => format!("no asset: {}", u.reason),
        None => "not resolved".to_string(),
    }
}

/// Go to definition: a room's declaration, an object group's, or an instance's own block.
pub fn definition(analysis: &Analysis, position: Position) -> Option<Range> {
    let occurrence = analysis.index().occurrence_at(analysis.offset(position))?;
    let symbol = &analysis.index().symbols[occurrence.symbol];
    let span = occurrence
        .instance
        .and_then(|n| symbol.instance_blocks.iter().find(|(i, _, _)| *i == n))
        .map_or(symbol.name_span, |(_, span, _)| *span);
    Some(analysis.range(span))
}

/// Find references: every place the symbol under the cursor is named (for an instance, the
/// places that name that instance), with or without the declaration.
pub fn references(
    analysis: &Analysis,
    position: Position,
    include_declaration: bool,
) -> Vec<Range> {
    let Some(occurrence) = analysis.index().occurrence_at(analysis.offset(position)) else {
        return Vec::new();
    };
    analysis
        .index()
        .occurrences_of(occurrence.symbol, occurrence.instance)
        .into_iter()
        .filter(|o| include_declaration || !o.is_declaration)
        .map(|o| analysis.range(o.span))
        .collect()
}

/// Prepare rename: the identifier a rename would change (the group's part of an instance name).
pub fn prepare_rename(analysis: &Analysis, position: Position) -> Option<PrepareRenameResponse> {
    let occurrence = analysis.index().occurrence_at(analysis.offset(position))?;
    let symbol = &analysis.index().symbols[occurrence.symbol];
    Some(PrepareRenameResponse::RangeWithPlaceholder {
        range: analysis.range(occurrence.name_span),
        placeholder: symbol.name.clone(),
    })
}

/// Rename a room or an object group across the file (its instances' names follow). An error
/// when the new name is not an identifier or is already taken in the same scope.
pub fn rename(
    analysis: &Analysis,
    uri: &Uri,
    position: Position,
    new_name: &str,
) -> Result<WorkspaceEdit, String> {
    let occurrence = analysis
        .index()
        .occurrence_at(analysis.offset(position))
        .ok_or("no room or object here to rename")?;
    if !index::is_identifier(new_name) {
        return Err(format!(
            "`{new_name}` is not a name: use letters, digits, `_` and inner `-`, starting with a letter, not ending in `-<number>`"
        ));
    }
    let symbol = &analysis.index().symbols[occurrence.symbol];
    let taken = analysis
        .index()
        .symbols
        .iter()
        .any(|s| s.name == new_name && s.kind.eq_room(symbol.kind) && s.room == symbol.room);
    if taken && new_name != symbol.name {
        return Err(format!("`{new_name}` is already declared here"));
    }
    let edits: Vec<TextEdit> = analysis
        .index()
        .occurrences_of(occurrence.symbol, None)
        .into_iter()
        .map(|o| TextEdit { range: analysis.range(o.name_span), new_text: new_name.to_string() })
        .collect();
    Ok(WorkspaceEdit { changes: Some(HashMap::from([(uri.clone(), edits)])), ..Default::default() })
}

impl HoloSymbol {
    fn eq_room(self, other: HoloSymbol) -> bool {
        (self == HoloSymbol::Room) == (other == HoloSymbol::Room)
    }
}

/// Document symbols: rooms with their objects (and instances), then doors.
#[allow(deprecated, reason = "DocumentSymbol::deprecated must be written; it is None")]
pub fn document_symbols(analysis: &Analysis) -> Vec<DocumentSymbol> {
    let index = analysis.index();
    let symbol =
        |name: String, detail: Option<String>, kind, span: Span, name_span: Span| DocumentSymbol {
            name,
            detail,
            kind,
            tags: None,
            deprecated: None,
            range: analysis.range(span),
            selection_range: analysis.range(name_span),
            children: None,
        };
    let mut out = Vec::new();
    for (r, room) in index.symbols.iter().enumerate().filter(|(_, s)| s.kind == HoloSymbol::Room) {
        let mut children = Vec::new();
        for (_, object) in index.objects_of(r) {
            let kind = if object.kind == HoloSymbol::WallObject {
                SymbolKind::FIELD
            } else {
                SymbolKind::OBJECT
            };
            let mut o = symbol(
                object.name.clone(),
                object.detail.clone(),
                kind,
                object.decl_span,
                object.name_span,
            );
            let instances: Vec<DocumentSymbol> = object
                .instance_blocks
                .iter()
                .map(|&(n, name_span, span)| {
                    symbol(
                        format!("{}-{n}", object.name),
                        None,
                        SymbolKind::VARIABLE,
                        span,
                        name_span,
                    )
                })
                .collect();
            o.children = (!instances.is_empty()).then_some(instances);
            children.push(o);
        }
        let mut s = symbol(
            room.name.clone(),
            room.detail.clone(),
            SymbolKind::MODULE,
            room.decl_span,
            room.name_span,
        );
        s.children = Some(children);
        out.push(s);
    }
    for item in &analysis.analysed.ast.items {
        if let crate::ast::Item::Door(d) = item {
            out.push(symbol(
                format!("door {} -- {}", d.from.name, d.to.name),
                Some(d.kind.name.clone()),
                SymbolKind::INTERFACE,
                d.span,
                d.from.span.to(d.to.span),
            ));
        }
    }
    out
}

/// Formatting: the whole document in `holoc fmt`'s canonical form (no edit when it already is,
/// an error when it has syntax errors).
pub fn formatting(analysis: &Analysis) -> Result<Vec<TextEdit>, String> {
    if crate::parse::parse(&analysis.sources, analysis.file).has_errors() {
        return Err("not formatting: the file has syntax errors".to_string());
    }
    let text = &analysis.source().text;
    // The canonical text with the document's own line breaks (those of its first line).
    let formatted = crate::fmt::print(&analysis.analysed.ast);
    let formatted = match line_break(text) {
        "\n" => formatted,
        other => formatted.replace('\n', other),
    };
    if formatted == text.as_str() {
        return Ok(Vec::new());
    }
    let end = analysis.source().lsp_position(text.len());
    Ok(vec![TextEdit {
        range: Range { start: Position::new(0, 0), end: Position::new(end.0, end.1) },
        new_text: formatted,
    }])
}

/// The line break a text uses: that of its first line (`\n` when it has none).
pub fn line_break(text: &str) -> &'static str {
    match text.find(['\n', '\r']).map(|i| &text.as_bytes()[i..]) {
        Some([b'\r', b'\n', ..]) => "\r\n",
        Some([b'\r', ..]) => "\r",
        _ => "\n",
    }
}

/// Code actions: the fixes of the diagnostics that touch `range` (did-you-mean, add a unit,
/// convert a unit, snap a corner, move a room), one quick fix each.
pub fn code_actions(
    analysis: &Analysis,
    solved: Option<&Solved>,
    uri: &Uri,
    range: Range,
) -> Vec<CodeActionOrCommand> {
    let start = analysis.offset(range.start);
    let end = analysis.offset(range.end);
    let lsp = diagnostics(analysis, None, usize::MAX);
    let mut all: Vec<&Diagnostic> = analysis.analysed.diagnostics.iter().collect();
    if let Some(solved) = solved {
        all.extend(&solved.diagnostics);
    }
    let mut actions = Vec::new();
    let errors_now = std::cell::OnceCell::new();
    for d in all {
        let Some(primary) = &d.primary else { continue };
        // The cursor may be on the diagnostic's place or on the text a fix rewrites.
        let touches = std::iter::once(primary.span)
            .chain(d.fixes.iter().map(|f| f.span))
            .any(|span| (span.start as usize) <= end && start <= (span.end as usize));
        if !touches || d.fixes.is_empty() {
            continue;
        }
        let lsp_diagnostic = as_sent(analysis, &lsp, d);
        // A fix that would add an error (a rename onto a name already declared, E0203) is
        // not offered; one that is left alone is preferred.
        let fixes: Vec<&Fix> =
            d.fixes.iter().filter(|f| !breaks(analysis, f, &errors_now)).collect();
        let preferred = fixes.len() == 1;
        for fix in fixes {
            actions.push(CodeActionOrCommand::CodeAction(action(
                analysis,
                uri,
                fix,
                lsp_diagnostic.cloned(),
                preferred,
            )));
        }
    }
    actions.extend(repair_action(analysis, uri, start, end, &lsp));
    actions
}

/// Whether applying `fix` gives the file a syntax or checker error it did not have (compared
/// by code and message, as spans move).
fn breaks(analysis: &Analysis, fix: &Fix, errors_now: &std::cell::OnceCell<Vec<Checked>>) -> bool {
    let text = &analysis.source().text;
    let (start, end) = (fix.span.start as usize, fix.span.end as usize);
    if fix.span.file != analysis.file
        || start > end
        || !text.is_char_boundary(start)
        || !text.is_char_boundary(end.min(text.len()))
        || end > text.len()
    {
        return true;
    }
    let errors = |text: &str| -> Vec<Checked> {
        let parsed = crate::parse::parse_str(text);
        let checked = crate::check::check(&parsed.value);
        let mut errors: Vec<Checked> = parsed
            .diagnostics
            .iter()
            .chain(&checked.diagnostics)
            .filter(|d| d.is_error())
            .map(|d| (d.code, d.message.clone()))
            .collect();
        errors.sort();
        errors
    };
    let mut fixed = text.to_string();
    fixed.replace_range(start..end, &fix.replacement);
    let before = errors_now.get_or_init(|| errors(text));
    errors(&fixed).iter().any(|e| before.binary_search(e).is_err())
}

/// An error of the front end, by code and message.
type Checked = (crate::diag::Code, String);

/// When the floor plan has errors that `holoc repair` can mend: one action that applies the
/// whole repair (every moved room's new corners), offered on the plan errors and on the
/// corner lists it rewrites.
fn repair_action(
    analysis: &Analysis,
    uri: &Uri,
    start: usize,
    end: usize,
    lsp: &[lsp_types::Diagnostic],
) -> Option<CodeActionOrCommand> {
    if analysis.analysed.plan.is_some() {
        return None;
    }
    let scene = analysis.analysed.scene.as_ref()?;
    let plan_errors: Vec<&Diagnostic> = analysis
        .analysed
        .diagnostics
        .iter()
        .filter(|d| d.is_error() && d.code.stage() == "plan")
        .collect();
    if plan_errors.is_empty() {
        return None;
    }
    let repaired =
        crate::plan::repair::repair(scene, crate::resolve::structure::StructureCatalog::builtin());
    if !repaired.value.changed {
        return None;
    }
    let fixes: Vec<&Fix> = repaired.diagnostics.iter().flat_map(|d| &d.fixes).collect();
    let touches = |span: Span| (span.start as usize) <= end && start <= (span.end as usize);
    let on_error = plan_errors.iter().filter_map(|d| d.primary.as_ref()).any(|p| touches(p.span));
    if fixes.is_empty() || !(on_error || fixes.iter().any(|f| touches(f.span))) {
        return None;
    }
    let edits: Vec<TextEdit> = fixes
        .iter()
        .map(|f| TextEdit { range: analysis.range(f.span), new_text: f.replacement.clone() })
        .collect();
    let diagnostics: Vec<lsp_types::Diagnostic> =
        plan_errors.iter().filter_map(|d| as_sent(analysis, lsp, d).cloned()).collect();
    let rooms = fixes.len();
    Some(CodeActionOrCommand::CodeAction(CodeAction {
        title: format!(
            "repair the floor plan: move the corners of {rooms} room{} (as `holoc repair`)",
            if rooms == 1 { "" } else { "s" }
        ),
        kind: Some(CodeActionKind::QUICKFIX),
        diagnostics: (!diagnostics.is_empty()).then_some(diagnostics),
        edit: Some(WorkspaceEdit {
            changes: Some(HashMap::from([(uri.clone(), edits)])),
            ..Default::default()
        }),
        command: None,
        is_preferred: Some(true),
        disabled: None,
        data: None,
    }))
}

/// The LSP diagnostic, among those sent, that stands for `d` (same place, same code).
fn as_sent<'a>(
    analysis: &Analysis,
    sent: &'a [lsp_types::Diagnostic],
    d: &Diagnostic,
) -> Option<&'a lsp_types::Diagnostic> {
    let range = analysis.range(d.primary.as_ref()?.span);
    let code = lsp_types::NumberOrString::String(d.code.as_str().to_string());
    sent.iter().find(|l| l.range == range && l.code.as_ref() == Some(&code))
}

fn action(
    analysis: &Analysis,
    uri: &Uri,
    fix: &Fix,
    diagnostic: Option<lsp_types::Diagnostic>,
    preferred: bool,
) -> CodeAction {
    let edit = TextEdit { range: analysis.range(fix.span), new_text: fix.replacement.clone() };
    CodeAction {
        title: fix.title.clone(),
        kind: Some(CodeActionKind::QUICKFIX),
        diagnostics: diagnostic.map(|d| vec![d]),
        edit: Some(WorkspaceEdit {
            changes: Some(HashMap::from([(uri.clone(), vec![edit])])),
            ..Default::default()
        }),
        command: None,
        is_preferred: Some(preferred),
        disabled: None,
        data: None,
    }
}

/// A location in the document.
pub fn location(uri: &Uri, range: Range) -> Location {
    Location { uri: uri.clone(), range }
}

/// What may start a line in each block, with the statement's form.
const TOP: &[(&str, &str)] = &[
    ("scene", "scene \"a cozy bedroom\" { wall height 2.7 m }"),
    ("room", "room bedroom \"bedroom\" { ... }"),
    ("door", "door exterior -- bedroom : doorway single \"white wooden door\""),
];
const SCENE: &[(&str, &str)] = &[
    ("wall height", "wall height 2.7 m"),
    ("seed", "seed 42"),
    ("ceiling", "ceiling \"white plaster\""),
    ("ceiling material", "ceiling material \"EggshellDrywall\""),
];
const ROOM: &[(&str, &str)] = &[
    ("corners", "corners in m (0, 0) (0, 4) (5, 4) (5, 0)"),
    ("floor", "floor \"oak parquet\""),
    ("floor material", "floor material \"WoodFloorsCross\""),
    ("walls", "walls \"white plaster\""),
    ("wall material", "wall material \"PureWhite\""),
    ("window", "window north fixed 150 cm x 120 cm, count 1, sill 90 cm"),
    ("object", "object sofa \"sofa\" { ... }"),
    ("wall object", "wall object painting \"painting\" { ... }"),
    ("ceiling", "ceiling \"flush mount light\""),
];
const OBJECT: &[(&str, &str)] = &[
    ("describe", "describe \"grey fabric sofa\""),
    ("size", "size 200 cm x 90 cm x 80 cm"),
    ("count", "count 2 varied"),
    ("asset", "asset \"Sofa_1\""),
    ("on top", "on top \"book\" x2 varied"),
    ("instance", "instance chair-1 { near table-0 }"),
    ("above", "above sofa-0"),
    ("height", "height 160 cm"),
    ("at", "at 2 m, 3 m"),
    ("facing", "facing 90 deg"),
    ("edge", "edge"),
    ("middle", "middle"),
];

/// Completion: the statements of the block around the cursor, relation names in object
/// blocks, the room's instances after a relation or `above`, rooms after `door`, and the words
/// of a window or door line. Every item carries a `textEdit` over what is being typed (the
/// word at the cursor, or the words of a phrase such as `in fr` for `in front of`), and the
/// answer is read from the syntax tree, so it is there while the line is half typed.
pub fn completion(analysis: &Analysis, position: Position) -> Vec<CompletionItem> {
    let offset = analysis.offset(position);
    let source = analysis.source();
    let text = source.text.as_str();
    let line_start = text[..offset].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let before = text[line_start..offset].trim_start().to_lowercase();
    let words: Vec<&str> = before.split_whitespace().collect();
    let complete_word = before.ends_with(char::is_whitespace) || before.is_empty();
    // The words before the one being typed.
    let settled: &[&str] =
        if complete_word { &words } else { &words[..words.len().saturating_sub(1)] };
    let index = analysis.index();
    let room = index.room_at(offset);
    let in_object = index.object_at(offset).is_some()
        || enclosing_block(&text[..offset])
            .is_some_and(|w| matches!(w.as_str(), "object" | "instance" | "ceiling" | "on"));

    let mut items = Vec::new();
    let keyword = |label: &str, detail: &str| CompletionItem {
        label: label.to_string(),
        kind: Some(CompletionItemKind::KEYWORD),
        detail: Some(detail.to_string()),
        ..Default::default()
    };
    let relation_or_above = !settled.is_empty() && {
        let phrase = settled.join(" ");
        phrase == "above" || RelationKind::from_words(&phrase).is_some()
    };
    if settled.first() == Some(&"door") {
        // `door a -- b : kind size`
        if settled.contains(&":") {
            let words: &[&str] = if settled.last() == Some(&":") {
                &["doorway", "doorframe", "open"]
            } else {
                &["single", "double"]
            };
            items.extend(words.iter().map(|w| keyword(w, "door")));
        } else {
            items.extend(room_items(analysis));
            items.push(keyword("exterior", "outside the house"));
        }
    } else if settled.first() == Some(&"window") {
        let words: &[&str] = match settled.len() {
            1 => &["north", "east", "south", "west"],
            2 => &["fixed", "hung", "slider"],
            _ => &[],
        };
        items.extend(words.iter().map(|w| keyword(w, "window")));
    } else if relation_or_above {
        if let Some(room) = room {
            items.extend(object_items(analysis, room, offset));
        }
    } else {
        let table = if in_object {
            OBJECT
        } else if room.is_some() {
            ROOM
        } else if enclosing_block(&text[..offset]).as_deref() == Some("scene") {
            SCENE
        } else {
            TOP
        };
        items.extend(table.iter().map(|(label, form)| keyword(label, form)));
        if in_object {
            for kind in RelationKind::ALL {
                items.push(CompletionItem {
                    label: kind.as_str().to_string(),
                    kind: Some(CompletionItemKind::OPERATOR),
                    detail: Some(relation_meaning(kind).to_string()),
                    ..Default::default()
                });
            }
        }
        // After the first word of a phrase (`in fr`), the phrases it begins.
        if !settled.is_empty() {
            items.retain(|item| item.label.contains(' ') && item.label.starts_with(&before));
        }
    }
    let edits = TypedWord::at(text, line_start, offset);
    for item in &mut items {
        let (start, end) = edits.range_for(text, &item.label);
        item.text_edit = Some(lsp_types::CompletionTextEdit::Edit(TextEdit {
            range: analysis.range(Span::new(analysis.file, start, end)),
            new_text: item.label.clone(),
        }));
    }
    items
}

/// What is being typed at the cursor: the word around it, and where the line's words start.
struct TypedWord {
    /// The start of the word at the cursor (identifier characters and `-`).
    start: usize,
    /// Its end, after the cursor.
    end: usize,
    /// The cursor.
    cursor: usize,
    /// The starts of the earlier words of the line, first first.
    earlier: Vec<usize>,
}

impl TypedWord {
    fn at(text: &str, line_start: usize, cursor: usize) -> TypedWord {
        let is_word = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
        let before: usize = text[line_start..cursor]
            .chars()
            .rev()
            .take_while(|&c| is_word(c))
            .map(char::len_utf8)
            .sum();
        let line_end = text[cursor..].find(['\n', '\r']).map_or(text.len(), |i| cursor + i);
        let after: usize =
            text[cursor..line_end].chars().take_while(|&c| is_word(c)).map(char::len_utf8).sum();
        let start = cursor - before;
        let mut earlier = Vec::new();
        let mut previous_space = true;
        for (i, c) in text[line_start..start].char_indices() {
            if previous_space && !c.is_whitespace() {
                earlier.push(line_start + i);
            }
            previous_space = c.is_whitespace();
        }
        TypedWord { start, end: cursor + after, cursor, earlier }
    }

    /// The bytes an item replaces: from the first word of the line from which the text typed
    /// so far begins the label (`in fr` for `in front of`), else the word at the cursor.
    fn range_for(&self, text: &str, label: &str) -> (usize, usize) {
        let label = label.to_lowercase();
        let start = self
            .earlier
            .iter()
            .copied()
            .find(|&s| label.starts_with(&text[s..self.cursor].to_lowercase()))
            .unwrap_or(self.start);
        (start, self.end)
    }
}

fn room_items(analysis: &Analysis) -> Vec<CompletionItem> {
    let mut seen = std::collections::BTreeSet::new();
    analysis
        .index()
        .symbols
        .iter()
        .filter(|s| s.kind == HoloSymbol::Room && seen.insert(s.name.as_str()))
        .map(|s| CompletionItem {
            label: s.name.clone(),
            kind: Some(CompletionItemKind::MODULE),
            detail: s.detail.clone(),
            ..Default::default()
        })
        .collect()
}

/// The instances a relation or `above` at `offset` may name: every instance of the room's
/// floor object groups (`nightstand-0`, `nightstand-1` for `count 2`; a bare group name is
/// ambiguous for a counted group, so none is offered), but not the object itself (all the
/// instances of the group whose block holds the cursor, or one instance in its own block).
fn object_items(analysis: &Analysis, room: usize, offset: usize) -> Vec<CompletionItem> {
    let index = analysis.index();
    let own = index.object_at(offset);
    let own_instance = own.and_then(|g| {
        index.symbols[g]
            .instance_blocks
            .iter()
            .find(|(_, _, block)| (block.start as usize) <= offset && offset < (block.end as usize))
            .map(|&(n, _, _)| n)
    });
    let mut items = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for (g, object) in index.objects_of(room) {
        // The first group of a name is the one the checker keeps; wall objects are no targets.
        if !seen.insert(object.name.as_str()) || object.kind != HoloSymbol::Object {
            continue;
        }
        for n in 0..object.count {
            if own == Some(g) && own_instance.is_none_or(|own| own == n) {
                continue;
            }
            items.push(CompletionItem {
                label: format!("{}-{n}", object.name),
                kind: Some(CompletionItemKind::VARIABLE),
                detail: object.detail.clone(),
                ..Default::default()
            });
        }
    }
    items
}

/// The first word of the line that opened the innermost block still open before the text's
/// end (`room`, `object`, `scene`, ...), found by counting braces outside strings and comments.
fn enclosing_block(text: &str) -> Option<String> {
    let mut open: Vec<usize> = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    let mut in_string = false;
    while i < bytes.len() {
        let b = bytes[i];
        if in_string {
            if b == b'\\' {
                i += 1;
            } else if b == b'"' || b == b'\n' {
                in_string = false;
            }
        } else if b == b'"' {
            in_string = true;
        } else if b == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        } else if b == b'{' {
            open.push(i);
        } else if b == b'}' {
            open.pop();
        }
        i += 1;
    }
    let at = *open.last()?;
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..at].trim_start();
    let first = line.split_whitespace().next()?;
    Some(if first == "wall" { "object".to_string() } else { first.to_string() })
}
