//! `helixreach demo [--out DIR] [--quick]`: the main job on the embedded default rig.
//!
//! Stages (each timed, each writing its CSV into DIR so `helixreach plot` can redraw any figure):
//! 1. **continuum boundary** on a Fibonacci half-sphere (the paper's 58,352 directions; 2,000
//!    with `--quick`) and on a fan of directions in the plane ω = 0 → `boundary.csv`,
//!    `boundary_omega0.csv`;
//! 2. **DER statics check** on a sample of those directions against the continuum, and a
//!    resolution sweep (n edges) for the speed-versus-error table → `der_check.csv`;
//! 3. **reachability** of the experiment's quarter-sphere on the rig, in both roll modes →
//!    `reach.csv`, `reach_omega0.csv`;
//! 4. **DER dynamics** along the paper's Fig. 4 directions → `series_*.csv`;
//! 5. **one planned trajectory** with the joint limits → `trajectory.csv`, `joint_limits.csv`;
//! 6. **figures** (PNG and SVG) and the **report**: `report.md` and `report.json` with every
//!    headline number and the settings that produced it.
//!
//! A stage whose library code is missing or fails is recorded as skipped, with the reason, in
//! both reports; the figures that need it are not drawn. Progress goes to stderr.

use anyhow::Context;
use helixreach::boundary::continuum;
use helixreach::boundary::der::{self, DerBoundaryParams};
use helixreach::directions::{fibonacci, Direction};
use helixreach::math::tol;
use helixreach::planning::planner::{Planner, RayPlan};
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::plot::{self, BoundaryRow, SpeedErrorRow};
use helixreach::rod::dynamics::{simulate_ray, SimParams, Simulation};
use helixreach::sweep::reach;
use rayon::prelude::*;
use serde_json::{json, Map, Value};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `helixreach demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Output directory for figures, CSVs and the report (`--out figures` regenerates the
    /// figures committed for the README).
    #[arg(long, default_value = "helixreach-demo")]
    pub out: PathBuf,
    /// A small, fast run (about a minute): fewer directions, coarser rods.
    #[arg(long)]
    pub quick: bool,
    /// The rig: a rig file or the name of an embedded rig.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
}

/// Every knob of a demo run (written into the report).
#[derive(Debug, Clone, serde::Serialize)]
struct Settings {
    mode: &'static str,
    rig: String,
    threads: usize,
    /// Continuum boundary: Fibonacci half-sphere size and relative tolerance on s*.
    continuum_directions: usize,
    continuum_tol_rel: f64,
    /// Directions of the ω = 0 fan (κ ≥ 0, τ from −1 to 1).
    fan_directions: usize,
    /// Continuum tolerances timed for the speed-versus-error figure, and the reference.
    continuum_tol_sweep: Vec<f64>,
    continuum_tol_reference: f64,
    /// Directions the speed sweeps are timed on.
    speed_sample: usize,
    /// DER statics: sample size, edges for the check, edges of the resolution sweep.
    der_sample: usize,
    der_n_edges: usize,
    der_n_sweep: Vec<usize>,
    der_tol_rel: f64,
    nu: f64,
    /// Reachability: quarter-sphere size per roll mode, and the fan size in the plane ω = 0.
    reach_directions: usize,
    reach_fan_directions: usize,
    /// DER dynamics (paper-sim rod): rays simulated (the paper's Fig. 4 directions first),
    /// edges, time step (s), ray speed ds/dt (1/s), sample spacing in s.
    dynamics_rays: usize,
    dynamics_n_edges: usize,
    dynamics_dt: f64,
    dynamics_speed: f64,
    dynamics_record_ds: f64,
}

impl Settings {
    fn new(quick: bool, rig: &str) -> Settings {
        let threads = rayon::current_num_threads();
        if quick {
            Settings {
                mode: "quick",
                rig: rig.into(),
                threads,
                continuum_directions: 2000,
                continuum_tol_rel: 1e-8,
                fan_directions: 91,
                continuum_tol_sweep: vec![1e-3, 1e-5, 1e-8],
                continuum_tol_reference: 1e-12,
                speed_sample: 100,
                der_sample: 6,
                der_n_edges: 30,
                der_n_sweep: vec![15, 30],
                der_tol_rel: 1e-6,
                nu: 0.33,
                reach_directions: 100,
                reach_fan_directions: 25,
                dynamics_rays: 1,
                dynamics_n_edges: 20,
                dynamics_dt: 2e-3,
                dynamics_speed: 0.5,
                dynamics_record_ds: 0.02,
            }
        } else {
            Settings {
                mode: "full",
                rig: rig.into(),
                threads,
                continuum_directions: 58_352,
                continuum_tol_rel: 1e-8,
                fan_directions: 361,
                continuum_tol_sweep: vec![1e-3, 1e-4, 1e-6, 1e-8, 1e-10],
                continuum_tol_reference: 1e-13,
                speed_sample: 2000,
                der_sample: 40,
                der_n_edges: 100,
                der_n_sweep: vec![25, 50, 100, 200],
                der_tol_rel: 1e-8,
                nu: 0.33,
                reach_directions: 2000,
                reach_fan_directions: 91,
                dynamics_rays: 2,
                dynamics_n_edges: 50,
                dynamics_dt: 2e-3,
                dynamics_speed: 0.1,
                dynamics_record_ds: 0.01,
            }
        }
    }
}

/// Progress on stderr with the elapsed time.
struct Progress {
    t0: Instant,
}

impl Progress {
    fn say(&self, stage: &str, msg: impl AsRef<str>) {
        eprintln!(
            "[{:>6.1} s] {stage}: {}",
            self.t0.elapsed().as_secs_f64(),
            msg.as_ref()
        );
    }
}

/// What a stage produced for the report.
#[derive(Debug)]
enum Outcome {
    Done(Map<String, Value>),
    Skipped(String),
}

/// Everything the run accumulates.
struct Run {
    out: PathBuf,
    settings: Settings,
    progress: Progress,
    stages: Vec<(String, Outcome, f64)>,
    figures: Vec<String>,
    speed_rows: Vec<SpeedErrorRow>,
    boundary: Vec<BoundaryRow>,
    fan: Vec<BoundaryRow>,
    reach: Vec<plot::ReachRow>,
    reach_fan: Vec<plot::ReachRow>,
    series: Vec<plot::Series>,
    /// (rows, limits, s*, subtitle) of the planned trajectory.
    trajectory: Option<(Vec<plot::TrajectoryRow>, Vec<plot::JointLimit>, f64, String)>,
}

impl Run {
    /// Run `f` as stage `name`, timing it; an error becomes a skipped stage with its message.
    fn stage(&mut self, name: &str, f: impl FnOnce(&mut Run) -> anyhow::Result<Outcome>) {
        self.progress.say(name, "start");
        let t = Instant::now();
        let outcome = match f(self) {
            Ok(o) => o,
            Err(e) => Outcome::Skipped(format!("failed: {e:#}")),
        };
        let secs = t.elapsed().as_secs_f64();
        match &outcome {
            Outcome::Done(_) => self.progress.say(name, format!("done in {secs:.1} s")),
            Outcome::Skipped(r) => self.progress.say(name, format!("SKIPPED: {r}")),
        }
        self.stages.push((name.to_string(), outcome, secs));
    }

    /// Render one figure as PNG and SVG (`stem.png`, `stem.svg`); failures are reported.
    fn figure(&mut self, stem: &str, f: impl Fn(&Path) -> helixreach::Result<()>) {
        for ext in ["png", "svg"] {
            let name = format!("{stem}.{ext}");
            match f(&self.out.join(&name)) {
                Ok(()) => self.figures.push(name),
                Err(e) => self
                    .progress
                    .say("figures", format!("{name} not drawn: {e}")),
            }
        }
    }
}

fn write_csv(path: &Path, text: &str) -> anyhow::Result<()> {
    helixreach::io::write_atomic(path, text.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

fn boundary_csv(rows: &[BoundaryRow], est: &[f64]) -> String {
    let mut s = String::from(
        "dir_kappa,dir_tau,dir_omega,s_star,kappa,tau,omega,method,resolution,est_error\n",
    );
    for (r, e) in rows.iter().zip(est) {
        let p = if r.s_star.is_finite() {
            r.dir.at(r.s_star)
        } else {
            [f64::INFINITY; 3]
        };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{}",
            r.dir.kappa,
            r.dir.tau,
            r.dir.omega,
            r.s_star,
            p[0],
            p[1],
            p[2],
            r.method,
            r.resolution,
            e
        );
    }
    s
}

/// Directions in the plane ω = 0, κ ≥ 0, from −τ̂ to +τ̂ (both ends excluded: the τ axis is the
/// degenerate straight rod).
fn omega0_fan(n: usize) -> Vec<Direction> {
    (1..=n)
        .filter_map(|i| {
            let a = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / (n + 1) as f64;
            Direction::new(a.cos(), a.sin(), 0.0).ok()
        })
        .collect()
}

fn stats(v: &[f64]) -> (f64, f64, f64) {
    let mut f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    f.sort_by(f64::total_cmp);
    (f[0], f[f.len() / 2], f[f.len() - 1])
}

/// Stage 1: the continuum boundary on the half-sphere and the ω = 0 fan, plus its tolerance
/// sweep for the speed-versus-error figure.
fn continuum_stage(run: &mut Run) -> anyhow::Result<Outcome> {
    let st = run.settings.clone();
    let solve = |dirs: &[Direction], tol: f64| -> Vec<(f64, f64, f64)> {
        dirs.par_iter()
            .map(|d| {
                let t = Instant::now();
                match continuum::critical_s(d, tol) {
                    Ok(c) => (c.s_star, c.est_error, t.elapsed().as_secs_f64()),
                    Err(_) => (f64::NAN, f64::NAN, t.elapsed().as_secs_f64()),
                }
            })
            .collect()
    };
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
                        method: "continuum".into(),
                        resolution: resolution.clone(),
                    },
                    r.1,
                )
            })
            .unzip()
    };
    let half = fibonacci(st.continuum_directions, false)?;
    let t = Instant::now();
    let res = solve(&half, st.continuum_tol_rel);
    let wall = t.elapsed().as_secs_f64();
    let failed = res.iter().filter(|r| r.0.is_nan()).count();
    let (rows, est) = to_rows(&half, &res);
    write_csv(&run.out.join("boundary.csv"), &boundary_csv(&rows, &est))?;
    run.progress.say(
        "continuum boundary",
        format!("{} directions in {wall:.2} s ({failed} failed)", half.len()),
    );
    let fan_dirs = omega0_fan(st.fan_directions);
    let fres = solve(&fan_dirs, st.continuum_tol_rel);
    let (fan, fest) = to_rows(&fan_dirs, &fres);
    write_csv(
        &run.out.join("boundary_omega0.csv"),
        &boundary_csv(&fan, &fest),
    )?;

    // Checks against closed forms: the κ axis (2π) and the ω axis (2·x₁, tan x₁ = x₁).
    let axis = |k, t, w| {
        continuum::critical_s(&Direction::new(k, t, w).unwrap(), st.continuum_tol_rel)
            .map(|c| c.s_star)
    };
    let k_axis = axis(1.0, 0.0, 0.0)?;
    let w_axis = axis(1e-6, 0.0, 1.0)?;
    let greenhill = 2.0 * continuum::GREENHILL_X1;

    // Tolerance sweep on a sample, against a tight reference.
    let stride = (half.len() / st.speed_sample).max(1);
    let sample: Vec<Direction> = half.iter().step_by(stride).copied().collect();
    let reference = solve(&sample, st.continuum_tol_reference);
    let mut sweep = Vec::new();
    for &tol in &st.continuum_tol_sweep {
        let r = solve(&sample, tol);
        let rel: Vec<f64> = r
            .iter()
            .zip(&reference)
            .filter(|(a, b)| a.0.is_finite() && b.0.is_finite())
            .map(|(a, b)| (a.0 - b.0).abs() / b.0)
            .collect();
        let cpu = r.iter().map(|x| x.2).sum::<f64>() / r.len() as f64;
        let (_, med, max) = stats(&rel);
        run.speed_rows.push(SpeedErrorRow {
            method: "continuum".into(),
            resolution: format!("tol={tol:e}"),
            time_per_direction_s: cpu,
            max_rel_err: max,
            median_rel_err: med,
        });
        sweep.push(json!({"tol_rel": tol, "cpu_seconds_per_direction": cpu, "max_rel_err": max, "median_rel_err": med}));
    }
    let s: Vec<f64> = rows.iter().map(|r| r.s_star).collect();
    let (mn, med, mx) = stats(&s);
    let n_inf = s.iter().filter(|x| x.is_infinite()).count();
    let mut m = Map::new();
    m.insert("directions".into(), json!(half.len()));
    m.insert("failed".into(), json!(failed));
    m.insert("tol_rel".into(), json!(st.continuum_tol_rel));
    m.insert("wall_seconds".into(), json!(wall));
    m.insert("s_star_min".into(), json!(mn));
    m.insert("s_star_median".into(), json!(med));
    m.insert("s_star_max_finite".into(), json!(mx));
    m.insert("stable_to_s_max".into(), json!(n_inf));
    m.insert("kappa_axis_s_star".into(), json!(k_axis));
    m.insert(
        "kappa_axis_rel_err_vs_2pi".into(),
        json!((k_axis / std::f64::consts::TAU - 1.0).abs()),
    );
    m.insert("omega_axis_s_star".into(), json!(w_axis));
    m.insert(
        "omega_axis_rel_err_vs_greenhill".into(),
        json!((w_axis / greenhill - 1.0).abs()),
    );
    m.insert("omega0_fan_directions".into(), json!(fan.len()));
    m.insert("tolerance_sweep".into(), Value::Array(sweep));
    run.boundary = rows;
    run.fan = fan;
    Ok(Outcome::Done(m))
}

/// Stage 3: reachability of the quarter-sphere in both roll modes (and the ω = 0 fan for the
/// section figure).
fn reach_stage(run: &mut Run) -> anyhow::Result<Outcome> {
    let st = run.settings.clone();
    let rig = Rig::load(&st.rig)?;
    let planner = Planner::new(rig.clone())?;
    let quarter = fibonacci(st.reach_directions, true)?;
    let fan: Vec<Direction> = omega0_fan(st.reach_fan_directions);
    let variants = [
        ("fixed", RollMode::Fixed, vec![0.0]),
        ("motor", RollMode::Motor, vec![0.0]),
    ];
    let mut all = Vec::new();
    let mut all_fan = Vec::new();
    let mut csv = format!("{}\n", reach::REACH_HEADER.join(","));
    let mut fan_csv = csv.clone();
    let mut m = Map::new();
    for (label, roll, azimuths) in &variants {
        let plan_all = |dirs: &[Direction]| -> Vec<helixreach::Result<RayPlan>> {
            dirs.par_iter()
                .map(|d| {
                    let s = continuum::critical_s(d, tol::S_STAR_REL)?.s_star;
                    planner.plan_best(d, s, azimuths, *roll, false)
                })
                .collect()
        };
        let t = Instant::now();
        let plans = plan_all(&quarter);
        let wall = t.elapsed().as_secs_f64();
        let fan_plans = plan_all(&fan);
        let mut counts = [0usize; 3];
        let mut causes: std::collections::BTreeMap<String, usize> = Default::default();
        let mut errors = 0;
        for (p, text, rows) in [
            (&plans, &mut csv, &mut all),
            (&fan_plans, &mut fan_csv, &mut all_fan),
        ] {
            for r in p {
                match r {
                    Ok(p) => {
                        let row = reach::reach_row(p);
                        let _ = writeln!(text, "{}", row.join(","));
                        rows.push(plot::ReachRow {
                            dir: p.dir,
                            s_star: p.s_star,
                            s_reached: p.s_reached,
                            class: row[5].parse().map_err(anyhow::Error::msg)?,
                            cause: row[6].parse().map_err(anyhow::Error::msg)?,
                            roll_mode: label.to_string(),
                        });
                    }
                    Err(_) => errors += 1,
                }
            }
        }
        for r in plans.iter().flatten() {
            counts[match r.class {
                helixreach::planning::planner::ReachClass::Testable => 0,
                helixreach::planning::planner::ReachClass::Partial => 1,
                helixreach::planning::planner::ReachClass::Blocked => 2,
            }] += 1;
            if let Some(c) = r.cause {
                *causes.entry(c.as_str().to_string()).or_default() += 1;
            }
        }
        let n = quarter.len() as f64;
        run.progress.say(
            "reachability",
            format!(
                "roll {label}: {:.1} % testable, {:.1} % partial, {:.1} % blocked ({} directions, {wall:.1} s)",
                100.0 * counts[0] as f64 / n,
                100.0 * counts[1] as f64 / n,
                100.0 * counts[2] as f64 / n,
                quarter.len()
            ),
        );
        m.insert(
            format!("roll_{label}"),
            json!({
                "directions": quarter.len(),
                "testable": counts[0],
                "partial": counts[1],
                "blocked": counts[2],
                "errors": errors,
                "fraction_testable": counts[0] as f64 / n,
                "fraction_partial": counts[1] as f64 / n,
                "fraction_blocked": counts[2] as f64 / n,
                "causes": causes,
                "azimuths": azimuths,
                "wall_seconds": wall,
            }),
        );
    }
    write_csv(&run.out.join("reach.csv"), &csv)?;
    write_csv(&run.out.join("reach_omega0.csv"), &fan_csv)?;
    run.reach = all;
    run.reach_fan = all_fan;
    Ok(Outcome::Done(m))
}

/// Stage 5: one planned trajectory (the first paper direction that is testable in roll mode
/// `fixed`, else the farthest partial one) with the joint limits.
fn trajectory_stage(run: &mut Run) -> anyhow::Result<Outcome> {
    let st = run.settings.clone();
    let rig = Rig::load(&st.rig)?;
    let planner = Planner::new(rig.clone())?;
    let mut best: Option<(String, RayPlan)> = None;
    for (name, d) in paper_directions() {
        let s = continuum::critical_s(&d, tol::S_STAR_REL)?.s_star;
        let p = planner.plan_best(&d, s, &[0.0], RollMode::Fixed, true)?;
        let better = best
            .as_ref()
            .is_none_or(|(_, b)| p.s_reached / p.s_end > b.s_reached / b.s_end);
        if better {
            best = Some((name.to_string(), p));
        }
        if best
            .as_ref()
            .is_some_and(|b| b.1.class == helixreach::planning::planner::ReachClass::Testable)
        {
            break;
        }
    }
    let Some((name, plan)) = best else {
        return Ok(Outcome::Skipped(
            "no paper direction could be planned".into(),
        ));
    };
    if plan.s_reached <= 0.0 {
        return Ok(Outcome::Skipped(format!(
            "every paper direction is blocked in roll mode fixed ({name})"
        )));
    }
    let traj = planner.trajectory(&plan)?;
    write_csv(&run.out.join("trajectory.csv"), &traj.to_csv())?;
    write_csv(&run.out.join("trajectory.json"), &traj.to_json())?;
    let mut limits: Vec<plot::JointLimit> = planner
        .model()
        .joints()
        .iter()
        .map(|j| plot::JointLimit {
            name: j.name.clone(),
            lower: j.lower,
            upper: j.upper,
        })
        .collect();
    if rig.motor.range.0.is_finite() && rig.motor.range.1.is_finite() {
        limits.push(plot::JointLimit {
            name: "motor".into(),
            lower: rig.motor.range.0,
            upper: rig.motor.range.1,
        });
    }
    let mut lcsv = String::from("joint,lower,upper\n");
    for l in &limits {
        let _ = writeln!(lcsv, "{},{},{}", l.name, l.lower, l.upper);
    }
    write_csv(&run.out.join("joint_limits.csv"), &lcsv)?;
    let rows = plot::read_trajectory(&run.out.join("trajectory.csv"))?;
    let mut m = Map::new();
    m.insert("direction".into(), json!(name));
    m.insert("roll_mode".into(), json!("fixed"));
    m.insert(
        "class".into(),
        json!(format!("{:?}", plan.class).to_lowercase()),
    );
    m.insert("s_star".into(), json!(plan.s_star));
    m.insert("s_reached".into(), json!(plan.s_reached));
    m.insert("waypoints".into(), json!(rows.len()));
    m.insert("max_joint_step_rad".into(), json!(plan.max_joint_step));
    m.insert("path_cost".into(), json!(plan.path_cost));
    m.insert("duration_s".into(), json!(traj.duration()));
    run.trajectory = Some((
        rows,
        limits,
        plan.s_star,
        format!("{name}, roll mode fixed"),
    ));
    Ok(Outcome::Done(m))
}

/// Stage 4: DER dynamics along the paper's Fig. 4 directions: e versus s, the detected s_dyn
/// against the continuum s*.
fn dynamics_stage(run: &mut Run) -> anyhow::Result<Outcome> {
    let st = run.settings.clone();
    let dirs: Vec<(&str, Direction)> = paper_directions()
        .into_iter()
        .take(st.dynamics_rays)
        .collect();
    let params = SimParams {
        n_edges: st.dynamics_n_edges,
        dt: st.dynamics_dt,
        speed: st.dynamics_speed,
        record_ds: st.dynamics_record_ds,
        ..Default::default()
    };
    let t = Instant::now();
    let sims: Vec<anyhow::Result<(Simulation, f64)>> = dirs
        .par_iter()
        .map(|(_, d)| {
            let t = Instant::now();
            let sim = simulate_ray(d, &params, &mut |_| {})?;
            Ok((sim, t.elapsed().as_secs_f64()))
        })
        .collect();
    let wall = t.elapsed().as_secs_f64();
    let mut rays = Vec::new();
    let mut series = Vec::new();
    for (k, ((name, d), r)) in dirs.iter().zip(sims).enumerate() {
        let (sim, secs) = r.with_context(|| format!("simulating {name}"))?;
        let s_cont = continuum::critical_s(d, tol::S_STAR_REL)?.s_star;
        let s_dyn = sim.s_dyn();
        let file = format!("series_{}.csv", k + 1);
        let mut csv = String::from("t,s,kappa,tau,omega,error,energy\n");
        for x in &sim.samples {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{}",
                x.t, x.s, x.kappa, x.tau, x.omega, x.error, x.energy
            );
        }
        write_csv(&run.out.join(&file), &csv)?;
        let rel = (s_dyn - s_cont).abs() / s_cont;
        run.progress.say("dynamics", format!("{name}: s_dyn = {s_dyn:.4}, continuum s* = {s_cont:.4} ({:.2} %), {} steps, {secs:.1} s", 100.0 * rel, sim.steps));
        if rel.is_finite() {
            run.speed_rows.push(SpeedErrorRow {
                method: "DER dynamics".into(),
                resolution: format!("n={} v={}", st.dynamics_n_edges, st.dynamics_speed),
                time_per_direction_s: secs,
                max_rel_err: rel,
                median_rel_err: rel,
            });
        }
        rays.push(json!({
            "direction": name,
            "s_dyn": s_dyn,
            "s_star_continuum": s_cont,
            "rel_diff": rel,
            "steps": sim.steps,
            "seconds": secs,
            "series_csv": file,
        }));
        series.push(plot::Series {
            label: name.to_string(),
            rows: sim
                .samples
                .iter()
                .map(|x| plot::SeriesRow {
                    t: x.t,
                    s: x.s,
                    error: x.error,
                })
                .collect(),
            s_detected: s_dyn.is_finite().then_some(s_dyn),
            s_reference: s_cont.is_finite().then_some(s_cont),
        });
    }
    let mut m = Map::new();
    m.insert("preset".into(), json!("paper-sim"));
    m.insert("n_edges".into(), json!(params.n_edges));
    m.insert("dt_s".into(), json!(params.dt));
    m.insert("ray_speed_per_s".into(), json!(params.speed));
    m.insert("wall_seconds".into(), json!(wall));
    m.insert("rays".into(), Value::Array(rays));
    run.series = series;
    Ok(Outcome::Done(m))
}

/// Stage 2: DER statics on a sample of the continuum directions.
fn der_check(run: &mut Run) -> anyhow::Result<Outcome> {
    let st = run.settings.clone();
    if run.boundary.is_empty() {
        return Ok(Outcome::Skipped(
            "needs the continuum boundary (stage 1) as the reference".into(),
        ));
    }
    // An even spread through the Fibonacci list, skipping rays stable to s_max.
    let finite: Vec<&BoundaryRow> = run
        .boundary
        .iter()
        .filter(|r| r.s_star.is_finite())
        .collect();
    let stride = (finite.len() / st.der_sample.max(1)).max(1);
    let sample: Vec<&BoundaryRow> = finite
        .iter()
        .step_by(stride)
        .take(st.der_sample)
        .copied()
        .collect();
    let mut csv = String::from(
        "dir_kappa,dir_tau,dir_omega,s_star_continuum,n_edges,s_star_der,rel_diff,seconds\n",
    );
    let mut out = Map::new();
    let mut ns = st.der_n_sweep.clone();
    if !ns.contains(&st.der_n_edges) {
        ns.push(st.der_n_edges);
    }
    ns.sort_unstable();
    let mut per_n = Vec::new();
    for &n in &ns {
        let p = DerBoundaryParams {
            n_edges: n,
            nu: st.nu,
            tol_rel: st.der_tol_rel,
            ..Default::default()
        };
        let t = Instant::now();
        let res: Vec<(f64, f64)> = sample
            .par_iter()
            .map(|r| {
                let t = Instant::now();
                let s = der::critical_s(&r.dir, &p)
                    .map(|c| c.s_star)
                    .unwrap_or(f64::NAN);
                (s, t.elapsed().as_secs_f64())
            })
            .collect();
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
            let _ = writeln!(
                csv,
                "{},{},{},{},{n},{s},{d},{secs}",
                r.dir.kappa, r.dir.tau, r.dir.omega, r.s_star
            );
        }
        let (_, med, max) = stats(&rel);
        let per_dir = cpu / sample.len() as f64;
        run.progress.say(
            "der check",
            format!("n = {n}: max rel diff {max:.2e}, median {med:.2e}, {:.1} ms/direction, {fails} failed", 1e3 * per_dir),
        );
        if !rel.is_empty() {
            run.speed_rows.push(SpeedErrorRow {
                method: "DER statics".into(),
                resolution: format!("n={n}"),
                time_per_direction_s: per_dir,
                max_rel_err: max,
                median_rel_err: med,
            });
        }
        per_n.push(json!({
            "n_edges": n,
            "directions": sample.len(),
            "failed": fails,
            "max_rel_diff_vs_continuum": max,
            "median_rel_diff_vs_continuum": med,
            "cpu_seconds_per_direction": per_dir,
            "wall_seconds": wall,
        }));
        if n == st.der_n_edges {
            out.insert("n_edges".into(), json!(n));
            out.insert("directions".into(), json!(sample.len()));
            out.insert("failed".into(), json!(fails));
            out.insert("max_rel_diff_vs_continuum".into(), json!(max));
            out.insert("median_rel_diff_vs_continuum".into(), json!(med));
            out.insert("cpu_seconds_per_direction".into(), json!(per_dir));
        }
    }
    out.insert("resolution_sweep".into(), Value::Array(per_n));
    write_csv(&run.out.join("der_check.csv"), &csv)?;
    Ok(Outcome::Done(out))
}

/// Run `helixreach demo`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let t0 = Instant::now();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let settings = Settings::new(args.quick, &args.rig);
    let mut run = Run {
        out: args.out.clone(),
        settings,
        progress: Progress { t0 },
        stages: Vec::new(),
        figures: Vec::new(),
        speed_rows: Vec::new(),
        boundary: Vec::new(),
        fan: Vec::new(),
        reach: Vec::new(),
        reach_fan: Vec::new(),
        series: Vec::new(),
        trajectory: None,
    };
    run.progress.say(
        "demo",
        format!(
            "{} run on rig `{}` with {} threads into {}",
            run.settings.mode,
            run.settings.rig,
            run.settings.threads,
            args.out.display()
        ),
    );
    run.stage("continuum boundary", continuum_stage);
    run.stage("der check", der_check);
    run.stage("reachability", reach_stage);
    run.stage("dynamics", dynamics_stage);
    run.stage("trajectory", trajectory_stage);
    run.stage("figures", figures);
    let total = t0.elapsed().as_secs_f64();
    write_reports(&run, total)?;
    run.progress.say(
        "demo",
        format!(
            "finished in {total:.1} s; report in {}",
            args.out.join("report.md").display()
        ),
    );
    Ok(())
}

fn figures(run: &mut Run) -> anyhow::Result<Outcome> {
    if !run.boundary.is_empty() {
        let b = run.boundary.clone();
        run.figure("boundary3d", |p| plot::boundary3d::render(&b, p));
    }
    if !run.fan.is_empty() {
        let (f, r) = (run.fan.clone(), run.reach_fan.clone());
        run.figure("section", |p| plot::section::render(&f, &r, p));
    }
    if !run.reach.is_empty() {
        let r = run.reach.clone();
        let marked: Vec<Direction> = paper_directions().iter().map(|d| d.1).collect();
        run.figure("directions", |p| {
            plot::direction_map::render(&r, &marked, "paper's directions", p)
        });
    }
    if !run.series.is_empty() {
        let s = run.series.clone();
        run.figure("error_vs_s", |p| plot::error_vs_s::render(&s, p));
    }
    if let Some((rows, limits, s_star, subtitle)) = run.trajectory.clone() {
        let opts = plot::trajectory::TrajectoryOptions {
            limits,
            s_star: Some(s_star),
            subtitle,
        };
        run.figure("trajectory", |p| plot::trajectory::render(&rows, &opts, p));
    }
    if !run.speed_rows.is_empty() {
        let rows = run.speed_rows.clone();
        let mut csv =
            String::from("method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n");
        for r in &rows {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                r.method, r.resolution, r.time_per_direction_s, r.max_rel_err, r.median_rel_err
            );
        }
        write_csv(&run.out.join("speed_error.csv"), &csv)?;
        run.figure("speed_error", |p| plot::speed_error::render(&rows, p));
    }
    let mut m = Map::new();
    m.insert("files".into(), json!(run.figures.clone()));
    Ok(Outcome::Done(m))
}

/// The paper's named directions: Fig. 4(b), Fig. 4(c) and the disturbance study of Fig. 5.
fn paper_directions() -> Vec<(&'static str, Direction)> {
    let r3 = 1.0 / 3f64.sqrt();
    [
        ("S = [0.594, 0.698, 0.4]", (0.594, 0.698, 0.4)),
        ("S = [1, 1, −1]/√3", (r3, r3, -r3)),
        ("S = [1, 1, 1]/√3", (r3, r3, r3)),
    ]
    .into_iter()
    .filter_map(|(n, (k, t, w))| Direction::new(k, t, w).ok().map(|d| (n, d)))
    .collect()
}

fn write_reports(run: &Run, total: f64) -> anyhow::Result<()> {
    let mut stages = Map::new();
    let mut skipped = Vec::new();
    for (name, o, secs) in &run.stages {
        let v = match o {
            Outcome::Done(m) => {
                let mut m = m.clone();
                m.insert("status".into(), json!("done"));
                m.insert("seconds".into(), json!(secs));
                Value::Object(m)
            }
            Outcome::Skipped(r) => {
                skipped.push(json!({ "stage": name, "reason": r }));
                json!({ "status": "skipped", "reason": r, "seconds": secs })
            }
        };
        stages.insert(name.replace(' ', "_"), v);
    }
    let report = json!({
        "helixreach_version": env!("CARGO_PKG_VERSION"),
        "settings": run.settings,
        "total_seconds": total,
        "stages": stages,
        "figures": run.figures,
        "skipped": skipped,
    });
    let text = serde_json::to_string_pretty(&report)?;
    write_csv(&run.out.join("report.json"), &text)?;
    write_csv(&run.out.join("report.md"), &markdown(run, &report, total))?;
    Ok(())
}

fn num(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) => format!("{x:.3e}"),
        Some(x) if x.fract() == 0.0 => format!("{x}"),
        Some(x) => format!("{x:.4}"),
        None => v.to_string(),
    }
}

fn markdown(run: &Run, report: &Value, total: f64) -> String {
    let mut md = String::new();
    let st = &run.settings;
    let _ = writeln!(md, "# helixreach demo report ({} run)\n", st.mode);
    let _ = writeln!(
        md,
        "Rig `{}`, {} threads, total {total:.1} s. Every number below is also in `report.json`, \
         with the settings that produced it.\n",
        st.rig, st.threads
    );
    let _ = writeln!(md, "| stage | status | seconds |\n|---|---|---|");
    for (name, o, secs) in &run.stages {
        let status = match o {
            Outcome::Done(_) => "done".to_string(),
            Outcome::Skipped(r) => format!("skipped — {r}"),
        };
        let _ = writeln!(md, "| {name} | {status} | {secs:.1} |");
    }
    for (name, o, _) in &run.stages {
        if let Outcome::Done(m) = o {
            let _ = writeln!(md, "\n## {name}\n");
            for (k, v) in m {
                match v {
                    Value::Array(a) if a.iter().all(|x| x.is_object()) && !a.is_empty() => {
                        let keys: Vec<String> = a[0]
                            .as_object()
                            .map(|o| o.keys().cloned().collect())
                            .unwrap_or_default();
                        let _ = writeln!(
                            md,
                            "**{k}**\n\n| {} |\n|{}",
                            keys.join(" | "),
                            "---|".repeat(keys.len())
                        );
                        for x in a {
                            let cells: Vec<String> = keys.iter().map(|c| num(&x[c])).collect();
                            let _ = writeln!(md, "| {} |", cells.join(" | "));
                        }
                        md.push('\n');
                    }
                    Value::Array(a) => {
                        let items: Vec<String> = a
                            .iter()
                            .map(|x| x.as_str().map(str::to_string).unwrap_or_else(|| num(x)))
                            .collect();
                        let _ = writeln!(md, "- {k}: {}", items.join(", "));
                    }
                    _ => {
                        let _ = writeln!(md, "- {k}: {}", num(v));
                    }
                }
            }
        }
    }
    let _ = writeln!(md, "\n## Figures\n");
    for f in &run.figures {
        if f.ends_with(".png") {
            let _ = writeln!(md, "![{f}]({f})");
        }
    }
    let _ = writeln!(
        md,
        "\n## Settings\n\n```json\n{}\n```",
        serde_json::to_string_pretty(&report["settings"]).unwrap_or_default()
    );
    md
}
