//! Criterion benchmarks of the continuum boundary: one direction at several tolerances, and a
//! 1000-direction Fibonacci batch (sequential). The full 58,352-direction timing and the
//! speed-versus-error table are produced by the CLI (see the README):
//! `helixreach boundary --method continuum --fibonacci 58352 --tol 1e-8 --out /tmp/b.csv` and
//! `helixreach boundary --method continuum --fibonacci 2000 --speed-report speed.csv`.
//! The DER peer runs in its own group, measured in thread CPU time.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

#[path = "common/cpu_time.rs"]
mod cpu_time;

use helixreach::boundary::continuum::critical_s;
use helixreach::directions::{fibonacci, Direction};
use std::hint::black_box;

fn one_direction(c: &mut Criterion) {
    // The paper's example direction (its Fig. 2b) and the diagonal of its Fig. 2c.
    let dirs = [
        ("fig2b", Direction::new(0.594, 0.698, 0.4).unwrap()),
        ("fig2c", Direction::new(1.0, 1.0, -1.0).unwrap()),
    ];
    let mut g = c.benchmark_group("continuum_critical_s");
    for (name, d) in dirs {
        for tol in [1e-4, 1e-8, 1e-12] {
            g.bench_with_input(BenchmarkId::new(name, tol), &tol, |b, &tol| {
                b.iter(|| critical_s(black_box(&d), tol).unwrap())
            });
        }
    }
    g.finish();
}

/// The peer: DER statics at n = 100 on the same direction, in thread CPU time
/// (`common/cpu_time.rs`: the number is single-thread CPU even on a loaded machine), at tol 1e-6
/// and at the default 1e-8 (the README's DER table uses 1e-8), so the continuum/DER ratio and
/// the goal of ≤ 5 ms per direction can be read off directly.
fn der_peer(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    use helixreach::boundary::der;
    let d = Direction::new(0.594, 0.698, 0.4).unwrap();
    let mut g = c.benchmark_group("der_critical_s");
    g.sample_size(10);
    for tol in [1e-6, 1e-8] {
        let p = der::DerBoundaryParams {
            n_edges: 100,
            tol_rel: tol,
            ..Default::default()
        };
        g.bench_function(format!("fig2b/n100_tol{tol:e}"), |b| {
            b.iter(|| der::critical_s(black_box(&d), &p).unwrap())
        });
    }
    g.finish();
}

fn lattice(c: &mut Criterion) {
    let dirs = fibonacci(1000, false).unwrap();
    let mut g = c.benchmark_group("continuum_lattice");
    g.sample_size(10);
    g.bench_function("fibonacci_1000_tol1e-8_sequential", |b| {
        b.iter(|| {
            dirs.iter()
                .map(|d| critical_s(d, 1e-8).unwrap().s_star)
                .filter(|s| s.is_finite())
                .sum::<f64>()
        })
    });
    g.finish();
}

// Plots off: criterion's plotters backend panics when no system font is available.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = one_direction, lattice
}
criterion_group! {
    name = der_benches;
    config = Criterion::default().without_plots().with_measurement(cpu_time::ThreadCpuTime);
    targets = der_peer
}
criterion_main!(benches, der_benches);
