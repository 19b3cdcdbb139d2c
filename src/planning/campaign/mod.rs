//! A test campaign: every testable ray of a direction set planned on a rig (or on the rigs of
//! a `layout`), put in an order that keeps robot time and clamp moves low, with the moves
//! between runs planned and the whole split into sessions (`helixreach campaign`).
//!
//! This module is the campaign's domain (planning, ordering, moves, sessions); it imports no
//! file format. Running a campaign into a folder is [`crate::experiment::campaign`]; its files
//! are the records of `records::campaign`.
//!
//! # Contract
//! - **Runs.** Each ray is planned as `helixreach plan` plans it ([`plan_run`]: the rig's
//!   azimuths, or the layout's azimuth for the ray, the bifurcation type when the rig's margin
//!   depends on it). A `testable` ray is a run: its time-parametrized trajectory (load, hold,
//!   unload) starts and ends at the straight rod (s = 0). A ray that is not testable is listed
//!   with its class and cause and planned no further; it has no files.
//! - **Transitions** happen at the straight-rod pose, between one run's last configuration and
//!   the next run's first ([`plan_transition`]), one of ([`TransitionKind`]):
//!   `none` (the same configuration), `reconfigure_at_straight` (a self-motion walk with the
//!   rod held at both ends, [`Planner::straight_reconfiguration`]: the rod end stays within
//!   1e-6 m / rad, every sample and chord checked against the straight rod), `unclamp_move`
//!   (the two configurations are not on one valid self-motion component, or their motor angles
//!   differ: the rod is unclamped and taken out of the robot's way, the arm makes a free
//!   joint-linear move checked for limits, self and scene collision without the rod, plus a
//!   stated handling time), `clamp_move` (into the first run of the next placement: the clamp
//!   is moved — a stated handling time — and the arm's free move is checked in the new
//!   placement's scene without the rod), `blocked` (the free move collides: listed, not
//!   planned). Moves are time-parametrized under the same limits as the runs
//!   ([`crate::planning::trajectory::time_parametrize`], from rest to rest; a free move is
//!   sampled every half `planner.max_joint_step` and has no rod-end speed limit).
//! - **Total robot time** = Σ run durations + Σ move times + Σ handling times.
//! - **Sessions** ([`schedule`]): in execution order, a run and the move into it go into the
//!   current session unless that would exceed the session length; then a new session starts
//!   with that move. A run is never split; a session exceeds the length only when it holds a
//!   single run (with its move) longer than the length.
//!
//! # Ordering heuristic ([`order_tour`])
//! One group per placement, in placement order (the fewest clamp moves: one per further
//! placement). Inside a group the runs form an open path minimizing the summed **move time
//! bound** between consecutive runs: the time of the straight joint-space move from rest to
//! rest, `max_c max(|Δ_c|/v_c, √(2|Δ_c|/A_c))` over the joints and the motor (v, A the rig's
//! scaled speed and acceleration limits; [`move_time`]). It is a lower bound of every kind of
//! move (a reconfiguration walks a longer path; an unclamp move adds handling), cheap enough
//! for all pairs; the real moves are planned only along the chosen order. Construction:
//! nearest neighbour from every run as the first (from the first [`NN_STARTS`] when there are
//! more, fewer for thousands of runs: at most ≈ 5·10⁷ bound evaluations), ties broken by input
//! order, the shortest kept; then passes of 2-opt (reverse a stretch whenever that shortens the
//! path; a run's end equals its start, so the cost is symmetric) and Or-opt (move one run to
//! another place whenever that shortens the path) until neither improves, at most
//! [`TWO_OPT_PASSES`] passes. Cost: O(min(n, NN_STARTS)·n² plus passes·n²) bound evaluations (and O(n²) copies per Or-opt pass) of
//! O(dof) each; 173 runs take milliseconds. Not optimal: the bound ignores which moves need
//! unclamping.
//!
//! # Layout input (`records::campaign::read_layout`)
//! `placements.csv` (`placement`, `rig_file`: the placed rig's TOML beside it) and
//! `assignment.csv` (per direction the placement that tests it, its azimuth, and the class);
//! a direction no placement tests is listed with its class and the cause
//! `no_placement_tests_it`, not planned.

use crate::directions::Direction;
use crate::error::Result;
use crate::math::Real;
use crate::planning::cause::BlockCause;
use crate::planning::planner::{Planner, RayPlan};
use crate::planning::rig::RollMode;
use crate::planning::trajectory::{time_parametrize, Phase, TimingLimits, TrajectoryPoint};
use std::path::PathBuf;

/// One bar of the campaign timeline (`timeline.png`, drawn with the `plots` feature): a run,
/// or the move and handling before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimelineBar {
    /// Session (1-based).
    pub session: usize,
    /// Start from the session's start (s).
    pub start_s: f64,
    /// End from the session's start (s).
    pub end_s: f64,
    /// Placement (1-based) of a run; `None` for a move.
    pub placement: Option<usize>,
}

/// Runs tried as the first of a nearest-neighbour path (all runs when fewer).
pub const NN_STARTS: usize = 64;
/// Most improvement passes (2-opt and Or-opt) over the path.
pub const TWO_OPT_PASSES: usize = 50;
/// Default session length (h).
pub const DEFAULT_SESSION_HOURS: Real = 8.0;
/// Default handling time of an unclamp move (s): unclamp the rod, take it out, put it back.
pub const DEFAULT_UNCLAMP_S: Real = 120.0;
/// Default handling time of a clamp move (s): move and fasten the clamp at the next placement.
pub const DEFAULT_CLAMP_MOVE_S: Real = 900.0;
/// Two configurations closer than this (rad, max-norm, joints and motor) are the same.
pub const SAME_CONFIGURATION: Real = 1e-9;

/// Plan one ray for execution, as `helixreach plan` does: the best of `azimuths`, the path
/// kept, and the bifurcation type of the direction when the rig's margin past s* depends on it
/// ([`crate::planning::rig::PlannerSettings::margin_for`]).
pub fn plan_run(
    planner: &Planner,
    dir: &Direction,
    s_star: Real,
    azimuths: &[Real],
    roll: RollMode,
) -> Result<RayPlan> {
    let kind = if planner.rig().planner.type_dependent() {
        Some(crate::bifurcation::planning_type(dir)?)
    } else {
        None
    };
    planner.plan_best_typed(dir, s_star, kind, azimuths, roll, true)
}

/// The move time bound between `(a, ma)` and `(b, mb)` (joints, motor) under `lim`: a straight
/// joint-space move from rest to rest (module docs).
///
/// ```
/// use helixreach::planning::campaign::move_time;
/// use helixreach::planning::trajectory::TimingLimits;
/// let lim = TimingLimits { joint_velocity: vec![1.0], joint_acceleration: vec![1.0],
///     motor_velocity: 1.0, motor_acceleration: 1.0, end_speed: 1.0, ray_speed: 1.0,
///     rod_length: 1.0, hold_time: 0.0 };
/// // 0.5 rad: the acceleration bound √(2·0.5/1) = 1 s beats 0.5/1 s.
/// assert!((move_time(&[0.0], 0.0, &[0.5], 0.0, &lim) - 1.0).abs() < 1e-12);
/// // 8 rad: the speed bound 8 s beats 4 s.
/// assert!((move_time(&[0.0], 0.0, &[0.0], 8.0, &lim) - 8.0).abs() < 1e-12);
/// ```
pub fn move_time(a: &[Real], ma: Real, b: &[Real], mb: Real, lim: &TimingLimits) -> Real {
    let one = |d: Real, v: Real, acc: Real| {
        let d = d.abs();
        (d / v).max((2.0 * d / acc).sqrt())
    };
    let mut t = one(mb - ma, lim.motor_velocity, lim.motor_acceleration);
    for (j, (x, y)) in a.iter().zip(b).enumerate() {
        t = t.max(one(y - x, lim.joint_velocity[j], lim.joint_acceleration[j]));
    }
    t
}

/// An open path through `n` runs minimizing Σ `cost(i, j)` over consecutive runs (module
/// docs, "Ordering heuristic"); `cost` must be symmetric. Deterministic.
///
/// ```
/// use helixreach::planning::campaign::order_tour;
/// // Points on a line, shuffled: the best open path visits them in order.
/// let x: [f64; 5] = [3.0, 0.0, 4.0, 1.0, 2.0];
/// let p = order_tour(5, |i, j| (x[i] - x[j]).abs());
/// let v: Vec<f64> = p.iter().map(|&i| x[i]).collect();
/// assert!(v == [0.0, 1.0, 2.0, 3.0, 4.0] || v == [4.0, 3.0, 2.0, 1.0, 0.0], "{v:?}");
/// ```
pub fn order_tour(n: usize, cost: impl Fn(usize, usize) -> Real) -> Vec<usize> {
    if n <= 2 {
        return (0..n).collect();
    }
    let length = |p: &[usize]| p.windows(2).map(|w| cost(w[0], w[1])).sum::<Real>();
    let mut best: Option<(Real, Vec<usize>)> = None;
    let mut used = vec![false; n];
    // At most ≈ 5·10⁷ cost evaluations for the starts.
    let starts = n.min(NN_STARTS).min((50_000_000 / (n * n)).max(1));
    for first in 0..starts {
        used.iter_mut().for_each(|u| *u = false);
        let mut path = Vec::with_capacity(n);
        path.push(first);
        used[first] = true;
        let mut cur = first;
        for _ in 1..n {
            let mut next = usize::MAX;
            let mut c_next = Real::INFINITY;
            for (j, &u) in used.iter().enumerate() {
                if !u {
                    let c = cost(cur, j);
                    if c < c_next {
                        c_next = c;
                        next = j;
                    }
                }
            }
            // Every cost infinite: take the first unused run.
            if next == usize::MAX {
                next = used.iter().position(|u| !u).unwrap_or(0);
            }
            used[next] = true;
            path.push(next);
            cur = next;
        }
        let len = length(&path);
        if best.as_ref().is_none_or(|(b, _)| len < *b) {
            best = Some((len, path));
        }
    }
    let Some((_, mut path)) = best else {
        return (0..n).collect();
    };
    // 2-opt on the open path: reversing path[i..=j] swaps the edges (i−1, i), (j, j+1) for
    // (i−1, j), (i, j+1); a missing edge (past either end) costs 0.
    let edge = |p: &[usize], a: Option<usize>, b: Option<usize>| match (a, b) {
        (Some(a), Some(b)) if b < p.len() => cost(p[a], p[b]),
        _ => 0.0,
    };
    for _ in 0..TWO_OPT_PASSES {
        let mut improved = false;
        for i in 0..n - 1 {
            for j in i + 1..n {
                let before = if i == 0 {
                    0.0
                } else {
                    edge(&path, Some(i - 1), Some(i))
                } + edge(&path, Some(j), Some(j + 1));
                let after = if i == 0 {
                    0.0
                } else {
                    edge(&path, Some(i - 1), Some(j))
                } + edge(&path, Some(i), Some(j + 1));
                if after < before - 1e-12 * before.abs().max(1.0) {
                    path[i..=j].reverse();
                    improved = true;
                }
            }
        }
        // Or-opt: move one run elsewhere when that shortens the path.
        for i in 0..n {
            let c = path[i];
            let prev = (i > 0).then(|| path[i - 1]);
            let next = path.get(i + 1).copied();
            let removed = prev.map_or(0.0, |p| cost(p, c)) + next.map_or(0.0, |q| cost(c, q))
                - match (prev, next) {
                    (Some(p), Some(q)) => cost(p, q),
                    _ => 0.0,
                };
            let mut rest = path.clone();
            rest.remove(i);
            // Insert before position k of `rest` (k = n − 1: at the end).
            let mut best_k = None;
            let mut best_add = removed - 1e-12 * removed.abs().max(1.0);
            for k in 0..n {
                let a = (k > 0).then(|| rest[k - 1]);
                let b = rest.get(k).copied();
                let add = a.map_or(0.0, |a| cost(a, c)) + b.map_or(0.0, |b| cost(c, b))
                    - match (a, b) {
                        (Some(a), Some(b)) => cost(a, b),
                        _ => 0.0,
                    };
                if add < best_add {
                    best_add = add;
                    best_k = Some(k);
                }
            }
            if let Some(k) = best_k {
                rest.insert(k, c);
                path = rest;
                improved = true;
            }
        }
        if !improved {
            break;
        }
    }
    path
}

/// The kind of a move between runs (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TransitionKind {
    /// Into the first run: the robot starts there.
    Start,
    /// The next run starts where the last one ended.
    None,
    /// Self-motion at the straight rod, the rod held.
    ReconfigureAtStraight,
    /// The rod unclamped, a free move.
    UnclampMove,
    /// The clamp moved to the next placement, a free move.
    ClampMove,
    /// The free move collides: not planned.
    Blocked,
}

impl TransitionKind {
    /// The name used in `campaign.csv`.
    pub fn as_str(&self) -> &'static str {
        match self {
            TransitionKind::Start => "start",
            TransitionKind::None => "none",
            TransitionKind::ReconfigureAtStraight => "reconfigure_at_straight",
            TransitionKind::UnclampMove => "unclamp_move",
            TransitionKind::ClampMove => "clamp_move",
            TransitionKind::Blocked => "blocked",
        }
    }
}

/// A planned move between runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Transition {
    /// Its kind.
    pub kind: TransitionKind,
    /// Robot motion time (s).
    pub motion_s: Real,
    /// Stated handling time (s).
    pub handling_s: Real,
    /// The move's samples `(t, joints, motor)` from the last configuration to the next (empty
    /// when nothing moves or the move is blocked).
    pub points: Vec<(Real, Vec<Real>, Real)>,
    /// Why a `blocked` move is blocked.
    pub cause: Option<BlockCause>,
}

impl Transition {
    fn still(kind: TransitionKind) -> Transition {
        Transition {
            kind,
            motion_s: 0.0,
            handling_s: 0.0,
            points: Vec::new(),
            cause: None,
        }
    }
}

/// Handling times of the moves (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Handling {
    /// Per unclamp move.
    pub unclamp_s: Real,
    /// Per clamp move.
    pub clamp_move_s: Real,
}

impl Default for Handling {
    fn default() -> Self {
        Handling {
            unclamp_s: DEFAULT_UNCLAMP_S,
            clamp_move_s: DEFAULT_CLAMP_MOVE_S,
        }
    }
}

/// Time-parametrize the joint path `path` (joints, motor) on `planner`'s limits, from rest to
/// rest, as the runs are.
fn timed(planner: &Planner, path: &[(Vec<Real>, Real)]) -> Result<Vec<(Real, Vec<Real>, Real)>> {
    let lim = crate::planning::trajectory::timing_limits(planner)?;
    let mut pts: Vec<TrajectoryPoint> = path
        .iter()
        .map(|(q, m)| TrajectoryPoint {
            t: 0.0,
            q: q.clone(),
            motor: *m,
            s: 0.0,
            kto: [0.0; 3],
            pose: planner.tool_pose(q),
            phase: Phase::Reconfigure,
            velocity: Vec::new(),
            acceleration: Vec::new(),
        })
        .collect();
    time_parametrize(&mut pts, &lim)?;
    Ok(pts.into_iter().map(|p| (p.t, p.q, p.motor)).collect())
}

/// The straight joint move from `(a, ma)` to `(b, mb)` from rest to rest on a trapezoidal
/// profile of the path parameter u ∈ [0, 1] (all channels in step): speed `V = min_c v_c/|Δ_c|`,
/// acceleration `A = min_c A_c/|Δ_c|` over the channels that move (the rig's scaled limits),
/// cruise at V when the move is long enough, else a triangle. Sampled uniformly in u, every
/// joint step within half the rig's `max_joint_step`, times `t(u)` exact on the profile.
fn trapezoid(
    planner: &Planner,
    (a, ma): (&[Real], Real),
    (b, mb): (&[Real], Real),
) -> Result<Vec<(Real, Vec<Real>, Real)>> {
    let lim = crate::planning::trajectory::timing_limits(planner)?;
    let (mut v, mut acc) = (Real::INFINITY, Real::INFINITY);
    let mut dmax: Real = 0.0;
    let chans = a
        .iter()
        .zip(b)
        .enumerate()
        .map(|(j, (x, y))| (y - x, lim.joint_velocity[j], lim.joint_acceleration[j]))
        .chain(std::iter::once((
            mb - ma,
            lim.motor_velocity,
            lim.motor_acceleration,
        )));
    for (k, (d, vc, ac)) in chans.enumerate() {
        if d != 0.0 {
            v = v.min(vc / d.abs());
            acc = acc.min(ac / d.abs());
        }
        if k < a.len() {
            dmax = dmax.max(d.abs());
        }
    }
    if !(v.is_finite() && acc.is_finite()) {
        return Ok(vec![(0.0, a.to_vec(), ma)]);
    }
    // Accelerate for t_a to speed v_top over u_a, cruise, decelerate symmetrically.
    let (t_a, v_top) = if v * v / acc >= 1.0 {
        let t = (1.0 / acc).sqrt();
        (t, acc * t)
    } else {
        (v / acc, v)
    };
    let u_a = 0.5 * v_top * t_a;
    let total = 2.0 * t_a + (1.0 - 2.0 * u_a).max(0.0) / v_top;
    let time = |u: Real| {
        if u <= u_a {
            (2.0 * u / acc).sqrt()
        } else if u >= 1.0 - u_a {
            total - (2.0 * (1.0 - u).max(0.0) / acc).sqrt()
        } else {
            t_a + (u - u_a) / v_top
        }
    };
    let step = 0.5 * planner.rig().planner.max_joint_step;
    let n = ((dmax / step).ceil() as usize).max(1);
    Ok((0..=n)
        .map(|k| {
            let u = k as Real / n as Real;
            let q = a.iter().zip(b).map(|(x, y)| x + u * (y - x)).collect();
            (time(u), q, ma + u * (mb - ma))
        })
        .collect())
}

/// Plan the move from `(from, m_from)` (the last run's end) to `(to, m_to)` (the next run's
/// start) on `planner` (the next run's rig); `clamp_move`: the next run is on another
/// placement. See the module docs.
pub fn plan_transition(
    planner: &Planner,
    (from, m_from): (&[Real], Real),
    (to, m_to): (&[Real], Real),
    clamp_move: bool,
    handling: &Handling,
) -> Result<Transition> {
    let same = from
        .iter()
        .zip(to)
        .all(|(x, y)| (x - y).abs() <= SAME_CONFIGURATION)
        && (m_from - m_to).abs() <= SAME_CONFIGURATION;
    if same && !clamp_move {
        return Ok(Transition::still(TransitionKind::None));
    }
    if !clamp_move && (m_from - m_to).abs() <= SAME_CONFIGURATION {
        if let Some(walk) = planner.straight_reconfiguration(from, to, m_from)? {
            let mut path = vec![(from.to_vec(), m_from)];
            path.extend(walk.into_iter().map(|q| (q, m_from)));
            let points = timed(planner, &path)?;
            return Ok(Transition {
                kind: TransitionKind::ReconfigureAtStraight,
                motion_s: points.last().map_or(0.0, |p| p.0),
                handling_s: 0.0,
                points,
                cause: None,
            });
        }
    }
    let (kind, handling_s) = if clamp_move {
        (TransitionKind::ClampMove, handling.clamp_move_s)
    } else {
        (TransitionKind::UnclampMove, handling.unclamp_s)
    };
    if same {
        return Ok(Transition {
            handling_s,
            ..Transition::still(kind)
        });
    }
    match planner.free_move(from, to, false)? {
        Ok(()) => {
            let points = trapezoid(planner, (from, m_from), (to, m_to))?;
            Ok(Transition {
                kind,
                motion_s: points.last().map_or(0.0, |p| p.0),
                handling_s,
                points,
                cause: None,
            })
        }
        Err(cause) => Ok(Transition {
            cause: Some(cause),
            handling_s,
            ..Transition::still(TransitionKind::Blocked)
        }),
    }
}

/// Where a run lies in the sessions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slot {
    /// Session (1-based).
    pub session: usize,
    /// Start of the run from the start of its session (s), after the move into it.
    pub start_s: Real,
}

/// Split runs into sessions of at most `session_s` (module docs): `blocks[i]` = (time of the
/// move into run i with its handling, duration of run i), in execution order. Returns each
/// run's slot and each session's length.
///
/// ```
/// use helixreach::planning::campaign::schedule;
/// let (slots, lengths) = schedule(&[(1.0, 4.0), (1.0, 4.0), (0.0, 12.0), (1.0, 1.0)], 10.0);
/// assert_eq!(slots.iter().map(|s| s.session).collect::<Vec<_>>(), [1, 1, 2, 3]);
/// assert_eq!(lengths, [10.0, 12.0, 2.0]);
/// assert_eq!(slots[1].start_s, 6.0);
/// ```
pub fn schedule(blocks: &[(Real, Real)], session_s: Real) -> (Vec<Slot>, Vec<Real>) {
    let mut slots = Vec::with_capacity(blocks.len());
    let mut lengths: Vec<Real> = Vec::new();
    for &(pre, run) in blocks {
        let need = pre + run;
        let count = lengths.len();
        match lengths.last_mut() {
            Some(cur) if *cur + need <= session_s => {
                slots.push(Slot {
                    session: count,
                    start_s: *cur + pre,
                });
                *cur += need;
            }
            _ => {
                lengths.push(need);
                slots.push(Slot {
                    session: lengths.len(),
                    start_s: pre,
                });
            }
        }
    }
    (slots, lengths)
}

/// A direction of a layout's `assignment.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct Assigned {
    /// The direction.
    pub dir: Direction,
    /// The 1-based placement that tests it; `None` when none does.
    pub placement: Option<usize>,
    /// The azimuth of that placement's plan.
    pub azimuth: Option<Real>,
    /// The layout's class (the best over the placements when none tests it).
    pub class: String,
    /// The farthest s the layout reached.
    pub s_reached: Option<Real>,
}

/// A layout folder read for a campaign: the placed rigs (in placement order) and the
/// assignment.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutInput {
    /// Each placement's rig file (`placements.csv` order, placement 1, 2, …).
    pub rig_files: Vec<PathBuf>,
    /// Every direction of `assignment.csv`, in file order.
    pub assigned: Vec<Assigned>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heap's algorithm: the shortest open path over every permutation (brute force).
    fn brute_force(n: usize, cost: &dyn Fn(usize, usize) -> Real) -> Real {
        let mut p: Vec<usize> = (0..n).collect();
        let len = |p: &[usize]| p.windows(2).map(|w| cost(w[0], w[1])).sum::<Real>();
        let mut best = len(&p);
        let mut c = vec![0; n];
        let mut i = 0;
        while i < n {
            if c[i] < i {
                if i % 2 == 0 {
                    p.swap(0, i);
                } else {
                    p.swap(c[i], i);
                }
                best = best.min(len(&p));
                c[i] += 1;
                i = 0;
            } else {
                c[i] = 0;
                i += 1;
            }
        }
        best
    }

    /// On 40 random sets of 7 points in the plane (Euclidean cost), the tour is a permutation,
    /// never longer than the input order, within 15 % of the brute-force optimum, and optimal
    /// on at least 35 (measured: 38 optimal, the others 1.6 % and 11 % longer).
    #[test]
    fn tours_against_brute_force() {
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as Real / (1u64 << 53) as Real
        };
        let mut optimal = 0;
        for _ in 0..40 {
            let pts: Vec<(Real, Real)> = (0..7).map(|_| (rnd(), rnd())).collect();
            let cost = |i: usize, j: usize| {
                ((pts[i].0 - pts[j].0).powi(2) + (pts[i].1 - pts[j].1).powi(2)).sqrt()
            };
            let tour = order_tour(7, cost);
            let mut sorted = tour.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..7).collect::<Vec<_>>());
            let len = |p: &[usize]| p.windows(2).map(|w| cost(w[0], w[1])).sum::<Real>();
            let best = brute_force(7, &cost);
            let got = len(&tour);
            assert!(got <= len(&(0..7).collect::<Vec<_>>()) + 1e-12);
            assert!(got <= 1.15 * best + 1e-12, "{got} vs optimum {best}");
            if got <= best + 1e-12 {
                optimal += 1;
            }
        }
        assert!(optimal >= 35, "optimal on {optimal} of 40");
    }
}
