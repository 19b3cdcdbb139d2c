//! Criterion benchmarks of the planner (issue 6): one ray of the seed rig at the seed's density
//! (2,000 waypoints uniform in s) and at the adaptive default (5 mm / 2°), collision checks
//! included. The peer, Descartes (10.4 s for 1,200 points, published), builds every rung from
//! fresh IK solutions; the same run times that rung construction here (`solve_all` with j0
//! sampled + collision checks, per waypoint, no graph search) so the per-waypoint ratio of the
//! two schemes is measured, not quoted. The start rung is computed once per planner (it is
//! shared by every ray) and excluded.
//!
//! Run: `cargo bench --bench planning`.
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::directions::Direction;
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use std::hint::black_box;

fn planner(waypoints: usize) -> Planner {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.waypoints = waypoints;
    Planner::new(rig).unwrap()
}

fn bench_ray(c: &mut Criterion) {
    // A ray of the experiment's quarter-sphere that the seed rig can test.
    let d = Direction::new(0.3, 0.9, 0.3).unwrap();
    let s_star = helixreach::boundary::continuum::critical_s(&d, 1e-10)
        .unwrap()
        .s_star;
    let mut g = c.benchmark_group("plan_one_ray");
    g.sample_size(10);
    for (name, n) in [("seed_density_2000", 2000), ("adaptive_default", 0)] {
        let p = planner(n);
        let plan = p.plan_ray(&d, s_star, 0.0, RollMode::Fixed, false).unwrap();
        eprintln!(
            "{name}: {} waypoints, class {}, max joint step {:.4}",
            plan.n_waypoints,
            plan.class.as_str(),
            plan.max_joint_step
        );
        g.bench_function(name, |b| {
            b.iter(|| black_box(p.plan_ray(&d, s_star, 0.0, RollMode::Fixed, true).unwrap()))
        });
    }
    // Descartes-like rungs: fresh IK at each waypoint (j0 sampled at 8 values, 50 restarts).
    let p = planner(0);
    let rig = p.rig();
    let ray = helixreach::planning::pose_path::Ray {
        dir: [d.kappa, d.tau, d.omega],
        azimuth: 0.0,
    };
    let wps = helixreach::planning::pose_path::pose_path(
        rig,
        &ray,
        s_star * 1.1,
        &helixreach::planning::pose_path::Spacing::of(rig),
    )
    .unwrap();
    let solver =
        helixreach::robot::IkSolver::new(p.model(), helixreach::robot::IkParams::default())
            .unwrap();
    let mut ws = p.collision().workspace();
    let picks: Vec<_> = wps.iter().step_by((wps.len() / 20).max(1)).collect();
    g.bench_function("descartes_like_fresh_rungs_20_waypoints", |b| {
        b.iter(|| {
            let mut n = 0usize;
            for w in &picks {
                let t = helixreach::robot::IkTarget::Pose(p.tip_target(&w.tool));
                for s in solver.solve_all(&t, &[]) {
                    n += usize::from(p.collision().check(s.joints(), &mut ws, None).is_none());
                }
            }
            black_box(n)
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench_ray
}
criterion_main!(benches);
