//! The cost of the bifurcation type against the cost of s* itself, on the same directions in
//! the same run, in thread CPU time (`common/cpu_time.rs`): DER statics at n = 100,
//! - `critical_s`: the DER s* alone (`boundary::der::critical_s`, tol 1e-7);
//! - `type`: s* plus the Koiter reduction (`bifurcation::classify` without the unloading);
//! - `type_and_return`: plus the static return point of the subcritical ray.
//!
//! `cargo bench --bench bifurcation`; the ratio type/critical_s is the figure of merit.
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::bifurcation::{classify, BifurcationParams};
use helixreach::boundary::der::{critical_s, DerBoundaryParams};
use helixreach::directions::Direction;
use std::hint::black_box;

#[path = "common/cpu_time.rs"]
mod cpu_time;

fn bench(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    // A subcritical and a supercritical direction of the seed's labelled runs.
    let dirs = [
        (
            "subcritical",
            Direction::new(0.838444, 0.544988, 0.0).unwrap(),
        ),
        (
            "supercritical",
            Direction::new(0.957826, 0.287348, 0.0).unwrap(),
        ),
    ];
    let der = DerBoundaryParams {
        n_edges: 100,
        tol_rel: 1e-7,
        ..DerBoundaryParams::default()
    };
    let typ = BifurcationParams {
        der,
        statics_return: false,
        ..BifurcationParams::default()
    };
    let full = BifurcationParams {
        der,
        ..BifurcationParams::default()
    };
    let mut g = c.benchmark_group("bifurcation_n100");
    g.sample_size(10);
    for (name, d) in dirs {
        g.bench_function(format!("{name}/critical_s"), |b| {
            b.iter(|| critical_s(black_box(&d), &der).unwrap())
        });
        g.bench_function(format!("{name}/type"), |b| {
            b.iter(|| classify(black_box(&d), &typ).unwrap())
        });
        if name == "subcritical" {
            g.bench_function(format!("{name}/type_and_return"), |b| {
                b.iter(|| classify(black_box(&d), &full).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    // No plots: the plotters backend needs a system font the CI image lacks.
    config = Criterion::default().without_plots().with_measurement(cpu_time::ThreadCpuTime);
    targets = bench
}
criterion_main!(benches);
