//! `helixreach layout`: candidate clamp placements over a bench region, the directions each can
//! test (full planner), the K placements that cover the most, the assignment of directions to
//! placements, one rig file per placement, figures (see `helixreach::layout`).

use super::args::DirectionArgs;
use helixreach::layout::candidates::{parse_tilts, Region};
use helixreach::layout::{read_references, run as run_layout, LayoutOptions, RunControl};
use helixreach::planning::rig::{azimuth_grid, Rig, RollMode};
use helixreach::sweep::driver::Shard;
use helixreach::sweep::reach::BoundaryTable;
use std::path::PathBuf;

/// Arguments of `helixreach layout`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach layout --fibonacci 4 --quarter --spacing 0.2 --placements 1 --out layout",
    "> helixreach layout --fibonacci 173 --quarter --spacing 0.05 --placements 3 --out layout"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The direction set.
    #[command(flatten)]
    pub dirs: DirectionArgs,
    /// Candidate region `x0:x1,y0:y1,z0:z1` (m, robot base frame); default ±0.15 m in x and y
    /// around the rig's clamp, at its height.
    #[arg(long, allow_hyphen_values = true)]
    pub region: Option<String>,
    /// Grid spacing (m).
    #[arg(long, default_value_t = helixreach::layout::DEFAULT_SPACING, allow_hyphen_values = true)]
    pub spacing: f64,
    /// Clamp-axis tilts in degrees, comma-separated (0 = the rig's orientation).
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    pub tilts: String,
    /// Headings per non-zero tilt (evenly spaced about the vertical).
    #[arg(long, default_value_t = 4)]
    pub headings: usize,
    /// Number of placements K.
    #[arg(long, default_value_t = 3)]
    pub placements: usize,
    /// Drive the rod to s*·(1 + M), 0 ≤ M ≤ 1 (0: to the boundary); overrides the rig's
    /// `planner.margin`.
    #[arg(long, value_name = "M", value_parser = super::args::parse_margin, allow_hyphen_values = true)]
    pub margin: Option<f64>,
    /// Roll mode (`fixed` or `motor`); default: the rig's.
    #[arg(long)]
    pub roll: Option<RollMode>,
    /// Try N azimuths per ray (default: the rig's choices).
    #[arg(long)]
    pub azimuths: Option<usize>,
    /// How each ray is decided: `ladder` or `exact` (the search of the valid set; overrides the
    /// rig's `planner.search`).
    #[arg(long)]
    pub search: Option<String>,
    /// s* per direction from a `helixreach boundary` CSV (default: continuum).
    #[arg(long)]
    pub boundary: Option<PathBuf>,
    /// Reference clamp positions to compare with (a seed `trajectories.csv`: each direction's
    /// `clamp_x,clamp_y,clamp_z`); evaluated, never chosen.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Branch-and-bound node budget per K of the exact cover.
    #[arg(long, default_value_t = helixreach::layout::EXACT_NODE_LIMIT)]
    pub exact_nodes: u64,
    /// Plan every ray, without the sampled end-pose check (for comparisons; see
    /// `helixreach::layout::precheck`).
    #[arg(long)]
    pub no_end_pose_check: bool,
    /// Process only shard I/N of the (candidate, direction) rays; merge the shards' rays.csv
    /// with `helixreach merge --key-columns 4`, then rerun with --resume.
    #[arg(long, allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Continue an existing run in --out (same settings only).
    #[arg(long)]
    pub resume: bool,
    /// Replace an existing run in --out (once the new rays are complete).
    #[arg(long, conflicts_with = "resume")]
    pub force: bool,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
}

/// Run `helixreach layout`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let dirs = args.dirs.load()?;
    let mut rig = Rig::load(&args.rig)?;
    if let Some(s) = &args.search {
        rig.planner.search = s.parse().map_err(|e| anyhow::anyhow!("--search: {e}"))?;
    }
    let mut opts = LayoutOptions::around(&rig);
    if let Some(r) = &args.region {
        opts.region = r.parse::<Region>()?;
    }
    opts.spacing = args.spacing;
    opts.tilts_deg = parse_tilts(&args.tilts)?;
    opts.headings = args.headings;
    opts.placements = args.placements;
    opts.margin = args.margin;
    opts.roll = args.roll;
    opts.azimuths = match args.azimuths {
        Some(0) => anyhow::bail!("--azimuths 0: need at least one azimuth"),
        Some(n) => Some(azimuth_grid(helixreach::limits::check_size(
            "--azimuths",
            n,
            helixreach::limits::MAX_AZIMUTHS,
        )?)),
        None => None,
    };
    opts.exact_node_limit = args.exact_nodes;
    opts.end_pose_check = !args.no_end_pose_check;
    if let Some(p) = &args.reference {
        opts.references = read_references(p, &dirs)?;
    }
    let table = match &args.boundary {
        Some(p) => Some(BoundaryTable::read(p)?),
        None => None,
    };
    super::gravity_gate(
        &rig,
        &args.rig,
        opts.margin,
        table.as_ref(),
        opts.azimuths.as_deref().unwrap_or(&rig.azimuths),
    )?;
    let control = RunControl {
        resume: args.resume,
        force: args.force,
        shard: args.shard,
        progress: !super::global().quiet,
        par: helixreach::par::Par::from_option(super::global().threads)?,
    };
    let t0 = std::time::Instant::now();
    let report = run_layout(&rig, &dirs, table.as_ref(), &opts, &control, &args.out)?;
    let Some(rep) = report else {
        status!(
            "layout: shard written in {:.1} s",
            t0.elapsed().as_secs_f64()
        );
        return Ok(());
    };
    let nd = rep.n_dirs;
    let pct = |n: usize| 100.0 * n as f64 / nd as f64;
    let best_single = rep.covered[..rep.n_grid].iter().copied().max().unwrap_or(0);
    if best_single == 0 {
        eprintln!(
            "layout: no candidate in the region can test any of the {nd} directions \
             (rays decided: {:?}); see {}/candidates.csv",
            rep.decided,
            args.out.display()
        );
    }
    for c in &rep.by_k {
        status!(
            "layout: K = {}: exact {} ({:.1} %{}), greedy {} ({:.1} %)",
            c.k,
            c.exact.covered,
            pct(c.exact.covered),
            if c.exact.proven {
                ", proven"
            } else {
                ", budget hit: lower bound"
            },
            c.greedy.covered,
            pct(c.greedy.covered)
        );
    }
    if let Some(r) = &rep.reference {
        status!(
            "layout: reference positions ({}): own position {}/{} ({:.1} %), union {} ({:.1} %)",
            r.positions,
            r.own,
            r.own_total,
            100.0 * r.own as f64 / r.own_total.max(1) as f64,
            r.union,
            pct(r.union)
        );
    }
    status!(
        "layout: {:.1} % of rays decided without per-ray planning ({:?}); {:.1} s -> {}",
        100.0 * rep.cheap_fraction(),
        rep.decided,
        t0.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}
