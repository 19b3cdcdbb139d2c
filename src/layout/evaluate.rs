//! The placement × direction sweep: for every candidate clamp pose and every direction, is the
//! ray testable (the full planner's answer with the rig's azimuth choices and roll mode)?
//!
//! # Shared work and early exits
//! - The boundary s* of each direction is computed once (continuum), not once per placement.
//! - One [`Planner`] per placement, built lazily on first use and shared by all its rays, so the
//!   straight rod's start rung (the same for every ray of the placement) is solved once.
//! - [`Planner::plan_best`] stops at the first testable azimuth.
//! - Cheap conservative checks ([`crate::layout::precheck`]) decide rays without planning:
//!   a straight rod out of reach (the whole placement), a waypoint out of reach on every
//!   azimuth, an infinite boundary, and (roll mode `fixed`) no valid configuration at the ray's
//!   end pose for any azimuth (the planner's sampled pointwise test, with its guarantee). A
//!   placement whose straight rod has no valid configuration (the planner's own start rung is
//!   empty: [`Planner::new`] reports an unreachable clamp) is decided by the planner, once, for
//!   all its rays.
//!
//! # Rows
//! Columns [`RAYS_HEADER`], keyed by `candidate,dir_kappa,dir_tau,dir_omega`. `class` is the
//! planner's `testable`/`partial`/`blocked`, or `unreachable` when the reach bound decided
//! or the end-pose check decided (s_reached then unknown: empty). `decided_by`: `planner`,
//! `clamp` (start rung, once per placement), `reach_bound`, `no_boundary`, `end_pose`.
//!
//! The sweep runs on [`crate::sweep::driver`]: rows in item order (candidate-major), bitwise
//! identical for any thread count, checkpointed, resumable and shardable.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::layout::candidates::Candidate;
use crate::layout::precheck::{end_pose_blocked, ReachBound};
use crate::math::Real;
use crate::planning::planner::{Planner, ReachClass};
use crate::planning::rig::{Rig, RollMode};
use crate::records::csv_out::CsvRecord;
use crate::records::layout::{RayRecord, RAY_KEY_COLUMNS};
use crate::records::{dir_key, fmt_real};
use crate::sweep::driver::{self, Row, SweepOptions, SweepSummary};
use crate::sweep::reach::{s_star_of, BoundaryTable};
use std::path::Path;
use std::sync::OnceLock;

/// Columns of `rays.csv` ([`RayRecord`]).
pub const RAYS_HEADER: &[&str] = RayRecord::HEADER;

/// What a placement's shared state turned out to be.
#[derive(Debug)]
enum Slot {
    /// The straight rod ends out of reach.
    OutOfReach,
    /// No valid start configuration (the planner's unreachable-clamp answer) and its cause.
    NoStart(String),
    /// A planner for the placed rig.
    Ready(Box<Planner>),
}

/// How a placement's rays are decided ([`Sweep::placement_kind`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlacementKind {
    /// The straight rod ends outside the reach bound: every ray `unreachable`, no planning.
    OutOfReach,
    /// The straight rod has no valid configuration: every ray `blocked`, decided once.
    NoStart,
    /// A planner with a start rung: rays are checked and planned one by one.
    Ready,
}

/// The sweep's fixed inputs.
#[derive(Debug)]
pub struct Sweep<'a> {
    /// The base rig (its clamp is replaced by each candidate's).
    pub rig: &'a Rig,
    /// Candidate clamp poses.
    pub candidates: &'a [Candidate],
    /// Directions.
    pub dirs: &'a [Direction],
    /// s* per direction (same order as `dirs`).
    pub s_star: Vec<Real>,
    /// Roll mode.
    pub roll: RollMode,
    /// Azimuths tried per ray.
    pub azimuths: Vec<Real>,
    /// Run the end-pose check ([`crate::layout::precheck`]) before planning (roll `fixed`).
    pub end_pose_check: bool,
    /// Every file the robot was loaded from ([`crate::robot::RobotModel::sources`]).
    pub robot_sources: Vec<crate::sources::SourceFile>,
    bound: ReachBound,
    slots: Vec<OnceLock<Result<Slot, String>>>,
}

/// One item of the sweep: (candidate index, direction index).
pub type Item = (usize, usize);

impl<'a> Sweep<'a> {
    /// Prepare a sweep: s* of every direction (from `table`, else the continuum test, in
    /// parallel on `par`), the reach bound of the rig's robot. The end-pose check is on
    /// ([`Sweep::end_pose_check`]).
    pub fn new(
        par: crate::par::Par,
        rig: &'a Rig,
        candidates: &'a [Candidate],
        dirs: &'a [Direction],
        table: Option<&BoundaryTable>,
        roll: RollMode,
        azimuths: Vec<Real>,
    ) -> Result<Sweep<'a>> {
        if azimuths.is_empty() {
            return Err(Error::invalid(
                "azimuths",
                "[]",
                "need at least one azimuth",
            ));
        }
        let model = rig.robot.load_model(&rig.source)?;
        let bound = ReachBound::of(&model, rig);
        let s_star = par
            .map(dirs, |d| s_star_of(d, table))?
            .into_iter()
            .collect::<Result<Vec<Real>>>()?;
        Ok(Sweep {
            rig,
            candidates,
            dirs,
            s_star,
            roll,
            azimuths,
            end_pose_check: true,
            robot_sources: model.sources().to_vec(),
            bound,
            slots: candidates.iter().map(|_| OnceLock::new()).collect(),
        })
    }

    /// The reach bound used by the cheap checks.
    pub fn bound(&self) -> &ReachBound {
        &self.bound
    }

    /// Every (candidate, direction) item, candidate-major.
    pub fn items(&self) -> Vec<Item> {
        (0..self.candidates.len())
            .flat_map(|c| (0..self.dirs.len()).map(move |d| (c, d)))
            .collect()
    }

    /// The key fields of an item (the first [`RAY_KEY_COLUMNS`] fields of its [`RayRecord`]).
    pub fn key(&self, &(c, d): &Item) -> Row {
        let mut k = vec![c.to_string()];
        k.extend(dir_key(&self.dirs[d]));
        k
    }

    fn slot(&self, c: usize) -> std::result::Result<&Slot, Error> {
        self.slots[c]
            .get_or_init(|| {
                let rig = self.candidates[c].place(self.rig);
                if self.bound.straight_out_of_reach(&rig) {
                    return Ok(Slot::OutOfReach);
                }
                match Planner::new(rig) {
                    Ok(p) => Ok(Slot::Ready(Box::new(p))),
                    Err(Error::InvalidParameter { field, reason, .. })
                        if field.ends_with("clamp.origin") =>
                    {
                        let cause = reason
                            .split("dominant cause: ")
                            .nth(1)
                            .map_or("no_ik", |s| s.trim_end_matches(')'));
                        Ok(Slot::NoStart(cause.to_string()))
                    }
                    Err(e) => Err(e.to_string()),
                }
            })
            .as_ref()
            .map_err(|e| Error::invalid("candidate", c, e.clone()))
    }

    /// What candidate `c`'s shared state is (computed once, on first use: the reach bound of
    /// the straight rod, then the planner's start rung): whether its rays are decided once for
    /// the whole placement ([`PlacementKind::OutOfReach`], [`PlacementKind::NoStart`]) or ray
    /// by ray ([`PlacementKind::Ready`]). Errors: the candidate's rig cannot be planned.
    pub fn placement_kind(&self, c: usize) -> Result<PlacementKind> {
        Ok(match self.slot(c)? {
            Slot::OutOfReach => PlacementKind::OutOfReach,
            Slot::NoStart(_) => PlacementKind::NoStart,
            Slot::Ready(_) => PlacementKind::Ready,
        })
    }

    /// The row of one item (a [`RayRecord`]).
    pub fn row(&self, item: &Item) -> Result<RayRecord<'_>> {
        let (c, d) = *item;
        let dir = &self.dirs[d];
        let s_star = self.s_star[d];
        // `cause` untyped: it borrows from the placement's slot or is a planner constant.
        let record = |class: &'static str,
                      s_reached: Option<Real>,
                      azimuth: Option<Real>,
                      cause,
                      decided_by: &'static str| {
            Ok(RayRecord {
                candidate: c,
                dir_kappa: dir.kappa,
                dir_tau: dir.tau,
                dir_omega: dir.omega,
                class,
                s_reached,
                azimuth,
                cause,
                s_star,
                decided_by,
            })
        };
        match self.slot(c)? {
            Slot::OutOfReach => record("unreachable", None, None, "no_ik", "reach_bound"),
            Slot::NoStart(cause) => record("blocked", Some(0.0), None, cause, "clamp"),
            Slot::Ready(planner) => {
                let rig = planner.rig();
                if !s_star.is_finite() {
                    return record("partial", None, None, "", "no_boundary");
                }
                let s_end = s_star * (1.0 + rig.planner.margin);
                if self
                    .bound
                    .ray_out_of_reach(rig, dir, s_end, &self.azimuths)?
                {
                    return record("unreachable", None, None, "no_ik", "reach_bound");
                }
                if self.end_pose_check
                    && self.roll == RollMode::Fixed
                    && end_pose_blocked(planner, dir, s_star, &self.azimuths)?
                {
                    return record("unreachable", None, None, "end_pose", "end_pose");
                }
                let p = planner.plan_best(dir, s_star, &self.azimuths, self.roll, false)?;
                record(
                    p.class.as_str(),
                    Some(p.s_reached),
                    Some(p.azimuth),
                    p.cause.map_or("", |c| c.as_str()),
                    "planner",
                )
            }
        }
    }

    /// Run the sweep into `opts.out` (header [`RAYS_HEADER`], [`RAY_KEY_COLUMNS`] key columns).
    pub fn run(&self, opts: &SweepOptions) -> Result<SweepSummary> {
        let items = self.items();
        driver::run(&items, |i| self.key(i), |i| self.row(i), opts)
    }
}

/// One row of `rays.csv`, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct RayResult {
    /// Candidate index.
    pub candidate: usize,
    /// Direction index (order of the direction set).
    pub dir: usize,
    /// `testable`, `partial`, `blocked` or `unreachable`.
    pub class: String,
    /// Farthest s reached (NaN when unknown).
    pub s_reached: Real,
    /// Azimuth of the plan (NaN when not planned).
    pub azimuth: Real,
    /// How the row was decided.
    pub decided_by: String,
}

impl RayResult {
    /// Whether the ray is testable.
    pub fn testable(&self) -> bool {
        self.class == ReachClass::Testable.as_str()
    }
}

/// Read a complete `rays.csv` of `n_candidates × dirs` (candidate-major, as [`Sweep::run`]
/// writes it); every key must match its item. Errors name the file and line.
pub fn read_rays(path: &Path, n_candidates: usize, dirs: &[Direction]) -> Result<Vec<RayResult>> {
    let mut table = crate::io::CsvInput::open(path)?;
    let hint = "a rays.csv written by `helixreach layout`";
    let mut cols = [0usize; RayRecord::HEADER.len()];
    for (k, name) in RAYS_HEADER.iter().enumerate() {
        cols[k] = table.column(name, hint)?;
    }
    let mut out = Vec::with_capacity(n_candidates * dirs.len());
    for (k, rec) in table.reader.records().enumerate() {
        let line = k + 2;
        let bad = |field: &str, reason: String| crate::io::bad_line(path, line, field, reason);
        let rec = rec.map_err(|e| bad("record", e.to_string()))?;
        let (c, d) = (k / dirs.len().max(1), k % dirs.len().max(1));
        let field = |i: usize| rec.get(cols[i]).unwrap_or("");
        let expect: [String; RAY_KEY_COLUMNS] = [
            c.to_string(),
            fmt_real(dirs.get(d).map_or(Real::NAN, |x| x.kappa)),
            fmt_real(dirs.get(d).map_or(Real::NAN, |x| x.tau)),
            fmt_real(dirs.get(d).map_or(Real::NAN, |x| x.omega)),
        ];
        for (i, e) in expect.iter().enumerate() {
            if field(i) != e {
                return Err(bad(
                    RAYS_HEADER[i],
                    format!(
                        "`{}` where item {k} has `{e}` (incomplete or foreign file)",
                        field(i)
                    ),
                ));
            }
        }
        let num = |i: usize| -> Result<Real> {
            let t = field(i);
            if t.is_empty() {
                Ok(Real::NAN)
            } else {
                t.parse()
                    .map_err(|_| bad(RAYS_HEADER[i], format!("`{t}` is not a number")))
            }
        };
        out.push(RayResult {
            candidate: c,
            dir: d,
            class: field(4).to_string(),
            s_reached: num(5)?,
            azimuth: num(6)?,
            decided_by: field(9).to_string(),
        });
    }
    if out.len() != n_candidates * dirs.len() {
        return Err(Error::File {
            path: path.to_path_buf(),
            reason: format!(
                "has {} rays, expected {} candidates × {} directions = {} (run the missing \
                 shards, merge them, then --resume)",
                out.len(),
                n_candidates,
                dirs.len(),
                n_candidates * dirs.len()
            ),
        });
    }
    Ok(out)
}
