//! `helixreach bifurcation`: the type of the loss of stability (subcritical snap or
//! supercritical gradual departure) at the DER-statics s* of every direction of a set, with
//! the post-buckling coefficient and, for subcritical rays, where the rod returns to the helix on
//! quasi-static unloading (`helixreach::bifurcation`). CSV columns
//! `dir_kappa,dir_tau,dir_omega,s_star,type,coefficient,s_return,hysteresis,resolution,reason`
//! (rows in input order; `coefficient > 0` ⇔ supercritical, see the library docs; `s_return`
//! and `hysteresis = s_star − s_return` empty when not computed; `reason` explains a
//! `degenerate` row, and why `s_return` is missing on a subcritical one; `s_star` is empty when
//! the DER s* itself was not found). A direction that cannot be decided is such a row, never an
//! abort of the sweep (`helixreach::bifurcation::classify`). Parallel over directions,
//! checkpointed, resumable (same settings) and shardable through `helixreach::sweep::driver`;
//! an existing `--out` is replaced only with `--force`.
//!
//! `--rel-tol E` chooses n per direction as `boundary --method der --rel-tol` does
//! (`helixreach::boundary::der::critical_s_to_rel_tol`: n doubled from `--n-edges` until the
//! Richardson estimate of the DER s*'s discretization error is ≤ E relative, an error past
//! `--max-n-edges`) and classifies at that n; the row's `resolution` is `n=N rel_err=R` (R the
//! Richardson estimate). A direction that needs more than `--max-n-edges` is a `degenerate` row
//! whose reason names the n it would need.

use super::args::{checkpoint_interval, DirectionArgs};
use super::boundary::dir_key;
use anyhow::Context;
use helixreach::bifurcation::{classify, Bifurcation, BifurcationParams};
use helixreach::boundary::der::DerBoundaryParams;
use helixreach::directions::Direction;
use helixreach::math::Real;
use helixreach::records::bifurcation::BifurcationRecord;
use helixreach::records::csv_out::CsvRecord;
use helixreach::rod::dynamics::presets::Preset;
use helixreach::sweep::driver::{self, Shard, SweepOptions};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `helixreach bifurcation`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach bifurcation --fibonacci 3 --n-edges 20 --out bifurcation.csv",
    "> helixreach bifurcation --fibonacci 200 --quarter --out bifurcation.csv"
))]
#[command(group(clap::ArgGroup::new("dirs").required(true).args(["directions", "fibonacci"])))]
pub struct Args {
    /// The direction set.
    #[command(flatten)]
    pub dirs: DirectionArgs,
    /// Number of DER edges.
    #[arg(long, default_value_t = 100)]
    pub n_edges: usize,
    /// The rod (`--rig`, `--preset`, field overrides; default `paper-sim` for ν): its ν, and
    /// its diameter over length for the self-contact check when a rod is given.
    #[command(flatten)]
    pub rod: super::rod_args::RodArgs,
    /// Skip the static unloading (no s_return for subcritical rays; much faster).
    #[arg(long)]
    pub no_return: bool,
    /// Choose n per direction, doubling from `--n-edges` until the Richardson estimate of the
    /// DER s*'s discretization error is at most this (relative), then classify at that n.
    #[arg(long, allow_negative_numbers = true)]
    pub rel_tol: Option<Real>,
    /// With --rel-tol: the largest n (an error row when reached, never a silent cap).
    #[arg(long, default_value_t = helixreach::boundary::der::DEFAULT_MAX_ADAPTIVE_EDGES, requires = "rel_tol")]
    pub max_n_edges: usize,
    /// Relative resolution of s_return.
    #[arg(long, default_value_t = helixreach::bifurcation::RETURN_TOL_REL)]
    pub return_tol: Real,
    /// Rod diameter (units of L) for the self-contact check of the far branch (default: 2h/L of
    /// the rod given by `--rig`/`--preset`/a field flag, else the seed's nitinol rod, 3.175e-3).
    #[arg(long)]
    pub contact_diameter: Option<Real>,
    /// Continue an existing --out (or its checkpoint OUT.partial) made with the same settings:
    /// compute only the missing directions.
    #[arg(long)]
    pub resume: bool,
    /// Replace an existing --out (it is kept until the new result is complete).
    #[arg(long)]
    pub force: bool,
    /// Process only block I (0-based) of N contiguous blocks of the directions.
    #[arg(long, allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Seconds between checkpoints (to OUT.partial).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub checkpoint_secs: f64,
    /// Output CSV.
    #[arg(long)]
    pub out: PathBuf,
}

/// The CSV record of one direction (what the sweep driver writes).
fn record(d: &Direction, b: &Bifurcation, resolution: &str) -> BifurcationRecord {
    BifurcationRecord::new(d, b, resolution)
}

/// Run `helixreach bifurcation`.
pub fn run(a: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_size, MAX_N_EDGES};
    // Cheap checks first: a bad output path or size fails before any computation.
    check_size("--n-edges", a.n_edges, MAX_N_EDGES)?;
    helixreach::io::check_output(&a.out)?;
    let checkpoint = checkpoint_interval(a.checkpoint_secs)?;
    let dirs = a.dirs.load()?;
    let rod = a.rod.resolve(Preset::PaperSim)?;
    let nu = rod.rod.nu;
    let contact_diameter = match (a.contact_diameter, rod.explicit) {
        (Some(d), _) => d,
        (None, true) => 2.0 * rod.rod.radius / rod.rod.length,
        (None, false) => BifurcationParams::default().contact_diameter,
    };
    let p = BifurcationParams {
        der: DerBoundaryParams {
            n_edges: a.n_edges,
            nu,
            tol_rel: helixreach::bifurcation::S_STAR_TOL_REL,
            ..DerBoundaryParams::default()
        },
        statics_return: !a.no_return,
        return_tol_rel: a.return_tol,
        contact_diameter,
    };
    p.validate().context("bifurcation parameters")?;
    let resolution = match a.rel_tol {
        Some(e) => {
            helixreach::error::require_positive("rel_tol", e)?;
            format!("rel_tol={e:e} n0={} n_max={}", a.n_edges, a.max_n_edges)
        }
        None => format!("n={}", a.n_edges),
    };
    let max_n = a.max_n_edges;
    let one = |d: &Direction| -> helixreach::Result<BifurcationRecord> {
        let Some(e) = a.rel_tol else {
            return Ok(record(d, &classify(d, &p)?, &resolution));
        };
        match helixreach::boundary::der::critical_s_to_rel_tol(d, &p.der, e, max_n) {
            Ok(ad) => {
                let at = BifurcationParams {
                    der: DerBoundaryParams {
                        n_edges: ad.n_edges,
                        ..p.der
                    },
                    ..p
                };
                let label = format!("n={} rel_err={:.2e}", ad.n_edges, ad.richardson_rel);
                Ok(record(d, &classify(d, &at)?, &label))
            }
            Err(err) => Ok(record(
                d,
                &helixreach::bifurcation::degenerate(
                    format!("no DER s* to rel_tol {e:e}: {err}"),
                    Real::NAN,
                ),
                &resolution,
            )),
        }
    };
    let mut opts = SweepOptions::new(&a.out, BifurcationRecord::HEADER, 3)
        .sweep("bifurcation")
        .setting("resolution", &resolution)
        .setting("nu", nu)
        .setting("statics_return", p.statics_return)
        .setting("return_tol", a.return_tol)
        .setting("contact_diameter", p.contact_diameter);
    opts.resume = a.resume;
    opts.force = a.force;
    opts.shard = a.shard;
    opts.checkpoint_interval = checkpoint;
    opts.progress = !super::global().quiet;
    opts.par = helixreach::par::Par::from_option(super::global().threads)?;
    let t0 = Instant::now();
    let summary = driver::run(&dirs, dir_key, one, &opts)?;
    status!(
        "bifurcation: {} directions ({} computed, {} resumed) in {:.3} s -> {}",
        summary.total,
        summary.computed,
        summary.resumed,
        t0.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}
