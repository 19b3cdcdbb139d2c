//! `helixreach demo --quick` end to end: into a temporary folder, then check that every stage
//! finished, that the report exists in both forms, that its numbers parse, are consistent with
//! the CSVs beside it and equal the golden run, and that every figure it lists exists and is a
//! non-trivial image. A failing stage or an invalid rig makes the demo exit non-zero.
//!
//! **Golden run.** `tests/data/demo_quick_golden.json` holds the stage numbers of a quick run,
//! minus the timings: a refactoring must not change a number. When upstream numerics or the
//! planner change the results on purpose (the default decision of a ray, a resolution),
//! regenerate it deliberately and say so in the commit:
//! `HELIXREACH_BLESS_GOLDEN=1 cargo test --release --features interop --test demo`.

use serde_json::Value;
use std::path::Path;
use std::process::Command;

mod common;
use common::png::Png;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

/// (width, height, share of non-white pixels, distinct colours) of a PNG.
fn png_stats(path: &Path) -> (u32, u32, f64, usize) {
    let png = Png::read(path);
    (
        png.width,
        png.height,
        png.non_white_fraction(),
        png.distinct_colours(),
    )
}

fn finite_numbers(v: &Value, path: &str, out: &mut Vec<(String, f64)>) {
    match v {
        Value::Number(n) => out.push((path.to_string(), n.as_f64().unwrap())),
        Value::Object(m) => {
            for (k, x) in m {
                finite_numbers(x, &format!("{path}.{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                finite_numbers(x, &format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

#[test]
fn demo_quick_writes_report_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("figs");
    let res = Command::new(BIN)
        .args(["demo", "--quick", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert!(res.status.success(), "demo failed: {stderr}");
    // Progress goes to stderr, stage by stage.
    for stage in [
        "continuum boundary",
        "der check",
        "reachability",
        "dynamics",
        "trajectory",
        "figures",
    ] {
        assert!(
            stderr.contains(&format!("{stage}: start")),
            "no progress for {stage}: {stderr}"
        );
    }

    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert_eq!(json["settings"]["mode"], "quick");
    assert!(json["total_seconds"].as_f64().unwrap() > 0.0);
    let stages = json["stages"].as_object().unwrap();
    for name in [
        "continuum_boundary",
        "der_check",
        "reachability",
        "dynamics",
        "trajectory",
        "figures",
    ] {
        let s = &stages[name];
        // Every stage must finish: there is no "skipped".
        assert_eq!(s["status"], "done", "{name}: {s}");
    }
    assert_eq!(stages.len(), 6, "unexpected stages: {:?}", stages.keys());
    assert_eq!(json["failed"].as_array().map(Vec::len), Some(0));
    compare_with_golden(&json);
    // Every number in the report parses as a finite number or is an explicit ∞ / NaN stand-in
    // (JSON has no ∞: serde writes null, which is not a number and is skipped here).
    let mut nums = Vec::new();
    finite_numbers(&json, "", &mut nums);
    assert!(!nums.is_empty());
    for (p, v) in &nums {
        assert!(v.is_finite(), "{p} = {v}");
    }

    // Numbers agree with the CSVs they summarize.
    {
        let c = &stages["continuum_boundary"];
        let rows = helixreach::records::read_boundary(&out.join("boundary.csv")).unwrap();
        assert_eq!(
            c["directions"].as_u64().unwrap() as usize,
            rows.len() + c["failed"].as_u64().unwrap() as usize
        );
        let finite: Vec<f64> = rows
            .iter()
            .map(|r| r.s_star)
            .filter(|s| s.is_finite())
            .collect();
        let min = finite.iter().copied().fold(f64::INFINITY, f64::min);
        assert!((c["s_star_min"].as_f64().unwrap() - min).abs() <= 1e-12 * min);
        // The κ axis closes into a circle at 2π (an analytic limit, checked by the demo too).
        assert!(c["kappa_axis_rel_err_vs_2pi"].as_f64().unwrap() < 1e-6);
    }
    {
        let rows = helixreach::records::read_reach(&out.join("reach.csv")).unwrap();
        for mode in ["fixed", "motor"] {
            let r = &stages["reachability"][format!("roll_{mode}")];
            let n: Vec<_> = rows.iter().filter(|x| x.roll_mode == mode).collect();
            let testable = n
                .iter()
                .filter(|x| x.class == helixreach::records::ReachClass::Testable)
                .count();
            assert_eq!(r["testable"].as_u64().unwrap() as usize, testable, "{mode}");
            let f = r["fraction_testable"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&f));
        }
    }

    // Every listed figure exists and is non-trivial; PNGs are listed with their SVG twins.
    let figures: Vec<&str> = json["figures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    let expect = [
        ("continuum_boundary", "boundary3d"),
        ("continuum_boundary", "section"),
        ("continuum_boundary", "speed_error"),
        ("reachability", "directions"),
        ("dynamics", "error_vs_s"),
        ("trajectory", "trajectory"),
    ];
    for (_stage, fig) in expect {
        assert!(
            figures.contains(&format!("{fig}.png").as_str()),
            "missing {fig}.png"
        );
    }
    for f in &figures {
        let p = out.join(f);
        assert!(p.is_file(), "{f} listed but missing");
        if f.ends_with(".png") {
            let (w, h, ink, colours) = png_stats(&p);
            assert!(w >= 800 && h >= 600, "{f}: {w}x{h}");
            assert!(
                ink > 0.03 && colours > 50,
                "{f} looks blank: ink {ink}, {colours} colours"
            );
            let svg = p.with_extension("svg");
            assert!(figures.contains(&svg.file_name().unwrap().to_str().unwrap()));
            let text = std::fs::read_to_string(&svg).unwrap();
            assert!(
                text.contains("<text") && text.len() > 5000,
                "{f}: SVG too small"
            );
            assert!(
                md.contains(&format!("]({f})")),
                "report.md does not embed {f}"
            );
        }
    }
}

/// Keys whose values are timings (they differ from run to run).
fn is_timing(key: &str) -> bool {
    key.contains("seconds") || key == "time_per_direction_s"
}

/// The stage numbers of a report without timings and statuses: what the golden file holds.
fn golden_view(stages: &Value) -> Value {
    match stages {
        Value::Object(m) => Value::Object(
            m.iter()
                .filter(|(k, _)| !is_timing(k) && k.as_str() != "status")
                .map(|(k, v)| (k.clone(), golden_view(v)))
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.iter().map(golden_view).collect()),
        v => v.clone(),
    }
}

/// Every leaf of `golden` equals the run's (numbers to 1e-12 relative: the same computation).
fn same(golden: &Value, run: &Value, path: &str, diffs: &mut Vec<String>) {
    match (golden, run) {
        (Value::Object(g), Value::Object(r)) => {
            for (k, gv) in g {
                match r.get(k) {
                    Some(rv) => same(gv, rv, &format!("{path}.{k}"), diffs),
                    None => diffs.push(format!("{path}.{k}: missing (golden {gv})")),
                }
            }
        }
        (Value::Array(g), Value::Array(r)) if g.len() == r.len() => {
            for (i, (gv, rv)) in g.iter().zip(r).enumerate() {
                same(gv, rv, &format!("{path}[{i}]"), diffs);
            }
        }
        (Value::Number(g), Value::Number(r)) => {
            let (g, r) = (g.as_f64().unwrap(), r.as_f64().unwrap());
            if (g - r).abs() > 1e-12 * g.abs().max(r.abs()) {
                diffs.push(format!("{path}: golden {g}, run {r}"));
            }
        }
        (g, r) if g != r => diffs.push(format!("{path}: golden {g}, run {r}")),
        _ => {}
    }
}

fn compare_with_golden(report: &Value) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/demo_quick_golden.json");
    let view = golden_view(&report["stages"]);
    if std::env::var_os("HELIXREACH_BLESS_GOLDEN").is_some() {
        std::fs::write(&path, serde_json::to_string_pretty(&view).unwrap() + "\n").unwrap();
        eprintln!("wrote {}", path.display());
        return;
    }
    let golden: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let mut diffs = Vec::new();
    same(&golden, &view, "stages", &mut diffs);
    assert!(
        diffs.is_empty(),
        "the demo's numbers differ from {} (regenerate it deliberately if upstream results \
         changed on purpose, see the file docs):\n{}",
        path.display(),
        diffs.join("\n")
    );
}

#[test]
fn demo_with_an_invalid_rig_fails_loudly() {
    let dir = tempfile::tempdir().unwrap();
    let res = Command::new(BIN)
        .args(["demo", "--quick", "--rig", "no-such-rig.toml", "--out"])
        .arg(dir.path().join("o"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert!(
        !res.status.success(),
        "exit 0 with an invalid rig: {stderr}"
    );
    assert!(stderr.contains("no-such-rig.toml"), "{stderr}");
}

/// Stages that fail (here: reachability and trajectory, on a rig whose clamp the arm cannot
/// reach) are reported as failed with the planner's error, and the study is not done; the
/// stages that do not need the rig still finish.
#[test]
fn a_failing_stage_fails_the_study() {
    use helixreach::experiment::{self, RunOptions, Settings};
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/sawyer-seed.toml"),
    )
    .unwrap();
    let far = text.replace(
        "origin = [0.85, -0.15, -0.144]",
        "origin = [6.0, -0.15, -0.144]",
    );
    assert_ne!(
        far, text,
        "the seed rig's clamp line moved; update this test"
    );
    let rig = dir.path().join("far.toml");
    std::fs::write(&rig, far).unwrap();
    let mut st = Settings::quick(rig.to_str().unwrap());
    st.continuum_directions = 40;
    st.fan_directions = 5;
    st.speed_sample = 5;
    st.der_sample = 1;
    st.der_n_sweep = vec![8];
    st.der_n_edges = 8;
    st.reach_directions = 4;
    st.reach_fan_directions = 2;
    st.dynamics_rays = 0;
    let report = experiment::run(&st, &RunOptions::new(dir.path().join("o"))).unwrap();
    assert!(!report.all_done());
    let failed: Vec<&str> = report.failed().map(|s| s.name).collect();
    assert_eq!(
        failed,
        ["reachability", "trajectory"],
        "{:?}",
        report.stages
    );
    for s in report.failed() {
        let e = s.result.as_ref().unwrap_err();
        assert!(
            e.contains("far.toml") && e.contains("unreachable clamp"),
            "{e}"
        );
    }
    assert!(report.reach.is_none() && report.trajectory.is_none());
    assert!(report.continuum.is_some() && report.der.is_some());
}
