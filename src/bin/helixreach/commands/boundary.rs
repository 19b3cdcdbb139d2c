//! `helixreach boundary`: the stability boundary s* along every direction of a set, written as
//! CSV (`dir_kappa,dir_tau,dir_omega,s_star,kappa,tau,omega,method,resolution,est_error`, rows in
//! input order; `s_star = inf` when the ray is stable up to `s_max`). Parallel over directions,
//! checkpointed, resumable and shardable through `helixreach::sweep::driver`, whose data-safety
//! rules apply: the output's sidecar `OUT.meta.json` records the settings (method, resolution,
//! tolerance, scan step, ν, direction-set digest, shard, tool version); an existing output is continued only
//! with `--resume` (same settings) or replaced only with `--force` (once the new result is
//! complete); checkpoints go to `OUT.partial`; `--out -` streams to stdout.
//!
//! With `--method der` the DER-statics boundary (`--n-edges N`) is computed instead; its
//! `resolution` column is `n=N` and `est_error` is the root-finding error plus the empirical
//! discretization bound of `boundary::der` (checked against the continuum). A direction the
//! method refuses (a DER s* outside that bound, a direction too close to κ = 0 for DER, a solve
//! that does not converge) is a row with `nan` numbers and the reason in the last column,
//! `refused`; `reach --boundary` and `layout --boundary` refuse such a row naming its line.
//!
//! `--gravity` (method der) loads the rod with its weight, g = 9.81 m/s² along −z of the rig's
//! base frame: the rod is the rig's (`--rig`), whose clamp rotation `[d1 d2 d3]` orients it
//! (without `--rig` the rod points up, the seed's clamp), and every ray is taken at the azimuth
//! `--azimuth` α (rad) about d3; s* is the DER statics s* of the loaded rod
//! (`helixreach::boundary::der`, "Gravity"), which depends on the rod's `L_gb/L` and on α. The
//! sidecar records gravity, azimuth and the weight per unit length in the helix frame.
//!
//! `--speed-report FILE` instead measures time per direction (one thread's CPU time, best of 3) and the error against a
//! tight-tolerance continuum reference, for several resolutions of the chosen method, and writes
//! `method,resolution,time_per_direction_s,max_rel_err,median_rel_err` (rows of other methods
//! already in FILE are kept).

use super::args::{checkpoint_interval, DirectionArgs};
use anyhow::{bail, Context};
use helixreach::boundary::continuum::{self, ContinuumParams, CriticalS};
use helixreach::boundary::der;
use helixreach::directions::Direction;
use helixreach::math::{Mat3, Real, Vec3};
use helixreach::rod::dynamics::presets::{Preset, STANDARD_GRAVITY};
use helixreach::sweep::driver::{self, Shard, SweepOptions};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use helixreach::records::BOUNDARY_HEADER as HEADER;

/// Which stability test: the library's one [`helixreach::boundary::Method`].
pub use helixreach::boundary::Method;

/// Arguments of `helixreach boundary`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach boundary --fibonacci 20 --quarter --out boundary.csv",
    "$ helixreach boundary --method der --n-edges 30 --fibonacci 4 --out -",
    "> helixreach boundary --fibonacci 2000 --quarter --out boundary.csv"
))]
#[command(group(clap::ArgGroup::new("dirs").required(true).args(["directions", "fibonacci"])))]
pub struct Args {
    /// Stability test.
    #[arg(long, value_enum, default_value = "continuum")]
    pub method: Method,
    /// Number of DER edges (method der), at most helixreach::limits::MAX_N_EDGES; with
    /// `--rel-tol` the starting n.
    #[arg(long, default_value_t = 100)]
    pub n_edges: usize,
    /// Method der: choose n per direction, doubling from `--n-edges` until the Richardson
    /// estimate of the discretization error is at most this (relative). The row's
    /// `resolution` is `n=N` of that direction and `est_error` the estimate (plus the
    /// bracket); a direction that needs more than `--max-n-edges` is a refused row naming the
    /// n it would need.
    #[arg(long, allow_negative_numbers = true)]
    pub rel_tol: Option<Real>,
    /// With --rel-tol: the largest n (an error when reached, never a silent cap).
    #[arg(long, default_value_t = der::DEFAULT_MAX_ADAPTIVE_EDGES, requires = "rel_tol")]
    pub max_n_edges: usize,
    /// The direction set.
    #[command(flatten)]
    pub dirs: DirectionArgs,
    /// The rod (`--rig`, `--preset`, field overrides; default `paper-sim`). Without gravity
    /// the boundary of the nondimensional rod depends on its Poisson ratio ν only (and not even
    /// on that in the continuum limit): the rig's other fields do not change s*.
    #[command(flatten)]
    pub rod: super::rod_args::RodArgs,
    /// Method der: load the rod with its weight (g = 9.81 m/s² along −z of the rig's base frame,
    /// oriented by the rig's clamp; without --rig the rod points up).
    #[arg(long)]
    pub gravity: bool,
    /// With --gravity: the azimuth α (rad) of every ray about the clamp tangent (the helix first
    /// curls toward cos α·d1 + sin α·d2 of the clamp frame).
    #[arg(
        long,
        default_value_t = 0.0,
        allow_negative_numbers = true,
        requires = "gravity"
    )]
    pub azimuth: Real,
    /// Relative tolerance on s*.
    #[arg(long, default_value_t = helixreach::math::tol::S_STAR_REL, allow_negative_numbers = true)]
    pub tol: Real,
    /// Scan step of the continuum test (arc length of the unit-direction helix).
    #[arg(long, default_value_t = continuum::DEFAULT_STEP, allow_negative_numbers = true)]
    pub step: Real,
    /// Continue an existing --out (or its checkpoint OUT.partial) made with the same settings:
    /// compute only the missing directions.
    #[arg(long)]
    pub resume: bool,
    /// Replace an existing --out (it is kept until the new result is complete).
    #[arg(long)]
    pub force: bool,
    /// Process only block I (0-based) of N contiguous blocks of the directions.
    #[arg(long, allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Seconds between checkpoints (to OUT.partial).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub checkpoint_secs: f64,
    /// Output CSV (`-`: standard output).
    #[arg(long, required_unless_present = "speed_report")]
    pub out: Option<PathBuf>,
    /// Write a speed-versus-error table for this method to FILE instead of a boundary.
    #[arg(long)]
    pub speed_report: Option<PathBuf>,
}

use helixreach::records::boundary::BoundaryRecord;
pub use helixreach::records::{dir_key, SpeedErrorRow};

/// One boundary record.
fn row(d: &Direction, r: CriticalS, method: &str, resolution: &str) -> BoundaryRecord {
    BoundaryRecord::new(d, r.s_star, method, resolution, r.est_error)
}

/// A solver for one direction: `(s*, resolution label)`.
type Solver = Box<dyn Fn(&Direction) -> helixreach::Result<CriticalS> + Sync>;

fn solver(
    method: Method,
    nu: Real,
    tol: Real,
    step: Real,
    n_edges: usize,
    weight: Vec3,
) -> anyhow::Result<(Solver, String)> {
    match method {
        Method::Continuum => {
            let p = ContinuumParams {
                nu,
                tol_rel: tol,
                step,
                ..ContinuumParams::default()
            };
            p.validate()?;
            Ok((
                Box::new(move |d| continuum::critical_s_with(d, &p)),
                format!("tol={tol:e}"),
            ))
        }
        Method::Der => {
            let p = der::DerBoundaryParams {
                n_edges,
                nu,
                tol_rel: tol,
                ..der::DerBoundaryParams::default()
            };
            p.validate()?;
            Ok((
                Box::new(move |d| {
                    der::critical_s_gravity(d, &p, weight).map(|r| CriticalS {
                        s_star: r.s_star,
                        est_error: r.est_error,
                    })
                }),
                format!("n={n_edges}"),
            ))
        }
    }
}

/// Run `helixreach boundary`.
pub fn run(a: Args) -> anyhow::Result<()> {
    // Cheap checks first: a bad output path or size fails before any computation.
    helixreach::limits::check_size("--n-edges", a.n_edges, helixreach::limits::MAX_N_EDGES)?;
    for p in a.out.iter().chain(&a.speed_report) {
        helixreach::io::check_output(p)?;
    }
    let checkpoint = checkpoint_interval(a.checkpoint_secs)?;
    let dirs = a.dirs.load()?;
    if let Some(report) = &a.speed_report {
        if a.gravity {
            bail!("--speed-report measures the gravity-free boundary; drop --gravity");
        }
        return speed_report(&a, &dirs, report);
    }
    let out = a.out.clone().context("--out is required")?;
    let resolved = a.rod.resolve(Preset::PaperSim)?;
    let nu = resolved.rod.nu;
    let weight = if a.gravity {
        if a.method != Method::Der {
            bail!("--gravity needs --method der (the continuum rod has no weight)");
        }
        let clamp = resolved
            .rig
            .as_ref()
            .map_or_else(Mat3::identity, |r| r.clamp_rotation());
        der::gravity_in_helix_frame(
            &resolved.rod,
            &clamp,
            a.azimuth,
            &Vec3::new(0.0, 0.0, -STANDARD_GRAVITY),
        )?
    } else {
        Vec3::zeros()
    };
    let (solve, resolution) = solver(a.method, nu, a.tol, a.step, a.n_edges, weight)?;
    let method = Method::as_str(a.method);
    let adaptive = match a.rel_tol {
        Some(e) if a.method == Method::Der => {
            let p = der::DerBoundaryParams {
                n_edges: a.n_edges,
                nu,
                tol_rel: a.tol,
                ..der::DerBoundaryParams::default()
            };
            p.validate()?;
            Some((p, e))
        }
        Some(_) => bail!("--rel-tol needs --method der (the continuum's accuracy is --tol)"),
        None => None,
    };
    let resolution = match adaptive {
        Some((_, e)) => format!("rel_tol={e:e} n0={} n_max={}", a.n_edges, a.max_n_edges),
        None => resolution,
    };
    let max_n = a.max_n_edges;
    let solve = move |d: &Direction| -> helixreach::Result<(CriticalS, Option<String>)> {
        match adaptive {
            Some((p, e)) => der::critical_s_to_rel_tol_gravity(d, &p, weight, e, max_n).map(|r| {
                (
                    CriticalS {
                        s_star: r.s_star,
                        est_error: r.est_error,
                    },
                    Some(format!("n={}", r.n_edges)),
                )
            }),
            None => solve(d).map(|r| (r, None)),
        }
    };
    let mut opts = SweepOptions::new(&out, HEADER, 3)
        .sweep("boundary")
        .setting("method", method)
        .setting("resolution", &resolution)
        .setting("tol", a.tol)
        .setting("nu", nu);
    if a.method == Method::Continuum {
        opts = opts.setting("step", a.step);
    }
    if a.gravity {
        opts = opts
            .setting("gravity", STANDARD_GRAVITY)
            .setting("azimuth", a.azimuth)
            .setting("rod", &resolved.source)
            .setting(
                "weight_helix_frame",
                format!("{},{},{}", weight.x, weight.y, weight.z),
            );
    }
    opts.resume = a.resume;
    opts.force = a.force;
    opts.shard = a.shard;
    opts.checkpoint_interval = checkpoint;
    opts.progress = !super::global().quiet;
    opts.par = helixreach::par::Par::from_option(super::global().threads)?;
    let t0 = Instant::now();
    let summary = driver::run(
        &dirs,
        dir_key,
        // A direction the method refuses is a row with its reason: the sweep finishes and
        // resumes past it.
        |d| match solve(d) {
            Ok((r, per_row)) => Ok(row(d, r, method, per_row.as_deref().unwrap_or(&resolution))),
            Err(e) => Ok(BoundaryRecord::refused(
                d,
                method,
                &resolution,
                &e.to_string(),
            )),
        },
        &opts,
    )?;
    status!(
        "boundary: {} directions ({} computed, {} resumed) in {:.3} s -> {}",
        summary.total,
        summary.computed,
        summary.resumed,
        t0.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// Timing passes per resolution in `--speed-report` (the best one is reported).
const REPEATS: usize = 3;

/// Least CPU time of one timing pass: the directions are solved again until it is reached, so
/// the per-direction time is far above the clock's resolution (1 ns for the thread CPU clock).
const MIN_PASS_SECONDS: f64 = 0.05;

/// Tolerance of the speed report's continuum reference s* (relative; with a 4× finer scan step).
const REFERENCE_TOL_REL: Real = 1e-13;

/// The continuum tolerances the speed report measures, coarse to fine (relative).
const CONTINUUM_TOL_SWEEP: [Real; 5] = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12];

/// Time per direction (single-thread CPU time, best of [`REPEATS`] passes) and error versus a tight
/// continuum reference ([`REFERENCE_TOL_REL`], a 4× finer scan step).
fn speed_report(a: &Args, dirs: &[Direction], path: &Path) -> anyhow::Result<()> {
    let nu = a.rod.resolve(Preset::PaperSim)?.rod.nu;
    let reference = ContinuumParams {
        nu,
        tol_rel: REFERENCE_TOL_REL,
        step: continuum::DEFAULT_STEP / 4.0,
        ..ContinuumParams::default()
    };
    let s_ref: Vec<Real> = dirs
        .iter()
        .map(|d| continuum::critical_s_with(d, &reference).map(|r| r.s_star))
        .collect::<helixreach::Result<_>>()?;
    let resolutions: Vec<(Real, usize)> = match a.method {
        Method::Continuum => CONTINUUM_TOL_SWEEP.iter().map(|&t| (t, 0)).collect(),
        Method::Der => [25, 50, 100, 200].iter().map(|&n| (a.tol, n)).collect(),
    };
    let method = Method::as_str(a.method);
    let mut lines = Vec::new();
    for (tol, n) in resolutions {
        let (solve, label) = solver(a.method, nu, tol, a.step, n, Vec3::zeros())?;
        // CPU time of this thread (wall time where unavailable), best of REPEATS passes: the
        // machine may be shared, and CPU time is what a free core would take.
        let mut per = f64::INFINITY;
        let mut s = Vec::new();
        for _ in 0..REPEATS {
            let c0 = helixreach::cpu_time::thread_cpu_seconds()?;
            let mut solved = 0usize;
            loop {
                // A failing direction counts as an infinite error (reported, not hidden).
                s = dirs
                    .iter()
                    .map(|d| solve(d).map(|r| r.s_star).unwrap_or(Real::NAN))
                    .collect::<Vec<Real>>();
                solved += dirs.len();
                if helixreach::cpu_time::thread_cpu_seconds()? - c0 >= MIN_PASS_SECONDS {
                    break;
                }
            }
            let dt = helixreach::cpu_time::thread_cpu_seconds()? - c0;
            per = per.min(dt / solved as f64);
        }
        if !(per > 0.0 && per.is_finite()) {
            bail!("{method} {label}: measured time per direction {per} s is not positive");
        }
        let failed: Vec<&Direction> = dirs
            .iter()
            .zip(&s)
            .filter(|(_, x)| x.is_nan())
            .map(|(d, _)| d)
            .collect();
        if let Some(d) = failed.first() {
            eprintln!(
                "warning: {method} {label}: {} of {} directions failed (first: {}); counted as \
                 infinite error",
                failed.len(),
                dirs.len(),
                dir_key(d).join(",")
            );
        }
        let mut errs: Vec<Real> = s
            .iter()
            .zip(&s_ref)
            .map(|(&x, &r)| {
                if x == r {
                    0.0
                } else if x.is_finite() && r.is_finite() {
                    ((x - r) / r).abs()
                } else {
                    Real::INFINITY
                }
            })
            .collect();
        errs.sort_by(|x, y| x.total_cmp(y));
        let max = *errs.last().unwrap_or(&0.0);
        let med = errs[errs.len() / 2];
        status!(
            "{method} {label}: {:.3e} s/direction, max rel err {max:.3e}, median {med:.3e}",
            per
        );
        lines.push(SpeedErrorRow {
            method: method.to_string(),
            resolution: label.to_string(),
            time_per_direction_s: per,
            max_rel_err: max,
            median_rel_err: med,
        });
    }
    // The header and this method's rows by the record; rows of other methods already in the
    // file are kept verbatim (one table for every method; they may hold infinite errors).
    let new = helixreach::records::csv_out::to_csv(&lines)?;
    let (header, body) = new.split_once('\n').unwrap_or((&new, ""));
    let mut text = format!("{header}\n");
    // Rows of other methods are kept from an existing regular file (a FIFO or device is only
    // written).
    let old = match std::fs::metadata(path) {
        Ok(m) if m.is_file() => std::fs::read_to_string(path).ok(),
        _ => None,
    };
    if let Some(old) = old {
        for l in old.lines().skip(1) {
            if !l.starts_with(&format!("{method},")) && !l.is_empty() {
                text.push_str(l);
                text.push('\n');
            }
        }
    }
    text.push_str(body);
    helixreach::io::write_atomic(path, text.as_bytes())?;
    Ok(())
}
