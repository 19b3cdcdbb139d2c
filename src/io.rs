//! File output shared by every command: atomic writes (temp file in the same directory, then
//! rename, so a reader never sees a half-written file and a crash never destroys the old one).

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
    let tmp = temp_path(path);
    {
        let mut f = std::fs::File::create(&tmp).map_err(io)?;
        f.write_all(bytes).map_err(io)?;
        f.sync_all().map_err(io)?;
    }
    std::fs::rename(&tmp, path).map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    /// Open `path` (fields trimmed) and read its header.
    pub fn open(path: &Path) -> Result<Self> {
        let file_err = |e: csv::Error| Error::File {
            path: path.to_path_buf(),
            reason: e.to_string(),
        };
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_path(path)
            .map_err(file_err)?;
        let headers = reader.headers().map_err(file_err)?.clone();
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
