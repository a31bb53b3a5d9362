//! The serde types of holoc's transcript: the record of every exchange with the model while a
//! scene was generated (`generate` writes it, `import` reads it back).
//!
//! Format `holoc-transcript`, version 1; see `book/src/reference/transcript.md`. Everything but
//! `stage` and `answer` in an exchange is optional, and unknown fields are ignored, so older
//! and hand-written transcripts still load.

use serde::{Deserialize, Serialize};

/// The value of the `format` field of every transcript.
pub const TRANSCRIPT_FORMAT: &str = "holoc-transcript";
/// The transcript version this crate writes and reads.
pub const TRANSCRIPT_VERSION: u32 = 1;

/// A whole transcript: the request, the model used and every exchange in order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Transcript {
    /// Always `"holoc-transcript"`.
    #[serde(default = "default_format")]
    pub format: String,
    /// Format version (1).
    #[serde(default = "default_version")]
    pub version: u32,
    /// The user's English request.
    #[serde(default)]
    pub request: String,
    /// The seed of the run.
    #[serde(default)]
    pub seed: u64,
    /// The model endpoint and settings, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelInfo>,
    /// Every exchange, in the order they happened (repairs are later attempts).
    #[serde(default)]
    pub exchanges: Vec<Exchange>,
    /// Totals over all exchanges, when recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub totals: Option<Totals>,
}

fn default_format() -> String {
    TRANSCRIPT_FORMAT.to_string()
}

fn default_version() -> u32 {
    TRANSCRIPT_VERSION
}

impl Default for Transcript {
    fn default() -> Self {
        Transcript {
            format: default_format(),
            version: TRANSCRIPT_VERSION,
            request: String::new(),
            seed: 0,
            model: None,
            exchanges: Vec::new(),
            totals: None,
        }
    }
}

impl Transcript {
    /// The exchange the importer uses for `(stage, room)`: the one with the highest
    /// `attempt` (the last one recorded on ties). `room` is compared exactly.
    pub fn latest(&self, stage: &str, room: Option<&str>) -> Option<&Exchange> {
        let mut best: Option<&Exchange> = None;
        for ex in &self.exchanges {
            if ex.stage == stage && ex.room.as_deref() == room {
                match best {
                    Some(b) if b.attempt > ex.attempt => {}
                    _ => best = Some(ex),
                }
            }
        }
        best
    }
}

/// The model endpoint and sampling settings.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ModelInfo {
    /// OpenAI-compatible base URL.
    #[serde(default)]
    pub base_url: String,
    /// Model name as sent to the endpoint.
    #[serde(default)]
    pub model: String,
    /// Sampling temperature.
    #[serde(default)]
    pub temperature: f64,
}

/// One prompt/answer exchange.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Exchange {
    /// Stage name (`floor-plan`, `wall-height`, `doorways`, `windows`, `objects`,
    /// `objects-pipe`, `floor-constraints`, `wall-constraints`, `small-objects`, `ceiling`,
    /// `absolute-layout`).
    pub stage: String,
    /// Room label for per-room stages, `null` for whole-scene stages.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub room: Option<String>,
    /// 0 for the first try, then 1, 2, … for repairs.
    #[serde(default)]
    pub attempt: u32,
    /// The prompt sent.
    #[serde(default)]
    pub prompt: String,
    /// The model's raw answer.
    pub answer: String,
    /// Template parameters used to fill the prompt.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameters: Option<serde_json::Value>,
    /// Milliseconds since the start of the run (not wall-clock time).
    #[serde(default)]
    pub started_ms: u64,
    /// How long the call took, in milliseconds.
    #[serde(default)]
    pub duration_ms: u64,
    /// Token usage reported by the endpoint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub usage: Option<Usage>,
    /// How many diagnostics importing this answer produced.
    #[serde(default)]
    pub diagnostics: u32,
}

/// Token usage of one call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Usage {
    /// Tokens in the prompt.
    #[serde(default)]
    pub prompt_tokens: u64,
    /// Tokens in the answer.
    #[serde(default)]
    pub completion_tokens: u64,
}

/// Totals over a whole run.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Totals {
    /// Number of calls made.
    #[serde(default)]
    pub calls: u64,
    /// Sum of prompt tokens.
    #[serde(default)]
    pub prompt_tokens: u64,
    /// Sum of completion tokens.
    #[serde(default)]
    pub completion_tokens: u64,
    /// Total seconds spent waiting on the model.
    #[serde(default)]
    pub seconds: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_exchange_loads_and_latest_attempt_wins() {
        let json = r#"{"format":"holoc-transcript","version":1,"request":"a bedroom",
            "exchanges":[{"stage":"floor-plan","answer":"a"},
                         {"stage":"floor-plan","answer":"b","attempt":1,"extra":true},
                         {"stage":"windows","room":"Bedroom","answer":"c"}]}"#;
        let t: Transcript = serde_json::from_str(json).expect("valid transcript");
        assert_eq!(t.latest("floor-plan", None).map(|e| e.answer.as_str()), Some("b"));
        assert_eq!(t.latest("windows", Some("Bedroom")).map(|e| e.answer.as_str()), Some("c"));
        assert!(t.latest("windows", None).is_none());
    }
}
