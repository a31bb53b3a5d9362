//! The language server in memory (`Connection::memory()`): every request it answers, in order,
//! with snapshots of what an editor receives.

mod common;

use lsp_server::{Connection, Message, Notification, Request, RequestId, Response};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::time::Duration;

const URI: &str = "file:///nonexistent/holoc-lsp-test/bedroom.holo";
const BEDROOM: &str = include_str!("../examples/bedroom.holo");

/// One editor session against a server thread.
struct Client {
    conn: Connection,
    server: Option<std::thread::JoinHandle<Result<holoc::lsp::Ending, String>>>,
    next_id: i32,
    /// Every `publishDiagnostics` received, in order.
    published: Vec<Value>,
    /// Every other notification received (`window/showMessage`, ...).
    messages: Vec<Value>,
}

impl Client {
    fn start(solve_on_save: bool) -> Client {
        Client::with(
            holoc::lsp::ServerOptions {
                catalogs: Vec::new(),
                objathor: None,
                solve_on_save,
                solve_gate: None,
            },
            json!({}),
        )
    }

    fn with(options: holoc::lsp::ServerOptions, initialization_options: Value) -> Client {
        Client::in_folders(options, initialization_options, &[])
    }

    /// A session whose client opened the workspace folders `folders` (`file:` URIs).
    fn in_folders(
        options: holoc::lsp::ServerOptions,
        initialization_options: Value,
        folders: &[String],
    ) -> Client {
        let (server_side, client_side) = Connection::memory();
        let server = std::thread::spawn(move || holoc::lsp::serve(&server_side, options));
        let mut client = Client {
            conn: client_side,
            server: Some(server),
            next_id: 0,
            published: Vec::new(),
            messages: Vec::new(),
        };
        let folders: Vec<Value> =
            folders.iter().map(|uri| json!({"uri": uri, "name": "workspace"})).collect();
        let caps = client.request(
            "initialize",
            json!({
                "capabilities": {},
                "initializationOptions": initialization_options,
                "workspaceFolders": folders,
            }),
        );
        assert!(caps["capabilities"]["hoverProvider"].as_bool().unwrap_or(false), "{caps}");
        client.notify("initialized", json!({}));
        client
    }

    fn notify(&self, method: &str, params: Value) {
        self.conn
            .sender
            .send(Message::Notification(Notification::new(method.to_string(), params)))
            .expect("the server is listening");
    }

    fn send_request(&mut self, method: &str, params: Value) -> RequestId {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        self.conn
            .sender
            .send(Message::Request(Request::new(id.clone(), method.to_string(), params)))
            .expect("the server is listening");
        id
    }

    /// Sends a request and returns its response, keeping the notifications that come first.
    fn response(&mut self, method: &str, params: Value) -> Response {
        let id = self.send_request(method, params);
        loop {
            match self.receive() {
                Message::Response(r) if r.id == id => return r,
                Message::Response(r) => panic!("a response to another request: {r:?}"),
                Message::Request(r) => panic!("the server asked the client: {r:?}"),
                Message::Notification(n) => self.keep(n),
            }
        }
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        let response = self.response(method, params);
        assert!(response.error.is_none(), "{method}: {:?}", response.error);
        response.result.unwrap_or(Value::Null)
    }

    fn receive(&self) -> Message {
        self.conn
            .receiver
            .recv_timeout(Duration::from_secs(120))
            .expect("the server answers within two minutes")
    }

    fn keep(&mut self, n: Notification) {
        if n.method == "textDocument/publishDiagnostics" {
            self.published.push(n.params);
        } else {
            self.messages.push(n.params);
        }
    }

    /// Waits for a publication that satisfies `wanted` (looking at those already received
    /// first) and returns it.
    fn wait_published(&mut self, wanted: impl Fn(&Value) -> bool) -> Value {
        self.wait_for(true, wanted)
    }

    /// Waits for a notification other than a publication (`window/logMessage`, ...) whose
    /// `message` contains `needle` (looking at those already received first).
    fn wait_message(&mut self, needle: &str) -> Value {
        self.wait_for(false, |m| m["message"].as_str().is_some_and(|t| t.contains(needle)))
    }

    /// Waits for a publication (`diagnostics`) or another notification that satisfies
    /// `wanted`, looking at those already received first.
    fn wait_for(&mut self, diagnostics: bool, wanted: impl Fn(&Value) -> bool) -> Value {
        let kept = if diagnostics { &self.published } else { &self.messages };
        if let Some(p) = kept.iter().find(|p| wanted(p)) {
            return p.clone();
        }
        loop {
            match self.receive() {
                Message::Notification(n) => {
                    let is_diag = n.method == "textDocument/publishDiagnostics";
                    self.keep(n);
                    if is_diag == diagnostics {
                        let list = if diagnostics { &self.published } else { &self.messages };
                        let last = list.last().expect("just kept");
                        if wanted(last) {
                            return last.clone();
                        }
                    }
                }
                other => panic!("unexpected {other:?}"),
            }
        }
    }

    fn open(&self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "holo", "version": 1, "text": text}}),
        );
    }

    fn change(&self, uri: &str, version: i32, changes: Value) {
        self.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": changes}),
        );
    }

    fn at(&mut self, method: &str, uri: &str, (line, character): (u32, u32)) -> Value {
        self.request(
            method,
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        )
    }

    fn stop(mut self) {
        self.request("shutdown", Value::Null);
        self.notify("exit", Value::Null);
        let result = self.server.take().expect("running").join().expect("the server thread ends");
        assert_eq!(result, Ok(holoc::lsp::Ending::AfterShutdown));
    }

    /// Says `exit` without `shutdown`: how the session ended.
    fn exit_at_once(mut self) -> Result<holoc::lsp::Ending, String> {
        self.notify("exit", Value::Null);
        self.server.take().expect("running").join().expect("the server thread ends")
    }
}

/// The 0-based line and UTF-16 column of the `nth` occurrence of `needle` (plus `shift`).
fn find(text: &str, needle: &str, nth: usize, shift: usize) -> (u32, u32) {
    let offset = text.match_indices(needle).nth(nth).expect("the needle is in the text").0 + shift;
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = text[..offset].matches('\n').count();
    let column: usize = text[line_start..offset].chars().map(char::len_utf16).sum();
    (line as u32, column as u32)
}

/// Diagnostics as short lines: `line:col code message` (the first line of the message).
fn diagnostics_text(published: &Value) -> String {
    let mut out = format!("version {}\n", published["version"]);
    for d in published["diagnostics"].as_array().expect("an array") {
        let message = d["message"].as_str().unwrap_or_default().lines().next().unwrap_or_default();
        let _ = writeln!(
            out,
            "{}:{} {} {}",
            d["range"]["start"]["line"],
            d["range"]["start"]["character"],
            d["code"].as_str().unwrap_or_default(),
            message
        );
    }
    out
}

/// Diagnostics in the short form of a publication with `version`, sorted as the server sorts
/// them.
fn short_form(
    sources: &holoc::source::SourceMap,
    mut diagnostics: Vec<holoc::diag::Diagnostic>,
    version: i32,
) -> String {
    holoc::diag::sort(&mut diagnostics);
    let lsp: Vec<Value> = holoc::diag::lsp::to_lsp(sources, &diagnostics)
        .into_iter()
        .map(|(_, d)| serde_json::to_value(d).expect("serializes"))
        .collect();
    diagnostics_text(&json!({"version": version, "diagnostics": lsp}))
}

/// What `holoc check` says of `text`, in the same short form (the server must agree with it).
fn check_text(text: &str, version: i32) -> String {
    let mut sources = holoc::source::SourceMap::new();
    let file = sources.add("/nonexistent/holoc-lsp-test/bedroom.holo", text);
    let catalog = holoc::resolve::Catalog::embedded();
    let diagnostics =
        holoc::compile::check_stages(&sources, file, &catalog, holoc::compile::CheckStage::Resolve);
    short_form(&sources, diagnostics, version)
}

fn snapshot(name: &str, value: &str) {
    insta::with_settings!({snapshot_path => "../snapshots/lsp", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!(name, value);
    });
}

/// Applies a `WorkspaceEdit`'s or a `TextEdit[]`'s edits (for `URI`) to `text`.
fn apply_edits(text: &str, edits: &Value) -> String {
    let edits = edits.get("changes").map_or(edits, |c| &c[URI]);
    let mut edits: Vec<&Value> = edits.as_array().expect("edits").iter().collect();
    let offset = |p: &Value| {
        let file = holoc::source::SourceFile::new("", text);
        file.offset_of_lsp(
            p["line"].as_u64().expect("line") as u32,
            p["character"].as_u64().expect("character") as u32,
        )
    };
    edits.sort_by_key(|e| std::cmp::Reverse(offset(&e["range"]["start"])));
    let mut out = text.to_string();
    for e in edits {
        let (s, t) = (offset(&e["range"]["start"]), offset(&e["range"]["end"]));
        out.replace_range(s..t, e["newText"].as_str().expect("text"));
    }
    out
}

#[test]
fn diagnostics_cover_every_stage_before_the_solver_and_carry_the_version() {
    let mut client = Client::start(false);
    // Two rooms touching only at a corner, with a door between them: a plan error (E0309)
    // that the checker alone does not see.
    let text = "room a \"a\" {\n  corners in m (0, 0) (0, 3) (3, 3) (3, 0)\n}\nroom b \"b\" {\n  corners in m (3, 3) (3, 6) (6, 6) (6, 3)\n}\ndoor exterior -- a : doorway single\ndoor a -- b : doorway single\n";
    client.open(URI, text);
    let first = client.wait_published(|p| p["version"] == 1);
    let shown = diagnostics_text(&first);
    assert!(shown.contains("E03"), "a floor-plan error: {shown}");
    assert_eq!(shown, check_text(text, 1));
    snapshot("plan_error_diagnostics", &shown);
    // Move room b so that it shares a wall with a: the error goes, with version 2.
    let fixed = text.replace("(3, 3) (3, 6) (6, 6) (6, 3)", "(3, 0) (3, 3) (6, 3) (6, 0)");
    client.change(URI, 2, json!([{"text": fixed}]));
    let second = client.wait_published(|p| p["version"] == 2);
    assert!(!diagnostics_text(&second).contains("E03"), "{second}");
    assert_eq!(diagnostics_text(&second), check_text(&fixed, 2));
    client.stop();
}

#[test]
fn past_the_cap_a_closing_diagnostic_counts_what_is_not_shown() {
    let mut client = Client::start(false);
    // 144 objects that each name an object that does not exist: 144 errors (E0201).
    let mut stools = String::new();
    for k in 0..144 {
        let _ = writeln!(stools, "  object stool_{k} \"stool\" {{\n    near ghost-{k}\n  }}");
    }
    let ceiling = "  ceiling \"round flush mount ceiling light\"\n";
    let text = BEDROOM.replacen(ceiling, &format!("{stools}{ceiling}"), 1);
    let all = check_text(&text, 1);
    assert_eq!(all.matches(" E0201 ").count(), 144, "{all}");
    client.open(URI, &text);
    let published = client.wait_published(|p| p["version"] == 1);
    let list = published["diagnostics"].as_array().expect("an array");
    let max = holoc::diag::MAX_SHOWN_PER_FILE;
    assert_eq!(list.len(), max + 1, "{published}");
    // The first `max` are `holoc check`'s first `max`, in its order.
    let shown = diagnostics_text(&published);
    let expected: Vec<&str> = all.lines().take(max + 1).collect();
    let got: Vec<&str> = shown.lines().take(max + 1).collect();
    assert_eq!(got, expected);
    // The closing one: where the first one left out is, as severe as the worst of them, with
    // how many and where to see them all.
    let closing = &list[max];
    let first_hidden = all.lines().nth(max + 1).expect("one left out");
    let at = format!(
        "{}:{} ",
        closing["range"]["start"]["line"], closing["range"]["start"]["character"]
    );
    assert!(first_hidden.starts_with(&at), "{first_hidden} vs {closing}");
    assert_eq!(closing["severity"], 1, "{closing}");
    let message = closing["message"].as_str().expect("a message");
    let hidden = all.lines().count() - 1 - max;
    assert!(
        message.starts_with(&format!("and {hidden} more diagnostic(s) from here on not shown (")),
        "{message}"
    );
    assert!(message.contains("`holoc check --format json`"), "{message}");
    client.stop();
}

/// Semantic tokens decoded: `line:column text type[+modifier…]`, one per line, with the types
/// and modifiers named by the server's legend (columns count UTF-16 code units).
fn decode_tokens(text: &str, tokens: &Value) -> Vec<String> {
    let legend = holoc::lsp::highlight::legend();
    let data: Vec<u32> = tokens["data"]
        .as_array()
        .expect("data")
        .iter()
        .map(|n| u32::try_from(n.as_u64().expect("a number")).expect("fits"))
        .collect();
    let lines: Vec<&str> = text.lines().collect();
    let (mut line, mut column) = (0, 0);
    let mut out = Vec::new();
    for t in data.chunks(5) {
        if t[0] > 0 {
            column = 0;
        }
        line += t[0];
        column += t[1];
        let units: Vec<u16> = lines[line as usize].encode_utf16().collect();
        let word =
            String::from_utf16(&units[column as usize..(column + t[2]) as usize]).expect("text");
        let mut kind = legend.token_types[t[3] as usize].as_str().to_string();
        for (bit, modifier) in legend.token_modifiers.iter().enumerate() {
            if t[4] & (1 << bit) != 0 {
                kind = format!("{kind}+{}", modifier.as_str());
            }
        }
        out.push(format!("{}:{} {word} {kind}", line + 1, column + 1));
    }
    out
}

#[test]
fn semantic_tokens_colour_keywords_names_references_units_strings_numbers_and_comments() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let caps = serde_json::to_value(holoc::lsp::capabilities()).expect("JSON");
    let provider = &caps["semanticTokensProvider"];
    assert_eq!(provider["full"], true, "{provider}");
    assert_eq!(provider["range"], true, "{provider}");
    let full =
        client.request("textDocument/semanticTokens/full", json!({"textDocument": {"uri": URI}}));
    let decoded = decode_tokens(BEDROOM, &full);
    let has = |entry: &str| decoded.iter().any(|d| d.ends_with(entry));
    for entry in [
        "room keyword",
        "bedroom namespace+declaration",
        "bed variable+declaration",
        "nightstand-0 variable+declaration",
        "bed-0 variable",
        "left of keyword",
        "face same as keyword",
        "cm type",
        "hung enumMember",
        "same enumMember",
        "x operator",
        "exterior namespace+defaultLibrary",
        "\"white panel door\" string",
        "4.5 number",
    ] {
        assert!(has(entry), "no `{entry}` in:\n{}", decoded.join("\n"));
    }
    assert!(decoded[0].starts_with("1:1 // A bedroom") && decoded[0].ends_with(" comment"));
    snapshot("semantic_tokens", &decoded.join("\n"));
    // A range gives the tokens of its lines, the same as the whole document's.
    let range = client.request(
        "textDocument/semanticTokens/range",
        json!({"textDocument": {"uri": URI},
               "range": {"start": {"line": 15, "character": 0}, "end": {"line": 30, "character": 0}}}),
    );
    let in_range: Vec<String> = decoded
        .iter()
        .filter(|d| {
            let line: u32 = d.split(':').next().and_then(|l| l.parse().ok()).expect("a line");
            (16..=31).contains(&line)
        })
        .cloned()
        .collect();
    assert_eq!(decode_tokens(BEDROOM, &range), in_range);
    // A document that is not open gets an error, not a crash.
    let response = client.response(
        "textDocument/semanticTokens/full",
        json!({"textDocument": {"uri": "file:///nonexistent/other.holo"}}),
    );
    assert!(response.error.is_some());
    client.stop();
}

#[test]
fn interleaved_edits_are_applied_strictly_in_order() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let mut expected = BEDROOM.to_string();
    // Type a new relation into the desk chair's block, one character per change, with a hover
    // request after every change: each hover sees the text as of the changes before it.
    let (line, column) = find(BEDROOM, "    face to desk-0\n", 0, 0);
    let typed = "    near wardrobe-0 // café ☕ 🪑 done\n";
    let mut col = column;
    let mut version = 1;
    for ch in typed.chars() {
        version += 1;
        let at = json!({"line": line, "character": col});
        client.change(
            URI,
            version,
            json!([{"range": {"start": at, "end": at}, "text": ch.to_string()}]),
        );
        let mut file = holoc::source::SourceFile::new("", expected.clone());
        let offset = file.offset_of_lsp(line, col);
        expected.insert(offset, ch);
        file = holoc::source::SourceFile::new("", expected.clone());
        let _ = file;
        col += ch.len_utf16() as u32;
        if ch == '\n' {
            break;
        }
        // Hover on `wardrobe-0` in the desk's block: the wardrobe, whatever is being typed.
        let hover = client.at("textDocument/hover", URI, find(&expected, "far wardrobe-0", 0, 5));
        assert!(
            hover["contents"]["value"].as_str().unwrap_or("").contains("`wardrobe`"),
            "{hover}"
        );
    }
    // A multi-line replacement spanning the typed text and a UTF-16 edit after the emoji.
    version += 1;
    let (l, c) = find(&expected, "done", 0, 0);
    client.change(
        URI,
        version,
        json!([
            {"range": {"start": {"line": l, "character": c}, "end": {"line": l, "character": c + 4}}, "text": "ok"},
        ]),
    );
    expected = expected.replacen("🪑 done", "🪑 ok", 1);
    let last = client.wait_published(|p| p["version"] == version);
    assert_eq!(diagnostics_text(&last), check_text(&expected, version));
    // Versions only grow, and the last published is the last sent.
    let versions: Vec<i64> =
        client.published.iter().map(|p| p["version"].as_i64().unwrap_or(-1)).collect();
    assert!(versions.windows(2).all(|w| w[0] < w[1]), "{versions:?}");
    assert_eq!(versions.last().copied(), Some(i64::from(version)));
    // The server's text is the expected text: formatting gives the same edits as `holoc fmt`.
    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": URI}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    let formatted = apply_edits(&expected, &edits);
    let parsed = holoc::parse::parse_str(&expected);
    assert_eq!(formatted, holoc::fmt::print(&parsed.value));
    assert!(expected.contains("    near wardrobe-0 // café ☕ 🪑 ok\n    face to desk-0"));
    client.stop();
}

#[test]
fn hover_shows_assets_rooms_and_relation_meanings() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let mut out = String::new();
    for (what, needle, nth, shift) in [
        ("room", "bedroom \"bedroom\"", 0, 2),
        ("object group", "object desk ", 0, 8),
        ("instance reference", "left of bed-0", 0, 9),
        ("group with instances", "object nightstand", 0, 9),
        ("relation", "in front of desk-0", 0, 3),
        ("global constraint", "    middle", 0, 6),
    ] {
        let hover = client.at("textDocument/hover", URI, find(BEDROOM, needle, nth, shift));
        let _ =
            write!(out, "## {what}\n{}\n\n", hover["contents"]["value"].as_str().unwrap_or("null"));
    }
    assert!(out.contains("area 18.00 m²"), "{out}");
    assert!(out.contains("score"), "{out}");
    snapshot("hover", &out);
    // Nothing to say on a blank line.
    assert_eq!(client.at("textDocument/hover", URI, (10, 0)), Value::Null);
    client.stop();
}

#[test]
fn definitions_and_references_follow_rooms_objects_and_instances() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let def = client.at("textDocument/definition", URI, find(BEDROOM, "left of bed-0", 0, 9));
    assert_eq!(
        def["range"]["start"],
        json!({"line": find(BEDROOM, "object bed ", 0, 7).0, "character": 9})
    );
    // `nightstand-1` written in an instance block leads to that block.
    let def = client.at("textDocument/definition", URI, find(BEDROOM, "nightstand-1", 0, 3));
    assert_eq!(def["range"]["start"]["line"], find(BEDROOM, "instance nightstand-1", 0, 0).0);
    let door_room = find(BEDROOM, "exterior -- bedroom", 0, 13);
    let def = client.at("textDocument/definition", URI, door_room);
    assert_eq!(def["range"]["start"]["line"], find(BEDROOM, "room bedroom", 0, 0).0);
    let bed = find(BEDROOM, "object bed ", 0, 8);
    let refs = client.request(
        "textDocument/references",
        json!({"textDocument": {"uri": URI}, "position": {"line": bed.0, "character": bed.1}, "context": {"includeDeclaration": true}}),
    );
    let lines: Vec<String> = refs
        .as_array()
        .expect("locations")
        .iter()
        .map(|l| {
            let line = l["range"]["start"]["line"].as_u64().unwrap_or(0) as usize;
            format!("{}: {}", line + 1, BEDROOM.lines().nth(line).unwrap_or("").trim())
        })
        .collect();
    snapshot("references_of_bed", &lines.join("\n"));
    assert_eq!(lines.len(), 9, "{lines:?}");
    client.stop();
}

#[test]
fn rename_changes_a_group_and_its_instances_and_refuses_bad_names() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let at = find(BEDROOM, "near bed-0", 0, 6);
    let prepared = client.at("textDocument/prepareRename", URI, at);
    assert_eq!(prepared["placeholder"], "bed");
    let edit = client.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": URI}, "position": {"line": at.0, "character": at.1}, "newName": "cot"}),
    );
    let renamed = apply_edits(BEDROOM, &edit);
    let code_lines = renamed.lines().filter(|l| !l.trim_start().starts_with("//"));
    assert!(code_lines.clone().all(|l| !l.contains("bed-0")), "{renamed}");
    assert!(renamed.contains("above cot-0") && renamed.contains("object cot \"bed\""), "{renamed}");
    assert_eq!(check_text(&renamed, 1), check_text(BEDROOM, 1), "renaming changes nothing else");
    let edits: Vec<String> = edit["changes"][URI]
        .as_array()
        .expect("edits")
        .iter()
        .map(|e| {
            let (s, t) = (&e["range"]["start"], &e["range"]["end"]);
            format!(
                "{}:{}-{}:{} {}",
                s["line"], s["character"], t["line"], t["character"], e["newText"]
            )
        })
        .collect();
    snapshot("rename_bed_to_cot", &edits.join("\n"));
    for (name, why) in
        [("desk", "already declared"), ("two words", "not a name"), ("bed-3", "not a name")]
    {
        let response = client.response(
            "textDocument/rename",
            json!({"textDocument": {"uri": URI}, "position": {"line": at.0, "character": at.1}, "newName": name}),
        );
        let error = response.error.expect("an error");
        assert!(error.message.contains(why), "{name}: {}", error.message);
    }
    // A room renames across its doors.
    let room = find(BEDROOM, "room bedroom", 0, 6);
    let edit = client.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": URI}, "position": {"line": room.0, "character": room.1}, "newName": "sleeping"}),
    );
    let renamed = apply_edits(BEDROOM, &edit);
    assert!(renamed.contains("door exterior -- sleeping"), "{renamed}");
    client.stop();
}

#[test]
fn document_symbols_list_rooms_objects_instances_and_doors() {
    fn outline(symbols: &Value, depth: usize, out: &mut String) {
        for s in symbols.as_array().into_iter().flatten() {
            let _ = writeln!(
                out,
                "{}{} [{}] {} @{}",
                "  ".repeat(depth),
                s["name"].as_str().unwrap_or(""),
                s["kind"],
                s["detail"].as_str().unwrap_or(""),
                s["selectionRange"]["start"]["line"].as_u64().unwrap_or(0) + 1
            );
            outline(&s["children"], depth + 1, out);
        }
    }
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    let symbols =
        client.request("textDocument/documentSymbol", json!({"textDocument": {"uri": URI}}));
    let mut out = String::new();
    outline(&symbols, 0, &mut out);
    snapshot("document_symbols", &out);
    client.stop();
}

#[test]
fn completion_offers_keywords_relations_and_names_in_scope() {
    let mut client = Client::start(false);
    let text = BEDROOM
        .replacen("    face to desk-0\n", "    face to desk-0\n    \n    near \n", 1)
        .replacen("door exterior", "door \ndoor exterior", 1);
    client.open(URI, &text);
    let labels = |items: &Value| -> String {
        items
            .as_array()
            .into_iter()
            .flatten()
            .map(|i| i["label"].as_str().unwrap_or("").to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out = String::new();
    let blank_in_object = find(&text, "    \n    near \n", 0, 4);
    let after_near = find(&text, "    near \n", 0, 9);
    let after_door = find(&text, "door \n", 0, 5);
    let room_line = find(&text, "  floor \"light", 0, 2);
    let top = (0, 0);
    for (what, at) in [
        ("object block", blank_in_object),
        ("after a relation", after_near),
        ("after door", after_door),
        ("room block", room_line),
        ("top level", top),
    ] {
        let items = client.request(
            "textDocument/completion",
            json!({"textDocument": {"uri": URI}, "position": {"line": at.0, "character": at.1}}),
        );
        let _ = write!(out, "## {what}\n{}\n\n", labels(&items));
    }
    assert!(
        out.contains("in front of") && out.contains("wardrobe-0") && out.contains("exterior"),
        "{out}"
    );
    snapshot("completion", &out);
    client.stop();
}

#[test]
fn formatting_gives_the_canonical_text_and_refuses_syntax_errors() {
    let mut client = Client::start(false);
    let messy = BEDROOM
        .replace("  object bed \"bed\" {", "object    bed \"bed\"   {")
        .replace("    edge\n", "  edge\n");
    client.open(URI, &messy);
    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": URI}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(apply_edits(&messy, &edits), BEDROOM);
    client.change(URI, 2, json!([{"text": BEDROOM}]));
    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": URI}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(edits, json!([]));
    client.change(URI, 3, json!([{"text": BEDROOM.replacen("seed 1", "seed 1 }}", 1)}]));
    let response = client.response(
        "textDocument/formatting",
        json!({"textDocument": {"uri": URI}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert!(response.error.expect("refused").message.contains("syntax errors"));
    client.stop();
}

#[test]
fn code_actions_apply_the_diagnostics_fixes() {
    let mut client = Client::start(false);
    let cases = [
        ("did-you-mean relation", BEDROOM.replacen("    far bed-0", "    fra bed-0", 1), "fra bed-0", "E0102"),
        ("did-you-mean object", BEDROOM.replacen("far wardrobe-0", "far wardrobe-1", 1), "wardrobe-1", "E0201"),
        ("did-you-mean room", BEDROOM.replacen("door exterior -- bedroom", "door exterior -- bedrom", 1), "bedrom", "E0202"),
        ("add a unit", BEDROOM.replacen("size 120 cm x 60 cm x 75 cm", "size 120 x 60 cm x 75 cm", 1), "120 x", "E0105"),
        ("convert a unit", BEDROOM.replacen("height 140 cm", "height 1400 mm", 1), "1400 mm", "E0106"),
        ("repair the floor plan", "room a \"a\" {\n  corners in m (0, 0) (0, 3) (3, 3) (3, 0)\n}\nroom b \"b\" {\n  corners in m (2.8, 0) (2.8, 3) (6, 3) (6, 0)\n}\ndoor exterior -- a : doorway single\ndoor a -- b : doorway single\n".to_string(), "b \"b\"", "E0305"),
        ("snap a corner", "room a \"a\" {\n  corners in m (0, 0) (0, 3) (3, 3) (3, 0)\n}\nroom b \"b\" {\n  corners in m (3.04, 0) (3, 3) (6, 3) (6, 0)\n}\ndoor exterior -- a : doorway single\ndoor a -- b : doorway single\n".to_string(), "(3.04, 0)", "W0301"),
    ];
    let mut out = String::new();
    for (version, (what, text, needle, code)) in cases.iter().enumerate() {
        let version = version as i32 + 1;
        if version == 1 {
            client.open(URI, text);
        } else {
            client.change(URI, version, json!([{"text": text}]));
        }
        let published = client.wait_published(|p| p["version"] == version);
        assert!(diagnostics_text(&published).contains(code), "{what}: {published}");
        let at = find(text, needle, 0, 0);
        let actions = client.request(
            "textDocument/codeAction",
            json!({"textDocument": {"uri": URI}, "range": {"start": {"line": at.0, "character": at.1}, "end": {"line": at.0, "character": at.1}}, "context": {"diagnostics": []}}),
        );
        let actions = actions.as_array().expect("actions").clone();
        let ours: Vec<&Value> =
            actions.iter().filter(|a| a["diagnostics"][0]["code"] == *code).collect();
        assert!(!ours.is_empty(), "{what}: {actions:?}");
        let _ = writeln!(out, "## {what}");
        for a in &ours {
            let _ = writeln!(
                out,
                "- {} (preferred: {})",
                a["title"].as_str().unwrap_or(""),
                a["isPreferred"]
            );
        }
        let fixed = apply_edits(text, &ours[0]["edit"]);
        let after = check_text(&fixed, version);
        assert!(!after.contains(code), "{what}: the fix leaves {after}\n{fixed}");
        out.push('\n');
    }
    snapshot("code_actions", &out);
    client.stop();
}

#[test]
fn a_solve_on_save_reports_objects_left_out_and_whether_relations_hold() {
    let mut client = Client::start(true);
    // A tiny room: the wardrobe cannot be placed.
    let text = BEDROOM.replacen(
        "corners in m (0, 0) (0, 4.5) (4, 4.5) (4, 0)",
        "corners in m (0, 0) (0, 2.6) (3, 2.6) (3, 0)",
        1,
    );
    client.open(URI, &text);
    let solved = client.wait_published(|p| diagnostics_text(p).contains("W05"));
    assert_eq!(solved["version"], 1);
    snapshot("solve_on_open", &diagnostics_text(&solved));
    let hover = client.at("textDocument/hover", URI, find(&text, "near bed-0", 0, 1));
    let value = hover["contents"]["value"].as_str().unwrap_or("");
    assert!(value.contains("After the last solve: `nightstand-0` near bed-0"), "{value}");
    // A change drops the solve's diagnostics until the next save.
    client.change(URI, 2, json!([{"text": text.replacen("seed 1", "seed 2", 1)}]));
    let changed = client.wait_published(|p| p["version"] == 2);
    assert!(!diagnostics_text(&changed).contains("W05"), "{changed}");
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": URI}}));
    let resolved =
        client.wait_published(|p| p["version"] == 2 && diagnostics_text(p).contains("W05"));
    assert_eq!(resolved["version"], 2);
    client.stop();
}

#[test]
fn catalogs_come_from_holoc_toml_beside_the_file() {
    let dir = std::env::temp_dir().join(format!("holoc-lsp-toml-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch");
    std::fs::copy("tests/catalog/procthor_small.json", dir.join("mine.json")).expect("copy");
    std::fs::write(dir.join("holoc.toml"), "catalogs = [\"mine.json\"]\n").expect("write");
    let uri = format!("file://{}/scene%20one.holo", dir.display());
    let text = BEDROOM.replacen(
        "    size 160 cm x 210 cm x 100 cm\n",
        "    size 160 cm x 210 cm x 100 cm\n    asset \"Test_Grand_Piano\"\n",
        1,
    );
    // Outside the client's workspace folders the configuration is not read.
    let mut outsider = Client::in_folders(
        holoc::lsp::ServerOptions {
            catalogs: Vec::new(),
            objathor: None,
            solve_on_save: false,
            solve_gate: None,
        },
        json!({}),
        &["file:///nonexistent/elsewhere".to_string()],
    );
    outsider.open(&uri, &text);
    let published = outsider.wait_published(|p| p["version"] == 1);
    assert!(diagnostics_text(&published).contains("E0401"), "{published}");
    outsider.stop();
    let mut client = Client::in_folders(
        holoc::lsp::ServerOptions {
            catalogs: Vec::new(),
            objathor: None,
            solve_on_save: false,
            solve_gate: None,
        },
        json!({}),
        &[format!("file://{}", dir.display())],
    );
    client.open(&uri, &text);
    let published = client.wait_published(|p| p["version"] == 1);
    assert!(!diagnostics_text(&published).contains("E0401"), "{published}");
    let hover = client.at("textDocument/hover", &uri, find(&text, "object bed ", 0, 8));
    assert!(
        hover["contents"]["value"].as_str().unwrap_or("").contains("Test_Grand_Piano"),
        "{hover}"
    );
    // The same file without the configuration: the pin names no asset.
    std::fs::remove_file(dir.join("holoc.toml")).expect("remove");
    let mut other = Client::start(false);
    other.open(&uri, &text);
    let published = other.wait_published(|p| p["version"] == 1);
    assert!(diagnostics_text(&published).contains("E0401"), "{published}");
    // And from the initialization options.
    let mut third = Client::with(
        holoc::lsp::ServerOptions {
            catalogs: Vec::new(),
            objathor: None,
            solve_on_save: false,
            solve_gate: None,
        },
        json!({"catalogs": [dir.join("mine.json")]}),
    );
    third.open(&uri, &text);
    let published = third.wait_published(|p| p["version"] == 1);
    assert!(!diagnostics_text(&published).contains("E0401"), "{published}");
    client.stop();
    other.stop();
    third.stop();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_requests_get_errors_never_a_crash() {
    let mut client = Client::start(false);
    let unknown =
        client.response("textDocument/foldingRange", json!({"textDocument": {"uri": URI}}));
    assert_eq!(unknown.error.expect("an error").code, lsp_server::ErrorCode::MethodNotFound as i32);
    let bad = client.response("textDocument/hover", json!({"nonsense": true}));
    assert_eq!(bad.error.expect("an error").code, lsp_server::ErrorCode::InvalidParams as i32);
    let closed = client.response(
        "textDocument/hover",
        json!({"textDocument": {"uri": URI}, "position": {"line": 0, "character": 0}}),
    );
    assert!(closed.error.expect("an error").message.contains("not open"));
    // A change to a document that is not open, a change past the end, garbage notifications.
    client.change(URI, 5, json!([{"text": "x"}]));
    client.notify("textDocument/didChange", json!({"garbage": 1}));
    client.open(URI, "room a {\n");
    client.change(URI, 2, json!([{"range": {"start": {"line": 99, "character": 99}, "end": {"line": 120, "character": 0}}, "text": "}\n"}]));
    let published = client.wait_published(|p| p["version"] == 2);
    assert!(published["diagnostics"].is_array());
    // Every request on a broken document still answers.
    for method in [
        "textDocument/hover",
        "textDocument/definition",
        "textDocument/completion",
        "textDocument/prepareRename",
    ] {
        let r = client.response(
            method,
            json!({"textDocument": {"uri": URI}, "position": {"line": 0, "character": 5}}),
        );
        assert!(r.error.is_none(), "{method}: {:?}", r.error);
    }
    client.notify("textDocument/didClose", json!({"textDocument": {"uri": URI}}));
    let cleared =
        client.wait_published(|p| p["diagnostics"] == json!([]) && p["version"].is_null());
    assert_eq!(cleared["uri"], URI);
    client.stop();
}

/// The labels of a completion answer, and each item's `textEdit` applied to `text`.
fn completions(
    client: &mut Client,
    uri: &str,
    text: &str,
    at: (u32, u32),
) -> Vec<(String, String)> {
    let items = client.at("textDocument/completion", uri, at);
    items
        .as_array()
        .expect("items")
        .iter()
        .map(|item| {
            let edit = &item["textEdit"];
            assert!(edit.is_object(), "every item carries a textEdit: {item}");
            let applied = apply_edits(text, &json!([edit]));
            let line = applied.lines().nth(at.0 as usize).unwrap_or("").trim().to_string();
            (item["label"].as_str().unwrap_or("").to_string(), line)
        })
        .collect()
}

#[test]
fn completion_offers_the_instances_of_counted_groups_on_half_typed_lines() {
    let mut client = Client::start(false);
    // Half-typed lines in the wardrobe's block and in `instance nightstand-0`: the file does
    // not check, and the counts still come from the text.
    let text = BEDROOM.replacen("    far bed-0\n", "    far bed-0\n    near \n", 1).replacen(
        "      left of bed-0\n",
        "      left of bed-0\n      near desk-\n",
        1,
    );
    client.open(URI, &text);
    let in_wardrobe = find(&text, "    near \n", 0, 9);
    let got = completions(&mut client, URI, &text, in_wardrobe);
    let labels: Vec<&str> = got.iter().map(|(l, _)| l.as_str()).collect();
    // Every instance of the `count 2` group, no bare group name, not the wardrobe itself, no
    // wall object.
    assert_eq!(labels, ["bed-0", "nightstand-0", "nightstand-1", "desk-0", "desk_chair-0"]);
    assert!(got.iter().any(|(_, line)| line == "near nightstand-1"), "{got:?}");
    // `near desk-` in nightstand-0's own block: accepting `desk-0` gives `near desk-0`, and the
    // instance itself is not offered (its sibling is).
    let half = find(&text, "near desk-\n", 0, 10);
    let got = completions(&mut client, URI, &text, half);
    let labels: Vec<&str> = got.iter().map(|(l, _)| l.as_str()).collect();
    assert!(labels.contains(&"nightstand-1") && !labels.contains(&"nightstand-0"), "{labels:?}");
    let desk = got.iter().find(|(l, _)| l == "desk-0").expect("desk-0 offered");
    assert_eq!(desk.1, "near desk-0");
    // A phrase half typed: `in fr` becomes `in front of`, not `in in front of`.
    let text = BEDROOM.replacen("    far bed-0\n", "    far bed-0\n    in fr\n", 1);
    client.change(URI, 2, json!([{"text": text}]));
    let got = completions(&mut client, URI, &text, find(&text, "    in fr\n", 0, 9));
    let front = got.iter().find(|(l, _)| l == "in front of").expect("offered");
    assert_eq!(front.1, "in front of");
    client.stop();
}

#[test]
fn relation_hover_and_hints_cover_every_instance_of_a_counted_group() {
    let mut client = Client::start(true);
    // `far bed-0` on the nightstand group applies to both instances, which are also near the
    // bed: it cannot hold for either.
    let text = BEDROOM.replacen(
        "    count 2 same\n    edge\n",
        "    count 2 same\n    edge\n    far bed-0\n",
        1,
    );
    client.open(URI, &text);
    let solved = client.wait_published(|p| {
        p["diagnostics"].as_array().is_some_and(|d| d.iter().any(|d| d["severity"] == 4))
    });
    let hints: Vec<&str> = solved["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .filter(|d| d["severity"] == 4)
        .filter_map(|d| d["message"].as_str())
        .collect();
    for n in 0..2 {
        let needle = format!("`nightstand-{n}` far bed-0 does not hold");
        assert!(hints.iter().any(|h| h.contains(&needle)), "{needle} in {hints:?}");
    }
    let hover = client.at("textDocument/hover", URI, find(&text, "    far bed-0\n", 0, 5));
    let value = hover["contents"]["value"].as_str().unwrap_or("");
    assert!(value.contains("holds for 0 of 2 instances"), "{value}");
    assert!(
        value.contains("`nightstand-0` far bed-0") && value.contains("`nightstand-1` far bed-0"),
        "{value}"
    );
    client.stop();
}

#[test]
fn locations_keep_the_editors_uri_and_link_to_absolute_pages() {
    let mut client = Client::start(false);
    // Object `desk` twice: E0203 with "first defined here".
    let text = BEDROOM.replacen("  object desk_chair ", "  object desk ", 1);
    for uri in ["file:///nonexistent/a%23b/caf%C3%A9%20%25/bedroom.holo", "untitled:Untitled-1"] {
        client.open(uri, &text);
        let published = client.wait_published(|p| p["uri"] == uri);
        let d = published["diagnostics"]
            .as_array()
            .expect("diagnostics")
            .iter()
            .find(|d| d["code"] == "E0203")
            .expect("a duplicate")
            .clone();
        assert_eq!(d["relatedInformation"][0]["location"]["uri"], uri, "{d} {published}");
        let href = d["codeDescription"]["href"].as_str().unwrap_or("");
        assert!(href.starts_with("file:///") && href.ends_with("/E0203.md"), "{href}");
        let def = client.at("textDocument/definition", uri, find(&text, "left of bed-0", 0, 9));
        assert_eq!(def["uri"], uri);
    }
    assert_eq!(
        holoc::diag::lsp::file_uri("/tmp/a#b/café %/x.holo").map(|u| u.as_str().to_string()),
        Some("file:///tmp/a%23b/caf%C3%A9%20%25/x.holo".to_string())
    );
    assert_eq!(
        holoc::lsp::uri_path("file:///tmp/a%23b/caf%C3%A9%20%25/x.holo"),
        Some(std::path::PathBuf::from("/tmp/a#b/café %/x.holo"))
    );
    client.stop();
}

#[test]
fn check_format_lsp_links_pages_as_the_server_does() {
    let dir = std::env::temp_dir().join(format!("holoc-lsp-check-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch");
    let path = dir.join("twice.holo");
    std::fs::write(&path, BEDROOM.replacen("  object desk_chair ", "  object desk ", 1))
        .expect("write");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_holoc"))
        .args(["check", "--format", "lsp"])
        .arg(&path)
        .output()
        .expect("holoc check runs");
    let printed: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let d = printed["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|item| &item["diagnostic"])
        .find(|d| d["code"] == "E0203")
        .expect("a duplicate");
    let href = d["codeDescription"]["href"].as_str().expect("a link");
    let server =
        holoc::lsp::features::code_href(holoc::diag::Code::parse("E0203").expect("a code"))
            .expect("the sources are here");
    assert_eq!(href, server.as_str());
    assert!(
        href.starts_with("file:///") && href.ends_with("/book/src/diagnostics/E0203.md"),
        "{href}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn line_endings_stay_as_the_document_has_them() {
    let mut client = Client::start(false);
    let messy = BEDROOM.replace("  object bed \"bed\" {", "object    bed \"bed\"   {");
    let crlf = messy.replace('\n', "\r\n");
    client.open(URI, &crlf);
    let edits = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": URI}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(apply_edits(&crlf, &edits), BEDROOM.replace('\n', "\r\n"));
    // Lone carriage returns end lines too: the typo's diagnostic is on its own line.
    let cr = BEDROOM.replacen("    far bed-0", "    fra bed-0", 1).replace('\n', "\r");
    client.change(URI, 2, json!([{"text": cr}]));
    let published = client.wait_published(|p| p["version"] == 2);
    let lf = cr.replace('\r', "\n");
    assert_eq!(diagnostics_text(&published), check_text(&lf, 2));
    let line = find(&lf, "fra bed-0", 0, 0).0;
    assert!(diagnostics_text(&published).contains(&format!("{line}:4 E0102")), "{published}");
    client.stop();
}

#[test]
fn fixes_never_break_the_file_and_phrases_get_fixed_whole() {
    let mut client = Client::start(false);
    // `count 2 cm`: one diagnostic (the unit), no follow-on about `nightstand-1`, and no fix
    // that renames an instance onto another (E0203).
    let text = BEDROOM.replacen("count 2 same", "count 2 cm same", 1);
    client.open(URI, &text);
    let published = client.wait_published(|p| p["version"] == 1);
    let shown = diagnostics_text(&published);
    assert!(shown.contains("E0106") && !shown.contains("E0201"), "{shown}");
    let end = find(&text, "door exterior", 0, 0);
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": URI}, "range": {"start": {"line": 0, "character": 0}, "end": {"line": end.0, "character": 0}}, "context": {"diagnostics": []}}),
    );
    let actions = actions.as_array().expect("actions");
    assert!(!actions.is_empty());
    for a in actions {
        let fixed = apply_edits(&text, &a["edit"]);
        let after = check_text(&fixed, 1);
        assert!(!after.contains("E0203") && !after.contains("E0101"), "{a}: {after}");
    }
    // A relation misspelt in two of its three words.
    let text = BEDROOM.replacen("    in front of desk-0", "    in frnt of desk-0", 1);
    client.change(URI, 2, json!([{"text": text}]));
    client.wait_published(|p| p["version"] == 2);
    let at = find(&text, "in frnt", 0, 1);
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": URI}, "range": {"start": {"line": at.0, "character": at.1}, "end": {"line": at.0, "character": at.1}}, "context": {"diagnostics": []}}),
    );
    let fix = actions
        .as_array()
        .expect("actions")
        .iter()
        .find(|a| a["title"] == "replace with `in front of`")
        .unwrap_or_else(|| panic!("a phrase fix in {actions}"))
        .clone();
    assert_eq!(apply_edits(&text, &fix["edit"]), BEDROOM);
    client.stop();
}

#[test]
fn changes_that_cannot_be_applied_are_refused_and_the_document_resynchronized() {
    let mut client = Client::start(false);
    client.open(URI, BEDROOM);
    client.wait_published(|p| p["version"] == 1);
    let typo = BEDROOM.replacen("    far bed-0", "    fra bed-0", 1);
    client.change(URI, 3, json!([{"text": typo}]));
    client.wait_published(|p| p["version"] == 3);
    // A version that goes back: refused, logged, the user told, the diagnostics cleared.
    let at = json!({"line": 0, "character": 0});
    client.change(URI, 2, json!([{"range": {"start": at, "end": at}, "text": "x"}]));
    let cleared = client.wait_published(|p| p["version"].is_null());
    assert_eq!(cleared["diagnostics"], json!([]));
    assert!(
        client
            .messages
            .iter()
            .any(|m| m["message"].as_str().unwrap_or("").contains("refused a change")),
        "{:?}",
        client.messages
    );
    let hover = client.response(
        "textDocument/hover",
        json!({"textDocument": {"uri": URI}, "position": {"line": 0, "character": 0}}),
    );
    assert!(hover.error.expect("out of sync").message.contains("out of sync"));
    // Ranged changes stay refused; the whole text brings the document back.
    client.change(URI, 4, json!([{"range": {"start": at, "end": at}, "text": "x"}]));
    client.change(URI, 5, json!([{"text": BEDROOM}]));
    let back = client.wait_published(|p| p["version"] == 5);
    assert_eq!(diagnostics_text(&back), check_text(BEDROOM, 5));
    // A change whose parameters cannot be read, and one whose range ends before it starts.
    client.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": URI, "version": 6}, "contentChanges": "garbage"}),
    );
    client.wait_published(|p| p["version"].is_null() && p["diagnostics"] == json!([]));
    client.change(URI, 7, json!([{"text": BEDROOM}]));
    client.wait_published(|p| p["version"] == 7);
    let (s, e) = (json!({"line": 3, "character": 0}), json!({"line": 1, "character": 0}));
    client.change(URI, 8, json!([{"range": {"start": s, "end": e}, "text": ""}]));
    client.wait_published(|p| p["version"].is_null() && p["diagnostics"] == json!([]));
    // Published versions never went back.
    let versions: Vec<i64> =
        client.published.iter().filter_map(|p| p["version"].as_i64()).collect();
    assert!(versions.windows(2).all(|w| w[0] <= w[1]), "{versions:?}");
    client.stop();
}

#[test]
fn exit_without_shutdown_ends_the_session_as_an_error() {
    let client = Client::start(false);
    assert_eq!(client.exit_at_once(), Ok(holoc::lsp::Ending::WithoutShutdown));
}

/// One message framed as the protocol sends it.
fn frame(body: &str) -> String {
    format!("Content-Length: {}\r\n\r\n{body}", body.len())
}

/// The next message the binary writes.
fn read_message(out: &mut impl std::io::BufRead) -> Value {
    let mut length = 0;
    loop {
        let mut line = String::new();
        out.read_line(&mut line).expect("a header");
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse().expect("a length");
        }
    }
    let mut body = vec![0; length];
    out.read_exact(&mut body).expect("a body");
    serde_json::from_slice(&body).expect("JSON")
}

/// The CPU time a process has used so far (user and system), in the kernel's clock ticks
/// (`USER_HZ`, 100 a second on Linux); `None` without `/proc`.
fn cpu_ticks(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command name (which may hold spaces) in parentheses.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the whole line, 12 and 13 after the name.
    Some(fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?)
}

#[test]
fn the_binary_uses_no_cpu_while_idle_with_or_without_the_solve() {
    use std::io::Write as _;
    if cpu_ticks(std::process::id()).is_none() {
        common::skip(
            "the_binary_uses_no_cpu_while_idle_with_or_without_the_solve",
            "/proc/<pid>/stat cannot be read on this system",
        );
        return;
    }
    for no_solve in [true, false] {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_holoc"));
        command.arg("lsp");
        if no_solve {
            command.arg("--no-solve");
        }
        let mut child = command
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("holoc lsp starts");
        let mut input = child.stdin.take().expect("stdin");
        let mut output = std::io::BufReader::new(child.stdout.take().expect("stdout"));
        let init = r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#;
        input.write_all(frame(init).as_bytes()).expect("write");
        assert!(read_message(&mut output)["result"]["capabilities"].is_object());
        let open = json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
            "textDocument": {"uri": URI, "languageId": "holo", "version": 1, "text": BEDROOM}}});
        input.write_all(frame(&open.to_string()).as_bytes()).expect("write");
        // The diagnostics of the open.
        assert_eq!(read_message(&mut output)["method"], "textDocument/publishDiagnostics");
        let pid = child.id();
        // Let the solve (when on) finish: idle is measured once the process has stopped
        // using CPU for a whole second, within a minute.
        let mut last = cpu_ticks(pid).expect("the server's CPU time");
        for _ in 0..60 {
            std::thread::sleep(Duration::from_secs(1));
            let now = cpu_ticks(pid).expect("the server's CPU time");
            if now == last {
                break;
            }
            last = now;
        }
        let before = cpu_ticks(pid).expect("the server's CPU time");
        std::thread::sleep(Duration::from_secs(3));
        let after = cpu_ticks(pid).expect("the server's CPU time");
        // 2% of a core over 3 s is 6 ticks of 10 ms; a spinning loop takes about 300.
        assert!(
            after - before <= 6,
            "holoc lsp{} used {} ticks of CPU in 3 s of idleness",
            if no_solve { " --no-solve" } else { "" },
            after - before
        );
        input.write_all(frame(r#"{"jsonrpc":"2.0","method":"exit"}"#).as_bytes()).expect("write");
        let _ = child.wait();
    }
}

#[test]
fn the_binary_answers_malformed_json_and_exits_by_the_protocol() {
    use std::io::Write as _;
    for (shutdown, code) in [(true, 0), (false, 1)] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_holoc"))
            .args(["lsp", "--no-solve"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("holoc lsp starts");
        let mut input = child.stdin.take().expect("stdin");
        let mut output = std::io::BufReader::new(child.stdout.take().expect("stdout"));
        input.write_all(frame("{not json").as_bytes()).expect("write");
        let answer = read_message(&mut output);
        assert_eq!(answer["id"], Value::Null, "{answer}");
        assert_eq!(answer["error"]["code"], -32700, "{answer}");
        let init = r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#;
        input.write_all(frame(init).as_bytes()).expect("write");
        assert!(read_message(&mut output)["result"]["capabilities"].is_object());
        input.write_all(frame("[1, 2").as_bytes()).expect("write");
        assert_eq!(read_message(&mut output)["error"]["code"], -32700);
        if shutdown {
            input
                .write_all(frame(r#"{"jsonrpc":"2.0","id":2,"method":"shutdown"}"#).as_bytes())
                .expect("write");
            assert_eq!(read_message(&mut output)["id"], 2);
        }
        input.write_all(frame(r#"{"jsonrpc":"2.0","method":"exit"}"#).as_bytes()).expect("write");
        let status = child.wait().expect("it exits");
        assert_eq!(status.code(), Some(code), "shutdown first: {shutdown}");
    }
}

#[test]
fn a_catalog_edited_on_disk_is_read_again() {
    let dir = std::env::temp_dir().join(format!("holoc-lsp-reload-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch");
    let catalog = std::fs::read_to_string("tests/catalog/procthor_small.json").expect("catalog");
    std::fs::write(dir.join("mine.json"), &catalog).expect("write");
    std::fs::write(dir.join("holoc.toml"), "catalogs = [\"mine.json\"]\n").expect("write");
    let uri = format!("file://{}/scene.holo", dir.display());
    let text = BEDROOM.replacen(
        "    size 160 cm x 210 cm x 100 cm\n",
        "    size 160 cm x 210 cm x 100 cm\n    asset \"Test_Grand_Piano\"\n",
        1,
    );
    let mut client = Client::in_folders(
        holoc::lsp::ServerOptions {
            catalogs: Vec::new(),
            solve_on_save: false,
            objathor: None,
            solve_gate: None,
        },
        json!({}),
        &[format!("file://{}", dir.display())],
    );
    client.open(&uri, &text);
    let published = client.wait_published(|p| p["version"] == 1);
    assert!(!diagnostics_text(&published).contains("E0401"), "{published}");
    // The piano leaves the catalog; the editor says a watched file changed.
    std::fs::write(dir.join("mine.json"), catalog.replace("Test_Grand_Piano", "Test_Other_Piano"))
        .expect("write");
    let before = client.published.len();
    client.notify(
        "workspace/didChangeWatchedFiles",
        json!({"changes": [{"uri": format!("file://{}/mine.json", dir.display()), "type": 2}]}),
    );
    let again = client.wait_published(|p| diagnostics_text(p).contains("E0401"));
    assert_eq!(again["version"], 1);
    assert!(client.published.len() > before);
    // Without a notification, the next keystroke reads it again too.
    std::fs::write(dir.join("mine.json"), &catalog).expect("write");
    client.change(&uri, 2, json!([{"text": text.clone()}]));
    let fine = client.wait_published(|p| p["version"] == 2);
    assert!(!diagnostics_text(&fine).contains("E0401"), "{fine}");
    client.stop();
    let _ = std::fs::remove_dir_all(&dir);
}

const THREE_URI: &str = "file:///nonexistent/holoc-lsp-test/three_rooms.holo";
/// Three small rooms in a row (`west`, `middle`, `east`), each with an object that cannot be
/// placed (W0501).
const THREE_ROOMS: &str = include_str!("lsp/three_rooms.holo");

/// The rooms whose W0501 a publication shows, in room order (`west`, `middle`, `east`).
fn rooms_with_w05(published: &Value) -> Vec<&'static str> {
    let w05: Vec<&str> = published["diagnostics"]
        .as_array()
        .expect("an array")
        .iter()
        .filter(|d| d["code"].as_str().is_some_and(|c| c.starts_with("W05")))
        .filter_map(|d| d["message"].as_str())
        .collect();
    ["west", "middle", "east"]
        .into_iter()
        .filter(|room| w05.iter().any(|m| m.contains(&format!("in room `{room}`"))))
        .collect()
}

/// A publication's diagnostics without the relation hints, in the short form.
fn without_hints(published: &Value) -> String {
    let mut kept = published.clone();
    if let Some(list) = kept["diagnostics"].as_array_mut() {
        list.retain(|d| d["severity"] != 4);
    }
    diagnostics_text(&kept)
}

/// What the server must show once a solve of `text` ends: what `holoc check` says and the
/// W05xx of `holoc build`, in the short form.
fn build_text(text: &str, version: i32) -> String {
    let mut sources = holoc::source::SourceMap::new();
    let file = sources.add("/nonexistent/holoc-lsp-test/three_rooms.holo", text);
    let catalog = holoc::resolve::Catalog::embedded();
    let mut diagnostics =
        holoc::compile::check_stages(&sources, file, &catalog, holoc::compile::CheckStage::Resolve);
    let built = holoc::compile::build(&sources, file, &holoc::compile::BuildOptions::new(&catalog));
    assert!(built.value.is_some(), "the scene builds: {:?}", built.diagnostics);
    diagnostics.extend(built.diagnostics.into_iter().filter(|d| d.code.stage() == "solve"));
    short_form(&sources, diagnostics, version)
}

#[test]
fn the_room_being_edited_is_solved_and_published_before_the_others() {
    let mut client = Client::start(true);
    client.open(THREE_URI, THREE_ROOMS);
    // Nothing edited yet: the first room comes first.
    let first = client.wait_published(|p| !rooms_with_w05(p).is_empty());
    assert_eq!((first["version"].clone(), rooms_with_w05(&first)), (json!(1), vec!["west"]));
    let whole = client.wait_published(|p| rooms_with_w05(p).len() == 3);
    assert_eq!(without_hints(&whole), build_text(THREE_ROOMS, 1));
    // An edit in the east room, then a save: the east room is solved and published first.
    let at = find(THREE_ROOMS, "120 cm x 50 cm", 0, 0);
    let end = (at.0, at.1 + 6);
    client.change(
        THREE_URI,
        2,
        json!([{"range": {"start": {"line": at.0, "character": at.1}, "end": {"line": end.0, "character": end.1}}, "text": "110 cm"}]),
    );
    let edited = THREE_ROOMS.replacen("120 cm x 50 cm", "110 cm x 50 cm", 1);
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": THREE_URI}}));
    let last = client.wait_published(|p| p["version"] == 2 && rooms_with_w05(p).len() == 3);
    assert_eq!(without_hints(&last), build_text(&edited, 2));
    // In order: the check's diagnostics alone, the east room's, then the others' as they
    // finish, each publication keeping the rooms already shown.
    let seen: Vec<Vec<&str>> = client
        .published
        .iter()
        .filter(|p| p["version"] == 2)
        .map(rooms_with_w05)
        .filter(|rooms| !rooms.is_empty())
        .collect();
    assert_eq!(seen.first(), Some(&vec!["east"]), "{seen:?}");
    for pair in seen.windows(2) {
        assert!(pair[0].iter().all(|r| pair[1].contains(r)), "{seen:?}");
    }
    let before: Vec<&Value> = client.published.iter().filter(|p| p["version"] == 2).collect();
    assert!(rooms_with_w05(before[0]).is_empty(), "the check's diagnostics come first");
    client.stop();
}

#[test]
fn an_edit_stops_a_solve_half_done_and_nothing_of_it_is_published_after() {
    // The server's solver waits at the gate after the first room of each solve.
    let (gate, gate_rx) = crossbeam_channel::unbounded::<()>();
    let mut client = Client::with(
        holoc::lsp::ServerOptions {
            catalogs: Vec::new(),
            objathor: None,
            solve_on_save: true,
            solve_gate: Some(gate_rx),
        },
        json!({}),
    );
    client.open(THREE_URI, THREE_ROOMS);
    let partial = client.wait_published(|p| !rooms_with_w05(p).is_empty());
    assert_eq!((partial["version"].clone(), rooms_with_w05(&partial)), (json!(1), vec!["west"]));
    // Hover answers for the room solved, and says the others are being solved.
    let hover = |client: &mut Client, needle: &str, shift: usize| {
        let value = client.at("textDocument/hover", THREE_URI, find(THREE_ROOMS, needle, 0, shift));
        value["contents"]["value"].as_str().unwrap_or_default().to_string()
    };
    let bed = hover(&mut client, "object bed", 7);
    assert!(bed.contains("After the last solve:\n- `bed-0`: left out (W0501)"), "{bed}");
    let far_bed = hover(&mut client, "far bed-0", 1);
    assert!(far_bed.contains("After the last solve:"), "{far_bed}");
    let table = hover(&mut client, "object table", 7);
    assert!(table.contains("The layout of room `east` is being solved"), "{table}");
    assert!(!table.contains("Save the file"), "{table}");
    let far_table = hover(&mut client, "far table-0", 1);
    assert!(far_table.contains("The layout of room `east` is being solved"), "{far_table}");
    // An edit in the middle room while the solver waits; the hover after it is answered once
    // the edit is applied (messages are handled in order), so the solve is cancelled then.
    let at = find(THREE_ROOMS, "100 cm x 35 cm", 0, 0);
    client.change(
        THREE_URI,
        2,
        json!([{"range": {"start": {"line": at.0, "character": at.1}, "end": {"line": at.0, "character": at.1 + 6}}, "text": "90 cm"}]),
    );
    // (The cursor stays in the middle room: the room solved first on save.)
    let sofa = hover(&mut client, "object sofa", 7);
    assert!(!sofa.contains("being solved") && !sofa.contains("After the last solve"), "{sofa}");
    let changed_at = client.published.len();
    gate.send(()).expect("the server listens");
    // The solve stops before its other rooms: the server says so in its log.
    client.wait_message("the solve of version 1 of `/nonexistent/holoc-lsp-test/three_rooms.holo` stopped after 1 of 3 room(s)");
    // A save solves the edited version, the middle room first.
    gate.send(()).expect("the server listens");
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": THREE_URI}}));
    let edited = THREE_ROOMS.replacen("100 cm x 35 cm", "90 cm x 35 cm", 1);
    let last = client.wait_published(|p| p["version"] == 2 && rooms_with_w05(p).len() == 3);
    assert_eq!(without_hints(&last), build_text(&edited, 2));
    // Nothing of version 1 after the edit, and version 2's first solved room is the middle.
    let after = &client.published[changed_at..];
    assert!(after.iter().all(|p| p["version"] == 2), "{after:?}");
    let of_v1: Vec<Vec<&str>> = (client.published.iter())
        .filter(|p| p["version"] == 1)
        .map(rooms_with_w05)
        .filter(|r| !r.is_empty())
        .collect();
    assert_eq!(of_v1, vec![vec!["west"]], "only the room solved before the edit");
    let of_v2 = client.published.iter().filter(|p| p["version"] == 2).map(rooms_with_w05);
    let of_v2: Vec<Vec<&str>> = of_v2.filter(|r| !r.is_empty()).collect();
    assert_eq!(of_v2.first(), Some(&vec!["middle"]), "{of_v2:?}");
    client.stop();
}
