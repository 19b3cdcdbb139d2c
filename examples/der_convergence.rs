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
//! `method,resolution,time_per_direction_s,evaluations,newton_iterations,solved,max_rel_err,worst_direction,median_rel_err,above_0.1pct,est_error_violations,not_decreasing,refused_kappa0,refused_resolution,refused_continuum_check,failed_solver,not_decreasing_above_floor`
//! (one row per resolution and Richardson pair); `OUT` with `.csv` replaced by
//! `_per_direction.csv` holds every direction's s* (reference and each n; empty where the
//! solve returned an error). The markdown table goes to stdout, progress to stderr.
//!
//! Columns: the time is the mean single-thread CPU time per direction (every direction, also
//! those that return an error), with the mean evaluations (Newton solves along the ray) and
//! Newton iterations; the errors are over the *solved* directions (an error returned is never a
//! number, and is counted by reason instead: the κ → 0 guard, the resolution guard, the check
//! against the continuum, a solver failure); `> 0.1 %` counts solved directions with a relative
//! error above 10⁻³; `est_error violated` counts solved directions whose |s* − reference|
//! exceeds the returned `est_error` (a truth defect: must be 0); `err(n) ≥ err(n/2)` counts the
//! directions solved at both resolutions whose error does not decrease, and in parentheses those
//! of them whose error at n/2 is above the noise floor of a DER s* (1e-5 relative, see
//! `NOISE_FLOOR`), where the comparison measures the discretization.
//!
//! Directions run in parallel (rayon); each solve is timed with its own thread's CPU time
//! ([`helixreach::cpu_time::thread_cpu_seconds`]), so the time per direction is single-thread
//! CPU time even on a shared machine. The DER search is seeded by the continuum s* (the
//! default; the seed's cost is included).

use helixreach::boundary::continuum;
use helixreach::boundary::der::{critical_s_with_work, rotation_per_edge, DerBoundaryParams};
use helixreach::directions::{fibonacci, Direction};
use helixreach::error::Error;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Largest direction count accepted (the paper's lattice has 58,352).
const MAX_DIRECTIONS: usize = 100_000;
/// Largest n accepted.
const MAX_EDGES: usize = 2_000;
/// The noise floor of a DER s* (relative): two valid searches of the same s* (with and without
/// the search's shortcuts, `boundary::der` "Continuation") differ by up to 2.5e-6 at n = 100
/// on the 2,000-direction half-sphere, two variants of the shortcuts by up to 1.5e-5 at
/// n = 200: the stability predicate's resolution (its Hessian holds stretching entries
/// k_s/ē ≈ 10¹⁰·n/100). An error below it does not measure the discretization, so
/// `err(n) ≥ err(n/2)` is also counted only where err(n/2) exceeds it.
const NOISE_FLOOR: f64 = 1e-5;

/// Why a direction returned no s* (the reasons the table counts).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Refusal {
    /// The κ → 0 extensibility guard.
    KappaZero,
    /// The resolution guard (too coarse n).
    Resolution,
    /// The check against the continuum (s* outside its est_error).
    ContinuumCheck,
    /// Any other error (Newton or continuation failure).
    Solver,
}

fn refusal(e: &Error) -> Refusal {
    let t = e.to_string();
    match e {
        Error::Inconsistent { .. } => Refusal::ContinuumCheck,
        Error::InvalidParameter { .. } if t.contains("kappa = 0 plane") => Refusal::KappaZero,
        Error::InvalidParameter { .. } if t.contains("too coarse") => Refusal::Resolution,
        _ => Refusal::Solver,
    }
}

/// One direction's outcome at one n.
#[derive(Clone, Copy)]
struct Solve {
    /// s* and est_error, or why none was returned.
    result: Result<(f64, f64), Refusal>,
    cpu: f64,
    evaluations: usize,
    iterations: usize,
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

/// One table row: per-direction relative errors (`None`: no s* returned).
struct Row {
    method: String,
    resolution: String,
    time: f64,
    evaluations: f64,
    iterations: f64,
    errs: Vec<Option<f64>>,
    violations: Option<usize>,
    not_decreasing: Option<usize>,
    /// Of `not_decreasing`, those with err(n/2) above [`NOISE_FLOOR`].
    not_decreasing_above_floor: Option<usize>,
    refused: Option<[usize; 4]>,
}

/// The n each direction needs for a relative error ≤ 0.1 %, extrapolated from its error at the
/// largest n with order 2 (`err ∝ 1/(n − 1)²`, the straddling clamps' `ē = 1/(n − 1)`), and the
/// edges per turn of the frames that is (turns = `rotation_per_edge·(n − 1)/2π` at the
/// continuum s*). Printed after the table; sound where the largest n is in the asymptotic
/// regime (the order-2 columns of the table say where it is).
fn resolution_needed(dirs: &[Direction], reference: &[f64], solved: &[(usize, Vec<Solve>, f64)]) {
    let Some((n, res, _)) = solved.last() else {
        return;
    };
    let c = helixreach::math::twist_ratio(DerBoundaryParams::default().nu).unwrap_or(f64::NAN);
    let mut need: Vec<(f64, f64, usize)> = Vec::new();
    for (i, x) in res.iter().enumerate() {
        if let (Ok((s, _)), r) = (x.result, reference[i]) {
            let e = rel_err(s, r);
            if e.is_finite() && r.is_finite() {
                let m = 1.0 + (*n as f64 - 1.0) * (e / 1e-3).sqrt();
                let phi = rotation_per_edge(&dirs[i], r, *n, c);
                let turns = phi * (*n as f64 - 1.0) / std::f64::consts::TAU;
                need.push((m.ceil(), (m - 1.0) / turns, i));
            }
        }
    }
    if need.is_empty() {
        return;
    }
    need.sort_by(|a, b| a.0.total_cmp(&b.0));
    let k = need.len();
    let over = |m: f64| need.iter().filter(|x| x.0 > m).count();
    let (m, per_turn, i) = need[k - 1];
    let per_max = need.iter().fold(0.0_f64, |a, x| a.max(x.1));
    println!(
        "Edges needed for ≤ 0.1 % (from err at n = {n}, order 2) over {k} directions: median {}, \
         99 % {}, max {m} at {} ({per_turn:.0} edges per turn of the frames there; max over all \
         directions {:.0}); directions needing n > 100: {}, > 200: {}",
        need[k / 2].0,
        need[(99 * k) / 100].0,
        name(&dirs[i]),
        per_max,
        over(100.0),
        over(200.0),
    );
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
    let mut solved: Vec<(usize, Vec<Solve>, f64)> = Vec::new();
    for &n in &ns {
        let p = DerBoundaryParams {
            n_edges: n,
            tol_rel: tol,
            ..Default::default()
        };
        let done = AtomicUsize::new(0);
        let wall = Instant::now();
        let res: Vec<Solve> = dirs
            .par_iter()
            .map(|d| {
                let c0 = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(f64::NAN);
                let (r, (evaluations, iterations)) = critical_s_with_work(d, &p);
                let cpu = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(f64::NAN) - c0;
                let result = match r {
                    Ok(c) => Ok((c.s_star, c.est_error)),
                    Err(e) => {
                        eprintln!("  n = {n}: {}: {e}", name(d));
                        Err(refusal(&e))
                    }
                };
                let k = done.fetch_add(1, Ordering::Relaxed) + 1;
                if k % (nd / 10).max(1) == 0 || k == nd {
                    eprintln!(
                        "  n = {n}: {k}/{nd} directions ({:.0} s)",
                        wall.elapsed().as_secs_f64()
                    );
                }
                Solve {
                    result,
                    cpu,
                    evaluations,
                    iterations,
                }
            })
            .collect();
        let mean = |f: &dyn Fn(&Solve) -> f64| res.iter().map(f).sum::<f64>() / nd as f64;
        let errs: Vec<Option<f64>> = res
            .iter()
            .zip(&reference)
            .map(|(x, &r)| x.result.ok().map(|(s, _)| rel_err(s, r)))
            .collect();
        let violations = res
            .iter()
            .zip(&reference)
            .filter(
                |(x, &r)| matches!(x.result, Ok((s, e)) if (s - r).abs() > e || (s - r).is_nan()),
            )
            .count();
        let mut refused = [0usize; 4];
        for x in &res {
            if let Err(why) = x.result {
                refused[why as usize] += 1;
            }
        }
        let not_decreasing_over = |floor: f64| {
            rows.last().map(|prev: &Row| {
                prev.errs
                    .iter()
                    .zip(&errs)
                    .filter(|(a, b)| matches!((a, b), (Some(a), Some(b)) if b >= a && *a > floor))
                    .count()
            })
        };
        let not_decreasing = not_decreasing_over(0.0);
        let not_decreasing_above_floor = not_decreasing_over(NOISE_FLOOR);
        rows.push(Row {
            method: "der-statics".into(),
            resolution: n.to_string(),
            time: mean(&|x| x.cpu),
            evaluations: mean(&|x| x.evaluations as f64),
            iterations: mean(&|x| x.iterations as f64),
            errs,
            violations: Some(violations),
            not_decreasing,
            not_decreasing_above_floor,
            refused: Some(refused),
        });
        let time = rows.last().map(|r| r.time).unwrap_or(f64::NAN);
        solved.push((n, res, time));
    }
    for w in solved.windows(2) {
        let (m, n2) = (w[0].0, w[1].0);
        let errs: Vec<Option<f64>> = w[0]
            .1
            .iter()
            .zip(&w[1].1)
            .zip(&reference)
            .map(|((a, b), r)| match (a.result, b.result) {
                (Ok((a, _)), Ok((b, _))) => Some(rel_err((4.0 * b - a) / 3.0, *r)),
                _ => None,
            })
            .collect();
        rows.push(Row {
            method: "der-statics-richardson".into(),
            resolution: format!("{m}+{n2}"),
            time: w[0].2 + w[1].2,
            evaluations: f64::NAN,
            iterations: f64::NAN,
            errs,
            violations: None,
            not_decreasing: None,
            not_decreasing_above_floor: None,
            refused: None,
        });
    }
    let mut csv = String::from(
        "method,resolution,time_per_direction_s,evaluations,newton_iterations,solved,max_rel_err,worst_direction,median_rel_err,above_0.1pct,est_error_violations,not_decreasing,refused_kappa0,refused_resolution,refused_continuum_check,failed_solver,not_decreasing_above_floor\n",
    );
    println!("DER statics vs continuum (tol 1e-10) on the {nd}-direction Fibonacci half-sphere, DER tol {tol:e}:");
    println!("| method | n | CPU time per direction | evaluations / Newton iterations | solved | max rel. error (solved) | worst direction | median rel. error | > 0.1 % | est_error violated | err(n) ≥ err(n/2) (above the {NOISE_FLOOR:e} floor) | refused: κ→0 / resolution / continuum check / solver |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let opt = |k: Option<usize>| k.map(|k| k.to_string()).unwrap_or_else(|| "–".into());
    for r in &rows {
        let ok: Vec<(usize, f64)> = r
            .errs
            .iter()
            .enumerate()
            .filter_map(|(i, e)| e.map(|e| (i, e)))
            .collect();
        let (imax, max) = ok.iter().fold(
            (0, 0.0_f64),
            |(bi, b), &(i, e)| if e > b { (i, e) } else { (bi, b) },
        );
        let med = median(&mut ok.iter().map(|x| x.1).collect::<Vec<_>>());
        let above = ok.iter().filter(|x| x.1 > 1e-3).count();
        let worst = name(&dirs[imax]);
        let work = if r.evaluations.is_finite() {
            format!("{:.1} / {:.1}", r.evaluations, r.iterations)
        } else {
            "–".into()
        };
        let refused_md = r
            .refused
            .map(|f| format!("{} / {} / {} / {}", f[0], f[1], f[2], f[3]))
            .unwrap_or_else(|| "–".into());
        println!(
            "| {} | {} | {:.2} ms | {work} | {} | {max:.2e} | {worst} | {med:.2e} | {above} | {} | {} | {refused_md} |",
            r.method,
            r.resolution,
            r.time * 1e3,
            ok.len(),
            opt(r.violations),
            match (r.not_decreasing, r.not_decreasing_above_floor) {
                (Some(a), Some(b)) => format!("{a} ({b})"),
                _ => "–".into(),
            },
        );
        let f = r.refused.map(|f| f.map(|k| k.to_string()));
        let f = f.unwrap_or_else(|| ["".into(), "".into(), "".into(), "".into()]);
        csv.push_str(&format!(
            "{},{},{:.6e},{:.2},{:.2},{},{max:.6e},\"{worst}\",{med:.6e},{above},{},{},{},{},{},{},{}\n",
            r.method,
            r.resolution,
            r.time,
            r.evaluations,
            r.iterations,
            ok.len(),
            r.violations.map(|k| k.to_string()).unwrap_or_default(),
            r.not_decreasing.map(|k| k.to_string()).unwrap_or_default(),
            f[0],
            f[1],
            f[2],
            f[3],
            r.not_decreasing_above_floor
                .map(|k| k.to_string())
                .unwrap_or_default()
        ));
    }
    resolution_needed(&dirs, &reference, &solved);
    helixreach::io::write_atomic(std::path::Path::new(&out), csv.as_bytes())?;
    let mut per = String::from("dir_kappa,dir_tau,dir_omega,s_star_continuum");
    for (n, _, _) in &solved {
        per.push_str(&format!(",s_star_der_{n},est_error_der_{n}"));
    }
    per.push('\n');
    for (i, d) in dirs.iter().enumerate() {
        per.push_str(&format!(
            "{},{},{},{}",
            d.kappa, d.tau, d.omega, reference[i]
        ));
        for (_, s, _) in &solved {
            match s[i].result {
                Ok((x, e)) => per.push_str(&format!(",{x},{e}")),
                Err(_) => per.push_str(",,"),
            }
        }
        per.push('\n');
    }
    let per_path = out.trim_end_matches(".csv").to_string() + "_per_direction.csv";
    helixreach::io::write_atomic(std::path::Path::new(&per_path), per.as_bytes())?;
    eprintln!("wrote {out} and {per_path}");
    Ok(())
}
