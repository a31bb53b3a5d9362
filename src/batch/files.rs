//! What the jobs of a run share on disk and in memory: the hashes of the files they read
//! (each file read and hashed once per run while its size and time stamp stay the same), the
//! loaded catalogs (one per distinct content), the per-job locks that let two runs on one
//! folder share the work, and the run's scratch folder (whose leftovers from killed runs are
//! removed when a run starts).

use crate::diag::Diagnostic;
use crate::resolve::Catalog;
use crate::source::SourceMap;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// A file's size and time stamp: a file whose stamp is unchanged is not read again.
type Stamp = (u64, Option<SystemTime>);

fn stamp(path: &Path) -> Option<Stamp> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.len(), meta.modified().ok()))
}

/// Where a run keeps the hashes of the files it read, for the next run into the same folder.
fn memo_path(out: &Path) -> PathBuf {
    out.join(".cache").join("file-hashes.tsv")
}

/// The SHA-256 of the files a run reads, by path.
#[derive(Debug, Default)]
pub struct FileHashes {
    known: Mutex<HashMap<PathBuf, (Stamp, String)>>,
}

impl FileHashes {
    /// The SHA-256 (hex) of the file's bytes, or `unreadable:<path>` when it cannot be read or
    /// is not a regular file.
    pub fn hash(&self, path: &Path) -> String {
        let lock = || self.known.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let Some(now) = stamp(path) else {
            return format!("unreadable:{}", path.display());
        };
        if let Some((seen, hash)) = lock().get(path) {
            if *seen == now {
                return hash.clone();
            }
        }
        // Only a regular file is read here (a named pipe or a device would block or never
        // end); the job's own read reports any other kind, with the limits of every input.
        if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
            return format!("unreadable:{}", path.display());
        }
        let hash = match crate::source::read_input(path, crate::resolve::MAX_CATALOG_BYTES) {
            Ok(bytes) => crate::resolve::sha256_hex(&bytes),
            Err(_) => return format!("unreadable:{}", path.display()),
        };
        lock().insert(path.to_path_buf(), (now, hash.clone()));
        hash
    }

    /// The hashes a previous run left in `out` (`.cache/file-hashes.tsv`): a file whose size and
    /// time stamp are those recorded is not read again, so resuming jobs that name a large
    /// catalog costs no reading of it. A missing or damaged memo is an empty one.
    pub fn load(out: &Path) -> FileHashes {
        let mut known = HashMap::new();
        let text = crate::source::read_text(&memo_path(out), 64 * 1024 * 1024).unwrap_or_default();
        for line in text.lines() {
            let mut f = line.splitn(4, '\t');
            let (Some(hash), Some(len), Some(time), Some(path)) =
                (f.next(), f.next(), f.next(), f.next())
            else {
                continue;
            };
            let Ok(len) = len.parse::<u64>() else { continue };
            let time = match time {
                "-" => None,
                t => match t.split_once('.').map(|(s, n)| (s.parse::<u64>(), n.parse::<u32>())) {
                    Some((Ok(s), Ok(n))) if n < 1_000_000_000 => {
                        SystemTime::UNIX_EPOCH.checked_add(std::time::Duration::new(s, n))
                    }
                    _ => continue,
                },
            };
            if hash.len() == 64 && hash.bytes().all(|b| b.is_ascii_hexdigit()) {
                known.insert(PathBuf::from(path), ((len, time), hash.to_string()));
            }
        }
        FileHashes { known: Mutex::new(known) }
    }

    /// Writes what the run knows for the next one (atomically, through `scratch`): the paths,
    /// sizes, time stamps and hashes, sorted by path. Paths with a tab or a line break are left
    /// out (they are hashed again).
    pub fn save(&self, out: &Path, scratch: &Path) -> std::io::Result<()> {
        let known = self.known.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut rows: Vec<(&PathBuf, &(Stamp, String))> = known.iter().collect();
        rows.sort_by(|a, b| a.0.cmp(b.0));
        let mut text = String::new();
        for (path, ((len, time), hash)) in rows {
            let Some(p) = path.to_str().filter(|p| !p.contains(['\t', '\n', '\r'])) else {
                continue;
            };
            let time = match time.and_then(|t| t.duration_since(SystemTime::UNIX_EPOCH).ok()) {
                Some(d) => format!("{}.{:09}", d.as_secs(), d.subsec_nanos()),
                None => "-".to_string(),
            };
            let _ = writeln!(text, "{hash}\t{len}\t{time}\t{p}");
        }
        drop(known);
        let path = memo_path(out);
        crate::cli::common::confine_io(out, &path)?;
        let tmp = scratch.join("file-hashes.tsv");
        std::fs::write(&tmp, text)?;
        std::fs::rename(&tmp, &path)
    }

    /// The file's size in bytes (0 when it cannot be read).
    pub fn len(&self, path: &Path) -> u64 {
        stamp(path).map_or(0, |s| s.0)
    }
}

/// A loaded catalog set: the catalog, the sources its diagnostics point into, the diagnostics.
pub type LoadedCatalogs = Arc<(Catalog, SourceMap, Vec<Diagnostic>)>;

/// The catalog sets a run has loaded, by the hashes of their files' contents: every job whose
/// catalogs have the same contents (every job without `catalog`, usually) shares one catalog,
/// loaded once. A changed file is a new key. At most [`CatalogCache::MAX_SETS`] sets are kept,
/// so memory stays flat with many distinct sets.
#[derive(Debug, Default)]
pub struct CatalogCache {
    sets: Mutex<HashMap<Vec<String>, LoadedCatalogs>>,
    /// Held while a set is loaded, so that jobs asking for the same new set at once load it
    /// once (the others wait, then find it).
    loading: Mutex<()>,
}

impl CatalogCache {
    /// The most catalog sets kept at once.
    pub const MAX_SETS: usize = 8;

    /// The catalog set of `paths`, loaded now or earlier; `files` gives their hashes.
    pub fn get(
        &self,
        paths: &[PathBuf],
        objathor: Option<&crate::resolve::objathor::ObjathorOptions>,
        files: &FileHashes,
    ) -> LoadedCatalogs {
        let mut key: Vec<String> = paths.iter().map(|p| files.hash(p)).collect();
        if let Some(o) = objathor {
            key.push(format!("objathor {o:?}"));
        }
        // A job that panicked while holding a lock leaves a map that is still whole (only
        // whole inserts and clears happen under it).
        let lock = || self.sets.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(found) = lock().get(&key) {
            return Arc::clone(found);
        }
        let _loading = self.loading.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(found) = lock().get(&key) {
            return Arc::clone(found);
        }
        let mut sources = SourceMap::new();
        let loaded = Catalog::load_with(paths, objathor, &mut sources);
        let set = Arc::new((loaded.value, sources, loaded.diagnostics));
        let mut sets = lock();
        if sets.len() >= Self::MAX_SETS {
            sets.clear();
        }
        Arc::clone(sets.entry(key).or_insert(set))
    }
}

/// An exclusive lock on a file, held until dropped (`flock(2)`; elsewhere than Unix every lock
/// is granted, so two runs on one folder are not kept apart there).
#[derive(Debug)]
pub struct FileLock {
    _file: std::fs::File,
    path: PathBuf,
}

impl FileLock {
    /// Takes the lock of `path` (made if missing) without waiting: `Ok(None)` when another
    /// process holds it.
    pub fn try_take(path: &Path) -> std::io::Result<Option<FileLock>> {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let file =
            std::fs::OpenOptions::new().create(true).truncate(false).write(true).open(path)?;
        #[cfg(unix)]
        {
            use rustix::fs::{flock, FlockOperation};
            match flock(&file, FlockOperation::NonBlockingLockExclusive) {
                Ok(()) => {}
                Err(e) if e == rustix::io::Errno::WOULDBLOCK => return Ok(None),
                Err(e) => return Err(e.into()),
            }
        }
        Ok(Some(FileLock { _file: file, path: path.to_path_buf() }))
    }

    /// Takes the lock of `path` (made if missing), waiting for another process to let it go.
    pub fn take(path: &Path) -> std::io::Result<FileLock> {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let file =
            std::fs::OpenOptions::new().create(true).truncate(false).write(true).open(path)?;
        #[cfg(unix)]
        rustix::fs::flock(&file, rustix::fs::FlockOperation::LockExclusive)?;
        Ok(FileLock { _file: file, path: path.to_path_buf() })
    }

    /// Removes the lock's file and lets the lock go. Only for a job whose folder is complete:
    /// a run that opened the old file and takes its lock afterwards finds the folder complete.
    pub fn remove(self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// The scratch folder of one run, `OUT/.tmp/<run>/`, with its lock `OUT/.tmp/<run>.lock` held
/// for as long as the run lives. Made by [`Scratch::create`], which first removes what killed
/// runs left (folders whose lock nobody holds); removed by [`Scratch::finish`].
#[derive(Debug)]
pub struct Scratch {
    /// The folder.
    pub dir: PathBuf,
    lock: Option<FileLock>,
}

impl Scratch {
    /// Cleans `out/.tmp/` of dead runs' leftovers and makes this run's folder.
    pub fn create(out: &Path) -> std::io::Result<Scratch> {
        let root = out.join(".tmp");
        let nanos = SystemTime::now()
            .duration_since(SystemTime::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let name = format!("run-{}-{nanos:09}", std::process::id());
        // `.tmp` must be a real folder of `out` before anything in it is removed or made: a
        // link to a folder elsewhere would have its files cleaned away.
        crate::cli::common::confine_io(out, &root.join(format!("{name}.lock")))?;
        Self::clean(&root);
        let lock = FileLock::try_take(&root.join(format!("{name}.lock")))?;
        let dir = root.join(name);
        std::fs::create_dir_all(&dir)?;
        Ok(Scratch { dir, lock })
    }

    /// Removes every entry of `root` that no live run holds: a `<name>.lock` that can be taken
    /// belongs to a dead run, and goes with its folder; anything else without a lock (the
    /// scratch of older versions) goes too.
    fn clean(root: &Path) {
        let Ok(entries) = std::fs::read_dir(root) else { return };
        let mut names: Vec<String> = entries
            .filter_map(Result::ok)
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        let is_lock = |n: &&String| Path::new(n.as_str()).extension().is_some_and(|e| e == "lock");
        for name in names.iter().filter(|n| !is_lock(n)) {
            let lock_path = root.join(format!("{name}.lock"));
            let held =
                lock_path.exists() && matches!(FileLock::try_take(&lock_path), Ok(None) | Err(_));
            if held {
                continue;
            }
            let path = root.join(name);
            if path.is_dir() {
                let _ = std::fs::remove_dir_all(&path);
            } else {
                let _ = std::fs::remove_file(&path);
            }
            let _ = std::fs::remove_file(&lock_path);
        }
        // Locks left without a folder.
        for name in names.iter().filter(is_lock) {
            let folder = root.join(name.trim_end_matches(".lock"));
            let path = root.join(name);
            if !folder.exists() && matches!(FileLock::try_take(&path), Ok(Some(_))) {
                let _ = std::fs::remove_file(&path);
            }
        }
    }

    /// Removes the run's folder and lock, and `.tmp/` when nothing else is in it.
    pub fn finish(mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
        if let Some(lock) = self.lock.take() {
            lock.remove();
        }
        if let Some(root) = self.dir.parent() {
            let _ = std::fs::remove_dir(root);
        }
    }
}
