//! `helixreach fk`: the tool pose of a URDF robot at a joint vector, as JSON
//! `{"position":[x,y,z],"rotation":[[…],[…],[…]]}` (rows of R, URDF root frame, metres).

use anyhow::Context;

/// Arguments of `helixreach fk`.
#[derive(Debug, clap::Args)]
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
    let r = f.rot;
    let json = serde_json::json!({
        "position": [f.pos.x, f.pos.y, f.pos.z],
        "rotation": [
            [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
            [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
            [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
        ],
    });
    println!("{json}");
    Ok(())
}
