//! The whole study — what `helixreach demo` runs — as library stages with typed outcomes.
//!
//! | stage | function | outcome | files written into the output directory |
//! |---|---|---|---|
//! | continuum boundary | [`continuum_survey`] | [`ContinuumSurvey`] | `boundary.csv`, `boundary_omega0.csv` |
//! | DER check | [`der_check`] | [`DerCheck`] | `der_check.csv` |
//! | reachability | [`reach_survey`] | [`ReachSurvey`] | `reach_{fixed,motor}.csv`, `reach_omega0_{fixed,motor}.csv` (sweep checkpoints), `reach.csv`, `reach_omega0.csv` |
//! | dynamics | [`dynamics_rays`] | [`DynamicsRays`] | `series_N.csv` |
//! | trajectory | [`trajectory`] | [`PlannedTrajectory`] | `trajectory.csv`, `trajectory.json` (each with its `.meta.json` sidecar), `joint_limits.csv` |
//! | figures (feature `plots`) | `figures` | `Figures` | PNG + SVG, `speed_error.csv` |
//!
//! Each stage returns `Result<Outcome>`: an error is a failed stage, never a skipped one.
//! [`run`] runs them in order, keeps going after a failure (a stage that needs an earlier
//! stage's result fails with a message naming it) and returns a [`StudyReport`] whose
//! [`StudyReport::all_done`] is false when any stage failed — the demo then exits non-zero.
//!
//! The reachability stage runs on the sweep driver ([`crate::sweep::driver`]): it checkpoints
//! while it runs, and with [`RunOptions::resume`] a rerun into the same directory keeps the rows
//! already finished. Progress goes to stderr (`[elapsed s] stage: message`).
//!
//! Every number of the outcomes is a pure function of the [`Settings`] except the timings
//! (`*seconds*`, `time_per_direction_s`).
//!
//! A study from Rust — `examples/study.rs`, included here (and compiled as a doctest):
//!
#![doc = "```no_run"]
#![doc = include_str!("../../examples/study.rs")]
#![doc = "```"]

mod boundary;
pub mod campaign;
mod dynamics;
#[cfg(feature = "plots")]
mod figures;
mod reach;
mod trajectory;

pub use boundary::{
    continuum_survey, der_check, ContinuumSurvey, DerCheck, DerSweepRow, TolSweepRow,
};
pub use dynamics::{dynamics_rays, DynamicsRay, DynamicsRays};
#[cfg(feature = "plots")]
pub use figures::{figures, Figures};
pub use reach::{reach_survey, ReachSurvey, RollSummary};
pub use trajectory::{trajectory, PlannedTrajectory};

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::records::SpeedErrorRow;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Every knob of a study (written into the report).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Settings {
    /// `quick` or `full`.
    pub mode: String,
    /// The rig: a rig file or the name of an embedded rig.
    pub rig: String,
    /// Worker threads of every parallel stage ([`run`] runs the study on a pool of this many;
    /// 1..=[`crate::limits::MAX_THREADS`]). Every number but the timings is the same for any
    /// count. Default: the calling pool's size.
    pub threads: usize,
    /// Continuum boundary: Fibonacci half-sphere size.
    pub continuum_directions: usize,
    /// Continuum boundary: relative tolerance on s*.
    pub continuum_tol_rel: Real,
    /// Directions of the ω = 0 fan (κ ≥ 0, τ from −1 to 1).
    pub fan_directions: usize,
    /// Continuum tolerances timed for the speed-versus-error figure.
    pub continuum_tol_sweep: Vec<Real>,
    /// The reference tolerance of that sweep.
    pub continuum_tol_reference: Real,
    /// Directions the speed sweeps are timed on.
    pub speed_sample: usize,
    /// DER statics: sample size.
    pub der_sample: usize,
    /// DER statics: edges of the check.
    pub der_n_edges: usize,
    /// DER statics: edges of the resolution sweep.
    pub der_n_sweep: Vec<usize>,
    /// DER statics: relative tolerance on s*.
    pub der_tol_rel: Real,
    /// Poisson ratio of the DER statics rod (at run time: the rig's `rod.poisson`).
    pub nu: Real,
    /// The rod of the DER dynamics stage: the rig's `[rod]`, filled in at run time
    /// ([`run_with_log`]); `None` before (then the `paper-sim` preset).
    pub rod: Option<crate::rod::dynamics::PhysicalRod>,
    /// Reachability: quarter-sphere size per roll mode.
    pub reach_directions: usize,
    /// Reachability: fan size in the plane ω = 0.
    pub reach_fan_directions: usize,
    /// DER dynamics (paper-sim rod): rays simulated (the paper's Fig. 4 directions first).
    pub dynamics_rays: usize,
    /// DER dynamics: edges.
    pub dynamics_n_edges: usize,
    /// DER dynamics: time step (s).
    pub dynamics_dt: Real,
    /// DER dynamics: ray speed ds/dt (1/s).
    pub dynamics_speed: Real,
    /// DER dynamics: sample spacing in s.
    pub dynamics_record_ds: Real,
}

/// Largest rod resolution (edges) of any stage: [`crate::limits::MAX_N_EDGES`].
pub const MAX_EDGES: usize = crate::limits::MAX_N_EDGES;

/// Largest direction count of any stage: [`crate::limits::MAX_DIRECTIONS`] (the one set of
/// limits; the paper's half-sphere is 58,352).
pub const MAX_DIRECTIONS: usize = crate::limits::MAX_DIRECTIONS;

impl Settings {
    /// The small, fast run (about a minute): fewer directions, coarser rods.
    pub fn quick(rig: &str) -> Settings {
        Settings {
            // Study settings, each named by its field (documented on `Settings`): not tolerance literals.
            mode: "quick".into(),
            rig: rig.into(),
            threads: rayon::current_num_threads(),
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
            rod: None,
            reach_directions: 100,
            reach_fan_directions: 25,
            dynamics_rays: 1,
            dynamics_n_edges: 20,
            dynamics_dt: 2e-3,
            dynamics_speed: 0.5,
            dynamics_record_ds: 0.02,
        }
    }

    /// The full study (the paper's 58,352 directions; minutes on two cores).
    pub fn full(rig: &str) -> Settings {
        Settings {
            // Study settings, each named by its field (documented on `Settings`): not tolerance literals.
            mode: "full".into(),
            rig: rig.into(),
            threads: rayon::current_num_threads(),
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
            rod: None,
            reach_directions: 2000,
            reach_fan_directions: 91,
            dynamics_rays: 2,
            dynamics_n_edges: 50,
            dynamics_dt: 2e-3,
            dynamics_speed: 0.1,
            dynamics_record_ds: 0.01,
        }
    }

    /// The parallelism of every parallel stage: [`Settings::threads`] workers.
    pub fn par(&self) -> Result<crate::par::Par> {
        crate::par::Par::threads(self.threads)
    }

    /// Check every size against its bound (clear errors naming the field and value).
    pub fn validate(&self) -> Result<()> {
        crate::limits::check_range("threads", self.threads, 1, crate::limits::MAX_THREADS)?;
        let sizes = [
            ("continuum_directions", self.continuum_directions),
            ("fan_directions", self.fan_directions),
            ("speed_sample", self.speed_sample),
            ("der_sample", self.der_sample),
            ("reach_directions", self.reach_directions),
            ("reach_fan_directions", self.reach_fan_directions),
        ];
        for (field, n) in sizes {
            if n == 0 || n > MAX_DIRECTIONS {
                return Err(Error::invalid(
                    field,
                    n,
                    format!("must be in 1..={MAX_DIRECTIONS}"),
                ));
            }
        }
        let max_edges = MAX_EDGES;
        for &n in self
            .der_n_sweep
            .iter()
            .chain([&self.der_n_edges, &self.dynamics_n_edges])
        {
            if !(4..=max_edges).contains(&n) {
                return Err(Error::invalid(
                    "n_edges",
                    n,
                    format!("must be in 4..={max_edges}"),
                ));
            }
        }
        if self.dynamics_rays > paper_directions().len() {
            return Err(Error::invalid(
                "dynamics_rays",
                self.dynamics_rays,
                format!(
                    "at most {} (the paper's directions)",
                    paper_directions().len()
                ),
            ));
        }
        Ok(())
    }
}

/// Stage progress on stderr with the elapsed time: `[  12.3 s] stage: message` (nothing when
/// quiet, neither the lines nor the sweeps' progress).
#[derive(Debug, Clone, Copy)]
pub struct Log {
    t0: Instant,
    quiet: bool,
}

impl Log {
    /// A log whose clock starts now.
    pub fn start() -> Log {
        Log {
            t0: Instant::now(),
            quiet: false,
        }
    }

    /// This log, printing nothing when `quiet`.
    pub fn quiet(self, quiet: bool) -> Log {
        Log { quiet, ..self }
    }

    /// Whether progress is shown (not quiet).
    pub fn shows(&self) -> bool {
        !self.quiet
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.t0.elapsed().as_secs_f64()
    }

    /// Print one line.
    pub fn say(&self, stage: &str, msg: impl AsRef<str>) {
        if self.quiet {
            return;
        }
        eprintln!("[{:>6.1} s] {stage}: {}", self.elapsed(), msg.as_ref());
    }
}

/// Where and how [`run`] writes.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Output directory (created).
    pub out: PathBuf,
    /// Keep the reachability rows an earlier run already wrote into `out`.
    pub resume: bool,
}

impl RunOptions {
    /// Write into `out`, no resume.
    pub fn new(out: impl Into<PathBuf>) -> RunOptions {
        RunOptions {
            out: out.into(),
            resume: false,
        }
    }
}

/// One stage of a [`StudyReport`].
#[derive(Debug, Clone)]
pub struct StageRecord {
    /// Stage name (`continuum boundary`, `der check`, …).
    pub name: &'static str,
    /// The outcome as JSON (the report's numbers), or the error message.
    pub result: std::result::Result<serde_json::Value, String>,
    /// Wall time of the stage.
    pub seconds: f64,
}

/// What [`run`] produced: every stage's record, and the typed outcomes of those that finished.
#[derive(Debug, Clone)]
pub struct StudyReport {
    /// The settings of the run.
    pub settings: Settings,
    /// Every stage, in run order.
    pub stages: Vec<StageRecord>,
    /// Stage 1.
    pub continuum: Option<ContinuumSurvey>,
    /// Stage 2.
    pub der: Option<DerCheck>,
    /// Stage 3.
    pub reach: Option<ReachSurvey>,
    /// Stage 4.
    pub dynamics: Option<DynamicsRays>,
    /// Stage 5.
    pub trajectory: Option<PlannedTrajectory>,
    /// Figure files written (PNG and SVG), relative to the output directory.
    pub figures: Vec<String>,
    /// Wall time of the whole run.
    pub total_seconds: f64,
}

impl StudyReport {
    /// True when every stage finished.
    pub fn all_done(&self) -> bool {
        self.stages.iter().all(|s| s.result.is_ok())
    }

    /// The failed stages.
    pub fn failed(&self) -> impl Iterator<Item = &StageRecord> {
        self.stages.iter().filter(|s| s.result.is_err())
    }

    /// The speed-versus-error rows of every method measured (continuum tolerances, DER
    /// statics resolutions, DER dynamics), in that order.
    pub fn speed_rows(&self) -> Vec<SpeedErrorRow> {
        let mut rows = Vec::new();
        if let Some(c) = &self.continuum {
            rows.extend(c.speed_rows.iter().cloned());
        }
        if let Some(d) = &self.der {
            rows.extend(d.speed_rows.iter().cloned());
        }
        if let Some(d) = &self.dynamics {
            rows.extend(d.speed_rows.iter().cloned());
        }
        rows
    }
}

/// Run one stage: time it, log start and end, record the outcome as JSON.
fn stage<T: Serialize>(
    log: &Log,
    stages: &mut Vec<StageRecord>,
    name: &'static str,
    f: impl FnOnce() -> Result<T>,
) -> Option<T> {
    log.say(name, "start");
    let t = Instant::now();
    let res = f().and_then(|o| {
        serde_json::to_value(&o)
            .map(|v| (o, v))
            .map_err(|e| Error::invalid("report", name, e.to_string()))
    });
    let seconds = t.elapsed().as_secs_f64();
    let (out, result) = match res {
        Ok((o, v)) => {
            log.say(name, format!("done in {seconds:.1} s"));
            (Some(o), Ok(v))
        }
        Err(e) => {
            log.say(name, format!("FAILED: {e}"));
            (None, Err(e.to_string()))
        }
    };
    stages.push(StageRecord {
        name,
        result,
        seconds,
    });
    out
}

/// An error for a stage that needs an earlier stage's result.
fn needs(stage: &str) -> Error {
    Error::invalid(
        "stage",
        stage,
        "failed earlier; this stage needs its result",
    )
}

/// Run the whole study into `opts.out` (see the module docs). Errors only when the output
/// directory cannot be created or the settings are invalid; a failing stage is recorded in the
/// report.
pub fn run(settings: &Settings, opts: &RunOptions) -> Result<StudyReport> {
    run_with_log(settings, opts, &Log::start())
}

/// [`run`] with a given log clock (the demo starts it before parsing).
pub fn run_with_log(settings: &Settings, opts: &RunOptions, log: &Log) -> Result<StudyReport> {
    settings.validate()?;
    settings
        .par()?
        .install(|| run_stages(settings, opts, log))?
}

/// The stages of [`run_with_log`], on the calling pool.
fn run_stages(settings: &Settings, opts: &RunOptions, log: &Log) -> Result<StudyReport> {
    // A rig that does not load fails the run before any work. Its rod is the rod of the
    // simulating stages (ν of the DER statics, the whole rod of the dynamics).
    let rig = crate::planning::rig::Rig::load(&settings.rig)?;
    let mut settings = settings.clone();
    settings.nu = rig.rod.nu;
    settings.rod = Some(rig.rod);
    let settings = &settings;
    let out = opts.out.as_path();
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let t0 = Instant::now();
    let mut stages = Vec::new();
    let st = settings;
    let continuum = stage(log, &mut stages, "continuum boundary", || {
        continuum_survey(st, out, log)
    });
    let der = stage(log, &mut stages, "der check", || match &continuum {
        Some(c) => der_check(st, &c.rows, out, log),
        None => Err(needs("continuum boundary")),
    });
    let reach = stage(log, &mut stages, "reachability", || {
        reach_survey(st, out, opts.resume, log)
    });
    let dynamics = stage(log, &mut stages, "dynamics", || dynamics_rays(st, out, log));
    let trajectory = stage(log, &mut stages, "trajectory", || trajectory(st, out));
    let mut report = StudyReport {
        settings: settings.clone(),
        stages,
        continuum,
        der,
        reach,
        dynamics,
        trajectory,
        figures: Vec::new(),
        total_seconds: 0.0,
    };
    #[cfg(feature = "plots")]
    {
        let mut stages = std::mem::take(&mut report.stages);
        if let Some(f) = stage(log, &mut stages, "figures", || figures(&report, out, log)) {
            report.figures = f.files;
        }
        report.stages = stages;
    }
    report.total_seconds = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// The paper's named directions: Fig. 4(b), Fig. 4(c) and the disturbance study of Fig. 5.
pub fn paper_directions() -> Vec<(&'static str, Direction)> {
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

/// Directions in the plane ω = 0, κ ≥ 0, from −τ̂ to +τ̂ (both ends excluded: the τ axis is the
/// degenerate straight rod).
pub fn omega0_fan(n: usize) -> Vec<Direction> {
    (1..=n)
        .filter_map(|i| {
            let a = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / (n + 1) as f64;
            Direction::new(a.cos(), a.sin(), 0.0).ok()
        })
        .collect()
}

/// (min, median, max) of the finite values (NaN each when there are none).
pub(crate) fn stats(v: &[f64]) -> (f64, f64, f64) {
    let mut f: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if f.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    f.sort_by(f64::total_cmp);
    (f[0], f[f.len() / 2], f[f.len() - 1])
}

/// Write a text file atomically into the output directory.
pub(crate) fn write(out: &Path, name: &str, text: &str) -> Result<()> {
    crate::io::write_atomic(&out.join(name), text.as_bytes())
}
