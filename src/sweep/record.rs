//! The settings record of a sweep output, kept in the sidecar `F.meta.json` beside the CSV `F`
//! (which is plain CSV: its first line is the header):
//!
//! ```text
//! {"tool":"helixreach 0.1.0","sweep":"boundary","settings":{"method":"continuum","tol":"1e-10"},
//!  "columns":[…],"items":2000,"items_digest":"9f…","shard":"0/4",
//!  "column_units":[{"name":"dir_kappa","unit":"1","meaning":"…"},…],
//!  "csv":{"rows":500,"bytes":61234,"fnv1a":"0c…"}}
//! ```
//!
//! It names what produced the rows: the tool version, the sweep, the caller's settings
//! (method, resolution, tolerance, rig digest, roll mode, margin, … as text), the columns, the
//! size and FNV-1a digest of the **whole** item set (before sharding: the key fields of every item,
//! in order), and the shard; then each column's unit and meaning
//! ([`crate::records::columns`]), and the size, row count and FNV-1a digest of the CSV it
//! describes. The sidecar is written atomically just before its CSV; a CSV whose bytes do not
//! match its sidecar's digest (an interrupted replacement, an edit) is refused, naming both files.
//!
//! - `--resume` continues a file only when its record equals the current one
//!   ([`SettingsRecord::differences`] names every mismatch);
//! - `merge` joins shard files only when their records agree except for the shard, every shard
//!   `0/N … N−1/N` is present once and in order, and the joined keys hash to `items_digest`;
//! - both read every row back through [`SweepFile::read`], which parses and checks each field
//!   by its column's rule ([`crate::records::columns`]), as a computed row is checked.
//!
//! ```
//! use helixreach::sweep::record::{SettingsRecord, SweepFile};
//! let keys = vec![vec!["1".to_string()], vec!["2".to_string()]];
//! let mut a = SettingsRecord::new("demo", &["candidate", "s_star"], &keys);
//! a.settings.insert("method".into(), "continuum".into());
//! let mut b = a.clone();
//! b.settings.insert("method".into(), "der".into());
//! assert_eq!(a.differences(&b), vec!["method: `continuum` vs `der`".to_string()]);
//! let dir = tempfile::tempdir().unwrap();
//! let out = dir.path().join("o.csv");
//! let rows = vec![vec!["1".to_string(), "6.5".to_string()]];
//! let cols = helixreach::records::columns::columns_of(&a.columns);
//! SweepFile::write(&out, &a, &cols, &rows)?;
//! assert_eq!(std::fs::read_to_string(&out).unwrap(), "candidate,s_star\n1,6.5\n");
//! let back = SweepFile::read(&out, None)?;
//! assert_eq!((back.record, back.rows), (a, rows));
//! # Ok::<(), helixreach::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::records::columns::{check_known, check_row_with, columns_of, Column};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// What produced a sweep output (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SettingsRecord {
    /// `helixreach <version>`.
    pub tool: String,
    /// The sweep (`boundary`, `reach`, …).
    pub sweep: String,
    /// The caller's settings, as text (method, tolerance, rig digest, …).
    pub settings: BTreeMap<String, String>,
    /// The CSV columns.
    pub columns: Vec<String>,
    /// Number of items of the whole set (before sharding).
    pub items: usize,
    /// FNV-1a 64 digest of the key fields of every item of the whole set, in order.
    pub items_digest: String,
    /// The shard `I/N`, if the output holds one block of the items.
    pub shard: Option<String>,
}

/// The tool name and version written in records.
pub fn tool_version() -> String {
    format!("helixreach {}", env!("CARGO_PKG_VERSION"))
}

/// FNV-1a 64-bit hash of `bytes`, as 16 hex digits (a content digest, not a security one).
///
/// ```
/// assert_eq!(helixreach::sweep::record::fnv1a_hex(b""), "cbf29ce484222325");
/// assert_eq!(helixreach::sweep::record::fnv1a_hex(b"a"), "af63dc4c8601ec8c");
/// ```
pub fn fnv1a_hex(bytes: &[u8]) -> String {
    let mut h = Fnv::new();
    h.write(bytes);
    h.hex()
}

/// Incremental FNV-1a 64.
#[derive(Debug, Clone, Copy)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

/// The digest of a list of item keys (fields joined by `,`, keys by `\n`).
pub fn keys_digest<'a>(keys: impl IntoIterator<Item = &'a Vec<String>>) -> String {
    let mut h = Fnv::new();
    for k in keys {
        for (i, f) in k.iter().enumerate() {
            if i > 0 {
                h.write(b",");
            }
            h.write(f.as_bytes());
        }
        h.write(b"\n");
    }
    h.hex()
}

impl SettingsRecord {
    /// A record for `sweep` with `columns` over the whole item set whose keys are `keys`; no
    /// settings, no shard.
    pub fn new(sweep: &str, columns: &[&str], keys: &[Vec<String>]) -> Self {
        SettingsRecord {
            tool: tool_version(),
            sweep: sweep.to_string(),
            settings: BTreeMap::new(),
            columns: columns.iter().map(|s| s.to_string()).collect(),
            items: keys.len(),
            items_digest: keys_digest(keys),
            shard: None,
        }
    }

    /// The record of the CSV output `path`, read from its sidecar (`path.meta.json`); `None`
    /// when there is no sidecar.
    pub fn read(path: &Path) -> Result<Option<Self>> {
        let sidecar = crate::io::sidecar_path(path);
        if std::fs::symlink_metadata(&sidecar).is_err() {
            return Ok(None);
        }
        Sidecar::read(path, &sidecar).map(|s| Some(s.record))
    }

    /// Every field that differs from `other`, as `name: \`mine\` vs \`other's\``.
    pub fn differences(&self, other: &SettingsRecord) -> Vec<String> {
        let mut d = Vec::new();
        let mut cmp = |name: &str, a: String, b: String| {
            if a != b {
                d.push(format!("{name}: `{a}` vs `{b}`"));
            }
        };
        cmp("tool", self.tool.clone(), other.tool.clone());
        cmp("sweep", self.sweep.clone(), other.sweep.clone());
        let keys: std::collections::BTreeSet<&String> =
            self.settings.keys().chain(other.settings.keys()).collect();
        for k in keys {
            let get = |m: &BTreeMap<String, String>| m.get(k).cloned().unwrap_or("(unset)".into());
            cmp(k, get(&self.settings), get(&other.settings));
        }
        cmp("header", self.columns.join(","), other.columns.join(","));
        cmp("items", self.items.to_string(), other.items.to_string());
        cmp(
            "items_digest (the direction set)",
            self.items_digest.clone(),
            other.items_digest.clone(),
        );
        let shard = |s: &Option<String>| s.clone().unwrap_or("none".into());
        cmp("shard", shard(&self.shard), shard(&other.shard));
        d
    }
}

/// One column's unit and meaning, as the sidecar lists them.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ColumnUnit {
    /// Column name.
    pub name: String,
    /// Unit (`1`: nondimensional; empty: text or a count).
    pub unit: String,
    /// What the column holds.
    pub meaning: String,
}

/// Size, rows and digest of the CSV a sidecar describes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CsvDigest {
    /// Data rows (after the header).
    pub rows: usize,
    /// Bytes of the whole file.
    pub bytes: u64,
    /// FNV-1a 64 of the whole file.
    pub fnv1a: String,
}

/// The sidecar `F.meta.json` of a sweep output `F` (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sidecar {
    /// What produced the rows.
    #[serde(flatten)]
    pub record: SettingsRecord,
    /// Every column's unit and meaning, in column order.
    pub column_units: Vec<ColumnUnit>,
    /// The CSV this sidecar belongs to.
    pub csv: CsvDigest,
}

impl Sidecar {
    /// The sidecar of `record` (its columns' rules `cols`) for the CSV `bytes` holding `rows`
    /// data rows.
    pub fn new(
        record: &SettingsRecord,
        cols: &[Column],
        rows: usize,
        bytes: &[u8],
    ) -> Result<Self> {
        check_known(&record.columns, cols)
            .map_err(|e| Error::invalid("columns", record.columns.join(","), e))?;
        Ok(Sidecar {
            record: record.clone(),
            column_units: record
                .columns
                .iter()
                .zip(cols)
                .map(|(name, c)| ColumnUnit {
                    name: name.clone(),
                    unit: c.unit.into(),
                    meaning: c.meaning.into(),
                })
                .collect(),
            csv: CsvDigest {
                rows,
                bytes: bytes.len() as u64,
                fnv1a: fnv1a_hex(bytes),
            },
        })
    }

    /// The JSON text (pretty, with a final newline).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self)
            .map(|s| s + "\n")
            .map_err(|e| Error::invalid("settings record", "", e.to_string()))
    }

    /// Read the sidecar `sidecar` of the CSV `csv` (errors name both).
    fn read(csv: &Path, sidecar: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(sidecar).map_err(|source| Error::Io {
            path: sidecar.to_path_buf(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|e| Error::File {
            path: sidecar.to_path_buf(),
            reason: format!(
                "is not the settings record of {} ({e}); refusing to use it",
                csv.display()
            ),
        })
    }
}

/// A sweep output read back: its record, header and rows.
#[derive(Debug, Clone)]
pub struct SweepFile {
    /// The settings record (from the sidecar).
    pub record: SettingsRecord,
    /// The header fields.
    pub header: Vec<String>,
    /// The rows, in file order.
    pub rows: Vec<Vec<String>>,
}

/// The plain CSV text of `header` and `rows`.
pub fn csv_bytes<'a>(
    header: &[String],
    rows: impl IntoIterator<Item = &'a Vec<String>>,
) -> Result<Vec<u8>> {
    let ser = |e: csv::Error| Error::invalid("row", "", e.to_string());
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header).map_err(ser)?;
    for r in rows {
        w.write_record(r).map_err(ser)?;
    }
    w.into_inner()
        .map_err(|e| Error::invalid("row", "", e.to_string()))
}

impl SweepFile {
    /// Read a sweep CSV and its sidecar, each once (so `path` may be a FIFO). Refused, naming
    /// both files: a CSV without its sidecar, a sidecar whose digest or header does not match
    /// the CSV; naming the file, line and column: a row that breaks its column's rule
    /// (`cols`, one per column; `None`: those of [`crate::records::columns::COLUMNS`]).
    pub fn read(path: &Path, cols: Option<&[Column]>) -> Result<SweepFile> {
        let sidecar = crate::io::sidecar_path(path);
        let both = |reason: String| Error::File {
            path: path.to_path_buf(),
            reason: format!("{reason} (settings record {})", sidecar.display()),
        };
        if std::fs::symlink_metadata(&sidecar).is_err() {
            return Err(both(
                "has no settings record beside it, so what produced its rows cannot be checked; \
                 refusing it"
                    .into(),
            ));
        }
        let meta = Sidecar::read(path, &sidecar)?;
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        if bytes.len() as u64 != meta.csv.bytes || fnv1a_hex(&bytes) != meta.csv.fnv1a {
            return Err(both(format!(
                "does not match its settings record: {} bytes, digest {}, where the record \
                 says {} bytes, digest {} (an interrupted replacement or an edited file); \
                 refusing it",
                bytes.len(),
                fnv1a_hex(&bytes),
                meta.csv.bytes,
                meta.csv.fnv1a
            )));
        }
        let mut rdr = csv::ReaderBuilder::new().from_reader(bytes.as_slice());
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| both(e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        if header != meta.record.columns {
            return Err(both(format!(
                "has header `{}`, its settings record says `{}`",
                header.join(","),
                meta.record.columns.join(",")
            )));
        }
        let cols = match cols {
            Some(c) => c.to_vec(),
            None => columns_of(&header),
        };
        check_known(&header, &cols).map_err(both)?;
        let mut rows = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            let line = rec
                .as_ref()
                .ok()
                .and_then(|r| r.position())
                .map_or(k + 2, |p| p.line() as usize);
            let bad = |reason: String| crate::io::bad_line(path, line, "row", reason);
            let rec = rec.map_err(|e| bad(e.to_string()))?;
            let row: Vec<String> = rec.iter().map(str::to_string).collect();
            check_row_with(&header, &cols, &row).map_err(bad)?;
            rows.push(row);
        }
        if rows.len() != meta.csv.rows {
            return Err(both(format!(
                "holds {} rows, its settings record says {}",
                rows.len(),
                meta.csv.rows
            )));
        }
        Ok(SweepFile {
            record: meta.record,
            header,
            rows,
        })
    }

    /// Write `rows` under `record`'s columns as the sweep output `path`: a regular file gets its
    /// sidecar (written atomically, just before the CSV, itself written atomically); standard
    /// output (`-`) and an existing device or FIFO get the plain CSV only, in place. Every row
    /// is checked by its column's rule first. No overwrite or lock checks: the callers hold the
    /// output's lock.
    pub fn write<'a, I>(
        path: &Path,
        record: &SettingsRecord,
        cols: &[Column],
        rows: I,
    ) -> Result<()>
    where
        I: IntoIterator<Item = &'a Vec<String>>,
        I::IntoIter: Clone,
    {
        let rows = rows.into_iter();
        check_known(&record.columns, cols)
            .map_err(|e| Error::invalid("columns", record.columns.join(","), e))?;
        for row in rows.clone() {
            check_row_with(&record.columns, cols, row)
                .map_err(|e| Error::invalid("row", row.join(","), e))?;
        }
        let bytes = csv_bytes(&record.columns, rows.clone())?;
        if crate::io::is_stdout(path) {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            return out
                .write_all(&bytes)
                .and_then(|()| out.flush())
                .map_err(|source| Error::Io {
                    path: path.to_path_buf(),
                    source,
                });
        }
        if crate::io::is_special(path) {
            return crate::io::write_in_place(path, &bytes);
        }
        let meta = Sidecar::new(record, cols, rows.count(), &bytes)?;
        crate::io::write_atomic(&crate::io::sidecar_path(path), meta.to_json()?.as_bytes())?;
        crate::io::write_atomic(path, &bytes)
    }

    /// Remove the sweep output `path` and its sidecar (absent files are fine).
    pub fn remove(path: &Path) -> Result<()> {
        for p in [path.to_path_buf(), crate::io::sidecar_path(path)] {
            match std::fs::remove_file(&p) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(Error::Io { path: p, source: e })
                }
                _ => {}
            }
        }
        Ok(())
    }
}
