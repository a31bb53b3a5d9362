//! The original Holodeck's own assets as a catalog: an objathor version folder
//! (`annotations.json.gz`, `features/clip_features.pkl`, `features/sbert_features.pkl`,
//! `assets/<uid>/…`) given with `--objathor DIR`.
//!
//! Its assets are appended to the [`Catalog`] after every other catalog, with a word index of
//! their own, so that the built-in choices do not change when the folder is added. A query
//! is ranked against them by [`rank`] in one of three [`Scoring`] modes; `resolve` takes
//! built-in assets first and these for the rest, or mixes the two by score ([`Mix`]), and
//! picks among the best by the seed ([`Pick`]). [`check_on_disk`] tells whether the chosen
//! assets are where AI2-THOR's `ProceduralAssetHookRunner` will look for them.

pub mod annotations;
#[cfg(feature = "clip")]
pub mod clip;
pub mod features;
pub mod fixture;
pub mod pickle;
pub mod stored;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::catalog::{Asset, Catalog, CatalogSource, PlacementKind};
use super::index::{Candidate, Query, TextIndex, SIZE_WEIGHT};
use crate::diag::{Code, Diagnostic};
use crate::source::{FileId, SourceMap, Span};
use annotations::{Entry, License};
use features::{Backing, FeatureRows, Features};

/// The largest feature file holoc reads, bytes.
pub const MAX_FEATURES_BYTES: u64 = 4 * 1024 * 1024 * 1024;

/// The original's CLIP thresholds (×100 cosine) by placement: floor and wall objects 31,
/// small objects 30, ceiling objects 29. They test the CLIP part of a score only.
pub fn clip_threshold(kind: PlacementKind) -> f64 {
    match kind {
        PlacementKind::Floor | PlacementKind::Wall => 31.0,
        PlacementKind::OnObject => 30.0,
        PlacementKind::Ceiling => 29.0,
    }
}

/// How many of the best candidates the seeded pick draws from: 10, or 5 for small objects (the
/// original's top 10 and top 5).
pub fn pick_pool(kind: PlacementKind) -> usize {
    if kind == PlacementKind::OnObject {
        5
    } else {
        10
    }
}

/// How many of the best lexical matches make the pseudo-query of the `features` mode.
pub const SEED_MATCHES: usize = 4;

/// How objathor assets are ranked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Scoring {
    /// Words only: BM25 relevance and the size term, as for every catalog.
    Lexical,
    /// The stored CLIP rows, without a model: the best lexical matches make a pseudo-query in
    /// CLIP space and candidates are ranked by `100·max cos` (+ SBERT cos) − the size term.
    Features,
    /// The original's formula with a CLIP text tower: not available in this build.
    Clip,
}

impl Scoring {
    /// The word used on the command line and in the report.
    pub fn as_str(self) -> &'static str {
        match self {
            Scoring::Lexical => "lexical",
            Scoring::Features => "features",
            Scoring::Clip => "clip",
        }
    }

    /// Parses [`Scoring::as_str`].
    pub fn parse(text: &str) -> Option<Scoring> {
        match text.trim() {
            "lexical" => Some(Scoring::Lexical),
            "features" => Some(Scoring::Features),
            "clip" => Some(Scoring::Clip),
            _ => None,
        }
    }
}

/// How objathor assets and the other catalogs' assets are combined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mix {
    /// Objathor's good assets first, as the original takes them (its retrieval scores only its
    /// own database); the other catalogs for what the folder has nothing good for.
    #[default]
    ObjathorFirst,
    /// The other catalogs first; objathor assets only for what they have nothing good for.
    BuiltinFirst,
    /// Both, merged by their lexical score.
    Score,
}

impl Mix {
    /// The word used on the command line and in the report.
    pub fn as_str(self) -> &'static str {
        match self {
            Mix::ObjathorFirst => "objathor-first",
            Mix::BuiltinFirst => "builtin-first",
            Mix::Score => "score",
        }
    }

    /// Parses [`Mix::as_str`].
    pub fn parse(text: &str) -> Option<Mix> {
        match text.trim() {
            "objathor-first" => Some(Mix::ObjathorFirst),
            "builtin-first" => Some(Mix::BuiltinFirst),
            "score" => Some(Mix::Score),
            _ => None,
        }
    }
}

/// How one asset is taken from the good candidates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Pick {
    /// The best one.
    #[default]
    Argmax,
    /// A draw from the softmax of the best 10 (5 for small objects) scores, from the seed.
    Seeded,
}

impl Pick {
    /// The word used on the command line and in the report.
    pub fn as_str(self) -> &'static str {
        match self {
            Pick::Argmax => "argmax",
            Pick::Seeded => "seeded",
        }
    }

    /// Parses [`Pick::as_str`].
    pub fn parse(text: &str) -> Option<Pick> {
        match text.trim() {
            "argmax" => Some(Pick::Argmax),
            "seeded" => Some(Pick::Seeded),
            _ => None,
        }
    }
}

/// What `--objathor` and its companions ask.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ObjathorOptions {
    /// A version folder, or the base folder that holds version folders.
    pub dir: PathBuf,
    /// The version folder's name under `dir` (`2023_09_23`).
    pub version: Option<String>,
    /// The scoring mode; `None` is `clip` with a text tower ([`ObjathorOptions::clip`]), else
    /// `features` when the folder has CLIP features, else `lexical`.
    pub scoring: Option<Scoring>,
    /// How objathor assets and the other catalogs combine.
    pub mix: Mix,
    /// How one asset is taken from the good ones.
    pub pick: Pick,
    /// Read the folder's files every time, never its index ([`stored`]), and write none.
    pub no_index: bool,
    /// The CLIP text tower's weights folder of the `clip` mode (`--objathor-clip DIR`: Hugging
    /// Face's `model.safetensors`, `config.json` and tokenizer files).
    pub clip: Option<PathBuf>,
}

impl ObjathorOptions {
    /// The options written as words (`holoc.toml`, a batch job, the language server's
    /// settings), the folder relative to `base`; `Ok(None)` without a folder, an error naming
    /// the first word that is not one of its setting's.
    pub fn from_words(
        base: &Path,
        dir: Option<&Path>,
        version: Option<&str>,
        scoring: Option<&str>,
        mix: Option<&str>,
        pick: Option<&str>,
        clip: Option<&Path>,
    ) -> Result<Option<ObjathorOptions>, String> {
        let Some(dir) = dir else { return Ok(None) };
        let scoring = match scoring {
            Some(s) => Some(Scoring::parse(s).ok_or_else(|| {
                format!("unknown objathor scoring `{s}` (lexical, features or clip)")
            })?),
            None => None,
        };
        let mix = match mix {
            Some(s) => Mix::parse(s).ok_or_else(|| {
                format!("unknown objathor mix `{s}` (objathor-first, builtin-first or score)")
            })?,
            None => Mix::default(),
        };
        let pick = match pick {
            Some(s) => Pick::parse(s)
                .ok_or_else(|| format!("unknown objathor pick `{s}` (argmax or seeded)"))?,
            None => Pick::default(),
        };
        Ok(Some(ObjathorOptions {
            dir: base.join(dir),
            version: version.map(str::to_string),
            scoring,
            mix,
            pick,
            no_index: false,
            clip: clip.map(|c| base.join(c)),
        }))
    }
}

/// A loaded objathor version folder, kept by the catalog.
#[derive(Clone, Debug)]
pub struct Objathor {
    /// The version folder.
    pub root: PathBuf,
    /// Its version (the folder's name).
    pub version: String,
    /// Index of its source in [`Catalog::sources`].
    pub source: usize,
    /// Its assets are the catalog's assets `start..end`.
    pub start: usize,
    /// One past its last asset.
    pub end: usize,
    /// Every other field of each asset's entry, by its place in the range.
    pub entries: Vec<Entry>,
    /// The feature rows, when the folder has them.
    pub features: Option<Arc<Features>>,
    /// The `assets/` folder, when there is one.
    pub assets_dir: Option<PathBuf>,
    /// Whether the folder is of the web-fetched generation (Holodeck `v2`, `2024_08_16` and
    /// later, or an `assets/` folder that is empty): its assets are fetched one at a time by
    /// `WebProceduralAssetHookRunner` when the house loads, so an asset missing from `assets/`
    /// is expected, not an error.
    pub fetched: bool,
    /// The scoring mode in force.
    pub scoring: Scoring,
    /// The scoring mode asked (`None`: chosen from what the folder holds).
    pub scoring_asked: Option<Scoring>,
    /// How it combines with the other catalogs.
    pub mix: Mix,
    /// How one asset is taken.
    pub pick: Pick,
    /// The files read, with their SHA-256: what the catalog lock records.
    pub files: Vec<(String, String)>,
    pub(crate) index: TextIndex,
    /// The folder's assets (by their place in its range) under each WordNet synset of the
    /// annotations (`synset`).
    pub(crate) synset_members: HashMap<String, Vec<usize>>,
    /// The index the folder was read from or written to ([`stored`]), when there is one.
    pub index_file: Option<PathBuf>,
    /// Whether the folder was read from that index (else from its files).
    pub from_index: bool,
    /// The CLIP text tower of the `clip` mode.
    #[cfg(feature = "clip")]
    pub tower: Option<Arc<clip::TextTower>>,
}

impl Objathor {
    /// Whether the catalog's asset at `idx` is one of this folder's.
    pub fn holds(&self, idx: usize) -> bool {
        (self.start..self.end).contains(&idx)
    }

    /// The entry of the catalog's asset at `idx`, when it is one of this folder's.
    pub fn entry(&self, idx: usize) -> Option<&Entry> {
        idx.checked_sub(self.start).and_then(|k| self.entries.get(k))
    }

    /// The licence of the catalog's asset at `idx`.
    pub fn license(&self, idx: usize) -> Option<&License> {
        self.entry(idx).and_then(|e| e.license.as_ref())
    }

    /// Whether the `features` mode uses CLIP text rows (else the view-averaged image rows) for
    /// its pseudo-query.
    pub fn pseudo_query_space(&self) -> Option<&'static str> {
        let f = self.features.as_ref()?;
        f.img.as_ref()?;
        Some(if f.text.is_some() { "clip-text" } else { "clip-image" })
    }
}

fn folder_error(dir: &Path, message: String, help: &str) -> Box<Diagnostic> {
    Box::new(
        Diagnostic::new(Code::E0404, message)
            .with_note(format!("`--objathor` is `{}`", dir.display()))
            .with_help(help.to_string()),
    )
}

fn annotations_in(dir: &Path) -> Option<PathBuf> {
    ["annotations.json.gz", "annotations.json"].iter().map(|n| dir.join(n)).find(|p| present(p))
}

/// Whether something that is not a folder stands at `path` (a named pipe or a device counts:
/// reading it then says what it is, instead of calling it missing).
fn present(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| !m.is_dir())
}

/// The version folder `options` names: `dir` itself when it holds the annotations (or its
/// `version` subfolder), else the one version folder under it.
fn version_folder(options: &ObjathorOptions) -> Result<(PathBuf, PathBuf), Box<Diagnostic>> {
    let dir = &options.dir;
    if !dir.is_dir() {
        return Err(folder_error(
            dir,
            format!("the objathor folder `{}` does not exist", dir.display()),
            "give the folder objathor downloaded into (e.g. `~/.objathor-assets/2023_09_23`)",
        ));
    }
    if let Some(version) = &options.version {
        let sub = dir.join(version);
        if let Some(a) = annotations_in(&sub) {
            return Ok((sub, a));
        }
        if dir.file_name().is_some_and(|n| n.to_string_lossy() == *version) {
            if let Some(a) = annotations_in(dir) {
                return Ok((dir.clone(), a));
            }
        }
        return Err(folder_error(
            dir,
            format!("the objathor folder has no version `{version}` with an `annotations.json.gz`"),
            "check `--objathor-version`, or give the version folder itself",
        ));
    }
    if let Some(a) = annotations_in(dir) {
        return Ok((dir.clone(), a));
    }
    let mut versions: Vec<(String, PathBuf)> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .flatten()
                .filter_map(|e| {
                    let path = e.path();
                    let a = annotations_in(&path)?;
                    Some((e.file_name().to_string_lossy().into_owned(), a))
                })
                .collect()
        })
        .unwrap_or_default();
    versions.sort();
    match versions.len() {
        0 => Err(folder_error(
            dir,
            format!(
                "the objathor folder `{}` has no `annotations.json.gz`, nor a version folder with one",
                dir.display()
            ),
            "give a version folder such as `~/.objathor-assets/2023_09_23`",
        )),
        1 => {
            let (name, a) = versions.remove(0);
            Ok((dir.join(name), a))
        }
        _ => {
            let names: Vec<String> = versions.iter().map(|(n, _)| format!("`{n}`")).collect();
            Err(folder_error(
                dir,
                format!("the objathor folder holds several versions: {}", names.join(", ")),
                "choose one with `--objathor-version`",
            ))
        }
    }
}

fn features_warning(path: &Path, why: &str) -> Diagnostic {
    Diagnostic::new(
        Code::W0405,
        format!("the objathor features file `{}` is not used: {why}", path.display()),
    )
    .with_help(
        "download the features with objathor's `download_features` script, or score with \
         `--objathor-scoring lexical`",
    )
}

/// A feature file read: the arrays it holds and the SHA-256 of its bytes.
struct FeatureFile {
    uids: Vec<String>,
    arrays: Vec<(String, FeatureRows)>,
    sha256: String,
}

/// The most a gzip feature file may hold once decompressed: it is decompressed into memory (a
/// gzip stream cannot be read at a row's place), so its bound is that of the memory, not the
/// 4 GiB of a plain file, whose rows are read from disk. 512 MiB hold 116,000 assets of image
/// features (objathor's 50,000 take 230 MB).
pub const MAX_GZIP_FEATURES_BYTES: u64 = 512 * 1024 * 1024;

/// Reads a pickled feature file (gzip allowed) with the arrays `keys` (the first required).
///
/// A regular file is read where it lies (issue 51: the largest legal file was held whole, 4.3
/// GB): its bytes are hashed as they stream by, its pickle is read without its arrays'
/// bytes, and its rows are read from disk when a query looks at them, as the folder's index's
/// are. A gzip file is decompressed into memory (at most [`MAX_GZIP_FEATURES_BYTES`]); a device
/// or pipe is read whole, as before.
fn read_features(path: &Path, keys: &[&str]) -> Result<FeatureFile, String> {
    let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
    if !regular {
        let bytes =
            crate::source::read_input(path, MAX_FEATURES_BYTES).map_err(|e| e.to_string())?;
        return features_of_bytes(bytes, keys);
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let len = file.metadata().map_err(|e| e.to_string())?.len();
    if len > MAX_FEATURES_BYTES {
        return Err(crate::source::ReadError::TooLarge(MAX_FEATURES_BYTES).to_string());
    }
    let len = usize::try_from(len).map_err(|e| e.to_string())?;
    let (sha256, gzip) = hash_file(&file, len)?;
    if gzip {
        use std::io::Read as _;
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(std::io::BufReader::new(&file))
            .take(MAX_GZIP_FEATURES_BYTES + 1)
            .read_to_end(&mut out)
            .map_err(|e| format!("bad gzip data: {e}"))?;
        check_gunzipped(&out)?;
        let out = Arc::new(out);
        let pickle =
            pickle::Pickle::read(&out).map_err(|e| format!("not a readable pickle: {e}"))?;
        return features_of_pickle(&Backing::Read(Arc::clone(&out)), &pickle, keys, sha256);
    }
    let file = Arc::new(file);
    let pickle =
        pickle::Pickle::read_file(&file, len).map_err(|e| format!("not a readable pickle: {e}"))?;
    features_of_pickle(&Backing::Stored(Arc::clone(&file), len), &pickle, keys, sha256)
}

/// The SHA-256 of the first `len` bytes of `file` (read a MiB at a time) and whether they
/// start as gzip data.
fn hash_file(file: &std::fs::File, len: usize) -> Result<(String, bool), String> {
    use sha2::Digest as _;
    let mut hasher = sha2::Sha256::new();
    let mut buf = vec![0u8; (1 << 20).min(len)];
    let mut gzip = false;
    let mut at = 0;
    while at < len {
        let n = buf.len().min(len - at);
        features::read_at(file, &mut buf[..n], at as u64)
            .map_err(|e| format!("it cannot be read: {e}"))?;
        if at == 0 {
            gzip = buf[..n].starts_with(&[0x1f, 0x8b]);
        }
        hasher.update(&buf[..n]);
        at += n;
    }
    Ok((super::catalog::digest_hex(&hasher.finalize()), gzip))
}

/// Refuses gzip data that decompressed to more than [`MAX_GZIP_FEATURES_BYTES`].
fn check_gunzipped(out: &[u8]) -> Result<(), String> {
    if out.len() as u64 > MAX_GZIP_FEATURES_BYTES {
        return Err(format!(
            "it holds more than {} MiB once decompressed, the most holoc decompresses (into \
             memory); decompress it (`gunzip`): an uncompressed feature file is read from disk, \
             up to {} GiB",
            MAX_GZIP_FEATURES_BYTES >> 20,
            MAX_FEATURES_BYTES >> 30
        ));
    }
    Ok(())
}

/// Reads the bytes of a pickled feature file (gzip allowed) with the arrays `keys` (the first
/// required): every shape checked against the bytes present before any row is looked at.
fn features_of_bytes(bytes: Vec<u8>, keys: &[&str]) -> Result<FeatureFile, String> {
    let sha256 = super::sha256_hex(&bytes);
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        use std::io::Read as _;
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(&bytes[..])
            .take(MAX_GZIP_FEATURES_BYTES + 1)
            .read_to_end(&mut out)
            .map_err(|e| format!("bad gzip data: {e}"))?;
        check_gunzipped(&out)?;
        out
    } else {
        bytes
    };
    let bytes = Arc::new(bytes);
    let pickle = pickle::Pickle::read(&bytes).map_err(|e| format!("not a readable pickle: {e}"))?;
    features_of_pickle(&Backing::Read(Arc::clone(&bytes)), &pickle, keys, sha256)
}

/// The arrays `keys` (the first required) and the `uids` of a read pickle whose bytes are
/// `backing`: every shape checked against the bytes present before any row is looked at.
fn features_of_pickle(
    backing: &Backing,
    pickle: &pickle::Pickle<'_>,
    keys: &[&str],
    sha256: String,
) -> Result<FeatureFile, String> {
    let uids = pickle.strings("uids")?.ok_or("it has no `uids`")?;
    let mut arrays = Vec::new();
    for (i, key) in keys.iter().enumerate() {
        match pickle.f16_array(key)? {
            Some(array) => {
                let rows = FeatureRows::new(backing, array).map_err(|e| format!("`{key}`: {e}"))?;
                if rows.len() != uids.len() {
                    return Err(format!("`{key}` has {} rows for {} uids", rows.len(), uids.len()));
                }
                arrays.push(((*key).to_string(), rows));
            }
            None if i == 0 => return Err(format!("it has no `{key}`")),
            None => {}
        }
    }
    Ok(FeatureFile { uids, arrays, sha256 })
}

fn feature_path(root: &Path, name: &str) -> Option<PathBuf> {
    [format!("{name}.pkl"), format!("{name}.pkl.gz")]
        .iter()
        .map(|n| root.join("features").join(n))
        .find(|p| present(p))
}

/// Why a folder's annotations cannot be used.
enum Unusable {
    /// They cannot be read (E0403).
    Unreadable(Box<Diagnostic>),
    /// Their text is not JSON (E0403, pointing into the text).
    NotJson(String, serde_json::Error),
}

/// Reads the folder's files: the annotations parsed, the feature files decoded.
fn read_folder(files: &stored::FolderFiles, source: usize) -> Result<stored::FolderRead, Unusable> {
    let name = files.annotations.display().to_string();
    // The annotations first (the feature files give each parsed asset its rows), the two
    // feature files' bytes read and hashed meanwhile.
    let (annotations, (clip, sbert)) = rayon::join(
        || {
            let bytes = crate::source::read_input(&files.annotations, super::MAX_CATALOG_BYTES)
                .map_err(|e| e.to_string())?;
            let sha = super::sha256_hex(&bytes);
            super::catalog::catalog_text_owned(bytes).map(|text| (text, sha))
        },
        || {
            rayon::join(
                || {
                    files
                        .clip
                        .as_ref()
                        .map(|p| read_features(p, &["img_features", "text_features"]))
                },
                || files.sbert.as_ref().map(|p| read_features(p, &["text_features"])),
            )
        },
    );
    let (text, annotations_sha256) = annotations.map_err(|message| {
        Unusable::Unreadable(Box::new(super::catalog::unreadable(&name, &message).with_help(
            "check the annotations of the folder given to `--objathor` (download them again \
             with objathor's script if they are damaged)",
        )))
    })?;
    let (parsed, problems) = match parse(&text, source) {
        Ok(found) => found,
        Err(e) => return Err(Unusable::NotJson(text, e)),
    };
    let rows = |file: Option<Result<FeatureFile, String>>| {
        file.map(|found| {
            found.map(|file| {
                let mut row_of: HashMap<&str, u32> = HashMap::with_capacity(file.uids.len());
                for (r, uid) in file.uids.iter().enumerate() {
                    row_of.insert(uid.as_str(), u32::try_from(r).unwrap_or(u32::MAX));
                }
                let rows_of = parsed
                    .iter()
                    .map(|(a, _)| row_of.get(&*a.id).copied().unwrap_or(u32::MAX))
                    .collect();
                stored::ReadFeatures { sha256: file.sha256, rows_of, arrays: file.arrays }
            })
        })
    };
    let (clip, sbert) = (rows(clip), rows(sbert));
    Ok(stored::FolderRead { annotations_sha256, text: Some(text), parsed, problems, clip, sbert })
}

/// Loads the version folder `options` names into `catalog` (after every other catalog),
/// adding the annotations' text to `sources` where a diagnostic points into it. The folder is
/// read from its index ([`stored`]) when one holds for its files, else read and indexed.
/// Returns the diagnostics: E0404 for a folder that cannot be used, E0403/W0402 for the
/// annotations as for any catalog, W0405 for feature files that cannot be used, E0405 for a
/// scoring mode that cannot run, W0407 for an index that could not be written.
pub fn load(
    options: &ObjathorOptions,
    catalog: &mut Catalog,
    sources: &mut SourceMap,
) -> Vec<Diagnostic> {
    let (root, annotations_path) = match version_folder(options) {
        Ok(found) => found,
        Err(d) => return vec![*d],
    };
    let version =
        root.file_name().map_or_else(|| "unknown".into(), |n| n.to_string_lossy().into_owned());
    let files = stored::FolderFiles {
        annotations: annotations_path,
        clip: feature_path(&root, "clip_features"),
        sbert: feature_path(&root, "sbert_features"),
    };
    let source = catalog.sources().len();
    let mut late = Vec::new();
    let mut index = None;
    let mut from_index = false;
    let found = if options.no_index { None } else { stored::open(&root, &version, &files) };
    let read = match found {
        Some((mut read, path)) => {
            for (asset, _) in &mut read.parsed {
                asset.source = source;
            }
            index = Some(path);
            from_index = true;
            read
        }
        None => {
            let read = match read_folder(&files, source) {
                Ok(read) => read,
                Err(Unusable::Unreadable(d)) => return vec![*d],
                Err(Unusable::NotJson(text, e)) => {
                    let file = sources.add(files.annotations.display().to_string(), text);
                    return vec![super::catalog::json_error(&sources.get(file).text, file, &e)];
                }
            };
            if !options.no_index {
                match stored::write(&root, &version, &files, &read) {
                    Ok(path) => index = Some(path),
                    Err(why) => late.push(
                        Diagnostic::new(
                            Code::W0407,
                            "the objathor folder's index could not be written; every build reads the folder again",
                        )
                        .with_note(why)
                        .with_help(
                            "make the folder writable, or set `HOLOC_CACHE_DIR` to a folder holoc may write",
                        ),
                    ),
                }
            }
            read
        }
    };
    let mut diags =
        install(read, (root, version, index, from_index), &files, options, catalog, sources);
    diags.extend(late);
    diags
}

/// Puts what was read of the folder `root` (its version, the index it came from or went to)
/// into `catalog`: its assets after all others, their entries and feature rows, the scoring
/// mode in force.
fn install(
    read: stored::FolderRead,
    (root, version, index_file, from_index): (PathBuf, String, Option<PathBuf>, bool),
    files: &stored::FolderFiles,
    options: &ObjathorOptions,
    catalog: &mut Catalog,
    sources: &mut SourceMap,
) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    let name = files.annotations.display().to_string();
    let source = catalog.sources().len();
    let stored::FolderRead { annotations_sha256, text, parsed, problems, clip, sbert } = read;
    if let Some(text) = text.filter(|_| !problems.is_empty()) {
        let file = sources.add(name.clone(), text);
        diags.extend(problem_diagnostics(&problems, file));
    }
    let mut files_read = vec![(name.clone(), annotations_sha256.clone())];
    let (start, end, entries, kept) = catalog.append_objathor(
        parsed,
        CatalogSource {
            name: "objathor".into(),
            version: Some(version.clone()),
            sha256: annotations_sha256,
            path: Some(name),
            n_assets: 0,
        },
    );
    let rows_of = |rows: &[u32]| -> Vec<u32> {
        kept.iter().map(|&i| rows.get(i).copied().unwrap_or(u32::MAX)).collect()
    };
    let mut features = Features::default();
    match (&files.clip, clip) {
        (Some(path), Some(Ok(file))) => {
            features.clip_row = rows_of(&file.rows_of);
            for (key, rows) in file.arrays {
                if key == "img_features" {
                    features.img = Some(rows);
                } else {
                    features.text = Some(rows);
                }
            }
            files_read.push((path.display().to_string(), file.sha256));
        }
        (Some(path), Some(Err(why))) => diags.push(features_warning(path, &why)),
        _ => diags.push(features_warning(
            &root.join("features").join("clip_features.pkl"),
            "there is no such file",
        )),
    }
    match (&files.sbert, sbert) {
        (Some(path), Some(Ok(file))) => {
            features.sbert_row = rows_of(&file.rows_of);
            features.sbert = file.arrays.into_iter().next().map(|(_, rows)| rows);
            files_read.push((path.display().to_string(), file.sha256));
        }
        (Some(path), Some(Err(why))) => diags.push(features_warning(path, &why)),
        _ => {}
    }
    let dims: Vec<usize> =
        [&features.img, &features.text].iter().filter_map(|r| r.as_ref().map(|r| r.dim)).collect();
    if dims.windows(2).any(|w| w[0] != w[1]) {
        diags.push(features_warning(
            files.clip.as_deref().unwrap_or(&root),
            "its image and text features have different lengths",
        ));
        features.img = None;
        features.text = None;
    }
    let has_clip = features.img.is_some();
    let asked = options.scoring.or(options.clip.as_ref().map(|_| Scoring::Clip));
    if let (Some(dir), Some(s)) = (&options.clip, options.scoring.filter(|s| *s != Scoring::Clip)) {
        diags.push(
            Diagnostic::new(
                Code::W0408,
                format!("the CLIP text tower is not used: the scoring mode is `{}`", s.as_str()),
            )
            .with_note(format!("`--objathor-clip {}` was given", dir.display()))
            .with_help("drop `--objathor-scoring` (a tower makes the mode `clip`), or drop `--objathor-clip`"),
        );
    }
    #[cfg(feature = "clip")]
    let mut tower = None;
    let scoring = match asked {
        Some(Scoring::Clip) if !has_clip => {
            diags.push(
                Diagnostic::new(
                    Code::E0405,
                    "the scoring mode `clip` needs the folder's CLIP image features, which are not usable",
                )
                .with_note(format!("looked for `{}`", root.join("features").join("clip_features.pkl").display()))
                .with_help("download the features, or use `--objathor-scoring lexical`"),
            );
            Scoring::Lexical
        }
        #[cfg(not(feature = "clip"))]
        Some(Scoring::Clip) => {
            diags.push(
                Diagnostic::new(
                    Code::E0405,
                    "the scoring mode `clip` is not available in this build of holoc",
                )
                .with_note(
                    "it runs CLIP's ViT-L-14 text tower in process, which this build leaves out (cargo feature `clip`)",
                )
                .with_help("build holoc with `--features clip`, or use `--objathor-scoring features` (the stored CLIP rows, no model) or `lexical`"),
            );
            Scoring::Lexical
        }
        #[cfg(feature = "clip")]
        Some(Scoring::Clip) => {
            let dim = features.img.as_ref().map_or(0, |r| r.dim);
            match clip_tower(options.clip.as_deref(), dim) {
                Ok(t) => {
                    tower = Some(t);
                    Scoring::Clip
                }
                Err(d) => {
                    diags.push(*d);
                    Scoring::Lexical
                }
            }
        }
        Some(Scoring::Features) if !has_clip => {
            diags.push(
                Diagnostic::new(
                    Code::E0405,
                    "the scoring mode `features` needs the folder's CLIP features, which are not usable",
                )
                .with_note(format!("looked for `{}`", root.join("features").join("clip_features.pkl").display()))
                .with_help("download the features, or use `--objathor-scoring lexical`"),
            );
            Scoring::Lexical
        }
        Some(s) => s,
        None if has_clip => Scoring::Features,
        None => Scoring::Lexical,
    };
    let assets_dir = Some(root.join("assets")).filter(|p| p.is_dir());
    let fetched = is_web_version(&version)
        || assets_dir
            .as_ref()
            .is_some_and(|d| std::fs::read_dir(d).map_or(true, |mut e| e.next().is_none()));
    let index = TextIndex::build(&catalog.assets()[start..end]);
    let mut synset_members: HashMap<String, Vec<usize>> = HashMap::new();
    for (k, e) in entries.iter().enumerate() {
        if let Some(synset) = &e.synset {
            synset_members.entry(synset.clone()).or_default().push(k);
        }
    }
    catalog.set_objathor(Objathor {
        root,
        version,
        source,
        start,
        end,
        entries,
        features: has_clip.then(|| Arc::new(features)),
        assets_dir,
        fetched,
        scoring,
        scoring_asked: options.scoring,
        mix: options.mix,
        pick: options.pick,
        files: files_read,
        index,
        synset_members,
        index_file,
        from_index,
        #[cfg(feature = "clip")]
        tower,
    });
    diags
}

/// The help of the clip mode's diagnostics: where the weights come from.
#[cfg(feature = "clip")]
const CLIP_WEIGHTS_HELP: &str = "point `--objathor-clip` at a folder with Hugging Face's `model.safetensors`, `config.json`, `vocab.json` and `merges.txt` of `laion/CLIP-ViT-L-14-laion2B-s32B-b82K` (the original's open_clip ViT-L-14 laion2b_s32b_b82k)";

/// The text towers loaded in this process, by folder and the weights file's length and time:
/// the language server and `holoc batch` load one once.
#[cfg(feature = "clip")]
type TowerCache =
    std::sync::Mutex<HashMap<(PathBuf, u64, Option<std::time::SystemTime>), Arc<clip::TextTower>>>;

/// The text tower of the weights folder `dir`, checked against the folder's CLIP rows of
/// length `dim`: E0406 without a folder, E0407 for weights and E0408 for tokenizer files that
/// cannot be used, E0409 for a tower whose embeddings are not of the rows' length.
#[cfg(feature = "clip")]
fn clip_tower(dir: Option<&Path>, dim: usize) -> Result<Arc<clip::TextTower>, Box<Diagnostic>> {
    static TOWERS: std::sync::OnceLock<TowerCache> = std::sync::OnceLock::new();
    let Some(dir) = dir else {
        return Err(Box::new(
            Diagnostic::new(
                Code::E0406,
                "the scoring mode `clip` needs CLIP's text tower, and no weights were given",
            )
            .with_note("the original embeds each query with open_clip ViT-L-14 (laion2b_s32b_b82k)")
            .with_help(CLIP_WEIGHTS_HELP),
        ));
    };
    let meta = std::fs::metadata(dir.join(clip::WEIGHTS_FILE)).ok();
    let key = (
        dir.to_path_buf(),
        meta.as_ref().map_or(0, std::fs::Metadata::len),
        meta.as_ref().and_then(|m| m.modified().ok()),
    );
    let cache = TOWERS.get_or_init(TowerCache::default);
    let cached = cache.lock().ok().and_then(|c| c.get(&key).cloned());
    let tower = match cached {
        Some(t) => t,
        None => {
            let t = Arc::new(clip::TextTower::load(dir).map_err(|e| {
                Box::new(match e {
                    clip::LoadError::Weights(path, why) => Diagnostic::new(
                        Code::E0407,
                        format!(
                            "the CLIP text tower's weights `{}` cannot be used: {why}",
                            path.display()
                        ),
                    )
                    .with_help(CLIP_WEIGHTS_HELP),
                    clip::LoadError::Tokenizer(path, why) => Diagnostic::new(
                        Code::E0408,
                        format!("the CLIP tokenizer `{}` cannot be used: {why}", path.display()),
                    )
                    .with_help(CLIP_WEIGHTS_HELP),
                })
            })?);
            if let Ok(mut c) = cache.lock() {
                c.insert(key, t.clone());
            }
            t
        }
    };
    if tower.config.projection != dim {
        return Err(Box::new(
            Diagnostic::new(
                Code::E0409,
                format!(
                    "the CLIP text tower makes embeddings of {} numbers, the folder's CLIP rows have {dim}",
                    tower.config.projection
                ),
            )
            .with_note(format!("the tower of `{}`", dir.display()))
            .with_help("the tower must be the model the folder's features were made with: ViT-L-14 (768) for objathor"),
        ));
    }
    Ok(tower)
}

/// The assets and entries of an annotations text (an object keyed by uid) and its unusable
/// entries; the JSON error when it is not an object of entries.
///
/// The entries are read one at a time as the parser meets them (each a `serde_json::Value`
/// only while it is read), never as one tree of the whole file: 512 MiB of annotations, the
/// most holoc reads, would otherwise take several times their size in memory.
fn parse(
    text: &str,
    source: usize,
) -> Result<(Vec<(Asset, Entry)>, stored::Problems), serde_json::Error> {
    use serde::de::DeserializeSeed as _;
    let mut entries =
        Entries { text, source, cursor: 0, out: Vec::new(), problems: stored::Problems::default() };
    let mut de = serde_json::Deserializer::from_str(text);
    (&mut entries).deserialize(&mut de)?;
    de.end()?;
    Ok((entries.out, entries.problems))
}

/// What [`parse`] has read so far.
struct Entries<'t> {
    text: &'t str,
    source: usize,
    cursor: usize,
    out: Vec<(Asset, Entry)>,
    problems: stored::Problems,
}

impl Entries<'_> {
    fn entry(&mut self, uid: String, value: &serde_json::Value) {
        let span = super::catalog::key_span(self.text, FileId(0), &uid, &mut self.cursor);
        match annotations::read_entry(&uid, value, self.source) {
            Ok(pair) => self.out.push(pair),
            // Past the first few, unusable entries are counted by reason in one warning.
            Err(why) if self.problems.shown.len() < MAX_ENTRY_WARNINGS => {
                let range = span.range();
                self.problems.shown.push((uid, why, (range.start, range.end)));
            }
            Err(why) => self.problems.more.entry(why).or_insert((0, uid)).0 += 1,
        }
    }
}

impl<'de> serde::de::DeserializeSeed<'de> for &mut Entries<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> serde::de::Visitor<'de> for &mut Entries<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        // The words of a catalog's reading (`catalog::parse_catalog`).
        f.write_str("a JSON object")
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        while let Some((uid, value)) = map.next_entry::<String, serde_json::Value>()? {
            self.entry(uid, &value);
        }
        Ok(())
    }
}

/// The warnings of the unusable entries, pointing into the annotations `file`.
fn problem_diagnostics(problems: &stored::Problems, file: FileId) -> Vec<Diagnostic> {
    let mut diags: Vec<Diagnostic> = problems
        .shown
        .iter()
        .map(|(uid, why, (a, b))| {
            super::catalog::bad_entry(file, Span::new(file, *a, *b), uid, why)
        })
        .collect();
    if !problems.more.is_empty() {
        let n: usize = problems.more.values().map(|(k, _)| k).sum();
        let mut d = Diagnostic::new(
            Code::W0402,
            format!(
                "{n} more objathor entr{} skipped (after the {MAX_ENTRY_WARNINGS} above)",
                if n == 1 { "y is" } else { "ies are" }
            ),
        );
        for (why, (k, first)) in &problems.more {
            d = d.with_note(format!("{k} × {why} (the first: `{first}`)"));
        }
        diags.push(d.with_help(
            "the rest of the folder is loaded; download the annotations again if they are damaged",
        ));
    }
    diags
}

/// How many unusable annotation entries get a warning of their own; the rest are counted in one.
pub const MAX_ENTRY_WARNINGS: usize = 10;

/// Reads an annotations file's bytes (gzip allowed) as [`load`] does, without a folder: the
/// number of assets read and the diagnostics. For the fuzz harness and tools.
pub fn read_annotations(bytes: &[u8], sources: &mut SourceMap) -> (usize, Vec<Diagnostic>) {
    let text = match super::catalog::catalog_text(bytes) {
        Ok(text) => text,
        Err(message) => return (0, vec![super::catalog::unreadable("annotations", &message)]),
    };
    match parse(&text, 0) {
        Ok((parsed, problems)) => {
            let file = sources.add("annotations.json", text);
            (parsed.len(), problem_diagnostics(&problems, file))
        }
        Err(e) => {
            let file = sources.add("annotations.json", text);
            (0, vec![super::catalog::json_error(&sources.get(file).text, file, &e)])
        }
    }
}

/// Reads a feature file's bytes (gzip allowed) as [`load`] does (the CLIP keys, then the SBERT
/// key when the CLIP ones are absent) and decodes every vector of every array it keeps,
/// measuring each against a unit query: the number of vectors. For the fuzz harness.
///
/// # Errors
/// Why the file is not used (what [`load`] reports as W0405).
pub fn read_feature_bytes(bytes: Vec<u8>) -> Result<usize, String> {
    let file = features_of_bytes(bytes.clone(), &["img_features", "text_features"])
        .or_else(|_| features_of_bytes(bytes, &["text_features"]))?;
    let mut n = 0;
    for (_, rows) in &file.arrays {
        let mut q = vec![0f32; rows.dim];
        q[0] = 1.0;
        let mut v = vec![0f32; rows.dim];
        for row in 0..rows.len() {
            for view in 0..rows.views {
                rows.decode(row, view, &mut v);
                let _ = rows.cosine(&q, row, view);
                n += 1;
            }
            let mut sum = vec![0f32; rows.dim];
            rows.add_unit_mean(row, &mut sum);
        }
    }
    Ok(n)
}

/// The least `blender_thor_similarity` an asset may have (the original's
/// `blender_thor_similarity_threshold`): below it the asset looks different in AI2-THOR than in
/// the renders its features come from, and is never a candidate. A missing value counts as 1.
pub const MIN_BLENDER_THOR_SIMILARITY: f64 = 0.6;

/// Whether the folder's asset at catalog index `idx` looks in AI2-THOR as in its renders.
fn looks_alike(obj: &Objathor, idx: usize) -> bool {
    obj.entry(idx).and_then(|e| e.blender_thor_similarity).unwrap_or(1.0)
        >= MIN_BLENDER_THOR_SIMILARITY
}

/// At most how many assets that share a WordNet synset with the seeds (and no word with the
/// request) are scored besides the lexical candidates.
pub const SYNSET_POOL: usize = 512;

/// The parts of a `features` score: `clip + sbert − 10 × size`.
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureScore {
    /// `100 × max over views cos(pseudo-query, image view)`.
    pub clip: f64,
    /// `cos(SBERT pseudo-query, SBERT row)`, when the folder has SBERT features.
    pub sbert: Option<f64>,
    /// The threshold the CLIP part must pass (only when `text_space`).
    pub threshold: f64,
    /// The candidate's lexical score (what `--objathor-mix score` compares).
    pub lexical_score: f64,
    /// Whether the pseudo-query is in CLIP's text space (made of the folder's text rows), so
    /// that the CLIP part is comparable with the original's thresholds. Without text rows it is
    /// an image-to-image cosine (74–100 for anything alike): it only orders candidates, and
    /// whether one is good enough is decided by its words.
    pub text_space: bool,
}

/// The unit mean of the vectors `rows` gives for `picks`, skipping `skip`; `None` when nothing
/// is left.
fn unit_mean(
    rows: &features::FeatureRows,
    picks: &[(usize, usize)],
    skip: Option<usize>,
) -> Option<Vec<f32>> {
    let mut q = vec![0f32; rows.dim];
    let mut v = vec![0f32; rows.dim];
    let mut any = false;
    for &(k, row) in picks {
        if Some(k) == skip {
            continue;
        }
        rows.decode(row, 0, &mut v);
        features::normalize(&mut v);
        for (s, x) in q.iter_mut().zip(&v) {
            *s += x;
        }
        any = true;
    }
    features::normalize(&mut q);
    any.then_some(q)
}

/// Ranks the folder's assets for `query`. Lexically (the best `limit` by words and size), then,
/// in the `features` mode, by their CLIP rows against a pseudo-query made of the best
/// [`SEED_MATCHES`] lexical matches:
/// - with CLIP text rows, the pseudo-query is their unit mean (CLIP's text space, where the
///   original's query lives); besides the lexical candidates, the assets the annotations put
///   under a seed's WordNet synset or its near synsets are scored too (at most
///   [`SYNSET_POOL`]: a `looking glass` under `mirror.n.01` for a `mirror`), and the CLIP part
///   must pass the original's threshold (an asset found by its synset alone is kept only then);
/// - with image rows only, the pseudo-query is the seeds' view-averaged image rows: the CLIP part
///   orders the lexical candidates but is never held against a threshold (see
///   [`FeatureScore::text_space`]).
///
/// The SBERT part of a seed is taken against the other seeds' rows (a seed would otherwise
/// score 1.0 against itself); a lone seed gets the best SBERT part of the other candidates.
/// Assets whose `blender_thor_similarity` is below [`MIN_BLENDER_THOR_SIMILARITY`] are never
/// candidates. Best first; ties by the seed.
pub fn rank(catalog: &Catalog, query: &Query, seed: u64, limit: usize) -> Vec<Candidate> {
    let Some(obj) = catalog.objathor() else { return Vec::new() };
    let mut lexical = super::index::rank_in(catalog, &obj.index, obj.start, query, seed, limit);
    lexical.retain(|c| looks_alike(obj, c.idx));
    #[cfg(feature = "clip")]
    if let (Some(tower), Some(features), Scoring::Clip) = (&obj.tower, &obj.features, obj.scoring) {
        if let Some(ranked) =
            clip_rank(catalog, obj, (&**tower, &**features), query, seed, &lexical)
        {
            return ranked;
        }
    }
    let (Some(features), Scoring::Features) = (&obj.features, obj.scoring) else {
        return lexical;
    };
    let Some(img) = &features.img else { return lexical };
    // The seeds: the best good matches with a CLIP row, as (asset of the folder, row).
    let seeds: Vec<(usize, usize)> = lexical
        .iter()
        .filter(|c| c.is_good_enough())
        .filter_map(|c| features.clip_row_of(c.idx - obj.start).map(|r| (c.idx - obj.start, r)))
        .take(SEED_MATCHES)
        .collect();
    if seeds.is_empty() {
        // Nothing the words name well enough: nothing is good enough.
        return lexical;
    }
    let text_space = features.text.is_some();
    let q = match &features.text {
        Some(text) => unit_mean(text, &seeds, None),
        None => {
            let mut q = vec![0f32; img.dim];
            for &(_, row) in &seeds {
                img.add_unit_mean(row, &mut q);
            }
            features::normalize(&mut q);
            Some(q)
        }
    };
    let Some(q) = q else { return lexical };

    let mut pool = lexical;
    // Assets found by their WordNet synset alone: kept only when their CLIP part passes.
    let mut wordless = std::collections::HashSet::new();
    if text_space {
        let taken: std::collections::HashSet<usize> = pool.iter().map(|c| c.idx).collect();
        let mut mates: Vec<usize> = Vec::new();
        for &(k, _) in &seeds {
            let Some(entry) = obj.entries.get(k) else { continue };
            let synsets = entry.synset.iter().chain(entry.near_synsets.iter().map(|(s, _)| s));
            for synset in synsets {
                mates.extend(obj.synset_members.get(synset.as_str()).into_iter().flatten());
            }
        }
        mates.sort_unstable();
        mates.dedup();
        for k in mates.into_iter().take(SYNSET_POOL) {
            if taken.contains(&(obj.start + k)) || !looks_alike(obj, obj.start + k) {
                continue;
            }
            if let Some(c) =
                super::index::wordless_candidate(catalog, &obj.index, obj.start, k, query, seed)
            {
                wordless.insert(c.idx);
                pool.push(c);
            }
        }
    }

    // SBERT pseudo-queries: all seeds, and each seed without itself.
    let sbert_seeds: Vec<(usize, usize)> = features
        .sbert
        .as_ref()
        .map(|_| {
            seeds.iter().filter_map(|&(k, _)| features.sbert_row_of(k).map(|r| (k, r))).collect()
        })
        .unwrap_or_default();
    let sbert_all = features.sbert.as_ref().and_then(|rows| unit_mean(rows, &sbert_seeds, None));
    let sbert_part = |k: usize| -> Option<Option<f64>> {
        let rows = features.sbert.as_ref()?;
        let row = features.sbert_row_of(k)?;
        let is_seed = sbert_seeds.iter().any(|s| s.0 == k);
        let q = if is_seed { unit_mean(rows, &sbert_seeds, Some(k)) } else { sbert_all.clone() };
        // `Some(None)`: a lone seed, given the others' best below.
        Some(q.map(|q| f64::from(rows.cosine(&q, row, 0))))
    };
    let threshold = clip_threshold(query.kind.unwrap_or(PlacementKind::Floor));
    let mut scored: Vec<(Candidate, f64, Option<Option<f64>>)> = pool
        .into_iter()
        .filter_map(|c| {
            let k = c.idx - obj.start;
            let row = features.clip_row_of(k)?;
            let clip = 100.0 * f64::from(img.max_cosine(&q, row));
            let sbert = sbert_part(k);
            Some((c, clip, sbert))
        })
        .collect();
    let best_other = scored
        .iter()
        .filter_map(|(_, _, s)| s.flatten())
        .filter(|x| !x.is_nan())
        .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))));
    let mut out: Vec<Candidate> = scored
        .drain(..)
        .map(|(c, clip, sbert)| {
            let sbert = match sbert {
                Some(Some(x)) => Some(x),
                Some(None) => best_other,
                None => None,
            };
            let score = clip + sbert.unwrap_or(0.0) - SIZE_WEIGHT * c.size_diff_m.unwrap_or(0.0);
            Candidate {
                features: Some(FeatureScore {
                    clip,
                    sbert,
                    threshold,
                    lexical_score: c.score,
                    text_space,
                }),
                score,
                ..c
            }
        })
        .filter(|c: &Candidate| !wordless.contains(&c.idx) || c.is_good_enough())
        .collect();
    out.sort_by(|a, b| {
        b.score
            .total_cmp(&a.score)
            .then(a.tie.cmp(&b.tie))
            .then_with(|| a.asset_id.cmp(&b.asset_id))
    });
    out
}

/// The text the original embeds for a query (`objaverse_retriever.py`'s callers): `a 3D model
/// of <key>, <description>` for floor and wall objects, `a 3D model of <object name>` for small
/// objects, `a 3D model of <description>` for ceiling objects (the object's name where there is
/// no description).
pub fn clip_query_text(query: &Query) -> String {
    let description = query.description.as_deref().map(str::trim).filter(|d| !d.is_empty());
    match (query.kind, description) {
        (Some(PlacementKind::OnObject), _) | (_, None) => {
            format!("a 3D model of {}", query.category)
        }
        (Some(PlacementKind::Ceiling), Some(d)) => format!("a 3D model of {d}"),
        (_, Some(d)) => format!("a 3D model of {}, {d}", query.category),
    }
}

/// The `clip` mode: the original's `retrieve` then its size re-ranking. The query
/// ([`clip_query_text`]) is embedded by the text tower; every asset of the folder that may be
/// placed as asked and looks alike in AI2-THOR gets `clip = 100 × max over views cos(query,
/// view)`; those with `clip` above the placement's threshold are kept, scored `clip − 10 ×
/// size difference` (the SBERT part is left out: holoc has no SBERT model, see the book), best
/// first, ties by the seed. `None` when the tower fails (then the lexical ranking stands).
#[cfg(feature = "clip")]
fn clip_rank(
    catalog: &Catalog,
    obj: &Objathor,
    (tower, features): (&clip::TextTower, &Features),
    query: &Query,
    seed: u64,
    lexical: &[Candidate],
) -> Option<Vec<Candidate>> {
    use rayon::prelude::*;
    let img = features.img.as_ref()?;
    let q = tower.embed(&clip_query_text(query)).ok()?;
    let threshold = clip_threshold(query.kind.unwrap_or(PlacementKind::Floor));
    let n = obj.end - obj.start;
    // Every asset's CLIP part, in parallel (each is its own; the order does not depend on it).
    let clip: Vec<Option<f64>> = (0..n)
        .into_par_iter()
        .map(|k| {
            if !super::index::allows(&obj.index, k, query.kind) || !looks_alike(obj, obj.start + k)
            {
                return None;
            }
            let row = features.clip_row_of(k)?;
            Some(100.0 * f64::from(img.max_cosine(&q, row)))
        })
        .collect();
    let lexical_scores: HashMap<usize, f64> = lexical.iter().map(|c| (c.idx, c.score)).collect();
    let mut out: Vec<Candidate> = clip
        .iter()
        .enumerate()
        .filter_map(|(k, clip)| {
            let clip = clip.filter(|c| *c > threshold)?;
            let c =
                super::index::wordless_candidate(catalog, &obj.index, obj.start, k, query, seed)?;
            let lexical_score = lexical_scores.get(&c.idx).copied().unwrap_or(c.score);
            Some(Candidate {
                features: Some(FeatureScore {
                    clip,
                    sbert: None,
                    threshold,
                    lexical_score,
                    text_space: true,
                }),
                score: clip - SIZE_WEIGHT * c.size_diff_m.unwrap_or(0.0),
                ..c
            })
        })
        .collect();
    out.sort_by(|a, b| {
        b.score
            .total_cmp(&a.score)
            .then(a.tie.cmp(&b.tie))
            .then_with(|| a.asset_id.cmp(&b.asset_id))
    });
    Some(out)
}

/// Whether an objathor asset fits the room as the original asks: each side at most 0.8 of the
/// room's (longer with longer, shorter with shorter, height with the wall's), the footprint at
/// most half the floor's box, and a wall object no deeper than 3 × its smaller other side.
/// `room` is `[long side, short side, wall height]` in metres.
pub fn fits_room(
    bbox_m: [f64; 3],
    kind: PlacementKind,
    room: [f64; 3],
) -> Result<(), &'static str> {
    if !matches!(kind, PlacementKind::Floor | PlacementKind::Wall) {
        return Ok(());
    }
    let [x, y, z] = bbox_m;
    let (long, short) = if x >= z { (x, z) } else { (z, x) };
    if long > 0.8 * room[0] + 1e-9 || short > 0.8 * room[1] + 1e-9 || y > 0.8 * room[2] + 1e-9 {
        return Err("a side is longer than 0.8 of the room's");
    }
    if long * short > 0.5 * room[0] * room[1] + 1e-9 {
        return Err("its footprint is more than half the floor");
    }
    if kind == PlacementKind::Wall && z > 3.0 * x.min(y) + 1e-9 {
        return Err("it is too deep for a wall object");
    }
    Ok(())
}

/// `e^x` for `x ≤ 0` with only additions, multiplications and divisions (the same bits on every
/// machine): a Taylor series at `x / 1024`, squared ten times.
fn exp_neg(x: f64) -> f64 {
    if x < -700.0 {
        return 0.0;
    }
    let y = x / 1024.0;
    let mut term = 1.0;
    let mut sum = 1.0;
    for k in 1..10 {
        term *= y / f64::from(k);
        sum += term;
    }
    for _ in 0..10 {
        sum *= sum;
    }
    sum
}

/// The order in which a seeded pick takes the good candidates: successive draws without
/// replacement from the softmax of the best `pool` scores (the original's `torch.multinomial`
/// over `softmax(scores)`, seeded), then the rest in rank order.
pub fn seeded_order(scores: &[f64], pool: usize, seed: u64, salt: &str) -> Vec<usize> {
    use rand::{Rng as _, SeedableRng as _};
    let n = scores.len().min(pool);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ fnv1a(salt));
    let mut left: Vec<usize> = (0..n).collect();
    let mut order = Vec::with_capacity(scores.len());
    while !left.is_empty() {
        let top = left.iter().map(|&i| scores[i]).fold(f64::NEG_INFINITY, f64::max);
        let weights: Vec<f64> = left.iter().map(|&i| exp_neg(scores[i] - top)).collect();
        let total: f64 = weights.iter().sum();
        let mut draw = rng.gen::<f64>() * total;
        let mut at = left.len() - 1;
        for (k, w) in weights.iter().enumerate() {
            if draw < *w {
                at = k;
                break;
            }
            draw -= w;
        }
        order.push(left.remove(at));
    }
    order.extend(n..scores.len());
    order
}

fn fnv1a(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The names an asset's model file may have in its folder, in the order the hook runner
/// tries them. A plain `.pkl` is not among them: the loader never reads one.
pub const MODEL_FILES: [&str; 5] = ["json", "json.gz", "msgpack", "msgpack.gz", "pkl.gz"];

/// The textures every asset folder must hold.
pub const TEXTURES: [&str; 2] = ["albedo.jpg", "normal.jpg"];

/// The texture the loader uses when present (`emissionTexturePath` is optional).
pub const OPTIONAL_TEXTURES: [&str; 1] = ["emission.jpg"];

/// What is missing of one asset's folder, in words; `None` when it is complete.
pub fn missing_on_disk(assets_dir: &Path, uid: &str) -> Option<String> {
    let folder = assets_dir.join(uid);
    if !folder.is_dir() {
        return Some(format!("there is no folder `{}`", folder.display()));
    }
    if !MODEL_FILES.iter().any(|ext| folder.join(format!("{uid}.{ext}")).is_file()) {
        if folder.join(format!("{uid}.pkl")).is_file() {
            return Some(format!(
                "`{}` has only `{uid}.pkl`, which the hook runner never reads (it reads \
                 `.pkl.gz`, `.json`, `.msgpack`): gzip it to `{uid}.pkl.gz`",
                folder.display()
            ));
        }
        return Some(format!(
            "`{}` has no `{uid}.pkl.gz` (nor `.json`, `.msgpack`)",
            folder.display()
        ));
    }
    let missing: Vec<&str> =
        TEXTURES.iter().copied().filter(|t| !folder.join(t).is_file()).collect();
    if missing.is_empty() {
        None
    } else {
        Some(format!("`{}` lacks {}", folder.display(), missing.join(", ")))
    }
}

/// The AI2-THOR commit Holodeck's `v2` branch (the web loader) runs.
pub const WEB_THOR_COMMIT: &str = "455cf72a1c8e0759a452422f2128fbc93a3cb06b";

/// The first version of the web-fetched generation (Holodeck's `v2` branch).
pub const FIRST_WEB_VERSION: &str = "2024_08_16";

/// Whether a version folder's name (a date, `YYYY_MM_DD`) is of the web-fetched generation.
pub fn is_web_version(version: &str) -> bool {
    let is_date = version.len() == 10
        && version.bytes().enumerate().all(|(i, b)| {
            if i == 4 || i == 7 {
                b == b'_'
            } else {
                b.is_ascii_digit()
            }
        });
    is_date && version >= FIRST_WEB_VERSION
}

/// Checks that every objathor asset of `asset_ids` is on disk where the hook runner looks:
/// with an `assets/` folder, each must have its folder, model file and textures (E0615 naming
/// it); without one, one warning that the assets are fetched when the house loads (W0614).
/// `span_of` gives where an id is written (a house file), when there is such a place.
pub fn check_on_disk<'a>(
    catalog: &Catalog,
    asset_ids: impl IntoIterator<Item = &'a str>,
    span_of: &dyn Fn(&str) -> Option<Span>,
) -> Vec<Diagnostic> {
    let Some(obj) = catalog.objathor() else { return Vec::new() };
    let mut uids: Vec<&str> = asset_ids
        .into_iter()
        .filter(|id| catalog.index_of(id).is_some_and(|i| obj.holds(i)))
        .collect();
    uids.sort_unstable();
    uids.dedup();
    if uids.is_empty() {
        return Vec::new();
    }
    let mut out = on_disk(obj, &uids, span_of);
    let unlicensed: Vec<&str> = uids
        .iter()
        .copied()
        .filter(|u| catalog.index_of(u).and_then(|i| obj.license(i)).is_none())
        .collect();
    if let Some(first) = unlicensed.first() {
        let n = unlicensed.len();
        out.push(
            Diagnostic::new(
                Code::W0406,
                format!(
                    "{n} objathor asset{} of the house {} no licence information: {} attribution{} \
                     {} empty",
                    if n == 1 { "" } else { "s" },
                    if n == 1 { "has" } else { "have" },
                    if n == 1 { "its" } else { "their" },
                    if n == 1 { "" } else { "s" },
                    if n == 1 { "is" } else { "are" },
                ),
            )
            .with_note(format!("for example `{first}`"))
            .with_help(format!(
                "download the folder's annotations again (`python -m \
                 objathor.dataset.download_annotations --version {}`), or pin assets whose \
                 licence you know",
                obj.version
            )),
        );
    }
    out
}

/// [`check_on_disk`] of the chosen assets `uids` (sorted, each once) of the folder.
fn on_disk(
    obj: &Objathor,
    uids: &[&str],
    span_of: &dyn Fn(&str) -> Option<Span>,
) -> Vec<Diagnostic> {
    let fetch_note = |n: usize, why: &str| {
        Diagnostic::new(
            Code::W0614,
            format!(
                "{n} objathor asset{} will be fetched when the house loads: {why}",
                if n == 1 { "" } else { "s" },
            ),
        )
    };
    let Some(dir) = obj.assets_dir.as_ref().filter(|_| !obj.fetched) else {
        let absent: Vec<&str> = match &obj.assets_dir {
            Some(dir) => {
                uids.iter().copied().filter(|u| missing_on_disk(dir, u).is_some()).collect()
            }
            None => uids.to_vec(),
        };
        let Some(first) = absent.first() else { return Vec::new() };
        let why = match (&obj.assets_dir, obj.fetched) {
            (Some(_), true) => format!(
                "`{}` is a web-fetched folder (version {}), whose `assets` folder fills as houses load",
                obj.root.display(),
                obj.version
            ),
            _ => format!("`{}` has no `assets` folder", obj.root.display()),
        };
        return vec![fetch_note(absent.len(), &why)
            .with_note(format!("for example `{first}`"))
            .with_help(format!(
                "load the house with `WebProceduralAssetHookRunner(asset_directory=…, \
                 target_dir=…)` (ai2thor commit {WEB_THOR_COMMIT}, Holodeck `v2`), or download \
                 the assets (`python -m objathor.dataset.download_assets --version {}`) and give \
                 that folder",
                obj.version
            ))];
    };
    uids.iter()
        .filter_map(|uid| {
            let why = missing_on_disk(dir, uid)?;
            let mut d =
                Diagnostic::new(Code::E0615, format!("the objathor asset `{uid}` is not on disk"))
                    .with_note(why)
                    .with_help(format!(
                        "download the folder's assets (`python -m objathor.dataset.download_assets \
                         --version {}`), or pin another asset than `{uid}`",
                        obj.version
                    ));
            if let Some(span) = span_of(uid) {
                d = d.with_primary(span, "chosen here");
            }
            Some(d)
        })
        .collect()
}

#[cfg(test)]
mod read_tests {
    use super::pickle::{f32_to_f16, write, NumpyModules, Value};
    use super::*;

    /// Every vector of every array of a feature file, decoded.
    fn vectors(file: &FeatureFile) -> Vec<(String, Vec<Vec<f32>>)> {
        file.arrays
            .iter()
            .map(|(key, rows)| {
                let mut out = Vec::new();
                for row in 0..rows.len() {
                    for view in 0..rows.views {
                        let mut v = vec![0f32; rows.dim];
                        rows.decode(row, view, &mut v);
                        out.push(v);
                    }
                }
                (key.clone(), out)
            })
            .collect()
    }

    fn pickles() -> Vec<(String, Vec<u8>)> {
        let uids: Vec<String> = (0..5).map(|i| format!("{i:032x}")).collect();
        let bits: Vec<u16> = (0..5 * 3 * 7).map(|i| f32_to_f16(i as f32 / 50.0 - 1.0)).collect();
        let values: Vec<f32> = (0..5 * 7).map(|i| i as f32 / 35.0 + 1e-4).collect();
        let mut out = Vec::new();
        for protocol in 2..=5 {
            for modules in [NumpyModules::Core, NumpyModules::UnderscoreCore] {
                let data = write(
                    &[
                        ("uids", Value::Strings(uids.clone())),
                        ("img_features", Value::F16 { shape: vec![5, 3, 7], bits: bits.clone() }),
                        ("text_features", Value::F32 { shape: vec![5, 7], values: values.clone() }),
                    ],
                    protocol,
                    modules,
                );
                out.push((format!("protocol {protocol} {modules:?}"), data));
            }
        }
        out
    }

    #[test]
    fn a_feature_file_read_from_disk_gives_the_rows_of_the_file_read_whole() {
        let dir = tempfile::tempdir().expect("scratch");
        for (what, data) in pickles() {
            let path = dir.path().join("clip_features.pkl");
            std::fs::write(&path, &data).expect("write");
            let keys = ["img_features", "text_features"];
            let whole = features_of_bytes(data.clone(), &keys).expect("reads whole");
            let streamed = read_features(&path, &keys).expect("reads from disk");
            // Protocol 2 writes the elements as latin-1 text, decoded into bytes of their own.
            assert_eq!(
                streamed.arrays.iter().all(|(_, r)| matches!(r.backing(), Backing::Stored(..))),
                !what.starts_with("protocol 2"),
                "{what}: the rows stay on disk"
            );
            assert_eq!(streamed.uids, whole.uids, "{what}");
            assert_eq!(streamed.sha256, whole.sha256, "{what}");
            assert_eq!(streamed.sha256, super::super::sha256_hex(&data), "{what}");
            assert_eq!(vectors(&streamed), vectors(&whole), "{what}");
            assert_eq!(streamed.arrays.len(), 2, "{what}");
            // What the index copies of them: the same bytes.
            for ((_, a), (_, b)) in streamed.arrays.iter().zip(&whole.arrays) {
                let (mut x, mut y) = (Vec::new(), Vec::new());
                a.write_raw(&mut x).expect("reads");
                b.write_raw(&mut y).expect("reads");
                assert_eq!(x, y, "{what}");
                assert_eq!(x.len(), a.raw_len(), "{what}");
            }
            // Gzip: decompressed into memory, the same rows.
            let gz = dir.path().join("clip_features.pkl.gz");
            let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
            std::io::Write::write_all(&mut enc, &data).expect("gzip");
            let packed = enc.finish().expect("gzip");
            std::fs::write(&gz, &packed).expect("write");
            let unpacked = read_features(&gz, &keys).expect("reads gzip");
            assert_eq!(unpacked.sha256, super::super::sha256_hex(&packed), "{what}");
            assert_eq!(vectors(&unpacked), vectors(&whole), "{what}");
        }
    }

    #[test]
    fn a_cut_or_overflowing_feature_file_on_disk_is_refused_as_when_read_whole() {
        let dir = tempfile::tempdir().expect("scratch");
        let path = dir.path().join("clip_features.pkl");
        let keys = ["img_features", "text_features"];
        for (what, data) in pickles() {
            for cut in [1, 7, data.len() / 2, data.len() - 1] {
                std::fs::write(&path, &data[..cut]).expect("write");
                let whole = features_of_bytes(data[..cut].to_vec(), &keys).err();
                let streamed = read_features(&path, &keys).err();
                assert!(streamed.is_some(), "{what}, cut at {cut}");
                assert_eq!(streamed, whole, "{what}, cut at {cut}");
            }
        }
        // A shape whose size wraps to zero bytes (issue 51, case 1).
        let uids: Vec<String> = (0..3).map(|i| format!("{i:032x}")).collect();
        for protocol in [4, 5] {
            let data = write(
                &[
                    ("uids", Value::Strings(uids.clone())),
                    ("img_features", Value::F16 { shape: vec![3, 1 << 62, 8], bits: Vec::new() }),
                ],
                protocol,
                NumpyModules::Core,
            );
            std::fs::write(&path, &data).expect("write");
            let why = read_features(&path, &keys).err().expect("refused");
            assert!(why.contains("holds more elements than any file can"), "{why}");
            assert_eq!(Some(why), features_of_bytes(data, &keys).err());
        }
    }
}
