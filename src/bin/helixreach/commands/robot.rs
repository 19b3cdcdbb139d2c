//! `helixreach robot`: print a robot's chain, joint limits and collision bodies.

use helixreach::robot::{CollisionModel, DisabledPairs, Shape};
use std::path::PathBuf;

/// Arguments of `helixreach robot`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach robot --robot panda",
    "$ helixreach robot --robot sawyer --write-disabled sawyer.collision.toml"
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
    /// Recompute the never-colliding link pairs by sampling and write them to this file
    /// (e.g. robots/sawyer.collision.toml).
    #[arg(long)]
    pub write_disabled: Option<PathBuf>,
    /// Random configurations sampled by --write-disabled: at least
    /// helixreach::limits::MIN_DISABLED_SAMPLES (10,000), so a pair that collides on 0.1 % of
    /// the configuration space is listed as never-colliding with probability < 5e-5; at most
    /// helixreach::limits::MAX_DISABLED_SAMPLES.
    #[arg(long, default_value_t = 50_000)]
    pub samples: usize,
    /// Seed of the sampling.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Replace an existing --write-disabled file (never the URDF itself).
    #[arg(long)]
    pub force: bool,
}

fn shape_text(s: &Shape) -> String {
    match *s {
        Shape::Sphere { radius } => format!("sphere r={radius}"),
        Shape::Box { half_extents: h } => {
            format!("box {}x{}x{}", 2.0 * h.x, 2.0 * h.y, 2.0 * h.z)
        }
        Shape::Cylinder {
            radius,
            half_length,
        } => format!("cylinder r={radius} length={}", 2.0 * half_length),
        Shape::Capsule {
            radius,
            half_length,
        } => format!("capsule r={radius} length={}", 2.0 * half_length),
    }
}

/// The `helixreach robot` line that regenerates a `--write-disabled` file: the robot, tool
/// link, load options, samples and seed it was made with (arguments with characters a shell
/// would split or expand are single-quoted).
fn regenerate_line(args: &Args, path: &std::path::Path) -> String {
    let quote = |a: &str| -> String {
        let plain = !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./:=,+@%".contains(c));
        if plain {
            a.to_string()
        } else {
            format!("'{}'", a.replace('\'', "'\\''"))
        }
    };
    let mut line = format!("helixreach robot --robot {}", quote(&args.robot));
    if let Some(tip) = &args.tip {
        line += &format!(" --tip {}", quote(tip));
    }
    for p in &args.load.package_path {
        line += &format!(" --package-path {}", quote(&p.to_string_lossy()));
    }
    for l in &args.load.no_collision {
        line += &format!(" --no-collision {}", quote(l));
    }
    line += &format!(
        " --samples {} --seed {} --write-disabled {}",
        args.samples,
        args.seed,
        quote(&path.to_string_lossy())
    );
    line
}

/// The `--write-disabled` output: never onto the URDF read.
fn disabled_out(args: &Args, path: &std::path::Path) -> helixreach::io::Output {
    helixreach::io::Output::new(path)
        .force(args.force)
        .input(std::path::Path::new(&args.robot))
}

/// Run `helixreach robot`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_range, MAX_DISABLED_SAMPLES, MIN_DISABLED_SAMPLES};
    if let Some(path) = &args.write_disabled {
        // Fewer samples would list pairs that do collide as never-colliding (0 samples: all).
        check_range(
            "--samples",
            args.samples,
            MIN_DISABLED_SAMPLES,
            MAX_DISABLED_SAMPLES,
        )?;
        disabled_out(&args, path).check()?;
    }
    let m = args.load.load(&args.robot, args.tip.as_deref())?;
    println!("robot {} ({})", m.name(), m.source());
    println!(
        "chain {} -> {} ({} joints)",
        m.root_link(),
        m.tip_link(),
        m.dof()
    );
    println!("joints (rad, rad/s):");
    for (i, j) in m.joints().iter().enumerate() {
        println!(
            "  {i} {:<12} {} -> {}  axis [{}, {}, {}]  limits [{}, {}]{}  velocity {}",
            j.name,
            j.parent_link,
            j.child_link,
            j.axis.x,
            j.axis.y,
            j.axis.z,
            j.lower,
            j.upper,
            if j.continuous {
                " (continuous: one turn)"
            } else {
                ""
            },
            j.velocity
        );
    }
    for (n, v) in m.frozen_joints() {
        println!("  frozen off-chain joint {n} = {v}");
    }
    let home = m.tool_pose(&vec![0.0; m.dof()])?;
    println!(
        "tool at q = 0: position [{:.6}, {:.6}, {:.6}]",
        home.pos.x, home.pos.y, home.pos.z
    );
    println!("collision bodies (link frame):");
    for l in m.links() {
        for c in &l.collision {
            let p = c.origin.pos;
            println!(
                "  {:<20} {:<36} at [{:.4}, {:.4}, {:.4}]",
                l.name,
                shape_text(&c.shape),
                p.x,
                p.y,
                p.z
            );
        }
    }
    for l in m.links() {
        for g in &l.meshes {
            let p = g.origin.pos;
            println!(
                "  {:<20} {:<36} at [{:.4}, {:.4}, {:.4}]",
                l.name,
                format!(
                    "mesh {} ({} triangles, hull {} vertices)",
                    g.mesh.file.display(),
                    g.mesh.triangles.len(),
                    g.mesh.hull_points.len()
                ),
                p.x,
                p.y,
                p.z
            );
        }
    }
    for s in m.ignored_geometry() {
        println!("  accepted without collision geometry: {s}");
    }
    if let Some(path) = &args.write_disabled {
        let d = DisabledPairs::compute(&m, args.samples, args.seed)?;
        let name = m.source().strip_prefix("builtin:").unwrap_or(m.source());
        let text = d.to_toml(name, &regenerate_line(&args, path))?;
        disabled_out(&args, path).write(text.as_bytes())?;
        status!(
            "wrote {} disabled pairs ({} samples) to {}",
            d.disabled.len(),
            d.samples,
            path.display()
        );
    }
    let cm = CollisionModel::for_model(&m)?;
    cm.announce();
    let disabled = DisabledPairs::for_model(&m)?;
    println!(
        "self-collision: {} body pairs checked; {} link pairs disabled ({} samples)",
        cm.n_self_pairs(),
        disabled.disabled.len(),
        disabled.samples
    );
    Ok(())
}
