//! The bifurcation type and the hysteresis of the seed's 42 labelled directions
//! (`tests/data/seed/bifurcation_examples.csv`), from DER statics and, optionally, from DER
//! dynamics with unloading (the seed's protocol and resolution: 101 vertices, ray speed 0.1).
//!
//! ```text
//! cargo run --release --example bifurcation_report -- [N_EDGES] [--nu NU] [--dynamic K] [--damping Z] [--out F.csv]
//! ```
//!
//! Writes one row per labelled direction:
//! `dir_kappa,dir_tau,dir_omega,label,type,coefficient,s_star,s_jump,s_return_static,
//! s_return_label,s_dyn,s_return_dyn,reason` and prints the agreement of the types and the
//! differences of the return points on stderr. `--dynamic K` runs the dynamics on every K-th
//! direction (0 = none; the default), which takes minutes per direction at n = 100, with
//! mass-proportional damping `--damping Z` (1/s, default 2; the dynamics refuse to unload without
//! damping). Without damping the post-snap rod rings: it leaves the far branch early and its helix error stays
//! above the threshold long after (the dynamic return then measures the ringing); ζ = 2/s follows the static far branch.

use helixreach::bifurcation::{classify, BifurcationParams};
use helixreach::boundary::der::DerBoundaryParams;
use helixreach::directions::Direction;
use helixreach::rod::dynamics::{simulate_ray, SimParams, Unload};
use rayon::prelude::*;
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut n = 100usize;
    let mut nu = 0.33;
    let mut dynamic = 0usize;
    let mut damping = 2.0;
    let mut out: Option<PathBuf> = None;
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--nu" => {
                nu = args[i + 1].parse()?;
                i += 1;
            }
            "--dynamic" => {
                dynamic = args[i + 1].parse()?;
                i += 1;
            }
            "--damping" => {
                damping = args[i + 1].parse()?;
                i += 1;
            }
            "--out" => {
                out = Some(args[i + 1].clone().into());
                i += 1;
            }
            a => n = a.parse()?,
        }
        i += 1;
    }
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/seed/bifurcation_examples.csv");
    let path = std::env::var("HELIXREACH_SEED_DATA")
        .map(|d| PathBuf::from(d).join("bifurcation_examples.csv"))
        .unwrap_or(path);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| anyhow::anyhow!("{}: {e} (set HELIXREACH_SEED_DATA)", path.display()))?;
    struct Label {
        dir: Direction,
        kind: String,
        s_jump: f64,
        s_return: f64,
    }
    let labels: Vec<Label> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x = |i: usize| f[i].parse::<f64>().unwrap_or(f64::NAN);
            Label {
                dir: Direction::new(x(0), x(1), x(2)).expect("seed direction"),
                kind: f[3].to_string(),
                s_jump: x(4),
                s_return: x(5),
            }
        })
        .collect();
    let p = BifurcationParams {
        der: DerBoundaryParams {
            n_edges: n,
            nu,
            tol_rel: 1e-7,
            ..DerBoundaryParams::default()
        },
        ..BifurcationParams::default()
    };
    let t0 = std::time::Instant::now();
    let rows: Vec<String> = labels
        .par_iter()
        .enumerate()
        .map(|(k, l)| {
            let b = classify(&l.dir, &p);
            let (ty, coef, s_star, s_ret, reason) = match &b {
                Ok(b) => (
                    b.kind.name().to_string(),
                    b.coefficient,
                    b.s_star,
                    b.s_return,
                    b.reason.replace(',', ";"),
                ),
                Err(e) => (format!("error: {e}"), f64::NAN, f64::NAN, f64::NAN, String::new()),
            };
            let (s_dyn, s_ret_dyn) = if dynamic > 0 && k % dynamic == 0 {
                let sp = SimParams {
                    n_edges: 100,
                    speed: 0.1,
                    dt: 2e-3,
                    damping,
                    unload: Some(Unload::default()),
                    ..SimParams::default()
                };
                match simulate_ray(&l.dir, &sp, &mut |_| {}) {
                    Ok(sim) => (sim.s_dyn(), sim.s_return.unwrap_or(f64::NAN)),
                    Err(e) => {
                        eprintln!("dynamics {k}: {e}");
                        (f64::NAN, f64::NAN)
                    }
                }
            } else {
                (f64::NAN, f64::NAN)
            };
            eprintln!(
                "{k:2} {:>13} -> {ty:>13} coef {coef:+.4e} s* {s_star:.4} (jump {:.4}) s_return {s_ret:.4} (label {:.4}) dyn {s_dyn:.4}/{s_ret_dyn:.4}",
                l.kind, l.s_jump, l.s_return
            );
            format!(
                "{},{},{},{},{ty},{coef},{s_star},{},{s_ret},{},{s_dyn},{s_ret_dyn},{reason}",
                l.dir.kappa, l.dir.tau, l.dir.omega, l.kind, l.s_jump, l.s_return
            )
        })
        .collect();
    let agree = rows
        .iter()
        .zip(&labels)
        .filter(|(r, l)| r.split(',').nth(4) == Some(l.kind.as_str()))
        .count();
    eprintln!(
        "n = {n}, ν = {nu}: type agrees on {agree} of {} labelled directions ({:.1} s wall)",
        labels.len(),
        t0.elapsed().as_secs_f64()
    );
    if let Some(o) = out {
        let mut s = String::from("dir_kappa,dir_tau,dir_omega,label,type,coefficient,s_star,s_jump,s_return_static,s_return_label,s_dyn,s_return_dyn,reason\n");
        for r in rows {
            s.push_str(&r);
            s.push('\n');
        }
        helixreach::io::write_atomic(&o, s.as_bytes())?;
    }
    Ok(())
}
