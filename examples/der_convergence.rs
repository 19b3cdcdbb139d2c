//! Speed versus error of the DER-statics boundary: for n = 25, 50, 100, 200 edges (both clamp
//! placements), the time per direction and the max/median relative error of s* against a
//! reference, over a Fibonacci set of directions on the half-sphere; plus the observed
//! convergence order.
//!
//! ```text
//! cargo run --release --example der_convergence -- [N_DIRECTIONS] [OUT.csv]
//! ```
//! (defaults: 24 directions, `target/der_convergence.csv`). The CSV has the columns
//! `method,resolution,time_per_direction_s,max_rel_err,median_rel_err` (one row per method and
//! n) for the speed-versus-error figure; the summary and the orders go to stdout.
//!
//! Reference: the continuum conjugate-point method (`boundary::continuum`, tol 1e-10).
//! The DER search is seeded by the continuum s* (the default; the time includes it). Rows are
//! sequential on one core; rays stable up to s_max (none in a generic set) are skipped in the
//! error statistics. The `der-statics-richardson-m` rows combine n = m and 2m as
//! `(4·s*_{2m} − s*_m)/3` (time = both solves).

use helixreach::boundary::continuum;
use helixreach::boundary::der::{critical_s, DerBoundaryParams};
use helixreach::directions::{fibonacci, Direction};
use helixreach::rod::clamp::ClampPlacement;
use std::time::Instant;

fn solve(dirs: &[Direction], n: usize, clamp: ClampPlacement, tol: f64) -> (Vec<f64>, f64) {
    let p = DerBoundaryParams {
        n_edges: n,
        tol_rel: tol,
        clamp,
        ..Default::default()
    };
    let t = Instant::now();
    let s: Vec<f64> = dirs
        .iter()
        .map(|d| critical_s(d, &p).map(|c| c.s_star).unwrap_or(f64::NAN))
        .collect();
    (s, t.elapsed().as_secs_f64() / dirs.len() as f64)
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

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let nd: usize = args.get(1).map(|a| a.parse()).transpose()?.unwrap_or(24);
    let out = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| "target/der_convergence.csv".into());
    let dirs = fibonacci(nd, false)?;
    let tol = 1e-7;
    eprintln!("reference: continuum conjugate points (tol 1e-10) on {nd} directions …");
    let t0 = Instant::now();
    let reference: Vec<f64> = dirs
        .iter()
        .map(|d| {
            continuum::critical_s(d, 1e-10)
                .map(|c| c.s_star)
                .unwrap_or(f64::NAN)
        })
        .collect();
    let t_cont = t0.elapsed().as_secs_f64() / nd as f64;
    let mut csv =
        String::from("method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n");
    println!(
        "| method | n | time per direction | max rel. error | median rel. error | median order |"
    );
    println!("|---|---|---|---|---|---|");
    println!(
        "| continuum (reference) | tol 1e-10 | {:.4} ms | – | – | – |",
        t_cont * 1e3
    );
    let mut straddle: Vec<(usize, Vec<f64>, f64)> = Vec::new();
    for (name, clamp) in [
        ("der-statics", ClampPlacement::Straddle),
        ("der-statics-inside", ClampPlacement::Inside),
    ] {
        let mut prev: Option<Vec<f64>> = None;
        for n in [25usize, 50, 100, 200] {
            let (s, t) = solve(&dirs, n, clamp, tol);
            let errs: Vec<f64> = s
                .iter()
                .zip(&reference)
                .filter(|(a, r)| a.is_finite() && r.is_finite())
                .map(|(a, r)| (a - r).abs() / r)
                .collect();
            let max = errs.iter().cloned().fold(0.0, f64::max);
            let med = median(&mut errs.clone());
            let order = prev
                .as_ref()
                .map(|p| {
                    let mut o: Vec<f64> = p
                        .iter()
                        .zip(&errs)
                        .filter(|(a, b)| **a > 0.0 && **b > 0.0)
                        .map(|(a, b)| (a / b).log2())
                        .collect();
                    median(&mut o)
                })
                .map(|o| format!("{o:.2}"))
                .unwrap_or_else(|| "–".into());
            println!(
                "| {name} | {n} | {:.3} ms | {max:.2e} | {med:.2e} | {order} |",
                t * 1e3
            );
            csv.push_str(&format!("{name},{n},{t:.6e},{max:.6e},{med:.6e}\n"));
            if clamp == ClampPlacement::Straddle {
                straddle.push((n, s.clone(), t));
            }
            prev = Some(errs);
        }
    }
    // Richardson extrapolation in n of the straddling DER, (4·s*_{2m} − s*_m)/3: O(1/n⁴) at
    // the cost of the two resolutions.
    for w in straddle.windows(2) {
        let (m, n2) = (w[0].0, w[1].0);
        let t = w[0].2 + w[1].2;
        let mut errs: Vec<f64> = w[0]
            .1
            .iter()
            .zip(&w[1].1)
            .zip(&reference)
            .filter(|((a, b), r)| a.is_finite() && b.is_finite() && r.is_finite())
            .map(|((a, b), r)| ((4.0 * b - a) / 3.0 - r).abs() / r)
            .collect();
        let max = errs.iter().cloned().fold(0.0, f64::max);
        let med = median(&mut errs);
        let name = format!("der-statics-richardson-{m}");
        println!(
            "| {name} | {n2} | {:.3} ms | {max:.2e} | {med:.2e} | – |",
            t * 1e3
        );
        csv.push_str(&format!("{name},{n2},{t:.6e},{max:.6e},{med:.6e}\n"));
    }
    helixreach::io::write_atomic(std::path::Path::new(&out), csv.as_bytes())?;
    eprintln!("wrote {out}");
    Ok(())
}
