//! A loopback chat-completions server (tiny_http on 127.0.0.1:0) that answers with scripted
//! replies in the OpenAI wire format, and the answers of a clean two-room run. Shared by the
//! tests of `generate` and `batch`; nothing here reaches the internet.

#![allow(dead_code, reason = "each test binary uses a different part")]

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// One reply of the fake server.
pub struct Reply {
    pub status: u16,
    pub body: String,
    pub retry_after: Option<&'static str>,
    pub delay_ms: u64,
}

impl Reply {
    pub fn answer(text: &str) -> Reply {
        let body = serde_json::json!({
            "id": "chatcmpl-test",
            "object": "chat.completion",
            "choices": [{"index": 0, "message": {"role": "assistant", "content": text}, "finish_reason": "stop"}],
            "usage": {"prompt_tokens": text.len() / 4 + 100, "completion_tokens": text.len() / 4},
        });
        Reply { status: 200, body: body.to_string(), retry_after: None, delay_ms: 0 }
    }

    pub fn status(status: u16, body: &str) -> Reply {
        Reply { status, body: body.to_string(), retry_after: None, delay_ms: 0 }
    }
}

/// What a request asked for, as the fake server reads it from the prompt.
#[derive(Debug)]
pub struct Asked {
    pub stage: &'static str,
    pub room: Option<String>,
    pub repair: bool,
    pub authorization: Option<String>,
}

pub type Script = dyn Fn(&Asked, usize) -> Reply + Send + Sync;

/// A loopback chat-completions server; stops when dropped.
pub struct Server {
    pub base_url: String,
    pub http: Arc<tiny_http::Server>,
    pub calls: Arc<AtomicUsize>,
    pub threads: Vec<std::thread::JoinHandle<()>>,
}

pub fn between(text: &str, before: &str, after: &str) -> Option<String> {
    let start = text.find(before)? + before.len();
    let end = text[start..].find(after)? + start;
    Some(text[start..end].to_string())
}

pub fn read_asked(prompt: &str, authorization: Option<String>) -> Asked {
    let repair = prompt.contains("Your previous answer was:");
    let (stage, room) = if prompt.contains("planning the floor plan") {
        ("floor-plan", None)
    } else if prompt.contains("How high, in metres") {
        ("wall-height", None)
    } else if prompt.contains("how the rooms of a floor plan connect") {
        ("doorways", None)
    } else if prompt.contains("choosing the windows") {
        ("windows", None)
    } else if prompt.contains("You are furnishing one room") {
        ("objects", between(prompt, "The room is the ", ". Its floor"))
    } else if prompt.contains("arranging the furniture of the ") {
        ("floor-constraints", between(prompt, "arranging the furniture of the ", ", whose"))
    } else if prompt.contains("hanging the wall objects of the ") {
        ("wall-constraints", between(prompt, "hanging the wall objects of the ", ", whose"))
    } else if prompt.contains("You are dressing the ") {
        ("small-objects", between(prompt, "You are dressing the ", " for this request"))
    } else if prompt.contains("one ceiling object") {
        ("ceiling", None)
    } else {
        ("unknown", None)
    };
    Asked { stage, room, repair, authorization }
}

impl Server {
    pub fn start(script: Arc<Script>) -> Server {
        let server = Arc::new(tiny_http::Server::http("127.0.0.1:0").expect("bind loopback"));
        let port = server.server_addr().to_ip().expect("an IP address").port();
        let calls = Arc::new(AtomicUsize::new(0));
        let mut threads = Vec::new();
        for _ in 0..6 {
            let server = Arc::clone(&server);
            let script = Arc::clone(&script);
            let calls = Arc::clone(&calls);
            threads.push(std::thread::spawn(move || {
                while let Ok(mut request) = server.recv() {
                    let n = calls.fetch_add(1, Ordering::SeqCst);
                    let mut body = String::new();
                    let _ = std::io::Read::read_to_string(request.as_reader(), &mut body);
                    let value: serde_json::Value = serde_json::from_str(&body).unwrap_or_default();
                    let prompt = value
                        .pointer("/messages/0/content")
                        .and_then(serde_json::Value::as_str)
                        .unwrap_or_default()
                        .to_string();
                    let authorization = request
                        .headers()
                        .iter()
                        .find(|h| h.field.equiv("Authorization"))
                        .map(|h| h.value.to_string());
                    let asked = read_asked(&prompt, authorization);
                    let reply = if request.url() == "/v1/chat/completions" {
                        script(&asked, n)
                    } else {
                        Reply::status(404, "{\"error\": \"no such route\"}")
                    };
                    if reply.delay_ms > 0 {
                        std::thread::sleep(Duration::from_millis(reply.delay_ms));
                    }
                    let mut response = tiny_http::Response::from_string(reply.body)
                        .with_status_code(reply.status)
                        .with_header(
                            tiny_http::Header::from_bytes("Content-Type", "application/json")
                                .expect("a valid header"),
                        );
                    if let Some(after) = reply.retry_after {
                        response = response.with_header(
                            tiny_http::Header::from_bytes("Retry-After", after)
                                .expect("a valid header"),
                        );
                    }
                    let _ = request.respond(response);
                }
            }));
        }
        Server { base_url: format!("http://127.0.0.1:{port}/v1"), http: server, calls, threads }
    }

    pub fn calls(&self) -> usize {
        self.calls.load(Ordering::SeqCst)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        for _ in &self.threads {
            self.http.unblock();
        }
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

pub const FLOOR_PLAN: &str = "Here is the plan:\n\
1. living room | oak hardwood, matte | light grey plaster, smooth | [(0, 0), (0, 6), (5, 6), (5, 0)]\n\
2. bedroom | beige carpet, soft | pale blue paint, matte | [(5, 0), (5, 4), (9, 4), (9, 0)]\n";

pub const LIVING_OBJECTS: &str = r#"The room needs a place to sit and read.
{"sofa": {"description": "light grey fabric sofa", "location": "floor", "size": [200, 90, 80], "quantity": 1, "variance_type": "same", "objects_on_top": [{"object_name": "cushion", "quantity": 2, "variance_type": "varied"}]},
 "coffee table": {"description": "low oak coffee table", "location": "floor", "size": [100, 60, 45], "quantity": 1, "variance_type": "same", "objects_on_top": []},
 "painting": {"description": "abstract painting, blue tones", "location": "wall", "size": [90, 3, 60], "quantity": 1, "variance_type": "same", "objects_on_top": []}}"#;

pub const BEDROOM_OBJECTS: &str = r#"{"bed": {"description": "double bed with white sheets", "location": "floor", "size": [200, 160, 50], "quantity": 1, "variance_type": "same", "objects_on_top": []},
 "nightstand": {"description": "small walnut nightstand", "location": "floor", "size": [45, 40, 55], "quantity": 2, "variance_type": "same", "objects_on_top": []}}"#;

/// The answers of a clean two-room run.
pub fn clean_answer(asked: &Asked) -> Reply {
    let room = asked.room.as_deref().unwrap_or("");
    let text = match (asked.stage, room) {
        ("floor-plan", _) => FLOOR_PLAN,
        ("wall-height", _) => "2.7",
        ("doorways", _) => {
            "exterior | living room | doorway | double | dark brown metal door\n\
             living room | bedroom | doorway | single | white wooden door"
        }
        ("windows", _) => "living room | west | fixed | (150, 120) | 2 | 90",
        ("objects", "living room") => LIVING_OBJECTS,
        ("objects", _) => BEDROOM_OBJECTS,
        ("floor-constraints", "living room") => {
            "sofa-0 | edge\ncoffee_table-0 | middle | near, sofa-0 | in front of, sofa-0 | face to, sofa-0"
        }
        ("floor-constraints", _) => {
            "bed-0 | edge\nnightstand-0 | edge | near, bed-0 | side of, bed-0\nnightstand-1 | edge | near, bed-0 | side of, bed-0"
        }
        ("wall-constraints", _) => "painting-0 | above, sofa-0 | 160",
        ("small-objects", "living room") => "coffee_table-0 (living room) | book, 2, varied",
        ("small-objects", _) => "nightstand-0 (bedroom) | table lamp, 1, same",
        ("ceiling", _) => "living room | flush mount ceiling light\nbedroom | small ceiling fan",
        _ => "I do not know this question.",
    };
    Reply::answer(text)
}
