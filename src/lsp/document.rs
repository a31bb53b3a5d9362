//! An open document: its text, its version, and what the compiler made of it.

use super::index::Index;
use crate::compile::Analysed;
use crate::diag::Diagnostic;
use crate::resolve::Catalog;
use crate::source::{FileId, SourceFile, SourceMap, Span};
use lsp_types::{Position, Range, TextDocumentContentChangeEvent};
use std::collections::BTreeMap;

/// What the background layout solve found so far for one version of a document (run on open
/// and save, room by room: the room being edited first, then the others as they finish).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solved {
    /// The document version it was run on.
    pub version: i32,
    /// The solver's diagnostics of the rooms solved so far (objects left out, relations given
    /// up, ...), in the order a whole-scene solve gives them.
    pub diagnostics: Vec<Diagnostic>,
    /// Each relation's outcome in the rooms solved so far, by the span of the constraint as
    /// written.
    pub relations: Vec<RelationOutcome>,
    /// Whether every room is solved (the solve of this version ended).
    pub complete: bool,
    /// Each room solved, by its place in the scene's room order.
    rooms: BTreeMap<usize, RoomSolve>,
}

/// What the solve found in one room.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RoomSolve {
    /// The room's name (`bedroom`).
    pub name: String,
    /// Its relations given up because their target is left out (W0505).
    pub given_up: Vec<Diagnostic>,
    /// Its other solver diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// The outcome of each relation written in it.
    pub relations: Vec<RelationOutcome>,
    /// Where each floor and wall object instance ended, by its name (`bed-0`): placed (and
    /// where), or left out (and why).
    pub objects: BTreeMap<String, String>,
}

impl Solved {
    /// Nothing solved yet of version `version`.
    pub fn new(version: i32) -> Solved {
        Solved { version, ..Solved::default() }
    }

    /// Adds a room just solved (`index`: its place in the scene's room order), or replaces what
    /// an earlier solve of the same version found in it.
    pub fn add(&mut self, index: usize, room: RoomSolve) {
        self.rooms.insert(index, room);
        // As a whole-scene solve lists them: every room's relations given up, then every
        // room's own, in room order.
        let given_up = self.rooms.values().flat_map(|r| r.given_up.iter());
        let own = self.rooms.values().flat_map(|r| r.diagnostics.iter());
        self.diagnostics = given_up.chain(own).cloned().collect();
        self.relations = self.rooms.values().flat_map(|r| r.relations.iter().cloned()).collect();
    }

    /// What the solve found in room `name`, once that room is solved.
    pub fn room(&self, name: &str) -> Option<&RoomSolve> {
        self.rooms.values().find(|r| r.name == name)
    }

    /// How many rooms are solved.
    pub fn rooms_solved(&self) -> usize {
        self.rooms.len()
    }
}

/// Whether a written relation holds in the solved layout.
#[derive(Clone, Debug, PartialEq)]
pub struct RelationOutcome {
    /// The constraint as written.
    pub span: Span,
    /// The instance it belongs to (`chair-1`).
    pub object: String,
    /// The relation in words (`near table-0`).
    pub text: String,
    /// Whether it holds.
    pub satisfied: bool,
    /// The measured value and its unit.
    pub value: f64,
    /// `m` or `deg`.
    pub unit: &'static str,
    /// The documented range of the measure, if the relation has one.
    pub range: Option<(f64, f64)>,
}

/// An open document.
#[derive(Debug)]
pub struct Document {
    /// The name diagnostics show (the file's path, or the URI).
    pub name: String,
    /// The URI the editor gave it (a `file:` URI, or `untitled:Untitled-1`), used for every
    /// location in it.
    pub uri: Option<lsp_types::Uri>,
    /// The version the client gave.
    pub version: i32,
    /// The current text, with where its lines start (kept up to date edit by edit).
    source: SourceFile,
    /// The analysis of the current text, or `None` when the text changed since.
    pub analysis: Option<Analysis>,
    /// The last background solve of this document, if its version is the current one.
    pub solved: Option<Solved>,
    /// What earlier versions' analyses keep for the next (parsed items, asset rankings, the
    /// last plan and asset choices).
    pub memo: super::incremental::Memo,
    /// The catalog the analysis and the rankings of `cache` were made with.
    catalog: Option<std::sync::Arc<Catalog>>,
    /// Where the user was last seen working (the start of the last edit, or the position of
    /// the last request that named one): the room there is solved first.
    pub focus: Option<Position>,
    /// Why the server's text can no longer be trusted to be the editor's (a change it had to
    /// refuse), until a change sends the whole text again.
    pub out_of_sync: Option<String>,
}

/// The result of every stage before the layout solver on one version of a document.
#[derive(Debug)]
pub struct Analysis {
    /// The document's text as a source map of one file.
    pub sources: SourceMap,
    /// Its file id.
    pub file: FileId,
    /// The stages' products and diagnostics.
    pub analysed: Analysed,
    /// Declarations and references, made when first asked for (a keystroke's diagnostics do
    /// not need them).
    index: std::cell::OnceCell<Index>,
    /// The document's URI, as the editor gave it.
    pub uri: Option<lsp_types::Uri>,
}

impl Analysis {
    /// Runs parse, check, plan and resolve on the text of `source`, reusing what `memo` kept
    /// of earlier versions where the edit did not touch it (see [`super::incremental`]).
    pub fn new(
        source: &SourceFile,
        uri: Option<lsp_types::Uri>,
        catalog: &Catalog,
        memo: &mut super::incremental::Memo,
    ) -> Analysis {
        let mut sources = SourceMap::new();
        // A copy of the document's text and line starts, without indexing the lines again.
        let file = sources.add_file(source.clone());
        let mut analysed = super::incremental::analyse(&sources, file, catalog, memo);
        crate::diag::sort(&mut analysed.diagnostics);
        Analysis { sources, file, analysed, index: std::cell::OnceCell::new(), uri }
    }

    /// Every room and object group, where each is declared and named.
    pub fn index(&self) -> &Index {
        self.index.get_or_init(|| Index::new(&self.analysed.ast))
    }

    /// The source file.
    pub fn source(&self) -> &SourceFile {
        self.sources.get(self.file)
    }

    /// The byte offset of an LSP position.
    pub fn offset(&self, position: Position) -> usize {
        self.source().offset_of_lsp(position.line, position.character)
    }

    /// The LSP range of a span.
    pub fn range(&self, span: Span) -> Range {
        let (l0, c0) = self.source().lsp_position(span.start as usize);
        let (l1, c1) = self.source().lsp_position(span.end as usize);
        Range { start: Position::new(l0, c0), end: Position::new(l1, c1) }
    }
}

impl Document {
    /// A document as opened.
    pub fn new(name: String, uri: Option<lsp_types::Uri>, version: i32, text: String) -> Document {
        Document {
            source: SourceFile::new(name.as_str(), text),
            name,
            uri,
            version,
            analysis: None,
            solved: None,
            memo: super::incremental::Memo::default(),
            catalog: None,
            focus: None,
            out_of_sync: None,
        }
    }

    /// Applies one change (a whole new text, or a range replaced) and forgets the analysis.
    /// A range that runs past the text is clamped to it, as clients expect; a range whose end
    /// comes before its start is refused (`Err`), as is any ranged change while the document
    /// is out of sync (a whole text brings it back).
    pub fn apply(&mut self, change: TextDocumentContentChangeEvent) -> Result<(), String> {
        match change.range {
            None => {
                self.source = SourceFile::new(self.name.as_str(), change.text);
                self.out_of_sync = None;
            }
            Some(_) if self.out_of_sync.is_some() => {
                return Err("a ranged change to a document out of sync".to_string());
            }
            Some(range) => {
                self.focus = Some(range.start);
                let backwards = (range.end.line, range.end.character)
                    < (range.start.line, range.start.character);
                if backwards {
                    return Err(format!(
                        "a change whose range ends ({}:{}) before it starts ({}:{})",
                        range.end.line,
                        range.end.character,
                        range.start.line,
                        range.start.character
                    ));
                }
                // The document's own line starts say where the range is; they are moved by the
                // change, not made again from the whole text.
                let start = self.source.offset_of_lsp(range.start.line, range.start.character);
                let end = self.source.offset_of_lsp(range.end.line, range.end.character);
                self.source.replace_range(start..end.max(start), &change.text);
            }
        }
        // The old analysis goes back to the memo, from which the next one is made in place
        // (what it does not take is freed off the thread that answers the editor).
        self.give_back();
        self.solved = None;
        Ok(())
    }

    /// Hands the analysis of the current text (if any) back to the memo.
    fn give_back(&mut self) {
        if let Some(mut old) = self.analysis.take() {
            let empty = crate::compile::Analysed {
                ast: crate::ast::File { items: Vec::new(), span: old.analysed.ast.span },
                scene: None,
                plan: None,
                resolved: None,
                diagnostics: Vec::new(),
            };
            let analysed = std::mem::replace(&mut old.analysed, empty);
            self.memo.give_back(analysed, &old.source().text);
            discard(old);
        }
    }

    /// The analysis of the current text, computed if the text or the catalog changed.
    pub fn analysis(&mut self, catalog: &std::sync::Arc<Catalog>) -> &Analysis {
        if !self.catalog.as_ref().is_some_and(|c| std::sync::Arc::ptr_eq(c, catalog)) {
            // A catalog edited on disk: every ranking and the analysis are made again.
            self.memo.forget();
            self.give_back();
            self.catalog = Some(std::sync::Arc::clone(catalog));
        }
        let (source, memo) = (&self.source, &mut self.memo);
        let uri = self.uri.clone();
        self.analysis.get_or_insert_with(|| Analysis::new(source, uri, catalog, memo))
    }

    /// The current text.
    pub fn text(&self) -> &str {
        &self.source.text
    }
}

/// Frees a value on a background thread (started on first use; inline if it cannot start).
fn discard(analysis: Analysis) {
    use std::sync::mpsc::{channel, Sender};
    use std::sync::{Mutex, OnceLock};
    static BIN: OnceLock<Option<Mutex<Sender<Box<Analysis>>>>> = OnceLock::new();
    let bin = BIN.get_or_init(|| {
        let (tx, rx) = channel::<Box<Analysis>>();
        std::thread::Builder::new()
            .name("holoc-lsp-free".to_string())
            .spawn(move || {
                for old in rx {
                    drop(old);
                }
            })
            .ok()
            .map(|_| Mutex::new(tx))
    });
    let sent = bin.as_ref().and_then(|tx| tx.lock().ok()).map(|tx| tx.send(Box::new(analysis)));
    // Without the thread (or with its channel closed) the value is dropped here.
    drop(sent);
}
