//! `holoc lsp`: a language server over stdio, built on `lsp-server` and `lsp-types`.
//!
//! One thread reads the client's messages and handles them strictly in order: a change is
//! applied before anything that follows it is read, and a request always sees every change
//! sent before it. Diagnostics are published with the document's version once no more
//! messages are waiting, so a burst of keystrokes is analysed once, for its last version, and
//! diagnostics of an older version are never sent. Every stage before the layout solver runs on
//! each change ([`crate::compile::analyse`]); on open and on save a layout solve runs on a
//! second thread, room by room: the room the user was last seen working in first (the last
//! edit, or the last request with a position; else the first room), then the others. Each
//! room's warnings (objects that cannot be placed) and relation outcomes are published as soon
//! as it is solved, if the document has not changed meanwhile; once every room is, they are
//! those of a whole-scene solve (`holoc build`). A change cancels the solve: one not yet
//! started never starts, and one running stops between rooms or inside the room's search
//! ([`crate::cancel`]); what it found is never shown.
//!
//! Catalogs come from the initialization options (`{"catalogs": ["a.json.gz"]}`) and from the
//! nearest `holoc.toml` in the document's folder or above it, inside the workspace folders the
//! client opened (`catalogs = ["assets.json"]`, paths relative to the file).

pub mod document;
pub mod features;
pub mod highlight;
pub mod incremental;
pub mod index;
pub mod transport;

use crate::resolve::objathor::ObjathorOptions;
use crate::resolve::Catalog;
use crossbeam_channel::{Receiver, Sender};
use document::{Analysis, Document, RelationOutcome, Solved};
use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::{notification, request, Uri};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// How the server is started.
#[derive(Clone, Debug, Default)]
pub struct ServerOptions {
    /// Catalogs given on the command line (`holoc lsp --catalog FILE`).
    pub catalogs: Vec<PathBuf>,
    /// The objathor folder of the command line (`--objathor DIR`).
    pub objathor: Option<crate::resolve::objathor::ObjathorOptions>,
    /// Whether layout solves run in the background on open and save.
    pub solve_on_save: bool,
    /// For tests and benchmarks: when set, the background solver waits for a message (or the
    /// sender's end) here after it has reported the first room of a solve, before it solves the
    /// others, so that a client can act while a solve is known to be half done.
    pub solve_gate: Option<Receiver<()>>,
}

/// How a session ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// `exit` after `shutdown`: the process exits with 0.
    AfterShutdown,
    /// `exit` without `shutdown`, or the input closed first: the process exits with 1, as the
    /// protocol asks.
    WithoutShutdown,
}

/// Runs the server on stdin and stdout until the client says `exit` (or closes its end).
pub fn run_stdio(options: ServerOptions) -> Result<Ending, String> {
    let (connection, io) = transport::stdio();
    let ending = serve(&connection, options)?;
    drop(connection);
    io.join()?;
    Ok(ending)
}

/// The server's capabilities.
pub fn capabilities() -> lsp_types::ServerCapabilities {
    use lsp_types::{
        CodeActionKind, CodeActionOptions, CodeActionProviderCapability, CompletionOptions, OneOf,
        RenameOptions, SaveOptions, ServerCapabilities, TextDocumentSyncCapability,
        TextDocumentSyncKind, TextDocumentSyncOptions, TextDocumentSyncSaveOptions,
    };
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Options(TextDocumentSyncOptions {
            open_close: Some(true),
            change: Some(TextDocumentSyncKind::INCREMENTAL),
            save: Some(TextDocumentSyncSaveOptions::SaveOptions(SaveOptions {
                include_text: Some(false),
            })),
            ..Default::default()
        })),
        hover_provider: Some(lsp_types::HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: lsp_types::WorkDoneProgressOptions::default(),
        })),
        document_symbol_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec![" ".to_string()]),
            ..Default::default()
        }),
        document_formatting_provider: Some(OneOf::Left(true)),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            ..Default::default()
        })),
        semantic_tokens_provider: Some(
            lsp_types::SemanticTokensOptions {
                legend: highlight::legend(),
                range: Some(true),
                full: Some(lsp_types::SemanticTokensFullOptions::Bool(true)),
                ..Default::default()
            }
            .into(),
        ),
        ..Default::default()
    }
}

/// The `initialize` request's parameters, answering every other request before it with
/// `ServerNotInitialized` and dropping other notifications; `None` when the client says `exit`
/// or goes away first.
fn handshake(connection: &Connection) -> Option<(lsp_server::RequestId, serde_json::Value)> {
    loop {
        match connection.receiver.recv().ok()? {
            Message::Request(r) if r.method == request::Initialize::METHOD => {
                return Some((r.id, r.params));
            }
            Message::Request(r) => {
                let _ = connection.sender.send(Message::Response(Response::new_err(
                    r.id,
                    ErrorCode::ServerNotInitialized as i32,
                    "the server is not initialized yet".to_string(),
                )));
            }
            Message::Notification(n) if n.method == notification::Exit::METHOD => return None,
            Message::Notification(_) | Message::Response(_) => {}
        }
    }
}

/// Serves one client on `connection`: the initialize handshake, then messages until `exit`.
/// Messages may follow `initialize` at once (`initialized` is not awaited before them).
pub fn serve(connection: &Connection, options: ServerOptions) -> Result<Ending, String> {
    let caps = serde_json::to_value(capabilities()).map_err(|e| e.to_string())?;
    let Some((id, init)) = handshake(connection) else { return Ok(Ending::WithoutShutdown) };
    let result = serde_json::json!({
        "capabilities": caps,
        "serverInfo": {"name": "holoc", "version": env!("CARGO_PKG_VERSION")},
    });
    connection
        .sender
        .send(Message::Response(Response::new_ok(id, result)))
        .map_err(|e| e.to_string())?;
    let mut catalogs = options.catalogs.clone();
    if let Some(paths) = init
        .get("initializationOptions")
        .and_then(|o| o.get("catalogs"))
        .and_then(serde_json::Value::as_array)
    {
        catalogs.extend(paths.iter().filter_map(|p| p.as_str().map(PathBuf::from)));
    }
    let mut objathor = options.objathor.clone();
    if let Some(o) = init.get("initializationOptions").filter(|o| o.get("objathor").is_some()) {
        let word = |k: &str| o.get(k).and_then(serde_json::Value::as_str);
        // A bad setting leaves the command line's folder in force.
        if let Ok(found) = crate::resolve::objathor::ObjathorOptions::from_words(
            Path::new(""),
            word("objathor").map(Path::new),
            word("objathorVersion"),
            word("objathorScoring"),
            word("objathorMix"),
            word("objathorPick"),
            word("objathorClip").map(Path::new),
        ) {
            objathor = found;
        }
    }
    // Without the solve there is no worker, and the loop waits on a channel that never
    // delivers (a dropped sender would make every wait return at once, spinning a core).
    let (jobs, mut results) = if options.solve_on_save {
        let (jobs, results) = solve_worker(options.solve_gate.clone());
        (Some(jobs), results)
    } else {
        (None, crossbeam_channel::never())
    };
    let mut server = Server {
        sender: connection.sender.clone(),
        documents: BTreeMap::new(),
        catalogs,
        objathor,
        catalog_cache: HashMap::new(),
        published: BTreeMap::new(),
        configs: HashMap::new(),
        roots: workspace_roots(&init),
        dirty: BTreeSet::new(),
        jobs,
        cancel: BTreeMap::new(),
        shutting_down: false,
    };
    loop {
        crossbeam_channel::select! {
            recv(connection.receiver) -> message => {
                let Ok(message) = message else { return Ok(server.ending()) };
                if server.handle(message) == Flow::Exit {
                    return Ok(server.ending());
                }
            }
            recv(results) -> event => {
                match event {
                    Ok(event) => server.solved(event),
                    // The solver thread is gone (it could not start, or the server's end of
                    // its queue closed): wait on the client alone from now on.
                    Err(_) => results = crossbeam_channel::never(),
                }
            }
        }
        if connection.receiver.is_empty() {
            server.publish_dirty();
        }
    }
}

#[derive(PartialEq, Eq)]
enum Flow {
    Continue,
    Exit,
}

/// What a document's catalog is made of: the catalog files and the objathor folder.
type CatalogKey = (Vec<PathBuf>, Option<ObjathorOptions>);

struct Server {
    sender: Sender<Message>,
    /// Open documents by URI.
    documents: BTreeMap<String, Document>,
    /// Catalogs of the command line and the initialization options.
    catalogs: Vec<PathBuf>,
    /// The objathor folder of the command line or the initialization options.
    objathor: Option<ObjathorOptions>,
    /// Loaded catalogs by their list of files and objathor folder, with the files' sizes and
    /// times when loaded.
    catalog_cache: HashMap<CatalogKey, (Vec<Stamp>, Arc<Catalog>)>,
    /// The last version published for each document (a publish never goes back).
    published: BTreeMap<String, i32>,
    /// Each `holoc.toml` read: when it was modified and the catalogs it lists.
    configs: HashMap<PathBuf, (Option<std::time::SystemTime>, Config)>,
    /// The client's workspace folders: where `holoc.toml` is looked up.
    roots: Vec<PathBuf>,
    /// Documents whose diagnostics must be (re)published.
    dirty: BTreeSet<String>,
    /// The background solver's queue, when solving on save is on.
    jobs: Option<Sender<SolveJob>>,
    /// The cancellation token of each document's last solve job.
    cancel: BTreeMap<String, Arc<crate::cancel::Token>>,
    shutting_down: bool,
}

impl Server {
    fn ending(&self) -> Ending {
        if self.shutting_down {
            Ending::AfterShutdown
        } else {
            Ending::WithoutShutdown
        }
    }

    fn send(&self, message: Message) {
        // The client is gone when this fails; the reader thread ends the loop.
        let _ = self.sender.send(message);
    }

    fn notify<N: lsp_types::notification::Notification>(&self, params: N::Params) {
        self.send(Message::Notification(Notification::new(N::METHOD.to_string(), params)));
    }

    /// Writes to the editor's log of the server (`window/logMessage`).
    fn log(&self, kind: lsp_types::MessageType, message: String) {
        self.notify::<notification::LogMessage>(lsp_types::LogMessageParams { typ: kind, message });
    }

    fn show(&self, kind: lsp_types::MessageType, message: String) {
        self.notify::<notification::ShowMessage>(lsp_types::ShowMessageParams {
            typ: kind,
            message,
        });
    }

    fn handle(&mut self, message: Message) -> Flow {
        match message {
            Message::Request(request) => {
                if request.method == request::Shutdown::METHOD {
                    self.shutting_down = true;
                    self.send(Message::Response(Response::new_ok(request.id, ())));
                    return Flow::Continue;
                }
                if self.shutting_down {
                    self.send(Message::Response(Response::new_err(
                        request.id,
                        ErrorCode::InvalidRequest as i32,
                        "the server is shutting down".to_string(),
                    )));
                    return Flow::Continue;
                }
                let id = request.id.clone();
                let response = match self.request(request) {
                    Ok(value) => Response { id, result: Some(value), error: None },
                    Err((code, message)) => Response::new_err(id, code as i32, message),
                };
                self.send(Message::Response(response));
            }
            Message::Notification(n) => {
                if n.method == notification::Exit::METHOD {
                    return Flow::Exit;
                }
                self.notification(n);
            }
            Message::Response(_) => {}
        }
        Flow::Continue
    }

    fn notification(&mut self, n: Notification) {
        match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(n.params)
                else {
                    return;
                };
                let uri = p.text_document.uri.as_str().to_string();
                let name = document_name(&p.text_document.uri);
                // Opened again without a close: its versions start afresh.
                self.published.remove(&uri);
                self.documents.insert(
                    uri.clone(),
                    Document::new(
                        name,
                        Some(p.text_document.uri),
                        p.text_document.version,
                        p.text_document.text,
                    ),
                );
                self.dirty.insert(uri.clone());
                self.schedule_solve(&uri);
            }
            notification::DidChangeTextDocument::METHOD => self.did_change(n.params),
            notification::DidSaveTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidSaveTextDocumentParams>(n.params)
                else {
                    return;
                };
                self.schedule_solve(p.text_document.uri.as_str());
            }
            notification::DidChangeWatchedFiles::METHOD => {
                // A catalog or `holoc.toml` changed on disk: every document is analysed again
                // (each is checked against the files' times when it is).
                self.dirty.extend(self.documents.keys().cloned());
            }
            notification::DidCloseTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(n.params)
                else {
                    return;
                };
                let uri = p.text_document.uri;
                let key = uri.as_str().to_string();
                if let Some(token) = self.cancel.remove(&key) {
                    token.cancel();
                }
                self.documents.remove(&key);
                self.dirty.remove(&key);
                self.published.remove(&key);
                // Clear what the editor shows for a closed file.
                self.notify::<notification::PublishDiagnostics>(
                    lsp_types::PublishDiagnosticsParams {
                        uri,
                        diagnostics: Vec::new(),
                        version: None,
                    },
                );
            }
            _ => {}
        }
    }

    /// A change: applied in order, or refused (logged) when it cannot be applied faithfully: a
    /// version that does not grow, parameters that cannot be read, a range that ends before it
    /// starts. A refused change leaves the document out of sync: its diagnostics are cleared,
    /// the user is asked to reopen it, and only a change with the whole text is applied until
    /// then (what a client sends after reopening, or on its own to resynchronize).
    fn did_change(&mut self, params: serde_json::Value) {
        use lsp_types::MessageType;
        let uri = params
            .get("textDocument")
            .and_then(|d| d.get("uri"))
            .and_then(serde_json::Value::as_str)
            .map(str::to_string);
        let parsed = serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(params);
        let Some(uri) = uri else {
            self.log(MessageType::ERROR, "holoc: a didChange without a document; ignored".into());
            return;
        };
        if let Some(token) = self.cancel.remove(&uri) {
            token.cancel();
        }
        if !self.documents.contains_key(&uri) {
            self.log(
                MessageType::WARNING,
                format!("holoc: a change to `{uri}`, which is not open"),
            );
            return;
        }
        let refused = match parsed {
            Err(e) => Some(format!("its parameters cannot be read ({e})")),
            Ok(p) => {
                let doc = self.documents.get_mut(&uri).expect("checked above");
                let version = p.text_document.version;
                let whole = p.content_changes.iter().any(|c| c.range.is_none());
                if version <= doc.version && !(doc.out_of_sync.is_some() && whole) {
                    Some(format!(
                        "its version {version} does not follow the document's {}",
                        doc.version
                    ))
                } else {
                    let mut why = None;
                    for change in p.content_changes {
                        if let Err(e) = doc.apply(change) {
                            why = Some(e);
                            break;
                        }
                    }
                    doc.version = version;
                    why
                }
            }
        };
        if let Some(why) = refused {
            let doc = self.documents.get_mut(&uri).expect("checked above");
            let first = doc.out_of_sync.is_none();
            if first {
                doc.out_of_sync = Some(why.clone());
            }
            self.log(MessageType::ERROR, format!("holoc: refused a change to `{uri}`: {why}"));
            if first {
                self.show(
                    MessageType::WARNING,
                    format!(
                        "holoc lost track of `{}` ({why}); close and reopen it to see its diagnostics again",
                        doc_name(&uri)
                    ),
                );
            }
        }
        self.dirty.insert(uri);
    }

    /// The catalog for a document: the server's catalogs and those of the nearest
    /// `holoc.toml`, loaded again when one of the files changes on disk.
    fn catalog_for(&mut self, uri: &str) -> Arc<Catalog> {
        let mut paths = self.catalogs.clone();
        let mut objathor = self.objathor.clone();
        let file = uri_path(uri);
        if let Some(found) = file.as_deref().and_then(|f| find_config(f, &self.roots)) {
            // Read again only when the file changed; a bad one is reported once.
            let modified = std::fs::metadata(&found).and_then(|m| m.modified()).ok();
            let known = self.configs.get(&found).filter(|(when, _)| *when == modified);
            let listed = match known {
                Some((_, listed)) => listed.clone(),
                None => {
                    let listed = read_config(&found).unwrap_or_else(|message| {
                        self.show(lsp_types::MessageType::WARNING, message);
                        (Vec::new(), None)
                    });
                    self.configs.insert(found, (modified, listed.clone()));
                    listed
                }
            };
            paths.extend(listed.0);
            if listed.1.is_some() {
                objathor = listed.1;
            }
        }
        // Each file's size and time: a catalog edited on disk is loaded again.
        let stamps: Vec<Stamp> = paths.iter().map(|p| stamp(p)).collect();
        let key = (paths, objathor);
        if let Some((known, catalog)) = self.catalog_cache.get(&key) {
            if *known == stamps {
                return Arc::clone(catalog);
            }
        }
        let mut sources = crate::source::SourceMap::new();
        let loaded = Catalog::load_with(&key.0, key.1.as_ref(), &mut sources);
        if !loaded.diagnostics.is_empty() {
            let text = crate::diag::format::render_short(&sources, &loaded.diagnostics);
            self.show(lsp_types::MessageType::WARNING, format!("holoc catalogs:\n{text}"));
        }
        let catalog = Arc::new(loaded.value);
        self.catalog_cache.insert(key, (stamps, Arc::clone(&catalog)));
        catalog
    }

    /// The document at `uri`, analysed.
    fn analysed(&mut self, uri: &str) -> Option<&mut Document> {
        let catalog = self.catalog_for(uri);
        let doc = self.documents.get_mut(uri)?;
        doc.analysis(&catalog);
        Some(doc)
    }

    fn publish_dirty(&mut self) {
        let dirty = std::mem::take(&mut self.dirty);
        for key in dirty {
            let Some(doc) = self.documents.get(&key) else { continue };
            let Some(uri) = doc.uri.clone() else { continue };
            if doc.out_of_sync.is_some() {
                // Nothing is known of the editor's text: show nothing rather than stale lines.
                self.notify::<notification::PublishDiagnostics>(
                    lsp_types::PublishDiagnosticsParams {
                        uri,
                        diagnostics: Vec::new(),
                        version: None,
                    },
                );
                continue;
            }
            let Some(doc) = self.analysed(&key) else { continue };
            let version = doc.version;
            let Some(analysis) = doc.analysis.as_ref() else { continue };
            // An editor shows a bounded list, as `holoc check` prints one, closed by a
            // diagnostic that counts the rest.
            let diagnostics = features::diagnostics(
                analysis,
                doc.solved.as_ref(),
                crate::diag::MAX_SHOWN_PER_FILE,
            );
            // The version published never goes back, whatever the client sent.
            let version = match self.published.get(&key) {
                Some(&last) if version < last => None,
                _ => {
                    self.published.insert(key.clone(), version);
                    Some(version)
                }
            };
            self.notify::<notification::PublishDiagnostics>(lsp_types::PublishDiagnosticsParams {
                uri,
                diagnostics,
                version,
            });
        }
    }

    fn schedule_solve(&mut self, uri: &str) {
        if self.jobs.is_none() {
            return;
        }
        let catalog = self.catalog_for(uri);
        let Some(doc) = self.documents.get_mut(uri) else { return };
        let focus = doc.focus;
        let analysis = doc.analysis(&catalog);
        if analysis.analysed.diagnostics.iter().any(crate::diag::Diagnostic::is_error) {
            return;
        }
        // The room the user was last seen in is solved first; else the first room.
        let first = focus
            .and_then(|p| features::room_at(analysis, analysis.offset(p)))
            .or_else(|| {
                let mut rooms = analysis.index().symbols.iter();
                rooms.find(|s| s.kind == index::SymbolKind::Room).map(|s| s.name.as_str())
            })
            .map(str::to_string);
        let cancel = crate::cancel::Token::new("solve");
        if let Some(old) = self.cancel.insert(uri.to_string(), Arc::clone(&cancel)) {
            old.cancel();
        }
        let job = SolveJob {
            uri: uri.to_string(),
            name: doc.name.clone(),
            version: doc.version,
            text: doc.text().to_string(),
            catalog,
            first,
            cancel,
        };
        if let Some(jobs) = &self.jobs {
            let _ = jobs.send(job);
        }
    }

    /// What the background solver reports: a room solved, kept (and published) if the
    /// document is still at the version solved; or the end of a solve.
    fn solved(&mut self, event: SolveEvent) {
        match event {
            SolveEvent::Room { uri, version, index, room } => {
                let Some(doc) = self.documents.get_mut(&uri) else { return };
                if doc.version != version {
                    return; // the document changed while it was solved
                }
                let solved = doc.solved.get_or_insert_with(|| Solved::new(version));
                solved.add(index, room);
                self.dirty.insert(uri);
            }
            SolveEvent::Ended { uri, version, rooms, total, cancelled } => {
                if cancelled {
                    let total = total.map_or_else(String::new, |n| format!(" of {n}"));
                    self.log(
                        lsp_types::MessageType::LOG,
                        format!(
                            "holoc: the solve of version {version} of `{}` stopped after {rooms}{total} room(s): a change (or a newer solve) cancelled it",
                            doc_name(&uri)
                        ),
                    );
                    return;
                }
                let Some(doc) = self.documents.get_mut(&uri) else { return };
                if doc.version != version {
                    return;
                }
                doc.solved.get_or_insert_with(|| Solved::new(version)).complete = true;
                self.dirty.insert(uri);
            }
        }
    }

    /// The analysis of an open document and its last solve, or the error a request on a
    /// document that is not open gets.
    fn opened(&mut self, uri: &Uri) -> Result<(&Analysis, Option<&Solved>), (ErrorCode, String)> {
        let not_open = || (ErrorCode::InvalidParams, format!("`{}` is not open", uri.as_str()));
        if let Some(why) = self.documents.get(uri.as_str()).and_then(|d| d.out_of_sync.clone()) {
            return Err((
                ErrorCode::RequestFailed,
                format!("`{}` is out of sync ({why}); close and reopen it", uri.as_str()),
            ));
        }
        let doc = self.analysed(uri.as_str()).ok_or_else(not_open)?;
        let analysis = doc.analysis.as_ref().ok_or_else(not_open)?;
        Ok((analysis, doc.solved.as_ref()))
    }

    /// The text of an open document, without analysing it (highlighting reads the text
    /// alone), or the error a request on a document that is not open or out of sync gets.
    fn text_of(&self, uri: &Uri) -> Result<&str, (ErrorCode, String)> {
        let doc = self
            .documents
            .get(uri.as_str())
            .ok_or_else(|| (ErrorCode::InvalidParams, format!("`{}` is not open", uri.as_str())))?;
        if let Some(why) = &doc.out_of_sync {
            return Err((
                ErrorCode::RequestFailed,
                format!("`{}` is out of sync ({why}); close and reopen it", uri.as_str()),
            ));
        }
        Ok(doc.text())
    }

    /// Keeps where a request says the user is (its position, or the start of its range) as
    /// the document's focus: the room there is solved first.
    fn note_focus(&mut self, params: &serde_json::Value) {
        let Some(uri) = params.pointer("/textDocument/uri").and_then(serde_json::Value::as_str)
        else {
            return;
        };
        let at = params.get("position").or_else(|| params.pointer("/range/start"));
        let Some(at) =
            at.and_then(|p| serde_json::from_value::<lsp_types::Position>(p.clone()).ok())
        else {
            return;
        };
        if let Some(doc) = self.documents.get_mut(uri) {
            doc.focus = Some(at);
        }
    }

    fn request(&mut self, request: Request) -> Result<serde_json::Value, (ErrorCode, String)> {
        fn params<P: serde::de::DeserializeOwned>(r: Request) -> Result<P, (ErrorCode, String)> {
            serde_json::from_value(r.params).map_err(|e| (ErrorCode::InvalidParams, e.to_string()))
        }
        fn json<T: serde::Serialize>(value: T) -> Result<serde_json::Value, (ErrorCode, String)> {
            serde_json::to_value(value).map_err(|e| (ErrorCode::InternalError, e.to_string()))
        }
        self.note_focus(&request.params);
        match request.method.as_str() {
            request::HoverRequest::METHOD => {
                let p: lsp_types::HoverParams = params(request)?;
                let at = p.text_document_position_params;
                let uri = at.text_document.uri;
                // A solve of this version runs while its token is not cancelled, until every
                // room is solved.
                let on_save = self.jobs.is_some();
                let running =
                    on_save && self.cancel.get(uri.as_str()).is_some_and(|t| !t.is_cancelled());
                let (analysis, solved) = self.opened(&uri)?;
                let solving = (on_save, running && !solved.is_some_and(|s| s.complete));
                json(features::hover(analysis, solved, solving, at.position))
            }
            request::GotoDefinition::METHOD => {
                let p: lsp_types::GotoDefinitionParams = params(request)?;
                let at = p.text_document_position_params;
                let uri = at.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                json(features::definition(analysis, at.position).map(|range| {
                    lsp_types::GotoDefinitionResponse::Scalar(features::location(&uri, range))
                }))
            }
            request::References::METHOD => {
                let p: lsp_types::ReferenceParams = params(request)?;
                let at = p.text_document_position;
                let uri = at.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                let ranges =
                    features::references(analysis, at.position, p.context.include_declaration);
                json(ranges.into_iter().map(|r| features::location(&uri, r)).collect::<Vec<_>>())
            }
            request::PrepareRenameRequest::METHOD => {
                let p: lsp_types::TextDocumentPositionParams = params(request)?;
                let uri = p.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                json(features::prepare_rename(analysis, p.position))
            }
            request::Rename::METHOD => {
                let p: lsp_types::RenameParams = params(request)?;
                let at = p.text_document_position;
                let uri = at.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                let edit = features::rename(analysis, &uri, at.position, &p.new_name)
                    .map_err(|m| (ErrorCode::RequestFailed, m))?;
                json(edit)
            }
            request::DocumentSymbolRequest::METHOD => {
                let p: lsp_types::DocumentSymbolParams = params(request)?;
                let uri = p.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                json(lsp_types::DocumentSymbolResponse::Nested(features::document_symbols(
                    analysis,
                )))
            }
            request::Completion::METHOD => {
                let p: lsp_types::CompletionParams = params(request)?;
                let at = p.text_document_position;
                let uri = at.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                json(lsp_types::CompletionResponse::Array(features::completion(
                    analysis,
                    at.position,
                )))
            }
            request::Formatting::METHOD => {
                let p: lsp_types::DocumentFormattingParams = params(request)?;
                let uri = p.text_document.uri;
                let (analysis, _) = self.opened(&uri)?;
                let edits =
                    features::formatting(analysis).map_err(|m| (ErrorCode::RequestFailed, m))?;
                json(edits)
            }
            request::CodeActionRequest::METHOD => {
                let p: lsp_types::CodeActionParams = params(request)?;
                let uri = p.text_document.uri;
                let (analysis, solved) = self.opened(&uri)?;
                json(features::code_actions(analysis, solved, &uri, p.range))
            }
            request::SemanticTokensFullRequest::METHOD => {
                let p: lsp_types::SemanticTokensParams = params(request)?;
                let text = self.text_of(&p.text_document.uri)?;
                let data = highlight::encode(text, &highlight::tokens(text), None);
                json(lsp_types::SemanticTokens { result_id: None, data })
            }
            request::SemanticTokensRangeRequest::METHOD => {
                let p: lsp_types::SemanticTokensRangeParams = params(request)?;
                let text = self.text_of(&p.text_document.uri)?;
                let lines = Some((p.range.start.line, p.range.end.line));
                let data = highlight::encode(text, &highlight::tokens(text), lines);
                json(lsp_types::SemanticTokens { result_id: None, data })
            }
            other => Err((ErrorCode::MethodNotFound, format!("holoc does not answer `{other}`"))),
        }
    }
}

/// A layout solve to run in the background.
struct SolveJob {
    uri: String,
    name: String,
    version: i32,
    text: String,
    catalog: Arc<Catalog>,
    /// The room to solve before the others (by name).
    first: Option<String>,
    /// Cancelled by a change to the document: the solve stops between rooms, or inside a
    /// room's search.
    cancel: Arc<crate::cancel::Token>,
}

/// What the background solver says of a job.
enum SolveEvent {
    /// One room solved.
    Room {
        uri: String,
        version: i32,
        /// The room's place in the scene's room order.
        index: usize,
        room: document::RoomSolve,
    },
    /// The job ended: every room solved, or stopped by its token (`cancelled`) after
    /// `rooms` of `total` rooms (`None` when no room was solved).
    Ended { uri: String, version: i32, rooms: usize, total: Option<usize>, cancelled: bool },
}

/// Starts the background solver: a thread that takes the newest job of each document and
/// solves it room by room, sending each room as it is solved and then the end of the job,
/// unless the job is cancelled meanwhile. `gate`: see [`ServerOptions::solve_gate`].
fn solve_worker(gate: Option<Receiver<()>>) -> (Sender<SolveJob>, Receiver<SolveEvent>) {
    let (job_tx, job_rx) = crossbeam_channel::unbounded::<SolveJob>();
    let (result_tx, result_rx) = crossbeam_channel::unbounded();
    // Without the thread there is no background solve; every diagnostic before the solver
    // is still published.
    let _ = std::thread::Builder::new().name("holoc-lsp-solve".to_string()).spawn(move || {
        while let Ok(first) = job_rx.recv() {
            // Only the newest job of each document is worth running.
            let mut newest: BTreeMap<String, SolveJob> = BTreeMap::new();
            newest.insert(first.uri.clone(), first);
            for job in job_rx.try_iter() {
                newest.insert(job.uri.clone(), job);
            }
            for job in newest.into_values() {
                if job.cancel.is_cancelled() {
                    continue;
                }
                if !solve(&job, &result_tx, gate.as_ref()) {
                    return;
                }
            }
        }
    });
    (job_tx, result_rx)
}

/// Solves one version of a document room by room, as `holoc build` does, sending what the
/// solver says of each room as soon as it is solved; `false` when the server is gone.
fn solve(job: &SolveJob, events: &Sender<SolveEvent>, gate: Option<&Receiver<()>>) -> bool {
    let _token = crate::cancel::scoped(Some(Arc::clone(&job.cancel)));
    let mut sources = crate::source::SourceMap::new();
    let file = sources.add(job.name.as_str(), job.text.as_str());
    let options = crate::compile::BuildOptions::new(&job.catalog);
    let done = AtomicUsize::new(0);
    let total = AtomicUsize::new(0);
    let on_room = |scene: &crate::check::Scene, room: crate::solve::RoomDone<'_>| {
        total.store(scene.rooms.len(), Ordering::SeqCst);
        let _ = events.send(SolveEvent::Room {
            uri: job.uri.clone(),
            version: job.version,
            index: room.index,
            room: room_solve(scene, &room),
        });
        if done.fetch_add(1, Ordering::SeqCst) == 0 {
            if let Some(gate) = gate {
                // A message or the sender's end: either lets the solve go on.
                let _ = gate.recv();
            }
        }
    };
    let _ = crate::compile::solve_by_room(&sources, file, &options, job.first.as_deref(), &on_room);
    let rooms = done.load(Ordering::SeqCst);
    let total = Some(total.load(Ordering::SeqCst)).filter(|_| rooms > 0);
    events
        .send(SolveEvent::Ended {
            uri: job.uri.clone(),
            version: job.version,
            rooms,
            total,
            cancelled: job.cancel.is_cancelled(),
        })
        .is_ok()
}

/// What the solver says of one room: its diagnostics, its relations' outcomes and where each
/// object ended.
fn room_solve(
    scene: &crate::check::Scene,
    done: &crate::solve::RoomDone<'_>,
) -> document::RoomSolve {
    let solver = |list: &[crate::diag::Diagnostic]| -> Vec<crate::diag::Diagnostic> {
        list.iter().filter(|d| d.code.stage() == "solve").cloned().collect()
    };
    let solved = done.solved;
    let mut objects = BTreeMap::new();
    for p in &solved.layout.floor {
        let Some(object) = solved.problem.objects.get(p.index) else { continue };
        objects.insert(
            object.id.clone(),
            format!("placed at ({:.2}, {:.2}) m, facing {}°", p.pose.x, p.pose.z, p.pose.rot.deg()),
        );
    }
    for p in &solved.layout.wall {
        objects.insert(
            p.id.clone(),
            format!(
                "placed on a wall at ({:.2}, {:.2}) m, {:.2} m up",
                p.position_m[0], p.position_m[2], p.position_m[1]
            ),
        );
    }
    for u in solved.layout.unplaced.iter().filter(|u| u.kind != "small") {
        objects.insert(u.id.clone(), format!("left out ({}): {}", u.code.as_str(), u.reason));
    }
    document::RoomSolve {
        name: scene.rooms.get(done.index).map(|r| r.name.clone()).unwrap_or_default(),
        given_up: solver(done.given_up),
        diagnostics: solver(done.diagnostics),
        relations: room_relation_outcomes(solved),
        objects,
    }
}

/// Every relation of every placed object with its measure; relations of objects left out are
/// reported as not holding.
pub fn relation_outcomes(layout: &crate::solve::Layout) -> Vec<RelationOutcome> {
    layout.rooms.iter().flat_map(room_relation_outcomes).collect()
}

/// Every relation of every placed object of one solved room with its measure; relations of
/// objects left out are reported as not holding.
pub fn room_relation_outcomes(room: &crate::solve::SolvedRoom) -> Vec<RelationOutcome> {
    let mut out = Vec::new();
    let mut placed = vec![false; room.problem.objects.len()];
    for p in &room.layout.floor {
        let Some(object) = room.problem.objects.get(p.index) else { continue };
        placed[p.index] = true;
        for (i, c) in object.constraints.iter().enumerate() {
            let (Some(span), Some(report)) = (c.span, p.constraints.get(i + 1)) else {
                continue;
            };
            out.push(RelationOutcome {
                span,
                object: object.id.clone(),
                text: report.text.clone(),
                satisfied: report.measure.satisfied,
                value: report.measure.value,
                unit: report.measure.unit,
                range: report.range,
            });
        }
    }
    for (k, object) in room.problem.objects.iter().enumerate() {
        if placed[k] {
            continue;
        }
        for c in &object.constraints {
            let Some(span) = c.span else { continue };
            let target = room.problem.objects.get(c.target).map_or("?", |t| t.id.as_str());
            out.push(RelationOutcome {
                span,
                object: object.id.clone(),
                text: format!("{} {target} (the object is left out)", c.written.as_str()),
                satisfied: false,
                value: f64::NAN,
                unit: "m",
                range: None,
            });
        }
    }
    out
}

/// The name diagnostics show for a document: its path for a `file:` URI, else the URI
/// (`untitled:Untitled-1` stays what it is).
fn document_name(uri: &Uri) -> String {
    doc_name(uri.as_str())
}

fn doc_name(uri: &str) -> String {
    uri_path(uri).map_or_else(|| uri.to_string(), |p| p.display().to_string())
}

/// The path of a `file:` URI, percent-decoded (by the `url` crate); `None` for another scheme.
pub fn uri_path(uri: &str) -> Option<PathBuf> {
    let url = url::Url::parse(uri).ok()?;
    if url.scheme() != "file" {
        return None;
    }
    url.to_file_path().ok()
}

/// What tells that a file changed on disk: its size and modification time (`None` when it
/// cannot be read).
type Stamp = Option<(u64, Option<std::time::SystemTime>)>;

fn stamp(path: &Path) -> Stamp {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.len(), meta.modified().ok()))
}

/// The largest `holoc.toml` the server reads, bytes.
pub const MAX_CONFIG_BYTES: u64 = 1024 * 1024;

/// The nearest `holoc.toml` in the file's folder or a folder above it, inside one of the
/// workspace folders the client opened (a folder above them, shared with other users, never
/// chooses the catalogs). Without workspace folders, none is read.
fn find_config(file: &Path, roots: &[PathBuf]) -> Option<PathBuf> {
    file.ancestors()
        .skip(1)
        .filter(|dir| roots.iter().any(|root| dir.starts_with(root)))
        .map(|dir| dir.join("holoc.toml"))
        .find(|p| p.is_file())
}

/// The workspace folders of the `initialize` parameters (`workspaceFolders`, else `rootUri`,
/// else `rootPath`), as paths.
fn workspace_roots(init: &serde_json::Value) -> Vec<PathBuf> {
    let folders: Vec<PathBuf> = init
        .get("workspaceFolders")
        .and_then(serde_json::Value::as_array)
        .map(|list| {
            list.iter()
                .filter_map(|f| f.get("uri").and_then(serde_json::Value::as_str))
                .filter_map(uri_path)
                .collect()
        })
        .unwrap_or_default();
    if !folders.is_empty() {
        return folders;
    }
    if let Some(root) = init.get("rootUri").and_then(serde_json::Value::as_str).and_then(uri_path) {
        return vec![root];
    }
    init.get("rootPath")
        .and_then(serde_json::Value::as_str)
        .map(PathBuf::from)
        .into_iter()
        .collect()
}

/// What a `holoc.toml` gives the server: its catalogs and its objathor folder.
type Config = (Vec<PathBuf>, Option<ObjathorOptions>);

/// The catalogs and objathor folder a `holoc.toml` lists, relative to its folder.
fn read_config(path: &Path) -> Result<Config, String> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Config {
        #[serde(default)]
        catalogs: Vec<PathBuf>,
        objathor: Option<PathBuf>,
        objathor_version: Option<String>,
        objathor_scoring: Option<String>,
        objathor_mix: Option<String>,
        objathor_pick: Option<String>,
        objathor_clip: Option<PathBuf>,
        /// The `[test]` table of `holoc test`, not the language server's.
        #[serde(default, rename = "test")]
        _test: Option<toml::Value>,
    }
    let bytes = crate::source::read_input(path, MAX_CONFIG_BYTES)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| format!("{}: the file is not UTF-8 text", path.display()))?;
    let config: Config = toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let objathor = ObjathorOptions::from_words(
        dir,
        config.objathor.as_deref(),
        config.objathor_version.as_deref(),
        config.objathor_scoring.as_deref(),
        config.objathor_mix.as_deref(),
        config.objathor_pick.as_deref(),
        config.objathor_clip.as_deref(),
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok((config.catalogs.into_iter().map(|p| dir.join(p)).collect(), objathor))
}

#[cfg(test)]
mod config_tests {
    use super::*;

    #[test]
    fn holoc_toml_names_the_objathor_folder_relative_to_itself() {
        let dir = tempfile::tempdir().expect("a folder");
        let path = dir.path().join("holoc.toml");
        std::fs::write(
            &path,
            "catalogs = [\"a.json\"]\nobjathor = \"assets/2023_09_23\"\nobjathor_mix = \"score\"\n",
        )
        .expect("written");
        let (catalogs, objathor) = read_config(&path).expect("read");
        assert_eq!(catalogs, vec![dir.path().join("a.json")]);
        let o = objathor.expect("the folder");
        assert_eq!(o.dir, dir.path().join("assets/2023_09_23"));
        assert_eq!(o.mix, crate::resolve::objathor::Mix::Score);
        std::fs::write(&path, "objathor = \"x\"\nobjathor_pick = \"random\"\n").expect("written");
        assert!(read_config(&path).is_err());
    }
}
