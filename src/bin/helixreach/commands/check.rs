//! `helixreach check`: validate an existing joint trajectory on a rig (joint limits, self / scene
//! / rod collision, joint steps and jumps, pose error against the ray's pose curve). The logic is
//! `helixreach::planning::check`. Prints a JSON summary on stdout; `--out` writes the per-row CSV.
//! Exit 0 whenever the check ran, whatever it found; 2 on bad input.

use anyhow::Context;
use helixreach::directions::Direction;
use helixreach::planning::check::{CheckOptions, Checker};
use helixreach::planning::rig::{parse_xyz, Rig};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `helixreach check`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The trajectory: whitespace rows of joint values (the seed's files), a headerless CSV, or
    /// a CSV with joint-name (or q0..) columns (helixreach `plan`, a MoveIt export).
    #[arg(long)]
    pub joints: PathBuf,
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
    /// Per-row CSV output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Run `helixreach check`.
pub fn run(args: Args) -> anyhow::Result<()> {
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
    let traj = checker.read(&args.joints)?;
    eprintln!(
        "checking {} rows of {} ({}) on rig {}",
        traj.rows(),
        args.joints.display(),
        traj.format,
        checker.rig().name
    );
    let opt = CheckOptions {
        direction,
        azimuth,
        s_max: args.s_max,
        clearance: args.clearance,
        held_edges: args.held_edges,
    };
    let rep = checker.check(&traj, &opt)?;
    if let Some(out) = &args.out {
        helixreach::io::write_atomic(out, rep.rows_csv()?.as_bytes())?;
    }
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string_pretty(&rep.to_json())?)?;
    stdout.flush()?;
    eprintln!(
        "{}: {} limit violations, {} colliding rows, max joint step {:.4} rad",
        if rep.passed() { "pass" } else { "FAIL" },
        rep.limit_violations,
        rep.collisions,
        rep.max_joint_step.0
    );
    Ok(())
}
