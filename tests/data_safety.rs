//! Data safety of sweep outputs, bounded inputs and CLI details: a finished result is
//! never replaced by less, every output records its settings and `--resume` refuses others,
//! one writer per output, stale temp files removed, checkpoints on time, `--out -` streams,
//! `merge` checks shards, outputs are checked before computing, every size is bounded.
//!
//! Library tests use a cheap synthetic sweep (`x → x²`); CLI tests run the real binary.

use helixreach::records::columns::{Column, Kind};
use helixreach::sweep::driver::{self, partial_path, Shard, SweepOptions};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

fn key(x: &u64) -> Vec<String> {
    vec![x.to_string()]
}

fn square(x: &u64) -> helixreach::Result<Vec<String>> {
    Ok(vec![x.to_string(), (x * x).to_string()])
}

/// The columns of the synthetic sweep: an item and its square.
const COLS: [Column; 2] = [
    Column::new("x", "", Kind::Count, "the item"),
    Column::new("x2", "", Kind::Count, "its square"),
];

fn opts(out: &Path) -> SweepOptions {
    SweepOptions::new(out, &["x", "x2"], 1)
        .column(COLS[0])
        .column(COLS[1])
        .sweep("squares")
        .setting("power", 2)
}

fn merge(
    inputs: &[PathBuf],
    key_columns: usize,
    out: &Path,
    force: bool,
) -> helixreach::Result<helixreach::sweep::merge::MergeSummary> {
    helixreach::sweep::merge::merge_with(inputs, key_columns, out, force, Some(&COLS))
}

fn items(n: u64) -> Vec<u64> {
    (0..n).collect()
}

/// The data rows of a sweep CSV (header skipped).
fn data_rows(path: &Path) -> Vec<String> {
    let t = std::fs::read_to_string(path).unwrap();
    t.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(str::to_string)
        .collect()
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_helixreach"));
    c.env("RAYON_NUM_THREADS", "2");
    c
}

/// Run the binary, killing it after `limit` (so a hang fails the test instead of blocking CI).
fn cli_within(args: &[&str], limit: Duration) -> Output {
    let mut child = bin()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > limit {
            child.kill().unwrap();
            let o = child.wait_with_output().unwrap();
            panic!(
                "`helixreach {}` still running after {limit:?}; stderr: {}",
                args.join(" "),
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn cli(args: &[&str]) -> Output {
    cli_within(args, Duration::from_secs(60))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

// ---------------------------------------------------------------------------------------------
// A finished result is never replaced by less
// ---------------------------------------------------------------------------------------------

#[test]
fn failed_sweep_leaves_the_finished_output_intact() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    driver::run(&items(50), key, square, &opts(&out)).unwrap();
    let finished = std::fs::read(&out).unwrap();
    let mut o = opts(&out);
    o.force = true;
    o.batch = 4;
    o.checkpoint_interval = Duration::ZERO;
    let e = driver::run(
        &items(50),
        key,
        |x| {
            if *x == 30 {
                Err(helixreach::Error::invalid("x", x, "boom"))
            } else {
                square(x)
            }
        },
        &o,
    )
    .unwrap_err();
    assert!(e.to_string().contains("item 30"), "{e}");
    assert_eq!(
        std::fs::read(&out).unwrap(),
        finished,
        "finished output replaced"
    );
    // The rows finished before the failure (0..29, and 31 of the failing batch 28..31) are
    // kept beside it.
    let kept = data_rows(&partial_path(&out));
    assert_eq!(kept.len(), 31);
    assert!(!kept.iter().any(|r| r.starts_with("30,")));
}

#[test]
fn rerun_over_a_finished_output_is_refused_without_resume_or_force() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    driver::run(&items(20), key, square, &opts(&out)).unwrap();
    let finished = std::fs::read(&out).unwrap();
    let computed = AtomicUsize::new(0);
    let e = driver::run(
        &items(5),
        key,
        |x| {
            computed.fetch_add(1, Ordering::Relaxed);
            square(x)
        },
        &opts(&out),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("--resume") && e.contains("--force"), "{e}");
    assert_eq!(computed.load(Ordering::Relaxed), 0);
    assert_eq!(std::fs::read(&out).unwrap(), finished);
    // --force replaces it, with a complete result.
    let mut o = opts(&out);
    o.force = true;
    driver::run(&items(5), key, square, &o).unwrap();
    assert_eq!(data_rows(&out).len(), 5);
    assert!(!partial_path(&out).exists());
}

/// An output deleted by hand with its settings record left beside it: a rerun is refused,
/// naming the record (not the missing output), and `--force` writes a complete result.
#[test]
fn a_left_settings_record_is_named_when_a_rerun_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    driver::run(&items(20), key, square, &opts(&out)).unwrap();
    std::fs::remove_file(&out).unwrap();
    let sidecar = helixreach::io::sidecar_path(&out);
    assert!(sidecar.exists());
    let e = driver::run(&items(5), key, square, &opts(&out))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&*sidecar.to_string_lossy()) && !e.contains("it already exists"),
        "{e}"
    );
    assert!(e.contains("--resume") && e.contains("--force"), "{e}");
    let mut o = opts(&out);
    o.force = true;
    driver::run(&items(5), key, square, &o).unwrap();
    assert_eq!(data_rows(&out).len(), 5);
}

/// Kill a real `boundary` run over a finished output once it has checkpointed: the finished
/// output is untouched, and `--resume` completes the checkpoint to exactly the uninterrupted
/// result.
#[test]
fn killed_rerun_keeps_the_finished_output_and_resume_completes_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let o = cli(&["boundary", "--fibonacci", "40", "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let finished = std::fs::read(&out).unwrap();

    let big = [
        "boundary",
        "--fibonacci",
        "1000000",
        "--checkpoint-secs",
        "0.2",
        "--out",
        s(&out),
    ];
    let mut args = big.to_vec();
    args.push("--force");
    let mut child = bin()
        .args(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let partial = partial_path(&out);
    let t0 = Instant::now();
    while !partial.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "no checkpoint in 60 s"
        );
        assert!(child.try_wait().unwrap().is_none(), "run ended early");
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(
        std::fs::read(&out).unwrap(),
        finished,
        "finished output replaced"
    );
    let rows = data_rows(&partial);
    assert!(!rows.is_empty() && rows.len() < 1_000_000);

    // A plain --resume would replace a result made with other settings: refused.
    let mut resume = big.to_vec();
    resume.push("--resume");
    let o = cli(&resume);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("items"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), finished);
}

#[test]
fn kill_and_resume_reproduces_the_uninterrupted_sweep() {
    // A smaller sweep killed after its first checkpoint, resumed: equal to a clean run.
    let dir = tempfile::tempdir().unwrap();
    let (out, clean) = (dir.path().join("k.csv"), dir.path().join("clean.csv"));
    let args = |p: &Path| {
        vec![
            "boundary".to_string(),
            "--fibonacci".into(),
            "6000".into(),
            "--tol".into(),
            "1e-12".into(),
            "--checkpoint-secs".into(),
            "0.1".into(),
            "--out".into(),
            s(p).into(),
        ]
    };
    let mut child = bin()
        .env("RAYON_NUM_THREADS", "1")
        .args(args(&out))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let partial = partial_path(&out);
    let t0 = Instant::now();
    let killed = loop {
        if partial.exists() {
            child.kill().unwrap();
            child.wait().unwrap();
            break true;
        }
        if child.try_wait().unwrap().is_some() {
            break false; // finished before the first checkpoint: nothing to resume
        }
        assert!(t0.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(5));
    };
    assert!(killed, "the sweep finished before its first checkpoint");
    // Progress reached the (non-terminal) stderr at the checkpoint.
    let err = child.wait_with_output().unwrap().stderr;
    let err = String::from_utf8_lossy(&err);
    assert!(
        err.contains("/6000 computed"),
        "no progress line on stderr: {err}"
    );
    assert!(
        !out.exists(),
        "a killed run must not leave a partial output in place"
    );
    let mut r = args(&out);
    r.push("--resume".into());
    let r: Vec<&str> = r.iter().map(String::as_str).collect();
    let o = cli(&r);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("resumed"), "{}", stderr(&o));
    let c: Vec<String> = args(&clean);
    let c: Vec<&str> = c.iter().map(String::as_str).collect();
    assert!(cli(&c).status.success());
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&clean).unwrap());
    assert!(!partial.exists());
}

// ---------------------------------------------------------------------------------------------
// Settings record and resume
// ---------------------------------------------------------------------------------------------

#[test]
fn resume_refuses_mismatched_settings_and_names_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    let o = cli(&["boundary", "--fibonacci", "8", "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let sidecar = std::fs::read_to_string(helixreach::io::sidecar_path(&out)).unwrap();
    let first = serde_json::from_str::<serde_json::Value>(&sidecar)
        .unwrap()
        .to_string();
    for f in [
        "\"method\":\"continuum\"",
        "\"tol\":",
        "\"sweep\":\"boundary\"",
        "\"tool\":\"helixreach",
        "\"items\":8",
        "\"items_digest\":",
    ] {
        assert!(first.contains(f), "record lacks {f}: {first}");
    }
    let o = cli(&[
        "boundary",
        "--fibonacci",
        "8",
        "--method",
        "der",
        "--resume",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("method: `continuum` vs `der`"), "{e}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    // The same settings resume: nothing recomputed, file unchanged.
    let o = cli(&["boundary", "--fibonacci", "8", "--resume", "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 computed, 8 resumed"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
}

#[test]
fn resume_with_another_shard_refuses_instead_of_dropping_rows() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.csv");
    assert!(cli(&["boundary", "--fibonacci", "9", "--out", s(&out)])
        .status
        .success());
    let o = cli(&[
        "boundary",
        "--fibonacci",
        "9",
        "--shard",
        "2/3",
        "--resume",
        "--out",
        s(&out),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("shard: `none` vs `2/3`"),
        "{}",
        stderr(&o)
    );
    assert_eq!(data_rows(&out).len(), 9);
}

#[test]
fn resume_refuses_rows_outside_the_item_set() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    driver::run(&items(10), key, square, &opts(&out)).unwrap();
    // Hand-add a row that is no item of the sweep: resuming must not silently drop it.
    let mut t = std::fs::read_to_string(&out).unwrap();
    t.push_str("99,9801\n");
    std::fs::write(&out, &t).unwrap();
    let mut o = opts(&out);
    o.resume = true;
    // The bytes no longer match the record's digest: refused as such.
    let e = driver::run(&items(10), key, square, &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("does not match its settings record"), "{e}");
    // With a matching record, the row itself is refused.
    let side = helixreach::io::sidecar_path(&out);
    let mut meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&side).unwrap()).unwrap();
    meta["csv"] = serde_json::json!({
        "rows": 11,
        "bytes": t.len(),
        "fnv1a": helixreach::sweep::record::fnv1a_hex(t.as_bytes()),
    });
    std::fs::write(&side, meta.to_string()).unwrap();
    let e = driver::run(&items(10), key, square, &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`99` is not an item"), "{e}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), t);
}

// ---------------------------------------------------------------------------------------------
// Lock, temp files, checkpoints
// ---------------------------------------------------------------------------------------------

#[test]
fn second_writer_of_an_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("l.csv");
    let started = std::sync::Barrier::new(2);
    let release = std::sync::Barrier::new(2);
    std::thread::scope(|sc| {
        let first = sc.spawn(|| {
            driver::run(
                &items(4),
                key,
                |x| {
                    if *x == 0 {
                        started.wait();
                        release.wait();
                    }
                    square(x)
                },
                &{
                    let mut o = opts(&out);
                    o.batch = 1;
                    o
                },
            )
        });
        started.wait();
        let e = driver::run(&items(4), key, square, &opts(&out))
            .unwrap_err()
            .to_string();
        assert!(e.contains("being written by another process"), "{e}");
        release.wait();
        first.join().unwrap().unwrap();
    });
    assert_eq!(data_rows(&out).len(), 4);
    assert!(!helixreach::io::lock_path(&out).exists());
}

#[test]
fn concurrent_cli_writers_second_fails_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.csv");
    let mut first = bin()
        .args(["boundary", "--fibonacci", "1000000", "--out", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = helixreach::io::lock_path(&out);
    let t0 = Instant::now();
    while !lock.exists() {
        assert!(t0.elapsed() < Duration::from_secs(30));
        std::thread::sleep(Duration::from_millis(10));
    }
    let o = cli(&["boundary", "--fibonacci", "10", "--force", "--out", s(&out)]);
    first.kill().unwrap();
    first.wait().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("being written by another process (pid"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

#[test]
fn stale_temp_files_of_killed_runs_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.csv");
    // 4194304 exceeds Linux's largest pid: a process that no longer exists.
    let stale = [
        dir.path().join("t.csv.4194304.tmp"),
        dir.path().join("t.csv.partial.4194304.tmp"),
    ];
    for p in &stale {
        std::fs::write(p, "half a row").unwrap();
    }
    driver::run(&items(3), key, square, &opts(&out)).unwrap();
    for p in &stale {
        assert!(!p.exists(), "{} left behind", p.display());
    }
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert_eq!(names, ["t.csv", "t.csv.meta.json"]);
}

#[test]
fn checkpoints_honour_the_interval() {
    // 20 ms items, 1 thread, 200 ms interval: the first checkpoint comes after ~250 ms (a batch
    // lasts a quarter interval), not after a large fixed batch (64 items = 1.3 s).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    let mut o = opts(&out);
    o.checkpoint_interval = Duration::from_millis(200);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let summary = pool
        .install(|| {
            driver::run(
                &items(100),
                key,
                |x| {
                    std::thread::sleep(Duration::from_millis(20));
                    square(x)
                },
                &o,
            )
        })
        .unwrap();
    let first = summary
        .first_checkpoint
        .expect("no checkpoint in a 2 s sweep");
    assert!(
        first < Duration::from_millis(600),
        "first checkpoint at {first:?}"
    );
    assert!(summary.checkpoints >= 4, "{summary:?}");
}

// ---------------------------------------------------------------------------------------------
// stdout and non-regular outputs
// ---------------------------------------------------------------------------------------------

#[test]
fn out_dash_streams_to_stdout_in_input_order() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f.csv");
    assert!(cli(&["boundary", "--fibonacci", "30", "--out", s(&file)])
        .status
        .success());
    let o = bin()
        .current_dir(dir.path())
        .args(["boundary", "--fibonacci", "30", "--out", "-"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(o.stdout, std::fs::read(&file).unwrap());
    assert!(!dir.path().join("-").exists(), "wrote a file named `-`");
}

#[cfg(unix)]
#[test]
fn non_regular_output_is_written_in_place() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe");
    let c = std::ffi::CString::new(s(&fifo)).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = fifo.clone();
    std::thread::spawn(move || {
        let _ = tx.send(std::fs::read_to_string(reader).unwrap());
    });
    driver::run(&items(5), key, square, &opts(&fifo)).unwrap();
    let text = rx.recv_timeout(Duration::from_secs(20)).unwrap();
    assert!(text.ends_with("x,x2\n0,0\n1,1\n2,4\n3,9\n4,16\n"), "{text}");
    let t = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(t.is_fifo(), "the FIFO was replaced by a regular file");
}

// ---------------------------------------------------------------------------------------------
// merge
// ---------------------------------------------------------------------------------------------

#[test]
fn merge_refuses_gaps_disorder_duplicates_and_mixed_settings() {
    let dir = tempfile::tempdir().unwrap();
    let n = 23;
    let whole = dir.path().join("whole.csv");
    driver::run(&items(n), key, square, &opts(&whole)).unwrap();
    let shard = |i: usize, power: u32| -> PathBuf {
        let p = dir.path().join(format!("s{i}-{power}.csv"));
        let mut o = opts(&p).setting("power", power);
        o.shard = Some(Shard::new(i, 3).unwrap());
        driver::run(&items(n), key, square, &o).unwrap();
        p
    };
    let sh: Vec<PathBuf> = (0..3).map(|i| shard(i, 2)).collect();
    let out = dir.path().join("m.csv");
    let err = |inputs: &[PathBuf]| merge(inputs, 1, &out, true).unwrap_err().to_string();

    let e = err(&sh[..2]);
    assert!(e.contains("missing 2/3"), "{e}");
    let e = err(&[sh[0].clone(), sh[2].clone(), sh[1].clone()]);
    assert!(e.contains("is shard 2/3, expected 1/3"), "{e}");
    let e = err(&[sh[0].clone(), sh[0].clone(), sh[2].clone()]);
    assert!(e.contains("expected 1/3"), "{e}");
    let e = err(&[sh[0].clone(), shard(1, 3), sh[2].clone()]);
    assert!(e.contains("power: `2` vs `3`"), "{e}");
    // An unfinished shard (a checkpoint given as a shard) holds too few rows.
    let cut = dir.path().join("cut.csv");
    let mut o = opts(&cut);
    o.shard = Some(Shard::new(1, 3).unwrap());
    o.batch = 2;
    o.checkpoint_interval = Duration::ZERO;
    let e = driver::run(
        &items(n),
        key,
        |x| {
            if *x == 11 {
                Err(helixreach::Error::invalid("x", x, "boom"))
            } else {
                square(x)
            }
        },
        &o,
    )
    .unwrap_err();
    assert!(e.to_string().contains("item 11"), "{e}");
    let e = err(&[sh[0].clone(), partial_path(&cut), sh[2].clone()]);
    assert!(e.contains("must hold 8 rows, it holds 5"), "{e}");
    // A shard cut after writing (its bytes no longer those its record describes).
    let t = std::fs::read_to_string(&sh[1]).unwrap();
    std::fs::write(&cut, &t[..t.len() - 3]).unwrap();
    std::fs::copy(
        helixreach::io::sidecar_path(&sh[1]),
        helixreach::io::sidecar_path(&cut),
    )
    .unwrap();
    let e = err(&[sh[0].clone(), cut, sh[2].clone()]);
    assert!(e.contains("does not match its settings record"), "{e}");
    // A file without a record (e.g. hand-made) cannot be checked: refused.
    let bare = dir.path().join("bare.csv");
    std::fs::write(&bare, "x,x2\n0,0\n").unwrap();
    assert!(err(&[bare]).contains("no settings record"));
    assert!(!out.exists());

    // The complete, ordered set merges to exactly the unsharded output.
    merge(&sh, 1, &out, false).unwrap();
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&whole).unwrap());
    // And an existing output is replaced only with force.
    assert!(merge(&sh, 1, &out, false).is_err());
}

// ---------------------------------------------------------------------------------------------
// Outputs checked before computing; bounds
// ---------------------------------------------------------------------------------------------

#[test]
fn unwritable_output_fails_before_computing() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let computed = AtomicUsize::new(0);
    let e = driver::run(
        &items(10),
        key,
        |x| {
            computed.fetch_add(1, Ordering::Relaxed);
            square(x)
        },
        &opts(&file.join("out.csv")),
    )
    .unwrap_err()
    .to_string();
    assert_eq!(computed.load(Ordering::Relaxed), 0, "{e}");
    assert!(e.contains("a-file"), "{e}");
    // The CLI checks --out before loading anything.
    let o = cli(&[
        "boundary",
        "--fibonacci",
        "10",
        "--out",
        s(&file.join("x.csv")),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("a-file"), "{}", stderr(&o));
}

#[test]
fn size_parameters_are_bounded_with_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    let out = s(&out);
    let cases: [(&[&str], &[&str]); 10] = [
        (
            &[
                "simulate",
                "--direction",
                "0.3,0.9,0.3",
                "--n-edges",
                "100000000",
                "--out",
                out,
            ],
            &["--n-edges", "100000000", "10000"],
        ),
        (
            &[
                "boundary",
                "--method",
                "der",
                "--n-edges",
                "100000000",
                "--fibonacci",
                "4",
                "--out",
                out,
            ],
            &["--n-edges", "100000000", "10000"],
        ),
        (
            &["boundary", "--fibonacci", "100000000000", "--out", out],
            &["--fibonacci", "100000000000", "10000000"],
        ),
        (
            &[
                "reach",
                "--fibonacci",
                "4",
                "--azimuths",
                "1000000000",
                "--out",
                out,
            ],
            &["--azimuths", "1000000000", "3600"],
        ),
        (
            &[
                "ik",
                "--robot",
                "sawyer",
                "--pose",
                "0.5,0,0.5,1,0,0,0",
                "--samples",
                "100000000",
            ],
            &["--samples", "100000000", "100000"],
        ),
        (
            &[
                "plan",
                "--direction",
                "0.3,0.9,0.3",
                "--waypoints",
                "100000000",
                "--out",
                out,
            ],
            &["--waypoints", "100000000", "max_waypoints"],
        ),
        (
            &[
                "boundary",
                "--fibonacci",
                "4",
                "--shard",
                "0/1000000000",
                "--out",
                out,
            ],
            &["shard", "1000000000"],
        ),
        (
            &[
                "boundary",
                "--fibonacci",
                "4",
                "--checkpoint-secs",
                "1e300",
                "--out",
                out,
            ],
            &["--checkpoint-secs", "1e300"],
        ),
        // Every sweep command reads its direction set by the same arguments (commands::args).
        (
            &["layout", "--fibonacci", "100000000000", "--out", out],
            &["--fibonacci", "100000000000", "10000000"],
        ),
        (
            &[
                "reach",
                "--fibonacci",
                "4",
                "--checkpoint-secs",
                "NaN",
                "--out",
                out,
            ],
            &["--checkpoint-secs", "NaN", "helixreach::limits"],
        ),
    ];
    for (args, needles) in cases {
        let t0 = Instant::now();
        let o = cli_within(args, Duration::from_secs(30));
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        for n in needles {
            assert!(e.contains(n), "{args:?}: `{n}` not in {e}");
        }
        assert!(
            t0.elapsed() < Duration::from_secs(20),
            "{args:?} took {:?}",
            t0.elapsed()
        );
    }
}

#[test]
fn rig_counts_are_bounded() {
    let text = include_str!("../robots/sawyer-seed.toml")
        .replace("redundancy_samples = 8", "redundancy_samples = 100000000");
    let e = helixreach::planning::rig::Rig::from_toml_str(&text, "big.toml", Path::new("robots"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("big.toml")
            && e.contains("planner.redundancy_samples")
            && e.contains("100000000"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// speed report, write-disabled, CLI details
// ---------------------------------------------------------------------------------------------

#[test]
fn speed_report_never_writes_zero_time() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("speed.csv");
    let o = cli(&["boundary", "--fibonacci", "3", "--speed-report", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let t = std::fs::read_to_string(&r).unwrap();
    let mut n = 0;
    for l in t.lines().skip(1) {
        let secs: f64 = l.split(',').nth(2).unwrap().parse().unwrap();
        assert!(secs > 1e-8 && secs < 1.0, "{l}");
        n += 1;
    }
    assert_eq!(n, 5, "{t}");
}

#[test]
fn write_disabled_requires_enough_samples() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("f.toml");
    for n in ["0", "9999"] {
        let o = cli(&[
            "robot",
            "--robot",
            "sawyer",
            "--samples",
            n,
            "--write-disabled",
            s(&f),
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert!(
            stderr(&o).contains("--samples") && stderr(&o).contains("10000"),
            "{}",
            stderr(&o)
        );
        assert!(!f.exists());
    }
}

/// The disabled-pair lists shipped in `robots/` against a fresh sampling with another seed: a
/// pair listed as never colliding must not collide in any fresh sample, a pair listed as always
/// colliding must collide in every one.
#[test]
fn shipped_disabled_pairs_agree_with_a_fresh_sampling() {
    use helixreach::robot::{DisabledPairs, RobotModel, BUILTINS};
    for b in BUILTINS.iter() {
        let m = RobotModel::load(b.name, None).unwrap();
        let shipped = DisabledPairs::for_model(&m).unwrap();
        let fresh = DisabledPairs::compute(&m, 20_000, shipped.seed.wrapping_add(7919)).unwrap();
        let set = |d: &DisabledPairs, why: &str| -> std::collections::BTreeSet<(String, String)> {
            d.disabled
                .iter()
                .filter(|p| p.reason == why)
                .map(|p| (p.a.clone().min(p.b.clone()), p.a.clone().max(p.b.clone())))
                .collect()
        };
        for why in ["never", "always"] {
            let (listed, seen) = (set(&shipped, why), set(&fresh, why));
            let wrong: Vec<_> = listed.difference(&seen).collect();
            assert!(
                wrong.is_empty(),
                "{}: shipped `{why}` pairs contradicted: {wrong:?}",
                b.name
            );
        }
    }
}

#[test]
fn negative_numbers_after_flags_parse() {
    let o = cli(&["helix", "--kappa", "1", "--tau", "-1", "--omega", "-0.5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A negative value reaches validation (named), not the argument parser.
    let o = cli(&["boundary", "--fibonacci", "4", "--tol", "-1", "--out", "-"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        !e.contains("unexpected argument") && e.contains("tol"),
        "{e}"
    );
}

#[test]
fn os_errors_are_printed_once() {
    let o = cli(&[
        "boundary",
        "--directions",
        "/nonexistent/d.csv",
        "--out",
        "-",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("/nonexistent/d.csv"), "{e}");
    assert_eq!(e.matches("No such file or directory").count(), 1, "{e}");
}

#[test]
fn unknown_robot_lists_the_built_in_ones() {
    let o = cli(&["fk", "--robot", "kuka", "--joints", "0,0,0,0,0,0,0"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("kuka") && e.contains("sawyer, panda, iiwa14"),
        "{e}"
    );
}

#[test]
fn huge_numbers_print_compactly_in_errors() {
    let o = cli(&[
        "boundary",
        "--fibonacci",
        "4",
        "--tol",
        "1e300",
        "--out",
        "-",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("1e300") && !e.contains("10000000000000000"),
        "{e}"
    );
}

/// Instant items followed by costly ones (a layout: placements ruled out at once, then planned
/// rays) still checkpoint on time: batches sized by the instant items alone would hold every
/// remaining item and run without a checkpoint or a progress line (a seed layout silent for
/// minutes).
#[test]
fn checkpoints_stay_on_time_when_items_turn_costly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    let mut o = opts(&out);
    o.checkpoint_interval = Duration::from_millis(100);
    // 300 instant items, then 50 costly ones per thread (≥ 0.5 s of sleep on every thread).
    let n = 300 + 50 * rayon::current_num_threads() as u64;
    let summary = driver::run(
        &items(n),
        key,
        |x| {
            if *x >= 300 {
                std::thread::sleep(Duration::from_millis(10));
            }
            square(x)
        },
        &o,
    )
    .unwrap();
    assert!(
        summary.checkpoints >= 2,
        "{} checkpoints, first at {:?}",
        summary.checkpoints,
        summary.first_checkpoint
    );
    assert_eq!(data_rows(&out).len(), n as usize);
}

// ---------------------------------------------------------------------------------------------
// The settings digest covers every input file that changes a result
// ---------------------------------------------------------------------------------------------

/// A rig directory holding a copy of the Sawyer's URDF and pair list and the seed rig pointing
/// at the copy: `(dir, rig path)`.
fn rig_with_copied_robot() -> (tempfile::TempDir, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let dir = tempfile::tempdir().unwrap();
    for f in ["sawyer.urdf", "sawyer.collision.toml"] {
        std::fs::copy(root.join(f), dir.path().join(f)).unwrap();
    }
    let rig = std::fs::read_to_string(root.join("sawyer-seed.toml"))
        .unwrap()
        .replace("urdf = \"sawyer\"", "urdf = \"sawyer.urdf\"");
    assert!(rig.contains("urdf = \"sawyer.urdf\""));
    let path = dir.path().join("rig.toml");
    std::fs::write(&path, rig).unwrap();
    (dir, path)
}

#[test]
fn resume_refuses_rows_of_a_changed_urdf_or_pair_list() {
    let (dir, rig) = rig_with_copied_robot();
    let out = dir.path().join("r.csv");
    let reach = |extra: &[&str]| {
        let mut a = vec![
            "reach",
            "--rig",
            s(&rig),
            "--fibonacci",
            "2",
            "--quarter",
            "--quiet",
            "--out",
            s(&out),
        ];
        a.extend_from_slice(extra);
        cli(&a)
    };
    let o = reach(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let record = std::fs::read_to_string(helixreach::io::sidecar_path(&out)).unwrap();
    assert!(record.contains("sawyer.urdf="), "{record}");
    // Control: unchanged files resume.
    let o = reach(&["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));

    // A narrowed joint limit in the URDF: the rows are another robot's.
    let urdf = dir.path().join("sawyer.urdf");
    let original = std::fs::read_to_string(&urdf).unwrap();
    let narrowed = original.replacen("lower=\"-3.0503\"", "lower=\"-1.0\"", 1);
    assert_ne!(narrowed, original);
    std::fs::write(&urdf, &narrowed).unwrap();
    let o = reach(&["--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("robot_files"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    std::fs::write(&urdf, &original).unwrap();

    // The never-colliding pair list edited, then removed.
    let pairs = dir.path().join("sawyer.collision.toml");
    let pairs_text = std::fs::read_to_string(&pairs).unwrap();
    std::fs::write(&pairs, format!("{pairs_text}\n# edited\n")).unwrap();
    let o = reach(&["--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("sawyer.collision.toml"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    // Without its pair list the Sawyer's straight-rod start self-collides: the error names the
    // missing file instead of only "self_collision".
    std::fs::remove_file(&pairs).unwrap();
    let o = reach(&["--resume"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("sawyer.collision.toml does not exist") && e.contains("--write-disabled"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
}

/// A binary STL of a cube of side `a` centred at the origin (12 triangles).
fn cube_stl(a: f32) -> Vec<u8> {
    let h = 0.5 * a;
    let v = |i: usize| {
        [
            if i & 4 == 0 { -h } else { h },
            if i & 2 == 0 { -h } else { h },
            if i & 1 == 0 { -h } else { h },
        ]
    };
    let faces = [
        (0, 1, 3),
        (0, 3, 2),
        (4, 6, 7),
        (4, 7, 5),
        (0, 4, 5),
        (0, 5, 1),
        (2, 3, 7),
        (2, 7, 6),
        (0, 2, 6),
        (0, 6, 4),
        (1, 5, 7),
        (1, 7, 3),
    ];
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for (i, j, k) in faces {
        b.extend(std::iter::repeat_n(0u8, 12));
        for p in [v(i), v(j), v(k)] {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
    }
    b
}

/// Every input file that changes a result is in the settings digest: a collision mesh, the
/// rig's SRDF and the `--boundary` table, each changed after a finished `reach`, make
/// `--resume` refuse (naming the setting and the file) and leave the output as it was.
#[test]
fn resume_refuses_rows_of_a_changed_mesh_srdf_or_boundary_table() {
    let (dir, rig) = rig_with_copied_robot();
    let d = dir.path();
    // A 1 cm cube inside the pedestal's cylinder (adds no contact), as a mesh, and an SRDF.
    std::fs::write(d.join("cube.stl"), cube_stl(0.01)).unwrap();
    let urdf = d.join("sawyer.urdf");
    let text = std::fs::read_to_string(&urdf).unwrap();
    let cyl = r#"<geometry><cylinder radius="0.18" length="0.62"/></geometry>
    </collision>"#;
    assert!(text.contains(cyl));
    let with_mesh = text.replacen(
        cyl,
        &format!(
            r#"{cyl}
    <collision>
      <origin xyz="-0.02 0 -0.29" rpy="0 0 0"/>
      <geometry><mesh filename="cube.stl"/></geometry>
    </collision>"#
        ),
        1,
    );
    std::fs::write(&urdf, with_mesh).unwrap();
    let srdf = d.join("sawyer.srdf");
    let srdf_text = r#"<?xml version="1.0"?>
<robot name="sawyer">
  <disable_collisions link1="pedestal" link2="controller_box" reason="Adjacent"/>
</robot>
"#;
    std::fs::write(&srdf, srdf_text).unwrap();
    let rig_text = std::fs::read_to_string(&rig).unwrap().replacen(
        "urdf = \"sawyer.urdf\"",
        "urdf = \"sawyer.urdf\"\nsrdf = \"sawyer.srdf\"",
        1,
    );
    std::fs::write(&rig, rig_text).unwrap();
    let b = d.join("b.csv");
    let o = cli(&[
        "boundary",
        "--fibonacci",
        "2",
        "--quarter",
        "--quiet",
        "--out",
        s(&b),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.join("r.csv");
    let reach = |extra: &[&str]| {
        let mut a = vec![
            "reach",
            "--rig",
            s(&rig),
            "--fibonacci",
            "2",
            "--quarter",
            "--boundary",
            s(&b),
            "--quiet",
            "--out",
            s(&out),
        ];
        a.extend_from_slice(extra);
        cli(&a)
    };
    let o = reach(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = std::fs::read_to_string(&out).unwrap();
    let record = std::fs::read_to_string(helixreach::io::sidecar_path(&out)).unwrap();
    for f in ["cube.stl=", "sawyer.srdf="] {
        assert!(record.contains(f), "{f} not in {record}");
    }
    // Control: unchanged files resume.
    let o = reach(&["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Each file changed in turn (and restored after).
    let refused = |file: &Path, changed: Vec<u8>, setting: &str, name: &str| {
        let original = std::fs::read(file).unwrap();
        assert_ne!(changed, original);
        std::fs::write(file, changed).unwrap();
        let o = reach(&["--resume"]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains(setting) && e.contains(name), "{e}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), rows);
        std::fs::write(file, original).unwrap();
    };
    refused(
        &d.join("cube.stl"),
        cube_stl(0.011),
        "robot_files",
        "cube.stl",
    );
    refused(
        &srdf,
        srdf_text.replace("Adjacent", "Never").into_bytes(),
        "robot_files",
        "sawyer.srdf",
    );
    let table = std::fs::read_to_string(&b).unwrap();
    let last = table.lines().last().unwrap().to_string();
    let f: Vec<&str> = last.split(',').collect();
    let nudged = format!("{}", f[3].parse::<f64>().unwrap() * 1.01);
    let edited = table.replace(&last, &last.replacen(f[3], &nudged, 1));
    refused(&b, edited.into_bytes(), "boundary", "table");
    // Restored, everything resumes again.
    let o = reach(&["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

// ---------------------------------------------------------------------------------------------
// A class never overstates the plan
// ---------------------------------------------------------------------------------------------

/// The seed rig with `planner.max_waypoints = 10`: the adaptive pose path of every ray is cut
/// long before s*·(1 + margin).
fn rig_with_few_waypoints() -> helixreach::planning::rig::Rig {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let text = std::fs::read_to_string(root.join("sawyer-seed.toml")).unwrap();
    assert!(text.contains("\nmax_waypoints = 20000\n"));
    let text = text.replace("\nmax_waypoints = 20000\n", "\nmax_waypoints = 10\n");
    helixreach::planning::rig::Rig::from_toml_str(&text, "few-waypoints.toml", &root).unwrap()
}

/// The class invariant: `testable` means the plan reached s*·(1 + margin) (its `s_end`).
/// With `max_waypoints = 10` the pose path ends early and no ray may be called testable.
#[test]
fn a_ray_cut_by_the_waypoint_limit_is_never_testable() {
    use helixreach::planning::cause::BlockCause;
    use helixreach::planning::planner::{Planner, ReachClass};
    let planner = Planner::new(rig_with_few_waypoints()).unwrap();
    let margin = planner.rig().planner.margin;
    let mut cut = 0;
    for d in helixreach::directions::fibonacci(6, true).unwrap() {
        let s_star = helixreach::boundary::continuum::critical_s(&d, 1e-10)
            .unwrap()
            .s_star;
        let plan = planner
            .plan_best_typed(&d, s_star, None, &[0.0], planner.rig().roll, false)
            .unwrap();
        let s_end = s_star * (1.0 + margin);
        assert!(
            plan.class != ReachClass::Testable || plan.s_reached >= s_end * (1.0 - 1e-12),
            "{d:?}: testable with s_reached {} < s*·(1 + margin) = {s_end}",
            plan.s_reached
        );
        if plan.cause == Some(BlockCause::WaypointLimit) {
            assert_eq!(plan.class, ReachClass::Partial, "{d:?}");
            assert!(plan.s_reached < s_end, "{d:?}");
            cut += 1;
        }
    }
    assert!(cut > 0, "no ray reported the waypoint limit");
}

/// The same through the binary (the reported reproduction): every row's class agrees with its
/// numbers.
#[test]
fn reach_rows_cut_by_the_waypoint_limit_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let text = std::fs::read_to_string(root.join("sawyer-seed.toml"))
        .unwrap()
        .replace("\nmax_waypoints = 20000\n", "\nmax_waypoints = 10\n");
    let rig = dir.path().join("rig.toml");
    std::fs::write(&rig, text).unwrap();
    let out = dir.path().join("r.csv");
    let o = cli(&[
        "reach",
        "--rig",
        s(&rig),
        "--fibonacci",
        "6",
        "--quarter",
        "--quiet",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = data_rows(&out);
    assert_eq!(rows.len(), 6);
    let mut cut = 0;
    for r in &rows {
        let f: Vec<&str> = r.split(',').collect();
        let (s_star, s_reached, class, cause) = (f[3], f[4], f[5], f[6]);
        let (s_star, s_reached): (f64, f64) = (s_star.parse().unwrap(), s_reached.parse().unwrap());
        // The seed rig's margin is 0.1.
        let reached_end = s_reached >= s_star * 1.1 * (1.0 - 1e-12);
        assert_eq!(class == "testable", reached_end, "{r}");
        cut += usize::from(cause == "waypoint_limit");
    }
    assert!(cut > 0, "{rows:?}");
}

// ---------------------------------------------------------------------------------------------
// A refused direction is a row with its reason
// ---------------------------------------------------------------------------------------------

/// `boundary --method der` on a set holding a direction DER refuses (κ̂ = 1e-9, too close to
/// the κ = 0 plane): the sweep finishes with that direction's row carrying the reason, resumes
/// past it, and a `--boundary` table with it is refused naming the line.
#[test]
fn a_refused_der_direction_is_a_row_and_the_sweep_finishes_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let dirs = dir.path().join("d.csv");
    std::fs::write(
        &dirs,
        "dir_kappa,dir_tau,dir_omega\n0.5,0.5,0.5\n1e-9,0.6,-0.8\n0.3,0.9,0.3\n",
    )
    .unwrap();
    let out = dir.path().join("b.csv");
    let run = |extra: &[&str]| {
        let mut a = vec![
            "boundary",
            "--method",
            "der",
            "--n-edges",
            "40",
            "--directions",
            s(&dirs),
            "--out",
            s(&out),
        ];
        a.extend_from_slice(extra);
        cli(&a)
    };
    let o = run(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = data_rows(&out);
    assert_eq!(rows.len(), 3, "{rows:?}");
    let f: Vec<&str> = rows[1].split(',').collect();
    // No s*: empty fields, never a NaN.
    assert_eq!(f[3], "", "{}", rows[1]);
    assert!(rows[1].contains("kappa = 0 plane"), "{}", rows[1]);
    for r in [&rows[0], &rows[2]] {
        let f: Vec<&str> = r.split(',').collect();
        assert!(f[3].parse::<f64>().unwrap().is_finite(), "{r}");
        assert_eq!(f.last(), Some(&""), "{r}");
    }
    let text = std::fs::read_to_string(&out).unwrap();
    let o = run(&["--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 computed, 3 resumed"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
    let o = cli(&[
        "reach",
        "--directions",
        s(&dirs),
        "--boundary",
        s(&out),
        "--out",
        s(&dir.path().join("r.csv")),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("b.csv:3") && stderr(&o).contains("refused"),
        "{}",
        stderr(&o)
    );
}
