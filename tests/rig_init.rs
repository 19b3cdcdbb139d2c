//! `helixreach rig init` on real arms (the vendored UR5 and Panda): the rig it writes is
//! accepted as written by `reach` and `plan`, and its clamp is where the arm holds the straight
//! rod (checked by IK and the collision model directly); a bad tool link is refused naming it
//! and the links there are. And what a 6-DOF arm is to the planner: every IK branch of the
//! straight rod a start, no self-motion at a full pose, reconfiguration impossible in roll
//! `fixed` (and said so); in roll `motor` its roll is a self-motion the search moves along.

mod common;

use common::robots::{self, ARMS};
use helixreach::directions::fibonacci;
use helixreach::math::{Real, Vec3};
use helixreach::planning::planner::{Planner, ReachClass, Reconfiguration};
use helixreach::planning::pose_path::PoseMap;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::robot::{Frame, IkParams, IkSolver, IkTarget, RobotModel};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn helixreach(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .expect("run helixreach")
}

fn arm(name: &str) -> &'static robots::Arm {
    ARMS.iter().find(|a| a.name == name).unwrap()
}

/// `rig init` for `arm` with tool link `tip`, written to `dir/NAME.toml`.
fn init(dir: &Path, name: &str, tip: &str) -> PathBuf {
    init_with(dir, name, tip, &[])
}

/// [`init`] with more options (`extra`).
fn init_with(dir: &Path, name: &str, tip: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("{name}.toml"));
    let urdf = robots::urdf(arm(name));
    let pkg = robots::package_dir();
    let mut args = vec![
        "rig",
        "init",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        tip,
        "--package-path",
        pkg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = helixreach(&args);
    assert!(
        o.status.success(),
        "rig init {name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// `rig init` for the Jaco2 (`kinova`) with its SRDF and a 0.3 m rod (at the default length no
/// clamp candidate holds the straight rod without collision).
fn init_jaco2(dir: &Path) -> PathBuf {
    let srdf = robots::urdf(arm("kinova"))
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("srdf/kinova.srdf");
    init_with(
        dir,
        "kinova",
        "j2s6s200_end_effector",
        &["--srdf", srdf.to_str().unwrap(), "--rod-length", "0.3"],
    )
}

/// The straight rod's nodes of `rig` (clamp to rod end, `rod_capsules` capsules).
fn straight_rod(rig: &Rig) -> Vec<Vec3> {
    let n = rig.planner.rod_capsules;
    let d3: Vec3 = rig.clamp_rotation().column(2).into_owned();
    (0..=n)
        .map(|i| rig.clamp.translation.vector + (i as Real / n as Real) * rig.rod.length * d3)
        .collect()
}

/// Every solution the library's IK finds for the tip pose holding `tool` (base frame) from
/// `restarts` random seeds, all joints free.
fn ik_all(
    model: &RobotModel,
    rig: &Rig,
    tool: &nalgebra::Isometry3<Real>,
    restarts: usize,
) -> Vec<Vec<Real>> {
    let tip = Frame::from_iso(&(tool * rig.tool.inverse()));
    let solver = IkSolver::new(
        model,
        IkParams {
            redundancy_joint: None,
            restarts,
            ..IkParams::default()
        },
    )
    .unwrap();
    solver
        .solve_all(&IkTarget::pose(tip).unwrap(), &[])
        .into_iter()
        .map(|s| s.joints().to_vec())
        .collect()
}

/// The configurations of `sols` that the rig's collision model (its padding, no scene) finds
/// free of self-collision and of the straight rod.
fn collision_free(model: &RobotModel, rig: &Rig, sols: &[Vec<Real>]) -> Vec<Vec<Real>> {
    let cm = rig
        .robot
        .collision_model(model, &rig.obstacles, &rig.source)
        .unwrap();
    let mut ws = cm.workspace();
    let nodes = straight_rod(rig);
    let rod = rig.rod_geometry(&nodes);
    sols.iter()
        .filter(|q| cm.check(q, &mut ws, Some(&rod)).is_none())
        .cloned()
        .collect()
}

#[test]
fn rig_init_writes_rigs_that_reach_accepts_for_a_6_and_a_7_dof_arm() {
    let dir = tempfile::tempdir().unwrap();
    for (name, tip, dof) in [("ur5", "tool0", 6), ("panda", "panda_link8", 7)] {
        let path = init(dir.path(), name, tip);
        let text = std::fs::read_to_string(&path).unwrap();
        // Commented, with the robot, the tip, padding, the collision model, no scene.
        assert!(
            text.lines().filter(|l| l.starts_with('#')).count() >= 10,
            "{text}"
        );
        assert!(
            text.contains("Collision model")
                && text.contains("padding = ")
                && text.contains("collision_model = \"primitives_then_hull\""),
            "{text}"
        );
        assert!(!text.contains("\n[[obstacle]]"), "{text}");
        let rig = Rig::from_file(&path).unwrap();
        assert_eq!(rig.robot.tip_link, tip);
        assert!(rig.obstacles.is_empty());
        assert!(rig.robot.collision.padding > 0.0);
        assert!(rig.tool.translation.vector.norm() > 0.0);
        // In front of the robot (+x), within reach.
        let model = rig.robot.load_model(&rig.source).unwrap();
        assert_eq!(model.dof(), dof);
        let o = rig.clamp.translation.vector;
        assert!(o.x > 0.1 && o.y.abs() < 1e-9, "{name}: clamp at {o:?}");
        // The straight rod is held: an IK solution of its end pose, checked by FK, is free of
        // self-collision and of the rod (the collision model directly, not the planner).
        let tool = rig.straight_tool_pose();
        let sols = ik_all(&model, &rig, &tool, 200);
        let free = collision_free(&model, &rig, &sols);
        assert!(
            !free.is_empty(),
            "{name}: {} IK solutions, none free",
            sols.len()
        );
        let fk = model
            .chain()
            .tool_pose(&free[0])
            .mul(&Frame::from_iso(&rig.tool));
        assert!((fk.pos - tool.translation.vector).norm() < 1e-8);
        // `reach` accepts the rig as written and plans rays from a real start.
        let csv = dir.path().join(format!("{name}-reach.csv"));
        let o = helixreach(&[
            "reach",
            "--rig",
            path.to_str().unwrap(),
            "--fibonacci",
            "20",
            "--quarter",
            "--threads",
            "1",
            "--out",
            csv.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{name}: {err}");
        let mut rd = csv::Reader::from_path(&csv).unwrap();
        let h = rd.headers().unwrap().clone();
        let col = |n: &str| h.iter().position(|c| c == n).unwrap();
        let (c_class, c_s) = (col("class"), col("s_reached"));
        let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.unwrap()).collect();
        assert_eq!(rows.len(), 20);
        let moved = rows
            .iter()
            .filter(|r| {
                matches!(&r[c_class], "testable" | "partial")
                    && r[c_s].parse::<Real>().unwrap() > 0.0
            })
            .count();
        assert!(moved >= 1, "{name}: no ray leaves the straight rod");
        let expect = if dof == 7 {
            "reconfiguration at a held pose: allowed"
        } else {
            "reconfiguration at a held pose: impossible (6 joints"
        };
        assert!(err.contains(expect), "{name}: {err}");
        eprintln!("{name}: {moved} of 20 rays leave the straight rod");
    }
}

#[test]
fn rig_init_refuses_a_bad_tip_naming_it_and_the_links() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bad.toml");
    let urdf = robots::urdf(arm("panda"));
    let pkg = robots::package_dir();
    let o = helixreach(&[
        "rig",
        "init",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        "panda_flange",
        "--package-path",
        pkg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for s in ["--tip", "panda_flange", "panda_link8", "panda_hand"] {
        assert!(err.contains(s), "missing {s}: {err}");
    }
    assert!(!out.exists());
}

/// A 6-DOF arm has no self-motion: every valid IK solution of the straight rod is its own
/// start component, and every IK branch (solutions modulo 2π per joint) that a brute-force IK
/// (ten times the restarts) finds valid is among the starts. Reconfiguration is impossible.
#[test]
fn every_ik_branch_of_a_6_dof_arm_is_a_start() {
    let dir = tempfile::tempdir().unwrap();
    let rig = Rig::from_file(&init(dir.path(), "ur5", "tool0")).unwrap();
    let planner = Planner::new(rig.clone()).unwrap();
    assert_eq!(
        planner.reconfiguration(RollMode::Fixed),
        Reconfiguration::Impossible {
            dof: 6,
            roll: RollMode::Fixed
        }
    );
    let comps = planner.start_components(RollMode::Fixed);
    assert!(comps.iter().all(|c| c.len() == 1), "{comps:?}");
    let starts = planner.start_configurations(RollMode::Fixed);
    assert_eq!(starts.len(), comps.len());
    let branch = |q: &[Real]| -> Vec<i64> {
        q.iter()
            .map(|x| (x.rem_euclid(std::f64::consts::TAU) * 1e3).round() as i64 % 6283)
            .collect()
    };
    let near = |a: &[i64], b: &[i64]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 2 || (x - y).abs() >= 6281)
    };
    let start_branches: Vec<Vec<i64>> = starts.iter().map(|q| branch(q)).collect();
    let model = planner.model();
    let brute = ik_all(model, &rig, &rig.straight_tool_pose(), 3000);
    let valid = collision_free(model, &rig, &brute);
    let mut branches: Vec<Vec<i64>> = Vec::new();
    for q in &valid {
        let b = branch(q);
        if !branches.iter().any(|x| near(x, &b)) {
            branches.push(b);
        }
    }
    assert!(!branches.is_empty());
    // A 6R arm has at most 8 branches modulo 2π at a pose (the UR's: 2 × 2 × 2).
    assert!(branches.len() <= 8, "{} branches", branches.len());
    for b in &branches {
        assert!(
            start_branches.iter().any(|s| near(s, b)),
            "valid branch {b:?} (milliradians mod 2π) is not a start"
        );
    }
    eprintln!(
        "ur5: {} starts, {} valid branches of {} brute-force solutions ({} valid)",
        starts.len(),
        branches.len(),
        brute.len(),
        valid.len()
    );
}

/// A 6-joint arm has a self-motion in roll `motor`: its roll about the rod at a held pose (the
/// motor turning the other way). On the Jaco2 (`rig init --srdf kinova.srdf --rod-length
/// 0.3`), direction 1 of the 100-direction quarter-sphere lattice is testable in roll `motor`
/// only through such moves: the search's path has reconfigurations, every one at a held pose
/// (s, the rod end and the rod tangent constant, the motor turning) within the joint-step
/// bound, and the rig's [`Planner::reconfiguration`] says `allowed` in roll `motor`
/// (`impossible` in roll `fixed`), as `plan` prints it. With reconfiguration forbidden it says
/// so, the path has none after s = 0 and the ray is not testable; the ladder, which does not
/// move along a 6-joint arm's roll, says that and has none.
#[test]
fn a_6_dof_arm_reconfigures_by_its_roll_in_roll_motor() {
    use helixreach::planning::rig::SearchMethod;
    use helixreach::planning::trajectory::Phase;
    let dir = tempfile::tempdir().unwrap();
    let rig_path = init_jaco2(dir.path());
    let rig = Rig::from_file(&rig_path).unwrap();
    let d = fibonacci(100, true).unwrap()[1];
    let s_star = helixreach::sweep::reach::s_star_of(&d, None).unwrap();
    let planner = Planner::new(rig.clone()).unwrap();
    assert_eq!(
        planner.reconfiguration(RollMode::Fixed),
        Reconfiguration::Impossible {
            dof: 6,
            roll: RollMode::Fixed
        }
    );
    assert_eq!(
        planner.reconfiguration(RollMode::Motor),
        Reconfiguration::Allowed
    );
    let plan = planner
        .plan_ray(&d, s_star, 0.0, RollMode::Motor, true)
        .unwrap();
    assert_eq!(plan.class, ReachClass::Testable, "{plan:?}");
    assert!(plan.reconfigurations > 0);
    let path = plan.path.as_ref().unwrap();
    let mut rolled = 0;
    for w in path.windows(2) {
        if w[1].phase != Phase::Reconfigure {
            continue;
        }
        assert_eq!(w[0].waypoint.s, w[1].waypoint.s);
        let step = (0..6)
            .map(|j| (w[1].q[j] - w[0].q[j]).abs())
            .fold(0.0, Real::max);
        assert!(step <= rig.planner.max_joint_step + 1e-12, "{step}");
        // The rod end (the tool frame's origin) and the rod tangent (its z axis) held.
        let want = &w[1].waypoint.tool;
        let z = Vec3::new(0.0, 0.0, 1.0);
        for q in [&w[0].q, &w[1].q] {
            let f = planner.model().chain().tool_pose(q);
            let origin = f.pos + f.rot * rig.tool.translation.vector;
            let tangent = f.rot * (rig.tool.rotation * z);
            assert!((origin - want.translation.vector).norm() < 1e-6);
            assert!((tangent - want.rotation * z).norm() < 1e-6);
        }
        rolled += usize::from((w[1].motor - w[0].motor).abs() > 1e-6);
    }
    assert!(rolled > 0);

    let mut forbidden = rig.clone();
    forbidden.planner.allow_reconfiguration = false;
    let p = Planner::new(forbidden).unwrap();
    assert_eq!(
        p.reconfiguration(RollMode::Motor),
        Reconfiguration::Forbidden
    );
    let plan = p.plan_ray(&d, s_star, 0.0, RollMode::Motor, true).unwrap();
    assert_ne!(plan.class, ReachClass::Testable);
    let path = plan.path.as_ref().unwrap();
    assert!(path
        .iter()
        .all(|x| x.phase != Phase::Reconfigure || x.waypoint.s == 0.0));

    let mut ladder = rig.clone();
    ladder.planner.search = SearchMethod::Ladder;
    let p = Planner::new(ladder).unwrap();
    assert_eq!(
        p.reconfiguration(RollMode::Motor),
        Reconfiguration::NotByLadder { dof: 6 }
    );
    let plan = p.plan_ray(&d, s_star, 0.0, RollMode::Motor, false).unwrap();
    assert_eq!(plan.reconfigurations, 0);

    let o = helixreach(&[
        "plan",
        "--rig",
        rig_path.to_str().unwrap(),
        "--direction",
        &format!("{},{},{}", d.kappa, d.tau, d.omega),
        "--roll",
        "motor",
        "--out",
        dir.path().join("t.csv").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("(reconfiguration allowed)"), "{err}");
}

/// Continuous joints are modelled as one turn, and said so: on the Jaco2 the joints whose URDF
/// type is `continuous` (read from the URDF text) are the model's continuous joints, each
/// limited to [−π, π], and the rig `rig init` writes names exactly them in a comment; the
/// UR5's rig (no continuous joint) has none.
#[test]
fn rig_init_names_the_continuous_joints() {
    let urdf = std::fs::read_to_string(robots::urdf(arm("kinova"))).unwrap();
    let mut want: Vec<String> = urdf
        .split("<joint ")
        .skip(1)
        .filter(|j| j[..j.find('>').unwrap()].contains("type=\"continuous\""))
        .map(|j| {
            let n = &j[j.find("name=\"").unwrap() + 6..];
            n[..n.find('"').unwrap()].to_string()
        })
        .collect();
    want.sort();
    assert_eq!(want.len(), 3, "{want:?}");
    let model = robots::load(arm("kinova"));
    let mut got: Vec<String> = Vec::new();
    for j in model.joints() {
        if j.continuous {
            assert_eq!(
                (j.lower, j.upper),
                (-std::f64::consts::PI, std::f64::consts::PI)
            );
            got.push(j.name.clone());
        }
    }
    got.sort();
    assert_eq!(got, want);
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(init_jaco2(dir.path())).unwrap();
    let at = text.find("# Continuous joints").expect("the note");
    let listed = text[at..].lines().nth(2).unwrap().trim_start_matches("# ");
    let mut listed: Vec<String> = listed.split(", ").map(str::to_string).collect();
    listed.sort();
    assert_eq!(listed, want);
    let ur5 = std::fs::read_to_string(init(dir.path(), "ur5", "tool0")).unwrap();
    assert!(!ur5.contains("Continuous joints"));
}

/// A 6-DOF rung that dies says why: its nodes' rejection. (Before, the rung's failed
/// spawns, locked-joint tracks a 6-DOF arm cannot follow, were counted too and made every
/// blocked UR5 ray `no_ik`.) For every partial ray on the UR5 rig, when the pose just past
/// where it stops has IK solutions (brute force), the cause is not `no_ik`; and some ray stops
/// for a collision.
#[test]
fn a_6_dof_block_cause_is_the_rejection_not_the_spawns() {
    let dir = tempfile::tempdir().unwrap();
    let rig = Rig::from_file(&init(dir.path(), "ur5", "tool0")).unwrap();
    let planner = Planner::new(rig.clone()).unwrap();
    let model = planner.model();
    let mut collisions = 0;
    for d in fibonacci(20, true).unwrap() {
        let s_star = helixreach::sweep::reach::s_star_of(&d, None).unwrap();
        let plan = planner
            .plan_ray(&d, s_star, 0.0, RollMode::Fixed, false)
            .unwrap();
        if plan.class != ReachClass::Partial {
            continue;
        }
        let cause = plan.cause.unwrap().as_str();
        collisions += usize::from(cause.ends_with("collision"));
        let s = plan.s_reached * (1.0 + 1e-4);
        let kto = [s * d.kappa, s * d.tau, s * d.omega];
        let (tool, _) = PoseMap::new(&rig, 0.0).end(kto).unwrap();
        let sols = ik_all(model, &rig, &tool, 300);
        assert!(
            sols.is_empty() || cause != "no_ik",
            "ray {d:?} stops at s = {} for no_ik, but the pose just past it has {} IK solutions",
            plan.s_reached,
            sols.len()
        );
    }
    assert!(collisions > 0, "no UR5 ray stops for a collision");
}

#[test]
fn a_6_dof_plan_says_reconfiguration_is_impossible() {
    let dir = tempfile::tempdir().unwrap();
    let rig = init(dir.path(), "ur5", "tool0");
    let out = dir.path().join("p.csv");
    let o = helixreach(&[
        "plan",
        "--rig",
        rig.to_str().unwrap(),
        "--direction",
        "1,1,1",
        "--allow-partial",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("reconfiguration impossible (6 joints in roll fixed: no self-motion"),
        "{err}"
    );
    let meta: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(helixreach::records::trajectory::meta_path(&out)).unwrap(),
    )
    .unwrap();
    assert!(meta["s_reached"].as_f64().unwrap() > 0.0, "{meta}");
    // `render` draws the 6-DOF plan: one frame row per default frame, each with the arm's
    // self clearance.
    let frames = dir.path().join("render");
    let o = helixreach(&[
        "render",
        "--rig",
        rig.to_str().unwrap(),
        "--trajectory",
        out.to_str().unwrap(),
        "--views",
        "iso",
        "--out",
        frames.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rd = csv::Reader::from_path(frames.join("render_frames.csv")).unwrap();
    let h = rd.headers().unwrap().clone();
    let c = h.iter().position(|c| c == "self_m").unwrap();
    let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.unwrap()).collect();
    assert!(rows.len() >= 2);
    assert!(rows.iter().all(|r| r[c].parse::<Real>().unwrap() > 0.0));
}

/// `ik` on a 6-DOF arm: every solution printed holds the pose (FK), they are isolated
/// (distinct), and they fall into at most 8 branches modulo 2π.
#[test]
fn ik_of_a_6_dof_arm_lists_its_branches() {
    let a = arm("ur5");
    let urdf = robots::urdf(a);
    let pkg = robots::package_dir();
    let o = helixreach(&[
        "ik",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        a.tip,
        "--package-path",
        pkg.to_str().unwrap(),
        "--pose",
        "0.4,0.1,0.3,0,1,0,0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rd = csv::Reader::from_reader(&o.stdout[..]);
    let rows: Vec<Vec<Real>> = rd
        .records()
        .map(|r| r.unwrap().iter().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() >= 2, "{} solutions", rows.len());
    let model = robots::load(a);
    let target = Vec3::new(0.4, 0.1, 0.3);
    let mut branches: Vec<Vec<Real>> = Vec::new();
    for r in &rows {
        let q = &r[..6];
        let fk = model.chain().tool_pose(q);
        assert!((fk.pos - target).norm() < 1e-8, "{q:?}");
        assert!(
            (fk.rot.column(2) - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-8,
            "{q:?}"
        );
        let b: Vec<Real> = q
            .iter()
            .map(|x| x.rem_euclid(std::f64::consts::TAU))
            .collect();
        let same = |c: &Vec<Real>| {
            c.iter().zip(&b).all(|(x, y)| {
                let d = (x - y).abs();
                d.min(std::f64::consts::TAU - d) < 1e-6
            })
        };
        if !branches.iter().any(same) {
            branches.push(b);
        }
    }
    assert!(branches.len() <= 8, "{} branches", branches.len());
}

/// No candidate holds the rod (a 4 m rod: its end is out of any arm's reach): an error saying
/// so with the planner's reason at the first candidate, and no file.
#[test]
fn rig_init_without_a_clamp_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("none.toml");
    let urdf = robots::urdf(arm("panda"));
    let pkg = robots::package_dir();
    let o = helixreach(&[
        "rig",
        "init",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        "panda_link8",
        "--package-path",
        pkg.to_str().unwrap(),
        "--rod-length",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for s in [
        "no clamp candidate",
        "straight 4 m rod",
        "dominant cause: no_ik",
    ] {
        assert!(err.contains(s), "missing {s:?}: {err}");
    }
    assert!(!out.exists());
}
