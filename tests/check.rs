//! `helixreach check` against the seed experiment's real data: every joint trajectory the real
//! Sawyer executed (`tests/data/seed/trajectories/`, with each run's own clamp position) must
//! pass the embedded `sawyer-seed` rig — inside the joint limits, free of self, scene and rod
//! collision — and its FK must lie on the ray's pose curve (an independent check of the rig's
//! frame conventions). The step statistics are compared with the figures `trajectories.csv`
//! states for each run. Then: the CLI end to end, bad input, and trajectories that DO fail.

mod common;
use common::seed_dir;
use helixreach::directions::Direction;
use helixreach::planning::check::{
    CheckOptions, CheckReport, Checker, Finding, JUMP, SEED_HELD_EDGES,
};
use helixreach::planning::rig::Rig;
use helixreach::records::trajectory::{parse_joint_file, read_joint_file};
use std::path::Path;
use std::process::Command;

/// One run of `trajectories.csv`.
struct Run {
    file: String,
    c1: f64,
    c2: f64,
    clamp: [f64; 3],
    n_rows: usize,
    s_end: f64,
    max_step: f64,
    steps_over: usize,
}

fn runs() -> Vec<Run> {
    let text = std::fs::read_to_string(seed_dir().join("trajectories.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (f, c1, c2, x, y, z) = (
        col("file"),
        col("c1"),
        col("c2"),
        col("clamp_x"),
        col("clamp_y"),
        col("clamp_z"),
    );
    let (nr, se, ms, so) = (
        col("n_rows"),
        col("s_end"),
        col("max_joint_step"),
        col("steps_over_0.2rad"),
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            let num = |i: usize| v[i].parse::<f64>().unwrap();
            Run {
                file: v[f].to_string(),
                c1: num(c1),
                c2: num(c2),
                clamp: [num(x), num(y), num(z)],
                n_rows: v[nr].parse().unwrap(),
                s_end: num(se),
                max_step: num(ms),
                steps_over: v[so].parse().unwrap(),
            }
        })
        .collect()
}

fn check_run(base: &Checker, run: &Run, held_edges: usize) -> CheckReport {
    check_run_opts(base, run, held_edges, JUMP)
}

fn check_run_opts(base: &Checker, run: &Run, held_edges: usize, max_step: f64) -> CheckReport {
    let rig = base.rig().with_clamp_origin(run.clamp).unwrap();
    let checker = base.with_rig(rig).unwrap();
    let traj = read_joint_file(
        &seed_dir().join("trajectories").join(&run.file),
        &checker.joint_names(),
    )
    .unwrap();
    let opt = CheckOptions {
        direction: Some(Direction::new(1.0, run.c1, run.c2).unwrap()),
        held_edges,
        max_step,
        ..CheckOptions::default()
    };
    checker.check(&traj, &opt).unwrap()
}

#[test]
fn every_seed_trajectory_passes_the_seed_rig() {
    let base = Checker::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    let runs = runs();
    assert_eq!(runs.len(), 58, "the seed ships 58 executed trajectories");
    let (mut worst_p, mut worst_r): (f64, f64) = (0.0, 0.0);
    for run in &runs {
        let rep = check_run(&base, run, SEED_HELD_EDGES);
        let f = &run.file;
        assert_eq!(rep.rows, run.n_rows, "{f}");
        assert_eq!(rep.limit_violations, 0, "{f}: {:?}", rep.to_json());
        assert!(rep.rod_checked, "{f}");
        assert_eq!(
            rep.collisions,
            0,
            "{f}: {}",
            serde_json::to_string(&rep.to_json()["colliding_pairs"]).unwrap()
        );
        // The path statistics the data states for each run (an independent computation).
        assert!(
            (rep.max_joint_step.0 - run.max_step).abs() < 1e-5,
            "{f}: {} vs {}",
            rep.max_joint_step.0,
            run.max_step
        );
        assert_eq!(rep.steps_over_jump, run.steps_over, "{f} (> {JUMP} rad)");
        // FK of every row lies on the ray's pose curve (the seed's last-edge frame) and the
        // projection recovers the run's s_end.
        let (p, r) = (
            rep.max_position_error.unwrap().0,
            rep.max_rotation_error.unwrap().0,
        );
        worst_p = worst_p.max(p);
        worst_r = worst_r.max(r);
        assert!(p <= POSITION_BOUND, "{f}: position error {p} m");
        assert!(r <= ROTATION_BOUND, "{f}: rotation error {r} rad");
        let s = rep.s_max_reached.unwrap();
        assert!(
            (s - run.s_end).abs() < 1e-4 * run.s_end,
            "{f}: s {s} vs {}",
            run.s_end
        );
        // The gate: the executed Descartes jumps (up to 1.63 rad) are steps over the default
        // bound and nothing else; with a 2 rad step bound the file passes the whole gate.
        assert_eq!(rep.segment_collisions, 0, "{f}");
        let steps = rep.finding_mask();
        assert!(steps == 0 || steps == Finding::Step as u8, "{f}: {steps}");
        assert_eq!(steps == 0, run.max_step <= JUMP, "{f}");
        let rep2 = check_run_opts(&base, run, SEED_HELD_EDGES, 2.0);
        assert_eq!(rep2.finding_mask(), 0, "{f}: {:?}", rep2.findings());
    }
    eprintln!("58/58 pass; worst pose error {worst_p:.3e} m, {worst_r:.3e} rad");
}

/// FK of the executed rows agrees with the seed's pose curve (end at node 100, last-edge frame)
/// to these bounds over all 58 runs (measured: 0.24 mm, 0.93 mrad; the largest at the last rows,
/// where the runs come back to s ≈ 0; rows on the Descartes waypoints agree to ≈ 2 µm). The
/// seed README's 0.2 mm / 0.2 mrad is not met by every row with this model.
const POSITION_BOUND: f64 = 0.25e-3;
const ROTATION_BOUND: f64 = 1.0e-3;

#[test]
fn continuum_end_frame_is_not_what_the_seed_held() {
    // The same run against the continuum end frame (the planner's PoseMap) is off by
    // millimetres: the seed's targets were the last edge of a 100-edge discrete helix.
    let base = Checker::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    let runs = runs();
    let run = runs.iter().find(|r| r.file == "c1_0.23_c2_0.txt").unwrap();
    let cont = check_run(&base, run, 0);
    let disc = check_run(&base, run, SEED_HELD_EDGES);
    let (pc, pd) = (
        cont.max_position_error.unwrap().0,
        disc.max_position_error.unwrap().0,
    );
    assert!(
        pc > 1e-3 && pd < 0.2e-3,
        "continuum {pc} m, discrete {pd} m"
    );
}

#[test]
fn a_trajectory_that_collides_or_leaves_the_limits_is_reported() {
    let base = Checker::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    let runs = runs();
    let run = runs.iter().find(|r| r.file == "c1_0.23_c2_0.txt").unwrap();
    let rig = base.rig().with_clamp_origin(run.clamp).unwrap();
    let path = seed_dir().join("trajectories").join(&run.file);
    // 1. An obstacle (a ball of 5 cm) where the motor tip is at row 500.
    let checker = base.with_rig(rig.clone()).unwrap();
    let traj = read_joint_file(&path, &checker.joint_names()).unwrap();
    let tip = checker.model().tool_pose(traj.row(500)).unwrap().pos;
    let mut blocked = rig.clone();
    blocked.obstacles.push(
        toml::from_str(&format!(
            "name = \"ball\"\nshape = {{ type = \"sphere\", radius = 0.05 }}\n\
             pose = {{ xyz = [{}, {}, {}] }}",
            tip.x, tip.y, tip.z
        ))
        .unwrap(),
    );
    let rep = base
        .with_rig(blocked)
        .unwrap()
        .check(&traj, &CheckOptions::default())
        .unwrap();
    assert!(rep.scene_collisions > 0 && rep.collisions >= rep.scene_collisions);
    assert!(!rep.row_checks[500].contacts.is_empty());
    assert!(rep.pairs.iter().any(|p| p.b == "obstacle ball"));
    assert!(!rep.passed());
    // 2. One joint value pushed past its upper limit.
    let mut bad = traj.clone();
    let upper = checker.model().joints()[3].upper;
    bad.q[10 * bad.dof + 3] = upper + 0.01;
    let rep = checker.check(&bad, &CheckOptions::default()).unwrap();
    assert_eq!(rep.limit_violations, 1);
    assert!(rep.row_checks[10]
        .limit
        .as_ref()
        .unwrap()
        .contains("right_j3"));
    // 3. The rod check is not blind: the run's own rod, thickened by a 0.3 m clearance,
    //    reaches the arm.
    let mut fat = rig.clone();
    fat.planner.rod_clearance = 0.3;
    let rep = base
        .with_rig(fat)
        .unwrap()
        .check(
            &traj,
            &CheckOptions {
                direction: Some(Direction::new(1.0, run.c1, run.c2).unwrap()),
                held_edges: SEED_HELD_EDGES,
                ..CheckOptions::default()
            },
        )
        .unwrap();
    assert!(rep.rod_collisions > 0 && rep.pairs.iter().any(|p| p.kind == "rod"));
}

#[test]
fn trajectory_formats_agree() {
    // The same rows as whitespace, headerless CSV, joint-name CSV (MoveIt-like, extra time
    // column) and helixreach's q0.. CSV give the same joints.
    let names: Vec<String> = (0..7).map(|j| format!("right_j{j}")).collect();
    let p = Path::new("t.txt");
    let ws = parse_joint_file(
        "0 0.1 0.2 0.3 0.4 0.5 0.6\n# comment\n\n1 1 1 1 1 1 1\n",
        p,
        &names,
    )
    .unwrap();
    let csv = parse_joint_file("0,0.1,0.2,0.3,0.4,0.5,0.6\n1,1,1,1,1,1,1\n", p, &names).unwrap();
    let moveit = parse_joint_file(
        "time,right_j6,right_j5,right_j4,right_j3,right_j2,right_j1,right_j0\n\
         0,0.6,0.5,0.4,0.3,0.2,0.1,0\n1,1,1,1,1,1,1,1\n",
        p,
        &names,
    )
    .unwrap();
    let own = parse_joint_file(
        "t,q0,q1,q2,q3,q4,q5,q6,motor,s\n0,0,0.1,0.2,0.3,0.4,0.5,0.6,0.25,0\n\
         1,1,1,1,1,1,1,1,0.5,1\n",
        p,
        &names,
    )
    .unwrap();
    for f in [&csv, &moveit, &own] {
        assert_eq!(f.q, ws.q);
    }
    assert_eq!(ws.lines, vec![1, 4]);
    assert_eq!(own.motor, Some(vec![0.25, 0.5]));
}

#[test]
fn bad_trajectory_files_name_file_line_and_value() {
    let names: Vec<String> = (0..7).map(|j| format!("right_j{j}")).collect();
    let p = Path::new("bad.txt");
    let cases = [
        (
            "0 0 0 0 0 0 0\n0 0 0 0 0 0\n",
            ":2:",
            "6 fields, expected 7",
        ),
        ("0 0 0 0 0 0 0\n0 0 NaN 0 0 0 0\n", ":2:", "NaN"),
        (
            "0 0 0 0 0 0 0\n0 0 x 0 0 0 0\n",
            ":2:",
            "`x` is not a number",
        ),
        ("0 0 0 0 0 0 inf\n", ":1:", "inf"),
        ("", "bad.txt", "empty file"),
        ("# only a comment\n\n", "bad.txt", "empty file"),
        ("a,b,c\n1,2,3\n", ":1:", "names neither"),
        ("t,q0,q1,q2,q3,q4,q5,q6\n", "bad.txt", "no joint rows"),
    ];
    for (text, at, what) in cases {
        let e = parse_joint_file(text, p, &names).unwrap_err().to_string();
        assert!(
            e.contains("bad.txt") && e.contains(at) && e.contains(what),
            "{text:?}: {e}"
        );
    }
}

fn cli(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_end_to_end_on_a_seed_trajectory() {
    let runs = runs();
    let run = &runs[0];
    let joints = seed_dir().join("trajectories").join(&run.file);
    let dir = tempfile::tempdir().unwrap();
    let rows = dir.path().join("rows.csv");
    let (dirn, clamp) = (
        format!("1,{},{}", run.c1, run.c2),
        format!("{},{},{}", run.clamp[0], run.clamp[1], run.clamp[2]),
    );
    let out = cli(&[
        "check",
        "--rig",
        "sawyer-seed",
        "--trajectory",
        joints.to_str().unwrap(),
        "--direction",
        &dirn,
        "--clamp",
        &clamp,
        "--out",
        rows.to_str().unwrap(),
        "--report-only",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    // The interface scripts grep for.
    assert!(text.contains("\"collisions\": 0") && text.contains("\"limit_violations\": 0"));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    for k in [
        "rows",
        "limit_violations",
        "collisions",
        "max_joint_step",
        "steps_over_0.2",
        "max_position_error",
        "max_rotation_error",
        "colliding_pairs",
        "collision_rows",
    ] {
        assert!(v.get(k).is_some(), "missing key {k}");
    }
    assert_eq!(v["rows"].as_u64().unwrap() as usize, run.n_rows);
    assert_eq!(
        v["steps_over_0.2"].as_u64().unwrap() as usize,
        run.steps_over
    );
    let csv = std::fs::read_to_string(&rows).unwrap();
    assert_eq!(csv.lines().count(), run.n_rows + 1);
    assert!(csv.starts_with("row,line,s,position_error,rotation_error,joint_step"));
}

#[test]
fn cli_bad_input_exits_2_with_file_line_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let good = write("good.txt", "0 -1 0 1.5 0 -0.5 0\n");
    let cases = [
        (
            write("cols.txt", "0 0 0 0 0 0 0 0\n"),
            None,
            vec!["cols.txt:1", "8 fields"],
        ),
        (
            write("nan.txt", "0 0 0 NaN 0 0 0\n"),
            None,
            vec!["nan.txt:1", "right_j3", "NaN"],
        ),
        (
            write("empty.txt", ""),
            None,
            vec!["empty.txt", "empty file"],
        ),
        (
            good.clone(),
            Some("0.8,nan,-0.14"),
            vec!["--clamp", "clamp.origin[1]", "NaN"],
        ),
        (
            good.clone(),
            Some("0.8,-0.14"),
            vec!["--clamp", "0.8,-0.14"],
        ),
    ];
    for (file, clamp, wants) in cases {
        let mut args = vec!["check", "--rig", "sawyer-seed", "--trajectory", &file];
        if let Some(c) = clamp {
            args.extend(["--clamp", c]);
        }
        let out = cli(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
        for w in wants {
            assert!(err.contains(w), "{args:?}: `{w}` not in {err}");
        }
    }
    // A file that runs but fails the check (here: a joint past its limit): the gate's exit
    // code 64 + 1, the report on stdout all the same.
    let over = write("over.txt", "0 -1 0 1.5 0 -0.5 9\n");
    let out = cli(&["check", "--trajectory", &over]);
    assert_eq!(out.status.code(), Some(65));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["limit_violations"], 1);
    assert!(v["max_position_error"].is_null());
}
