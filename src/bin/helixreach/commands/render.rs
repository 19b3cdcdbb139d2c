//! `helixreach render`: snapshots of the robot, rod and scene along a planned trajectory
//! (strip PNG + SVG, per-frame clearances CSV, optional animated GIF). Glue over
//! [`helixreach::plot::render::render_trajectory`].

use helixreach::planning::rig::Rig;
use helixreach::plot::render::{
    render_trajectory, ClearanceKind, FrameSelection, RenderOptions, TrajectoryRender, View,
};
use std::path::PathBuf;

/// Arguments of `helixreach render`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach plan --direction 0.6,0.79,0.12 --out trajectory.csv",
    "$ helixreach render --trajectory trajectory.csv --out frames"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// Trajectory CSV as `helixreach plan` writes it (a `phase` column is used when present).
    #[arg(long, value_name = "FILE")]
    pub trajectory: PathBuf,
    /// N frames evenly in time instead of the default (s = 0, ¼, ½, ¾, 1 of s*, the end, every
    /// reconfiguration).
    #[arg(long)]
    pub frames: Option<usize>,
    /// s* for the default frames; default: the continuum boundary of the trajectory's direction.
    #[arg(long, allow_negative_numbers = true)]
    pub s_star: Option<f64>,
    /// Views, comma-separated, from front, side, top, iso.
    #[arg(long, default_value = "front,side,top,iso")]
    pub views: String,
    /// Write link names on the links.
    #[arg(long)]
    pub labels: bool,
    /// Also write an animated GIF of the whole trajectory (`render.gif`).
    #[arg(long)]
    pub gif: bool,
    /// GIF frames, evenly in time.
    #[arg(long, default_value_t = 100)]
    pub gif_frames: usize,
    /// GIF frame delay (ms).
    #[arg(long, default_value_t = 100)]
    pub gif_delay_ms: u32,
    /// Helix azimuth (rad) when the trajectory has neither an `azimuth` column nor rod ends.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f64,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

/// Run `helixreach render`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_size, MAX_FRAMES};
    if let Some(n) = args.frames {
        check_size("--frames", n, MAX_FRAMES)?;
    }
    check_size("--gif-frames", args.gif_frames, MAX_FRAMES)?;
    let rig = Rig::load(&args.rig)?;
    let views = View::parse_list(&args.views)?;
    let frames = match args.frames {
        Some(n) => FrameSelection::Even(n),
        None => FrameSelection::Default {
            s_star: args.s_star,
        },
    };
    let d = TrajectoryRender::default();
    let opts = TrajectoryRender {
        frames,
        strip: RenderOptions {
            views: views.clone(),
            labels: args.labels,
            ..d.strip
        },
        gif_frames: args.gif.then_some(args.gif_frames),
        gif: RenderOptions {
            views,
            labels: args.labels,
            ..d.gif
        },
        gif_delay_ms: args.gif_delay_ms,
        azimuth: args.azimuth,
        progress: !super::global().quiet,
        par: helixreach::par::Par::from_option(super::global().threads)?,
    };
    let t0 = std::time::Instant::now();
    let sum = render_trajectory(&rig, &args.trajectory, &opts, &args.out)?;
    let mins: Vec<String> = ClearanceKind::ALL
        .iter()
        .zip(sum.min_clearance)
        .map(|(k, m)| match m {
            Some(m) => format!("{} {:.4} m", k.as_str(), m),
            None => format!("{} -", k.as_str()),
        })
        .collect();
    status!(
        "render: {} frames (azimuth {:.4} rad), smallest clearance over them: {}; wrote {}, {}, {}{} in {:.2} s",
        sum.frames.len(),
        (sum.azimuth * 1e4).round() / 1e4 + 0.0,
        mins.join(", "),
        sum.strip_png.display(),
        sum.strip_svg.display(),
        sum.frames_csv.display(),
        sum.gif
            .as_ref()
            .map_or(String::new(), |g| format!(", {}", g.display())),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
