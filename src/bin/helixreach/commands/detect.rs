//! `helixreach detect`: the snap from a recorded run (joints + tracked marker), see
//! `helixreach::detect`.
//!
//! - One run: `--observations FILE --direction K,T,W [--clamp x,y,z] [--out samples.csv]`:
//!   JSON summary on stdout, the per-sample CSV with `--out`. Exit 0 when a snap was seen, 1 when
//!   not (the summary says why), 2 on bad input.
//! - A batch: `--runs runs.csv --out measured.csv`: one row per run, in order, parallel and
//!   resumable like the sweeps; the output is what `compare --measured` reads.

use super::args::checkpoint_interval;
use anyhow::Context;
use helixreach::detect::{run_record, DetectOptions, Detector};
use helixreach::directions::Direction;
use helixreach::planning::rig::{parse_xyz, Rig};
use helixreach::records::csv_out::{self, CsvRecord};
use helixreach::records::detect::{read_detect_runs, DetectRunRecord};
use helixreach::sweep::driver::{run as run_sweep, SweepOptions};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `helixreach detect`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "> helixreach detect --observations run.txt --direction 0.75,0,0.66 --out samples.csv",
    "> helixreach detect --runs runs.csv --out measured.csv"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// One run's observation file (joints, marker x y z in the camera frame, image row(s)).
    #[arg(long, conflicts_with = "runs", requires = "direction")]
    pub observations: Option<PathBuf>,
    /// The run's direction `κ,τ,ω` (normalized).
    #[arg(long, allow_hyphen_values = true)]
    pub direction: Option<String>,
    /// The clamp origin `x,y,z` (base frame, m); fitted from the joints when absent.
    #[arg(long, allow_hyphen_values = true)]
    pub clamp: Option<String>,
    /// A batch: CSV with `observations` (path relative to it), `dir_kappa,dir_tau,dir_omega`,
    /// optional `clamp_x,clamp_y,clamp_z`.
    #[arg(long, requires = "out")]
    pub runs: Option<PathBuf>,
    /// Helix azimuth α (rad) of the runs.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f64,
    /// Fit the extrinsics on samples before s first exceeds this fraction of the continuum s*.
    #[arg(long, default_value_t = 0.6)]
    pub fit_fraction: f64,
    /// One run: the per-sample CSV. Batch: the measured file (`-`: standard output).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Batch: continue an existing --out (or its checkpoint) made with the same settings.
    #[arg(long)]
    pub resume: bool,
    /// Batch: replace an existing --out (kept until the new result is complete).
    #[arg(long)]
    pub force: bool,
    /// Batch: seconds between checkpoints.
    #[arg(long, default_value_t = 10.0)]
    pub checkpoint_secs: f64,
}

/// Run `helixreach detect`.
pub fn run(args: Args) -> anyhow::Result<()> {
    if !(args.fit_fraction > 0.0 && args.fit_fraction <= 1.0) {
        anyhow::bail!("--fit-fraction {}: must lie in (0, 1]", args.fit_fraction);
    }
    let options = DetectOptions {
        azimuth: args.azimuth,
        fit_fraction: args.fit_fraction,
        ..DetectOptions::default()
    };
    let rig = Rig::load(&args.rig)?;
    let rig_name = rig.name.clone();
    let det = Detector::new(rig, options)?;
    if let Some(runs) = &args.runs {
        let out = args.out.as_ref().expect("clap requires --out with --runs");
        helixreach::io::check_output(out)?;
        let list = read_detect_runs(runs)?;
        let mut sweep = SweepOptions::new(out, DetectRunRecord::HEADER, 1)
            .sweep("detect")
            .setting("rig", &rig_name)
            .setting("azimuth", args.azimuth)
            .setting("fit_fraction", args.fit_fraction)
            .setting("runs", runs.display());
        sweep.resume = args.resume;
        sweep.force = args.force;
        sweep.checkpoint_interval = checkpoint_interval(args.checkpoint_secs)?;
        sweep.progress = !super::global().quiet;
        sweep.par = helixreach::par::Par::from_option(super::global().threads)?;
        let t0 = std::time::Instant::now();
        let summary = run_sweep(
            &list,
            |r| vec![r.observations.clone()],
            |r| {
                let rec = run_record(&det, r);
                if rec.reason == "rejected" {
                    eprintln!("{}:{}: rejected: {}", runs.display(), r.line, rec.notes);
                }
                Ok(rec)
            },
            &sweep,
        )?;
        status!(
            "detect: {} runs ({} computed, {} resumed) in {:.1} s -> {}",
            summary.total,
            summary.computed,
            summary.resumed,
            t0.elapsed().as_secs_f64(),
            out.display()
        );
        return Ok(());
    }
    let Some(obs_path) = &args.observations else {
        anyhow::bail!("give --observations FILE --direction K,T,W, or --runs runs.csv --out FILE");
    };
    let d = args
        .direction
        .as_deref()
        .expect("clap requires --direction");
    let [k, t, w] = parse_xyz("--direction", d)?;
    let dir = Direction::new(k, t, w).with_context(|| format!("--direction `{d}`"))?;
    let clamp = args
        .clamp
        .as_deref()
        .map(|c| parse_xyz("--clamp", c))
        .transpose()?;
    if let Some(out) = &args.out {
        helixreach::io::check_output(out)?;
    }
    let obs = det.read(obs_path)?;
    let r = det.detect(&obs, &dir, clamp)?;
    if let Some(out) = &args.out {
        let text = csv_out::to_csv(&r.sample_records())?;
        helixreach::io::write_atomic(out, text.as_bytes())?;
    }
    let mut stdout = std::io::stdout().lock();
    writeln!(
        stdout,
        "{}",
        serde_json::to_string_pretty(&r.summary_json())?
    )?;
    stdout.flush()?;
    match r.outcome.s_snap {
        Some(s) => {
            status!(
                "snap at s = {s:.5} ({} confidence){}",
                r.outcome.confidence.as_str(),
                r.outcome
                    .s_return
                    .map_or(String::new(), |x| format!(", back at s = {x:.5}"))
            );
            Ok(())
        }
        None => {
            eprintln!(
                "no snap seen: {} ({})",
                r.outcome.reason.as_str(),
                r.outcome.notes.join("; ")
            );
            std::process::exit(1);
        }
    }
}
