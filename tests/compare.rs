//! Measured versus simulated boundaries: the `compare` library and command.
//!
//! Checked against an independent recomputation of the paper's statistics from the written CSV,
//! the seed's 119 measured snap points (read from `tests/data/seed/`, relative to the crate
//! root), and
//! every kind of bad input.

mod common;
use common::seed_data;
use helixreach::compare::{compare, match_boundary, Measured};
use helixreach::directions::Direction;
use helixreach::records::compare::read_measured;
use std::path::PathBuf;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn seed_measured_file_reads_119_unit_directions_in_order() {
    let m = read_measured(&seed_data("measured_boundary.csv")).unwrap();
    assert_eq!(m.rows.len(), 119);
    assert!(m.notes.is_empty(), "{:?}", m.notes);
    assert!((m.rows[0].dir.kappa - 0.875754).abs() < 1e-5);
    assert!((m.rows[0].s_measured - 8.01886).abs() < 1e-12);
    assert_eq!(m.rows[0].line, 2);
    assert_eq!(m.rows[118].line, 120);
}

#[test]
fn statistics_are_the_papers_err_with_population_std() {
    let d = |k, t, w| Direction::new(k, t, w).unwrap();
    let m = vec![
        Measured {
            dir: d(1.0, 0.1, 0.0),
            s_measured: 7.0,
            line: 2,
        },
        Measured {
            dir: d(1.0, 0.2, 0.0),
            s_measured: 9.0,
            line: 3,
        },
        Measured {
            dir: d(1.0, 0.3, 0.0),
            s_measured: 8.0,
            line: 4,
        },
        Measured {
            dir: d(1.0, 0.4, 0.0),
            s_measured: 5.0,
            line: 5,
        },
    ];
    let sim = [Some(8.0), Some(8.0), None, Some(4.0)];
    let c = compare(&m, &sim);
    // err = 1/8, 1/8, 1/4 → mean 1/6, population variance ((1/24)²·2 + (1/12)²)/3.
    let mean = 1.0 / 6.0;
    let var = (2.0 * (1.0f64 / 24.0).powi(2) + (1.0f64 / 12.0).powi(2)) / 3.0;
    assert_eq!(c.stats.count, 3);
    assert!((c.stats.mean - mean).abs() < 1e-15);
    assert!((c.stats.max - 0.25).abs() < 1e-15);
    assert!((c.stats.std - var.sqrt()).abs() < 1e-15);
    assert!((c.stats.mean_signed_diff - (-1.0 + 1.0 + 1.0) / 3.0).abs() < 1e-15);
    assert_eq!(c.missing, vec![2]);
    assert_eq!(c.rows.len(), 4, "a direction without a value keeps its row");
    assert_eq!(c.rows[2].s_sim, None);
    assert_eq!(c.rows[1].signed_diff, Some(1.0));
    let j = c.summary_json(&m);
    assert_eq!(j["std_kind"], "population");
    assert_eq!(j["missing"][0]["line"], 4);
}

#[test]
fn boundary_values_match_by_direction_not_by_row() {
    let d = |k, t, w| Direction::new(k, t, w).unwrap();
    let m = vec![
        Measured {
            dir: d(1.0, 1.0, 0.0),
            s_measured: 7.0,
            line: 2,
        },
        Measured {
            dir: d(1.0, 0.0, 1.0),
            s_measured: 7.0,
            line: 3,
        },
    ];
    let b = vec![
        (d(1.0, 0.0, 1.0), 6.0),
        (d(2.0, 2.0, 0.0), 5.0),
        (d(0.0, 1.0, 0.0), f64::INFINITY),
    ];
    assert_eq!(match_boundary(&m, &b), vec![Some(5.0), Some(6.0)]);
    let m2 = vec![Measured {
        dir: d(0.0, 1.0, 0.0),
        s_measured: 7.0,
        line: 2,
    }];
    assert_eq!(match_boundary(&m2, &b), vec![None], "s* = inf has no value");
}

#[test]
fn bad_measured_files_name_file_line_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let h = "dir_kappa,dir_tau,dir_omega,s_measured\n";
    let cases = [
        (
            "zero.csv",
            format!("{h}1,0,0,7\n1,0.1,0,0\n"),
            ":3: s_measured: 0 must be > 0",
        ),
        (
            "neg.csv",
            format!("{h}1,0,0,-2.5\n"),
            ":2: s_measured: -2.5 must be > 0",
        ),
        (
            "nan.csv",
            format!("{h}1,0,0,7\nNaN,0,0,7\n"),
            ":3: dir_kappa: NaN is not finite",
        ),
        (
            "text.csv",
            format!("{h}1,0,zero,7\n"),
            ":2: dir_omega: `zero` is not a number",
        ),
        ("neg_kappa.csv", format!("{h}-1,0,0,7\n"), ":2: direction"),
        (
            "unknown.csv",
            "dir_kappa,dir_tau,dir_omega,s_measured,s_star\n1,0,0,7,6\n".into(),
            "unknown column `s_star`",
        ),
        (
            "missing.csv",
            "dir_kappa,dir_tau,s_measured\n1,0,7\n".into(),
            "missing column `dir_omega`",
        ),
        ("empty.csv", h.to_string(), "no measured directions"),
    ];
    for (name, text, want) in cases {
        let p = write(&dir, name, &text);
        let e = read_measured(&p).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
    // Not normalized: normalized with a note naming the line.
    let p = write(&dir, "scaled.csv", &format!("{h}2,0,0,7\n1,0,0,7\n"));
    let m = read_measured(&p).unwrap();
    assert_eq!(m.notes.len(), 1);
    assert!(
        m.notes[0].contains("scaled.csv:2") && m.notes[0].contains("normalized"),
        "{}",
        m.notes[0]
    );
    assert_eq!(m.rows[0].dir.kappa, 1.0);
}

#[test]
fn cli_continuum_on_the_seed_points_keeps_order_and_its_json_matches_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    let meas = seed_data("measured_boundary.csv");
    let o = Command::new(BIN)
        .args(["compare", "--measured"])
        .arg(&meas)
        .args(["--method", "continuum", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "dir_kappa,dir_tau,dir_omega,s_measured,s_sim,err,signed_diff"
    );
    let m = read_measured(&meas).unwrap();
    let mut errs = vec![];
    for (l, r) in lines.zip(&m.rows) {
        let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(f[3], r.s_measured, "rows in the order of the measured file");
        // The simulated value is the continuum s* of that direction (recomputed here).
        let s = helixreach::boundary::continuum::critical_s(&r.dir, 1e-10)
            .unwrap()
            .s_star;
        assert!((f[4] - s).abs() < 1e-8 * s);
        assert!((f[5] - (f[3] - f[4]).abs() / f[4]).abs() < 1e-14);
        assert!((f[6] - (f[3] - f[4])).abs() < 1e-12);
        errs.push(f[5]);
    }
    assert_eq!(errs.len(), 119);
    let n = errs.len() as f64;
    let mean = errs.iter().sum::<f64>() / n;
    let std = (errs.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert_eq!(j["count"], 119);
    assert!((j["mean"].as_f64().unwrap() - mean).abs() < 1e-12);
    assert!((j["std"].as_f64().unwrap() - std).abs() < 1e-12);
    assert_eq!(j["missing"].as_array().unwrap().len(), 0);
    // The real rod snaps near the prediction: the paper reports a few per cent on average.
    assert!(mean < 0.1, "mean err {mean}");
}

#[test]
fn cli_boundary_file_lists_directions_without_a_value() {
    let dir = tempfile::tempdir().unwrap();
    let meas = write(
        &dir,
        "m.csv",
        "dir_kappa,dir_tau,dir_omega,s_measured\n1,0,0,6.5\n0.6,0.8,0,7\n",
    );
    let b = write(
        &dir,
        "b.csv",
        "dir_kappa,dir_tau,dir_omega,s_star\n1,0,0,6.283185307179586\n",
    );
    let out = dir.path().join("c.csv");
    let o = Command::new(BIN)
        .args(["compare", "--measured"])
        .arg(&meas)
        .arg("--boundary")
        .arg(&b)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["count"], 1);
    assert_eq!(j["missing"][0]["line"], 3);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("m.csv:3")
            && err.contains("no simulated boundary")
            && err.contains("not in")
            && err.contains("b.csv"),
        "{err}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().nth(2).unwrap(), "0.6,0.8,0,7,,,");
    // A bad measured file fails with exit code 2 and names file, line and value.
    let bad = write(
        &dir,
        "bad.csv",
        "dir_kappa,dir_tau,dir_omega,s_measured\n1,0,0,0\n",
    );
    let o = Command::new(BIN)
        .args(["compare", "--measured"])
        .arg(&bad)
        .args(["--method", "continuum", "--out"])
        .arg(dir.path().join("x.csv"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.csv:2") && err.contains("s_measured"),
        "{err}"
    );
}

/// A boundary computed on other directions matches no measured row: refused, naming both files
/// and the way out, nothing written; the boundary on the measured directions then compares.
#[test]
fn cli_boundary_on_other_directions_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let meas = write(
        &dir,
        "m.csv",
        "dir_kappa,dir_tau,dir_omega,s_measured\n1,0,0,6.3\n0.6,0.8,0,7.1\n",
    );
    let run = |args: &[&str]| {
        Command::new(BIN)
            .current_dir(dir.path())
            .args(args)
            .output()
            .unwrap()
    };
    let o = run(&[
        "--quiet",
        "boundary",
        "--fibonacci",
        "7",
        "--out",
        "fib.csv",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = run(&[
        "compare",
        "--measured",
        meas.to_str().unwrap(),
        "--boundary",
        "fib.csv",
        "--out",
        "c.csv",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("fib.csv holds none of the 2 directions of")
            && err.contains("m.csv")
            && err.contains("--directions"),
        "{err}"
    );
    assert!(o.stdout.is_empty());
    assert!(!dir.path().join("c.csv").exists());
    // What the error suggests works.
    let o = run(&[
        "--quiet",
        "boundary",
        "--directions",
        meas.to_str().unwrap(),
        "--out",
        "on.csv",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = run(&[
        "compare",
        "--measured",
        meas.to_str().unwrap(),
        "--boundary",
        "on.csv",
        "--out",
        "c.csv",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["count"], 2);
}
