//! The `generate` stage: English request → LLM answers → `.holo` text.

pub mod client;
pub mod prompts;
