//! Layout speed: 200 candidate clamp placements × 173 directions on the seed rig (goal:
//! ≤ 5 min on 2 cores), and the fraction of rays decided by the cheap checks.
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
//!
//! **Sample mode** (`HELIXREACH_BENCH_SAMPLE=23,67,105,149,186`: candidate indices of the full
//! grid): instead of the whole layout, the listed placements' rays one by one on this thread,
//! each timed in thread CPU time, with the placement kind of every one of the 200 candidates
//! (the once-per-placement start rung, also timed). Prints CPU per ray by how it was decided
//! (cheap check or planner, class, cause) and the extrapolation to the whole 200 × 173 grid:
//! (placements with a start) × (their mean CPU in the sample) + the measured cost of the others.

use helixreach::directions::fibonacci;
use helixreach::layout::candidates::grid;
use helixreach::layout::evaluate::{PlacementKind, Sweep};
use helixreach::layout::{run, LayoutOptions, RunControl};
use helixreach::planning::rig::Rig;
use std::collections::BTreeMap;

/// Process CPU time (s) of all threads.
fn process_cpu_s() -> f64 {
    helixreach::cpu_time::process_cpu_seconds().expect("process CPU clock")
}

/// This thread's CPU time (s).
fn thread_cpu_s() -> f64 {
    helixreach::cpu_time::thread_cpu_seconds().expect("thread CPU clock")
}

/// Sample mode (module docs): per-ray thread CPU on the listed candidates of the full grid.
fn sample(rig: &Rig, opts: &LayoutOptions, n_dirs: usize, picks: &[usize]) {
    let cands = grid(&opts.region, opts.spacing, &opts.tilts_deg, opts.headings).expect("grid");
    let dirs = fibonacci(n_dirs, true).expect("directions");
    let sweep = Sweep::new(
        helixreach::par::Par::all(),
        rig,
        &cands,
        &dirs,
        None,
        rig.roll,
        rig.azimuths.clone(),
    )
    .expect("sweep");
    // Placement kinds of the whole grid (start rungs, once each), timed.
    let mut kinds: BTreeMap<String, (usize, f64)> = BTreeMap::new();
    for c in 0..cands.len() {
        let t = thread_cpu_s();
        let k = sweep.placement_kind(c).expect("placement");
        let e = kinds.entry(format!("{k:?}")).or_default();
        e.0 += 1;
        e.1 += thread_cpu_s() - t;
    }
    println!(
        "layout sample: {} candidates × {} directions; placement kinds (count, start-rung CPU s):",
        cands.len(),
        dirs.len()
    );
    for (k, (n, cpu)) in &kinds {
        println!("  {k}: {n} placements, {cpu:.2} s CPU");
    }
    // Per-ray CPU on the picked candidates, by (decided_by, class, cause).
    let mut by: BTreeMap<(String, String, String), (usize, f64)> = BTreeMap::new();
    let (mut ready_cpu, mut ready_n) = (0.0, 0usize);
    for &c in picks {
        assert!(c < cands.len(), "candidate {c} not in the grid");
        let kind = sweep.placement_kind(c).expect("placement");
        let t0 = thread_cpu_s();
        for d in 0..dirs.len() {
            let t = thread_cpu_s();
            let row = sweep.row(&(c, d)).expect("row");
            let dt = thread_cpu_s() - t;
            let e = by
                .entry((
                    row.decided_by.to_string(),
                    row.class.to_string(),
                    row.cause.to_string(),
                ))
                .or_default();
            e.0 += 1;
            e.1 += dt;
        }
        let cpu = thread_cpu_s() - t0;
        let o = cands[c].origin;
        println!(
            "  candidate {c} ({:.2}, {:.2}, {:.3}) {kind:?}: {cpu:.1} s CPU for {} rays",
            o[0],
            o[1],
            o[2],
            dirs.len()
        );
        if kind == PlacementKind::Ready {
            ready_cpu += cpu;
            ready_n += 1;
        }
    }
    println!("  rays by (decided_by, class, cause): count, CPU s, mean ms");
    let (mut n_all, mut n_cheap, mut cpu_all) = (0usize, 0usize, 0.0);
    for ((by_, class, cause), (n, cpu)) in &by {
        println!(
            "    {by_:<10} {class:<11} {cause:<16} {n:>5} {cpu:>8.1} {:>8.1}",
            1e3 * cpu / *n as f64
        );
        n_all += n;
        cpu_all += cpu;
        if by_ != "planner" {
            n_cheap += n;
        }
    }
    println!(
        "  sample: {n_all} rays, {cpu_all:.1} s CPU ({:.0} ms per ray), {:.1} % decided by cheap checks",
        1e3 * cpu_all / n_all.max(1) as f64,
        100.0 * n_cheap as f64 / n_all.max(1) as f64
    );
    if ready_n > 0 {
        let n_ready = kinds.get("Ready").map_or(0, |e| e.0);
        let per = ready_cpu / ready_n as f64;
        let other: f64 = kinds
            .iter()
            .filter(|(k, _)| *k != "Ready")
            .map(|(_, e)| e.1)
            .sum();
        let total = n_ready as f64 * per + kinds.values().map(|e| e.1).sum::<f64>();
        println!(
            "  extrapolated: {n_ready} placements with a start × {per:.1} s (sample mean of {ready_n}) \
             + start rungs {:.1} s (of which {other:.1} s for the {} without) = {total:.0} s CPU \
             ({:.1} min on 2 idle cores)",
            kinds.values().map(|e| e.1).sum::<f64>(),
            cands.len() - n_ready,
            total / 120.0
        );
    }
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
    if let Ok(list) = std::env::var("HELIXREACH_BENCH_SAMPLE") {
        let picks: Vec<usize> = list
            .split(',')
            .map(|t| {
                t.trim()
                    .parse()
                    .expect("HELIXREACH_BENCH_SAMPLE: candidate indices")
            })
            .collect();
        sample(&rig, &opts, n_dirs, &picks);
        return;
    }
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
