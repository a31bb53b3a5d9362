//! Reading an input file with bounds: only as many bytes as the caller allows, and never
//! waiting for ever.
//!
//! A regular file is read directly. A named pipe (FIFO) is refused before it is opened, since
//! opening one waits for a writer. Anything else that is not a folder (a device such as
//! `/dev/zero`, the anonymous pipe of a shell's `<(command)`, a link to a FIFO) is opened and
//! read on a helper thread: at most the caller's limit of bytes, and the read gives up after
//! [`STREAM_TIMEOUT`] (the helper thread is then left blocked; it holds nothing but its file).
//! Every path holoc takes as an input goes through [`read_input`]: scenes, answers, houses,
//! catalogs, manifests, `holoc.toml`.

use std::io::Read as _;
use std::path::Path;
use std::time::Duration;

/// How long a device or pipe may take to deliver its whole content.
pub const STREAM_TIMEOUT: Duration = Duration::from_secs(10);

/// Why an input could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReadError {
    /// The path names a named pipe (FIFO).
    NamedPipe,
    /// The path names a folder.
    Folder,
    /// The path names a socket.
    Socket,
    /// The input holds more than the limit (of this many bytes).
    TooLarge(u64),
    /// A device or pipe did not end within [`STREAM_TIMEOUT`].
    Timeout,
    /// Any other I/O error, as the system words it.
    Io(String),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::NamedPipe => f.write_str("it is a named pipe"),
            ReadError::Folder => f.write_str("it is a folder"),
            ReadError::Socket => f.write_str("it is a socket"),
            ReadError::TooLarge(limit) => write!(f, "it is larger than {}", size(*limit)),
            ReadError::Timeout => write!(
                f,
                "it is a device or pipe that did not end within {} s",
                STREAM_TIMEOUT.as_secs()
            ),
            ReadError::Io(e) => f.write_str(e),
        }
    }
}

/// A byte count as people read it (`32 MiB`, `1 KiB`, `100 bytes`).
fn size(bytes: u64) -> String {
    if bytes >= 1024 * 1024 && bytes % (1024 * 1024) == 0 {
        format!("{} MiB", bytes / (1024 * 1024))
    } else if bytes >= 1024 && bytes % 1024 == 0 {
        format!("{} KiB", bytes / 1024)
    } else {
        format!("{bytes} bytes")
    }
}

/// The bytes of the file at `path`, at most `limit` of them (more is [`ReadError::TooLarge`]).
///
/// # Errors
/// A named pipe, a folder or a socket; an input over the limit; a device or pipe that does
/// not end within [`STREAM_TIMEOUT`]; any I/O error.
pub fn read_input(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let io = |e: std::io::Error| ReadError::Io(e.to_string());
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo()) {
            return Err(ReadError::NamedPipe);
        }
        if std::fs::metadata(path).is_ok_and(|m| m.file_type().is_socket()) {
            return Err(ReadError::Socket);
        }
    }
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() {
        return Err(ReadError::Folder);
    }
    if meta.is_file() {
        // A regular file over the limit is refused without reading it (a 4 GiB feature file
        // was read whole to be refused); one within it is read into a buffer of its size.
        if meta.len() > limit {
            return Err(ReadError::TooLarge(limit));
        }
        let file = std::fs::File::open(path).map_err(io)?;
        return read_limited_into(file, limit, usize::try_from(meta.len()).unwrap_or(0));
    }
    // A device or an anonymous pipe: opened and read on a helper thread, waited for at most
    // the timeout.
    let (tx, rx) = std::sync::mpsc::channel();
    let owned = path.to_path_buf();
    std::thread::Builder::new()
        .name("holoc-read".to_string())
        .spawn(move || {
            let read = std::fs::File::open(&owned).map_err(io).and_then(|f| read_limited(f, limit));
            let _ = tx.send(read);
        })
        .map_err(io)?;
    rx.recv_timeout(STREAM_TIMEOUT).unwrap_or(Err(ReadError::Timeout))
}

/// Like [`read_input`], with `-` standing for standard input (read up to the same limit).
///
/// # Errors
/// As [`read_input`]; standard input has no time limit (a person may be typing into it).
pub fn read_input_or_stdin(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    if path.as_os_str() != "-" {
        return read_input(path, limit);
    }
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge(limit));
    }
    Ok(bytes)
}

/// The text of a file holoc wrote itself (a summary, a memo, a count of tries), read as
/// [`read_input`] reads any input: a named pipe or a device put in its place cannot hang the
/// command or fill the memory. Text that is not UTF-8 is an [`ReadError::Io`].
///
/// # Errors
/// As [`read_input`], and text that is not UTF-8.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    String::from_utf8(read_input(path, limit)?)
        .map_err(|e| ReadError::Io(format!("it is not UTF-8 text: {}", e.utf8_error())))
}

/// Reads at most `limit` bytes of `file`; one more is [`ReadError::TooLarge`].
fn read_limited(file: std::fs::File, limit: u64) -> Result<Vec<u8>, ReadError> {
    read_limited_into(file, limit, 0)
}

/// [`read_limited`] into a buffer made for `expected` bytes (a regular file's size: the buffer
/// is not grown by doubling, which held up to twice the file while it was copied).
fn read_limited_into(
    file: std::fs::File,
    limit: u64,
    expected: usize,
) -> Result<Vec<u8>, ReadError> {
    let mut bytes = Vec::new();
    // The size may have changed since it was asked: the bytes read are what count.
    bytes.try_reserve_exact(expected).map_err(|e| ReadError::Io(e.to_string()))?;
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge(limit));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_is_read_into_a_buffer_of_its_size_or_refused_by_its_size() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("f");
        std::fs::write(&path, vec![7u8; 5000]).expect("written");
        let read = read_input(&path, 5000).expect("read");
        assert_eq!((read.len(), read.capacity()), (5000, 5000));
        assert_eq!(read_input(&path, 4999), Err(ReadError::TooLarge(4999)));
        std::fs::write(&path, b"").expect("written");
        assert_eq!(read_input(&path, 0), Ok(Vec::new()));
    }

    #[test]
    fn a_device_stops_at_the_limit() {
        if Path::new("/dev/zero").exists() {
            assert_eq!(read_input(Path::new("/dev/zero"), 1000), Err(ReadError::TooLarge(1000)));
        }
    }

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(size(32 * 1024 * 1024), "32 MiB");
        assert_eq!(size(2048), "2 KiB");
        assert_eq!(size(100), "100 bytes");
    }
}
