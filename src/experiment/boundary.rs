//! Stages 1 and 2: the continuum boundary survey (with its tolerance sweep and closed-form
//! checks) and the DER statics check against it.

use super::{omega0_fan, stats, write, Log, Settings};
use crate::boundary::continuum;
use crate::boundary::der::{self, DerBoundaryParams};
use crate::directions::{fibonacci, Direction};
use crate::error::Result;
use crate::par::Par;
use crate::records::boundary::{BoundaryRecord, DerCheckRecord};
use crate::records::{csv_out, BoundaryRow, SpeedErrorRow};
use serde::Serialize;
use std::time::Instant;

/// One tolerance of the continuum speed-versus-error sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TolSweepRow {
    /// Relative tolerance on s*.
    pub tol_rel: f64,
    /// Mean time per direction (s, measured inside the parallel loop).
    pub cpu_seconds_per_direction: f64,
    /// Largest relative difference to the reference tolerance.
    pub max_rel_err: f64,
    /// Median relative difference to the reference tolerance.
    pub median_rel_err: f64,
}

/// Outcome of [`continuum_survey`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContinuumSurvey {
    /// Half-sphere directions asked.
    pub directions: usize,
    /// Directions whose test failed (not in `rows`).
    pub failed: usize,
    /// Relative tolerance on s*.
    pub tol_rel: f64,
    /// Wall time of the half-sphere.
    pub wall_seconds: f64,
    /// Smallest finite s*.
    pub s_star_min: f64,
    /// Median finite s*.
    pub s_star_median: f64,
    /// Largest finite s*.
    pub s_star_max_finite: f64,
    /// Directions stable up to s_max.
    pub stable_to_s_max: usize,
    /// s* on the κ axis (closed form 2π).
    pub kappa_axis_s_star: f64,
    /// Its relative difference to 2π.
    pub kappa_axis_rel_err_vs_2pi: f64,
    /// s* near the ω axis (closed form 2·x₁, tan x₁ = x₁).
    pub omega_axis_s_star: f64,
    /// Its relative difference to 2·x₁.
    pub omega_axis_rel_err_vs_greenhill: f64,
    /// Directions of the ω = 0 fan solved.
    pub omega0_fan_directions: usize,
    /// The tolerance sweep.
    pub tolerance_sweep: Vec<TolSweepRow>,
    /// The half-sphere rows (as in `boundary.csv`).
    #[serde(skip)]
    pub rows: Vec<BoundaryRow>,
    /// The ω = 0 fan rows (as in `boundary_omega0.csv`).
    #[serde(skip)]
    pub fan: Vec<BoundaryRow>,
    /// The speed-versus-error rows of the tolerance sweep.
    #[serde(skip)]
    pub speed_rows: Vec<SpeedErrorRow>,
}

/// κ̂ of the direction that stands for the ω axis in the closed-form check (Greenhill's twisted
/// straight rod, approached as κ → 0⁺).
const OMEGA_AXIS_KAPPA: f64 = 1e-6;

/// (s*, est_error, seconds) per direction; NaN s* when the test failed.
fn solve(par: Par, dirs: &[Direction], tol: f64) -> Result<Vec<(f64, f64, f64)>> {
    par.map(dirs, |d| {
        let t = Instant::now();
        match continuum::critical_s(d, tol) {
            Ok(c) => (c.s_star, c.est_error, t.elapsed().as_secs_f64()),
            Err(_) => (f64::NAN, f64::NAN, t.elapsed().as_secs_f64()),
        }
    })
}

/// The boundary CSV of `rows` with their error estimates (the record layer's columns and row).
fn boundary_csv(rows: &[BoundaryRow], est: &[f64]) -> Result<String> {
    let records: Vec<BoundaryRecord> = rows
        .iter()
        .zip(est)
        .map(|(r, e)| BoundaryRecord::new(&r.dir, r.s_star, &r.method, &r.resolution, *e))
        .collect();
    csv_out::to_csv(&records)
}

/// Stage 1: the continuum boundary on the Fibonacci half-sphere and the ω = 0 fan (written to
/// `boundary.csv`, `boundary_omega0.csv`), the closed-form checks on the κ and ω axes, and the
/// tolerance sweep for the speed-versus-error figure.
pub fn continuum_survey(
    st: &Settings,
    out: &std::path::Path,
    log: &Log,
) -> Result<ContinuumSurvey> {
    let par = st.par()?;
    let resolution = format!("tol={:e}", st.continuum_tol_rel);
    let to_rows = |dirs: &[Direction], res: &[(f64, f64, f64)]| -> (Vec<BoundaryRow>, Vec<f64>) {
        dirs.iter()
            .zip(res)
            .filter(|(_, r)| !r.0.is_nan())
            .map(|(d, r)| {
                (
                    BoundaryRow {
                        dir: *d,
                        s_star: r.0,
                        method: crate::boundary::Method::Continuum.as_str().into(),
                        resolution: resolution.clone(),
                    },
                    r.1,
                )
            })
            .unzip()
    };
    let half = fibonacci(st.continuum_directions, false)?;
    let t = Instant::now();
    let res = solve(par, &half, st.continuum_tol_rel)?;
    let wall = t.elapsed().as_secs_f64();
    let failed = res.iter().filter(|r| r.0.is_nan()).count();
    let (rows, est) = to_rows(&half, &res);
    write(out, "boundary.csv", &boundary_csv(&rows, &est)?)?;
    log.say(
        "continuum boundary",
        format!("{} directions in {wall:.2} s ({failed} failed)", half.len()),
    );
    let fan_dirs = omega0_fan(st.fan_directions);
    let fres = solve(par, &fan_dirs, st.continuum_tol_rel)?;
    let (fan, fest) = to_rows(&fan_dirs, &fres);
    write(out, "boundary_omega0.csv", &boundary_csv(&fan, &fest)?)?;

    // Checks against closed forms: the κ axis (2π) and the ω axis (2·x₁, tan x₁ = x₁).
    let axis = |k, t, w| -> Result<f64> {
        Ok(continuum::critical_s(&Direction::new(k, t, w)?, st.continuum_tol_rel)?.s_star)
    };
    let k_axis = axis(1.0, 0.0, 0.0)?;
    // Just off the ω axis: the κ → 0⁺ limit, which the check compares with Greenhill.
    let w_axis = axis(OMEGA_AXIS_KAPPA, 0.0, 1.0)?;
    let greenhill = 2.0 * continuum::GREENHILL_X1;

    // Tolerance sweep on a sample, against a tight reference.
    let stride = (half.len() / st.speed_sample).max(1);
    let sample: Vec<Direction> = half.iter().step_by(stride).copied().collect();
    let reference = solve(par, &sample, st.continuum_tol_reference)?;
    let mut tolerance_sweep = Vec::new();
    let mut speed_rows = Vec::new();
    for &tol in &st.continuum_tol_sweep {
        let r = solve(par, &sample, tol)?;
        let rel: Vec<f64> = r
            .iter()
            .zip(&reference)
            .filter(|(a, b)| a.0.is_finite() && b.0.is_finite())
            .map(|(a, b)| (a.0 - b.0).abs() / b.0)
            .collect();
        let cpu = r.iter().map(|x| x.2).sum::<f64>() / r.len() as f64;
        let (_, med, max) = stats(&rel);
        speed_rows.push(SpeedErrorRow {
            method: crate::boundary::Method::Continuum.as_str().into(),
            resolution: format!("tol={tol:e}"),
            time_per_direction_s: cpu,
            max_rel_err: max,
            median_rel_err: med,
        });
        tolerance_sweep.push(TolSweepRow {
            tol_rel: tol,
            cpu_seconds_per_direction: cpu,
            max_rel_err: max,
            median_rel_err: med,
        });
    }
    let s: Vec<f64> = rows.iter().map(|r| r.s_star).collect();
    let (mn, med, mx) = stats(&s);
    Ok(ContinuumSurvey {
        directions: half.len(),
        failed,
        tol_rel: st.continuum_tol_rel,
        wall_seconds: wall,
        s_star_min: mn,
        s_star_median: med,
        s_star_max_finite: mx,
        stable_to_s_max: s.iter().filter(|x| x.is_infinite()).count(),
        kappa_axis_s_star: k_axis,
        kappa_axis_rel_err_vs_2pi: (k_axis / std::f64::consts::TAU - 1.0).abs(),
        omega_axis_s_star: w_axis,
        omega_axis_rel_err_vs_greenhill: (w_axis / greenhill - 1.0).abs(),
        omega0_fan_directions: fan.len(),
        tolerance_sweep,
        rows,
        fan,
        speed_rows,
    })
}

/// One resolution of the DER check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DerSweepRow {
    /// Edges n.
    pub n_edges: usize,
    /// Sample directions.
    pub directions: usize,
    /// Directions where DER statics failed or returned a non-finite s*.
    pub failed: usize,
    /// Largest relative difference to the continuum.
    pub max_rel_diff_vs_continuum: f64,
    /// Median relative difference to the continuum.
    pub median_rel_diff_vs_continuum: f64,
    /// Mean time per direction (s, measured inside the parallel loop).
    pub cpu_seconds_per_direction: f64,
    /// Wall time of this resolution.
    pub wall_seconds: f64,
}

/// Outcome of [`der_check`]: the check resolution's numbers, and the whole resolution sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DerCheck {
    /// Edges of the check.
    pub n_edges: usize,
    /// Sample directions.
    pub directions: usize,
    /// Failed directions at the check resolution.
    pub failed: usize,
    /// Largest relative difference to the continuum at the check resolution.
    pub max_rel_diff_vs_continuum: f64,
    /// Median relative difference to the continuum at the check resolution.
    pub median_rel_diff_vs_continuum: f64,
    /// Mean time per direction at the check resolution.
    pub cpu_seconds_per_direction: f64,
    /// Every resolution, ascending.
    pub resolution_sweep: Vec<DerSweepRow>,
    /// The speed-versus-error rows (resolutions with at least one finite difference).
    #[serde(skip)]
    pub speed_rows: Vec<SpeedErrorRow>,
}

/// Stage 2: DER statics on an even spread of the finite continuum rows (rays stable to s_max
/// skipped), at every resolution of the sweep → `der_check.csv`.
pub fn der_check(
    st: &Settings,
    boundary: &[BoundaryRow],
    out: &std::path::Path,
    log: &Log,
) -> Result<DerCheck> {
    let finite: Vec<&BoundaryRow> = boundary.iter().filter(|r| r.s_star.is_finite()).collect();
    if finite.is_empty() {
        return Err(crate::Error::invalid(
            "boundary",
            "0 finite rows",
            "the DER check needs continuum rows with a finite s* as its reference",
        ));
    }
    let stride = (finite.len() / st.der_sample.max(1)).max(1);
    let sample: Vec<&BoundaryRow> = finite
        .iter()
        .step_by(stride)
        .take(st.der_sample)
        .copied()
        .collect();
    let mut check_rows = Vec::new();
    let mut ns = st.der_n_sweep.clone();
    if !ns.contains(&st.der_n_edges) {
        ns.push(st.der_n_edges);
    }
    ns.sort_unstable();
    let mut sweep = Vec::new();
    let mut speed_rows = Vec::new();
    for &n in &ns {
        let p = DerBoundaryParams {
            n_edges: n,
            nu: st.nu,
            tol_rel: st.der_tol_rel,
            ..Default::default()
        };
        let t = Instant::now();
        let res: Vec<(f64, f64)> = st.par()?.map(&sample, |r| {
            let t = Instant::now();
            let s = der::critical_s(&r.dir, &p)
                .map(|c| c.s_star)
                .unwrap_or(f64::NAN);
            (s, t.elapsed().as_secs_f64())
        })?;
        let wall = t.elapsed().as_secs_f64();
        let mut rel = Vec::new();
        let mut fails = 0;
        let mut cpu = 0.0;
        for (r, (s, secs)) in sample.iter().zip(&res) {
            let d = (s - r.s_star).abs() / r.s_star;
            if d.is_finite() {
                rel.push(d);
            } else {
                fails += 1;
            }
            cpu += secs;
            check_rows.push(DerCheckRecord {
                dir: (&r.dir).into(),
                s_star_continuum: r.s_star,
                n_edges: n,
                s_star_der: *s,
                rel_diff: d,
                seconds: *secs,
            });
        }
        let (_, med, max) = stats(&rel);
        let per_dir = cpu / sample.len() as f64;
        log.say(
            "der check",
            format!(
                "n = {n}: max rel diff {max:.2e}, median {med:.2e}, {:.1} ms/direction, {fails} failed",
                1e3 * per_dir
            ),
        );
        if !rel.is_empty() {
            speed_rows.push(SpeedErrorRow {
                method: "DER statics".into(),
                resolution: format!("n={n}"),
                time_per_direction_s: per_dir,
                max_rel_err: max,
                median_rel_err: med,
            });
        }
        sweep.push(DerSweepRow {
            n_edges: n,
            directions: sample.len(),
            failed: fails,
            max_rel_diff_vs_continuum: max,
            median_rel_diff_vs_continuum: med,
            cpu_seconds_per_direction: per_dir,
            wall_seconds: wall,
        });
    }
    write(out, "der_check.csv", &csv_out::to_csv(&check_rows)?)?;
    let at = sweep
        .iter()
        .find(|r| r.n_edges == st.der_n_edges)
        .cloned()
        .unwrap_or_else(|| sweep[0].clone());
    Ok(DerCheck {
        n_edges: at.n_edges,
        directions: at.directions,
        failed: at.failed,
        max_rel_diff_vs_continuum: at.max_rel_diff_vs_continuum,
        median_rel_diff_vs_continuum: at.median_rel_diff_vs_continuum,
        cpu_seconds_per_direction: at.cpu_seconds_per_direction,
        resolution_sweep: sweep,
        speed_rows,
    })
}
