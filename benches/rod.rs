//! DER benchmarks: energy + gradient + Hessian assembly, one banded LDLᵀ factorization, and
//! the DER-statics boundary per direction for n = 25, 50, 100, 200 (seeded inputs: fixed
//! directions; setup excluded). The error of each resolution against the reference is printed
//! by `cargo run --release --example der_convergence`, which also writes the CSV.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use helixreach::boundary::der::{critical_s, DerBoundaryParams, DerRay};
use helixreach::directions::{fibonacci, Direction};
use helixreach::rod::{energy, Workspace};
use std::hint::black_box;

fn equilibrium(n: usize) -> DerRay {
    let dir = Direction::new(1.0, 1.0, 1.0).unwrap();
    let p = DerBoundaryParams {
        n_edges: n,
        ..Default::default()
    };
    let mut ray = DerRay::new(&dir, &p).unwrap();
    ray.evaluate(6.0).unwrap();
    ray
}

fn kernels(c: &mut Criterion) {
    let mut g = c.benchmark_group("rod_kernels");
    for n in [50usize, 100, 200] {
        let ray = equilibrium(n);
        let rod = ray.rod().clone();
        let st = ray.state().unwrap().clone();
        let mut ws = Workspace::new(&rod);
        g.bench_with_input(BenchmarkId::new("assemble_e_g_h", n), &n, |b, _| {
            b.iter(|| {
                black_box(energy::energy_gradient_hessian(
                    &rod,
                    &st,
                    &mut ws.grad,
                    &mut ws.hess,
                ))
            })
        });
        energy::hessian(&rod, &st, &mut ws.hess);
        let free = rod.free_range_clamped();
        g.bench_with_input(BenchmarkId::new("banded_ldlt_factor", n), &n, |b, _| {
            b.iter(|| {
                ws.ldlt.factor(&ws.hess, free.clone()).unwrap();
                black_box(ws.ldlt.inertia())
            })
        });
    }
    g.finish();
}

fn boundary(c: &mut Criterion) {
    let mut g = c.benchmark_group("der_boundary_per_direction");
    g.sample_size(10);
    // Four fixed directions of a Fibonacci set (seeded by construction), cycled.
    let dirs = fibonacci(24, false).unwrap();
    let picks = [dirs[6], dirs[10], dirs[15], dirs[20]];
    for n in [25usize, 50, 100, 200] {
        let p = DerBoundaryParams {
            n_edges: n,
            tol_rel: 1e-7,
            ..Default::default()
        };
        let mut k = 0;
        g.bench_with_input(BenchmarkId::new("critical_s", n), &n, |b, _| {
            b.iter(|| {
                k = (k + 1) % picks.len();
                black_box(critical_s(&picks[k], &p).unwrap())
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    // No plots: the plotters backend needs a system font the build machines lack.
    config = Criterion::default().without_plots();
    targets = kernels, boundary
}
criterion_main!(benches);
