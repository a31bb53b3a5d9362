//! The build identity of this holoc (made by `build.rs`): the version, a hash of the data and
//! prompts it embeds, a hash of its source and the git commit. `holoc --version` prints it and
//! `holoc batch` puts it into every job's hash.

/// The crate version.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// SHA-256 (12 hex digits) of `data/`, `prompts/` and `grammar/`.
pub const DATA: &str = env!("HOLOC_BUILD_DATA");
/// SHA-256 (12 hex digits) of `src/`.
pub const SOURCE: &str = env!("HOLOC_BUILD_SOURCE");
/// The git commit (12 hex digits), `HOLOC_BUILD_COMMIT` when set at build time, or `unknown`.
pub const COMMIT: &str = env!("HOLOC_BUILD_COMMIT");

/// `0.1.0 (commit 0123456789ab, data 0123456789ab, source 0123456789ab)`: what `--version`
/// shows and what a batch job's hash holds.
pub const LONG_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("HOLOC_BUILD_COMMIT"),
    ", data ",
    env!("HOLOC_BUILD_DATA"),
    ", source ",
    env!("HOLOC_BUILD_SOURCE"),
    ")"
);
