//! `helixreach check` as a gate: one exit code bit per kind of finding (64 + the bits), exit 0
//! with `--report-only`, and zero findings on the planner's own trajectories (the pose error
//! measured at each row's own s: no projection artefact).

use helixreach::directions::{fibonacci, Direction};
use helixreach::planning::check::{CheckOptions, Checker};
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::records::trajectory::parse_joint_file;
use helixreach::sweep::reach::s_star_of;
use std::path::Path;
use std::process::{Command, Output};

fn helixreach(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .expect("run helixreach")
}

/// A collision-free configuration of the seed rig (the start of a planned ray).
const SAFE: [f64; 7] = [
    -0.9906864743626965,
    -0.592756327835948,
    -2.2255578844018356,
    -0.7686491423744042,
    2.422480316652661,
    1.6212802471920007,
    1.3395252680936554,
];

fn rows(qs: &[[f64; 7]]) -> String {
    qs.iter()
        .map(|q| {
            q.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A timed CSV (`t,right_j0..right_j6`) moving joint 0 by `q0(t)` sampled every `dt`.
fn timed(q0: impl Fn(f64) -> f64, duration: f64, dt: f64) -> String {
    let mut s = String::from("t,right_j0,right_j1,right_j2,right_j3,right_j4,right_j5,right_j6\n");
    let n = (duration / dt).round() as usize;
    for k in 0..=n {
        let t = k as f64 * dt;
        let mut q = SAFE;
        q[0] += q0(t);
        s.push_str(&format!("{t}"));
        for x in q {
            s.push_str(&format!(",{x}"));
        }
        s.push('\n');
    }
    s
}

fn code(dir: &Path, name: &str, text: &str, extra: &[&str]) -> (i32, serde_json::Value) {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    let mut args = vec![
        "check",
        "--rig",
        "sawyer-seed",
        "--trajectory",
        p.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = helixreach(&args);
    let v = serde_json::from_slice(&o.stdout).unwrap_or(serde_json::Value::Null);
    (o.status.code().unwrap(), v)
}

#[test]
fn exit_code_per_kind_of_finding() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Clean: one safe row.
    assert_eq!(code(d, "ok.txt", &rows(&[SAFE]), &[]).0, 0);
    // Limit: right_j6 past 4.71 rad.
    let mut q = SAFE;
    q[6] = 5.0;
    let (c, v) = code(d, "limit.txt", &rows(&[q]), &[]);
    assert_eq!(c, 64 + 1, "{v}");
    assert_eq!(v["findings"]["limit"], 1);
    // Collision: the shoulder pitched down into the table.
    let (c, v) = code(
        d,
        "coll.txt",
        &rows(&[[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]),
        &[],
    );
    assert_eq!((c, v["collisions"].as_u64()), (64 + 2, Some(1)), "{v}");
    // Step: 0.3 rad of joint 0 between two rows (no time column: no rates).
    let mut q = SAFE;
    q[0] += 0.3;
    let (c, v) = code(d, "step.txt", &rows(&[SAFE, q]), &[]);
    assert_eq!(c, 64 + 4, "{v}");
    // ... which a larger step bound accepts, and --report-only reports with exit 0.
    assert_eq!(
        code(d, "step.txt", &rows(&[SAFE, q]), &["--max-step", "0.5"]).0,
        0
    );
    let (c, v) = code(d, "step.txt", &rows(&[SAFE, q]), &["--report-only"]);
    assert_eq!((c, v["findings"]["step"].as_u64()), (0, Some(1)));
    // Velocity only: joint 0 (1.74 rad/s, 2 rad/s² on the seed rig) accelerates at 1.9 rad/s²
    // from rest for 1 s and decelerates as long: the finite-difference acceleration is 1.9
    // everywhere, the peak speed 1.9 rad/s.
    let a = 1.9;
    let bang = move |t: f64| {
        if t <= 1.0 {
            0.5 * a * t * t
        } else {
            a - 0.5 * a * (2.0 - t) * (2.0 - t)
        }
    };
    let (c, v) = code(d, "vel.csv", &timed(bang, 2.0, 0.01), &[]);
    assert_eq!(c, 64 + 8, "{v}");
    assert!(
        (v["max_velocity_ratio"].as_f64().unwrap() - 1.9 / 1.74).abs() < 0.02,
        "{v}"
    );
    // Acceleration only: the same profile at 2.5 rad/s² for 0.5 s (peak 1.25 rad/s).
    let a = 2.5;
    let bang = move |t: f64| {
        if t <= 0.5 {
            0.5 * a * t * t
        } else {
            0.25 * a - 0.5 * a * (1.0 - t) * (1.0 - t)
        }
    };
    let (c, v) = code(d, "acc.csv", &timed(bang, 1.0, 0.01), &[]);
    assert_eq!(c, 64 + 16, "{v}");
    assert!(
        (v["max_acceleration_ratio"].as_f64().unwrap() - 2.5 / 2.0).abs() < 1e-6,
        "{v}"
    );
}

#[test]
fn pose_error_at_the_file_s_is_a_finding() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("p.csv");
    let ray = "0.3,0.9,0.3";
    let o = helixreach(&["plan", "--direction", ray, "--out", csv.to_str().unwrap()]);
    assert!(o.status.success());
    let (c, v) = code(
        dir.path(),
        "p.csv",
        &std::fs::read_to_string(&csv).unwrap(),
        &["--direction", ray],
    );
    assert_eq!(c, 0, "{v}");
    // Shift every row's s by 0.05: the poses no longer lie where the file says.
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let is = header.split(',').position(|h| h == "s").unwrap();
    let mut shifted = format!("{header}\n");
    for l in lines {
        let mut f: Vec<String> = l.split(',').map(str::to_string).collect();
        f[is] = (f[is].parse::<f64>().unwrap() + 0.05).to_string();
        shifted.push_str(&f.join(","));
        shifted.push('\n');
    }
    let (c, v) = code(dir.path(), "shifted.csv", &shifted, &["--direction", ray]);
    assert_eq!(c, 64 + 32, "{v}");
    assert!(v["pose_at_file_s"].as_bool().unwrap());
}

/// `check` finds nothing on what `plan` writes, for 50 rays (testable and, as far as they go,
/// partial ones): limits, collisions, steps, speeds and accelerations from the time column, and
/// the pose at every row's own s.
#[test]
fn planned_trajectories_pass_the_gate_on_50_rays() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let planner = Planner::new(rig.clone()).unwrap();
    let checker = Checker::new(rig).unwrap();
    let names = checker.joint_names();
    let dirs: Vec<Direction> = fibonacci(50, true).unwrap();
    let mut classes = std::collections::BTreeMap::new();
    for d in &dirs {
        let s_star = s_star_of(d, None).unwrap();
        let plan = planner
            .plan_best_typed(d, s_star, None, &[0.0], RollMode::Fixed, true)
            .unwrap();
        *classes.entry(plan.class.as_str()).or_insert(0) += 1;
        if plan.s_reached <= 0.0 {
            continue;
        }
        let traj = planner.trajectory(&plan).unwrap();
        let text = helixreach::records::trajectory::trajectory_csv(&traj).unwrap();
        let file = parse_joint_file(&text, Path::new("plan.csv"), &names).unwrap();
        let opt = CheckOptions {
            direction: Some(*d),
            ..CheckOptions::default()
        };
        let rep = checker.check(&file, &opt).unwrap();
        assert_eq!(
            rep.finding_mask(),
            0,
            "{d:?} ({}): {:?}; pose {:?} {:?}",
            plan.class.as_str(),
            rep.findings(),
            rep.max_position_error,
            rep.max_rotation_error
        );
        assert!(rep.timed && rep.pose_at_file_s);
    }
    eprintln!("50 rays: {classes:?}");
    assert!(
        classes.get("testable").copied().unwrap_or(0) >= 10,
        "{classes:?}"
    );
}
