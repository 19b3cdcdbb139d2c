//! `helixreach check`: validate an existing joint trajectory on a rig (joint limits, self / scene
//! / rod collision, joint steps and jumps, pose error against the ray's pose curve). The logic is
//! `helixreach::planning::check`. Prints a JSON summary on stdout; `--out` writes the per-row CSV
//! (`self_collision` 0/1 and `self_pairs`, every self-colliding link pair, among its columns).
//! `--robot URDF` (with `--tip`, `--package-path`, `--srdf`, `--padding`) checks a robot without a
//! rig: limits, self-collision, steps and the URDF speeds (`Checker::for_robot`).
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
use helixreach::planning::rig::{parse_xyz, Rig, RobotSpec};
use helixreach::robot::collision::{CollisionSettings, MAX_PADDING};
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
    /// Check a robot without a rig: a URDF file or a built-in robot (sawyer, panda, iiwa14).
    /// Joint limits, self-collision, steps and the URDF speed limits; no scene, rod, motor,
    /// pose or acceleration limits.
    #[arg(long, conflicts_with_all = ["rig", "direction", "azimuth", "clamp"])]
    pub robot: Option<String>,
    /// With --robot: the tool link, which fixes the chain and its joints (default: the robot's).
    #[arg(long, requires = "robot")]
    pub tip: Option<String>,
    /// With --robot: mesh search paths and links without collision geometry.
    #[command(flatten)]
    pub load: super::args::RobotLoadArgs,
    /// With --robot: a MoveIt SRDF whose <disable_collisions> pairs are not checked.
    #[arg(long, requires = "robot")]
    pub srdf: Option<PathBuf>,
    /// With --robot: padding of every collision body (m).
    #[arg(long, requires = "robot", default_value_t = 0.0)]
    pub padding: f64,
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
        let mut o = Output::new(o)
            .force(args.force)
            .input(&args.trajectory)
            .input(std::path::Path::new(&args.rig));
        if let Some(r) = &args.robot {
            o = o.input(std::path::Path::new(r));
        }
        if let Some(s) = &args.srdf {
            o = o.input(s);
        }
        o
    });
    if let Some(o) = &out {
        o.check()?;
    }
    let (checker, direction, azimuth) = match &args.robot {
        Some(robot) => (robot_checker(&args, robot)?, None, 0.0),
        None => rig_checker(&args)?,
    };
    finish(&args, out.as_ref(), &checker, direction, azimuth)
}

/// The checker of `--robot` (no rig).
fn robot_checker(args: &Args, robot: &str) -> anyhow::Result<Checker> {
    let tip = match &args.tip {
        Some(t) => t.clone(),
        None => args.load.load(robot, None)?.tip_link().to_string(),
    };
    let spec = RobotSpec {
        urdf: robot.to_string(),
        dir: PathBuf::from("."),
        tip_link: tip,
        package_paths: args.load.package_path.clone(),
        no_collision: args.load.no_collision.clone(),
        collision: CollisionSettings {
            padding: args.padding,
            link_padding: Vec::new(),
            kind: Default::default(),
        },
        srdf: args.srdf.clone(),
    };
    if !(args.padding.is_finite() && (0.0..=MAX_PADDING).contains(&args.padding)) {
        anyhow::bail!(
            "--padding {}: must be finite, in 0..={MAX_PADDING} m",
            args.padding
        );
    }
    Ok(Checker::for_robot(spec)?)
}

/// The checker of `--rig` (with `--clamp`), the direction and the azimuth.
fn rig_checker(args: &Args) -> anyhow::Result<(Checker, Option<Direction>, f64)> {
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
    Ok((Checker::new(rig)?, direction, azimuth))
}

/// Check the trajectory, write the rows, print the summary; the verdict.
fn finish(
    args: &Args,
    out: Option<&Output>,
    checker: &Checker,
    direction: Option<Direction>,
    azimuth: f64,
) -> anyhow::Result<()> {
    let traj =
        helixreach::records::trajectory::read_joint_file(&args.trajectory, &checker.joint_names())?;
    status!(
        "checking {} rows of {} ({}) on {}",
        traj.rows(),
        args.trajectory.display(),
        traj.format,
        if checker.robot_only() {
            format!("robot {} (no rig)", checker.model().name())
        } else {
            format!("rig {}", checker.rig().name)
        }
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
    if let Some(out) = out {
        out.write(helixreach::records::check::check_rows_csv(&rep)?.as_bytes())?;
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
