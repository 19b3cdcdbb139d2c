//! `helixreach rig init`: a commented rig for any URDF arm, with the clamp placed in front of
//! the robot where it holds the straight rod (`helixreach::planning::rig_init`), that `reach`,
//! `plan`, `layout` and `render` accept as written.

use helixreach::io::Output;
use helixreach::planning::rig_init::{
    rig_init, RigInitOptions, DEFAULT_PADDING, DEFAULT_TOOL_OFFSET, SCORE_DIRECTIONS,
};
use std::path::PathBuf;

/// Arguments of `helixreach rig`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach rig init --robot panda --tip fer_link8 --out panda_rig.toml",
    "$ helixreach reach --rig panda_rig.toml --fibonacci 4 --quarter --out reach.csv",
    "> helixreach rig init --robot my_arm.urdf --tip tool0 --package-path ~/ws/src --out my_rig.toml"
))]
pub struct Args {
    #[command(subcommand)]
    pub command: RigCommand,
}

/// The `rig` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum RigCommand {
    /// Write a commented rig for a URDF arm: robot, tip, tool offset, a clamp in front of the
    /// robot within reach, the rod, padding, the collision model, an empty scene.
    Init(InitArgs),
}

/// Arguments of `helixreach rig init`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach rig init --robot panda --tip fer_link8 --out panda_rig.toml",
    "$ helixreach reach --rig panda_rig.toml --fibonacci 4 --quarter --out reach.csv",
    "> helixreach rig init --robot my_arm.urdf --tip tool0 --package-path ~/ws/src --out my_rig.toml"
))]
pub struct InitArgs {
    /// URDF file, or a built-in robot: sawyer, panda, iiwa14.
    #[arg(long)]
    pub robot: String,
    /// The link that carries the rod motor (the flange or the tool link).
    #[arg(long)]
    pub tip: String,
    /// Mesh search paths and links without collision geometry.
    #[command(flatten)]
    pub load: super::args::RobotLoadArgs,
    /// A MoveIt SRDF whose <disable_collisions> pairs are not checked.
    #[arg(long)]
    pub srdf: Option<PathBuf>,
    /// The rod end's distance from the tip link along its z axis (m).
    #[arg(long, default_value_t = DEFAULT_TOOL_OFFSET)]
    pub tool_offset: f64,
    /// Padding of every collision body of the robot (m).
    #[arg(long, default_value_t = DEFAULT_PADDING)]
    pub padding: f64,
    /// Rod length (m); default the seed's 0.51 m, shorter for a small arm.
    #[arg(long)]
    pub rod_length: Option<f64>,
    /// The rig's name (default: the output file's stem).
    #[arg(long)]
    pub name: Option<String>,
    /// Output rig TOML (`-`: standard output).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing output file (never the URDF or the SRDF).
    #[arg(long)]
    pub force: bool,
}

/// Run `helixreach rig`.
pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        RigCommand::Init(a) => init(a),
    }
}

fn init(args: InitArgs) -> anyhow::Result<()> {
    let mut out = Output::new(&args.out)
        .force(args.force)
        .input(std::path::Path::new(&args.robot));
    if let Some(s) = &args.srdf {
        out = out.input(s);
    }
    out.check()?;
    let stdout = helixreach::io::is_stdout(&args.out);
    let dir = if stdout {
        std::env::current_dir()?
    } else {
        match args.out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    let name = match &args.name {
        Some(n) => n.clone(),
        None if !stdout => args
            .out
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "my-rig".into()),
        None => "my-rig".into(),
    };
    let opts = RigInitOptions {
        robot: args.robot.clone(),
        tip_link: args.tip.clone(),
        package_paths: args.load.package_path.clone(),
        no_collision: args.load.no_collision.clone(),
        srdf: args.srdf.clone(),
        name,
        tool_offset: args.tool_offset,
        padding: args.padding,
        rod_length: args.rod_length,
        par: helixreach::par::Par::from_option(super::global().threads)?,
    };
    let r = rig_init(&opts, &dir)?;
    out.write(r.text.as_bytes())?;
    let c = &r.candidates[r.chosen];
    status!(
        "rig init: {} joints; clamp at [{}, {}, {}] (reach {:.3} m from [{:.3}, {:.3}, {:.3}]), \
         {} start configurations, {} of {SCORE_DIRECTIONS} quarter-sphere end poses held \
         (best of {} candidates){}{}{}",
        r.dof,
        c.origin[0],
        c.origin[1],
        c.origin[2],
        r.reach_sampled,
        r.reach.centre.x,
        r.reach.centre.y,
        r.reach.centre.z,
        c.starts,
        c.score,
        r.candidates.len(),
        if r.dof == 7 {
            ""
        } else {
            "; not 7 joints: no self-motion at a full pose, every IK branch is a start and \
             reconfiguration is impossible in roll fixed (in roll motor a 6-joint arm's roll is \
             its self-motion)"
        },
        if r.continuous.is_empty() {
            String::new()
        } else {
            format!(
                "; continuous joints {} modelled as [-pi, pi] (a path that would turn one past \
                 +-pi stops there)",
                r.continuous.join(", ")
            )
        },
        if stdout {
            String::new()
        } else {
            format!(" -> {}", args.out.display())
        }
    );
    Ok(())
}
