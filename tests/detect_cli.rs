//! `helixreach detect` end to end on the vendored seed runs: one run (JSON on stdout, per-sample
//! CSV, exit code), the batch (`--runs`) read by `compare --measured`, resume of a finished batch,
//! `plot detection`, and bad input naming the file and line.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

/// Unpack a vendored run into `dir`.
fn unpack(name: &str, dir: &Path) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/seed_observations")
        .join(format!("{name}.txt.gz"));
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(src).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let p = dir.join(format!("{name}.txt"));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn one_run_batch_compare_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let snap = unpack("test_c1_0.75_c2_0", d);
    unpack("test_c1_0.23796_c2_-0.11174", d);
    // One run with a snap: exit 0, JSON summary, per-sample CSV with one row per sample.
    let out = Command::new(BIN)
        .args(["detect", "--rig", "sawyer-seed", "--direction", "0.8,0.6,0"])
        .args(["--clamp", "0.85,-0.15,-0.146", "--observations"])
        .arg(&snap)
        .arg("--out")
        .arg(d.join("samples.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["reason"], "snap");
    let s = v["s_snap"].as_f64().unwrap();
    assert!((s - 7.58075).abs() / 7.58075 < 0.01, "{s}");
    let csv = std::fs::read_to_string(d.join("samples.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4510 + 1);
    std::fs::write(d.join("summary.json"), &out.stdout).unwrap();
    // The figure.
    let st = Command::new(BIN)
        .args(["plot", "detection", "--input"])
        .arg(d.join("samples.csv"))
        .arg("--input2")
        .arg(d.join("summary.json"))
        .arg("--out")
        .arg(d.join("det.svg"))
        .status()
        .unwrap();
    assert!(st.success());
    let svg = std::fs::read_to_string(d.join("det.svg")).unwrap();
    assert!(svg.contains("predicted s*") && svg.contains("snap at s ="));
    // A supercritical run: no snap, exit 1, the reason on stdout.
    let out = Command::new(BIN)
        .args([
            "detect",
            "--direction",
            "0.967138437,0.230140262,-0.108068049",
        ])
        .args(["--clamp", "0.85,-0.15,-0.146", "--observations"])
        .arg(d.join("test_c1_0.23796_c2_-0.11174.txt"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (v["reason"].as_str(), v["s_snap"].as_f64()),
        (Some("gradual"), None)
    );
    // The batch, with one bad run (a missing file): rows in order, the bad one rejected.
    std::fs::write(
        d.join("runs.csv"),
        "observations,dir_kappa,dir_tau,dir_omega,clamp_x,clamp_y,clamp_z\n\
         test_c1_0.75_c2_0.txt,0.8,0.6,0,0.85,-0.15,-0.146\n\
         test_c1_0.23796_c2_-0.11174.txt,0.967138437,0.230140262,-0.108068049,,,\n\
         missing.txt,0.8,0.6,0,0.85,-0.15,-0.146\n",
    )
    .unwrap();
    let run_batch = |extra: &[&str]| {
        Command::new(BIN)
            .args(["detect", "--quiet", "--runs"])
            .arg(d.join("runs.csv"))
            .arg("--out")
            .arg(d.join("measured.csv"))
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run_batch(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("runs.csv:4") && err.contains("missing.txt"),
        "{err}"
    );
    let text = std::fs::read_to_string(d.join("measured.csv")).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows.len(), 4);
    assert!(rows[1].starts_with("test_c1_0.75_c2_0.txt,") && rows[1].contains(",snap,"));
    assert!(rows[2].contains(",,,none,gradual,"), "{}", rows[2]);
    assert!(rows[3].contains(",rejected,"), "{}", rows[3]);
    // A finished batch is not redone without --resume or --force.
    assert!(!run_batch(&[]).status.success());
    // compare reads it: one measured direction, the runs without a snap skipped with a note.
    let out = Command::new(BIN)
        .args(["compare", "--method", "continuum", "--measured"])
        .arg(d.join("measured.csv"))
        .arg("--out")
        .arg(d.join("cmp.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["count"], 1);
    assert!(String::from_utf8_lossy(&out.stderr).contains("2 runs without a snap"));
}

#[test]
fn bad_files_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.txt");
    std::fs::write(&p, "1 2 3 4 5 6 7 0.1 0.2 0.3\n1 2 3 4 5 6 0.1 0.2 0.3\n").unwrap();
    let out = Command::new(BIN)
        .args(["detect", "--direction", "0.8,0.6,0", "--observations"])
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.txt:2") && err.contains("9 fields"),
        "{err}"
    );
    std::fs::write(&p, "").unwrap();
    let out = Command::new(BIN)
        .args(["detect", "--direction", "0.8,0.6,0", "--observations"])
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("empty file"));
}
