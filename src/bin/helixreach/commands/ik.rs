//! `helixreach ik`: every IK solution found for a tool pose, as CSV on stdout: one row per
//! solution with the joint values (rad), the position error (m) and the rotation error (rad; the
//! tool-axis angle with `--free-roll`), both measured by FK. The pose is `fk`'s output:
//! `x,y,z,qw,qx,qy,qz`, or with `--matrix` the 4×4 homogeneous matrix.

use super::fk::parse_list;
use anyhow::Context;
use helixreach::records::ik::{ik_csv, IkSolutionRecord};
use helixreach::robot::{pose_from_matrix, pose_from_xyz_wxyz, IkParams, IkSolver, IkTarget};
use std::io::Write;

/// Arguments of `helixreach ik`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach ik --robot sawyer --pose 0.6,0.1,0.3,0,1,0,0",
    "$ helixreach ik --robot sawyer --samples 2 --pose \"$(helixreach fk --robot sawyer --joints 0,-1,0,1.5,0,-0.5,0)\""
))]
pub struct Args {
    /// URDF file, or a built-in robot: sawyer, panda, iiwa14.
    #[arg(long)]
    pub robot: String,
    /// Tool link (default: the robot's tool link).
    #[arg(long)]
    pub tip: Option<String>,
    /// Mesh search paths and links without collision geometry.
    #[command(flatten)]
    pub load: super::args::RobotLoadArgs,
    /// Tool pose in the root frame: x,y,z,qw,qx,qy,qz (m; unit quaternion, scalar first), as
    /// `fk` prints it.
    #[arg(long, allow_hyphen_values = true)]
    pub pose: String,
    /// `--pose` is the 4×4 homogeneous matrix instead: 16 values row by row, separated by commas
    /// or white space (as `fk --matrix` prints it).
    #[arg(long)]
    pub matrix: bool,
    /// Leave the roll about the tool z axis free (only position + tool axis are imposed).
    #[arg(long)]
    pub free_roll: bool,
    /// Number of values of the redundancy joint (evenly spaced over its range), at most
    /// helixreach::limits::MAX_IK_SAMPLES.
    #[arg(long, default_value_t = 8)]
    pub samples: usize,
    /// The joint locked as the redundancy parameter (0-based).
    #[arg(long, default_value_t = 0)]
    pub redundancy_joint: usize,
    /// Random restarts per redundancy value, at most helixreach::limits::MAX_IK_RESTARTS.
    #[arg(long, default_value_t = 50)]
    pub restarts: usize,
    /// Seed of the random restarts.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// Run `helixreach ik`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_size, MAX_IK_RESTARTS, MAX_IK_SAMPLES};
    check_size("--samples", args.samples, MAX_IK_SAMPLES)?;
    check_size("--restarts", args.restarts, MAX_IK_RESTARTS)?;
    let model = args.load.load(&args.robot, args.tip.as_deref())?;
    let pose = if args.matrix {
        // fk --matrix's four lines of commas, or values separated by white space only.
        let joined = if args.pose.contains(',') {
            let lines: Vec<&str> = args.pose.trim().lines().map(str::trim).collect();
            lines.join(",")
        } else {
            args.pose.split_whitespace().collect::<Vec<_>>().join(",")
        };
        let v = parse_list("--pose", &joined)?;
        pose_from_matrix(&v).context("--pose (with --matrix)")?
    } else {
        pose_from_xyz_wxyz(&parse_list("--pose", &args.pose)?).context("--pose")?
    };
    let mut target = IkTarget::pose(pose)?;
    if args.free_roll {
        target = target.free_roll();
    }
    let params = IkParams {
        samples: args.samples,
        redundancy_joint: Some(args.redundancy_joint),
        restarts: args.restarts,
        rng_seed: args.seed,
        ..IkParams::default()
    };
    let solver = IkSolver::new(&model, params)?;
    let sols = solver.solve_all(&target, &[]);
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let names: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
    let rows: Vec<IkSolutionRecord<'_>> = sols
        .iter()
        .map(|s| IkSolutionRecord {
            q: s.joints(),
            position_error: s.position_error,
            rotation_error: s.rotation_error,
        })
        .collect();
    out.write_all(ik_csv(&names, &rows)?.as_bytes())?;
    out.flush()?;
    status!("{} solutions", sols.len());
    Ok(())
}
