//! Reading the houses the diff compares from files, and pairing two folders of houses.
//!
//! A folder's houses are: each subfolder with a `house.json` (a `holoc batch` job folder),
//! named by the `id` of its `job.json` or, in a `holoc batch` output, by the job its
//! `summary.json` gives the folder's hash (else the folder's name), with its `report.json`; and
//! each file `NAME.house.json` or `NAME.json` at the top (not `summary*.json`, `job.json` or
//! `*.report.json`), named `NAME`, with `NAME.report.json` beside it when there is one. Two
//! folders are paired by those names, so two batch runs pair by job even though a changed job
//! gets another hash, hence another folder.

use super::{diff, Diff, HouseView, Options};
use crate::diag::{Code, Diagnostic};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One house of a folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The name it pairs by.
    pub key: String,
    /// Its house file.
    pub house: PathBuf,
    /// Its build report, when there is one.
    pub report: Option<PathBuf>,
}

/// The largest house or report the diff reads, bytes (as every input of holoc).
const MAX_BYTES: u64 = 32 * 1024 * 1024;

#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn read_json(path: &Path, what: &str) -> Result<serde_json::Value, Diagnostic> {
    let bytes = crate::source::read_input_or_stdin(path, MAX_BYTES).map_err(|e| {
        Diagnostic::new(
            Code::E0001,
            format!("cannot read `{}`: {e}", crate::diag::visible(&path.display().to_string())),
        )
        .with_help("check the path and the file's permissions")
    })?;
    serde_json::from_slice(&bytes).map_err(|e| {
        Diagnostic::new(
            Code::E0601,
            format!("`{}` is not a {what}: the file is not valid JSON: {e}", path.display()),
        )
        .with_help("fix the JSON syntax")
    })
}

/// Reads a house file and, when given, its build report.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn load(house: &Path, report: Option<&Path>) -> Result<HouseView, Diagnostic> {
    let value = read_json(house, "house")?;
    let mut view = HouseView::read(&value).map_err(|why| {
        Diagnostic::new(Code::E0601, format!("`{}` is not a house: {why}", house.display()))
            .with_help("give an AI2-THOR house JSON file, a `.holo` scene or a folder of houses")
    })?;
    if let Some(path) = report {
        add_report(&mut view, path)?;
    }
    Ok(view)
}

/// Reads a build report into a house's view (its relations, request and seed).
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn add_report(view: &mut HouseView, path: &Path) -> Result<(), Diagnostic> {
    let value = read_json(path, "build report")?;
    view.add_report(&value).map_err(|why| {
        Diagnostic::new(Code::E0601, format!("`{}` is not a build report: {why}", path.display()))
            .with_help("give the file `holoc build --report` wrote")
    })
}

/// The houses of a folder, sorted by name.
pub fn entries(folder: &Path) -> std::io::Result<Vec<Entry>> {
    let mut out = Vec::new();
    let mut paths: Vec<PathBuf> =
        std::fs::read_dir(folder)?.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    // A `holoc batch` output names each job's folder by its hash; its summary says which job
    // (manifest `id`) each hash is.
    let ids: std::collections::BTreeMap<String, String> =
        crate::source::read_text(&folder.join("summary.json"), MAX_BYTES)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v.get("jobs").and_then(|j| j.as_array()).cloned())
            .unwrap_or_default()
            .iter()
            .filter_map(|j| {
                let hash = j.get("hash")?.as_str()?;
                let id = j.get("id")?.as_str()?;
                Some((hash.to_string(), id.to_string()))
            })
            .collect();
    for path in paths {
        let Some(name) = path.file_name().and_then(|n| n.to_str()).map(str::to_string) else {
            continue;
        };
        if name.starts_with('.') {
            continue;
        }
        if path.is_dir() {
            let house = path.join("house.json");
            if !house.is_file() {
                continue;
            }
            let key = crate::source::read_text(&path.join("job.json"), MAX_BYTES)
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
                .and_then(|v| v.get("id").and_then(|i| i.as_str()).map(str::to_string))
                .or_else(|| ids.get(&name).cloned())
                .unwrap_or_else(|| name.clone());
            let report = Some(path.join("report.json")).filter(|p| p.is_file());
            out.push(Entry { key, house, report });
        } else if let Some(stem) = name.strip_suffix(".json") {
            if stem.ends_with(".report") || stem.starts_with("summary") || stem == "job" {
                continue;
            }
            let key = stem.strip_suffix(".house").unwrap_or(stem).to_string();
            let report = Some(folder.join(format!("{key}.report.json"))).filter(|p| p.is_file());
            out.push(Entry { key, house: path, report });
        }
    }
    out.sort_by(|a, b| a.key.cmp(&b.key).then_with(|| a.house.cmp(&b.house)));
    // Two houses of one name (two jobs with the same id): the later ones get their folder's name.
    for i in 1..out.len() {
        if out[i].key == out[i - 1].key {
            let parent = out[i]
                .house
                .parent()
                .and_then(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            out[i].key = format!("{} ({parent})", out[i].key);
        }
    }
    Ok(out)
}

/// How one name of two folders compares.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// The same within the tolerances.
    Same,
    /// Different.
    Changed(Diff),
    /// Only the first folder has it.
    OnlyFirst,
    /// Only the second folder has it.
    OnlySecond,
    /// One of its files could not be read.
    Error(Box<Diagnostic>),
}

/// One name of two folders and how it compares.
#[derive(Clone, Debug, PartialEq)]
pub struct Paired {
    /// The name.
    pub key: String,
    /// How it compares.
    pub outcome: Outcome,
}

/// Pairs two folders' houses by name and compares each pair, calling `each` in name order.
/// Pairs are compared `chunk` at a time on the current rayon pool; only one chunk of houses
/// is in memory at once.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
pub fn compare(
    a: &[Entry],
    b: &[Entry],
    options: &Options,
    chunk: usize,
    mut each: impl FnMut(Paired),
) {
    let mut jobs: Vec<(String, Option<&Entry>, Option<&Entry>)> = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let order = match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) => x.key.cmp(&y.key),
            (Some(_), None) => std::cmp::Ordering::Less,
            _ => std::cmp::Ordering::Greater,
        };
        match order {
            std::cmp::Ordering::Less => {
                jobs.push((a[i].key.clone(), Some(&a[i]), None));
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                jobs.push((b[j].key.clone(), None, Some(&b[j])));
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                jobs.push((a[i].key.clone(), Some(&a[i]), Some(&b[j])));
                i += 1;
                j += 1;
            }
        }
    }
    for part in jobs.chunks(chunk.max(1)) {
        let results: Vec<Paired> = part
            .par_iter()
            .map(|(key, x, y)| {
                let outcome = match (x, y) {
                    (Some(x), Some(y)) => {
                        let both = load(&x.house, x.report.as_deref())
                            .and_then(|hx| load(&y.house, y.report.as_deref()).map(|hy| (hx, hy)));
                        match both {
                            Ok((hx, hy)) => {
                                let d = diff(&hx, &hy, options);
                                if d.is_empty() {
                                    Outcome::Same
                                } else {
                                    Outcome::Changed(d)
                                }
                            }
                            Err(e) => Outcome::Error(Box::new(e)),
                        }
                    }
                    (Some(_), None) => Outcome::OnlyFirst,
                    _ => Outcome::OnlySecond,
                };
                Paired { key: key.clone(), outcome }
            })
            .collect();
        for r in results {
            each(r);
        }
    }
}
