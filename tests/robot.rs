//! Robot model tests: the compiled kinematics against k (an independent library) and finite
//! differences, IK solutions re-checked by FK and limits, collision against parry's own
//! pairwise queries, and clear errors for bad input.

use helixreach::math::{rotation_angle, Mat3, Real, Vec3};
#[cfg(feature = "interop")]
use helixreach::robot::{k_bridge::KRobot, Frame};
use helixreach::robot::{
    pose_from_xyz_wxyz, IkParams, IkSolver, IkTarget, Jacobian, RobotModel, MAX_DOF,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const ROBOTS: [&str; 3] = ["sawyer", "panda", "iiwa14"];
const SEED_Q: [Real; 7] = [-0.857, -0.873, -1.819, -0.034, 1.860, 2.434, -2.200];

#[cfg(feature = "interop")]
fn frame_diff(a: &Frame, b: &Frame) -> (Real, Real) {
    ((a.pos - b.pos).norm(), (a.rot - b.rot).abs().max())
}

// The k cross-checks run with `--features interop` (the README's test command).
#[cfg(feature = "interop")]
#[test]
fn compiled_fk_equals_k_fk_at_10000_random_configs() {
    for name in ROBOTS {
        let m = RobotModel::load(name, None).unwrap();
        let k = KRobot::new(&m).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut worst: (Real, Real) = (0.0, 0.0);
        for _ in 0..10_000 {
            let q = m.random_config(&mut rng);
            let q = &q[..m.dof()];
            let (dp, dr) = frame_diff(&m.chain().tool_pose(q), &k.tool_pose(q));
            worst = (worst.0.max(dp), worst.1.max(dr));
        }
        assert!(
            worst.0 <= 1e-12 && worst.1 <= 1e-12,
            "{name}: tool pose vs k: {worst:?}"
        );
    }
}

// The k cross-checks run with `--features interop` (the README's test command).
#[cfg(feature = "interop")]
#[test]
fn every_link_frame_equals_k() {
    for name in ROBOTS {
        let m = RobotModel::load(name, None).unwrap();
        let k = KRobot::new(&m).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut buf = vec![Frame::identity(); m.chain().n_links()];
        for _ in 0..1000 {
            let q = m.random_config(&mut rng);
            let q = &q[..m.dof()];
            m.chain().link_frames(q, &mut buf);
            let kf = k.link_frames(q);
            for (i, (a, b)) in buf.iter().zip(&kf).enumerate() {
                let (dp, dr) = frame_diff(a, b);
                assert!(
                    dp <= 1e-12 && dr <= 1e-12,
                    "{name} link {}: {dp:e} {dr:e}",
                    m.links()[i].name
                );
            }
            // The tool link frame of the tree equals the tool pose of the chain.
            let (dp, dr) = frame_diff(&buf[m.tip_index()], &m.chain().tool_pose(q));
            assert!(dp <= 1e-12 && dr <= 1e-12);
        }
    }
}

#[test]
fn reference_poses_of_the_flanges() {
    // shared/reference/robots/README.md: flange positions at q = 0 and at named poses.
    let s = RobotModel::load("sawyer", Some("right_hand")).unwrap();
    let p = s.tool_pose(&[0.0; 7]).unwrap().pos;
    assert!((p - Vec3::new(1.0155, 0.1603, 0.3170)).norm() < 1e-4, "{p}");
    let neutral = [0.0, -1.18, 0.0, 2.18, 0.0, 0.57, 3.3161];
    let p = s.tool_pose(&neutral).unwrap().pos;
    assert!((p - Vec3::new(0.4496, 0.1603, 0.2158)).norm() < 1e-4, "{p}");
    let panda = RobotModel::load("panda", None).unwrap();
    let pi = std::f64::consts::PI;
    let ready = [
        0.0,
        -pi / 4.0,
        0.0,
        -3.0 * pi / 4.0,
        0.0,
        pi / 2.0,
        pi / 4.0,
    ];
    let p = panda.tool_pose(&ready).unwrap().pos;
    assert!((p - Vec3::new(0.3069, 0.0, 0.5903)).norm() < 1e-4, "{p}");
    let iiwa = RobotModel::load("iiwa14", None).unwrap();
    let p = iiwa.tool_pose(&[0.0; 7]).unwrap().pos;
    assert!((p - Vec3::new(0.0, 0.0, 1.306)).norm() < 1e-4, "{p}");
    // The motor tip is (0.003, 0.0035, 0.171) from right_hand, same rotation.
    let tip = RobotModel::load("sawyer", None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..100 {
        let q = tip.random_config(&mut rng);
        let h = s.chain().tool_pose(&q[..7]);
        let t = tip.chain().tool_pose(&q[..7]);
        let expect = h.transform_point(&Vec3::new(0.003, 0.0035, 0.171));
        assert!((t.pos - expect).norm() < 1e-14);
        assert!((t.rot - h.rot).abs().max() < 1e-15);
    }
}

/// Rotation vector of a small rotation: vee((R − Rᵀ)/2) = sin θ·axis (θ³ error, ~1e-18 here).
fn vee_log(r: &Mat3) -> Vec3 {
    0.5 * Vec3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    )
}

#[test]
fn jacobian_equals_central_differences() {
    for name in ROBOTS {
        let m = RobotModel::load(name, None).unwrap();
        let n = m.dof();
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let h = 1e-6;
        for _ in 0..200 {
            let q = m.random_config(&mut rng);
            let mut jac = Jacobian::zeros();
            let f0 = m.chain().jacobian(&q[..n], &mut jac);
            assert_eq!(f0, m.chain().tool_pose(&q[..n]));
            for i in 0..MAX_DOF {
                if i >= n {
                    assert_eq!(jac.column(i).norm(), 0.0);
                    continue;
                }
                let (mut qp, mut qm) = (q, q);
                qp[i] += h;
                qm[i] -= h;
                let fp = m.chain().tool_pose(&qp[..n]);
                let fm = m.chain().tool_pose(&qm[..n]);
                let v = (fp.pos - fm.pos) / (2.0 * h);
                let w = vee_log(&(fp.rot * fm.rot.transpose())) / (2.0 * h);
                let jv: Vec3 = jac.fixed_view::<3, 1>(0, i).into_owned();
                let jw: Vec3 = jac.fixed_view::<3, 1>(3, i).into_owned();
                assert!((jv - v).norm() < 1e-8, "{name} col {i} v: {jv} vs {v}");
                assert!((jw - w).norm() < 1e-8, "{name} col {i} w: {jw} vs {w}");
            }
        }
    }
}

fn check_solution(m: &RobotModel, target: &IkTarget, q: &[Real]) {
    assert!(m.within_limits(q, 0.0), "outside limits: {q:?}");
    let f = m.tool_pose(q).unwrap();
    let (pe, ae) = target.errors(&f);
    assert!(pe <= 1e-10 && ae <= 1e-10, "errors {pe:e} {ae:e}");
}

#[test]
fn ik_solves_random_reachable_poses_and_every_solution_checks_out() {
    for name in ROBOTS {
        let m = RobotModel::load(name, None).unwrap();
        let solver = IkSolver::new(&m, IkParams::default()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let trials = 1000;
        let mut ok = 0;
        for _ in 0..trials {
            let q = m.random_config(&mut rng);
            let target = IkTarget::pose(m.chain().tool_pose(&q[..m.dof()])).unwrap();
            if let Some(sol) = solver.solve(&target, None) {
                check_solution(&m, &target, sol.joints());
                ok += 1;
            }
        }
        let rate = ok as Real / trials as Real;
        println!("{name}: IK success {rate}");
        assert!(rate >= 0.99, "{name}: IK success rate {rate}");
    }
}

#[test]
fn ik_all_solutions_are_distinct_valid_and_respect_the_redundancy_lock() {
    let m = RobotModel::load("sawyer", None).unwrap();
    let params = IkParams {
        samples: 6,
        restarts: 20,
        ..IkParams::default()
    };
    let solver = IkSolver::new(&m, params.clone()).unwrap();
    let target = IkTarget::pose(m.chain().tool_pose(&SEED_Q)).unwrap();
    let sols = solver.solve_all(&target, &[&SEED_Q]);
    assert!(sols.len() >= 6, "only {} solutions", sols.len());
    // Explicit lock values are honoured exactly.
    let locked = IkSolver::new(
        &m,
        IkParams {
            lock_values: vec![-1.2, -0.9],
            ..params.clone()
        },
    )
    .unwrap()
    .solve_all(&target, &[&SEED_Q]);
    for v in [-1.2, -0.9] {
        assert!(
            locked.iter().any(|s| s.joints()[0] == v),
            "no solution at j0 = {v}"
        );
    }
    for s in &locked {
        check_solution(&m, &target, s.joints());
    }
    for (i, s) in sols.iter().enumerate() {
        check_solution(&m, &target, s.joints());
        for t in &sols[..i] {
            let d = s
                .joints()
                .iter()
                .zip(t.joints())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, Real::max);
            assert!(d > params.dedup_tolerance);
        }
    }
    // Deterministic for a given seed.
    assert_eq!(sols, solver.solve_all(&target, &[&SEED_Q]));
}

#[test]
fn ik_free_roll_matches_position_and_axis_only() {
    let m = RobotModel::load("sawyer", None).unwrap();
    let solver = IkSolver::new(&m, IkParams::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut ok = 0;
    for _ in 0..200 {
        let q = m.random_config(&mut rng);
        let f = m.chain().tool_pose(&q[..7]);
        let target = IkTarget::pose(f).unwrap().free_roll();
        if let Some(sol) = solver.solve(&target, None) {
            check_solution(&m, &target, sol.joints());
            let g = m.chain().tool_pose(sol.joints());
            // Independent check: position and z axis by FK.
            assert!((g.pos - f.pos).norm() < 1e-10);
            assert!((g.rot.column(2) - f.rot.column(2)).norm() < 1e-10);
            ok += 1;
        }
    }
    assert!(ok >= 199, "{ok}/200");
}

#[test]
fn ik_track_follows_a_small_motion_to_the_nearby_solution() {
    let m = RobotModel::load("sawyer", None).unwrap();
    let solver = IkSolver::new(&m, IkParams::default()).unwrap();
    // From the Sawyer's named `neutral` pose (right_j6 moved into its range).
    let mut q = [0.0, -1.18, 0.0, 2.18, 0.0, 0.57, 0.3];
    let start = m.chain().tool_pose(&q);
    for k in 1..=100 {
        // Move the tool 0.5 mm per step along +z and turn it 0.1° about x.
        let mut t = start;
        t.pos.z += 0.5e-3 * k as Real;
        t.rot = helixreach::math::so3_exp(&Vec3::new(0.1f64.to_radians() * k as Real, 0.0, 0.0))
            * start.rot;
        let target = IkTarget::pose(t).unwrap();
        let sol = solver
            .track(&target, &q, None)
            .unwrap_or_else(|| panic!("track fails at step {k} from {q:?}"));
        check_solution(&m, &target, sol.joints());
        let step = sol
            .joints()
            .iter()
            .zip(&q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, Real::max);
        assert!(step < 0.1, "joint jump {step} at step {k}");
        q.copy_from_slice(sol.joints());
    }
}

/// `IkSolver::predict` (a track's first trial) is second-order close to where the track from
/// the same configuration ends: for targets a joint step h away (h = 0.02, 0.01, 0.005 rad
/// along random directions from random configurations inside the limits), the predictor's
/// distance to the track's end shrinks about fourfold per halving of h (median ratio within
/// 3.5–4.5, none below 2) and is less than the track's own move; on a target the configuration
/// already reaches it returns the configuration.
#[test]
fn ik_predict_is_second_order_close_to_where_a_track_ends() {
    use rand::Rng;
    let m = RobotModel::load("sawyer", None).unwrap();
    let solver = IkSolver::new(&m, IkParams::default().tracking()).unwrap();
    let (lo, hi) = (m.lower(), m.upper());
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let dist = |a: &[Real], b: &[Real]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, Real::max)
    };
    let mut ratios = Vec::new();
    while ratios.len() < 200 {
        // Away from the limits by more than the largest step.
        let mut q = m.random_config(&mut rng);
        for j in 0..7 {
            q[j] = q[j].clamp(lo[j] + 0.1, hi[j] - 0.1);
        }
        let dir: Vec<Real> = (0..7).map(|_| rng.random_range(-1.0..1.0)).collect();
        let here = IkTarget::pose(m.chain().tool_pose(&q[..7])).unwrap();
        let p0 = solver.predict(&here, &q[..7]).unwrap();
        assert!(dist(&p0[..7], &q[..7]) < 1e-9, "{q:?}");
        let mut errs = Vec::new();
        for h in [0.02, 0.01, 0.005] {
            let mut qt = q;
            for j in 0..7 {
                qt[j] += h * dir[j];
            }
            let target = IkTarget::pose(m.chain().tool_pose(&qt[..7])).unwrap();
            let Some(sol) = solver.track(&target, &q[..7], None) else {
                break;
            };
            let p = solver.predict(&target, &q[..7]).unwrap();
            let moved = dist(sol.joints(), &q[..7]);
            let e = dist(&p[..7], sol.joints());
            assert!(e < moved, "h {h}: predictor {e} off, track moved {moved}");
            errs.push(e);
        }
        if errs.len() == 3 && errs[2] > 1e-12 {
            ratios.push(errs[0] / errs[1]);
            ratios.push(errs[1] / errs[2]);
        }
    }
    ratios.sort_by(Real::total_cmp);
    let median = ratios[ratios.len() / 2];
    assert!(
        ratios[0] >= 2.0,
        "smallest error ratio per halving {}",
        ratios[0]
    );
    assert!(
        (3.5..4.5).contains(&median),
        "median error ratio per halving {median}"
    );
}

#[test]
fn bad_input_gives_clear_errors() {
    let e = RobotModel::from_urdf_file("/nonexistent/robot.urdf", None).unwrap_err();
    assert!(e.to_string().contains("/nonexistent/robot.urdf"), "{e}");
    let e =
        RobotModel::from_urdf_str("<robot name='x'><link name='a'>", "bad.urdf", None).unwrap_err();
    assert!(
        e.to_string().contains("bad.urdf") && e.to_string().contains("malformed"),
        "{e}"
    );
    let e = RobotModel::load("sawyer", Some("right_gripper")).unwrap_err();
    assert!(
        e.to_string().contains("tip_link") && e.to_string().contains("right_gripper"),
        "{e}"
    );
    let m = RobotModel::load("sawyer", None).unwrap();
    let e = m.tool_pose(&[0.0; 6]).unwrap_err();
    assert!(
        e.to_string().contains("joints") && e.to_string().contains("right_j6"),
        "{e}"
    );
    let e = m
        .tool_pose(&[0.0, 0.0, Real::NAN, 0.0, 0.0, 0.0, 0.0])
        .unwrap_err();
    assert!(e.to_string().contains("right_j2"), "{e}");
    let e = pose_from_xyz_wxyz(&[0.5, Real::NAN, 0.0, 1.0, 0.0, 0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("pose.y"), "{e}");
    let e = pose_from_xyz_wxyz(&[0.5, 0.0, 0.0, 0.9, 0.0, 0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("quaternion"), "{e}");
    let e = IkTarget::axis(Vec3::zeros(), Vec3::zeros()).unwrap_err();
    assert!(e.to_string().contains("axis"), "{e}");
    // A non-finite joint origin names the joint.
    let bad = helixreach::robot::builtin("panda")
        .unwrap()
        .urdf
        .replace("xyz=\"0 0 0.333\"", "xyz=\"0 0 nan\"");
    let e = RobotModel::from_urdf_str(&bad, "panda-bad.urdf", None).unwrap_err();
    assert!(e.to_string().contains("fer_joint1"), "{e}");
    // Rotation angle helper sanity (used by every IK check above).
    assert!(rotation_angle(&Mat3::identity()).abs() < 1e-15);
}

mod collision {
    use super::*;
    use helixreach::robot::collision::{BodyRef, ObstaclePose};
    use helixreach::robot::{CollisionModel, DisabledPairs, RodGeometry, SceneObstacle, Shape};

    #[test]
    fn self_collision_agrees_with_parry_pairwise_queries() {
        for name in ROBOTS {
            let m = RobotModel::load(name, None).unwrap();
            let cm = CollisionModel::for_model(&m).unwrap();
            let mut ws = cm.workspace();
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            let (mut hits, mut free) = (0, 0);
            for _ in 0..2000 {
                let q = m.random_config(&mut rng);
                cm.update(&q[..m.dof()], &mut ws);
                let fast = cm.self_collision(&ws);
                let reference = cm.self_collision_parry(&ws);
                assert_eq!(fast.is_some(), !reference.is_empty(), "{name} at {q:?}");
                if let Some(c) = fast {
                    let (BodyRef::Link(a), BodyRef::Link(b)) = (c.a, c.b) else {
                        panic!("self contact between non-links")
                    };
                    assert!(
                        reference.contains(&(a, b)),
                        "{name}: {c:?} not in {reference:?}"
                    );
                    hits += 1;
                } else {
                    free += 1;
                }
            }
            // The sample exercises both outcomes.
            assert!(hits > 10 && free > 10, "{name}: {hits} hits, {free} free");
        }
    }

    #[test]
    fn sawyer_home_and_seed_configuration_are_collision_free() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        for q in [[0.0; 7], SEED_Q] {
            assert_eq!(cm.check(&q, &mut ws, None), None, "at {q:?}");
            let c = cm.clearance(&q, &mut ws, None).unwrap();
            assert!(c.distance > 0.0, "{q:?}: {c:?}");
        }
    }

    #[test]
    fn stored_never_colliding_lists_are_consistent_with_fresh_sampling() {
        // A pair never in collision over the stored N samples is also never in collision
        // over a prefix of the same random stream; "always" pairs likewise always collide.
        for name in ROBOTS {
            let m = RobotModel::load(name, None).unwrap();
            let stored = DisabledPairs::for_model(&m).unwrap();
            assert!(
                stored.samples >= 20_000,
                "{name}: {} samples",
                stored.samples
            );
            let fresh = DisabledPairs::compute(&m, 10_000, stored.seed).unwrap();
            for p in &stored.disabled {
                assert!(
                    fresh.disabled.contains(p),
                    "{name}: stored {p:?} contradicted by fresh sampling"
                );
            }
        }
    }

    fn obstacle(name: &str, shape: Shape, xyz: [Real; 3]) -> SceneObstacle {
        SceneObstacle {
            name: name.into(),
            shape,
            pose: ObstaclePose { xyz, rpy: [0.0; 3] },
        }
    }

    #[test]
    fn scene_obstacles_collide_and_clearance_matches_geometry() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let q = [0.0; 7];
        let tip = m.tool_pose(&q).unwrap().pos; // the arm is stretched along +x at home
        let mut cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        // A ball just beyond the tool along +x: the collet cylinder (r 12 mm) ends at the
        // tip, so the distance to a ball at tip + (d + R) x̂ is d.
        for d in [0.05, 0.02, 0.003] {
            let r = 0.03;
            let ball = obstacle(
                "ball",
                Shape::Sphere { radius: r },
                [tip.x + d + r, tip.y, tip.z],
            );
            cm.set_obstacles(&[ball]).unwrap();
            cm.update(&q, &mut ws);
            let c = cm.scene_clearance(&ws).unwrap();
            assert_eq!(c.b, BodyRef::Obstacle(0));
            assert_eq!(cm.name(c.a), "right_motor_base");
            assert!((c.distance - d).abs() < 1e-6, "d {d}: {c:?}");
            assert_eq!(cm.check(&q, &mut ws, None), None);
        }
        let ball = obstacle(
            "ball",
            Shape::Sphere { radius: 0.03 },
            [tip.x + 0.02, tip.y, tip.z],
        );
        cm.set_obstacles(&[ball]).unwrap();
        let c = cm.check(&q, &mut ws, None).unwrap();
        assert_eq!(cm.name(c.b), "obstacle ball");
        // A table top under the pedestal top is hit by nothing at home; a box through the
        // shoulder is.
        let table = obstacle(
            "table",
            Shape::Box {
                half_extents: Vec3::new(0.5, 0.5, 0.02),
            },
            [0.85, -0.15, -0.3],
        );
        cm.set_obstacles(std::slice::from_ref(&table)).unwrap();
        assert_eq!(cm.check(&q, &mut ws, None), None);
        let wall = obstacle(
            "wall",
            Shape::Cylinder {
                radius: 0.05,
                half_length: 0.5,
            },
            [0.0, 0.0, 0.3],
        );
        cm.set_obstacles(&[table, wall]).unwrap();
        let c = cm.check(&q, &mut ws, None).unwrap();
        assert_eq!(c.b, BodyRef::Obstacle(1));
        // Bad obstacles name themselves.
        let bad = obstacle("post", Shape::Sphere { radius: -1.0 }, [0.0; 3]);
        let e = cm.set_obstacles(&[bad]).unwrap_err();
        assert!(
            e.to_string().contains("post") && e.to_string().contains("radius"),
            "{e}"
        );
    }

    #[test]
    fn the_rod_collides_with_the_arm_and_its_ends_can_be_ignored() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        let q = [0.0; 7];
        let tool = m.tool_pose(&q).unwrap();
        // A straight rod hanging from the tool along the tool axis (away from the arm).
        let axis: Vec3 = tool.rot.column(2).into_owned();
        let nodes: Vec<Vec3> = (0..=50)
            .map(|i| tool.pos + axis * (0.51 * (1.0 - i as Real / 50.0)))
            .collect();
        let rod = |ignore_tool: Real, nodes: &[Vec3]| -> Option<helixreach::robot::Contact> {
            let r = RodGeometry {
                nodes,
                radius: 0.8e-3,
                ignore_near_tool: ignore_tool,
                ignore_near_clamp: 0.0,
                against_scene: false,
            };
            let mut ws2 = cm.workspace();
            cm.check(&q, &mut ws2, Some(&r))
        };
        // The last segment ends inside the collet: a hit unless the tool end is ignored.
        let c = rod(0.0, &nodes).expect("rod end touches the collet");
        assert_eq!(cm.name(c.b), "right_motor_base");
        assert_eq!(rod(0.03, &nodes), None);
        // A rod bent back through the forearm hits it.
        cm.update(&q, &mut ws);
        let l4 = m.link_index("right_l4").unwrap();
        let through = cm.link_frames(&ws)[l4].transform_point(&Vec3::new(0.0, 0.0, 0.15));
        // Clamp end first: up through the forearm, then over to the hanging rod and the tool.
        let bent: Vec<Vec3> = [
            through - Vec3::z() * 0.3,
            through,
            through + Vec3::z() * 0.3,
        ]
        .into_iter()
        .chain(nodes.iter().copied())
        .collect();
        let c = rod(0.03, &bent).expect("rod through the forearm");
        assert!(matches!(c.a, BodyRef::Rod(_)));
        assert_eq!(cm.name(c.b), "right_l4");
    }
}

/// Gap between two axis-aligned boxes (centre, half extents): the norm of the per-axis gaps.
fn aabb_gap(c1: [Real; 3], h1: [Real; 3], c2: [Real; 3], h2: [Real; 3]) -> Real {
    (0..3)
        .map(|i| ((c1[i] - c2[i]).abs() - h1[i] - h2[i]).max(0.0).powi(2))
        .sum::<Real>()
        .sqrt()
}

/// Box–box clearance is exact. parry 0.25's `query::distance` overestimates cuboid–cuboid gaps
/// whose closest features are edges (dimforge/parry#431): the seed rig's pedestal feet to its
/// table read 0.2093 m for a true 0.1978 m. Reference: the analytic gap of the two axis-aligned
/// boxes as the files state them (`robots/sawyer.urdf` pedestal_feet, `robots/sawyer-seed.toml`
/// table).
#[test]
fn box_box_scene_clearance_equals_the_analytic_gap() {
    use helixreach::planning::planner::Planner;
    use helixreach::planning::rig::Rig;
    use helixreach::robot::collision::BodyRef;
    let planner = Planner::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    let c = planner.collision();
    let mut ws = c.workspace();
    // q = 0: the arm stretches forward far above the table; the feet are the closest body.
    c.update(&[0.0; 7], &mut ws);
    let contact = c.scene_clearance(&ws).unwrap();
    let feet = planner
        .model()
        .links()
        .iter()
        .position(|l| l.name == "pedestal_feet")
        .unwrap();
    assert_eq!(
        (contact.a, contact.b),
        (BodyRef::Link(feet), BodyRef::Obstacle(0))
    );
    let want = aabb_gap(
        [-0.1225, 0.0, -0.758],
        [0.385, 0.35, 0.155],
        [0.85, -0.15, -0.525],
        [0.40, 0.50, 0.015],
    );
    assert!((want - 0.19780).abs() < 1e-4, "reference {want}");
    assert!(
        (contact.distance - want).abs() < 1e-9,
        "scene clearance {} vs analytic {want}",
        contact.distance
    );
}
