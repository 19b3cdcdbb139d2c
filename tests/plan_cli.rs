//! `helixreach plan` as a lab runs it: a ray the robot cannot drive to its target is a "no"
//! (exit 3, nothing written) unless `--allow-partial`, whose outputs say how far they go.

use std::path::Path;
use std::process::{Command, Output};

fn helixreach(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .expect("run helixreach")
}

/// A ray that stops early: on the seed rig it stops at s ≈ 2.13 of its target s*·1.1 ≈ 7.33 (no IK).
const PARTIAL_RAY: &str = "0.9294,0.075,0.3614";

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_partial_plan_exits_3_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("p.csv");
    let js = dir.path().join("p.json");
    let o = helixreach(&[
        "plan",
        "--direction",
        PARTIAL_RAY,
        "--out",
        csv.to_str().unwrap(),
        "--json",
        js.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("partial") && err.contains("no_ik"), "{err}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn allow_partial_writes_the_trajectory_as_far_as_it_goes() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("p.csv");
    let js = dir.path().join("p.json");
    let o = helixreach(&[
        "plan",
        "--direction",
        PARTIAL_RAY,
        "--allow-partial",
        "--out",
        csv.to_str().unwrap(),
        "--json",
        js.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [&csv, &js] {
        let meta = json(&helixreach::records::trajectory::meta_path(f));
        assert_eq!(meta["class"], "partial");
        assert_eq!(meta["cause"], "no_ik");
        let (reached, target, star) = (
            meta["s_reached"].as_f64().unwrap(),
            meta["s_target"].as_f64().unwrap(),
            meta["s_star"].as_f64().unwrap(),
        );
        // Target = s*·(1 + margin) with the seed rig's 10 % margin.
        assert!((target - 1.1 * star).abs() < 1e-9 * target, "{meta}");
        assert!(reached > 1.0 && reached < 0.5 * target, "{meta}");
    }
    // The CSV names its joint columns as the JSON message and the sidecar do: the robot's
    // URDF joints (the seed rig's Sawyer: right_j0..right_j6), velocities v_<joint>.
    let meta = json(&helixreach::records::trajectory::meta_path(&csv));
    let names: Vec<String> = json(&js)["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect();
    assert_eq!(names, meta["joint_names"].as_array().unwrap().clone());
    let urdf: Vec<String> = (0..7).map(|j| format!("right_j{j}")).collect();
    assert_eq!(names, urdf);
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert_eq!(header[0], "t");
    assert_eq!(header[1..8], urdf);
    assert_eq!(header[8], "motor");
    assert!(header.contains(&"v_right_j6") && header.contains(&"a_right_j0"));
    assert!(!header
        .iter()
        .any(|h| h.starts_with('q') && h[1..].parse::<u32>().is_ok()));
    // `check` reads it by those names on the seed rig.
    let o = helixreach(&[
        "check",
        "--trajectory",
        csv.to_str().unwrap(),
        "--report-only",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("(csv header: joint names)"), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        v["rows"].as_u64().unwrap() as usize,
        text.lines().count() - 1
    );
    // The CSV goes no farther than s_reached, and it does get there.
    let rows = helixreach::records::read_trajectory(&csv).unwrap();
    let reached = meta["s_reached"].as_f64().unwrap();
    let s_max = rows.iter().map(|r| r.s).fold(0.0, f64::max);
    assert!((s_max - reached).abs() < 1e-12, "{s_max} vs {reached}");
}
