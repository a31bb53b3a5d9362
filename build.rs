//! Captures the build identity of holoc: a hash of the data and prompts it embeds, a hash of
//! its source, and the git commit it was built from (or `HOLOC_BUILD_COMMIT`, for builds
//! outside a git checkout). `holoc --version` shows them and `holoc batch` puts them into every
//! job's hash, so a holoc that would build a job differently redoes it.
//!
//! It also turns the embedded object catalog into Rust source (see [`embedded_catalog`]).

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
    embedded_catalog();
    println!(
        "cargo:rustc-env=HOLOC_EMBEDDED_CATALOG_SHA256={}",
        file_sha256("data/catalog/objects.tsv")
    );
    println!("cargo:rustc-env=HOLOC_BUILD_DATA={}", tree_hash(&["data", "prompts", "grammar"]));
    println!("cargo:rustc-env=HOLOC_BUILD_SOURCE={}", tree_hash(&["src"]));
    println!("cargo:rustc-env=HOLOC_BUILD_COMMIT={}", commit());
}

// The embedded object catalog, made ready at compile time: `data/catalog/objects.tsv` becomes
// static arrays of assets, of their ids in order and of their word index, so that a build
// neither parses the catalog nor indexes its words. The words are normalized and the
// placements decided by the very files the run-time code uses (included below).

#[allow(dead_code, reason = "build.rs uses only the normalizing part of the word rules")]
#[path = "src/resolve/text.rs"]
mod text;

#[allow(dead_code, reason = "build.rs uses only the flags and `category_allows`")]
#[path = "src/resolve/placement.rs"]
mod placement;

/// One asset row of the embedded catalog.
struct Row {
    id: String,
    object_type: String,
    category: String,
    description: String,
    bbox_m: [f64; 3],
    kinds: String,
    receptacle: bool,
}

/// A Rust expression for an `f64`, exactly the value (`{:?}` prints the shortest text that
/// reads back to the same bits).
fn f64_literal(v: f64) -> String {
    if v.is_nan() {
        "f64::NAN".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "f64::INFINITY" } else { "f64::NEG_INFINITY" }.to_string()
    } else {
        format!("{v:?}_f64")
    }
}

/// The same hash of an asset id as `resolve::index` computes (FNV-1a, 64 bits).
fn fnv1a(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Writes `OUT_DIR/embedded_catalog.rs` from `data/catalog/objects.tsv`: the rows are read by
/// the rules the run-time reader had (comment, header and malformed lines skipped, a later row
/// replacing an earlier one of the same id in its place), and the index is the one
/// `TextIndex::build` makes (a test in `resolve::catalog` checks both).
fn embedded_catalog() {
    const PATH: &str = "data/catalog/objects.tsv";
    println!("cargo:rerun-if-changed={PATH}");
    let tsv = std::fs::read_to_string(PATH).expect("data/catalog/objects.tsv is readable");
    let mut name = "procthor-builtin".to_string();
    let mut version = None;
    let mut rows: Vec<Row> = Vec::new();
    let mut by_id: std::collections::BTreeMap<String, usize> = std::collections::BTreeMap::new();
    // Placement flags and category of each object type, first row wins (every 9-field line that
    // is not a comment, as `builtin_type_placements` read them).
    let mut types: std::collections::BTreeMap<String, (String, String)> =
        std::collections::BTreeMap::new();
    for line in tsv.lines() {
        if !line.starts_with('#') {
            if let [_, object_type, category, _, _, _, _, kinds, _] =
                line.split('\t').collect::<Vec<_>>()[..]
            {
                types
                    .entry(object_type.to_string())
                    .or_insert_with(|| (kinds.to_string(), category.to_string()));
            }
        }
        if let Some(rest) = line.strip_prefix("#name\t") {
            name = rest.to_string();
            continue;
        }
        if let Some(rest) = line.strip_prefix("#version\t") {
            version = Some(rest.to_string());
            continue;
        }
        if line.starts_with('#') || line.starts_with("asset_id\t") || line.is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        let [id, object_type, category, description, x, y, z, kinds, receptacle] = f[..] else {
            continue;
        };
        let (Ok(x), Ok(y), Ok(z)) = (x.parse(), y.parse(), z.parse()) else {
            continue;
        };
        let row = Row {
            id: id.to_string(),
            object_type: object_type.to_string(),
            category: category.to_string(),
            description: description.to_string(),
            bbox_m: [x, y, z],
            kinds: kinds.to_string(),
            receptacle: receptacle == "1",
        };
        if let Some(&i) = by_id.get(id) {
            rows[i] = row;
        } else {
            by_id.insert(id.to_string(), rows.len());
            rows.push(row);
        }
    }

    let mut out = String::new();
    let _ = writeln!(out, "// Generated by build.rs from {PATH}; do not edit.");
    let _ = writeln!(out, "pub(super) const NAME: &str = {name:?};");
    let _ = writeln!(out, "pub(super) const VERSION: Option<&str> = {version:?};");
    let placements = |letters: &str| {
        let p = placement::Placements::from_letters(letters);
        format!(
            "Placements {{ on_floor: {}, on_wall: {}, on_object: {}, on_ceiling: {} }}",
            p.on_floor, p.on_wall, p.on_object, p.on_ceiling
        )
    };
    let _ = writeln!(out, "pub(super) static ASSETS: [Asset; {}] = [", rows.len());
    for r in &rows {
        let _ = writeln!(
            out,
            "Asset {{ id: B({:?}), object_type: B({:?}), category: B({:?}), description: \
             B({:?}), bbox_m: [{}, {}, {}], placements: {}, receptacle: {}, source: 0 }},",
            r.id,
            r.object_type,
            r.category,
            r.description,
            f64_literal(r.bbox_m[0]),
            f64_literal(r.bbox_m[1]),
            f64_literal(r.bbox_m[2]),
            placements(&r.kinds),
            r.receptacle
        );
    }
    let _ = writeln!(out, "];");
    let _ = writeln!(out, "pub(super) static BY_ID: [(&str, u32); {}] = [", by_id.len());
    for (id, i) in &by_id {
        let _ = writeln!(out, "({id:?}, {i}),");
    }
    let _ = writeln!(out, "];");
    let _ = writeln!(out, "pub(super) static TYPES: [(&str, Placements, &str); {}] = [", types.len());
    for (object_type, (kinds, category)) in &types {
        let _ = writeln!(out, "({object_type:?}, {}, {category:?}),", placements(kinds));
    }
    let _ = writeln!(out, "];");

    // The word index, as `TextIndex::build` makes it.
    let mut postings: std::collections::BTreeMap<String, Vec<(u32, u32)>> =
        std::collections::BTreeMap::new();
    let (mut doc_len, mut doc_head, mut kind_start, mut kind_words) =
        (Vec::new(), Vec::new(), vec![0u32], Vec::new());
    let (mut id_hash, mut allowed) = (Vec::new(), Vec::new());
    let mut total = 0u64;
    for (i, r) in rows.iter().enumerate() {
        let category = text::normalize(&r.category);
        let description = text::normalize(&r.description);
        let mut counts: std::collections::BTreeMap<&str, u32> = std::collections::BTreeMap::new();
        for t in &category {
            *counts.entry(t).or_default() += 2;
        }
        for t in &description {
            *counts.entry(t).or_default() += 1;
        }
        let len = (2 * category.len() + description.len()) as u32;
        for (t, tf) in counts {
            postings.entry(t.to_string()).or_default().push((i as u32, tf));
        }
        doc_len.push(len);
        let head = text::head(&category).unwrap_or_default().to_string();
        kind_words.extend(
            category.iter().filter(|t| **t != head && !text::is_attribute(t)).cloned(),
        );
        kind_start.push(kind_words.len() as u32);
        doc_head.push(head);
        id_hash.push(fnv1a(&r.id));
        let p = placement::Placements::from_letters(&r.kinds);
        let mut bits = 0u8;
        for (k, kind) in placement::PlacementKind::ALL.into_iter().enumerate() {
            if placement::category_allows(&r.category, p, r.bbox_m[1], kind) {
                bits |= 1 << k;
            }
        }
        allowed.push(bits);
        total += u64::from(len);
    }
    let avg_len = if rows.is_empty() { 1.0 } else { (total as f64 / rows.len() as f64).max(1.0) };
    let list = |out: &mut String, name: &str, ty: &str, items: Vec<String>| {
        let _ = writeln!(out, "static {name}: [{ty}; {}] = [{}];", items.len(), items.join(","));
    };
    let mut terms = Vec::new();
    let mut term_start = vec![0usize];
    let mut entries = Vec::new();
    for (term, list) in &postings {
        terms.push(format!("{term:?}"));
        entries.extend(list.iter().map(|(d, tf)| format!("({d},{tf})")));
        term_start.push(entries.len());
    }
    list(&mut out, "TERMS", "&str", terms);
    list(&mut out, "TERM_START", "u32", term_start.iter().map(usize::to_string).collect());
    list(&mut out, "POSTINGS", "(u32, u32)", entries);
    list(&mut out, "DOC_LEN", "u32", doc_len.iter().map(u32::to_string).collect());
    list(&mut out, "DOC_HEAD", "Word", doc_head.iter().map(|w| format!("B({w:?})")).collect());
    list(&mut out, "KIND_START", "u32", kind_start.iter().map(u32::to_string).collect());
    list(&mut out, "KIND_WORDS", "Word", kind_words.iter().map(|w| format!("B({w:?})")).collect());
    list(&mut out, "ID_HASH", "u64", id_hash.iter().map(|h| format!("{h:#x}")).collect());
    list(&mut out, "ALLOWED", "u8", allowed.iter().map(u8::to_string).collect());
    let _ = writeln!(
        out,
        "pub(super) static INDEX: StaticIndex = StaticIndex {{ terms: &TERMS, term_start: \
         &TERM_START, postings: &POSTINGS, doc_len: &DOC_LEN, doc_head: &DOC_HEAD, kind_start: \
         &KIND_START, kind_words: &KIND_WORDS, id_hash: &ID_HASH, allowed: &ALLOWED, avg_len: {} \
         }};",
        f64_literal(avg_len)
    );
    let dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    std::fs::write(Path::new(&dir).join("embedded_catalog.rs"), out)
        .expect("OUT_DIR is writable");
}
