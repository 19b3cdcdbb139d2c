//! Resumable, checkpointed, deterministic parallel map over a list of items (directions, rays,
//! …), producing one CSV row per item.
//!
//! The driver is generic: the caller gives the items, a `key` function (the leading CSV fields
//! that identify an item, e.g. `dir_kappa,dir_tau,dir_omega`), a `compute` closure returning the
//! full row of an item, and [`SweepOptions`] (output path, header, resume, shard, checkpoint
//! interval, progress bar). `helixreach boundary` and `helixreach reach` are both built on it.
//!
//! # Guarantees
//! - **Parallel at the outermost level only**: items are processed in batches; each batch is a
//!   rayon `par_iter` over items (the closure itself should be sequential).
//! - **Deterministic**: rows are written in input order, and each row is a pure function of its
//!   item, so the output is bitwise identical for any thread count.
//! - **Atomic**: the output is only ever replaced with [`crate::io::write_atomic`] (temp file +
//!   rename): a reader or a crash never sees a half-written file.
//! - **Checkpointed**: every `checkpoint_interval` (and when an item fails) the rows finished so
//!   far are written to the output, in input order.
//! - **Resumable**: with `resume`, rows of an existing output whose key matches an item are kept
//!   and the item is not recomputed. Keys are compared as text, so format floats with `{}`
//!   (shortest round-trip) and they match exactly. The existing header must equal the new one.
//!   Rows of the old file whose key is not among the items are dropped (counted in the summary).
//! - **Sharding**: `shard = I/N` (0-based) keeps the contiguous block `[I·n/N, (I+1)·n/N)` of the
//!   items, so concatenating the shard outputs in shard order (`helixreach merge`) restores the
//!   input order.
//!
//! ```
//! use helixreach::sweep::driver::{run, SweepOptions};
//! let dir = tempfile::tempdir().unwrap();
//! let out = dir.path().join("squares.csv");
//! let items: Vec<u32> = (1..=5).collect();
//! let opts = SweepOptions::new(&out, &["x", "x2"], 1);
//! let summary = run(&items, |x| vec![x.to_string()], |x| Ok(vec![x.to_string(), (x * x).to_string()]), &opts)?;
//! assert_eq!(summary.computed, 5);
//! assert_eq!(std::fs::read_to_string(&out).unwrap(), "x,x2\n1,1\n2,4\n3,9\n4,16\n5,25\n");
//! # Ok::<(), helixreach::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::io::write_atomic;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::{Duration, Instant};

/// One CSV row (its fields).
pub type Row = Vec<String>;

/// A shard `I/N`: the `I`-th (0-based) of `N` contiguous blocks of the items.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which block, `0 ≤ index < count`.
    pub index: usize,
    /// How many blocks.
    pub count: usize,
}

impl Shard {
    /// A checked shard.
    pub fn new(index: usize, count: usize) -> Result<Self> {
        if count == 0 || index >= count {
            return Err(Error::invalid(
                "shard",
                format!("{index}/{count}"),
                "must be I/N with 0 <= I < N",
            ));
        }
        Ok(Shard { index, count })
    }

    /// The item range of this shard among `n` items.
    ///
    /// ```
    /// use helixreach::sweep::driver::Shard;
    /// let r: Vec<_> = (0..3).map(|i| Shard::new(i, 3).unwrap().range(10)).collect();
    /// assert_eq!(r, vec![0..3, 3..6, 6..10]);
    /// ```
    pub fn range(&self, n: usize) -> std::ops::Range<usize> {
        (self.index * n / self.count)..((self.index + 1) * n / self.count)
    }
}

impl FromStr for Shard {
    type Err = Error;
    /// Parse `I/N`.
    fn from_str(s: &str) -> Result<Self> {
        let bad = || Error::invalid("shard", s, "must be I/N with 0 <= I < N (e.g. 0/4)");
        let (a, b) = s.split_once('/').ok_or_else(bad)?;
        let i = a.trim().parse().map_err(|_| bad())?;
        let n = b.trim().parse().map_err(|_| bad())?;
        Shard::new(i, n)
    }
}

/// Options of [`run`].
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// Output CSV.
    pub out: PathBuf,
    /// The CSV header (column names).
    pub header: Vec<String>,
    /// How many leading columns form an item's key (≥ 1, ≤ header length).
    pub key_columns: usize,
    /// Keep rows of an existing output whose key matches an item instead of recomputing them.
    pub resume: bool,
    /// Process only this block of the items.
    pub shard: Option<Shard>,
    /// Minimum time between checkpoints of the output.
    pub checkpoint_interval: Duration,
    /// Show an indicatif progress bar on stderr.
    pub progress: bool,
    /// Items per parallel batch (0: automatic, about 1 % of the work, at least 64).
    pub batch: usize,
}

impl SweepOptions {
    /// Options with defaults: no resume, no shard, checkpoint every 10 s, no progress bar,
    /// automatic batch size.
    pub fn new(out: &Path, header: &[&str], key_columns: usize) -> Self {
        SweepOptions {
            out: out.to_path_buf(),
            header: header.iter().map(|s| s.to_string()).collect(),
            key_columns,
            resume: false,
            shard: None,
            checkpoint_interval: Duration::from_secs(10),
            progress: false,
            batch: 0,
        }
    }
}

/// What a [`run`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepSummary {
    /// Items selected (after sharding).
    pub total: usize,
    /// Items computed in this run.
    pub computed: usize,
    /// Items taken from the existing output (resume).
    pub resumed: usize,
    /// Rows of the existing output that matched no item and were dropped.
    pub dropped: usize,
    /// Checkpoints written before the final output.
    pub checkpoints: usize,
}

/// Read the rows of an existing output, keyed by their first `key_columns` fields.
fn read_existing(opts: &SweepOptions) -> Result<HashMap<Row, Row>> {
    let path = &opts.out;
    let file_err = |reason: String| Error::File {
        path: path.clone(),
        reason,
    };
    let mut rdr = csv::ReaderBuilder::new()
        .from_path(path)
        .map_err(|e| file_err(e.to_string()))?;
    let header: Row = rdr
        .headers()
        .map_err(|e| file_err(e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    if header != opts.header {
        return Err(file_err(format!(
            "cannot resume: its header `{}` differs from `{}`",
            header.join(","),
            opts.header.join(",")
        )));
    }
    let mut map = HashMap::new();
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| Error::BadLine {
            path: path.clone(),
            line: k + 2,
            field: "record".into(),
            reason: e.to_string(),
        })?;
        let row: Row = rec.iter().map(str::to_string).collect();
        map.insert(row[..opts.key_columns].to_vec(), row);
    }
    Ok(map)
}

/// Serialize the header and the finished rows (in input order) as CSV.
fn to_csv(header: &[String], rows: &[Option<Row>]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let ser = |e: csv::Error| Error::invalid("row", "", e.to_string());
    w.write_record(header).map_err(ser)?;
    for r in rows.iter().flatten() {
        w.write_record(r).map_err(ser)?;
    }
    w.into_inner()
        .map_err(|e| Error::invalid("row", "", e.to_string()))
}

/// Run `compute` over `items` (see the module docs), writing `opts.out`.
///
/// `key(item)` must equal the first `opts.key_columns` fields of `compute(item)`; a mismatch,
/// a row of the wrong length or a failing item is an error (after a checkpoint of the rows
/// finished so far), naming the item's key.
pub fn run<T, K, F>(items: &[T], key: K, compute: F, opts: &SweepOptions) -> Result<SweepSummary>
where
    T: Sync,
    K: Fn(&T) -> Row,
    F: Fn(&T) -> Result<Row> + Sync,
{
    let ncols = opts.header.len();
    if opts.key_columns == 0 || opts.key_columns > ncols {
        return Err(Error::invalid(
            "key_columns",
            opts.key_columns,
            format!("must be in 1..={ncols} (the header length)"),
        ));
    }
    let range = match opts.shard {
        Some(s) => s.range(items.len()),
        None => 0..items.len(),
    };
    let items = &items[range];
    let keys: Vec<Row> = items.iter().map(&key).collect();
    let mut rows: Vec<Option<Row>> = vec![None; items.len()];

    let mut resumed = 0;
    let mut dropped = 0;
    if opts.resume && opts.out.exists() {
        let existing = read_existing(opts)?;
        let mut used = std::collections::HashSet::new();
        for (slot, k) in rows.iter_mut().zip(&keys) {
            if let Some(r) = existing.get(k) {
                *slot = Some(r.clone());
                used.insert(k.clone());
                resumed += 1;
            }
        }
        dropped = existing.len() - used.len();
    }

    let todo: Vec<usize> = (0..items.len()).filter(|&i| rows[i].is_none()).collect();
    let pb = if opts.progress {
        let pb = indicatif::ProgressBar::with_draw_target(
            Some(todo.len() as u64),
            indicatif::ProgressDrawTarget::stderr(),
        );
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, eta {eta})",
        ) {
            pb.set_style(style);
        }
        pb
    } else {
        indicatif::ProgressBar::hidden()
    };

    let batch = if opts.batch > 0 {
        opts.batch
    } else {
        (todo.len() / 100).clamp(64, 8192)
    };
    let mut last_checkpoint = Instant::now();
    let mut checkpoints = 0;
    let mut computed = 0;
    for chunk in todo.chunks(batch) {
        let results: Vec<Result<Row>> = chunk
            .par_iter()
            .map(|&i| {
                let r = compute(&items[i]);
                pb.inc(1);
                r
            })
            .collect();
        let mut failure = None;
        for (&i, r) in chunk.iter().zip(results) {
            let checked = r.and_then(|row| {
                if row.len() != ncols {
                    Err(Error::invalid(
                        "row",
                        row.join(","),
                        format!("has {} fields, the header has {ncols}", row.len()),
                    ))
                } else if row[..opts.key_columns] != keys[i][..] {
                    Err(Error::invalid(
                        "row",
                        row.join(","),
                        format!("does not start with its key `{}`", keys[i].join(",")),
                    ))
                } else {
                    Ok(row)
                }
            });
            match checked {
                Ok(row) => {
                    rows[i] = Some(row);
                    computed += 1;
                }
                Err(e) if failure.is_none() => failure = Some((i, e)),
                Err(_) => {}
            }
        }
        if let Some((i, e)) = failure {
            pb.abandon();
            write_atomic(&opts.out, &to_csv(&opts.header, &rows)?)?;
            return Err(Error::Item {
                key: keys[i].join(","),
                cause: Box::new(e),
            });
        }
        if last_checkpoint.elapsed() >= opts.checkpoint_interval && computed < todo.len() {
            write_atomic(&opts.out, &to_csv(&opts.header, &rows)?)?;
            checkpoints += 1;
            last_checkpoint = Instant::now();
        }
    }
    pb.finish_and_clear();
    write_atomic(&opts.out, &to_csv(&opts.header, &rows)?)?;
    Ok(SweepSummary {
        total: items.len(),
        computed,
        resumed,
        dropped,
        checkpoints,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parse_and_cover() {
        assert!("3/3".parse::<Shard>().is_err());
        assert!("a/3".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        let n = 17;
        let mut all = vec![];
        for i in 0..4 {
            all.extend(format!("{i}/4").parse::<Shard>().unwrap().range(n));
        }
        assert_eq!(all, (0..n).collect::<Vec<_>>());
    }
}
