//! The input files a result depends on, each with a digest of its contents.
//!
//! A loaded robot ([`crate::robot::RobotModel::sources`]) lists every file read while loading
//! it — the URDF, its `.collision.toml` (or the fact that there is none), and whatever else the
//! loader reads (meshes, SRDF) — so a sweep can record them in its settings
//! ([`crate::sweep::record`]) and `--resume`/`merge` refuse to mix rows computed from different
//! files. A file is identified by its **name** (not its directory, so shards computed on
//! different machines still merge) and its contents by an FNV-1a 64 digest
//! ([`crate::sweep::record::fnv1a_hex`]); a file that was looked for and not found is recorded as
//! `absent`, so creating it later is a change too.
//!
//! ```
//! use helixreach::sources::{SourceFile, sources_setting};
//! let a = SourceFile::from_bytes("robots/arm.urdf", b"<robot/>");
//! let b = SourceFile::absent("robots/arm.collision.toml");
//! assert_eq!(a.name(), "arm.urdf");
//! assert_eq!(
//!     sources_setting(&[a.clone(), b]),
//!     format!("arm.urdf={} arm.collision.toml=absent", a.digest().unwrap())
//! );
//! // A different content is a different digest.
//! assert_ne!(a.digest(), SourceFile::from_bytes("arm.urdf", b"<robot />").digest());
//! ```

use crate::error::{Error, Result};
use crate::sweep::record::fnv1a_hex;
use std::path::Path;

/// One input file: where it was read from and the digest of its contents (`None` when the file
/// was looked for and does not exist).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceFile {
    path: String,
    digest: Option<String>,
}

impl SourceFile {
    /// A file whose contents are `bytes` (read from `path`, or embedded under that name).
    pub fn from_bytes(path: &str, bytes: &[u8]) -> SourceFile {
        SourceFile {
            path: path.to_string(),
            digest: Some(fnv1a_hex(bytes)),
        }
    }

    /// A file that was looked for at `path` and does not exist.
    pub fn absent(path: &str) -> SourceFile {
        SourceFile {
            path: path.to_string(),
            digest: None,
        }
    }

    /// Read `path`: its contents and its record. Errors name the file.
    pub fn read(path: &Path) -> Result<(Vec<u8>, SourceFile)> {
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let s = SourceFile::from_bytes(&path.display().to_string(), &bytes);
        Ok((bytes, s))
    }

    /// Read `path` if it exists (else an `absent` record and `None`).
    pub fn read_optional(path: &Path) -> Result<(Option<Vec<u8>>, SourceFile)> {
        match std::fs::read(path) {
            Ok(bytes) => {
                let s = SourceFile::from_bytes(&path.display().to_string(), &bytes);
                Ok((Some(bytes), s))
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                Ok((None, SourceFile::absent(&path.display().to_string())))
            }
            Err(source) => Err(Error::Io {
                path: path.to_path_buf(),
                source,
            }),
        }
    }

    /// The path as given when it was read.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// The file name (the last component of the path; the path itself when it has none).
    pub fn name(&self) -> &str {
        Path::new(&self.path)
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or(&self.path)
    }

    /// The content digest (16 hex digits), `None` for an absent file.
    pub fn digest(&self) -> Option<&str> {
        self.digest.as_deref()
    }
}

/// The settings-record text of a list of input files: `name=digest` (or `name=absent`) for each,
/// in load order, separated by spaces.
pub fn sources_setting(sources: &[SourceFile]) -> String {
    sources
        .iter()
        .map(|s| format!("{}={}", s.name(), s.digest().unwrap_or("absent")))
        .collect::<Vec<_>>()
        .join(" ")
}
