//! IK success rate and time per solution, ours vs k's `JacobianIkSolver`, on the same random
//! reachable poses (FK of uniformly random in-limit configurations). Every solution of either
//! solver is re-checked here by our FK (≤ 1e-9 m / rad) and the joint limits.
//!
//! Run: `cargo run --release --example ik_report -- [robot] [n_poses] [restarts]`
//! (defaults: sawyer 10000 50).

use helixreach::math::Real;
use helixreach::robot::k_bridge::KRobot;
use helixreach::robot::{IkParams, IkSolver, IkTarget, RobotModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// CPU time of this thread (s), from /proc/thread-self/schedstat (immune to other processes
/// sharing the cores; 0 where unavailable).
fn cpu_time() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(0.0, |ns| ns * 1e-9)
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn pct(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p) as usize]
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let robot = args.get(1).map(String::as_str).unwrap_or("sawyer");
    let n: usize = args
        .get(2)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(10_000);
    let restarts: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(50);
    let m = RobotModel::load(robot, None)?;
    let dof = m.dof();
    let solver = IkSolver::new(
        &m,
        IkParams {
            restarts,
            ..IkParams::default()
        },
    )?;
    let k = KRobot::new(&m)?;
    let ksolver = k::JacobianIkSolver::new(1e-10, 1e-10, 0.5, 100);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let poses: Vec<_> = (0..n)
        .map(|_| {
            let q = m.random_config(&mut rng);
            m.chain().tool_pose(&q[..dof])
        })
        .collect();
    let verify = |target: &IkTarget, q: &[Real]| -> bool {
        let (pe, ae) = target.errors(&m.chain().tool_pose(q));
        m.within_limits(q, 0.0) && pe <= 1e-9 && ae <= 1e-9
    };

    println!("robot {robot} ({dof} joints), {n} random reachable poses, seeds: ChaCha8 2024");
    // Kinematics and collision, CPU time per call (batch of 1e6 / 1e5 calls).
    {
        let qs: Vec<Vec<Real>> = (0..1024)
            .map(|_| m.random_config(&mut rng)[..dof].to_vec())
            .collect();
        let per_call = |calls: usize, f: &mut dyn FnMut(usize)| -> f64 {
            let c0 = cpu_time();
            for i in 0..calls {
                f(i & 1023);
            }
            1e9 * (cpu_time() - c0) / calls as f64
        };
        let mut acc = 0.0;
        let fk = per_call(1_000_000, &mut |i| {
            acc += std::hint::black_box(m.chain().tool_pose(&qs[i])).pos.x
        });
        let mut jac = helixreach::robot::Jacobian::zeros();
        let jt = per_call(1_000_000, &mut |i| {
            acc += std::hint::black_box(m.chain().jacobian(&qs[i], &mut jac))
                .pos
                .x
        });
        let kfk = per_call(100_000, &mut |i| {
            acc += std::hint::black_box(k.tool_pose(&qs[i])).pos.x
        });
        let kj = per_call(100_000, &mut |i| {
            k.arm.set_joint_positions_unchecked(&qs[i]);
            k.arm.update_transforms();
            acc += std::hint::black_box(k::jacobian(&k.arm))[(0, 0)]
        });
        let cm = helixreach::robot::CollisionModel::for_model(&m)?;
        let mut ws = cm.workspace();
        let mut hits = 0usize;
        let col = per_call(100_000, &mut |i| {
            hits += usize::from(cm.check(&qs[i], &mut ws, None).is_some())
        });
        println!(
            "CPU time per call: FK tool {fk:.0} ns (k {kfk:.0} ns, ratio {:.1}), Jacobian {jt:.0} ns (k {kj:.0} ns, ratio {:.1}), self-collision check {col:.0} ns ({} body pairs, {:.1} % of random configs in collision) [{}]",
            kfk / fk,
            kj / jt,
            cm.n_self_pairs(),
            100.0 * hits as f64 / 100_000.0,
            acc.is_finite()
        );
    }
    for (label, free_roll) in [("full pose", false), ("free roll", true)] {
        let (mut ok, mut times) = (0usize, Vec::with_capacity(n));
        let c0 = cpu_time();
        for p in &poses {
            let mut t = IkTarget::pose(*p)?;
            if free_roll {
                t = t.free_roll();
            }
            let t0 = Instant::now();
            let sol = solver.solve(&t, None);
            let dt = t0.elapsed().as_secs_f64();
            if let Some(s) = sol {
                assert!(verify(&t, s.joints()), "ours returned an invalid solution");
                ok += 1;
                times.push(dt);
            }
        }
        let cpu = cpu_time() - c0;
        println!(
            "helixreach LM ({label}, ≤{restarts} restarts): success {:.2} % ({ok}/{n}), CPU {:.2} µs per pose, wall median {:.2} µs, p90 {:.2} µs per solution",
            100.0 * ok as f64 / n as f64,
            1e6 * cpu / n as f64,
            1e6 * median(&mut times.clone()),
            1e6 * pct(&mut times, 0.9)
        );
    }

    // k: the same poses, the same restart budget (random seeds from the same kind of stream).
    let (mut ok, mut invalid, mut times) = (0usize, 0usize, Vec::with_capacity(n));
    let mut krng = ChaCha8Rng::seed_from_u64(0);
    let c0 = cpu_time();
    for p in &poses {
        let t = IkTarget::pose(*p)?;
        let t0 = Instant::now();
        let mut found = None;
        for _ in 0..restarts.max(1) {
            let seed = m.random_config(&mut krng);
            if let Some(q) = k.solve_ik(&ksolver, p, &seed[..dof]) {
                found = Some(q);
                break;
            }
        }
        let dt = t0.elapsed().as_secs_f64();
        if let Some(q) = found {
            if verify(&t, &q) {
                ok += 1;
                times.push(dt);
            } else {
                invalid += 1;
            }
        }
    }
    let cpu = cpu_time() - c0;
    println!(
        "k JacobianIkSolver (full pose, 1e-10, 100 iterations, ≤{restarts} restarts): success {:.2} % ({ok}/{n}; {invalid} converged but failed the FK/limit check), CPU {:.2} µs per pose, wall median {:.2} µs, p90 {:.2} µs per solution",
        100.0 * ok as f64 / n as f64,
        1e6 * cpu / n as f64,
        1e6 * median(&mut times.clone()),
        1e6 * pct(&mut times, 0.9)
    );

    // Track mode: one LM run from a nearby configuration (0.01 rad per joint away).
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut ok, mut times) = (0usize, Vec::with_capacity(n));
    let mut cpu = 0.0;
    for _ in 0..n {
        let q = m.random_config(&mut rng);
        let t = IkTarget::pose(m.chain().tool_pose(&q[..dof]))?;
        let mut seed = q;
        for (i, s) in seed.iter_mut().enumerate().take(dof) {
            let j = &m.joints()[i];
            *s = (*s + 0.01).clamp(j.lower, j.upper);
        }
        let c0 = cpu_time();
        let t0 = Instant::now();
        let sol = solver.track(&t, &seed[..dof], None);
        let dt = t0.elapsed().as_secs_f64();
        cpu += cpu_time() - c0;
        if let Some(s) = sol {
            assert!(verify(&t, s.joints()));
            ok += 1;
            times.push(dt);
        }
    }
    println!(
        "helixreach track (seed 0.01 rad off per joint): success {:.2} %, CPU {:.2} µs per call (incl. ~1 µs schedstat read), wall median {:.2} µs",
        100.0 * ok as f64 / n as f64,
        1e6 * cpu / n as f64,
        1e6 * median(&mut times)
    );
    Ok(())
}
