//! An executed joint trajectory as a **witness** of a feasible ray: how far a run the real robot
//! drove (the seed experiment's) proves that an undisturbed path exists on our model of the rig.
//!
//! Given a run's joint rows and the ray `S̄` it drove (roll `fixed`, azimuth 0, the planner's rig
//! with the run's clamp), [`witness`]:
//!
//! 1. **projects** every row onto our ray: its `s` is the arc parameter whose continuum end pose
//!    is nearest to the row's tool pose ([`check`](super::check) with a direction); the loading
//!    rows are taken up to the target `s_end = s*(1 + margin)` or the run's farthest row;
//! 2. **corrects** each row onto our pose at its `s` by one IK track from the run's joints (the
//!    seed held the end frame of a 100-edge discrete helix, ≈ 3 mm / 2 mrad from our continuum end
//!    frame), the first row onto the straight rod, and checks each corrected row for joint limits
//!    and self / scene / rod collision;
//! 3. **classifies each jump**: a step over the rig's `max_joint_step` between consecutive
//!    corrected rows is a legal planner move only as a self-motion walk at a held pose. The earlier
//!    row is tracked onto the later row's pose, then walks at that held pose (both ways, resolution
//!    `self_motion_step`, every sample valid and inside the limits) must pass within half a joint
//!    step of the later row. Else the two rows lie on different connected valid components of the
//!    self-motion manifold and the run disturbed the rod there ([`WitnessEnd::Disjoint`]).
//!
//! The witness extent is the `s` of the last good row before the first invalid row or disjoint
//! jump, or the run's farthest `s` capped at `s_end`. A planner that stops before the extent
//! (less a waypoint or two) misses a path the witness proves feasible; a run that reaches
//! `s_end` ([`WitnessEnd::Target`]) proves the ray testable. Used by `tests/planning_seed.rs`
//! (every planner miss must be explained) and `examples/seed_witness.rs` (the per-run report).
//!
//! `records::clamp_runs::read_seed_runs` reads the seed's run index (`trajectories.csv`: `file`,
//! direction, clamp) and `records::trajectory::read_joint_file` a run's joint file; this module
//! imports no file format.
//!
//! ```no_run
//! use helixreach::planning::{planner::{Planner, RigOverrides}, rig::Rig, witness};
//! use helixreach::records::{clamp_runs::read_seed_runs, trajectory::read_joint_file};
//! let seed = std::path::Path::new("../shared/seed-data");
//! let runs = read_seed_runs(&seed.join("trajectories.csv"))?;
//! let r = &runs[0];
//! let rig = RigOverrides { margin: Some(0.0), clamp: Some(r.clamp), ..Default::default() }
//!     .apply(&Rig::load("sawyer-seed")?)?;
//! let planner = Planner::new(rig)?;
//! let names: Vec<String> = planner.model().joints().iter().map(|j| j.name.clone()).collect();
//! let traj = read_joint_file(&seed.join("trajectories").join(&r.file), &names)?;
//! let w = witness::witness(&planner, &traj, &r.dir)?;
//! println!("{}: a witness to s = {:.3}, then {:?}", r.file, w.verdict.extent, w.verdict.end);
//! # Ok::<(), helixreach::Error>(())
//! ```

use super::check::{CheckOptions, Checker, JointFile};
use super::planner::Planner;
use super::pose_path::PoseMap;
use super::self_motion::{walk, Held, WalkSettings, Q};
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{tol, Real};
use crate::robot::{IkParams, IkSolver, IkTarget, MAX_DOF};
use std::path::{Path, PathBuf};

/// Smallest walk step of a jump's self-motion walks (rad; the walk halves its step down to this
/// near an obstacle or a limit before it stops).
pub const WALK_MIN_STEP: Real = 1e-4;
/// Most samples of one self-motion walk (bounds the work per jump).
pub const WALK_MAX_SAMPLES: usize = 4000;

/// One executed run of the seed experiment: its joint file, direction and clamp position.
#[derive(Debug, Clone, PartialEq)]
pub struct SeedRun {
    /// The joint file's name (relative to the index's `trajectories/` folder).
    pub file: String,
    /// The ray the run drove.
    pub dir: Direction,
    /// The clamp origin in the base frame (m).
    pub clamp: [Real; 3],
}

/// How far a run is a witness (in `s` on our ray), and why it stops being one there.
#[derive(Debug, Clone, PartialEq)]
pub struct Witness {
    /// The last `s` the run proves reachable undisturbed.
    pub extent: Real,
    /// Why the witness ends at `extent`.
    pub end: WitnessEnd,
}

/// Why a witness ends.
#[derive(Debug, Clone, PartialEq)]
pub enum WitnessEnd {
    /// It reaches our target `s_end`: every step is a ladder edge or a self-motion walk at a held
    /// pose, so the planner must find the ray testable.
    Target,
    /// The run's farthest `s` (projected on our ray) is short of our target `s_end`.
    Short,
    /// A row, corrected onto our pose, is invalid in our model (limits, collision, or the IK
    /// correction fails); the text names the `s` and the reason.
    Invalid(String),
    /// A jump between two rows joins two configurations that no self-motion walk at the held
    /// pose joins (different connected valid components): the run disturbed the rod there.
    Disjoint {
        /// The jump's largest joint step (rad).
        step: Real,
        /// The `s` and where the walks stopped (a collision pair, a joint limit, the manifold end).
        walks_stop: String,
    },
}

/// A jump of the corrected run: a step over `max_joint_step` between two rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Jump {
    /// `s` of the later row.
    pub s: Real,
    /// Largest joint step (rad).
    pub step: Real,
    /// Whether a self-motion walk at the later row's pose joins the two rows.
    pub joined: bool,
    /// Where the walks stopped when they did not join (empty when joined).
    pub walks_stop: String,
}

/// The whole classification of one run (see the module docs).
#[derive(Debug, Clone)]
pub struct WitnessTrace {
    /// Every row's `s` by projection onto our ray (continuum end frame).
    pub s_rows: Vec<Real>,
    /// Index of the row with the largest `s`.
    pub far_row: usize,
    /// Every row's `s` by projection onto the 100-edge discrete end frame the seed targeted
    /// ([`SEED_HELD_EDGES`](super::check::SEED_HELD_EDGES)): its largest value.
    pub s_far_discrete: Real,
    /// The corrected rows `(s, q)`, in order, up to the first invalid row.
    pub rows: Vec<(Real, Vec<Real>)>,
    /// The largest correction (max-norm joint change of a row onto our pose, rad).
    pub max_correction: Real,
    /// The jumps classified, up to the first disjoint one.
    pub jumps: Vec<Jump>,
    /// The verdict.
    pub verdict: Witness,
}

/// The max-norm distance of two joint vectors over their common length.
fn max_diff(a: &[Real], b: &[Real]) -> Real {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, Real::max)
}

/// Classify the executed run `traj` (its joint rows, as `records::trajectory::read_joint_file`
/// reads any trajectory file) of the ray `dir` on `planner` (its rig with the run's clamp), roll
/// `fixed`, azimuth 0; see the module docs. Errors when it has no rows.
pub fn witness(planner: &Planner, traj: &JointFile, dir: &Direction) -> Result<WitnessTrace> {
    let checker = Checker::new(planner.rig().clone())?;
    witness_of(planner, &checker, traj, dir, &traj.path)
}

fn witness_of(
    planner: &Planner,
    checker: &Checker,
    traj: &JointFile,
    dir: &Direction,
    path: &Path,
) -> Result<WitnessTrace> {
    let rig = planner.rig();
    let model = planner.model();
    let dof = model.dof();
    let step = rig.planner.max_joint_step;
    if traj.rows() == 0 {
        return Err(Error::File {
            path: PathBuf::from(path),
            reason: "no joint rows".into(),
        });
    }
    let opt = CheckOptions {
        direction: Some(*dir),
        ..CheckOptions::default()
    };
    let project = |opt: &CheckOptions| -> Result<Vec<Real>> {
        let rep = checker.check(traj, opt)?;
        rep.row_checks
            .iter()
            .map(|c| {
                c.s.ok_or_else(|| Error::File {
                    path: PathBuf::from(path),
                    reason: "a row has no projection onto the ray".into(),
                })
            })
            .collect()
    };
    let s_rows = project(&opt)?;
    let s_far_discrete = project(&CheckOptions {
        held_edges: super::check::SEED_HELD_EDGES,
        ..opt
    })?
    .into_iter()
    .fold(Real::NEG_INFINITY, Real::max);
    let s_star = crate::boundary::continuum::critical_s(dir, tol::S_STAR_REL)?.s_star;
    let s_end = s_star * (1.0 + rig.planner.margin);
    let far_row = (0..s_rows.len())
        .max_by(|&a, &b| s_rows[a].total_cmp(&s_rows[b]))
        .unwrap_or(0);
    let mut trace = WitnessTrace {
        far_row,
        s_far_discrete,
        rows: Vec::new(),
        max_correction: 0.0,
        jumps: Vec::new(),
        verdict: Witness {
            extent: s_rows[far_row].min(s_end),
            end: if s_rows[far_row] < s_end {
                WitnessEnd::Short
            } else {
                WitnessEnd::Target
            },
        },
        s_rows,
    };
    let map = PoseMap::new(rig, 0.0);
    let solver = IkSolver::new(model, IkParams::without_redundancy())?;
    let cm = planner.collision();
    let mut ws = cm.workspace();
    let (lo, hi) = (model.lower(), model.upper());
    let inside = |q: &[Real]| (0..dof).all(|j| q[j] >= lo[j] && q[j] <= hi[j]);
    let rod_at = |s: Real| {
        map.centerline(
            [s * dir.kappa, s * dir.tau, s * dir.omega],
            rig.planner.rod_capsules,
        )
    };
    // 1–2: corrected rows up to s_end.
    for i in 0..=far_row {
        let s = if i == 0 {
            0.0
        } else {
            trace.s_rows[i].min(s_end)
        };
        let kto = [s * dir.kappa, s * dir.tau, s * dir.omega];
        let tip = planner.tip_target(&map.end(kto)?.0);
        let before = trace.rows.last().map_or(0.0, |r| r.0);
        let invalid = |why: String| Witness {
            extent: before,
            end: WitnessEnd::Invalid(format!("s = {s:.3}: {why}")),
        };
        let Some(sol) = solver.track(&IkTarget::Pose(tip), traj.row(i), None) else {
            trace.verdict = invalid("the IK correction does not converge".into());
            return Ok(trace);
        };
        let q = sol.joints().to_vec();
        let nodes = rod_at(s)?;
        let rod = rig.rod_geometry(&nodes);
        if !inside(&q) {
            trace.verdict = invalid("joint limit".into());
            return Ok(trace);
        }
        if let Some(c) = cm.check(&q, &mut ws, Some(&rod)) {
            trace.verdict = invalid(format!("{}|{}", cm.name(c.a), cm.name(c.b)));
            return Ok(trace);
        }
        trace.max_correction = trace.max_correction.max(max_diff(&q, traj.row(i)));
        trace.rows.push((s, q));
        if s >= s_end {
            break;
        }
    }
    // 3: jumps.
    let track = IkSolver::new(model, IkParams::default())?;
    let settings = WalkSettings {
        max_step: rig.planner.self_motion_step,
        min_step: WALK_MIN_STEP,
        joint_step_bound: step,
        max_samples: WALK_MAX_SAMPLES,
    };
    for w in trace.rows.windows(2) {
        let d = max_diff(&w[0].1, &w[1].1);
        if d <= step {
            continue;
        }
        let (s1, q1) = (w[1].0, &w[1].1);
        let tip = model.chain().tool_pose(q1);
        let (joined, walks_stop) = match solver.track(&IkTarget::Pose(tip), &w[0].1, None) {
            None => (false, "no track onto the held pose".to_string()),
            Some(a) => {
                let held = Held {
                    chain: model.chain(),
                    solver: &track,
                    tip,
                    dof,
                };
                let nodes = rod_at(s1)?;
                let rod = rig.rod_geometry(&nodes);
                let mut qa: Q = [0.0; MAX_DOF];
                qa[..dof].copy_from_slice(a.joints());
                let mut stops = Vec::new();
                let mut joined = max_diff(&qa[..dof], q1) <= 0.5 * step;
                for sign in [1.0, -1.0] {
                    if joined {
                        break;
                    }
                    let mut stop = String::from("manifold end");
                    let (_, hit) = walk(
                        &held,
                        &qa,
                        sign,
                        &settings,
                        |_, b| {
                            if !inside(&b[..dof]) {
                                stop = "joint limit".into();
                                return false;
                            }
                            match cm.check(&b[..dof], &mut ws, Some(&rod)) {
                                None => true,
                                Some(c) => {
                                    stop = format!("{}|{}", cm.name(c.a), cm.name(c.b));
                                    false
                                }
                            }
                        },
                        |q| max_diff(&q[..dof], q1) <= 0.5 * step,
                    );
                    joined = hit;
                    stops.push(stop);
                }
                (
                    joined,
                    if joined {
                        String::new()
                    } else {
                        stops.join(" / ")
                    },
                )
            }
        };
        trace.jumps.push(Jump {
            s: s1,
            step: d,
            joined,
            walks_stop: walks_stop.clone(),
        });
        if !joined {
            trace.verdict = Witness {
                extent: w[0].0,
                end: WitnessEnd::Disjoint {
                    step: d,
                    walks_stop: format!("s = {s1:.3}: {walks_stop}"),
                },
            };
            return Ok(trace);
        }
    }
    Ok(trace)
}
