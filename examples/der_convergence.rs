//! Speed versus error of the DER-statics boundary on a Fibonacci half-sphere of directions: for
//! each resolution n the time per direction (single-thread CPU time) and the max/median relative
//! error of s* against the continuum reference (tolerance 1e-10), with the worst direction named;
//! the Richardson extrapolation `(4·s*_{2m} − s*_m)/3` of consecutive resolutions; and the
//! number of directions on which the error does not decrease from n to 2n (order 2 requires 0).
//!
//! ```text
//! cargo run --release --example der_convergence -- [N_DIRECTIONS] [OUT.csv] [NS] [TOL]
//! ```
//! Defaults: 24 directions, `target/der_convergence.csv`, NS = `25,50,100,200`, TOL = 1e-8 (the
//! DER root tolerance, relative). The summary CSV has the columns
//! `method,resolution,time_per_direction_s,max_rel_err,median_rel_err,worst_direction,failures,not_decreasing`
//! (one row per resolution and Richardson pair); `OUT` with `.csv` replaced by
//! `_per_direction.csv` holds every direction's s* (reference and each n). The markdown table goes
//! to stdout, progress to stderr.
//!
//! Directions run in parallel (rayon); each solve is timed with its own thread's CPU time
//! (`/proc/thread-self/schedstat`), so the time per direction is single-thread CPU time even on a
//! shared machine. A failed solve or a non-finite s* where the reference is finite counts as an
//! infinite error and is named (never skipped). The DER search is seeded by the continuum s*
//! (the default; the seed's cost is included).

use helixreach::boundary::continuum;
use helixreach::boundary::der::{critical_s, DerBoundaryParams};
use helixreach::directions::{fibonacci, Direction};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Largest direction count accepted (the paper's lattice has 58,352).
const MAX_DIRECTIONS: usize = 100_000;
/// Largest n accepted.
const MAX_EDGES: usize = 2_000;

/// CPU time of the calling thread in seconds (Linux), wall time elsewhere.
fn thread_cpu_seconds(fallback: &Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .map(|ns| ns * 1e-9)
        .unwrap_or_else(|| fallback.elapsed().as_secs_f64())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len();
    if m == 0 {
        return f64::NAN;
    }
    if m % 2 == 1 {
        v[m / 2]
    } else {
        0.5 * (v[m / 2 - 1] + v[m / 2])
    }
}

fn rel_err(x: f64, r: f64) -> f64 {
    if x == r {
        0.0
    } else if x.is_finite() && r.is_finite() {
        ((x - r) / r).abs()
    } else {
        f64::INFINITY
    }
}

fn name(d: &Direction) -> String {
    format!("({:.4}, {:.4}, {:.4})", d.kappa, d.tau, d.omega)
}

struct Row {
    method: String,
    resolution: String,
    time: f64,
    errs: Vec<f64>,
    failures: usize,
    not_decreasing: Option<usize>,
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let nd: usize = args.get(1).map(|a| a.parse()).transpose()?.unwrap_or(24);
    if nd == 0 || nd > MAX_DIRECTIONS {
        anyhow::bail!("N_DIRECTIONS = {nd}: must be in 1..={MAX_DIRECTIONS}");
    }
    let out = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| "target/der_convergence.csv".into());
    let ns: Vec<usize> = match args.get(3) {
        Some(a) => a
            .split(',')
            .map(|x| x.trim().parse::<usize>())
            .collect::<Result<_, _>>()?,
        None => vec![25, 50, 100, 200],
    };
    if ns.is_empty() || ns.iter().any(|&n| !(4..=MAX_EDGES).contains(&n)) {
        anyhow::bail!("NS = {ns:?}: every n must be in 4..={MAX_EDGES}");
    }
    let tol: f64 = args.get(4).map(|a| a.parse()).transpose()?.unwrap_or(1e-8);
    if !(tol > 0.0 && tol < 0.5) {
        anyhow::bail!("TOL = {tol}: must be in (0, 0.5)");
    }
    let dirs = fibonacci(nd, false)?;
    eprintln!("reference: continuum conjugate points (tol 1e-10) on {nd} directions …");
    let reference: Vec<f64> = dirs
        .par_iter()
        .map(|d| {
            continuum::critical_s(d, 1e-10)
                .map(|c| c.s_star)
                .unwrap_or(f64::NAN)
        })
        .collect();
    let mut rows: Vec<Row> = Vec::new();
    let mut solved: Vec<(usize, Vec<f64>, f64)> = Vec::new();
    for &n in &ns {
        let p = DerBoundaryParams {
            n_edges: n,
            tol_rel: tol,
            ..Default::default()
        };
        let done = AtomicUsize::new(0);
        let wall = Instant::now();
        let res: Vec<(f64, f64)> = dirs
            .par_iter()
            .map(|d| {
                let t0 = Instant::now();
                let c0 = thread_cpu_seconds(&t0);
                let s = match critical_s(d, &p) {
                    Ok(c) => c.s_star,
                    Err(e) => {
                        eprintln!("  n = {n}: {}: {e}", name(d));
                        f64::NAN
                    }
                };
                let dt = thread_cpu_seconds(&t0) - c0;
                let k = done.fetch_add(1, Ordering::Relaxed) + 1;
                if k % (nd / 10).max(1) == 0 || k == nd {
                    eprintln!(
                        "  n = {n}: {k}/{nd} directions ({:.0} s)",
                        wall.elapsed().as_secs_f64()
                    );
                }
                (s, dt)
            })
            .collect();
        let s: Vec<f64> = res.iter().map(|r| r.0).collect();
        let time = res.iter().map(|r| r.1).sum::<f64>() / nd as f64;
        let errs: Vec<f64> = s
            .iter()
            .zip(&reference)
            .map(|(&x, &r)| rel_err(x, r))
            .collect();
        let failures = s.iter().filter(|x| x.is_nan()).count();
        let not_decreasing = solved.last().map(|(_, prev, _)| {
            prev.iter()
                .zip(&s)
                .zip(&reference)
                .filter(|((a, b), r)| {
                    rel_err(**b, **r) >= rel_err(**a, **r) && rel_err(**a, **r) > 0.0
                })
                .count()
        });
        rows.push(Row {
            method: "der-statics".into(),
            resolution: n.to_string(),
            time,
            errs,
            failures,
            not_decreasing,
        });
        solved.push((n, s, time));
    }
    for w in solved.windows(2) {
        let (m, n2) = (w[0].0, w[1].0);
        let errs: Vec<f64> = w[0]
            .1
            .iter()
            .zip(&w[1].1)
            .zip(&reference)
            .map(|((a, b), r)| rel_err((4.0 * b - a) / 3.0, *r))
            .collect();
        rows.push(Row {
            method: "der-statics-richardson".into(),
            resolution: format!("{m}+{n2}"),
            time: w[0].2 + w[1].2,
            errs,
            failures: 0,
            not_decreasing: None,
        });
    }
    let mut csv = String::from(
        "method,resolution,time_per_direction_s,max_rel_err,median_rel_err,worst_direction,failures,not_decreasing\n",
    );
    println!("DER statics vs continuum (tol 1e-10) on the {nd}-direction Fibonacci half-sphere, DER tol {tol:e}:");
    println!("| method | n | CPU time per direction | max rel. error | worst direction | median rel. error | failed | err(2n) ≥ err(n) |");
    println!("|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let (imax, max) =
            r.errs.iter().enumerate().fold(
                (0, 0.0_f64),
                |(bi, b), (i, &e)| if e > b { (i, e) } else { (bi, b) },
            );
        let med = median(&mut r.errs.clone());
        let worst = name(&dirs[imax]);
        let nd_txt = r
            .not_decreasing
            .map(|k| k.to_string())
            .unwrap_or_else(|| "–".into());
        println!(
            "| {} | {} | {:.2} ms | {max:.2e} | {worst} | {med:.2e} | {} | {nd_txt} |",
            r.method,
            r.resolution,
            r.time * 1e3,
            r.failures
        );
        csv.push_str(&format!(
            "{},{},{:.6e},{max:.6e},{med:.6e},\"{worst}\",{},{nd_txt}\n",
            r.method, r.resolution, r.time, r.failures
        ));
    }
    helixreach::io::write_atomic(std::path::Path::new(&out), csv.as_bytes())?;
    let mut per = String::from("dir_kappa,dir_tau,dir_omega,s_star_continuum");
    for (n, _, _) in &solved {
        per.push_str(&format!(",s_star_der_{n}"));
    }
    per.push('\n');
    for (i, d) in dirs.iter().enumerate() {
        per.push_str(&format!(
            "{},{},{},{}",
            d.kappa, d.tau, d.omega, reference[i]
        ));
        for (_, s, _) in &solved {
            per.push_str(&format!(",{}", s[i]));
        }
        per.push('\n');
    }
    let per_path = out.trim_end_matches(".csv").to_string() + "_per_direction.csv";
    helixreach::io::write_atomic(std::path::Path::new(&per_path), per.as_bytes())?;
    eprintln!("wrote {out} and {per_path}");
    Ok(())
}
