//! The folder's index: what a load makes of an objathor version folder, written once so that
//! later builds do not read it again.
//!
//! Reading a 50,000-asset folder means decompressing and parsing some 100 MB of annotations,
//! hashing and decoding 400 MB of feature pickles: about a second of CPU and 700 MB each build.
//! The index holds the result: the annotations' assets and entries already parsed (a `postcard`
//! encoding of them, with the unusable entries' reasons), each asset's feature rows, the files'
//! SHA-256 for the catalog lock, and the feature arrays as plain rows, read one row at a time
//! where they lie in the file: a build reads only the rows its queries look at. (A memory map
//! was tried first: the kernel maps the pages around each one touched, so a build's few
//! thousand rows brought the whole 400 MB into its resident memory.)
//!
//! **Where**: `<folder>/.holoc-index/objathor.idx`, or, when the folder cannot be written, under
//! the user's cache folder (`$HOLOC_CACHE_DIR`, else `$XDG_CACHE_HOME/holoc`, else
//! `~/.cache/holoc`), in `objathor/<version>-<hash of the folder's path>.idx`.
//!
//! **When it holds**: the index records each file it was made from (its name in the folder,
//! length, modification time and inode) and the holoc release and format that wrote it. A
//! build whose files all stamp the same uses it; any other difference (a file replaced,
//! touched, added or removed, another holoc) reads the folder again and writes a new index.
//! The SHA-256 it hands the lock are those computed when it was written.
//!
//! **Layout**: a 64-byte prelude (`HOLOCOBJ`, the format, the header's place and length), the
//! sections (feature rows as they were in the pickles, float16 or float32 in their byte order,
//! each at a multiple of 64 bytes; the annotations' text when an entry was unusable, so its
//! warnings point into it as on the first build), then the header. The file is written to a
//! temporary file, synced and renamed: a reader sees the old index or the whole new one, and
//! the file a running build reads is never changed under it.

use std::io::{Seek as _, SeekFrom, Write as _};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::annotations::Entry;
use super::features::{Backing, FeatureRows};
use crate::resolve::catalog::Asset;

/// The index format; a holoc that reads the folder differently writes another number.
const FORMAT: u32 = 1;
const MAGIC: &[u8; 8] = b"HOLOCOBJ";
const PRELUDE: u64 = 64;
const ALIGN: u64 = 64;
/// The name of the index inside the folder's own index folder.
const FILE_NAME: &str = "objathor.idx";
/// How close to the stamps' time a file's modification time makes its stamp unable to vouch
/// for it: two seconds (the coarsest clock of the file systems holoc runs on).
const RACY_NS: u128 = 2_000_000_000;
/// The index folder made inside the version folder.
pub const FOLDER_NAME: &str = ".holoc-index";

/// The files of a version folder that a load reads.
#[derive(Clone, Debug)]
pub(crate) struct FolderFiles {
    /// `annotations.json.gz` (or `annotations.json`).
    pub annotations: PathBuf,
    /// `features/clip_features.pkl`, when present.
    pub clip: Option<PathBuf>,
    /// `features/sbert_features.pkl`, when present.
    pub sbert: Option<PathBuf>,
}

/// The unusable annotation entries: the first few with the place of their key, the rest
/// counted by reason (with the first uid of each).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Problems {
    /// `(uid, why, byte range of its key)`.
    pub shown: Vec<(String, String, (usize, usize))>,
    /// Why → (how many, the first uid).
    pub more: std::collections::BTreeMap<String, (usize, String)>,
}

impl Problems {
    pub fn is_empty(&self) -> bool {
        self.shown.is_empty() && self.more.is_empty()
    }
}

/// One feature file as a load uses it.
#[derive(Clone, Debug)]
pub(crate) struct ReadFeatures {
    /// SHA-256 of the file's bytes.
    pub sha256: String,
    /// Per parsed annotation entry: its row, or `u32::MAX`.
    pub rows_of: Vec<u32>,
    /// The arrays kept, by key (`img_features`, `text_features`).
    pub arrays: Vec<(String, FeatureRows)>,
}

/// What a load makes of a folder, read from its files or from its index.
#[derive(Clone, Debug)]
pub(crate) struct FolderRead {
    /// SHA-256 of the annotations file's bytes.
    pub annotations_sha256: String,
    /// The annotations' text, for the diagnostics that point into it (`None`: read from an
    /// index of a folder with no unusable entry, where nothing points into it).
    pub text: Option<String>,
    /// The assets and entries, in the file's order.
    pub parsed: Vec<(Asset, Entry)>,
    /// The unusable entries.
    pub problems: Problems,
    /// The CLIP feature file: its rows, or why it is not used.
    pub clip: Option<Result<ReadFeatures, String>>,
    /// The SBERT feature file.
    pub sbert: Option<Result<ReadFeatures, String>>,
}

/// Where a file was when the index was made.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Stamp {
    /// Its path relative to the folder.
    name: String,
    len: u64,
    /// Modification time, nanoseconds since 1970 (0 where the system has none).
    modified_ns: u128,
    inode: u64,
}

/// Rows stored in a section.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Section {
    offset: u64,
    shape: [u64; 3],
    item: u8,
    big_endian: bool,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct StoredFeatures {
    sha256: String,
    rows_of: Vec<u32>,
    arrays: Vec<(String, Section)>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct Header {
    holoc: String,
    /// When the stamps were taken, nanoseconds since 1970.
    stamped_ns: u128,
    stamps: Vec<Stamp>,
    annotations_sha256: String,
    parsed: Vec<(Asset, Entry)>,
    problems: Problems,
    clip: Option<Result<StoredFeatures, String>>,
    sbert: Option<Result<StoredFeatures, String>>,
    /// The annotations' text (offset, length), kept when an entry was unusable.
    text: Option<(u64, u64)>,
}

fn stamp(root: &Path, path: &Path) -> Option<Stamp> {
    let meta = std::fs::metadata(path).ok()?;
    let modified_ns = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    #[cfg(unix)]
    let inode = std::os::unix::fs::MetadataExt::ino(&meta);
    #[cfg(not(unix))]
    let inode = 0;
    let name = path.strip_prefix(root).unwrap_or(path).to_string_lossy().into_owned();
    Some(Stamp { name, len: meta.len(), modified_ns, inode })
}

fn stamps(root: &Path, files: &FolderFiles) -> Option<Vec<Stamp>> {
    [Some(&files.annotations), files.clip.as_ref(), files.sbert.as_ref()]
        .into_iter()
        .flatten()
        .map(|p| stamp(root, p))
        .collect()
}

fn now_ns() -> u128 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos())
}

/// The holoc release that writes an index (a rebuilt holoc of another release reads folders
/// again).
fn release() -> String {
    format!("{} source {}", crate::build_info::VERSION, crate::build_info::SOURCE)
}

/// The user's cache folder for holoc.
fn cache_dir() -> Option<PathBuf> {
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    var("HOLOC_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("holoc")))
        .or_else(|| var("HOME").map(|d| d.join(".cache").join("holoc")))
}

/// The places the index of the folder `root` may be, in the order they are tried.
fn places(root: &Path, version: &str) -> Vec<PathBuf> {
    let mut out = vec![root.join(FOLDER_NAME).join(FILE_NAME)];
    if let Some(cache) = cache_dir() {
        let canonical = std::fs::canonicalize(root).unwrap_or_else(|_| root.to_path_buf());
        let hash = crate::resolve::sha256_hex(canonical.to_string_lossy().as_bytes());
        let safe: String = version
            .chars()
            .map(
                |c| if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') { c } else { '_' },
            )
            .collect();
        out.push(cache.join("objathor").join(format!("{safe}-{}.idx", &hash[..16])));
    }
    out
}

/// The folder's index and where it is, when one holds for its files as they are now.
pub(crate) fn open(
    root: &Path,
    version: &str,
    files: &FolderFiles,
) -> Option<(FolderRead, PathBuf)> {
    let now = stamps(root, files)?;
    places(root, version).into_iter().find_map(|path| {
        let read = open_at(&path, &now).ok()?;
        Some((read, path))
    })
}

fn open_at(path: &Path, now: &[Stamp]) -> Result<FolderRead, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    if !file.metadata().map_err(|e| e.to_string())?.is_file() {
        return Err("not a regular file".into());
    }
    let len = usize::try_from(file.metadata().map_err(|e| e.to_string())?.len())
        .map_err(|e| e.to_string())?;
    decode(&Backing::Stored(Arc::new(file), len), Some(now))
}

/// Reads an index's bytes as a build does, without a folder to compare its stamps with, and
/// decodes every vector it holds: the number of assets. For the fuzz harness.
///
/// # Errors
/// Why the bytes are not an index holoc would use.
pub fn read_index_bytes(bytes: Vec<u8>) -> Result<usize, String> {
    let read = decode(&Backing::Read(Arc::new(bytes)), None)?;
    for features in [&read.clip, &read.sbert].into_iter().flatten().flatten() {
        for (_, rows) in &features.arrays {
            let mut v = vec![0f32; rows.dim];
            for row in 0..rows.len() {
                for view in 0..rows.views {
                    rows.decode(row, view, &mut v);
                }
            }
        }
    }
    Ok(read.parsed.len())
}

/// The index in `bytes`; with `now`, only when its stamps are those and the holoc that wrote
/// it is this one. Every section is checked to lie inside the bytes.
fn decode(backing: &Backing, now: Option<&[Stamp]>) -> Result<FolderRead, String> {
    let bytes = backing.get(0, PRELUDE as usize).ok_or("not a holoc objathor index")?;
    if &bytes[..8] != MAGIC {
        return Err("not a holoc objathor index".into());
    }
    let word = |at: usize| -> u64 {
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        u64::from_le_bytes(b)
    };
    let format = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
    if format != FORMAT {
        return Err(format!("format {format}, not {FORMAT}"));
    }
    let (at, len) = (word(16), word(24));
    let header_bytes = usize::try_from(at)
        .ok()
        .zip(usize::try_from(len).ok())
        .and_then(|(a, l)| backing.get(a, l))
        .ok_or("its header lies outside the file")?;
    let header: Header = postcard::from_bytes(&header_bytes).map_err(|e| e.to_string())?;
    if let Some(now) = now {
        if header.holoc != release() {
            return Err(format!("written by holoc {}", header.holoc));
        }
        if header.stamps != now {
            return Err("the folder's files changed since it was written".into());
        }
        // A file changed within the clock's resolution of the stamps could have changed again
        // after them with the same stamp (as git's "racily clean" files): such an index cannot
        // vouch for it, and the folder is read again.
        if now.iter().any(|s| s.modified_ns.saturating_add(RACY_NS) >= header.stamped_ns) {
            return Err("a file changed just before the index was written".into());
        }
    }
    let n = header.parsed.len();
    let features = |stored: Option<Result<StoredFeatures, String>>| -> Result<_, String> {
        let Some(stored) = stored else { return Ok(None) };
        let stored = match stored {
            Ok(s) => s,
            Err(why) => return Ok(Some(Err(why))),
        };
        if stored.rows_of.len() != n {
            return Err("its rows do not match its entries".into());
        }
        let mut arrays = Vec::with_capacity(stored.arrays.len());
        for (key, s) in stored.arrays {
            let shape = s.shape.map(|x| usize::try_from(x).unwrap_or(usize::MAX));
            let start = usize::try_from(s.offset).map_err(|e| e.to_string())?;
            let rows = FeatureRows::within(
                backing.clone(),
                start,
                shape,
                usize::from(s.item),
                s.big_endian,
            )?;
            if stored.rows_of.iter().any(|r| *r != u32::MAX && *r as usize >= rows.len()) {
                return Err(format!("`{key}` has fewer rows than its assets name"));
            }
            arrays.push((key, rows));
        }
        Ok(Some(Ok(ReadFeatures { sha256: stored.sha256, rows_of: stored.rows_of, arrays })))
    };
    let clip = features(header.clip)?;
    let sbert = features(header.sbert)?;
    let text = match header.text {
        Some((a, l)) => {
            let slice = usize::try_from(a)
                .ok()
                .zip(usize::try_from(l).ok())
                .and_then(|(a, l)| backing.get(a, l))
                .ok_or("its text lies outside the file")?;
            Some(String::from_utf8(slice.to_vec()).map_err(|e| e.to_string())?)
        }
        None if header.problems.is_empty() => None,
        None => return Err("it lacks the text its warnings point into".into()),
    };
    if header.parsed.iter().any(|(a, _)| !a.bbox_m.iter().all(|x| x.is_finite() && *x >= 0.0)) {
        return Err("an asset's size is not a size".into());
    }
    Ok(FolderRead {
        annotations_sha256: header.annotations_sha256,
        text,
        parsed: header.parsed,
        problems: header.problems,
        clip,
        sbert,
    })
}

/// Writes the index of the folder `root` made of `read`: in the folder, else in the cache
/// folder. The path written, or why neither could be.
pub(crate) fn write(
    root: &Path,
    version: &str,
    files: &FolderFiles,
    read: &FolderRead,
) -> Result<PathBuf, String> {
    let stamped_ns = now_ns();
    let Some(now) = stamps(root, files) else {
        return Err("a file of the folder could not be looked at".into());
    };
    let mut why = Vec::new();
    for path in places(root, version) {
        match write_at(&path, (&now, stamped_ns), read) {
            Ok(()) => return Ok(path),
            Err(e) => why.push(format!("`{}`: {e}", path.display())),
        }
    }
    Err(why.join("; "))
}

/// A writer that counts the bytes written through it.
struct Counted<'w> {
    out: &'w mut std::io::BufWriter<tempfile::NamedTempFile>,
    n: u64,
}

impl std::io::Write for Counted<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        self.n += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// The index file being written: where the next byte goes.
struct Out {
    file: std::io::BufWriter<tempfile::NamedTempFile>,
    at: u64,
}

impl Out {
    /// Writes `bytes` at the next multiple of [`ALIGN`]; their offset.
    fn put(&mut self, bytes: &[u8]) -> std::io::Result<u64> {
        self.put_with(|w| w.write_all(bytes))
    }

    /// Writes what `write` writes at the next multiple of [`ALIGN`]; its offset.
    fn put_with(
        &mut self,
        write: impl FnOnce(&mut Counted<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<u64> {
        let pad = (ALIGN - self.at % ALIGN) % ALIGN;
        self.file.write_all(&[0u8; ALIGN as usize][..pad as usize])?;
        let start = self.at + pad;
        let mut counted = Counted { out: &mut self.file, n: 0 };
        write(&mut counted)?;
        self.at = start + counted.n;
        Ok(start)
    }

    fn features(
        &mut self,
        f: Option<&Result<ReadFeatures, String>>,
    ) -> std::io::Result<Option<Result<StoredFeatures, String>>> {
        let Some(f) = f else { return Ok(None) };
        let f = match f {
            Ok(f) => f,
            Err(why) => return Ok(Some(Err(why.clone()))),
        };
        let mut arrays = Vec::new();
        for (key, rows) in &f.arrays {
            let (shape, item, big_endian) = rows.raw();
            let offset = self.put_with(|w| rows.write_raw(w))?;
            let section =
                Section { offset, shape: shape.map(|x| x as u64), item: item as u8, big_endian };
            arrays.push((key.clone(), section));
        }
        Ok(Some(Ok(StoredFeatures {
            sha256: f.sha256.clone(),
            rows_of: f.rows_of.clone(),
            arrays,
        })))
    }
}

/// [`Header`] borrowed from what was read: the same encoding, without a copy of the entries.
#[derive(Serialize)]
struct HeaderOut<'a> {
    holoc: &'a str,
    stamped_ns: u128,
    stamps: &'a [Stamp],
    annotations_sha256: &'a str,
    parsed: &'a [(Asset, Entry)],
    problems: &'a Problems,
    clip: Option<Result<StoredFeatures, String>>,
    sbert: Option<Result<StoredFeatures, String>>,
    text: Option<(u64, u64)>,
}

fn write_at(
    path: &Path,
    (stamps, stamped_ns): (&[Stamp], u128),
    read: &FolderRead,
) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    // `.holoc-<pid>-XXXXXX.tmp`, as every atomic write of holoc's: a run killed while writing
    // leaves one, which a later run removes once its process has ended.
    let (prefix, suffix) = (crate::cli::common::TEMP_PREFIX, crate::cli::common::TEMP_SUFFIX);
    crate::cli::common::remove_stale_temporaries(dir);
    let tmp = tempfile::Builder::new()
        .prefix(&format!("{prefix}{}-", std::process::id()))
        .suffix(suffix)
        .tempfile_in(dir)?;
    let mut out = Out { file: std::io::BufWriter::new(tmp), at: PRELUDE };
    out.file.write_all(&[0u8; PRELUDE as usize])?;
    let clip = out.features(read.clip.as_ref())?;
    let sbert = out.features(read.sbert.as_ref())?;
    let text = match (&read.text, read.problems.is_empty()) {
        (Some(text), false) => Some((out.put(text.as_bytes())?, text.len() as u64)),
        _ => None,
    };
    let holoc = release();
    let header = HeaderOut {
        holoc: &holoc,
        stamped_ns,
        stamps,
        annotations_sha256: &read.annotations_sha256,
        parsed: &read.parsed,
        problems: &read.problems,
        clip,
        sbert,
        text,
    };
    let encoded = postcard::to_stdvec(&header).map_err(std::io::Error::other)?;
    let header_at = out.put(&encoded)?;
    let mut tmp = out.file.into_inner().map_err(std::io::IntoInnerError::into_error)?;
    let mut prelude = [0u8; PRELUDE as usize];
    prelude[..8].copy_from_slice(MAGIC);
    prelude[8..12].copy_from_slice(&FORMAT.to_le_bytes());
    prelude[16..24].copy_from_slice(&header_at.to_le_bytes());
    prelude[24..32].copy_from_slice(&(encoded.len() as u64).to_le_bytes());
    tmp.seek(SeekFrom::Start(0))?;
    tmp.write_all(&prelude)?;
    // Readable by whoever may read the folder (a temporary file is private).
    #[cfg(unix)]
    std::fs::set_permissions(tmp.path(), std::os::unix::fs::PermissionsExt::from_mode(0o644))?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}
