//! `helixreach campaign`: every testable ray of a direction set (or of a `layout` assignment)
//! planned, ordered and split into sessions (see `helixreach::planning::campaign`).
//!
//! Exit code 0 when at least one ray is testable (the campaign has a run), 3
//! ([`super::EXIT_NOT_TESTABLE`]) when none is (the outputs are still written, listing every
//! ray with its cause), 2 on an error (bad input: nothing is written).

use super::args::{checkpoint_interval, DirectionArgs, RigOverrideArgs};
use anyhow::{bail, Context};
use helixreach::experiment::campaign::{
    run_campaign, CampaignInput, CampaignOptions, Ray, Unplanned,
};
use helixreach::planning::campaign::{
    Handling, DEFAULT_CLAMP_MOVE_S, DEFAULT_SESSION_HOURS, DEFAULT_UNCLAMP_S,
};
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::records::campaign::read_layout;
use helixreach::sweep::reach::BoundaryTable;
use std::path::PathBuf;

/// Arguments of `helixreach campaign`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach campaign --fibonacci 6 --quarter --session-hours 0.5 --out campaign",
    "> helixreach campaign --rig sawyer-seed --fibonacci 173 --quarter --out campaign",
    "> helixreach campaign --layout layout --out campaign"
))]
pub struct Args {
    /// Rig: an embedded rig name (`sawyer-seed`, `panda-bench`) or a rig TOML file (not with
    /// --layout, whose placements give the rigs).
    #[arg(long, default_value = "sawyer-seed")]
    pub rig: String,
    /// The direction set.
    #[command(flatten)]
    pub dirs: DirectionArgs,
    /// A `helixreach layout --out` folder: its placements' rigs and the direction assignment
    /// (`placements.csv`, `assignment.csv`) instead of --rig and a direction set.
    #[arg(long, conflicts_with_all = ["directions", "fibonacci"])]
    pub layout: Option<PathBuf>,
    /// s* per direction from a `helixreach boundary` CSV (default: computed, continuum).
    #[arg(long)]
    pub boundary: Option<PathBuf>,
    /// Roll mode (`fixed` or `motor`); default: the (first) rig's.
    #[arg(long)]
    pub roll: Option<RollMode>,
    /// Overrides of the rig's settings (every placement's with --layout).
    #[command(flatten)]
    pub overrides: RigOverrideArgs,
    /// Session length (h): runs are never split across sessions.
    #[arg(long, default_value_t = DEFAULT_SESSION_HOURS)]
    pub session_hours: f64,
    /// Handling time of an unclamp move (s): the rod unclamped for a free move between runs.
    #[arg(long, default_value_t = DEFAULT_UNCLAMP_S)]
    pub unclamp_seconds: f64,
    /// Handling time of a clamp move (s): the clamp moved to the next placement.
    #[arg(long, default_value_t = DEFAULT_CLAMP_MOVE_S)]
    pub clamp_move_seconds: f64,
    /// Continue the campaign in --out (its `rays.csv` checkpoint) made with the same settings.
    #[arg(long)]
    pub resume: bool,
    /// Replace the campaign in --out.
    #[arg(long)]
    pub force: bool,
    /// Seconds between checkpoints of `rays.csv`.
    #[arg(long, default_value_t = 10.0)]
    pub checkpoint_secs: f64,
    /// The campaign folder (created).
    #[arg(long)]
    pub out: PathBuf,
}

fn seconds(flag: &str, x: f64, max: f64) -> anyhow::Result<f64> {
    if !(x.is_finite() && (0.0..=max).contains(&x)) {
        bail!(
            "invalid {flag} {}: must be in 0..={max}",
            helixreach::error::fmt_num(x)
        );
    }
    Ok(x)
}

/// Run `helixreach campaign`.
pub fn run(args: Args) -> anyhow::Result<()> {
    // Every input is read and checked before anything is written.
    let session_h = seconds("--session-hours", args.session_hours, 24.0 * 365.0)?;
    anyhow::ensure!(session_h > 0.0, "invalid --session-hours 0: must be > 0");
    let handling = Handling {
        unclamp_s: seconds("--unclamp-seconds", args.unclamp_seconds, 86_400.0)?,
        clamp_move_s: seconds("--clamp-move-seconds", args.clamp_move_seconds, 86_400.0)?,
    };
    let checkpoint = checkpoint_interval(args.checkpoint_secs)?;
    let boundary = match &args.boundary {
        Some(p) => Some(BoundaryTable::read(p)?),
        None => None,
    };
    let width = |n: usize| n.saturating_sub(1).to_string().len().max(3);
    let (planners, rays, unplanned, source) = match &args.layout {
        Some(dir) => {
            let layout = read_layout(dir)?;
            let mut planners = Vec::new();
            for f in &layout.rig_files {
                let rig = Rig::load(f.to_str().context("rig file name is not UTF-8")?)?;
                let rig = args.overrides.apply(&rig)?;
                planners.push(Planner::new(rig)?);
            }
            let w = width(layout.assigned.len());
            let mut rays = Vec::new();
            let mut unplanned = Vec::new();
            for (i, a) in layout.assigned.iter().enumerate() {
                match a.placement {
                    Some(p) => rays.push(Ray {
                        placement: p,
                        dir: a.dir,
                        azimuths: match a.azimuth {
                            Some(z) => vec![z],
                            None => planners[p - 1].rig().azimuths.clone(),
                        },
                        name: format!("p{p}_d{i:0w$}"),
                    }),
                    None => unplanned.push(Unplanned {
                        dir: a.dir,
                        class: a.class.clone(),
                        s_reached: a.s_reached,
                        cause: "no_placement_tests_it".into(),
                    }),
                }
            }
            let digest = helixreach::sweep::record::fnv1a_hex(
                &std::fs::read(dir.join("assignment.csv"))
                    .with_context(|| format!("{}", dir.join("assignment.csv").display()))?,
            );
            (
                planners,
                rays,
                unplanned,
                format!("layout assignment {digest}"),
            )
        }
        None => {
            let dirs = args.dirs.load()?;
            let rig = args.overrides.apply(&Rig::load(&args.rig)?)?;
            let planner = Planner::new(rig)?;
            let w = width(dirs.len());
            let az = planner.rig().azimuths.clone();
            let rays = dirs
                .iter()
                .enumerate()
                .map(|(i, d)| Ray {
                    placement: 1,
                    dir: *d,
                    azimuths: az.clone(),
                    name: format!("d{i:0w$}"),
                })
                .collect();
            (vec![planner], rays, Vec::new(), "rig".to_string())
        }
    };
    for (i, planner) in planners.iter().enumerate() {
        let mut azimuths: Vec<f64> = rays
            .iter()
            .filter(|r| r.placement == i + 1)
            .flat_map(|r| r.azimuths.iter().copied())
            .collect();
        azimuths.sort_by(f64::total_cmp);
        azimuths.dedup();
        let name = planner.rig().source.clone();
        super::gravity_gate(planner.rig(), &name, None, boundary.as_ref(), &azimuths)?;
    }
    let roll = args.roll.unwrap_or(planners[0].rig().roll);
    if args.out.exists() {
        anyhow::ensure!(
            args.out.is_dir(),
            "{}: exists and is not a folder (--out names the campaign folder)",
            args.out.display()
        );
    } else {
        let parent = args
            .out
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        anyhow::ensure!(
            parent.is_dir(),
            "{}: its parent folder {} does not exist",
            args.out.display(),
            parent.display()
        );
    }
    if !(args.resume || args.force)
        && ["rays.csv", "rays.csv.partial", "campaign.csv"]
            .iter()
            .any(|f| args.out.join(f).exists())
    {
        bail!(
            "{}: holds a campaign; give --resume to continue it or --force to replace it",
            args.out.display()
        );
    }
    let input = CampaignInput {
        planners,
        rays,
        unplanned,
        roll,
        boundary,
        azimuth_source: source,
    };
    let opts = CampaignOptions {
        out: args.out.clone(),
        resume: args.resume,
        force: args.force,
        checkpoint_interval: checkpoint,
        progress: !super::global().quiet,
        session_s: session_h * 3600.0,
        handling,
        par: helixreach::par::Par::from_option(super::global().threads)?,
    };
    let t0 = std::time::Instant::now();
    let s = run_campaign(&input, &opts)?;
    status!(
        "campaign: {} rays, {} runs ({} not testable) on {} placement(s); robot time {:.2} h \
         (runs {:.2} h, moves {:.2} h, handling {:.2} h) in {} session(s) of at most {} h; \
         moves {:?}; {} planned, {} resumed, in {:.1} s -> {}",
        s.rays,
        s.runs,
        s.not_testable,
        s.placements,
        s.total_h,
        s.run_s / 3600.0,
        s.transition_s / 3600.0,
        s.handling_s / 3600.0,
        s.sessions.len(),
        session_h,
        s.transitions,
        s.computed,
        s.resumed,
        t0.elapsed().as_secs_f64(),
        args.out.display()
    );
    if let Some(n) = s.transitions.get("blocked") {
        eprintln!(
            "warning: {n} move(s) between runs collide even with the rod unclamped (transition \
             `blocked` in {}): plan them by hand",
            args.out.join("campaign.csv").display()
        );
    }
    if s.runs == 0 {
        return Err(super::Verdict {
            code: super::EXIT_NOT_TESTABLE,
            message: format!(
                "no ray is testable: the campaign has no run ({} lists every ray with its cause)",
                args.out.join("campaign.csv").display()
            ),
        }
        .into());
    }
    Ok(())
}
