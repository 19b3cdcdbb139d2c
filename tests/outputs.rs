//! The one writer, through every command that writes a file: a FIFO and a character device given
//! as the output survive (written in place, never replaced by a regular file); no overwrite
//! without `--force`, never onto the command's own input or a finished sweep output, nor onto a
//! path a running writer holds locked; symlinks planted at the lock, probe and temp names are
//! never followed; a failed write (file size limit) leaves no temp file and the previous output
//! intact; `merge` and `--resume` check every row read back (NaN, text, a number cut short) and
//! `merge` reads each input once (a FIFO).
//!
//! The device tests need `mknod` (root, as in CI); they fail, not skip, without it.

#![cfg(unix)]

use helixreach::io::{lock_path, sidecar_path, temp_path, write_atomic, Output};
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_helixreach"));
    c.env("RAYON_NUM_THREADS", "2");
    c
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Run the binary (killed after 120 s: a hang fails the test).
fn run(args: &[&str]) -> std::process::Output {
    let mut child = bin()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > Duration::from_secs(120) {
            child.kill().unwrap();
            panic!("helixreach {args:?} did not finish in 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(args: &[&str]) -> std::process::Output {
    let o = run(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

fn mkfifo(p: &Path) {
    let c = std::ffi::CString::new(s(p)).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(
        unsafe { libc::mkfifo(c.as_ptr(), 0o600) },
        0,
        "mkfifo {p:?}"
    );
}

/// A character device equal to /dev/null (major 1, minor 3).
fn mknod_null(p: &Path) -> u64 {
    let c = std::ffi::CString::new(s(p)).unwrap();
    // SAFETY: a valid NUL-terminated path; the device number of /dev/null.
    let rc = unsafe { libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 3)) };
    assert_eq!(
        rc,
        0,
        "mknod {p:?}: {} (the writer tests run as root)",
        std::io::Error::last_os_error()
    );
    use std::os::unix::fs::MetadataExt;
    std::fs::symlink_metadata(p).unwrap().rdev()
}

/// Run `args` with `OUT` replaced by a FIFO, then by a character device; both must survive as
/// what they were, the FIFO must have carried text starting with `head`, and no sidecar or temp
/// file may appear beside them.
fn survives_fifo_and_device(args: &[&str], head: &str) {
    let dir = tempfile::tempdir().unwrap();
    // The figure's format follows the extension.
    let ext = if args[0] == "plot" { "png" } else { "csv" };
    let fifo = dir.path().join(format!("pipe.{ext}"));
    mkfifo(&fifo);
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = fifo.clone();
    std::thread::spawn(move || {
        let _ = tx.send(std::fs::read(reader).unwrap_or_default());
    });
    let with = |target: &Path| -> Vec<String> {
        args.iter()
            .map(|a| {
                if *a == "OUT" {
                    s(target).to_string()
                } else {
                    a.to_string()
                }
            })
            .collect()
    };
    let a = with(&fifo);
    let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    // Unblock a reader still waiting to open (the command failed before opening the FIFO).
    let _ = std::fs::OpenOptions::new()
        .write(true)
        .custom_flags_nonblock()
        .open(&fifo);
    assert!(o.status.success(), "{args:?} into a FIFO: {}", stderr(&o));
    let got = rx.recv_timeout(Duration::from_secs(30)).unwrap();
    assert!(
        got.starts_with(head.as_bytes()),
        "{args:?}: the FIFO carried {:?}",
        String::from_utf8_lossy(&got[..got.len().min(200)])
    );
    let t = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(t.is_fifo(), "{args:?}: the FIFO was replaced");

    let null = dir.path().join(format!("null.{ext}"));
    let rdev = mknod_null(&null);
    let a = with(&null);
    let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{args:?} into a device: {}", stderr(&o));
    use std::os::unix::fs::MetadataExt;
    let m = std::fs::symlink_metadata(&null).unwrap();
    assert!(
        m.file_type().is_char_device() && m.rdev() == rdev,
        "{args:?}: the device was replaced"
    );
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names.len(),
        2,
        "{args:?}: files appeared beside them: {names:?}"
    );
}

trait NonBlock {
    fn custom_flags_nonblock(&mut self) -> &mut Self;
}

impl NonBlock for std::fs::OpenOptions {
    fn custom_flags_nonblock(&mut self) -> &mut Self {
        use std::os::unix::fs::OpenOptionsExt;
        self.custom_flags(libc::O_NONBLOCK)
    }
}

/// Inputs shared by the command tests: a measured file, a trajectory, a boundary sweep and its
/// shards.
struct Inputs {
    _dir: tempfile::TempDir,
    measured: PathBuf,
    trajectory: PathBuf,
    boundary: PathBuf,
    shards: Vec<PathBuf>,
}

fn inputs() -> Inputs {
    let dir = tempfile::tempdir().unwrap();
    let measured = dir.path().join("m.csv");
    std::fs::write(
        &measured,
        "dir_kappa,dir_tau,dir_omega,s_measured\n1,0,0,6.3\n0.6,0.8,0,7.1\n",
    )
    .unwrap();
    let trajectory = dir.path().join("t.csv");
    ok(&[
        "plan",
        "--direction",
        "0.6,0.8,0",
        "--waypoints",
        "20",
        "--allow-partial",
        "--out",
        s(&trajectory),
    ]);
    let boundary = dir.path().join("b.csv");
    ok(&["boundary", "--fibonacci", "12", "--out", s(&boundary)]);
    let shards: Vec<PathBuf> = (0..2)
        .map(|i| {
            let p = dir.path().join(format!("s{i}.csv"));
            let shard = format!("{i}/2");
            ok(&[
                "boundary",
                "--fibonacci",
                "12",
                "--shard",
                &shard,
                "--out",
                s(&p),
            ]);
            p
        })
        .collect();
    Inputs {
        _dir: dir,
        measured,
        trajectory,
        boundary,
        shards,
    }
}

#[test]
fn every_command_writes_fifos_and_devices_in_place() {
    let i = inputs();
    let header = "dir_kappa,dir_tau,dir_omega";
    survives_fifo_and_device(
        &[
            "plan",
            "--direction",
            "0.6,0.8,0",
            "--waypoints",
            "20",
            "--allow-partial",
            "--out",
            "OUT",
        ],
        "t,",
    );
    let traj = s(&i.trajectory).to_string();
    let scratch = tempfile::tempdir().unwrap();
    let t2 = scratch.path().join("t2.csv");
    survives_fifo_and_device(
        &[
            "plan",
            "--direction",
            "0.6,0.8,0",
            "--waypoints",
            "20",
            "--allow-partial",
            "--out",
            s(&t2),
            "--force",
            "--json",
            "OUT",
        ],
        "{",
    );
    survives_fifo_and_device(
        &[
            "simulate",
            "--direction",
            "1,0,0",
            "--s-max",
            "0.2",
            "--out",
            "OUT",
        ],
        "t,",
    );
    survives_fifo_and_device(
        &[
            "compare",
            "--measured",
            s(&i.measured),
            "--method",
            "continuum",
            "--out",
            "OUT",
        ],
        header,
    );
    survives_fifo_and_device(
        &[
            "check",
            "--trajectory",
            &traj,
            "--report-only",
            "--out",
            "OUT",
        ],
        "",
    );
    let mut merge = vec!["merge", "--out", "OUT"];
    merge.extend(i.shards.iter().map(|p| s(p)));
    survives_fifo_and_device(&merge, header);
    survives_fifo_and_device(&["boundary", "--fibonacci", "5", "--out", "OUT"], header);
    survives_fifo_and_device(
        &[
            "bifurcation",
            "--fibonacci",
            "1",
            "--n-edges",
            "20",
            "--out",
            "OUT",
        ],
        header,
    );
    survives_fifo_and_device(
        &[
            "reach",
            "--rig",
            "sawyer-seed",
            "--fibonacci",
            "1",
            "--quarter",
            "--out",
            "OUT",
        ],
        header,
    );
    survives_fifo_and_device(
        &[
            "plot",
            "boundary3d",
            "--input",
            s(&i.boundary),
            "--out",
            "OUT",
        ],
        "",
    );
    survives_fifo_and_device(
        &[
            "robot",
            "--robot",
            "sawyer",
            "--write-disabled",
            "OUT",
            "--samples",
            "10000",
        ],
        "",
    );
}

/// No overwrite without `--force`; never onto the command's own input, nor
/// onto a finished sweep output, nor onto a path a running writer holds locked.
#[test]
fn commands_never_overwrite_inputs_finished_results_or_locked_paths() {
    let i = inputs();
    let measured = std::fs::read(&i.measured).unwrap();
    let o = run(&[
        "compare",
        "--measured",
        s(&i.measured),
        "--method",
        "continuum",
        "--out",
        s(&i.measured),
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("is an input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&i.measured).unwrap(), measured);

    let traj = std::fs::read(&i.trajectory).unwrap();
    let o = run(&[
        "check",
        "--trajectory",
        s(&i.trajectory),
        "--out",
        s(&i.trajectory),
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("is an input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&i.trajectory).unwrap(), traj);

    // Without --force an existing file is kept; with it, it is replaced.
    let o = run(&[
        "plan",
        "--direction",
        "1,0,0",
        "--waypoints",
        "20",
        "--allow-partial",
        "--out",
        s(&i.trajectory),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&i.trajectory).unwrap(), traj);

    // A trajectory (its sidecar is no sweep record) is replaced with --force, sidecar and all.
    ok(&[
        "plan",
        "--direction",
        "1,0,0",
        "--waypoints",
        "20",
        "--allow-partial",
        "--force",
        "--out",
        s(&i.trajectory),
    ]);
    let meta = std::fs::read_to_string(sidecar_path(&i.trajectory)).unwrap();
    assert!(meta.contains("\"format\""), "{meta}");

    // A finished sweep output (it has a settings record) is never replaced by another command.
    let finished = std::fs::read(&i.boundary).unwrap();
    for args in [
        vec![
            "plan",
            "--direction",
            "1,0,0",
            "--waypoints",
            "20",
            "--allow-partial",
            "--force",
            "--out",
        ],
        vec![
            "simulate",
            "--direction",
            "1,0,0",
            "--s-max",
            "0.2",
            "--force",
            "--out",
        ],
    ] {
        let mut a = args.clone();
        a.push(s(&i.boundary));
        let o = run(&a);
        assert_eq!(o.status.code(), Some(2), "{a:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("finished sweep output"),
            "{}",
            stderr(&o)
        );
        assert_eq!(std::fs::read(&i.boundary).unwrap(), finished);
    }

    // A path a running writer holds locked.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("held.csv");
    let lock = helixreach::io::OutputLock::acquire(&out).unwrap();
    let o = run(&[
        "simulate",
        "--direction",
        "1,0,0",
        "--s-max",
        "0.2",
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("is being written"), "{}", stderr(&o));
    assert!(!out.exists());
    drop(lock);
    ok(&[
        "simulate",
        "--direction",
        "1,0,0",
        "--s-max",
        "0.2",
        "--out",
        s(&out),
    ]);
}

/// Symlinks planted at the lock, temp and probe names are never followed.
#[test]
fn planted_symlinks_are_never_followed() {
    let dir = tempfile::tempdir().unwrap();
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    let out = dir.path().join("out.csv");

    // OUT.lock → victim: the writer refuses the lock, the victim is untouched.
    std::os::unix::fs::symlink(&victim, lock_path(&out)).unwrap();
    let e = Output::new(&out).write(b"x\n").unwrap_err().to_string();
    assert!(e.contains("symbolic link"), "{e}");
    let o = run(&["boundary", "--fibonacci", "4", "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    std::fs::remove_file(lock_path(&out)).unwrap();

    // OUT.<pid>.tmp → victim (this process's temp name, used by the atomic write and by the
    // probe of the output's directory): replaced by the writer's own file, never written through.
    std::os::unix::fs::symlink(&victim, temp_path(&out)).unwrap();
    helixreach::io::check_output(&out).unwrap();
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    std::os::unix::fs::symlink(&victim, temp_path(&out)).unwrap();
    write_atomic(&out, b"new\n").unwrap();
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "new\n");
    assert!(std::fs::symlink_metadata(temp_path(&out)).is_err());

    // A lock file hard-linked to another file is refused (it would be truncated).
    let out2 = dir.path().join("out2.csv");
    std::fs::hard_link(&victim, lock_path(&out2)).unwrap();
    let e = Output::new(&out2).write(b"x\n").unwrap_err().to_string();
    assert!(e.contains("single link"), "{e}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
}

/// A write that fails part-way (the file size limit, as a full disk) leaves no temp file and
/// the previous output intact.
#[test]
fn a_failed_write_leaves_no_temp_and_the_old_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    ok(&["boundary", "--fibonacci", "40", "--out", s(&out)]);
    let before = std::fs::read(&out).unwrap();
    // SIGXFSZ ignored (inherited through exec): a write past the limit fails with EFBIG.
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f 2; exec {} boundary --fibonacci 2000 --force --out {}",
            env!("CARGO_BIN_EXE_helixreach"),
            s(&out)
        ))
        .output()
        .unwrap();
    assert!(!o.status.success(), "the limited write succeeded");
    assert_eq!(std::fs::read(&out).unwrap(), before, "old output damaged");
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temp files left: {left:?}");
}

/// Rewrite `csv` (a sweep output) with `text` and fix its sidecar's digest, so that only the
/// row checks can refuse it.
fn tamper(csv: &Path, text: &str) {
    std::fs::write(csv, text).unwrap();
    let side = sidecar_path(csv);
    let mut meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&side).unwrap()).unwrap();
    meta["csv"] = serde_json::json!({
        "rows": text.lines().count() - 1,
        "bytes": text.len(),
        "fnv1a": helixreach::sweep::record::fnv1a_hex(text.as_bytes()),
    });
    std::fs::write(&side, meta.to_string()).unwrap();
}

/// `merge` and `--resume` parse and check every row read back.
#[test]
fn merge_and_resume_refuse_bad_rows() {
    let i = inputs();
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&i.shards[1]).unwrap();
    let first_row = text.lines().nth(1).unwrap().to_string();
    let fields: Vec<&str> = first_row.split(',').collect();
    for (what, s_star, expect) in [
        ("nan", "NaN".to_string(), "is NaN"),
        ("text", "abc".to_string(), "is not a number"),
        ("cut", fields[3][..3].to_string() + "e", "is not a number"),
    ] {
        let bad = dir.path().join(format!("{what}.csv"));
        std::fs::copy(&i.shards[1], &bad).unwrap();
        std::fs::copy(sidecar_path(&i.shards[1]), sidecar_path(&bad)).unwrap();
        let mut f = fields.clone();
        f[3] = &s_star;
        tamper(&bad, &text.replacen(&first_row, &f.join(","), 1));
        let out = dir.path().join(format!("merged-{what}.csv"));
        let o = run(&["merge", "--out", s(&out), s(&i.shards[0]), s(&bad)]);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&format!("{what}.csv:2")) && e.contains("s_star") && e.contains(expect),
            "{what}: {e}"
        );
        assert!(!out.exists());

        // The same file as a checkpoint to resume.
        let res = dir.path().join(format!("res-{what}.csv"));
        std::fs::copy(&bad, format!("{}.partial", s(&res))).unwrap();
        std::fs::copy(sidecar_path(&bad), format!("{}.partial.meta.json", s(&res))).unwrap();
        let o = run(&[
            "boundary",
            "--fibonacci",
            "12",
            "--shard",
            "1/2",
            "--resume",
            "--out",
            s(&res),
        ]);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(&o));
        assert!(stderr(&o).contains("s_star"), "{what}: {}", stderr(&o));
        assert!(!res.exists());
    }
    // A CSV without its sidecar is refused naming both files.
    let bare = dir.path().join("bare.csv");
    std::fs::copy(&i.shards[0], &bare).unwrap();
    let o = run(&[
        "merge",
        "--out",
        s(&dir.path().join("x.csv")),
        s(&bare),
        s(&i.shards[1]),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("bare.csv") && e.contains("bare.csv.meta.json"),
        "{e}"
    );
}

/// `merge` reads each input once: a shard given as a FIFO (its sidecar beside it) merges.
#[test]
fn merge_reads_each_input_once() {
    let i = inputs();
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("s1.csv");
    mkfifo(&fifo);
    std::fs::copy(sidecar_path(&i.shards[1]), sidecar_path(&fifo)).unwrap();
    let bytes = std::fs::read(&i.shards[1]).unwrap();
    let w = fifo.clone();
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new().write(true).open(w).unwrap();
        f.write_all(&bytes).unwrap();
    });
    let out = dir.path().join("merged.csv");
    ok(&["merge", "--out", s(&out), s(&i.shards[0]), s(&fifo)]);
    writer.join().unwrap();
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&i.boundary).unwrap()
    );
}

/// Standard output: CSV outputs stream there; a figure (binary) is refused with a clear error.
#[test]
fn dash_is_standard_output_and_binary_is_refused_there() {
    let i = inputs();
    let o = ok(&[
        "compare",
        "--measured",
        s(&i.measured),
        "--method",
        "continuum",
        "--out",
        "-",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.starts_with("dir_kappa,dir_tau,dir_omega,s_measured"),
        "{text}"
    );
    let o = run(&[
        "plot",
        "boundary3d",
        "--input",
        s(&i.boundary),
        "--out",
        "-",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("standard output"), "{}", stderr(&o));
}
