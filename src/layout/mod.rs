//! Rig layout ([architecture §8](crate::architecture)): where to put the clamp so that the robot can test a whole
//! direction set, and which directions to run from each placement.
//!
//! | module | holds |
//! |---|---|
//! | [`candidates`] | the grid of candidate clamp poses over a bench region, tilted clamp axes |
//! | [`precheck`] | cheap checks before planning: geometric proofs, the sampled end-pose test |
//! | [`evaluate`] | the placement × direction sweep (full planner, shared work, resumable) |
//! | [`set_cover`] | maximum coverage with K placements: greedy, exact branch and bound |
//! | [`report`] | the output files: candidates, placements, assignment, coverage, rigs, figures |
//!
//! # Workflow ([`run`])
//! 1. Candidates: the grid over [`LayoutOptions::region`] (plus, optionally, reference clamp
//!    positions such as the seed's hand-chosen ones, evaluated but never chosen).
//! 2. `rays.csv`: every candidate × direction, decided by the full planner with the rig's
//!    azimuths and roll mode, or by a cheap check ([`evaluate`], [`precheck`]).
//! 3. Coverage sets per candidate; for every k ≤ K the greedy and the exact maximum coverage
//!    ([`set_cover`]); the K placements are the exact optimum when it is proven, else greedy's.
//! 4. Every direction is assigned to the first chosen placement (in order of decreasing marginal
//!    gain) that tests it, with that placement's azimuth.
//! 5. One rig TOML per placement (loadable by `Rig::load`, same answers as `reach`), CSV records
//!    and figures ([`report`]).
//!
//! A region where no candidate covers anything is a valid answer (coverage 0, reported), not an
//! error.

pub mod candidates;
pub mod evaluate;
pub mod precheck;
pub mod report;
pub mod set_cover;

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::rig::{Rig, RollMode};
use crate::sweep::driver::{Shard, SweepOptions};
use crate::sweep::reach::BoundaryTable;
use candidates::{grid, Candidate, Region};
use evaluate::{read_rays, RayResult, Sweep, RAYS_HEADER};
use set_cover::{exact, greedy, BitSet, Cover};
use std::path::{Path, PathBuf};

/// Largest number of placements K.
pub const MAX_PLACEMENTS: usize = 20;

/// Default search budget of the exact cover (branch-and-bound nodes per k).
pub const EXACT_NODE_LIMIT: u64 = 20_000_000;

/// Half-width (m) of the default region around the rig's clamp (x and y).
pub const DEFAULT_HALF_WIDTH: Real = 0.15;

/// Default grid spacing (m).
pub const DEFAULT_SPACING: Real = 0.05;

/// What to search.
#[derive(Debug, Clone)]
pub struct LayoutOptions {
    /// Bench region of the candidate grid (base frame, m).
    pub region: Region,
    /// Grid spacing (m).
    pub spacing: Real,
    /// Clamp-axis tilts (degrees; 0 = the rig's).
    pub tilts_deg: Vec<Real>,
    /// Headings per non-zero tilt.
    pub headings: usize,
    /// Number of placements K (1 ..= [`MAX_PLACEMENTS`]).
    pub placements: usize,
    /// Overrides the rig's planner margin past the boundary
    /// ([`MARGIN_RULE`](crate::planning::rig::MARGIN_RULE)).
    pub margin: Option<Real>,
    /// Roll mode (default: the rig's).
    pub roll: Option<RollMode>,
    /// Azimuths per ray (default: the rig's choices).
    pub azimuths: Option<Vec<Real>>,
    /// Node budget of the exact cover per k.
    pub exact_node_limit: u64,
    /// Reference clamp positions (named), evaluated over all directions but never chosen.
    pub references: Vec<Reference>,
    /// Rule rays out by the sampled end-pose check before planning (roll `fixed`; see
    /// [`precheck`], "End pose"). On by default; off for comparisons.
    pub end_pose_check: bool,
}

/// A reference clamp position: e.g. where the seed ran some of its directions.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// Clamp origin (m, base frame), rig's clamp orientation.
    pub origin: [Real; 3],
    /// Indices of the directions the reference ran at this position.
    pub own: Vec<usize>,
}

impl LayoutOptions {
    /// Defaults for `rig`: ±[`DEFAULT_HALF_WIDTH`] around its clamp at its height,
    /// [`DEFAULT_SPACING`], upright, K = 3.
    pub fn around(rig: &Rig) -> LayoutOptions {
        LayoutOptions {
            region: Region::around(&rig.clamp.translation.vector, DEFAULT_HALF_WIDTH),
            spacing: DEFAULT_SPACING,
            tilts_deg: vec![0.0],
            headings: 4,
            placements: 3,
            margin: None,
            roll: None,
            azimuths: None,
            exact_node_limit: EXACT_NODE_LIMIT,
            references: vec![],
            end_pose_check: true,
        }
    }
}

/// How to run the sweep.
#[derive(Debug, Clone, Default)]
pub struct RunControl {
    /// Keep finished rays of an existing `rays.csv` (same settings only).
    pub resume: bool,
    /// Replace an existing `rays.csv` (once the new one is complete).
    pub force: bool,
    /// Only this shard of the (candidate, direction) items; no summary outputs.
    pub shard: Option<Shard>,
    /// Progress and the summary line on stderr.
    pub progress: bool,
    /// The parallelism of the sweep (s* of the directions, the rays).
    pub par: crate::par::Par,
}

/// Coverage of the best k placements.
#[derive(Debug, Clone, PartialEq)]
pub struct CoverageAtK {
    /// k.
    pub k: usize,
    /// Greedy.
    pub greedy: Cover,
    /// Exact (branch and bound).
    pub exact: Cover,
}

/// One chosen placement.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// Candidate index.
    pub candidate: usize,
    /// The pose.
    pub pose: Candidate,
    /// Directions it tests.
    pub covered: usize,
    /// Directions it adds to the earlier placements.
    pub new: usize,
    /// Union with the earlier placements.
    pub cumulative: usize,
    /// The rig file written for it.
    pub rig_file: PathBuf,
}

/// The seed comparison: coverage of reference positions next to layout's.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceCoverage {
    /// Directions testable at the reference position they were run at.
    pub own: usize,
    /// Directions assigned to some reference position.
    pub own_total: usize,
    /// Directions testable at any reference position.
    pub union: usize,
    /// Number of distinct reference positions.
    pub positions: usize,
}

/// What [`run`] found.
#[derive(Debug, Clone)]
pub struct LayoutReport {
    /// Candidate poses (grid, then references).
    pub candidates: Vec<Candidate>,
    /// How many leading candidates are the grid (eligible for the cover).
    pub n_grid: usize,
    /// Directions.
    pub n_dirs: usize,
    /// Directions covered per candidate.
    pub covered: Vec<usize>,
    /// Coverage for k = 1 ..= K.
    pub by_k: Vec<CoverageAtK>,
    /// The K placements, in order of decreasing marginal gain.
    pub placements: Vec<Placement>,
    /// Rays decided by each means: (`decided_by`, count).
    pub decided: Vec<(String, usize)>,
    /// Reference coverage (when references were given).
    pub reference: Option<ReferenceCoverage>,
    /// Per direction: (placement rank 0-based, its ray) or `None` when no placement tests it.
    pub assignment: Vec<Option<(usize, RayResult)>>,
}

impl LayoutReport {
    /// Fraction of rays decided without the per-ray planner (cheap checks + once-per-placement
    /// start rung).
    pub fn cheap_fraction(&self) -> Real {
        let total: usize = self.decided.iter().map(|(_, n)| n).sum();
        let cheap: usize = self
            .decided
            .iter()
            .filter(|(k, _)| k != "planner")
            .map(|(_, n)| n)
            .sum();
        cheap as Real / total.max(1) as Real
    }
}

/// Read reference clamp positions from a seed `trajectories.csv`
/// (`dir_kappa,dir_tau,dir_omega,clamp_x,clamp_y,clamp_z`), matched to `dirs` (to
/// [`tol::DIRECTION_MATCH`](crate::math::tol::DIRECTION_MATCH) after normalization). Every
/// listed direction must be among `dirs`.
pub fn read_references(path: &Path, dirs: &[Direction]) -> Result<Vec<Reference>> {
    let mut refs: Vec<Reference> = Vec::new();
    for row in crate::records::clamp_runs::read_clamped_directions(path, false)? {
        let d = row.dir;
        let idx = dirs
            .iter()
            .position(|x| {
                use crate::math::tol::DIRECTION_MATCH as M;
                (x.kappa - d.kappa).abs() < M
                    && (x.tau - d.tau).abs() < M
                    && (x.omega - d.omega).abs() < M
            })
            .ok_or_else(|| {
                crate::io::bad_line(
                    path,
                    row.line,
                    "direction",
                    "not in the layout's direction set".into(),
                )
            })?;
        match refs.iter_mut().find(|r| r.origin == row.clamp) {
            Some(r) => r.own.push(idx),
            None => refs.push(Reference {
                origin: row.clamp,
                own: vec![idx],
            }),
        }
    }
    Ok(refs)
}

/// The settings recorded in `rays.csv` (compared by the sweep driver on resume): digests of the
/// rig (without name, description and location), of every file the robot was loaded from
/// (`robot_files`), of the directions and the candidate poses, the roll mode, the azimuths and
/// where s* comes from.
fn settings(
    so: SweepOptions,
    rig: &Rig,
    dirs: &[Direction],
    cands: &[Candidate],
    roll: RollMode,
    azimuths: &[Real],
    table: Option<&BoundaryTable>,
) -> SweepOptions {
    use crate::sweep::reach::fmt_real as f;
    use crate::sweep::record::fnv1a_hex;
    let mut r = rig.clone();
    r.name.clear();
    r.description.clear();
    r.source.clear();
    r.robot.dir = PathBuf::new();
    let dir_text: String = dirs
        .iter()
        .map(|d| format!("{},{},{};", f(d.kappa), f(d.tau), f(d.omega)))
        .collect();
    let cand_text: String = cands
        .iter()
        .map(|c| {
            let o = c.origin;
            format!(
                "{},{},{},{},{};",
                f(o[0]),
                f(o[1]),
                f(o[2]),
                f(c.tilt),
                f(c.heading)
            )
        })
        .collect();
    let az: Vec<String> = azimuths.iter().map(|&a| f(a)).collect();
    so.sweep("layout")
        .setting("rig", rig.name.as_str())
        .setting("rig_digest", fnv1a_hex(format!("{r:?}").as_bytes()))
        .setting("roll_mode", roll.as_str())
        .setting("azimuths", az.join(" "))
        .setting("margin", f(rig.planner.margin))
        .setting(
            "directions",
            format!("{} {}", dirs.len(), fnv1a_hex(dir_text.as_bytes())),
        )
        .setting(
            "candidates",
            format!("{} {}", cands.len(), fnv1a_hex(cand_text.as_bytes())),
        )
        .setting(
            "boundary",
            match table {
                Some(t) => format!("table {}", t.digest()),
                None => format!("continuum tol={:e}", crate::math::tol::S_STAR_REL),
            },
        )
}

/// Run the layout (see the module docs) writing into `out_dir`. Returns `None` for a shard run
/// (only `rays.csv` is written; merge the shards with `helixreach merge --key-columns 4` into
/// one directory's `rays.csv`, then run again with `resume` to get the summary).
pub fn run(
    rig: &Rig,
    dirs: &[Direction],
    table: Option<&BoundaryTable>,
    opts: &LayoutOptions,
    control: &RunControl,
    out_dir: &Path,
) -> Result<Option<LayoutReport>> {
    if dirs.is_empty() {
        return Err(Error::invalid(
            "directions",
            0,
            "the direction set must not be empty",
        ));
    }
    // A whole run needs s* of every direction (a shard's rays name a missing one as they go).
    if let (Some(t), None) = (table, control.shard) {
        t.check_covers(dirs)?;
    }
    if opts.placements == 0 || opts.placements > MAX_PLACEMENTS {
        return Err(Error::invalid(
            "placements",
            opts.placements,
            format!("must be in 1..={MAX_PLACEMENTS}"),
        ));
    }
    let mut rig = rig.clone();
    if let Some(m) = opts.margin {
        if !crate::planning::rig::margin_ok(m) {
            return Err(Error::invalid(
                "margin",
                m,
                crate::planning::rig::MARGIN_RULE,
            ));
        }
        rig.planner.margin = m;
    }
    let roll = opts.roll.unwrap_or(rig.roll);
    let azimuths = opts
        .azimuths
        .clone()
        .unwrap_or_else(|| rig.azimuths.clone());
    for a in &azimuths {
        crate::error::require_finite("azimuths", *a)?;
    }
    let mut cands = grid(&opts.region, opts.spacing, &opts.tilts_deg, opts.headings)?;
    let n_grid = cands.len();
    for r in &opts.references {
        cands.push(Candidate {
            origin: r.origin,
            tilt: 0.0,
            heading: 0.0,
        });
    }

    let rays_path = out_dir.join("rays.csv");
    let mut sweep = Sweep::new(
        control.par,
        &rig,
        &cands,
        dirs,
        table,
        roll,
        azimuths.clone(),
    )?;
    sweep.end_pose_check = opts.end_pose_check;
    let mut so = SweepOptions::new(
        &rays_path,
        RAYS_HEADER,
        crate::records::layout::RAY_KEY_COLUMNS,
    );
    so.resume = control.resume;
    so.force = control.force;
    so.shard = control.shard;
    so.progress = control.progress;
    so.par = control.par;
    let so = settings(so, &rig, dirs, &cands, roll, &azimuths, table)
        .setting(
            "robot_files",
            crate::sources::sources_setting(&sweep.robot_sources),
        )
        .setting("end_pose_check", opts.end_pose_check.to_string());
    let summary = sweep.run(&so)?;
    if control.progress {
        eprintln!(
            "layout: {} rays ({} candidates × {} directions; {} computed, {} resumed) -> {}",
            summary.total,
            cands.len(),
            dirs.len(),
            summary.computed,
            summary.resumed,
            rays_path.display()
        );
    }
    if control.shard.is_some() {
        return Ok(None);
    }

    let rays = read_rays(&rays_path, cands.len(), dirs)?;
    let report = summarize(&rig, dirs, cands.clone(), n_grid, &rays, opts)?;
    report::write_all(&rig, dirs, &report, &rays, sweep.bound(), out_dir)?;
    Ok(Some(report))
}

/// The coverage sets, covers, placements and assignment from the finished rays.
fn summarize(
    _rig: &Rig,
    dirs: &[Direction],
    cands: Vec<Candidate>,
    n_grid: usize,
    rays: &[RayResult],
    opts: &LayoutOptions,
) -> Result<LayoutReport> {
    let nd = dirs.len();
    let mut sets: Vec<BitSet> = vec![BitSet::new(nd); cands.len()];
    let mut decided: Vec<(String, usize)> = Vec::new();
    for r in rays {
        if r.testable() {
            sets[r.candidate].insert(r.dir);
        }
        match decided.iter_mut().find(|(k, _)| *k == r.decided_by) {
            Some((_, n)) => *n += 1,
            None => decided.push((r.decided_by.clone(), 1)),
        }
    }
    let covered: Vec<usize> = sets.iter().map(BitSet::count).collect();
    let grid_sets = &sets[..n_grid];
    let mut by_k = Vec::new();
    for k in 1..=opts.placements {
        let g = greedy(grid_sets, k);
        let e = exact(grid_sets, k, opts.exact_node_limit);
        by_k.push(CoverageAtK {
            k,
            greedy: g,
            exact: e,
        });
    }
    let last = by_k.last().expect("K >= 1");
    let chosen = if last.exact.proven && last.exact.covered >= last.greedy.covered {
        last.exact.chosen.clone()
    } else {
        last.greedy.chosen.clone()
    };
    // Order the chosen placements by decreasing marginal gain (greedy within the choice).
    let sub: Vec<BitSet> = chosen.iter().map(|&i| sets[i].clone()).collect();
    let order = greedy(&sub, sub.len()).chosen;
    let mut cum = BitSet::new(nd);
    let mut placements = Vec::new();
    for (rank, &j) in order.iter().enumerate() {
        let c = chosen[j];
        let new = cum.gain(&sets[c]);
        cum.union_with(&sets[c]);
        placements.push(Placement {
            candidate: c,
            pose: cands[c],
            covered: covered[c],
            new,
            cumulative: cum.count(),
            rig_file: PathBuf::from(format!("placement_{}.toml", rank + 1)),
        });
    }
    let at = |c: usize, d: usize| &rays[c * nd + d];
    let assignment = (0..nd)
        .map(|d| {
            placements
                .iter()
                .enumerate()
                .find(|(_, p)| sets[p.candidate].contains(d))
                .map(|(rank, p)| (rank, at(p.candidate, d).clone()))
        })
        .collect();
    let reference = if opts.references.is_empty() {
        None
    } else {
        let mut own = BitSet::new(nd);
        let mut own_total = BitSet::new(nd);
        let mut union = BitSet::new(nd);
        for (i, r) in opts.references.iter().enumerate() {
            let c = n_grid + i;
            union.union_with(&sets[c]);
            for &d in &r.own {
                own_total.insert(d);
                if sets[c].contains(d) {
                    own.insert(d);
                }
            }
        }
        Some(ReferenceCoverage {
            own: own.count(),
            own_total: own_total.count(),
            union: union.count(),
            positions: opts.references.len(),
        })
    };
    Ok(LayoutReport {
        candidates: cands,
        n_grid,
        n_dirs: nd,
        covered,
        by_k,
        placements,
        decided,
        reference,
        assignment,
    })
}
