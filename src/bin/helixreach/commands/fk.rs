//! `helixreach fk`: the tool pose of a URDF robot at a joint vector (URDF root frame, metres), in
//! the one pose format of the command line: `x,y,z,qw,qx,qy,qz` (unit quaternion, scalar first,
//! `qw ≥ 0`) on one line, what `ik --pose` reads; `--matrix`: the 4×4 homogeneous matrix, one
//! row per line, what `ik --matrix --pose` reads.

use anyhow::Context;
use helixreach::records::fmt_real;
use helixreach::robot::pose_to_xyz_wxyz;

/// Arguments of `helixreach fk`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach fk --robot sawyer --joints 0,-1,0,1.5,0,-0.5,0",
    "$ helixreach fk --robot sawyer --joints 0,-1,0,1.5,0,-0.5,0 --matrix"
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
    /// Joint values (rad), comma-separated, root first.
    #[arg(long, allow_hyphen_values = true)]
    pub joints: String,
    /// Print the 4×4 homogeneous matrix (four lines `r00,r01,r02,x` … `0,0,0,1`) instead of
    /// `x,y,z,qw,qx,qy,qz`.
    #[arg(long)]
    pub matrix: bool,
}

/// Parse a comma-separated list of numbers; `what` names the option in errors.
pub fn parse_list(what: &str, s: &str) -> anyhow::Result<Vec<f64>> {
    s.split(',')
        .enumerate()
        .map(|(i, t)| {
            t.trim()
                .parse::<f64>()
                .with_context(|| format!("{what}: value {} ({t:?}) is not a number", i + 1))
        })
        .collect()
}

/// Run `helixreach fk`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let model = args.load.load(&args.robot, args.tip.as_deref())?;
    let q = parse_list("--joints", &args.joints)?;
    let f = model.tool_pose(&q)?;
    let line = |v: &[f64]| v.iter().map(|&x| fmt_real(x)).collect::<Vec<_>>().join(",");
    if args.matrix {
        let r = f.rot;
        for i in 0..3 {
            println!("{}", line(&[r[(i, 0)], r[(i, 1)], r[(i, 2)], f.pos[i]]));
        }
        println!("0,0,0,1");
    } else {
        println!("{}", line(&pose_to_xyz_wxyz(&f)));
    }
    Ok(())
}
