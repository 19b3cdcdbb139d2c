//! `helixreach reach`: the reachability sweep of a rig over a direction set
//! (see `helixreach::sweep::reach`).

use super::args::{checkpoint_interval, DirectionArgs, RigOverrideArgs};
use helixreach::experiment::RollSummary;
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{azimuth_grid, Rig, RollMode};
use helixreach::sweep::driver::{Shard, SweepOptions};
use helixreach::sweep::reach::{run as run_reach, BoundaryTable, ReachOptions, REACH_HEADER};
use std::path::PathBuf;

/// Arguments of `helixreach reach`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach reach --fibonacci 6 --quarter --out reach.csv",
    "> helixreach reach --fibonacci 2000 --quarter --roll motor --out reach.csv",
    "> helixreach boundary --method der --gravity --rig my-rig.toml --azimuth 0 --fibonacci 200 --quarter --out b0.csv",
    "> helixreach boundary --method der --gravity --rig my-rig.toml --azimuth 3.141592653589793 --fibonacci 200 --quarter --out b1.csv",
    "> helixreach reach --rig my-rig.toml --azimuths 2 --boundary b0.csv --boundary b1.csv --fibonacci 200 --quarter --out reach.csv"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file.
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The direction set.
    #[command(flatten)]
    pub dirs: DirectionArgs,
    /// s* per direction from a `helixreach boundary` CSV (default: computed, continuum).
    /// Repeat it with boundaries computed with gravity, one per azimuth (`boundary --method
    /// der --gravity --azimuth A`): each azimuth is then planned to its own s*.
    #[arg(long)]
    pub boundary: Vec<PathBuf>,
    /// Roll mode (`fixed` or `motor`); default: the rig's.
    #[arg(long)]
    pub roll: Option<RollMode>,
    /// Try N azimuths evenly spaced in [0, 2π) per ray and keep the best (default: the rig's
    /// azimuth choices).
    #[arg(long)]
    pub azimuths: Option<usize>,
    /// Overrides of the rig's settings.
    #[command(flatten)]
    pub overrides: RigOverrideArgs,
    /// Process only shard I/N (0-based) of the directions.
    #[arg(long, allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Continue an existing --out (or its checkpoint OUT.partial) made with the same settings:
    /// compute only the missing directions.
    #[arg(long)]
    pub resume: bool,
    /// Replace an existing --out (it is kept until the new result is complete).
    #[arg(long)]
    pub force: bool,
    /// Seconds between checkpoints (to OUT.partial).
    #[arg(long, default_value_t = 10.0)]
    pub checkpoint_secs: f64,
    /// Output CSV (`-`: standard output). See `helixreach::sweep::driver` for the data-safety
    /// rules (settings record, lock, --resume/--force).
    #[arg(long)]
    pub out: PathBuf,
}

/// Run `helixreach reach`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_size, MAX_AZIMUTHS};
    helixreach::io::check_output(&args.out)?;
    if let Some(n) = args.azimuths {
        check_size("--azimuths", n, MAX_AZIMUTHS)?;
    }
    let checkpoint = checkpoint_interval(args.checkpoint_secs)?;
    let dirs = args.dirs.load()?;
    let rig = args.overrides.apply(&Rig::load(&args.rig)?)?;
    let opts = ReachOptions {
        roll: args.roll.unwrap_or(rig.roll),
        azimuths: match args.azimuths {
            Some(0) => anyhow::bail!("--azimuths 0: need at least one azimuth"),
            Some(n) => azimuth_grid(n),
            None => rig.azimuths.clone(),
        },
    };
    let table = match args.boundary.as_slice() {
        [] => None,
        files => Some(BoundaryTable::read_per_azimuth(files)?),
    };
    super::gravity_gate(&rig, &args.rig, None, table.as_ref(), &opts.azimuths)?;
    let planner = Planner::new(rig)?;
    status!(
        "reconfiguration at a held pose: {}",
        planner.reconfiguration(opts.roll)
    );
    let mut sweep = SweepOptions::new(&args.out, REACH_HEADER, 3);
    sweep.resume = args.resume;
    sweep.force = args.force;
    sweep.checkpoint_interval = checkpoint;
    sweep.shard = args.shard;
    sweep.progress = !super::global().quiet;
    sweep.par = helixreach::par::Par::from_option(super::global().threads)?;
    let t0 = std::time::Instant::now();
    let summary = run_reach(&planner, &dirs, table.as_ref(), &opts, &sweep)?;
    status!(
        "reach: {} directions ({} computed, {} resumed) in {:.1} s -> {}",
        summary.total,
        summary.computed,
        summary.resumed,
        t0.elapsed().as_secs_f64(),
        args.out.display()
    );
    // The class counts, read back from a regular output file (not from stdout, a FIFO or a
    // device).
    if std::fs::metadata(&args.out).is_ok_and(|m| m.is_file()) {
        let rows = helixreach::records::read_reach(&args.out)?;
        let c = RollSummary::of(&rows, &opts.azimuths, 0.0);
        status!(
            "reach: {} testable, {} partial, {} blocked, {} undecided",
            c.testable,
            c.partial,
            c.blocked,
            c.undecided
        );
        if c.undecided > 0 {
            eprintln!(
                "warning: reach: {} undecided: their search hit planner.max_search_nodes = {} before \
                 finding a path or exhausting its piece (class `undecided`, s_reached the farthest \
                 s found); a rig with a larger bound may decide some of them, at a cost that grows \
                 with the bound (in roll motor a ray's pieces can hold millions of nodes)",
                match c.undecided {
                    1 => "1 ray".to_string(),
                    n => format!("{n} rays"),
                },
                planner.rig().planner.max_search_nodes
            );
        }
    }
    Ok(())
}
