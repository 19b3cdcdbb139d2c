//! `helixreach check`: validate an existing joint trajectory on a rig (joint limits, self / scene
//! / rod collision, joint steps and jumps, pose error against the ray's pose curve). The logic is
//! `helixreach::planning::check`. Prints a JSON summary on stdout; `--out` writes the per-row CSV.
//!
//! # A gate
//! Exit 0 when nothing is found; 2 on bad input; otherwise 64 + a bit per kind of finding
//! (`helixreach::planning::check::Finding`): 1 a joint or motor limit, 2 a collision (at a row or
//! inside an interpolated step), 4 a joint step over `--max-step`, 8 a speed over its limit and
//! 16 an acceleration over its limit (both from the `t` column, by finite differences), 32 a pose
//! error over `--position-tolerance`/`--rotation-tolerance` (with `--direction`). The JSON's
//! `findings` counts each kind. `--report-only` reports and exits 0.
//!
//! The seed's 58 executed files (`trajectories/*.txt`) have no time column and Descartes jumps
//! of up to 1.63 rad that the real robot did execute: their limits and collisions pass
//! (`"limit_violations": 0`, `"collisions": 0`, no colliding interpolated step), and the default
//! gate fails them on steps (exit 68) — and, measured against the continuum end frame, on pose
//! (≈ 3 mm; exit 100). Gate them with `--max-step 2 --held-edges 100` (the frame their Descartes
//! targets used; every one then exits 0), or report with `--report-only`.

use anyhow::Context;
use helixreach::directions::Direction;
use helixreach::io::Output;
use helixreach::planning::check::{CheckOptions, Checker};
use helixreach::planning::rig::{parse_xyz, Rig};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `helixreach check`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach plan --direction 0.6,0.79,0.12 --out trajectory.csv",
    "$ helixreach check --trajectory trajectory.csv --direction 0.6,0.79,0.12 --out rows.csv",
    "> helixreach check --trajectory executed.txt --direction 1,0.23,0 --held-edges 100 --max-step 2"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The trajectory: whitespace rows of joint values (the seed's files), a headerless CSV, or
    /// a CSV with joint-name (or q0..) columns (helixreach `plan`, a MoveIt export).
    // `--joints FILE`: the earlier spelling, kept as a hidden alias (`--joints` now means values).
    #[arg(long, value_name = "FILE", alias = "joints")]
    pub trajectory: PathBuf,
    /// The ray's direction `κ,τ,ω` (normalized): enables the pose error and the rod check.
    #[arg(long, allow_hyphen_values = true)]
    pub direction: Option<String>,
    /// Helix azimuth α (rad) of the ray; default: the rig's first azimuth choice.
    #[arg(long, allow_hyphen_values = true)]
    pub azimuth: Option<f64>,
    /// Clamp origin `x,y,z` (base frame, m), overriding the rig's.
    #[arg(long, allow_hyphen_values = true)]
    pub clamp: Option<String>,
    /// Largest s of the pose projection's full scan.
    #[arg(long, default_value_t = 20.0)]
    pub s_max: f64,
    /// Also compute each row's smallest scene and rod clearance.
    #[arg(long)]
    pub clearance: bool,
    /// Which end frame the arm holds: 0 = the continuum end frame (the planner's); N = the
    /// last-edge frame of an N-edge discrete helix (the seed's Descartes targets: N = 100).
    #[arg(long, default_value_t = 0)]
    pub held_edges: usize,
    /// Per-row CSV output (`-`: standard output, before the JSON summary).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Step bound (rad): a larger step of any joint between two rows is a finding.
    #[arg(long, default_value_t = helixreach::planning::check::JUMP)]
    pub max_step: f64,
    /// Largest position error (m) of a row from the ray's pose curve (with --direction).
    #[arg(long, default_value_t = helixreach::planning::check::POSITION_TOLERANCE)]
    pub position_tolerance: f64,
    /// Largest rotation error (rad) of a row from the ray's pose curve (with --direction).
    #[arg(long, default_value_t = helixreach::planning::check::ROTATION_TOLERANCE)]
    pub rotation_tolerance: f64,
    /// Report the findings and exit 0 (the gate's exit code is 64 + the finding bits).
    #[arg(long)]
    pub report_only: bool,
    /// Replace an existing output file (never one of this command's inputs).
    #[arg(long)]
    pub force: bool,
}

/// Run `helixreach check`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let out = args.out.as_ref().map(|o| {
        Output::new(o)
            .force(args.force)
            .input(&args.trajectory)
            .input(std::path::Path::new(&args.rig))
    });
    if let Some(o) = &out {
        o.check()?;
    }
    let mut rig = Rig::load(&args.rig)?;
    if let Some(c) = &args.clamp {
        rig = rig
            .with_clamp_origin(parse_xyz("--clamp", c)?)
            .context("--clamp")?;
    }
    let direction = match &args.direction {
        Some(d) => {
            let [k, t, w] = parse_xyz("--direction", d)?;
            Some(Direction::new(k, t, w).with_context(|| format!("--direction `{d}`"))?)
        }
        None => None,
    };
    let azimuth = args
        .azimuth
        .unwrap_or_else(|| rig.azimuths.first().copied().unwrap_or(0.0));
    let checker = Checker::new(rig)?;
    let traj = checker.read(&args.trajectory)?;
    status!(
        "checking {} rows of {} ({}) on rig {}",
        traj.rows(),
        args.trajectory.display(),
        traj.format,
        checker.rig().name
    );
    let opt = CheckOptions {
        direction,
        azimuth,
        s_max: args.s_max,
        clearance: args.clearance,
        held_edges: args.held_edges,
        max_step: positive("--max-step", args.max_step)?,
        velocity_scale: 1.0,
        acceleration_scale: 1.0,
        position_tolerance: positive("--position-tolerance", args.position_tolerance)?,
        rotation_tolerance: positive("--rotation-tolerance", args.rotation_tolerance)?,
    };
    let rep = checker.check(&traj, &opt)?;
    if let Some(out) = &out {
        out.write(rep.rows_csv()?.as_bytes())?;
    }
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string_pretty(&rep.to_json())?)?;
    stdout.flush()?;
    let found: Vec<String> = rep
        .findings()
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(f, n)| format!("{n} {}", f.as_str()))
        .collect();
    let summary = format!(
        "{} limit violations, {} colliding rows, max joint step {:.4} rad",
        rep.limit_violations, rep.collisions, rep.max_joint_step.0
    );
    let mask = rep.finding_mask();
    if mask == 0 {
        eprintln!("pass: {summary}");
        return Ok(());
    }
    let message = format!("FAIL ({}): {summary}", found.join(", "));
    if args.report_only {
        eprintln!("{message} (--report-only: exit 0)");
        return Ok(());
    }
    Err(super::Verdict {
        code: 64 + mask,
        message,
    }
    .into())
}

fn positive(flag: &str, v: f64) -> anyhow::Result<f64> {
    anyhow::ensure!(
        v.is_finite() && v > 0.0,
        "{flag} {v}: must be finite and > 0"
    );
    Ok(v)
}
