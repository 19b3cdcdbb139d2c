//! Join the shard outputs of a sweep (`--shard I/N`, see [`super::driver`]) into the output of
//! the whole item set, refusing anything that is not exactly that:
//!
//! - every input has its [`SettingsRecord`] (its sidecar `F.meta.json`, [`super::record`]);
//!   the records agree except for the shard; each input is read once (a FIFO works) and every
//!   row is parsed and checked by its columns' rules, as a computed row is;
//! - the inputs are the shards `0/N, 1/N, …, N−1/N`, each once, in that order (a missing,
//!   repeated or misplaced shard is named);
//! - each shard holds exactly its block's number of rows (`Shard::range(items)`), no key twice;
//! - the joined keys hash to the record's `items_digest` (the rows are those of the whole set,
//!   in order).
//!
//! The merged file carries the common record with no shard — the same record a single
//! unsharded run writes, so it can be resumed or compared. It is written like a sweep output:
//! locked, atomically with its sidecar, and an existing output is replaced only with `force`
//! (never one of the inputs); `-` streams the plain CSV to standard output.

use super::driver::Shard;
use super::record::{keys_digest, SettingsRecord, SweepFile};
use crate::error::{Error, Result};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// What [`merge`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MergeSummary {
    /// Rows written.
    pub rows: usize,
    /// Shard files joined.
    pub shards: usize,
}

fn file_err(path: &Path, reason: String) -> Error {
    Error::File {
        path: path.to_path_buf(),
        reason,
    }
}

/// Merge the shard files `inputs` (in shard order) into `out` (see the module docs).
/// `key_columns` leading fields identify a row; every row is checked by its column's rule in
/// [`crate::records::columns::COLUMNS`].
pub fn merge(
    inputs: &[PathBuf],
    key_columns: usize,
    out: &Path,
    force: bool,
) -> Result<MergeSummary> {
    merge_with(inputs, key_columns, out, force, None)
}

/// [`merge`] with the columns' rules `cols` (one per column, for a sweep whose columns are not
/// in [`crate::records::columns::COLUMNS`]; `None`: those).
pub fn merge_with(
    inputs: &[PathBuf],
    key_columns: usize,
    out: &Path,
    force: bool,
    cols: Option<&[crate::records::columns::Column]>,
) -> Result<MergeSummary> {
    if inputs.is_empty() {
        return Err(Error::invalid("inputs", 0, "give the shard files to merge"));
    }
    for p in inputs {
        if crate::io::same_path(out, p) {
            return Err(file_err(
                out,
                format!(
                    "is an input of this merge ({}); refusing to overwrite it, even with --force",
                    p.display()
                ),
            ));
        }
    }
    let streaming = crate::io::is_stdout(out) || crate::io::is_special(out);
    let _lock = if streaming {
        None
    } else {
        crate::io::check_output(out)?;
        let lock = crate::io::OutputLock::acquire(out)?;
        let sidecar = crate::io::sidecar_path(out);
        if (out.exists() || sidecar.exists()) && !force {
            return Err(file_err(
                out,
                "already exists; refusing to overwrite it (--force replaces it)".into(),
            ));
        }
        Some(lock)
    };
    let mut common: Option<(SettingsRecord, Vec<String>)> = None;
    let mut keys: Vec<Vec<String>> = Vec::new();
    let mut seen = HashSet::new();
    let mut all_rows = Vec::new();
    let mut count = None;
    for (k, p) in inputs.iter().enumerate() {
        let f = SweepFile::read(p, cols)?;
        let rec = f.record;
        let shard: Shard = match &rec.shard {
            Some(s) => s.parse()?,
            None => {
                return Err(file_err(
                    p,
                    "is not a shard output (its settings record has no shard)".into(),
                ))
            }
        };
        let n = *count.get_or_insert(shard.count);
        if shard.count != n {
            return Err(file_err(
                p,
                format!("is shard {shard}, but the first input is one of {n} shards"),
            ));
        }
        if shard.index != k {
            return Err(file_err(
                p,
                format!(
                    "is shard {shard}, expected {k}/{n} at position {} (give every shard 0/{n} \
                     … {}/{n} once, in order)",
                    k + 1,
                    n - 1
                ),
            ));
        }
        if key_columns == 0 || key_columns > f.header.len() {
            return Err(Error::invalid(
                "key_columns",
                key_columns,
                format!("must be in 1..={} (the header length)", f.header.len()),
            ));
        }
        let mut unsharded = rec.clone();
        unsharded.shard = None;
        match &common {
            None => common = Some((unsharded, f.header.clone())),
            Some((r0, h0)) => {
                if *h0 != f.header {
                    return Err(file_err(
                        p,
                        format!(
                            "header `{}` differs from `{}` of {}",
                            f.header.join(","),
                            h0.join(","),
                            inputs[0].display()
                        ),
                    ));
                }
                let d = r0.differences(&unsharded);
                if !d.is_empty() {
                    return Err(file_err(
                        p,
                        format!(
                            "was made with other settings than {} ({} vs this file): {}",
                            inputs[0].display(),
                            inputs[0].display(),
                            d.join("; ")
                        ),
                    ));
                }
            }
        }
        let expected = shard.range(rec.items).len();
        if f.rows.len() != expected {
            return Err(file_err(
                p,
                format!(
                    "shard {shard} of {} items must hold {expected} rows, it holds {} \
                     (unfinished?)",
                    rec.items,
                    f.rows.len()
                ),
            ));
        }
        for (j, row) in f.rows.into_iter().enumerate() {
            let key: Vec<String> = row.iter().take(key_columns).cloned().collect();
            if !seen.insert(key.clone()) {
                return Err(crate::io::bad_line(
                    p,
                    j + 2,
                    "key",
                    format!(
                        "`{}` already present in an earlier input (overlapping shards?)",
                        key.join(",")
                    ),
                ));
            }
            keys.push(key);
            all_rows.push(row);
        }
    }
    let (rec, header) = common.ok_or_else(|| Error::invalid("inputs", 0, "no input"))?;
    let n = count.unwrap_or(0);
    if inputs.len() != n {
        return Err(Error::invalid(
            "inputs",
            inputs.len(),
            format!(
                "the inputs are shards of {n}: missing {}",
                (inputs.len()..n)
                    .map(|i| format!("{i}/{n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    if keys_digest(&keys) != rec.items_digest {
        return Err(Error::invalid(
            "inputs",
            inputs.len(),
            "the joined keys are not the sweep's item set in order (digest mismatch)",
        ));
    }
    debug_assert_eq!(header, rec.columns);
    let cols = match cols {
        Some(c) => c.to_vec(),
        None => crate::records::columns::columns_of(&rec.columns),
    };
    SweepFile::write(out, &rec, &cols, &all_rows)?;
    Ok(MergeSummary {
        rows: all_rows.len(),
        shards: inputs.len(),
    })
}
