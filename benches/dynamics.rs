//! Criterion benchmarks of the DER dynamics.
//!
//! - `implicit_step/n{50,100}`: one implicit Euler step (Newton on the banded system, ~2
//!   iterations) of the paper-sim rod, the end moving along S̄ = [1,1,1]/√3 at v = 0.1/s with
//!   Δt = 2 ms, starting from the DER-statics equilibrium at s = 5 (s* ≈ 10.7); the state is
//!   reset to that start every 10,000 steps so the rod stays on the stable branch. Steps per
//!   second = 1/time.
//! - `quasi_static_ray/dynamics_n20`: one full quasi-static ray (n = 20, v = 0.005/s,
//!   Δt = 0.5 s; s_dyn within 0.5 % of the statics s*), next to
//!   `quasi_static_ray/der_statics_n20`: the DER-statics boundary of the same ray and n
//!   (tol_rel = 1e-6). Their ratio is the speed argument for statics.

use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::boundary::der::{critical_s, DerBoundaryParams, DerRay};
use helixreach::directions::Direction;
use helixreach::helix::Helix;
use helixreach::math::{Real, Vec3};
use helixreach::rod::clamp::ClampPlacement;
use helixreach::rod::dynamics::{
    simulate_ray, EndClamp, PhysicalRod, SimParams, Stepper, StepperParams,
};
use std::hint::black_box;

fn stepper(n: usize, dir: &Direction, s0: Real) -> Stepper {
    let params = DerBoundaryParams {
        n_edges: n,
        ..Default::default()
    };
    let mut ray = DerRay::new(dir, &params).unwrap();
    ray.evaluate(s0).unwrap();
    let rod = PhysicalRod::paper_sim();
    Stepper::new(
        ray.rod().clone(),
        ClampPlacement::Straddle,
        ray.state().unwrap().clone(),
        0.5 * rod.slenderness().powi(2),
        Vec3::zeros(),
        0.0,
        StepperParams::default(),
    )
    .unwrap()
}

fn implicit_step(c: &mut Criterion) {
    let dir = Direction::new(1.0, 1.0, 1.0).unwrap();
    let rod = PhysicalRod::paper_sim();
    let t0 = rod.time_unit();
    let (dt, v) = (2e-3, 0.1);
    let c_ratio = 1.0 / (1.0 + rod.nu);
    let mut g = c.benchmark_group("implicit_step");
    for n in [50usize, 100] {
        let s0 = 5.0;
        let start = stepper(n, &dir, s0);
        let mut st = start.clone();
        let mut k = 0usize;
        g.bench_function(format!("n{n}"), |b| {
            b.iter(|| {
                if k == 10_000 {
                    st = start.clone();
                    k = 0;
                }
                let s_next = s0 + v * dt * (k + 1) as Real;
                let ds = v * dt;
                let end = |lam: Real| {
                    let [kk, tt, ww] = dir.at(s_next - ds + lam * ds);
                    let pose = Helix::new(kk, tt, ww)
                        .unwrap()
                        .end_pose_unchecked(1.0, c_ratio);
                    EndClamp {
                        position: pose.position,
                        frame: pose.material,
                    }
                };
                k += 1;
                black_box(st.step(dt / t0, Some(&end)).unwrap())
            })
        });
    }
    g.finish();
}

fn quasi_static_ray(c: &mut Criterion) {
    let dir = Direction::new(1.0, 1.0, 1.0).unwrap();
    let rod = PhysicalRod::paper_sim();
    let n = 20;
    let mut g = c.benchmark_group("quasi_static_ray");
    g.sample_size(10);
    let p = SimParams {
        n_edges: n,
        speed: 0.005,
        dt: 0.5,
        record_ds: 0.005,
        ..Default::default()
    };
    g.bench_function("dynamics_n20", |b| {
        b.iter(|| black_box(simulate_ray(&dir, &p, &mut |_| {}).unwrap().s_dyn()))
    });
    let sp = DerBoundaryParams {
        n_edges: n,
        nu: rod.nu,
        tol_rel: 1e-6,
        stretch: 4.0 / rod.slenderness().powi(2),
        ..Default::default()
    };
    g.bench_function("der_statics_n20", |b| {
        b.iter(|| black_box(critical_s(&dir, &sp).unwrap().s_star))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    // No plots: the plotters backend needs a system font the CI image lacks.
    config = Criterion::default().without_plots();
    targets = implicit_step, quasi_static_ray
}
criterion_main!(benches);
