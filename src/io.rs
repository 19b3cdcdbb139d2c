//! The one writer of every file a command writes, and the CSV input helpers.
//!
//! # What each output kind gets
//! - **A regular file** (new or existing): written atomically — a temp file `NAME.<pid>.tmp` in
//!   the same directory, created with `O_CREAT|O_EXCL|O_NOFOLLOW` (a planted symlink or file at
//!   that name is never followed nor truncated), written, fsynced, renamed over `NAME`. A reader
//!   never sees a half-written file; a failure (a full disk, a signal) removes the temp file and
//!   leaves the previous file untouched. Temp files of killed processes are removed.
//! - **An existing device or FIFO** (`/dev/null`, a named pipe, a terminal): written in place,
//!   never replaced by a regular file.
//! - **`-`**: standard output (a binary format such as PNG is refused there with a clear error).
//!
//! [`Output`] adds what a command's `--out` needs on top of that: no overwrite of an existing
//! file without `--force`; never onto one of the command's own inputs (even with `--force`),
//! nor onto a sweep output that has a settings record (`F.meta.json`), nor onto a path whose
//! lock (`NAME.lock`, see [`OutputLock`]) a running writer holds; and every check made once
//! before computing ([`Output::check`]) and again when writing.
//!
//! Lock, probe and temp files are created with `O_NOFOLLOW` (and the probe and temp files with
//! `O_EXCL`): a symlink planted at `NAME.lock` or `NAME.<pid>.tmp` is refused or replaced,
//! never followed.

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

/// Create `path` as a new regular file (`O_CREAT|O_EXCL|O_NOFOLLOW`, mode 0666 less the umask):
/// never opens an existing file or follows a symlink at `path`.
pub fn create_new(path: &Path) -> std::io::Result<std::fs::File> {
    let mut o = std::fs::OpenOptions::new();
    o.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(libc::O_NOFOLLOW);
    }
    o.open(path)
}

/// [`create_new`] of a temp path that belongs to this process (its name holds our pid): an
/// entry already there (left by a dead process of the same pid, or planted) is unlinked — never
/// followed — and the creation tried once more.
fn create_temp(tmp: &Path) -> std::io::Result<std::fs::File> {
    match create_new(tmp) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            std::fs::remove_file(tmp)?;
            create_new(tmp)
        }
        r => r,
    }
}

/// Write `bytes` to `path` atomically (see the module docs): a temp file created exclusively,
/// fsynced, renamed over `path`; on any failure the temp file is removed and `path` is
/// untouched. An existing device or FIFO at `path` is written in place instead. Parent
/// directories are created. No overwrite checks: commands use [`Output`].
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let p = dir.path().join("a.txt");
/// helixreach::io::write_atomic(&p, b"hello").unwrap();
/// assert_eq!(std::fs::read(&p).unwrap(), b"hello");
/// ```
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    if is_special(path) {
        return write_in_place(path, bytes);
    }
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
    let f = create_temp(&tmp).map_err(|source| Error::Io {
        path: tmp.clone(),
        source,
    })?;
    let written = write_sync(f, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(e));
    }
    Ok(())
}

/// Write all of `bytes` into `f` and fsync it (the file is closed on return).
fn write_sync(mut f: std::fs::File, bytes: &[u8]) -> std::io::Result<()> {
    f.write_all(bytes)?;
    f.sync_all()
}

/// Write `bytes` into the existing non-regular file `path` (a device, a FIFO) in place: opened
/// for writing without creating or truncating it.
pub fn write_in_place(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(io)?;
    f.write_all(bytes).and_then(|()| f.flush()).map_err(io)
}

/// The sidecar of a CSV output `F`: `F.meta.json` beside it, holding the settings record and
/// the columns with their units.
pub fn sidecar_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".meta.json");
    path.with_file_name(name)
}

/// A command's output file (see the module docs): the path, whether an existing file may be
/// replaced (`--force`), the command's inputs (never written onto), and whether the format is
/// binary (refused on standard output).
///
/// ```
/// use helixreach::io::Output;
/// let dir = tempfile::tempdir().unwrap();
/// let input = dir.path().join("m.csv");
/// std::fs::write(&input, "x\n1\n").unwrap();
/// // Never onto an input, even with --force.
/// let e = Output::new(&input).force(true).input(&input).check().unwrap_err();
/// assert!(e.to_string().contains("is an input"), "{e}");
/// // No overwrite without --force.
/// let out = dir.path().join("o.csv");
/// Output::new(&out).write(b"a\n").unwrap();
/// assert!(Output::new(&out).write(b"b\n").is_err());
/// Output::new(&out).force(true).write(b"b\n").unwrap();
/// assert_eq!(std::fs::read(&out).unwrap(), b"b\n");
/// ```
#[derive(Debug, Clone)]
pub struct Output {
    path: PathBuf,
    force: bool,
    inputs: Vec<PathBuf>,
    binary: Option<&'static str>,
}

/// What an output path is.
enum Target {
    Stdout,
    Special,
    File,
}

impl Output {
    /// An output at `path` (`-`: standard output); no `--force`, no inputs, text format.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Output {
            path: path.into(),
            force: false,
            inputs: Vec::new(),
            binary: None,
        }
    }

    /// Allow replacing an existing file (`--force`).
    pub fn force(mut self, force: bool) -> Self {
        self.force = force;
        self
    }

    /// A file the command reads: never written onto, even with `--force`.
    pub fn input(mut self, path: &Path) -> Self {
        self.inputs.push(path.to_path_buf());
        self
    }

    /// The format is binary (e.g. `"a PNG image"`): refused on standard output.
    pub fn binary(mut self, what: &'static str) -> Self {
        self.binary = Some(what);
        self
    }

    /// The output path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn err(&self, reason: String) -> Error {
        Error::File {
            path: self.path.clone(),
            reason,
        }
    }

    fn target(&self) -> Result<Target> {
        if is_stdout(&self.path) {
            if let Some(what) = self.binary {
                return Err(self.err(format!(
                    "{what} cannot be written to standard output; give a file"
                )));
            }
            return Ok(Target::Stdout);
        }
        for input in &self.inputs {
            if same_path(&self.path, input) {
                return Err(self.err(format!(
                    "is an input of this command ({}); refusing to overwrite it, even with --force",
                    input.display()
                )));
            }
        }
        if is_special(&self.path) {
            return Ok(Target::Special);
        }
        let exists = std::fs::symlink_metadata(&self.path).is_ok();
        if exists && !self.force {
            return Err(self.err(
                "already exists; refusing to overwrite it (give --force to replace it)".into(),
            ));
        }
        let sidecar = sidecar_path(&self.path);
        if exists && is_sweep_record(&sidecar) {
            return Err(self.err(format!(
                "is a finished sweep output (its settings record {} exists); refusing to \
                 replace it, even with --force: remove both files first or give another path",
                sidecar.display()
            )));
        }
        check_output(&self.path)?;
        Ok(Target::File)
    }

    /// Every check of a write (see the module docs), without writing: call it before computing.
    pub fn check(&self) -> Result<()> {
        if let Target::File = self.target()? {
            // A running writer holds the lock: refused now, not after the computation.
            drop(OutputLock::acquire(&self.path)?);
        }
        Ok(())
    }

    /// Write `bytes` (checked again first): to standard output, in place into a device or
    /// FIFO, or atomically into a regular file under its [`OutputLock`].
    pub fn write(&self, bytes: &[u8]) -> Result<()> {
        self.write_impl(bytes, None)
    }

    /// [`Output::write`], and for a regular file its sidecar `F.meta.json` ([`sidecar_path`])
    /// holding `meta`, written atomically just before it under the same lock (standard output,
    /// devices and FIFOs get `bytes` only).
    pub fn write_with_sidecar(&self, bytes: &[u8], meta: &[u8]) -> Result<()> {
        self.write_impl(bytes, Some(meta))
    }

    fn write_impl(&self, bytes: &[u8], meta: Option<&[u8]>) -> Result<()> {
        match self.target()? {
            Target::Stdout => {
                let mut out = std::io::stdout().lock();
                out.write_all(bytes)
                    .and_then(|()| out.flush())
                    .map_err(|source| Error::Io {
                        path: self.path.clone(),
                        source,
                    })
            }
            Target::Special => write_in_place(&self.path, bytes),
            Target::File => {
                let _lock = OutputLock::acquire(&self.path)?;
                if let Some(meta) = meta {
                    write_atomic(&sidecar_path(&self.path), meta)?;
                }
                write_atomic(&self.path, bytes)
            }
        }
    }
}

/// Whether `path` is the settings record of a sweep output (a JSON object with an
/// `items_digest`, see `crate::sweep::record`): such an output is a finished result that only
/// its sweep (`--force`) replaces.
fn is_sweep_record(path: &Path) -> bool {
    let Ok(f) = std::fs::File::open(path) else {
        return false;
    };
    if !f.metadata().is_ok_and(|m| m.is_file()) {
        return false;
    }
    // A record is a few kB; a larger file is read only so far.
    let mut text = String::new();
    let _ = std::io::Read::read_to_string(&mut std::io::Read::take(f, 1 << 20), &mut text);
    serde_json::from_str::<serde_json::Value>(&text).is_ok_and(|v| v.get("items_digest").is_some())
}

/// Whether `a` and `b` name the same existing file (same device and inode; elsewhere: equal
/// canonical paths).
pub fn same_path(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
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
    // The probe is created exclusively and never through a symlink, and removed at once.
    let probe = temp_path(path);
    create_temp(&probe).map_err(|e| err(format!("cannot write in its directory: {e}")))?;
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
            let mut file = open_lock_file(&lock_path).map_err(io)?;
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

/// Open (creating it if absent) the lock file at `path` without following a symlink there
/// (`O_NOFOLLOW`; a new one is created with `O_EXCL`), and check that it is a regular file with
/// a single link: a planted symlink, FIFO, device or hard link to another file is refused, so
/// the lock never truncates or blocks on anything but its own file.
fn open_lock_file(path: &Path) -> std::io::Result<std::fs::File> {
    let mut o = std::fs::OpenOptions::new();
    o.read(true).write(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    let file = match o.clone().create_new(true).open(path) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => o.open(path),
        r => r,
    }
    .map_err(|e| {
        if e.raw_os_error() == Some(ELOOP) {
            std::io::Error::other("is a symbolic link; a lock file is never followed")
        } else {
            e
        }
    })?;
    let m = file.metadata()?;
    #[cfg(unix)]
    let single = {
        use std::os::unix::fs::MetadataExt;
        m.nlink() == 1
    };
    #[cfg(not(unix))]
    let single = true;
    if !m.is_file() || !single {
        return Err(std::io::Error::other(
            "is not a regular file with a single link; refusing to use it as a lock",
        ));
    }
    Ok(file)
}

#[cfg(unix)]
const ELOOP: i32 = libc::ELOOP;
#[cfg(not(unix))]
const ELOOP: i32 = -1;

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
    /// Open `path` (fields trimmed, `#` comment lines skipped) and read its header.
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
