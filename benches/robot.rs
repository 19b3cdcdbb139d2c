//! Robot benchmarks, ours vs k (nalgebra 0.30 `k` crate) in the same run on the same seeded
//! inputs: FK of the tool, geometric Jacobian, IK per solved pose (random reachable poses, both
//! with random restarts), and a whole-configuration self-collision check (Sawyer).
//! Success rates are not a criterion figure: `cargo run --release --example ik_report`.
//!
//! Times are this thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`), so other processes sharing the
//! cores do not inflate them.
//!
//! Run: `cargo bench --bench robot`

#[path = "common/cpu_time.rs"]
mod cpu_time;

use cpu_time::ThreadCpuTime;
use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::robot::k_bridge::KRobot;
use helixreach::robot::{CollisionModel, IkParams, IkSolver, IkTarget, Jacobian, RobotModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

fn configs(m: &RobotModel, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| m.random_config(&mut rng)[..m.dof()].to_vec())
        .collect()
}

fn kinematics<M: Measurement>(c: &mut Criterion<M>) {
    let m = RobotModel::load("sawyer", None).unwrap();
    let k = KRobot::new(&m).unwrap();
    let qs = configs(&m, 1024, 1);
    let mut g = c.benchmark_group("robot_kinematics_sawyer");
    g.measurement_time(Duration::from_secs(3));
    let mut i = 0;
    g.bench_function("fk_tool/helixreach", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(m.chain().tool_pose(black_box(&qs[i])))
        })
    });
    g.bench_function("fk_tool/k", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(k.tool_pose(black_box(&qs[i])))
        })
    });
    let mut jac = Jacobian::zeros();
    g.bench_function("jacobian/helixreach", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(m.chain().jacobian(black_box(&qs[i]), &mut jac));
        })
    });
    g.bench_function("jacobian/k", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            k.arm.set_joint_positions_unchecked(black_box(&qs[i]));
            k.arm.update_transforms();
            black_box(k::jacobian(&k.arm))
        })
    });
    g.finish();
}

fn inverse_kinematics<M: Measurement>(c: &mut Criterion<M>) {
    let m = RobotModel::load("sawyer", None).unwrap();
    let k = KRobot::new(&m).unwrap();
    let poses: Vec<_> = configs(&m, 64, 2)
        .iter()
        .map(|q| m.chain().tool_pose(q))
        .collect();
    let solver = IkSolver::new(&m, IkParams::default()).unwrap();
    let ksolver = k::JacobianIkSolver::new(1e-10, 1e-10, 0.5, 100);
    let mut g = c.benchmark_group("robot_ik_sawyer_per_pose");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    let mut i = 0;
    g.bench_function("helixreach_lm", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let t = IkTarget::Pose(poses[i]);
            black_box(solver.solve(&t, None))
        })
    });
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    g.bench_function("k_jacobian_ik_solver", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            for _ in 0..50 {
                let seed = m.random_config(&mut rng);
                if let Some(q) = k.solve_ik(&ksolver, &poses[i], &seed[..7]) {
                    return black_box(Some(q));
                }
            }
            None
        })
    });
    let seeds = configs(&m, 64, 2);
    g.bench_function("helixreach_track", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let mut s = seeds[i].clone();
            s.iter_mut().for_each(|x| *x += 0.01);
            black_box(solver.track(&IkTarget::Pose(poses[i]), &s, None))
        })
    });
    g.finish();
}

fn collision<M: Measurement>(c: &mut Criterion<M>) {
    let m = RobotModel::load("sawyer", None).unwrap();
    let cm = CollisionModel::for_model(&m).unwrap();
    let mut ws = cm.workspace();
    let qs = configs(&m, 1024, 4);
    let mut g = c.benchmark_group("robot_collision_sawyer");
    g.measurement_time(Duration::from_secs(3));
    let mut i = 0;
    g.bench_function("self_collision_check", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(cm.check(black_box(&qs[i]), &mut ws, None))
        })
    });
    g.bench_function("clearance", |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(cm.clearance(black_box(&qs[i]), &mut ws, None))
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpuTime);
    targets = kinematics, inverse_kinematics, collision
}
criterion_main!(benches);
