//! Captures the build identity of holoc: a hash of the data and prompts it embeds, a hash of
//! its source, and the git commit it was built from (or `HOLOC_BUILD_COMMIT`, for builds
//! outside a git checkout). `holoc --version` shows them and `holoc batch` puts them into every
//! job's hash, so a holoc that would build a job differently redoes it.

use sha2::{Digest as _, Sha256};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files(&path, out);
        } else {
            out.push(path);
        }
    }
}

/// SHA-256 over the names and bytes of every file under `dirs`, in name order (12 hex digits).
fn tree_hash(dirs: &[&str]) -> String {
    let mut all = Vec::new();
    for dir in dirs {
        println!("cargo:rerun-if-changed={dir}");
        files(Path::new(dir), &mut all);
    }
    all.sort();
    let mut hasher = Sha256::new();
    for path in all {
        hasher.update(path.to_string_lossy().replace('\\', "/").as_bytes());
        hasher.update([0]);
        hasher.update(std::fs::read(&path).unwrap_or_default());
        hasher.update([0]);
    }
    hasher.finalize().iter().take(6).fold(String::new(), |mut hex, b| {
        let _ = write!(hex, "{b:02x}");
        hex
    })
}

fn commit() -> String {
    println!("cargo:rerun-if-env-changed=HOLOC_BUILD_COMMIT");
    if let Ok(c) = std::env::var("HOLOC_BUILD_COMMIT") {
        if !c.trim().is_empty() {
            return c.trim().to_string();
        }
    }
    // The commit moves when HEAD or the branch it names moves.
    if let Ok(head) = std::fs::read_to_string(".git/HEAD") {
        println!("cargo:rerun-if-changed=.git/HEAD");
        if let Some(reference) = head.trim().strip_prefix("ref: ") {
            println!("cargo:rerun-if-changed=.git/{reference}");
        }
    }
    std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|c| !c.is_empty())
        .unwrap_or_else(|| "unknown".to_string())
}

/// The SHA-256 of one file, in hex (the embedded object catalog's identity, computed here so
/// that a build does not hash 300 KB at start-up).
fn file_sha256(path: &str) -> String {
    println!("cargo:rerun-if-changed={path}");
    let bytes = std::fs::read(path).unwrap_or_default();
    Sha256::digest(&bytes).iter().fold(String::new(), |mut hex, b| {
        let _ = write!(hex, "{b:02x}");
        hex
    })
}

fn main() {
    println!(
        "cargo:rustc-env=HOLOC_EMBEDDED_CATALOG_SHA256={}",
        file_sha256("data/catalog/objects.tsv")
    );
    println!("cargo:rustc-env=HOLOC_BUILD_DATA={}", tree_hash(&["data", "prompts", "grammar"]));
    println!("cargo:rustc-env=HOLOC_BUILD_SOURCE={}", tree_hash(&["src"]));
    println!("cargo:rustc-env=HOLOC_BUILD_COMMIT={}", commit());
}
