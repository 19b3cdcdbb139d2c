//! `helixreach plan`: plan one ray on a rig and write its time-parametrized joint + motor
//! trajectory (CSV; optionally the arm's ROS 2 `trajectory_msgs/msg/JointTrajectory` as JSON,
//! as `ros2 topic pub` YAML and as a `FollowJointTrajectory` goal YAML):
//! load to s*·(1 + margin), hold, unload along the same path (a `phase` column marks them and the
//! self-motion reconfigurations).
//!
//! A ray the robot cannot drive to its target s*·(1 + margin) (class `partial` or `blocked`) is
//! a "no": nothing is written and the exit code is 3 ([`super::EXIT_NOT_TESTABLE`]). With
//! `--allow-partial` the trajectory is written as far as it goes. Every output `F` has the
//! sidecar `F.meta.json` naming `class`, `cause`, `s_reached`, `s_target`, `s_star`, the
//! direction and the phases (`helixreach::records::trajectory::TrajectoryMeta`).

use super::args::RigOverrideArgs;
use anyhow::Context;
use helixreach::directions::Direction;
use helixreach::io::Output;
use helixreach::planning::campaign::plan_run;
use helixreach::planning::planner::{Planner, ReachClass};
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::records::trajectory::{
    message_json, message_yaml, trajectory_csv, trajectory_meta_json, Channels, JointTrajectoryMsg,
};
use helixreach::sweep::reach::s_star_of;
use std::path::PathBuf;

/// Arguments of `helixreach plan`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach plan --direction 0.6,0.79,0.12 --out trajectory.csv --json trajectory.json",
    "$ helixreach plan --direction 0.92,0.12,0.36 --allow-partial --margin 0 --out partial.csv"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The ray's direction `κ,τ,ω` (normalized; κ ≥ 0).
    #[arg(long, allow_hyphen_values = true)]
    pub direction: String,
    /// Helix azimuth α (rad); default: the best of the rig's azimuth choices.
    #[arg(long, allow_hyphen_values = true)]
    pub azimuth: Option<f64>,
    /// Roll mode (`fixed` or `motor`); default: the rig's.
    #[arg(long)]
    pub roll: Option<RollMode>,
    /// The boundary s* along the ray; default: the continuum conjugate-point test.
    #[arg(long, allow_negative_numbers = true)]
    pub s_star: Option<f64>,
    /// Waypoints uniform in s instead of the rig's spacing (e.g. 2000, the seed's density); at
    /// most the rig's `max_waypoints`.
    #[arg(long)]
    pub waypoints: Option<usize>,
    /// Overrides of the rig's settings.
    #[command(flatten)]
    pub overrides: RigOverrideArgs,
    /// Output trajectory CSV (`-`: standard output).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the arm's trajectory as a ROS 2 `trajectory_msgs/msg/JointTrajectory` in JSON
    /// (exactly the message's fields).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Also write the arm's trajectory as the YAML `ros2 topic pub … trajectory_msgs/msg/
    /// JointTrajectory "$(cat F)"` reads.
    #[arg(long)]
    pub yaml: Option<PathBuf>,
    /// Also write the arm's trajectory as a `control_msgs/action/FollowJointTrajectory` goal in
    /// YAML (`ros2 action send_goal … "$(cat F)"`).
    #[arg(long)]
    pub goal_yaml: Option<PathBuf>,
    /// Also write a ROS 2 bag (MCAP, CDR): the arm's and the rod motor's `JointTrajectory` on
    /// their own topics and the sidecar JSON (outcome, phases) as an annotation topic
    /// (`helixreach::records::ros2_bag`).
    #[arg(long)]
    pub bag: Option<PathBuf>,
    /// Write the trajectory of a ray that cannot be driven to its target, as far as it goes
    /// (its sidecar says `partial` or `blocked`, with the cause and `s_reached`); without it
    /// such a ray writes nothing and exits 3.
    #[arg(long)]
    pub allow_partial: bool,
    /// Replace an existing output file (never one of this command's inputs).
    #[arg(long)]
    pub force: bool,
}

fn parse_direction(s: &str) -> anyhow::Result<Direction> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--direction `{s}`: expected three numbers κ,τ,ω"))?;
    anyhow::ensure!(
        v.len() == 3,
        "--direction `{s}`: expected three numbers κ,τ,ω"
    );
    Ok(Direction::new(v[0], v[1], v[2])?)
}

/// The rig overrides of `--margin`, `--clamp` and `--no-reconfiguration`.
/// Run `helixreach plan`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let rig_file = std::path::Path::new(&args.rig);
    let out = Output::new(&args.out).force(args.force).input(rig_file);
    out.check()?;
    // Every further output: never onto the rig or the trajectory CSV.
    // (output, which message: 0 JSON, 1 YAML, 2 goal YAML, 3 ROS 2 bag)
    let extra: Vec<(Output, usize)> = [&args.json, &args.yaml, &args.goal_yaml, &args.bag]
        .into_iter()
        .enumerate()
        .filter_map(|(k, p)| p.as_ref().map(|j| (j, k)))
        .map(|(j, k)| {
            let o = Output::new(j)
                .force(args.force)
                .input(rig_file)
                .input(&args.out);
            (o, k)
        })
        .collect();
    for (j, _) in &extra {
        j.check()?;
    }
    let dir = parse_direction(&args.direction)?;
    let rig = Rig::load(&args.rig)?;
    let mut rig = args.overrides.apply(&rig)?;
    if let Some(n) = args.waypoints {
        let max = rig.planner.max_waypoints;
        anyhow::ensure!(
            (2..=max).contains(&n),
            "--waypoints {n}: must be in 2..={max} (the rig's max_waypoints, {})",
            rig.source
        );
        rig.planner.waypoints = n;
    }
    let roll = args.roll.unwrap_or(rig.roll);
    let azimuths = match args.azimuth {
        Some(a) => vec![a],
        None => rig.azimuths.clone(),
    };
    let s_star = match args.s_star {
        Some(s) => s,
        None => {
            super::gravity_gate(&rig, &args.rig, None, None, &azimuths)?;
            s_star_of(&dir, None)?
        }
    };
    let planner = Planner::new(rig)?;
    let t0 = std::time::Instant::now();
    // The bifurcation type decides the margin past s* only when the rig's margins differ.
    let plan = plan_run(&planner, &dir, s_star, &azimuths, roll)?;
    let dt = t0.elapsed().as_secs_f64();
    let assumed = plan.assumed_type.map_or("any", |t| t.name());
    if plan.class != ReachClass::Testable && !args.allow_partial {
        return Err(super::Verdict {
            code: super::EXIT_NOT_TESTABLE,
            message: format!(
                "{}: the robot drives the ray to s = {} of its target {} (s* = {}, cause {}; \
                 reconfiguration {}); nothing written (--allow-partial writes the trajectory as \
                 far as it goes)",
                plan.class.as_str(),
                plan.s_reached,
                plan.s_end,
                plan.s_star,
                plan.cause.map_or("-", |c| c.as_str()),
                planner.reconfiguration(plan.roll),
            ),
        }
        .into());
    }
    let traj = planner.trajectory(&plan)?;
    let meta = trajectory_meta_json(&traj)?;
    let mut files = vec![(out, trajectory_csv(&traj)?.into_bytes())];
    let arm = JointTrajectoryMsg::new(&traj, Channels::Arm)?;
    for (o, k) in extra {
        let bytes = match k {
            0 => message_json(&arm)?.into_bytes(),
            1 => message_yaml(&arm, false).into_bytes(),
            2 => message_yaml(&arm, true).into_bytes(),
            _ => helixreach::records::ros2_bag::trajectory_bag(&traj)?,
        };
        files.push((o, bytes));
    }
    for (o, bytes) in files {
        o.write_with_sidecar(&bytes, meta.as_bytes())?;
    }
    status!(
        "{}: s* = {}, s_reached = {} of {} (bifurcation assumed: {assumed}) ({} of {} waypoints), \
         cause {}, azimuth {}, roll {}, {} reconfigurations (reconfiguration {}), {} back-offs, cost {:.4}, max joint step {:.4} rad, \
         duration {:.1} s (load, hold, unload); planned in {:.3} s",
        plan.class.as_str(),
        plan.s_star,
        plan.s_reached,
        plan.s_end,
        plan.n_reached,
        plan.n_waypoints,
        plan.cause.map_or("-", |c| c.as_str()),
        plan.azimuth,
        plan.roll,
        plan.reconfigurations,
        planner.reconfiguration(plan.roll),
        plan.backoffs,
        plan.path_cost,
        plan.max_joint_step,
        traj.duration(),
        dt
    );
    Ok(())
}
