//! Criterion benchmarks of the helix end pose (goal ≤ 100 ns per pose).
//!
//! Inputs: 1024 seeded random helices (κ log-uniform in [1e-6, 60], τ, ω uniform in [−60, 60],
//! ν uniform in (−1, 0.5]), built outside the timed loop. Each iteration evaluates all 1024, so
//! the per-pose time is the reported time / 1024 (criterion also prints the throughput).
//!
//! Peers in the same run, for a ratio:
//! - `textbook`: the same pose from `math::so3_exp`, `math::so3_left_jacobian` and two full
//!   products with `rot_z` (what one writes without fusing the formulas);
//! - `nalgebra_expm`: the 4×4 SE(3) twist matrix exponentiated by nalgebra's general `exp()`.
//!
//! Two groups run the same bodies: `helix_end_pose_x1024` with criterion's wall clock, and
//! `helix_end_pose_cpu_x1024` with the thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`), which is
//! the meaningful figure on a shared, oversubscribed machine (it excludes time the thread spent
//! descheduled, though not cache and SMT contention).
//!
//! Run: `cargo bench --bench helix`.

#[path = "common/cpu_time.rs"]
mod cpu_time;

use cpu_time::ThreadCpuTime;
use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use helixreach::helix::{twist_ratio, Helix};
use helixreach::math::{hat, rot_z, so3_exp, so3_left_jacobian, Mat3, Vec3};
use nalgebra::Matrix4;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

const N: usize = 1024;

fn inputs() -> Vec<(Helix, f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    (0..N)
        .map(|_| {
            let k = (1e-6f64.ln() + rng.random::<f64>() * (60f64.ln() - 1e-6f64.ln())).exp();
            let t = rng.random_range(-60.0..60.0);
            let w = rng.random_range(-60.0..60.0);
            let nu = rng.random_range(-0.99..0.5);
            (Helix::new(k, t, w).unwrap(), nu)
        })
        .collect()
}

fn end_pose(c: &mut Criterion) {
    bodies(c, "helix_end_pose_x1024");
}

fn end_pose_cpu(c: &mut Criterion<ThreadCpuTime>) {
    bodies(c, "helix_end_pose_cpu_x1024");
}

fn bodies<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let hs = inputs();
    let cs: Vec<f64> = hs.iter().map(|(_, nu)| twist_ratio(*nu).unwrap()).collect();
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("end_pose", |b| {
        b.iter(|| {
            for (h, nu) in &hs {
                black_box(black_box(h).end_pose(1.0, *nu).unwrap());
            }
        })
    });
    g.bench_function("end_pose_unchecked", |b| {
        b.iter(|| {
            for ((h, _), c) in hs.iter().zip(&cs) {
                black_box(black_box(h).end_pose_unchecked(1.0, *c));
            }
        })
    });
    g.bench_function("textbook", |b| {
        b.iter(|| {
            for ((h, _), c) in hs.iter().zip(&cs) {
                let h = black_box(h);
                let w = h.darboux();
                let f = so3_exp(&w);
                let r = so3_left_jacobian(&w) * Vec3::z();
                let q: Mat3 = f * rot_z(-h.tau());
                let m: Mat3 = q * rot_z(h.omega() / c);
                black_box((r, q, m));
            }
        })
    });
    g.bench_function("nalgebra_expm", |b| {
        b.iter(|| {
            for (h, _) in &hs {
                let h = black_box(h);
                let mut x = Matrix4::<f64>::zeros();
                x.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(&h.darboux()));
                x[(2, 3)] = 1.0;
                black_box(x.exp());
            }
        })
    });
    g.finish();
}

// Plots off: criterion's plotters backend panics when no system font is available.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = end_pose
}
criterion_group! {
    name = benches_cpu;
    config = Criterion::default().without_plots().with_measurement(ThreadCpuTime);
    targets = end_pose_cpu
}
criterion_main!(benches, benches_cpu);
