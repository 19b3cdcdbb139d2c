//! The settings record of a sweep output: the first line of every CSV the
//! [`driver`](super::driver) writes, a `#` comment (CSV readers skip it with
//! `comment = '#'`, as [`crate::io::CsvInput`] and the plot loaders do):
//!
//! ```text
//! # helixreach-settings {"tool":"helixreach 0.1.0","sweep":"boundary","settings":{"method":"continuum","tol":"1e-10"},"columns":[…],"items":2000,"items_digest":"9f…","shard":"0/4"}
//! dir_kappa,dir_tau,dir_omega,s_star,…
//! ```
//!
//! It names what produced the rows: the tool version, the sweep, the caller's settings
//! (method, resolution, tolerance, rig digest, roll mode, margin, … as text), the columns, the
//! size and FNV-1a digest of the **whole** item set (before sharding: the key fields of every item,
//! in order), and the shard. Being inside the file, it is replaced atomically with the rows.
//!
//! - `--resume` continues a file only when its record equals the current one
//!   ([`SettingsRecord::differences`] names every mismatch);
//! - `merge` joins shard files only when their records agree except for the shard, every shard
//!   `0/N … N−1/N` is present once and in order, and the joined keys hash to `items_digest`.
//!
//! ```
//! use helixreach::sweep::record::SettingsRecord;
//! let keys = vec![vec!["1".to_string()], vec!["2".to_string()]];
//! let mut a = SettingsRecord::new("demo", &["x", "y"], &keys);
//! a.settings.insert("method".into(), "continuum".into());
//! let mut b = a.clone();
//! b.settings.insert("method".into(), "der".into());
//! assert_eq!(a.differences(&b), vec!["method: `continuum` vs `der`".to_string()]);
//! let line = a.line();
//! assert!(line.starts_with("# helixreach-settings {"));
//! assert_eq!(SettingsRecord::parse_line(&line).unwrap(), Some(a));
//! ```

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::BufRead;
use std::path::Path;

/// The prefix of the record line.
pub const PREFIX: &str = "# helixreach-settings ";

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

    /// The record line (with its trailing newline).
    pub fn line(&self) -> String {
        // Serializing a struct of strings cannot fail.
        let json = serde_json::to_string(self).unwrap_or_default();
        format!("{PREFIX}{json}\n")
    }

    /// Parse a record line: `Ok(None)` when `line` is not a record line.
    pub fn parse_line(line: &str) -> Result<Option<Self>> {
        let Some(json) = line.trim_end().strip_prefix(PREFIX) else {
            return Ok(None);
        };
        serde_json::from_str(json)
            .map(Some)
            .map_err(|e| Error::invalid("settings record", json, e.to_string()))
    }

    /// The record on the first line of `path`, `None` when the file has none.
    pub fn read(path: &Path) -> Result<Option<Self>> {
        let f = std::fs::File::open(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut first = String::new();
        std::io::BufReader::new(f)
            .read_line(&mut first)
            .map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Self::parse_line(&first).map_err(|e| Error::BadLine {
            path: path.to_path_buf(),
            line: 1,
            field: "settings record".into(),
            reason: e.to_string(),
        })
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

/// A sweep output read back: its record (if any), header and rows.
#[derive(Debug, Clone)]
pub struct SweepFile {
    /// The settings record, `None` for a CSV without one.
    pub record: Option<SettingsRecord>,
    /// The header fields.
    pub header: Vec<String>,
    /// The rows, in file order.
    pub rows: Vec<Vec<String>>,
}

impl SweepFile {
    /// Read a sweep CSV (record line optional). Errors name the file and line.
    pub fn read(path: &Path) -> Result<SweepFile> {
        let record = SettingsRecord::read(path)?;
        let file_err = |reason: String| Error::File {
            path: path.to_path_buf(),
            reason,
        };
        let mut rdr = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_path(path)
            .map_err(|e| file_err(e.to_string()))?;
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| file_err(e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let first_line = if record.is_some() { 3 } else { 2 };
        let mut rows = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            let rec = rec
                .map_err(|e| crate::io::bad_line(path, k + first_line, "record", e.to_string()))?;
            rows.push(rec.iter().map(str::to_string).collect());
        }
        Ok(SweepFile {
            record,
            header,
            rows,
        })
    }
}
