//! The model side: the [`Llm`] trait, the OpenAI-compatible HTTP client and the replay client.
//!
//! The HTTP client speaks the chat-completions API (`POST {base_url}/chat/completions` with one
//! user message), which OpenAI, Azure-style gateways, vLLM, the llama.cpp server and Ollama all
//! serve. It retries 429 and 5xx answers and timeouts with a deterministic, capped exponential
//! backoff that honours `Retry-After`. The API key is kept out of every string it produces.

use crate::diag::{Code, Diagnostic};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt;
use std::time::Duration;

/// One question sent to the model.
#[derive(Clone, Copy, Debug)]
pub struct LlmRequest<'a> {
    /// The stage name (`floor-plan`, `objects`, …).
    pub stage: &'a str,
    /// The room label for per-room stages.
    pub room: Option<&'a str>,
    /// 0 for the first question, `n` for the `n`-th repair round.
    pub attempt: u32,
    /// The whole prompt, sent as one user message.
    pub prompt: &'a str,
}

/// Token counts reported by the server (0 when it reports none).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Usage {
    /// Tokens of the prompt.
    pub prompt_tokens: u64,
    /// Tokens of the answer.
    pub completion_tokens: u64,
}

/// The model's answer to one question.
#[derive(Clone, Debug, PartialEq)]
pub struct LlmAnswer {
    /// The text of the answer.
    pub text: String,
    /// Token counts.
    pub usage: Usage,
}

/// What is recorded about the model in a transcript.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelInfo {
    /// The server address (without `/chat/completions`).
    pub base_url: String,
    /// The model name.
    pub model: String,
    /// The sampling temperature.
    pub temperature: f64,
    /// The sampling parameters sent with every request, as recorded in each exchange.
    pub parameters: BTreeMap<String, Value>,
}

/// Why a question got no answer. The facts only; [`LlmError::to_diagnostic`] words them.
#[derive(Clone, Debug, PartialEq)]
pub enum LlmError {
    /// 401 or 403.
    Unauthorized {
        /// The HTTP status.
        status: u16,
        /// The start of the body (key removed).
        body: String,
    },
    /// 404.
    NotFound {
        /// The URL asked.
        url: String,
        /// The model asked for.
        model: String,
        /// The start of the body (key removed).
        body: String,
    },
    /// No connection.
    Unreachable {
        /// The server address.
        base_url: String,
        /// What the connection layer said (key removed).
        reason: String,
    },
    /// No answer in time, on every try.
    Timeout {
        /// The time limit per try.
        seconds: f64,
        /// How many tries were made.
        tries: u32,
    },
    /// 429 or 5xx on every try, or another 4xx.
    Server {
        /// The last HTTP status.
        status: u16,
        /// How many tries were made.
        tries: u32,
        /// The start of the last body (key removed).
        body: String,
        /// The server's `Retry-After`, when it sent one.
        retry_after: Option<Duration>,
    },
    /// A 200 whose body is not a chat completion.
    InvalidResponse {
        /// What is missing or wrong.
        reason: String,
    },
    /// A replayed transcript has no answer for this question.
    MissingReplay {
        /// The stage.
        stage: String,
        /// The room, if any.
        room: Option<String>,
        /// The attempt.
        attempt: u32,
    },
}

impl LlmError {
    /// Whether the error may pass if the same request is sent again later: the server could
    /// not be reached or dropped the connection, did not answer in time, or answered 429 or
    /// 5xx. (A holoc built without its HTTP client is not that.)
    pub fn is_transient(&self) -> bool {
        match self {
            LlmError::Unreachable { reason, .. } => !reason.contains(NO_CLIENT),
            LlmError::Timeout { .. } => true,
            LlmError::Server { status, .. } => *status == 429 || (500..=599).contains(status),
            _ => false,
        }
    }

    /// The diagnostic for this error.
    pub fn to_diagnostic(&self) -> Diagnostic {
        match self {
            LlmError::Unauthorized { status, body } => Diagnostic::new(
                Code::E0803,
                format!("the model server refused the API key (HTTP {status})"),
            )
            .with_help("set `HOLOC_API_KEY` (or `OPENAI_API_KEY`) to a key this server accepts")
            .with_note_opt(body_note(body)),
            LlmError::NotFound { url, model, body } => Diagnostic::new(
                Code::E0804,
                format!("the model server has no `POST {url}` for model `{model}` (HTTP 404)"),
            )
            .with_help("check `--base-url` (the part before `/chat/completions`, often ending in `/v1`) and `--model`")
            .with_note_opt(body_note(body)),
            LlmError::Unreachable { base_url, reason } => Diagnostic::new(
                Code::E0805,
                format!("the model server at `{base_url}` could not be reached"),
            )
            .with_help("check that the server is running and that `--base-url` is right")
            .with_note(reason.clone()),
            LlmError::Timeout { seconds, tries } => Diagnostic::new(
                Code::E0806,
                format!("the model server did not answer within {seconds} s ({tries} {})", plural(*tries, "try", "tries")),
            )
            .with_help("raise `--timeout`, or use a faster model"),
            LlmError::Server { status, tries, body, .. } => Diagnostic::new(
                Code::E0807,
                format!("the model server kept failing: HTTP {status} after {tries} {}", plural(*tries, "try", "tries")),
            )
            .with_help("wait and run again, raise `--retries`, or lower `--jobs`")
            .with_note_opt(body_note(body)),
            LlmError::InvalidResponse { reason } => Diagnostic::new(
                Code::E0808,
                format!("the model server's reply is not a chat completion: {reason}"),
            )
            .with_help("check that `--base-url` points at an OpenAI-compatible API"),
            LlmError::MissingReplay { stage, room, attempt } => {
                let room = room.as_ref().map(|r| format!(", room `{r}`")).unwrap_or_default();
                let which = if *attempt == 0 {
                    "its first ask".to_string()
                } else {
                    format!("repair round {attempt}")
                };
                Diagnostic::new(
                    Code::E0810,
                    format!("the replayed transcript has no answer for stage `{stage}`{room}, {which}"),
                )
                .with_help("replay with the prompts and options the transcript was recorded with, or use `holoc import`")
            }
        }
    }
}

trait NoteOpt {
    fn with_note_opt(self, note: Option<String>) -> Self;
}

impl NoteOpt for Diagnostic {
    fn with_note_opt(self, note: Option<String>) -> Diagnostic {
        match note {
            Some(n) => self.with_note(n),
            None => self,
        }
    }
}

fn body_note(body: &str) -> Option<String> {
    (!body.trim().is_empty()).then(|| format!("the server said: {}", body.trim()))
}

fn plural(n: u32, one: &'static str, many: &'static str) -> &'static str {
    if n == 1 {
        one
    } else {
        many
    }
}

/// A language model that answers one question at a time. Implementations must be usable from
/// several threads at once (per-room stages run in parallel).
pub trait Llm: Sync {
    /// Answers one question.
    fn complete(&self, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError>;

    /// What the transcript records about the model.
    fn info(&self) -> ModelInfo;
}

/// Settings of the HTTP client.
#[derive(Clone)]
pub struct HttpOptions {
    /// The address before `/chat/completions`, e.g. `https://api.openai.com/v1`.
    pub base_url: String,
    /// The model name.
    pub model: String,
    /// The API key, sent as a bearer token; `None` sends no `Authorization` header.
    pub api_key: Option<String>,
    /// The sampling temperature.
    pub temperature: f64,
    /// The sampling seed passed to the server (servers that ignore it are fine).
    pub seed: Option<u64>,
    /// The longest answer, in tokens (`None`: the server's default).
    pub max_tokens: Option<u32>,
    /// Time limit for one try.
    pub timeout: Duration,
    /// How many times a failed try (429, 5xx, timeout) is repeated.
    pub retries: u32,
    /// The wait before the first retry; it doubles for each further retry.
    pub base_delay: Duration,
    /// The longest wait between two tries, `Retry-After` included.
    pub max_delay: Duration,
}

impl fmt::Debug for HttpOptions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HttpOptions")
            .field("base_url", &self.base_url)
            .field("model", &self.model)
            .field("api_key", &self.api_key.as_ref().map(|_| "[redacted]"))
            .field("temperature", &self.temperature)
            .field("seed", &self.seed)
            .field("max_tokens", &self.max_tokens)
            .field("timeout", &self.timeout)
            .field("retries", &self.retries)
            .field("base_delay", &self.base_delay)
            .field("max_delay", &self.max_delay)
            .finish()
    }
}

impl HttpOptions {
    /// Defaults for a server and a model: temperature 0, 120 s per try, 3 retries starting at
    /// 1 s and capped at 30 s.
    pub fn new(base_url: impl Into<String>, model: impl Into<String>) -> HttpOptions {
        HttpOptions {
            base_url: base_url.into(),
            model: model.into(),
            api_key: None,
            temperature: 0.0,
            seed: None,
            max_tokens: None,
            timeout: Duration::from_secs(120),
            retries: 3,
            base_delay: Duration::from_secs(1),
            max_delay: Duration::from_secs(30),
        }
    }

    /// The wait before retry number `retry` (0-based): `base_delay · 2^retry`, or the server's
    /// `Retry-After`, capped at `max_delay`.
    pub fn backoff(&self, retry: u32, retry_after: Option<Duration>) -> Duration {
        let doubled = self.base_delay.saturating_mul(1u32 << retry.min(20));
        retry_after.unwrap_or(doubled).min(self.max_delay)
    }
}

/// What carries the requests: reqwest's blocking client; in a holoc built without the
/// `generate` feature, nothing (every request fails with [`LlmError::Unreachable`], naming the
/// feature).
#[cfg(feature = "generate")]
type Transport = reqwest::blocking::Client;
#[cfg(not(feature = "generate"))]
type Transport = std::convert::Infallible;

/// The OpenAI-compatible chat-completions client (blocking reqwest).
pub struct HttpLlm {
    options: HttpOptions,
    client: Result<Transport, String>,
}

impl fmt::Debug for HttpLlm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HttpLlm").field("options", &self.options).finish_non_exhaustive()
    }
}

impl HttpLlm {
    /// A client with these settings.
    pub fn new(options: HttpOptions) -> HttpLlm {
        #[cfg(feature = "generate")]
        let client = reqwest::blocking::Client::builder()
            .timeout(options.timeout)
            .connect_timeout(options.timeout.min(Duration::from_secs(30)))
            .user_agent(concat!("holoc/", env!("CARGO_PKG_VERSION")))
            .build()
            .map_err(|e| e.to_string());
        #[cfg(not(feature = "generate"))]
        let client = Err(format!(
            "this holoc was built {NO_CLIENT} (the HTTP client); install it with the default \
             features to ask a model"
        ));
        HttpLlm { options, client }
    }

    #[cfg(feature = "generate")]
    fn url(&self) -> String {
        format!("{}/chat/completions", self.options.base_url.trim_end_matches('/'))
    }

    /// Removes the API key from a text that came from the network, and cuts it to 300
    /// characters (for error messages).
    ///
    /// The key is removed from the whole text before the cut, and a cut that ends in the first
    /// characters of the key loses them too, so no part of the key reaches the message.
    fn scrub(&self, text: &str) -> String {
        let redacted = self.redact(text);
        let cut: String = redacted.chars().take(300).collect();
        match self.options.api_key.as_deref().filter(|k| !k.is_empty()) {
            Some(key) => drop_key_prefix(&cut, key),
            None => cut,
        }
    }

    /// Removes the API key from a whole text that came from the network (an answer): a server
    /// that echoes it must not put it into the scene, the transcript or any excerpt. Every
    /// escape form is matched (see [`redact_key`]).
    fn redact(&self, text: &str) -> String {
        match self.options.api_key.as_deref().filter(|k| !k.is_empty()) {
            Some(key) => redact_key(text, key),
            None => text.to_owned(),
        }
    }

    #[cfg(feature = "generate")]
    fn body(&self, prompt: &str) -> Value {
        let mut body = json!({
            "model": self.options.model,
            "messages": [{"role": "user", "content": prompt}],
            "temperature": self.options.temperature,
        });
        if let Some(seed) = self.options.seed {
            body["seed"] = json!(seed);
        }
        if let Some(max) = self.options.max_tokens {
            body["max_tokens"] = json!(max);
        }
        body
    }
}

/// The text with every occurrence of `key` replaced by `[redacted]`, whatever the form each of
/// its characters is written in: as itself, as a JSON escape (`\u0073`, any case, `\/`), as
/// percent-encoding of its UTF-8 bytes (`%73`, any case), or as an HTML character reference
/// (`&#115;`, `&#x73;`). Forms may be mixed within one occurrence. The key may be split by line
/// breaks (`\n`, `\r\n`, or their JSON escapes, each followed by any spaces or tabs), and it
/// may be base64-encoded, standard or URL-safe, at any of the three byte alignments inside a
/// longer encoded text (a `Basic` authorisation, say): the characters that only the key's bytes
/// decide are redacted, themselves in any of the forms above. Linear in the text times the
/// key's length.
pub fn redact_key(text: &str, key: &str) -> String {
    if key.is_empty() {
        return text.to_owned();
    }
    let mut patterns = vec![key.to_owned()];
    patterns.extend(base64_cores(key.as_bytes()));
    let firsts: Vec<char> = patterns.iter().filter_map(|p| p.chars().next()).collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    'text: while i < text.len() {
        let c = text[i..].chars().next().unwrap_or_default();
        let may_start = firsts.contains(&c) || matches!(c, '\\' | '%' | '&');
        if may_start {
            for pattern in &patterns {
                if let Some(end) = key_at(text, i, pattern) {
                    out.push_str("[redacted]");
                    i = end;
                    continue 'text;
                }
            }
        }
        out.push(c);
        i += c.len_utf8();
    }
    out
}

/// The shortest base64 run [`redact_key`] looks for: shorter runs of a short key's encoding
/// would match ordinary text.
const MIN_BASE64_RUN: usize = 8;

/// The base64 characters that encode only bytes of `key`, for each of the three alignments of
/// the key in an encoded stream, in the standard and the URL-safe alphabet (no padding: the
/// last characters also depend on what follows the key).
fn base64_cores(key: &[u8]) -> Vec<String> {
    use base64::Engine as _;
    let mut out: Vec<String> = Vec::new();
    for engine in [
        base64::engine::general_purpose::STANDARD_NO_PAD,
        base64::engine::general_purpose::URL_SAFE_NO_PAD,
    ] {
        for offset in 0..3 {
            let mut bytes = vec![0u8; offset];
            bytes.extend_from_slice(key);
            let encoded = engine.encode(&bytes);
            // Character k holds bits 6k..6k+6; the key's bits are 8·offset..8·(offset+len).
            let start = (8 * offset).div_ceil(6);
            let end = (8 * (offset + key.len()) / 6).min(encoded.len());
            if let Some(core) = encoded.get(start..end).filter(|c| c.len() >= MIN_BASE64_RUN) {
                if !out.iter().any(|o| o == core) {
                    out.push(core.to_owned());
                }
            }
        }
    }
    out
}

/// Where an occurrence of `key` (in any of [`redact_key`]'s forms) starting at byte `at` ends.
fn key_at(text: &str, at: usize, key: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut i = at;
    for (n, c) in key.chars().enumerate() {
        if n > 0 {
            i = past_line_break(bytes, i);
        }
        i = char_at(text, bytes, i, c)?;
    }
    Some(i)
}

/// Past a line break at byte `i` (`\n`, `\r\n`, `\r`, or the JSON escapes `\\n` and `\\r`,
/// one or more, then spaces and tabs); `i` itself when there is none.
fn past_line_break(bytes: &[u8], mut i: usize) -> usize {
    let start = i;
    loop {
        match bytes.get(i..) {
            Some([b'\n' | b'\r', ..]) => i += 1,
            Some([b'\\', b'n' | b'r', ..]) => i += 2,
            _ => break,
        }
    }
    if i == start {
        return i;
    }
    while matches!(bytes.get(i), Some(b' ' | b'\t')) {
        i += 1;
    }
    i
}

/// Where the character `c`, written in one of [`redact_key`]'s forms at byte `i`, ends.
fn char_at(text: &str, bytes: &[u8], i: usize, c: char) -> Option<usize> {
    let rest = text.get(i..)?;
    if rest.starts_with(c) {
        return Some(i + c.len_utf8());
    }
    let hex = |s: &str| u32::from_str_radix(s, 16).ok();
    match bytes.get(i)? {
        b'\\' => {
            if c == '/' && rest.starts_with("\\/") {
                return Some(i + 2);
            }
            let code =
                rest.get(2..6).filter(|_| rest[1..].starts_with(['u', 'U'])).and_then(hex)?;
            (code == c as u32).then_some(i + 6)
        }
        b'%' => {
            let mut buf = [0u8; 4];
            let mut j = i;
            for &b in c.encode_utf8(&mut buf).as_bytes() {
                let byte =
                    text.get(j..j + 3).filter(|s| s.starts_with('%')).and_then(|s| hex(&s[1..]))?;
                if byte != u32::from(b) {
                    return None;
                }
                j += 3;
            }
            Some(j)
        }
        b'&' => {
            let end = rest.get(..12).unwrap_or(rest).find(';')?;
            let code = rest.get(2..end).filter(|_| rest.starts_with("&#"))?;
            let code = match code.strip_prefix(['x', 'X']) {
                Some(h) => hex(h)?,
                None => code.parse().ok()?,
            };
            (code == c as u32).then_some(i + end + 1)
        }
        _ => None,
    }
}

/// The text without a last run that begins the key (at least its first four characters, or
/// the whole key when shorter, in any of [`redact_key`]'s forms): what a cut right inside the
/// key would leave.
fn drop_key_prefix(text: &str, key: &str) -> String {
    let n = key.chars().count();
    let least = n.min(4);
    let bytes = text.as_bytes();
    // The longest form of a character is 12 bytes (`%xx` for each of 4 bytes).
    let from = text.len().saturating_sub(12 * n);
    for p in (from..text.len()).filter(|&p| text.is_char_boundary(p)) {
        let mut i = p;
        let mut matched = 0;
        for c in key.chars() {
            if i == text.len() {
                break;
            }
            match char_at(text, bytes, i, c) {
                Some(end) => {
                    i = end;
                    matched += 1;
                }
                None => {
                    matched = 0;
                    break;
                }
            }
        }
        if i == text.len() && matched >= least && matched < n {
            return format!("{}[redacted]", &text[..p]);
        }
    }
    text.to_owned()
}

#[cfg(feature = "generate")]
fn retry_after(response: &reqwest::blocking::Response) -> Option<Duration> {
    let value = response.headers().get(reqwest::header::RETRY_AFTER)?.to_str().ok()?;
    let seconds: f64 = value.trim().parse().ok()?;
    (seconds.is_finite() && seconds >= 0.0).then(|| Duration::from_secs_f64(seconds.min(3600.0)))
}

/// How a holoc without its HTTP client says so (an error that retrying cannot fix).
const NO_CLIENT: &str = "without its `generate` feature";

/// The server used when neither `--base-url` nor `HOLOC_BASE_URL` is given.
pub const DEFAULT_BASE_URL: &str = "https://api.openai.com/v1";
/// The model used when neither `--model` nor `HOLOC_MODEL` is given.
pub const DEFAULT_MODEL: &str = "gpt-4o";

/// Reads `choices[0].message.content` and `usage` from the body of a chat completion (any
/// text: a body that is not a completion is an error message, never a panic).
pub fn parse_completion(body: &str) -> Result<LlmAnswer, String> {
    let value: Value =
        serde_json::from_str(body).map_err(|e| format!("the body is not JSON ({e})"))?;
    let text = value
        .pointer("/choices/0/message/content")
        .and_then(Value::as_str)
        .ok_or_else(|| "missing `choices[0].message.content`".to_string())?;
    let count =
        |name: &str| value.pointer(&format!("/usage/{name}")).and_then(Value::as_u64).unwrap_or(0);
    Ok(LlmAnswer {
        text: text.to_string(),
        usage: Usage {
            prompt_tokens: count("prompt_tokens"),
            completion_tokens: count("completion_tokens"),
        },
    })
}

impl Llm for HttpLlm {
    fn complete(&self, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        let client = self.client.as_ref().map_err(|reason| LlmError::Unreachable {
            base_url: self.options.base_url.clone(),
            reason: self.scrub(reason),
        })?;
        self.post(client, request)
    }

    fn info(&self) -> ModelInfo {
        self.model_info()
    }
}

impl HttpLlm {
    /// Without the HTTP client there is no client to post with.
    #[cfg(not(feature = "generate"))]
    #[allow(clippy::unused_self, clippy::trivially_copy_pass_by_ref)]
    fn post(&self, client: &Transport, _request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        match *client {}
    }

    /// Posts the request, retrying timeouts, 429 and 5xx answers with backoff.
    #[cfg(feature = "generate")]
    fn post(&self, client: &Transport, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        let url = self.url();
        let body = self.body(request.prompt);
        let tries = self.options.retries.saturating_add(1);
        let mut last = None;
        for n in 0..tries {
            let mut builder = client.post(&url).json(&body);
            if let Some(key) = self.options.api_key.as_deref().filter(|k| !k.is_empty()) {
                builder = builder.bearer_auth(key);
            }
            let wait = match builder.send() {
                Err(error) if error.is_timeout() => {
                    last = Some(LlmError::Timeout {
                        seconds: self.options.timeout.as_secs_f64(),
                        tries: n + 1,
                    });
                    self.options.backoff(n, None)
                }
                Err(error) => {
                    let mut reason = error.to_string();
                    let mut source = std::error::Error::source(&error);
                    while let Some(cause) = source {
                        reason = format!("{reason}: {cause}");
                        source = cause.source();
                    }
                    return Err(LlmError::Unreachable {
                        base_url: self.options.base_url.clone(),
                        reason: self.scrub(&reason),
                    });
                }
                Ok(response) => {
                    let status = response.status().as_u16();
                    let after = retry_after(&response);
                    let text = match response.text() {
                        Ok(text) => text,
                        Err(error) if error.is_timeout() => {
                            last = Some(LlmError::Timeout {
                                seconds: self.options.timeout.as_secs_f64(),
                                tries: n + 1,
                            });
                            std::thread::sleep(self.options.backoff(n, None));
                            continue;
                        }
                        // The connection broke while the answer came (reset, closed): as
                        // passing as a server that could not be reached.
                        Err(error) => {
                            return Err(LlmError::Unreachable {
                                base_url: self.options.base_url.clone(),
                                reason: self.scrub(&format!(
                                    "the connection broke while the answer came ({error})"
                                )),
                            })
                        }
                    };
                    match status {
                        200..=299 => {
                            // The raw body and the decoded answer are both redacted: an
                            // escape the JSON decoding turns into the key is caught too.
                            return parse_completion(&self.redact(&text))
                                .map(|mut answer| {
                                    answer.text = self.redact(&answer.text);
                                    answer
                                })
                                .map_err(|reason| LlmError::InvalidResponse {
                                    reason: self.scrub(&reason),
                                });
                        }
                        401 | 403 => {
                            return Err(LlmError::Unauthorized { status, body: self.scrub(&text) })
                        }
                        404 => {
                            return Err(LlmError::NotFound {
                                url,
                                model: self.options.model.clone(),
                                body: self.scrub(&text),
                            })
                        }
                        429 | 500..=599 => {
                            last = Some(LlmError::Server {
                                status,
                                tries: n + 1,
                                body: self.scrub(&text),
                                retry_after: after,
                            });
                            self.options.backoff(n, after)
                        }
                        _ => {
                            return Err(LlmError::Server {
                                status,
                                tries: n + 1,
                                body: self.scrub(&text),
                                retry_after: None,
                            })
                        }
                    }
                }
            };
            if n + 1 < tries {
                std::thread::sleep(wait);
            }
        }
        Err(last.unwrap_or(LlmError::Server {
            status: 0,
            tries,
            body: String::new(),
            retry_after: None,
        }))
    }

    /// The model and settings this client asks with.
    fn model_info(&self) -> ModelInfo {
        let mut parameters = BTreeMap::new();
        parameters.insert("temperature".to_string(), json!(self.options.temperature));
        if let Some(seed) = self.options.seed {
            parameters.insert("seed".to_string(), json!(seed));
        }
        if let Some(max) = self.options.max_tokens {
            parameters.insert("max_tokens".to_string(), json!(max));
        }
        ModelInfo {
            base_url: self.options.base_url.clone(),
            model: self.options.model.clone(),
            temperature: self.options.temperature,
            parameters,
        }
    }
}

/// One recorded answer for [`ReplayLlm`].
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedAnswer {
    /// The stage name.
    pub stage: String,
    /// The room label, if any.
    pub room: Option<String>,
    /// The attempt.
    pub attempt: u32,
    /// The answer text.
    pub answer: String,
    /// Token counts as recorded.
    pub usage: Usage,
}

/// A model that answers from a recorded transcript, without any network.
#[derive(Clone, Debug)]
pub struct ReplayLlm {
    answers: BTreeMap<(String, Option<String>, u32), (String, Usage)>,
    info: ModelInfo,
}

impl ReplayLlm {
    /// A replay of these answers; a later answer for the same question replaces an earlier one.
    pub fn new(answers: Vec<RecordedAnswer>, info: ModelInfo) -> ReplayLlm {
        let answers = answers
            .into_iter()
            .map(|a| ((a.stage, a.room, a.attempt), (a.answer, a.usage)))
            .collect();
        ReplayLlm { answers, info }
    }
}

impl Llm for ReplayLlm {
    fn complete(&self, request: &LlmRequest<'_>) -> Result<LlmAnswer, LlmError> {
        let key = (request.stage.to_string(), request.room.map(str::to_string), request.attempt);
        match self.answers.get(&key) {
            Some((text, usage)) => Ok(LlmAnswer { text: text.clone(), usage: *usage }),
            None => Err(LlmError::MissingReplay {
                stage: request.stage.to_string(),
                room: request.room.map(str::to_string),
                attempt: request.attempt,
            }),
        }
    }

    fn info(&self) -> ModelInfo {
        self.info.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write as _;

    #[test]
    fn backoff_doubles_and_is_capped() {
        let mut options = HttpOptions::new("http://x", "m");
        options.base_delay = Duration::from_millis(100);
        options.max_delay = Duration::from_millis(350);
        assert_eq!(options.backoff(0, None), Duration::from_millis(100));
        assert_eq!(options.backoff(1, None), Duration::from_millis(200));
        assert_eq!(options.backoff(2, None), Duration::from_millis(350));
        assert_eq!(options.backoff(40, None), Duration::from_millis(350));
        assert_eq!(options.backoff(0, Some(Duration::from_secs(9))), Duration::from_millis(350));
    }

    #[test]
    fn debug_hides_the_key() {
        let mut options = HttpOptions::new("http://x", "m");
        options.api_key = Some("sk-secret-123".into());
        let client = HttpLlm::new(options);
        assert!(!format!("{client:?}").contains("sk-secret-123"));
        assert_eq!(client.scrub("echo sk-secret-123!"), "echo [redacted]!");
    }

    /// A character of the key written in one of the forms a server may use.
    fn encode(c: char, form: u8) -> String {
        match form % 6 {
            0 => c.to_string(),
            1 => format!("\\u{:04x}", c as u32),
            2 => format!("\\u{:04X}", c as u32),
            3 => {
                let mut buf = [0u8; 4];
                c.encode_utf8(&mut buf).bytes().fold(String::new(), |mut s, b| {
                    let _ = write!(s, "%{b:02x}");
                    s
                })
            }
            4 => {
                let mut buf = [0u8; 4];
                c.encode_utf8(&mut buf).bytes().fold(String::new(), |mut s, b| {
                    let _ = write!(s, "%{b:02X}");
                    s
                })
            }
            _ => format!("&#{};", c as u32),
        }
    }

    /// Every form [`encode`] writes, decoded.
    fn decode(text: &str) -> String {
        let mut out = text.to_string();
        for k in 0..6u8 {
            for c in (0x20u8..0x7f).map(char::from) {
                out = out.replace(&encode(c, k), &c.to_string());
            }
        }
        out
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
        #[test]
        fn the_key_never_survives_in_any_form(
            key in "[A-Za-z0-9_-]{8,40}",
            forms in proptest::collection::vec(0u8..6, 40),
            before in "[ -~]{0,320}",
            after in "[ -~]{0,40}",
            cut in 0usize..400,
        ) {
            let key = format!("sk-{key}");
            let encoded: String =
                key.chars().zip(forms.iter().cycle()).map(|(c, &f)| encode(c, f)).collect();
            let text = format!("{before}{encoded}{after}");
            let redacted = redact_key(&text, &key);
            proptest::prop_assert!(!redacted.contains(&key));
            proptest::prop_assert!(!decode(&redacted).contains(&key), "{redacted}");
            // An error message cuts the body: no prefix of the key is left at the cut.
            let mut options = HttpOptions::new("http://x", "m");
            options.api_key = Some(key.clone());
            let client = HttpLlm::new(options);
            let body: String = text.chars().take(cut.max(1)).collect();
            let scrubbed = client.scrub(&body);
            let plain = decode(&scrubbed);
            proptest::prop_assert!(!plain.contains(&key), "{scrubbed}");
            for n in 4..key.len() {
                proptest::prop_assert!(!plain.ends_with(&key[..n]), "{scrubbed}");
            }
        }
    }

    #[test]
    fn escaped_keys_are_redacted() {
        let key = "sk-abc/123";
        for text in [
            "x sk-abc/123 y",
            "x \\u0073\\u006b-abc\\/123 y",
            "x %73%6B%2dabc%2F123 y",
            "x &#115;&#x6b;-abc/123 y",
        ] {
            assert_eq!(redact_key(text, key), "x [redacted] y", "{text}");
        }
        assert_eq!(drop_key_prefix("error: sk-ab", key), "error: [redacted]");
        assert_eq!(drop_key_prefix("error: sk", key), "error: sk");
    }

    #[test]
    fn keys_split_by_line_breaks_are_redacted() {
        let key = "sk-abc/123";
        for text in ["x sk-ab\nc/123 y", "x sk-abc/\r\n   123 y", "x sk-\\nabc\\r\\n/123 y"] {
            assert_eq!(redact_key(text, key), "x [redacted] y", "{text:?}");
        }
        // A break before or after the key is not part of it.
        assert_eq!(redact_key("\nsk-abc/123\n", key), "\n[redacted]\n");
    }

    #[test]
    fn base64_keys_are_redacted_at_every_alignment() {
        use base64::Engine as _;
        let key = "sk-live-0123456789abcdef?>~";
        let engines = [
            base64::engine::general_purpose::STANDARD,
            base64::engine::general_purpose::URL_SAFE,
            base64::engine::general_purpose::URL_SAFE_NO_PAD,
        ];
        for engine in engines {
            for prefix in ["", "u", "us", "user:"] {
                let encoded = engine.encode(format!("{prefix}{key}"));
                // Whole, split over two lines as MIME does, and JSON-escaped (`\/`).
                let split = format!("{}\n{}", &encoded[..10], &encoded[10..]);
                let escaped = encoded.replace('/', "\\/");
                for text in [&encoded, &split, &escaped] {
                    let redacted = redact_key(&format!("Basic {text} end"), key);
                    assert!(redacted.contains("[redacted]"), "{text} -> {redacted}");
                    // What is left of the encoding: the prefix's characters and the one
                    // each end shares with the bytes around the key, never a run of its own.
                    let longest = redacted
                        .split(|c: char| !(c.is_ascii_alphanumeric() || "+/-_=".contains(c)))
                        .map(str::len)
                        .max()
                        .unwrap_or(0);
                    assert!(longest <= 9, "{text} -> {redacted}");
                }
            }
        }
        // Ordinary text is left alone.
        assert_eq!(redact_key("a plain answer\nwith lines", key), "a plain answer\nwith lines");
    }

    #[test]
    fn completion_parsing() {
        let ok = r#"{"choices":[{"message":{"role":"assistant","content":"3.0"}}],"usage":{"prompt_tokens":5,"completion_tokens":1}}"#;
        let answer = parse_completion(ok).expect("a valid completion");
        assert_eq!(answer.text, "3.0");
        assert_eq!(answer.usage, Usage { prompt_tokens: 5, completion_tokens: 1 });
        assert!(parse_completion("{}").is_err());
        assert!(parse_completion("<html>").is_err());
    }
}
