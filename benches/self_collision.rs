//! Self-collision check per configuration (FK of every link, posing, then the first-hit walk
//! over the self pairs), on the vendored mesh arms under each collision model (`hull`,
//! `primitives`, `primitives_then_hull`) and on the built-in Sawyer's hand-written capsules.
//! Two sets of 1,024 seeded random in-limit configurations per robot, cycled:
//! - `self_collision_random`: as drawn (some in contact, which ends the walk at the first hit);
//! - `self_collision_free`: only configurations free under the arm's `hull` model (the same
//!   configurations for the three models; under `hull` and `primitives_then_hull` every pair is
//!   walked, the cost of a free configuration, the common case along a planned path; the
//!   `primitives` model may still stop at a capsule contact that the hulls do not have).
//!
//! Pairs as the planner checks them: the robot's own never-colliding list (none for the
//! vendored arms: every pair not joined by a joint), except for an arm some of whose link pairs
//! always overlap (Baxter's shoulder covers and its torso): no configuration of it is free
//! without the list that `helixreach robot --write-disabled` computes, so that list
//! (`DisabledPairs::compute`, 10,000 samples) is used for it.
//!
//! Times are this thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`).
//!
//! Run: `cargo bench --bench self_collision`

#[path = "common/cpu_time.rs"]
mod cpu_time;
#[path = "../tests/common/robots.rs"]
mod robots;

use cpu_time::ThreadCpuTime;
use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::limits::MIN_DISABLED_SAMPLES;
use helixreach::robot::collision::{CollisionKind, CollisionSettings};
use helixreach::robot::{CollisionModel, DisabledPairs, RobotModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

/// 1,024 random configurations (only those `cm` finds free if `free`).
fn configs(m: &RobotModel, cm: &CollisionModel, free: bool) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut ws = cm.workspace();
    let mut out = Vec::new();
    for _ in 0..10_000_000 {
        if out.len() == 1024 {
            return out;
        }
        let q = m.random_config(&mut rng)[..m.dof()].to_vec();
        if !free || cm.check(&q, &mut ws, None).is_none() {
            out.push(q);
        }
    }
    panic!("fewer than 1024 free configurations in 10 million draws");
}

/// Whether any of 10,000 random configurations is free under `cm`.
fn any_free(m: &RobotModel, cm: &CollisionModel) -> bool {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut ws = cm.workspace();
    (0..10_000).any(|_| {
        let q = m.random_config(&mut rng)[..m.dof()].to_vec();
        cm.check(&q, &mut ws, None).is_none()
    })
}

fn bench_model<M: Measurement>(
    g: &mut criterion::BenchmarkGroup<'_, M>,
    name: &str,
    qs: &[Vec<f64>],
    cm: &CollisionModel,
) {
    let mut ws = cm.workspace();
    let mut i = 0;
    g.bench_function(name, |b| {
        b.iter(|| {
            i = (i + 1) & 1023;
            black_box(cm.check(black_box(&qs[i]), &mut ws, None))
        })
    });
}

fn self_collision<M: Measurement>(c: &mut Criterion<M>) {
    for (group, free) in [
        ("self_collision_random", false),
        ("self_collision_free", true),
    ] {
        let mut g = c.benchmark_group(group);
        models(&mut g, free);
        g.finish();
    }
}

fn models<M: Measurement>(g: &mut criterion::BenchmarkGroup<'_, M>, free: bool) {
    for arm in &robots::ARMS {
        let m = robots::load(arm);
        let mut disabled = DisabledPairs::for_model(&m).unwrap();
        if !any_free(&m, &CollisionModel::new(&m, &disabled, &[]).unwrap()) {
            disabled = DisabledPairs::compute(&m, MIN_DISABLED_SAMPLES, 4).unwrap();
        }
        let model = |kind| {
            CollisionModel::with_settings(
                &m,
                &disabled,
                &[],
                &CollisionSettings {
                    kind,
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let qs = configs(&m, &model(CollisionKind::Hull), free);
        for kind in CollisionKind::ALL {
            let name = format!("{}/{}", arm.name, kind.name());
            bench_model(g, &name, &qs, &model(kind));
        }
    }
    let sawyer = RobotModel::load("sawyer", None).unwrap();
    let cm = CollisionModel::for_model(&sawyer).unwrap();
    let qs = configs(&sawyer, &cm, free);
    bench_model(g, "sawyer/builtin_capsules", &qs, &cm);
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpuTime);
    targets = self_collision
}
criterion_main!(benches);
