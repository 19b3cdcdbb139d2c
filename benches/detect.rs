//! Criterion benchmark of `detect` on one recorded run of the seed (goal ≤ 50 ms CPU for
//! ≈ 4,000 samples).
//!
//! Input: `tests/data/seed_observations/test_c1_0.75_c2_0.txt.gz` (4,510 samples: 7 joints and a
//! marker each), decompressed outside the timed loop. Timed: parsing the text and the whole
//! detection with the clamp given (FK, projection, extrinsics and arc-length fit, e, jump), and
//! the same with the clamp fitted from the joints. Measured with the thread's CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`), the meaningful figure on a shared machine.
//!
//! Run: `cargo bench --bench detect`.

#[path = "common/cpu_time.rs"]
mod cpu_time;

use cpu_time::ThreadCpuTime;
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::detect::{DetectOptions, Detector};
use helixreach::directions::Direction;
use helixreach::planning::rig::Rig;
use helixreach::records::detect::parse_observations;
use std::hint::black_box;
use std::io::Read;
use std::path::Path;

fn detect_run(c: &mut Criterion<ThreadCpuTime>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/seed_observations/test_c1_0.75_c2_0.txt.gz");
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(&path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let det = Detector::new(Rig::load("sawyer-seed").unwrap(), DetectOptions::default()).unwrap();
    let dir = Direction::new(0.8, 0.6, 0.0).unwrap();
    let clamp = [0.85, -0.15, -0.146];
    let mut g = c.benchmark_group("detect_cpu");
    g.sample_size(20);
    g.bench_function("run_4510_samples_clamp_given", |b| {
        b.iter(|| {
            let obs = parse_observations(black_box(&text), &path, 7).unwrap();
            black_box(det.detect(&obs, &dir, Some(clamp)).unwrap())
        })
    });
    g.bench_function("run_4510_samples_clamp_fitted", |b| {
        b.iter(|| {
            let obs = parse_observations(black_box(&text), &path, 7).unwrap();
            black_box(det.detect(&obs, &dir, None).unwrap())
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpuTime);
    targets = detect_run
}
criterion_main!(benches);
