//! The `import` stage: raw LLM answers (one stage at a time, a holoc transcript, or an original
//! Holodeck scene JSON) → a `.holo` syntax tree.

pub mod transcript;

pub use transcript::{Exchange, ModelInfo, Totals, Transcript, Usage};
