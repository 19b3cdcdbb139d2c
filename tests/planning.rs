//! Planning tests: every planned trajectory is checked independently of the planner —
//! the expected rod-end pose is rebuilt here from the helix module and the rig's frames (not from
//! `planning::pose_path`), configurations and segments are re-checked with a fresh collision model
//! at a finer interpolation, and limits and steps are recomputed from the joint values.

use helixreach::directions::Direction;
use helixreach::helix::{discrete, Helix};
use helixreach::math::{rot_z, rotation_angle, Mat3, Real, Vec3};
use helixreach::planning::planner::{Planner, RayPlan, ReachClass};
use helixreach::planning::rig::{Rig, RollMode, SearchMethod};
use helixreach::planning::trajectory::Phase;
use helixreach::robot::collision::RodGeometry;
use helixreach::robot::{CollisionModel, Frame};
use std::sync::OnceLock;

fn seed_planner() -> &'static Planner {
    static P: OnceLock<Planner> = OnceLock::new();
    P.get_or_init(|| Planner::new(Rig::load("sawyer-seed").unwrap()).unwrap())
}

/// P = [e2 e1 −e3]: tool x = d2, tool y = d1, tool z = −d3, written out here.
fn p_matrix() -> Mat3 {
    Mat3::from_columns(&[Vec3::y(), Vec3::x(), -Vec3::z()])
}

/// Expected tool position, transported tool rotation and material frame (base frame) of the
/// helix `kto` on `rig` at azimuth `alpha`, from the helix module.
fn expected(rig: &Rig, kto: [Real; 3], alpha: Real) -> (Vec3, Mat3, Mat3) {
    let h = Helix::new(kto[0], kto[1], kto[2]).unwrap();
    let e = h.end_pose(rig.rod.length, rig.rod.nu).unwrap();
    let rc = rig.clamp_rotation();
    let ra = rot_z(alpha);
    let p = rig.clamp.translation.vector + rc * ra * e.position;
    let transported = rc * ra * e.transported * ra.transpose();
    let material = rc * ra * e.material * ra.transpose();
    (p, transported * p_matrix(), material)
}

/// Check a planned path against every requirement of a trajectory, independently of the planner.
fn verify(planner: &Planner, plan: &RayPlan) {
    let rig = planner.rig();
    let model = planner.model();
    let path = plan.path.as_ref().expect("path");
    let loads = path.iter().filter(|p| p.phase == Phase::Load).count();
    // The ladder loads every waypoint once. The search's `n_reached` counts distinct slices: a
    // slice driven back over is loaded again, and a bridged load adds its intermediate poses.
    if rig.planner.search == SearchMethod::Ladder {
        assert_eq!(loads, plan.n_reached);
    } else {
        assert!(
            loads >= plan.n_reached,
            "{loads} loads, {} slices",
            plan.n_reached
        );
    }
    let runs = |phase: Phase| {
        path.windows(2)
            .filter(|w| w[0].phase != phase && w[1].phase == phase)
            .count()
    };
    assert_eq!(runs(Phase::Reconfigure), plan.reconfigurations);
    assert_eq!(runs(Phase::Backoff), plan.backoffs);
    // Back-off only below s*; past s* the path only moves forward.
    let mut last_past = plan.s_star;
    for pt in path {
        let s = pt.waypoint.s;
        if pt.phase == Phase::Backoff {
            assert!(
                s <= plan.s_star,
                "back-off at s = {s} past s* = {}",
                plan.s_star
            );
        }
        if s > plan.s_star {
            assert!(s >= last_past, "s = {s} after {last_past} past s*");
            last_past = s;
        }
    }
    let (lower, upper) = (model.lower(), model.upper());
    let mut cm = CollisionModel::for_model(model).unwrap();
    cm.set_obstacles(&rig.obstacles).unwrap();
    let mut ws = cm.workspace();
    let tool = Frame::from_iso(&rig.tool);
    let rod_nodes = |kto: [Real; 3]| -> Vec<Vec3> {
        let h = Helix::new(kto[0], kto[1], kto[2]).unwrap();
        let rc = rig.clamp_rotation() * rot_z(plan.azimuth);
        discrete::nodes(&h, rig.planner.rod_capsules)
            .into_iter()
            .map(|x| rig.clamp.translation.vector + rc * (x * rig.rod.length))
            .collect()
    };
    let c = 1.0 / (1.0 + rig.rod.nu);
    let dof = model.dof();
    for (k, pt) in path.iter().enumerate() {
        let w = &pt.waypoint;
        // The waypoint's helix is s·S̄.
        let want_kto = [
            w.s * plan.dir.kappa,
            w.s * plan.dir.tau,
            w.s * plan.dir.omega,
        ];
        for i in 0..3 {
            assert!((w.kto[i] - want_kto[i]).abs() <= 1e-12 * (1.0 + w.s));
        }
        // FK reproduces the expected rod-end pose.
        let fk = model.chain().tool_pose(&pt.q).mul(&tool);
        let (p, r_transported, material) = expected(rig, w.kto, plan.azimuth);
        let dp = (fk.pos - p).norm();
        assert!(dp <= 1e-6, "waypoint {k}: position off by {dp:e} m");
        match plan.roll {
            RollMode::Fixed => {
                let da = rotation_angle(&(r_transported.transpose() * fk.rot));
                assert!(da <= 1e-6, "waypoint {k}: rotation off by {da:e} rad");
                // The motor adds ω/c.
                assert!((pt.motor - w.kto[2] / c).abs() <= 1e-12 * (1.0 + pt.motor.abs()));
            }
            RollMode::Motor => {
                let z_err = fk.rot.column(2).cross(&r_transported.column(2)).norm();
                assert!(z_err <= 1e-6, "waypoint {k}: tool axis off by {z_err:e}");
            }
        }
        // Arm frame in the [d1 d2 d3] convention, turned by the motor about d3, is the rod's
        // material frame (both roll modes).
        let arm_d = fk.rot * p_matrix().transpose();
        let realised = arm_d * rot_z(pt.motor);
        let dm = rotation_angle(&(material.transpose() * realised));
        assert!(dm <= 1e-6, "waypoint {k}: material frame off by {dm:e} rad");
        // Joint limits.
        for j in 0..dof {
            assert!(
                pt.q[j] >= lower[j] && pt.q[j] <= upper[j],
                "waypoint {k}: joint {j} out of limits"
            );
        }
        // Collision at the waypoint and along the segment from the previous one (finer than the
        // planner's interpolation; the rod of the later waypoint, without the planner's clearance).
        let nodes = rod_nodes(w.kto);
        let rod = RodGeometry {
            nodes: &nodes,
            radius: rig.rod.radius,
            ignore_near_tool: rig.planner.rod_end_exclusion,
            ignore_near_clamp: 0.0,
            against_scene: false,
        };
        assert!(
            cm.check(&pt.q, &mut ws, Some(&rod)).is_none(),
            "waypoint {k} collides"
        );
        if k > 0 {
            let a = &path[k - 1].q;
            let dmax = (0..dof)
                .map(|j| (pt.q[j] - a[j]).abs())
                .fold(0.0, Real::max);
            assert!(
                dmax <= rig.planner.max_joint_step + 1e-12,
                "step {k}: {dmax} rad above the bound"
            );
            let n = (dmax / 0.005).ceil() as usize;
            let mut q = vec![0.0; dof];
            for i in 1..n {
                let t = i as Real / n as Real;
                for j in 0..dof {
                    q[j] = a[j] + t * (pt.q[j] - a[j]);
                }
                let hit = cm.check(&q, &mut ws, Some(&rod));
                assert!(
                    hit.is_none(),
                    "segment {k} collides at t = {t}: {:?}",
                    hit.map(|h| (cm.name(h.a), cm.name(h.b)))
                );
            }
            match pt.phase {
                Phase::Load => assert!(w.s > path[k - 1].waypoint.s, "s must increase"),
                Phase::Reconfigure => {
                    // s constant, and the rod end stays put along the joint-linear chord.
                    assert_eq!(
                        w.s,
                        path[k - 1].waypoint.s,
                        "s constant while reconfiguring"
                    );
                    for i in 1..8 {
                        let t = i as Real / 8.0;
                        let q: Vec<Real> = (0..dof).map(|j| a[j] + t * (pt.q[j] - a[j])).collect();
                        let f = model.chain().tool_pose(&q).mul(&tool);
                        let dp = (f.pos - p).norm();
                        let da = rotation_angle(&(r_transported.transpose() * f.rot));
                        match plan.roll {
                            RollMode::Fixed => assert!(dp <= 1e-6 && da <= 1e-6, "{dp:e} {da:e}"),
                            RollMode::Motor => assert!(dp <= 1e-6, "{dp:e}"),
                        }
                    }
                    assert_eq!(
                        pt.motor,
                        path[k - 1].motor,
                        "the motor holds while reconfiguring"
                    );
                }
                _ => panic!("phase {} in a planned path", pt.phase),
            }
        }
    }
    // The reported max joint step is the path's.
    let max_step = path
        .windows(2)
        .map(|p| {
            (0..dof)
                .map(|j| (p[1].q[j] - p[0].q[j]).abs())
                .fold(0.0, Real::max)
        })
        .fold(0.0, Real::max);
    assert!((max_step - plan.max_joint_step).abs() < 1e-15);
    // Time parametrization: every joint and the motor within their scaled limits.
    let traj = planner.trajectory(plan).unwrap();
    // The seed's protocol: load (with reconfigurations), one hold, unload along the same path.
    let n = path.len();
    assert_eq!(traj.points.len(), 2 * n);
    assert_eq!(traj.points[n].phase, Phase::Hold);
    assert!(traj.points[n].t - traj.points[n - 1].t >= rig.planner.hold_time);
    for k in 0..n {
        assert_eq!(traj.points[k].phase, path[k].phase);
        let back = &traj.points[2 * n - 1 - k];
        assert_eq!(back.q, path[k].q, "unloading retraces loading");
        assert_eq!(back.s, path[k].waypoint.s);
        if k + 1 < n {
            let want = if path[k + 1].phase == Phase::Reconfigure {
                Phase::Reconfigure
            } else {
                Phase::Unload
            };
            assert_eq!(back.phase, want);
        }
    }
    assert_eq!(traj.points.last().unwrap().s, 0.0);
    let scale = rig.planner.velocity_scale;
    for wdw in traj.points.windows(2) {
        let dt = wdw[1].t - wdw[0].t;
        assert!(dt > 0.0 || wdw[1].q == wdw[0].q);
        if dt > 0.0 {
            for (j, jt) in model.joints().iter().enumerate() {
                assert!(
                    (wdw[1].q[j] - wdw[0].q[j]).abs() / dt <= jt.velocity * scale * (1.0 + 1e-9)
                );
            }
            assert!(
                (wdw[1].motor - wdw[0].motor).abs() / dt
                    <= rig.motor.max_velocity * scale * (1.0 + 1e-9)
            );
            let dv = (wdw[1].pose.translation.vector - wdw[0].pose.translation.vector).norm() / dt;
            assert!(dv <= rig.planner.end_speed * (1.0 + 1e-9));
        }
    }
}

fn s_star(d: &Direction) -> Real {
    helixreach::boundary::continuum::critical_s(d, 1e-10)
        .unwrap()
        .s_star
}

#[test]
fn fixed_roll_paths_verify() {
    let planner = seed_planner();
    let mut testable = 0;
    for (k, t, w) in [(0.3, 0.9, 0.3), (0.5, 0.5, 0.7), (0.9, 0.1, 0.4)] {
        let d = Direction::new(k, t, w).unwrap();
        let plan = planner
            .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, true)
            .unwrap();
        assert!(
            plan.n_reached > 10,
            "{d:?}: reached only {} waypoints",
            plan.n_reached
        );
        verify(planner, &plan);
        if plan.class == ReachClass::Testable {
            testable += 1;
            assert!(plan.s_reached >= plan.s_star * 1.1 * (1.0 - 1e-12));
            assert!(plan.cause.is_none());
        } else {
            assert!(plan.cause.is_some() && plan.s_reached < plan.s_end);
        }
    }
    assert!(testable >= 1, "no testable ray among the three");
}

/// How far a plan got must agree with its class and cause: testable reaches the target
/// s*·(1 + margin) with every waypoint, anything else stops short with a cause.
fn assert_progress(plan: &RayPlan) {
    let end = plan.s_star * 1.1;
    assert!(
        (plan.s_end - end).abs() <= 1e-12 * end,
        "target {} vs s*·1.1 = {end}",
        plan.s_end
    );
    let last = plan
        .path
        .as_ref()
        .and_then(|p| p.last())
        .map(|p| p.waypoint.s);
    if plan.class == ReachClass::Testable {
        assert!(plan.s_reached >= plan.s_end * (1.0 - 1e-12), "{plan:?}");
        assert_eq!(plan.n_reached, plan.n_waypoints);
        assert!(plan.cause.is_none());
        assert!(last.is_some_and(|s| (s - plan.s_end).abs() <= 1e-12 * plan.s_end));
    } else {
        assert!(plan.cause.is_some() && plan.s_reached < plan.s_end);
    }
}

#[test]
fn motor_roll_and_azimuth_paths_verify() {
    let planner = seed_planner();
    let d = Direction::new(0.5, 0.5, 0.7).unwrap();
    let fixed = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, true)
        .unwrap();
    let plan = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Motor, true)
        .unwrap();
    verify(planner, &plan);
    assert_progress(&fixed);
    assert_progress(&plan);
    // The motor frees the roll: every fixed-roll configuration is a motor-roll one, so the motor
    // plan gets at least as far; on this ray of the seed rig it reaches the whole target
    // s*·(1 + margin) (the seed rig's margin is 0.10).
    assert!(
        plan.s_reached >= fixed.s_reached * (1.0 - 1e-12),
        "motor {} < fixed {}",
        plan.s_reached,
        fixed.s_reached
    );
    assert_eq!(plan.class, ReachClass::Testable, "motor plan: {plan:?}");
    let plan = planner
        .plan_ray(&d, s_star(&d), 2.0, RollMode::Fixed, true)
        .unwrap();
    verify(planner, &plan);
}

#[test]
fn uniform_waypoints_at_the_seed_density() {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.waypoints = 400;
    let planner = Planner::new(rig).unwrap();
    let d = Direction::new(0.3, 0.9, 0.3).unwrap();
    let plan = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, true)
        .unwrap();
    assert!(plan.n_waypoints >= 400);
    verify(&planner, &plan);
}

#[test]
fn unreachable_direction_is_a_blocked_row_not_an_error() {
    // A motor that can hardly turn: the first waypoint of a twisting ray needs ω/c > 1e-9.
    let text = helixreach::planning::rig::EMBEDDED_RIGS[0].1.replace(
        "max_velocity = 3.0",
        "max_velocity = 3.0\nlower = -1e-9\nupper = 1e-9",
    );
    let rig = Rig::from_toml_str(&text, "tiny-motor.toml", std::path::Path::new(".")).unwrap();
    let planner = Planner::new(rig).unwrap();
    let d = Direction::new(0.1, 0.1, 0.99).unwrap();
    let plan = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, false)
        .unwrap();
    assert_eq!(plan.class, ReachClass::Blocked);
    assert_eq!(plan.cause.map(|c| c.as_str()), Some("joint_limit"));
    assert_eq!(plan.s_reached, 0.0);
    let row = helixreach::sweep::reach::reach_row(&plan).unwrap();
    assert_eq!(row[5], "blocked");
    assert_eq!(row[6], "joint_limit");
}

#[test]
fn bad_rigs_and_inputs_are_clear_errors() {
    let seed = helixreach::planning::rig::EMBEDDED_RIGS[0].1;
    let load = |from: &str, to: &str| {
        assert!(seed.contains(from));
        Rig::from_toml_str(
            &seed.replacen(from, to, 1),
            "bad.toml",
            std::path::Path::new("."),
        )
    };
    // Unreachable clamp: 5 m in front of the robot.
    let rig = load(
        "origin = [0.85, -0.15, -0.144]",
        "origin = [5.0, -0.15, -0.144]",
    )
    .unwrap();
    let e = Planner::new(rig).unwrap_err().to_string();
    assert!(
        e.contains("bad.toml") && e.contains("clamp.origin") && e.contains("unreachable"),
        "{e}"
    );
    // A rig referring to a missing link.
    let rig = load(
        "tip_link = \"right_motor_tip\"",
        "tip_link = \"right_nose\"",
    )
    .unwrap();
    let e = Planner::new(rig).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("right_nose"), "{e}");
    // A negative margin (0 is allowed: the seed drove to the boundary).
    let e = load("margin = 0.10", "margin = -0.1")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.toml: planner.margin") && e.contains("= -0.1"),
        "{e}"
    );
    assert!(load("margin = 0.10", "margin = 0.0").is_ok());
    // κ < 0.
    let e = Direction::new(-0.1, 0.5, 0.5).unwrap_err().to_string();
    assert!(e.contains("dir_kappa"), "{e}");
    // A bad s*.
    let d = Direction::new(0.5, 0.5, 0.5).unwrap();
    assert!(seed_planner()
        .plan_ray(&d, -1.0, 0.0, RollMode::Fixed, false)
        .is_err());
    assert!(seed_planner()
        .plan_ray(&d, f64::NAN, 0.0, RollMode::Fixed, false)
        .is_err());
}

#[test]
fn second_arm_rig_plans() {
    let planner = Planner::new(Rig::load("panda-bench").unwrap()).unwrap();
    let d = Direction::new(0.3, 0.9, 0.3).unwrap();
    let plan = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, true)
        .unwrap();
    assert!(plan.n_reached > 10, "{plan:?}");
    verify(&planner, &plan);
}

#[test]
fn sweep_is_identical_for_one_and_two_threads() {
    use helixreach::sweep::driver::SweepOptions;
    use helixreach::sweep::reach::{run, ReachOptions, REACH_HEADER};
    let dirs = helixreach::directions::fibonacci(6, true).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = ReachOptions {
        roll: RollMode::Fixed,
        azimuths: vec![0.0],
    };
    let mut outs = Vec::new();
    for threads in [1, 2] {
        let out = dir.path().join(format!("reach{threads}.csv"));
        let sweep = SweepOptions::new(&out, REACH_HEADER, 3);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| run(seed_planner(), &dirs, None, &opts, &sweep))
            .unwrap();
        outs.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(outs[0], outs[1]);
    let text = String::from_utf8(outs[0].clone()).unwrap();
    // Plain CSV: the header, 6 rows (the settings record is in the sidecar).
    assert_eq!(text.lines().count(), 7);
    assert_eq!(text.lines().next(), Some(REACH_HEADER.join(",").as_str()));
}

#[test]
fn the_verifier_catches_corrupted_paths() {
    // The checks above can fail: a 1 mrad error in one joint, or a motor angle off by 1e-3,
    // is caught.
    let planner = seed_planner();
    let d = Direction::new(0.3, 0.9, 0.3).unwrap();
    let plan = planner
        .plan_ray(&d, s_star(&d), 0.0, RollMode::Fixed, true)
        .unwrap();
    let corrupt = |f: &dyn Fn(&mut RayPlan)| {
        let mut bad = plan.clone();
        f(&mut bad);
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| verify(planner, &bad))).is_err()
    };
    assert!(corrupt(&|p| p.path.as_mut().unwrap()[5].q[3] += 1e-3));
    assert!(corrupt(&|p| p.path.as_mut().unwrap()[7].motor += 1e-3));
    assert!(corrupt(&|p| p.azimuth += 1e-3));
    assert!(corrupt(
        &|p| p.path.as_mut().unwrap()[6].phase = Phase::Reconfigure
    ));
}

/// A scene obstacle that forces a reconfiguration: a ball of radius 0.09 m where the
/// unobstructed plan of (0.5, 0.5, 0.7) puts `right_l3` at 30 % of its path (found by a search
/// over link positions of that path). Without reconfiguration no plan gets past s ≈ 9.1 (a ball
/// of 0.07 m the search passes without one: its load steps that land in collision continue
/// along the self-motion within the joint-step bound, and steer the arm around it); with
/// it the ray is testable, and `verify` re-checks every intermediate configuration of every
/// reconfiguration with a fresh collision model that includes the ball: the rod end within
/// 1e-6 m / 1e-6 rad along each joint-linear chord, s and the motor constant, limits, self /
/// scene / rod collision at 0.005 rad, steps ≤ `max_joint_step`.
#[test]
fn an_obstacle_forces_a_reconfiguration() {
    use helixreach::robot::collision::{ObstaclePose, SceneObstacle};
    use helixreach::robot::Shape;
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.obstacles.push(SceneObstacle {
        name: "probe".into(),
        shape: Shape::Sphere { radius: 0.09 },
        pose: ObstaclePose {
            xyz: [0.20101114348229562, 0.3789120671947688, 0.5599953923814629],
            rpy: [0.0; 3],
        },
    });
    let d = Direction::new(0.5, 0.5, 0.7).unwrap();
    let s = s_star(&d);
    let mut none = rig.clone();
    none.planner.allow_reconfiguration = false;
    let blocked = Planner::new(none)
        .unwrap()
        .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
        .unwrap();
    assert_ne!(
        blocked.class,
        ReachClass::Testable,
        "the ball must block every plan without reconfiguration"
    );
    let planner = Planner::new(rig).unwrap();
    let plan = planner.plan_ray(&d, s, 0.0, RollMode::Fixed, true).unwrap();
    assert_eq!(
        plan.class,
        ReachClass::Testable,
        "reconfiguration must get past the ball (without: s = {})",
        blocked.s_reached
    );
    assert!(plan.reconfigurations >= 1);
    verify(&planner, &plan);
}
