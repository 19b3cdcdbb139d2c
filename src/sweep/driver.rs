//! Resumable, checkpointed, deterministic parallel map over a list of items (directions, rays,
//! …), producing one CSV row per item — the engine of every sweep (`boundary`, `reach`,
//! `bifurcation`, `layout`, …).
//!
//! The caller gives the items, a `key` function (the leading CSV fields that identify an item,
//! e.g. `dir_kappa,dir_tau,dir_omega`), a `compute` closure returning the item's record (any
//! `Serialize` row: a record of [`crate::records`] such as `ReachRecord`, or the fields as a
//! `Vec<String>`; its fields in header order), and [`SweepOptions`]: output path, header, the **settings** that produce the rows (see
//! [`SweepOptions::setting`]), resume/force, shard, checkpoint interval, progress.
//!
//! # Guarantees (the data-safety rules)
//! - **A finished result is never replaced by less.** The output file is written only once,
//!   atomically ([`crate::io::write_atomic`]), when every item of the run is done. Checkpoints
//!   go to the sibling `OUT.partial` ([`partial_path`]), removed when the output is complete. A
//!   failed or killed run leaves the previous output untouched.
//! - **Existing outputs are not overwritten unless asked.** If `OUT` or `OUT.partial` exists, the
//!   run is refused unless `resume` (continue it) or `force` (replace it, once complete) is set.
//!   Replacing an output that was made with *different* settings always needs `force`.
//! - **Every output records its settings** in its sidecar `OUT.meta.json`
//!   ([`SettingsRecord`], [`super::record`]): tool version, sweep name, the caller's settings,
//!   columns (with units), size and digest of the whole item set, shard, and the digest of the
//!   CSV. The CSV itself is plain: its first line is the header. `resume` continues
//!   `OUT.partial` (else `OUT`) only when its record equals the current one, listing every
//!   difference otherwise; every row read back is checked as a computed row is (its fields by
//!   their columns' rules, [`crate::records::columns`]); a row whose key is not an item of the
//!   run, or a duplicate key, is refused (never dropped).
//! - **One writer per output.** An exclusive [`OutputLock`] is held for
//!   the whole run; a second writer fails at once with a clear error. Temp files of killed
//!   runs (`OUT.<pid>.tmp`) are removed.
//! - **Outputs are checked before computing**: the lock file is created beside the output, so a
//!   missing or read-only directory fails before the first item.
//! - **Checkpoints honour the interval**: each batch runs until a deadline a quarter of
//!   `checkpoint_interval` away (≥ 20 ms, ≤ 2 s) — workers claim items in input order and stop
//!   claiming at the deadline, so a batch is a prefix of the remaining items whatever they cost —
//!   and the first checkpoint comes within about 1.25 × the interval (plus one item's time), also
//!   when cheap items are followed by costly ones.
//! - **Parallel at the outermost level only** (rayon workers over the items of a batch, as many
//!   as [`SweepOptions::par`] gives: [`crate::par::Par`], applied to every batch) and
//!   **deterministic**: rows are in input order and each row is a pure function of its item, so
//!   the output is identical for any thread count.
//! - **Standard output and devices**: `OUT = -` streams the header and rows (plain CSV, no
//!   sidecar) to stdout in
//!   input order as batches finish; an existing non-regular `OUT` (`/dev/stdout`, a FIFO) is
//!   written in place the same way, never replaced by a rename. Neither can be resumed.
//! - **Sharding**: `shard = I/N` (0-based) keeps the contiguous block `[I·n/N, (I+1)·n/N)` of
//!   the items; `helixreach merge` ([`super::merge`]) joins the shard files after checking they
//!   are complete, in order and made with equal settings.
//! - **Progress** on stderr when `progress` is set: a bar on a terminal, else a line every 10 s
//!   and at every checkpoint.
//!
//! ```
//! use helixreach::sweep::driver::{run, SweepOptions};
//! let dir = tempfile::tempdir().unwrap();
//! let out = dir.path().join("squares.csv");
//! let items: Vec<u32> = (1..=5).collect();
//! use helixreach::records::columns::{Column, Kind};
//! let opts = SweepOptions::new(&out, &["x", "x2"], 1)
//!     .column(Column::new("x", "", Kind::Count, "the item"))
//!     .column(Column::new("x2", "", Kind::Count, "its square"))
//!     .sweep("squares")
//!     .setting("power", 2);
//! let summary = run(&items, |x| vec![x.to_string()], |x| Ok(vec![x.to_string(), (x * x).to_string()]), &opts)?;
//! assert_eq!(summary.computed, 5);
//! let text = std::fs::read_to_string(&out).unwrap();
//! assert_eq!(text, "x,x2\n1,1\n2,4\n3,9\n4,16\n5,25\n");
//! let meta = std::fs::read_to_string(dir.path().join("squares.csv.meta.json")).unwrap();
//! assert!(meta.contains(r#""power": "2""#), "{meta}");
//!
//! // Running again over the finished file is refused; `resume` with other settings too.
//! assert!(run(&items, |x| vec![x.to_string()], |x| Ok(vec![x.to_string(), "0".into()]), &opts).is_err());
//! let mut cubes = opts.clone().setting("power", 3);
//! cubes.resume = true;
//! let e = run(&items, |x| vec![x.to_string()], |x| Ok(vec![x.to_string(), (x * x * x).to_string()]), &cubes).unwrap_err();
//! assert!(e.to_string().contains("power: `2` vs `3`"), "{e}");
//! # Ok::<(), helixreach::Error>(())
//! ```

use super::record::{csv_bytes, SettingsRecord, SweepFile};
use crate::error::{Error, Result};
use crate::io::{is_special, is_stdout, OutputLock};
use crate::par::Par;
use crate::records::columns::Column;
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::{AtomicUsize, Ordering};
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
    /// A checked shard (`count` ≤ [`crate::limits::MAX_SHARDS`]).
    pub fn new(index: usize, count: usize) -> Result<Self> {
        if count == 0 || index >= count {
            return Err(Error::invalid(
                "shard",
                format!("{index}/{count}"),
                "must be I/N with 0 <= I < N",
            ));
        }
        crate::limits::check_size("shard count N", count, crate::limits::MAX_SHARDS)?;
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
        // u128: no overflow for any usize n.
        let at = |i: usize| (i as u128 * n as u128 / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
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
    /// Output CSV; `-` is standard output.
    pub out: PathBuf,
    /// The CSV header (column names).
    pub header: Vec<String>,
    /// How many leading columns form an item's key (≥ 1, ≤ header length).
    pub key_columns: usize,
    /// The sweep's name in the settings record (`boundary`, `reach`, …).
    pub sweep: String,
    /// The settings that produce the rows (method, resolution, tolerance, rig digest, …), as
    /// text; recorded in the output and compared on resume.
    pub settings: std::collections::BTreeMap<String, String>,
    /// Continue an existing output (or its checkpoint) made with the same settings.
    pub resume: bool,
    /// Replace an existing output (only once the new result is complete).
    pub force: bool,
    /// Process only this block of the items.
    pub shard: Option<Shard>,
    /// Minimum time between checkpoints (to `OUT.partial`).
    pub checkpoint_interval: Duration,
    /// Show progress on stderr.
    pub progress: bool,
    /// Items per parallel batch (0: automatic, from the measured throughput).
    pub batch: usize,
    /// Each column's unit and rule, by default from [`crate::records::columns::COLUMNS`]; a
    /// column without one is refused before the run ([`SweepOptions::column`] gives one).
    pub columns: Vec<Column>,
    /// The parallelism of the computation (default [`Par::all`]: the pool as found).
    pub par: Par,
}

impl SweepOptions {
    /// Options with defaults: sweep name `sweep`, no settings, no resume, no force, no shard,
    /// checkpoint every 10 s, no progress, automatic batch size.
    pub fn new(out: &Path, header: &[&str], key_columns: usize) -> Self {
        SweepOptions {
            out: out.to_path_buf(),
            header: header.iter().map(|s| s.to_string()).collect(),
            key_columns,
            sweep: "sweep".into(),
            settings: Default::default(),
            resume: false,
            force: false,
            shard: None,
            checkpoint_interval: Duration::from_secs(10),
            progress: false,
            batch: 0,
            columns: crate::records::columns::columns_of(header),
            par: Par::all(),
        }
    }

    /// Set the parallelism.
    pub fn par(mut self, par: Par) -> Self {
        self.par = par;
        self
    }

    /// Give the column of `c.name` its unit and rule (for a column not in
    /// [`crate::records::columns::COLUMNS`]).
    pub fn column(mut self, c: Column) -> Self {
        if let Some(k) = self.header.iter().position(|h| h == c.name) {
            self.columns[k] = c;
        }
        self
    }

    /// Set the sweep's name.
    pub fn sweep(mut self, name: &str) -> Self {
        self.sweep = name.to_string();
        self
    }

    /// Record one setting (formatted with `Display`; floats print shortest round-trip).
    pub fn setting(mut self, name: &str, value: impl std::fmt::Display) -> Self {
        self.settings.insert(name.to_string(), value.to_string());
        self
    }
}

/// What a [`run`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepSummary {
    /// Items selected (after sharding).
    pub total: usize,
    /// Items computed in this run.
    pub computed: usize,
    /// Items taken from the existing output or checkpoint (resume).
    pub resumed: usize,
    /// Always 0: rows outside the current set are refused, never dropped (kept for
    /// compatibility).
    pub dropped: usize,
    /// Checkpoints written before the final output.
    pub checkpoints: usize,
    /// Time from the start of the computation to the first checkpoint, if any.
    pub first_checkpoint: Option<Duration>,
}

/// The checkpoint file of an output: `OUT.partial` beside it.
pub fn partial_path(out: &Path) -> PathBuf {
    let mut name = out
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".partial");
    out.with_file_name(name)
}

/// CSV text of some rows (no header).
fn rows_csv<'a>(rows: impl Iterator<Item = &'a Row>) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.write_record(r)
            .map_err(|e| Error::invalid("row", "", e.to_string()))?;
    }
    w.into_inner()
        .map_err(|e| Error::invalid("row", "", e.to_string()))
}

/// Where the rows go.
enum Sink {
    /// A regular file: checkpoints to `OUT.partial`, atomic replace at the end, locked.
    File { _lock: OutputLock },
    /// Standard output or a non-regular file, written in order as batches finish.
    Stream(Box<dyn Write>),
}

/// Refuse what would overwrite or mix results; load the rows to resume from.
fn prepare_file(
    opts: &SweepOptions,
    record: &SettingsRecord,
    keys: &[Row],
    rows: &mut [Option<Row>],
) -> Result<usize> {
    let out = &opts.out;
    let partial = partial_path(out);
    crate::io::remove_stale_temps(out);
    crate::io::remove_stale_temps(&partial);
    // A file, or its settings record alone (the file deleted by hand), is an earlier run's.
    let found = |p: &Path| {
        let sidecar = crate::io::sidecar_path(p);
        if std::fs::symlink_metadata(p).is_ok() {
            Some(p.to_path_buf())
        } else {
            std::fs::symlink_metadata(&sidecar)
                .is_ok()
                .then_some(sidecar)
        }
    };
    let (out_found, partial_found) = (found(out), found(&partial));
    let (out_exists, partial_exists) = (out_found.is_some(), partial_found.is_some());
    if !opts.resume && !opts.force && (out_exists || partial_exists) {
        let what = match (out_found, partial_found) {
            (Some(p), _) if p == *out => "it already exists".to_string(),
            (Some(p), _) => format!(
                "an earlier run's settings record {} exists (the output itself is gone)",
                p.display()
            ),
            (None, p) => format!(
                "an unfinished run's checkpoint {} exists",
                p.unwrap_or(partial.clone()).display()
            ),
        };
        return Err(Error::File {
            path: out.clone(),
            reason: format!(
                "{what}; refusing to overwrite it: resume it (--resume, same settings only) or \
                 replace it once the new result is complete (--force)"
            ),
        });
    }
    let mismatch = |path: &Path, file: &Option<SettingsRecord>, action: &str| -> Option<Error> {
        let reason = match file {
            None => format!(
                "it has no settings record {} (not written by this helixreach version)",
                crate::io::sidecar_path(path).display()
            ),
            Some(r) if r == record => return None,
            Some(r) => format!(
                "it was made with other settings (file vs this run): {}",
                r.differences(record).join("; ")
            ),
        };
        Some(Error::File {
            path: path.to_path_buf(),
            reason: format!("cannot {action}: {reason}"),
        })
    };
    if out_exists && !opts.force {
        if let Some(e) = mismatch(
            out,
            &SettingsRecord::read(out)?,
            "continue or replace it without --force",
        ) {
            return Err(e);
        }
    }
    if !opts.resume {
        return Ok(0);
    }
    let source = if partial_exists {
        partial
    } else if out_exists {
        out.clone()
    } else {
        return Ok(0);
    };
    let file = SweepFile::read(&source, Some(&opts.columns))?;
    if let Some(e) = mismatch(&source, &Some(file.record), "resume") {
        return Err(e);
    }
    let index: HashMap<&Row, usize> = keys.iter().enumerate().map(|(i, k)| (k, i)).collect();
    let mut resumed = 0;
    let line0 = 2; // header, first row
    for (n, row) in file.rows.into_iter().enumerate() {
        let bad = |reason: String| crate::io::bad_line(&source, n + line0, "key", reason);
        if row.len() != opts.header.len() {
            return Err(bad(format!(
                "has {} fields, the header has {}",
                row.len(),
                opts.header.len()
            )));
        }
        let key = row[..opts.key_columns].to_vec();
        let Some(&i) = index.get(&key) else {
            return Err(bad(format!(
                "`{}` is not an item of this run; refusing to drop it (use --force to \
                 recompute, or another --out)",
                key.join(",")
            )));
        };
        if rows[i].is_some() {
            return Err(bad(format!("`{}` appears twice", key.join(","))));
        }
        rows[i] = Some(row);
        resumed += 1;
    }
    Ok(resumed)
}

/// Progress on stderr: an indicatif bar on a terminal, else a line every 10 s.
struct Progress {
    bar: crate::progress::Bar,
    lines: bool,
    total: usize,
    name: String,
    t0: Instant,
    last: Instant,
}

impl Progress {
    fn new(on: bool, total: usize, name: &str) -> Self {
        let tty = std::io::stderr().is_terminal();
        let bar = if on && tty && crate::progress::Bar::DRAWS {
            crate::progress::Bar::new(total)
        } else {
            crate::progress::Bar::hidden()
        };
        Progress {
            bar,
            lines: on && (!tty || !crate::progress::Bar::DRAWS),
            total,
            name: name.to_string(),
            t0: Instant::now(),
            last: Instant::now(),
        }
    }

    /// Report `done` items: a line every 10 s, or at once with `now` (a checkpoint).
    fn batch_done(&mut self, done: usize, now: bool) {
        if self.lines && (now || self.last.elapsed() >= Duration::from_secs(10)) {
            self.last = Instant::now();
            let t = self.t0.elapsed().as_secs_f64();
            let eta = t / done.max(1) as f64 * (self.total - done) as f64;
            eprintln!(
                "{}: {done}/{} computed ({:.1} %), {t:.0} s elapsed, eta {eta:.0} s",
                self.name,
                self.total,
                100.0 * done as f64 / self.total.max(1) as f64
            );
        }
    }
}

/// `f(i)` for a prefix of `chunk`, in parallel on the rayon pool, results in `chunk` order.
///
/// `threads` workers claim positions in order from one counter and compute every position they
/// claim; with a `deadline`, no worker claims a new position after it (the first `threads`
/// positions are always claimed, so every call makes progress). The claimed positions are
/// therefore exactly `0..m` for some `m ≥ 1`: a prefix, whatever the items cost.
fn compute_prefix<R: Send>(
    chunk: &[usize],
    deadline: Option<Instant>,
    threads: usize,
    f: impl Fn(usize) -> R + Sync,
) -> Vec<R> {
    let counter = AtomicUsize::new(0);
    let workers = threads.clamp(1, chunk.len().max(1));
    let mut done: Vec<(usize, R)> = (0..workers)
        .into_par_iter()
        .flat_map_iter(|_| {
            let mut mine = Vec::new();
            loop {
                if deadline.is_some_and(|d| Instant::now() >= d)
                    && counter.load(Ordering::Relaxed) >= workers
                {
                    break;
                }
                let k = counter.fetch_add(1, Ordering::Relaxed);
                if k >= chunk.len() {
                    break;
                }
                mine.push((k, f(chunk[k])));
            }
            mine
        })
        .collect();
    done.sort_unstable_by_key(|(k, _)| *k);
    debug_assert!(done.iter().enumerate().all(|(n, (k, _))| n == *k));
    done.into_iter().map(|(_, r)| r).collect()
}

/// Run `compute` over `items` (see the module docs), writing `opts.out`, on `opts.par`.
///
/// `compute(item)` gives the item's record `R` (its fields, by
/// [`csv_out::fields`](crate::records::csv_out::fields), are the CSV row). `key(item)` must
/// equal the first `opts.key_columns` fields of that row; a mismatch, a row of the wrong length
/// or a failing item is an error (after a checkpoint of the rows finished so far), naming the
/// item's key.
pub fn run<T, R, K, F>(items: &[T], key: K, compute: F, opts: &SweepOptions) -> Result<SweepSummary>
where
    T: Sync,
    R: serde::Serialize,
    K: Fn(&T) -> Row,
    F: Fn(&T) -> Result<R> + Sync,
{
    let ncols = opts.header.len();
    if opts.key_columns == 0 || opts.key_columns > ncols {
        return Err(Error::invalid(
            "key_columns",
            opts.key_columns,
            format!("must be in 1..={ncols} (the header length)"),
        ));
    }
    let max_interval = Duration::from_secs_f64(crate::limits::MAX_CHECKPOINT_SECS);
    if opts.checkpoint_interval > max_interval {
        return Err(Error::invalid(
            "checkpoint interval (s)",
            opts.checkpoint_interval.as_secs_f64(),
            format!(
                "must be <= {} s (helixreach::limits)",
                crate::limits::MAX_CHECKPOINT_SECS
            ),
        ));
    }
    crate::records::columns::check_known(&opts.header, &opts.columns)
        .map_err(|e| Error::invalid("columns", opts.header.join(","), e))?;
    let all_keys: Vec<Row> = items.iter().map(&key).collect();
    if let Some(k) = all_keys.iter().find(|k| k.len() != opts.key_columns) {
        return Err(Error::invalid(
            "key",
            k.join(","),
            format!(
                "has {} fields, key_columns is {}",
                k.len(),
                opts.key_columns
            ),
        ));
    }
    let header: Vec<&str> = opts.header.iter().map(String::as_str).collect();
    let mut record = SettingsRecord::new(&opts.sweep, &header, &all_keys);
    record.settings = opts.settings.clone();
    record.shard = opts.shard.map(|s| s.to_string());
    let range = match opts.shard {
        Some(s) => s.range(items.len()),
        None => 0..items.len(),
    };
    let items = &items[range.clone()];
    let keys = &all_keys[range];
    let mut rows: Vec<Option<Row>> = vec![None; items.len()];

    let streaming = is_stdout(&opts.out) || is_special(&opts.out);
    let mut sink = if streaming {
        if opts.resume {
            return Err(Error::invalid(
                "out",
                opts.out.display(),
                "standard output or a device cannot be resumed; give a file",
            ));
        }
        let w: Box<dyn Write> = if is_stdout(&opts.out) {
            Box::new(std::io::stdout())
        } else {
            let f = std::fs::OpenOptions::new()
                .write(true)
                .open(&opts.out)
                .map_err(|source| Error::Io {
                    path: opts.out.clone(),
                    source,
                })?;
            Box::new(f)
        };
        Sink::Stream(w)
    } else {
        crate::io::check_output(&opts.out)?;
        let lock = OutputLock::acquire(&opts.out)?;
        Sink::File { _lock: lock }
    };
    let stream_err = |source| Error::Io {
        path: opts.out.clone(),
        source,
    };
    let resumed = match &mut sink {
        Sink::File { .. } => prepare_file(opts, &record, keys, &mut rows)?,
        Sink::Stream(w) => {
            w.write_all(&csv_bytes(&opts.header, std::iter::empty())?)
                .map_err(stream_err)?;
            0
        }
    };

    let todo: Vec<usize> = (0..items.len()).filter(|&i| rows[i].is_none()).collect();
    let mut progress = Progress::new(opts.progress, todo.len(), &opts.sweep);
    let threads = opts.par.count();
    let target =
        (opts.checkpoint_interval / 4).clamp(Duration::from_millis(20), Duration::from_secs(2));
    let partial = partial_path(&opts.out);
    let t0 = Instant::now();
    let mut last_checkpoint = t0;
    let mut first_checkpoint = None;
    let mut checkpoints = 0;
    let mut computed = 0;
    let mut next = 0;
    while next < todo.len() {
        // A fixed batch (`opts.batch`), or every remaining item under a deadline: workers claim
        // items in input order and stop claiming at the deadline, so the finished items are a
        // prefix of the remainder whatever the items cost.
        let (chunk, deadline) = if opts.batch > 0 {
            (&todo[next..(next + opts.batch).min(todo.len())], None)
        } else {
            (&todo[next..], Some(Instant::now() + target))
        };
        let bar = &progress.bar;
        let results = opts.par.install(|| {
            compute_prefix(chunk, deadline, threads, |i| {
                let r = compute(&items[i]).and_then(|r| crate::records::csv_out::fields(&r));
                bar.inc(1);
                r
            })
        })?;
        let chunk = &chunk[..results.len()];
        next += chunk.len();
        let mut failure = None;
        for (&i, r) in chunk.iter().zip(results) {
            let checked = r.and_then(|row| {
                if row.len() != ncols {
                    Err(Error::invalid(
                        "row",
                        row.join(","),
                        format!("has {} fields, the header has {ncols}", row.len()),
                    ))
                } else if let Err(e) =
                    crate::records::columns::check_row_with(&opts.header, &opts.columns, &row)
                {
                    Err(Error::invalid("row", row.join(","), e))
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
        if let Sink::Stream(w) = &mut sink {
            // Rows in input order up to the first failure.
            let upto = failure.as_ref().map_or(chunk.len(), |(i, _)| {
                chunk.iter().position(|&c| c == *i).unwrap_or(0)
            });
            let bytes = rows_csv(chunk[..upto].iter().filter_map(|&i| rows[i].as_ref()))?;
            w.write_all(&bytes)
                .and_then(|_| w.flush())
                .map_err(stream_err)?;
        }
        if let Some((i, e)) = failure {
            progress.bar.abandon();
            if matches!(sink, Sink::File { .. }) && computed > 0 {
                SweepFile::write(&partial, &record, &opts.columns, rows.iter().flatten())?;
            }
            return Err(Error::Item {
                key: crate::error::compact_number_text(keys[i].join(",")),
                cause: Box::new(e),
            });
        }
        if matches!(sink, Sink::File { .. })
            && last_checkpoint.elapsed() >= opts.checkpoint_interval
            && next < todo.len()
        {
            // The line first: whoever sees the checkpoint file has seen the line.
            progress.batch_done(computed, true);
            SweepFile::write(&partial, &record, &opts.columns, rows.iter().flatten())?;
            checkpoints += 1;
            first_checkpoint.get_or_insert(t0.elapsed());
            last_checkpoint = Instant::now();
        } else {
            progress.batch_done(computed, false);
        }
    }
    progress.bar.finish_and_clear();
    match &mut sink {
        Sink::File { .. } => {
            SweepFile::write(&opts.out, &record, &opts.columns, rows.iter().flatten())?;
            SweepFile::remove(&partial)?;
        }
        Sink::Stream(w) => w.flush().map_err(stream_err)?,
    }
    Ok(SweepSummary {
        total: items.len(),
        computed,
        resumed,
        dropped: 0,
        checkpoints,
        first_checkpoint,
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
        assert!("0/1000000000".parse::<Shard>().is_err());
        let n = 17;
        let mut all = vec![];
        for i in 0..4 {
            all.extend(format!("{i}/4").parse::<Shard>().unwrap().range(n));
        }
        assert_eq!(all, (0..n).collect::<Vec<_>>());
    }
}
