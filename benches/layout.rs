//! Layout speed: 200 candidate clamp placements × 173 directions on the seed rig (issue 11's
//! target: ≤ 5 min on 2 cores), and the fraction of rays decided by the cheap checks.
//!
//! Not a criterion loop (one run is minutes): the whole layout runs once on a rayon pool of
//! `HELIXREACH_BENCH_THREADS` threads (default 2) and the bench prints the wall time and the
//! process CPU time (`CLOCK_PROCESS_CPUTIME_ID`, all threads; on a loaded machine the figure to
//! compare: CPU / 2 is the wall time two idle cores would need). `HELIXREACH_BENCH_QUICK=1`
//! runs 20 × 17 instead.
//!
//! Candidates: x 0.55 … 1.00 m (10), y −0.45 … 0.50 m (20) at the seed clamp's height; the
//! 173-direction quarter-sphere Fibonacci lattice.
//!
//! Run: `cargo bench --bench layout`.

use helixreach::directions::fibonacci;
use helixreach::layout::{run, LayoutOptions, RunControl};
use helixreach::planning::rig::Rig;

/// Process CPU time (s) of all threads.
fn process_cpu_s() -> f64 {
    helixreach::cpu_time::process_cpu_seconds().expect("process CPU clock")
}

fn main() {
    let quick = std::env::var("HELIXREACH_BENCH_QUICK").is_ok_and(|v| v == "1");
    let threads: usize = std::env::var("HELIXREACH_BENCH_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2);
    let rig = Rig::load("sawyer-seed").expect("embedded rig");
    let mut opts = LayoutOptions::around(&rig);
    let (region, n_dirs) = if quick {
        ("0.75:0.95,-0.3:0.15,-0.144:-0.144", 17)
    } else {
        ("0.55:1.0,-0.45:0.5,-0.144:-0.144", 173)
    };
    opts.region = region.parse().expect("region");
    opts.spacing = 0.05;
    opts.placements = 3;
    let dirs = fibonacci(n_dirs, true).expect("directions");
    let tmp = tempfile::tempdir().expect("tempdir");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    let (c0, t0) = (process_cpu_s(), std::time::Instant::now());
    let rep = pool
        .install(|| run(&rig, &dirs, None, &opts, &RunControl::default(), tmp.path()))
        .expect("layout")
        .expect("not sharded");
    let (cpu, wall) = (process_cpu_s() - c0, t0.elapsed().as_secs_f64());
    let rays = rep.candidates.len() * rep.n_dirs;
    println!(
        "layout bench: {} candidates × {} directions = {rays} rays on {threads} threads",
        rep.candidates.len(),
        rep.n_dirs
    );
    println!(
        "  wall {wall:.1} s, process CPU {cpu:.1} s ({:.2} ms CPU per ray; CPU/2 = {:.1} s)",
        1e3 * cpu / rays as f64,
        cpu / 2.0
    );
    println!(
        "  decided without per-ray planning: {:.1} % ({:?})",
        100.0 * rep.cheap_fraction(),
        rep.decided
    );
    for c in &rep.by_k {
        println!(
            "  K = {}: exact {} (proven {}), greedy {}",
            c.k, c.exact.covered, c.exact.proven, c.greedy.covered
        );
    }
}
