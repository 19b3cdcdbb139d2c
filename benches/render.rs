//! Criterion benchmarks of `render`, on this thread's CPU time (the meaningful figure
//! on the shared machine): the three stages of one GIF frame of the seed ray at the seed's
//! density (2,000 waypoints), default GIF options (four views of 330 × 320 px):
//! posing a row (FK, clearances, their points), drawing it into an RGB buffer, and reducing it
//! to a GIF palette + LZW (`palette::reduce`), with NeuQuant (speed 10, plotters' GIF backend's
//! quantizer) as the peer. A 100-frame GIF costs about 100 × the sum of the stages, split over
//! the cores (frames are drawn and encoded in parallel), plus writing.
//!
//! Run: `cargo bench --bench render`.
use criterion::{criterion_group, criterion_main, Criterion};
use helixreach::directions::Direction;
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::plot::render::{
    palette, render_rgb, Arrangement, Configuration, Layout, Scene, TrajectoryRender,
};
use std::hint::black_box;

#[path = "common/cpu_time.rs"]
mod cpu_time;

fn bench_frame(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.waypoints = 2000;
    let planner = Planner::new(rig.clone()).unwrap();
    let d = Direction::new(0.3, 0.9, 0.3).unwrap();
    let s_star = helixreach::boundary::continuum::critical_s(&d, 1e-10)
        .unwrap()
        .s_star;
    let plan = planner
        .plan_ray(&d, s_star, 0.0, RollMode::Fixed, true)
        .unwrap();
    let traj = planner.trajectory(&plan).unwrap();
    assert!(traj.points.len() >= 2000);
    let scene = Scene::new(&rig).unwrap();
    let configs: Vec<Configuration> = (0..100)
        .map(|k| {
            let p = &traj.points[k * (traj.points.len() - 1) / 99];
            Configuration {
                q: p.q.clone(),
                kto: p.kto,
                azimuth: 0.0,
            }
        })
        .collect();
    let snaps: Vec<_> = configs.iter().map(|c| scene.snapshot(c).unwrap()).collect();
    let opts = TrajectoryRender::default().gif;
    let layout = Layout::new(&snaps, &opts, Arrangement::Row).unwrap();
    let (w, h) = layout.size();
    let rgb = render_rgb(&scene, &snaps[50], &layout, &opts).unwrap();

    let mut g = c.benchmark_group("gif_frame");
    g.sample_size(10);
    let mut k = 0;
    g.bench_function("pose_row", |b| {
        b.iter(|| {
            k = (k + 1) % configs.len();
            black_box(scene.snapshot(&configs[k]).unwrap())
        })
    });
    g.bench_function("draw_rgb", |b| {
        b.iter(|| {
            k = (k + 1) % snaps.len();
            black_box(render_rgb(&scene, &snaps[k], &layout, &opts).unwrap())
        })
    });
    g.bench_function("palette_and_lzw", |b| {
        b.iter(|| {
            let (pal, idx) = palette::reduce(&rgb);
            let mut f = gif::Frame::from_palette_pixels(w as u16, h as u16, idx, pal, None);
            f.make_lzw_pre_encoded();
            black_box(f)
        })
    });
    // The peer: NeuQuant at speed 10, as plotters' GIF backend quantizes (LZW not included).
    g.bench_function("neuquant_peer", |b| {
        b.iter(|| black_box(gif::Frame::from_rgb_speed(w as u16, h as u16, &rgb, 10)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(cpu_time::ThreadCpuTime).without_plots();
    targets = bench_frame
}
criterion_main!(benches);
