//! File output shared by every command: atomic writes (temp file `NAME.<pid>.tmp` in the same
//! directory, then rename, so a reader never sees a half-written file and a crash never destroys
//! the old one), removal of the temp files a killed process left behind, exclusive output locks,
//! output-path checks made before any computation, and the CSV input helpers.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The temporary sibling used while `path` is being written.
pub fn temp_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(format!(".{}.tmp", std::process::id()));
    path.with_file_name(name)
}

/// Write `bytes` to `path` atomically (write a temp file, fsync, rename over `path`).
/// Parent directories are created.
///
/// ```
/// let dir = std::env::temp_dir().join("helixreach-doc-io");
/// let p = dir.join("a.txt");
/// helixreach::io::write_atomic(&p, b"hello").unwrap();
/// assert_eq!(std::fs::read(&p).unwrap(), b"hello");
/// ```
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent).map_err(io)?;
        }
    }
    remove_stale_temps(path);
    let tmp = temp_path(path);
    {
        let mut f = std::fs::File::create(&tmp).map_err(io)?;
        f.write_all(bytes).map_err(io)?;
        f.sync_all().map_err(io)?;
    }
    std::fs::rename(&tmp, path).map_err(io)
}

/// Whether process `pid` is alive (Unix `kill(pid, 0)`; elsewhere: assumed alive).
fn process_alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(p) = libc::pid_t::try_from(pid) else {
            return false;
        };
        // SAFETY: signal 0 only checks whether the process exists; no signal is sent.
        let rc = unsafe { libc::kill(p, 0) };
        rc == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Remove the temp files `NAME.<pid>.tmp` of `path` (see [`temp_path`]) left by processes that
/// no longer run (a killed sweep). Best effort: returns how many were removed.
pub fn remove_stale_temps(path: &Path) -> usize {
    let (Some(name), dir) = (path.file_name(), path.parent()) else {
        return 0;
    };
    let dir = match dir {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let prefix = format!("{}.", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let n = e.file_name();
        let n = n.to_string_lossy();
        let pid = n
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(".tmp"))
            .and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid {
            if pid != std::process::id()
                && !process_alive(pid)
                && std::fs::remove_file(e.path()).is_ok()
            {
                removed += 1;
            }
        }
    }
    removed
}

/// True when `path` means standard output (`-`).
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// True when `path` exists and is not a regular file (a device such as `/dev/stdout`, a FIFO):
/// such outputs are written in place, never replaced by a rename.
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Check, before any computation, that `path` can be written: standard output (`-`) and
/// existing non-regular files are fine; otherwise `path` must not be a directory and its
/// directory must exist (or be creatable) and accept a new file (probed with a temp file that is
/// removed at once).
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// assert!(helixreach::io::check_output(&dir.path().join("a.csv")).is_ok());
/// let e = helixreach::io::check_output(dir.path()).unwrap_err().to_string();
/// assert!(e.contains("is a directory"), "{e}");
/// ```
pub fn check_output(path: &Path) -> Result<()> {
    if is_stdout(path) || is_special(path) {
        return Ok(());
    }
    let err = |reason: String| Error::File {
        path: path.to_path_buf(),
        reason,
    };
    if path.is_dir() {
        return Err(err("is a directory, expected an output file".into()));
    }
    if path.file_name().is_none() {
        return Err(err("has no file name".into()));
    }
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent).map_err(|e| {
                err(format!(
                    "cannot create its directory {}: {e}",
                    parent.display()
                ))
            })?;
        }
    }
    let probe = temp_path(path);
    std::fs::File::create(&probe)
        .map_err(|e| err(format!("cannot write in its directory: {e}")))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// An exclusive lock on an output path, held until dropped.
///
/// The lock is an OS advisory lock (`flock`) on the sibling `NAME.lock`, which exists only while
/// a writer holds it (it is removed on drop; a lock file whose inode changed under us is retried,
/// so a writer that loses the race never holds a lock on a removed file). A second writer of the
/// same output gets [`Error::File`] naming the path and the holder's pid. The lock is released
/// by the OS when the process dies, so a killed run never blocks the next one.
#[derive(Debug)]
pub struct OutputLock {
    lock_path: PathBuf,
    _file: std::fs::File,
}

/// The lock file of `path`.
pub fn lock_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".lock");
    path.with_file_name(name)
}

impl OutputLock {
    /// Take the exclusive lock of `path`, or fail at once if another process holds it.
    ///
    /// ```
    /// let dir = tempfile::tempdir().unwrap();
    /// let p = dir.path().join("out.csv");
    /// let lock = helixreach::io::OutputLock::acquire(&p).unwrap();
    /// drop(lock);
    /// assert!(!dir.path().join("out.csv.lock").exists());
    /// ```
    pub fn acquire(path: &Path) -> Result<OutputLock> {
        let lock_path = lock_path(path);
        let io = |source| Error::Io {
            path: lock_path.clone(),
            source,
        };
        loop {
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&lock_path)
                .map_err(io)?;
            if !try_lock(&file).map_err(io)? {
                let mut holder = String::new();
                let _ = std::io::Read::read_to_string(&mut file, &mut holder);
                let holder = holder.trim();
                let who = if holder.is_empty() {
                    "another process".to_string()
                } else {
                    format!("another process (pid {holder})")
                };
                return Err(Error::File {
                    path: path.to_path_buf(),
                    reason: format!(
                        "is being written by {who}: two writers of one output are refused                          (lock {})",
                        lock_path.display()
                    ),
                });
            }
            if same_file(&file, &lock_path) {
                file.set_len(0).map_err(io)?;
                write!(file, "{}", std::process::id()).map_err(io)?;
                return Ok(OutputLock {
                    lock_path,
                    _file: file,
                });
            }
            // The previous holder removed the lock file between our open and lock: retry.
        }
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still locked; the file handle (and the lock) closes after.
        let _ = std::fs::remove_file(&self.lock_path);
    }
}

/// Try to take an exclusive `flock` without blocking: `Ok(false)` when another holds it.
#[cfg(unix)]
fn try_lock(f: &std::fs::File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a valid, open file descriptor owned by `f`.
    let rc = unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if rc == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    if e.raw_os_error() == Some(libc::EWOULDBLOCK) {
        Ok(false)
    } else {
        Err(e)
    }
}

/// Elsewhere: no OS lock (always granted).
#[cfg(not(unix))]
fn try_lock(_f: &std::fs::File) -> std::io::Result<bool> {
    Ok(true)
}

/// Whether the open file `f` is still the file at `path` (same device and inode).
#[cfg(unix)]
fn same_file(f: &std::fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (f.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_f: &std::fs::File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_temps_of_dead_processes_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.csv");
        // pid 4194304 is above Linux's largest pid_max (2^22 - 1): never alive.
        let dead = dir.path().join("x.csv.4194304.tmp");
        let other = dir.path().join("y.csv.4194304.tmp");
        for f in [&dead, &other] {
            std::fs::write(f, "partial").unwrap();
        }
        write_atomic(&p, b"ok").unwrap();
        assert!(!dead.exists());
        assert!(
            other.exists(),
            "another output's temp is not ours to remove"
        );
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("sub").join("x.csv");
        write_atomic(&p, b"a").unwrap();
        write_atomic(&p, b"bb").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"bb");
        let n = std::fs::read_dir(p.parent().unwrap()).unwrap().count();
        assert_eq!(n, 1, "temp file left behind");
    }
}

/// A CSV file opened for reading by column name; every error names the file.
///
/// ```
/// let dir = std::env::temp_dir().join("helixreach-doc-csvin");
/// std::fs::create_dir_all(&dir).unwrap();
/// let p = dir.join("a.csv");
/// std::fs::write(&p, "x,y\n1,2\n").unwrap();
/// let t = helixreach::io::CsvInput::open(&p).unwrap();
/// assert_eq!(t.column("y", "").unwrap(), 1);
/// assert!(t.column("z", "").unwrap_err().to_string().contains("missing column `z`"));
/// ```
#[derive(Debug)]
pub struct CsvInput {
    path: PathBuf,
    headers: csv::StringRecord,
    /// The reader, positioned at the first record.
    pub reader: csv::Reader<std::fs::File>,
}

impl CsvInput {
    /// Open `path` (fields trimmed, `#` comment lines such as a sweep's settings record skipped)
    /// and read its header.
    pub fn open(path: &Path) -> Result<Self> {
        let file_err = |e: csv::Error| Error::File {
            path: path.to_path_buf(),
            reason: e.to_string(),
        };
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .from_path(path)
            .map_err(file_err)?;
        let mut headers = reader.headers().map_err(file_err)?.clone();
        // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first column's name.
        if let Some(first) = headers.get(0).and_then(|h| h.strip_prefix('\u{feff}')) {
            let mut fixed = csv::StringRecord::new();
            fixed.push_field(first.trim());
            for h in headers.iter().skip(1) {
                fixed.push_field(h);
            }
            headers = fixed;
            reader.set_headers(headers.clone());
        }
        for (i, h) in headers.iter().enumerate() {
            if let Some(j) = headers.iter().take(i).position(|g| g == h) {
                return Err(Error::BadLine {
                    path: path.to_path_buf(),
                    line: 1,
                    field: "header".into(),
                    reason: format!(
                        "column `{h}` appears twice (columns {} and {}): which one holds the \
                         values is ambiguous",
                        j + 1,
                        i + 1
                    ),
                });
            }
        }
        Ok(CsvInput {
            path: path.to_path_buf(),
            headers,
            reader,
        })
    }

    /// Index of column `name`; `hint` (e.g. "header must contain kappa,tau,omega") is appended
    /// to the error when non-empty.
    pub fn column(&self, name: &str, hint: &str) -> Result<usize> {
        self.headers.iter().position(|h| h == name).ok_or_else(|| {
            let hint = if hint.is_empty() {
                String::new()
            } else {
                format!(" ({hint})")
            };
            self.file_error(format!("missing column `{name}`{hint}"))
        })
    }

    /// An [`Error::File`] about this file.
    pub fn file_error(&self, reason: String) -> Error {
        Error::File {
            path: self.path.clone(),
            reason,
        }
    }
}

/// The 1-based line of a CSV record in its file (counting `#` comment lines such as a settings
/// record), or `fallback` when the reader did not record a position.
pub fn line_of(rec: &csv::StringRecord, fallback: usize) -> usize {
    rec.position().map_or(fallback, |p| p.line() as usize)
}

/// An [`Error::BadLine`] for `path` at 1-based `line`.
pub fn bad_line(path: &Path, line: usize, field: &str, reason: String) -> Error {
    Error::BadLine {
        path: path.to_path_buf(),
        line,
        field: field.into(),
        reason,
    }
}

/// Parse column `col` (named `name`) of a CSV record at `line` as a number; the error names the
/// file, line, field and the offending text. Non-finite values (`inf`, `NaN`) parse; callers
/// that forbid them validate afterwards.
pub fn parse_field(
    path: &Path,
    line: usize,
    rec: &csv::StringRecord,
    col: usize,
    name: &str,
) -> Result<f64> {
    let s = rec.get(col).unwrap_or("");
    s.parse::<f64>()
        .map_err(|_| bad_line(path, line, name, format!("`{s}` is not a number")))
}
