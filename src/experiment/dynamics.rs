//! Stage 4: DER dynamics along the paper's Fig. 4 directions: the helix error e versus s, and
//! the detected s_dyn against the continuum s*.

use super::{paper_directions, write, Log, Settings};
use crate::boundary::continuum;
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::tol;
use crate::records::{Series, SeriesRow, SpeedErrorRow};
use crate::rod::dynamics::{simulate_ray, SimParams, Simulation};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// One simulated ray.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DynamicsRay {
    /// The paper's name of the direction.
    pub direction: String,
    /// Detected instability distance (∞ — `null` in JSON — when none was seen).
    pub s_dyn: f64,
    /// The continuum s* of the same direction.
    pub s_star_continuum: f64,
    /// `|s_dyn − s*| / s*`.
    pub rel_diff: f64,
    /// Implicit Euler steps.
    pub steps: usize,
    /// Wall time of the ray.
    pub seconds: f64,
    /// The series file in the output directory.
    pub series_csv: String,
}

/// Outcome of [`dynamics_rays`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DynamicsRays {
    /// The rod preset.
    pub preset: String,
    /// Edges.
    pub n_edges: usize,
    /// Time step (s).
    pub dt_s: f64,
    /// Ray speed ds/dt (1/s).
    pub ray_speed_per_s: f64,
    /// Wall time of all rays (parallel).
    pub wall_seconds: f64,
    /// Every ray, in the paper's order.
    pub rays: Vec<DynamicsRay>,
    /// The e-versus-s series, for the figure.
    #[serde(skip)]
    pub series: Vec<Series>,
    /// Speed-versus-error rows (rays with a finite difference).
    #[serde(skip)]
    pub speed_rows: Vec<SpeedErrorRow>,
}

/// Stage 4: simulate the first `dynamics_rays` paper directions (in parallel) with the
/// rig's rod ([`Settings::rod`]; `paper-sim` when unset) → `series_N.csv` (`t,s,kappa,tau,omega,error,energy`).
pub fn dynamics_rays(st: &Settings, out: &Path, log: &Log) -> Result<DynamicsRays> {
    let dirs: Vec<(&str, Direction)> = paper_directions()
        .into_iter()
        .take(st.dynamics_rays)
        .collect();
    let rod = st
        .rod
        .unwrap_or_else(crate::rod::dynamics::PhysicalRod::paper_sim);
    let params = SimParams {
        rod,
        n_edges: st.dynamics_n_edges,
        dt: st.dynamics_dt,
        speed: st.dynamics_speed,
        record_ds: st.dynamics_record_ds,
        ..Default::default()
    };
    let t = Instant::now();
    let sims: Vec<Result<(Simulation, f64)>> = st.par()?.map(&dirs, |(_, d)| {
        let t = Instant::now();
        let sim = simulate_ray(d, &params, &mut |_| {})?;
        Ok((sim, t.elapsed().as_secs_f64()))
    })?;
    let wall = t.elapsed().as_secs_f64();
    let mut rays = Vec::new();
    let mut series = Vec::new();
    let mut speed_rows = Vec::new();
    for (k, ((name, d), r)) in dirs.iter().zip(sims).enumerate() {
        let (sim, secs) = r.map_err(|e| Error::Item {
            key: format!("simulating {name}"),
            cause: Box::new(e),
        })?;
        let s_cont = continuum::critical_s(d, tol::S_STAR_REL)?.s_star;
        let s_dyn = sim.s_dyn();
        let file = format!("series_{}.csv", k + 1);
        write(out, &file, &crate::records::series::series_csv(&sim)?)?;
        let rel = (s_dyn - s_cont).abs() / s_cont;
        log.say(
            "dynamics",
            format!(
                "{name}: s_dyn = {s_dyn:.4}, continuum s* = {s_cont:.4} ({:.2} %), {} steps, {secs:.1} s",
                100.0 * rel,
                sim.steps
            ),
        );
        if rel.is_finite() {
            speed_rows.push(SpeedErrorRow {
                method: "DER dynamics".into(),
                resolution: format!("n={} v={}", st.dynamics_n_edges, st.dynamics_speed),
                time_per_direction_s: secs,
                max_rel_err: rel,
                median_rel_err: rel,
            });
        }
        rays.push(DynamicsRay {
            direction: name.to_string(),
            s_dyn,
            s_star_continuum: s_cont,
            rel_diff: rel,
            steps: sim.steps,
            seconds: secs,
            series_csv: file,
        });
        series.push(Series {
            label: name.to_string(),
            rows: sim
                .samples
                .iter()
                .map(|x| SeriesRow {
                    t: x.t,
                    s: x.s,
                    error: x.error,
                })
                .collect(),
            s_detected: s_dyn.is_finite().then_some(s_dyn),
            s_reference: s_cont.is_finite().then_some(s_cont),
        });
    }
    Ok(DynamicsRays {
        preset: if st.rod.is_some() {
            "the rig's rod".into()
        } else {
            "paper-sim".into()
        },
        n_edges: params.n_edges,
        dt_s: params.dt,
        ray_speed_per_s: params.speed,
        wall_seconds: wall,
        rays,
        series,
        speed_rows,
    })
}
