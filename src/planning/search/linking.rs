//! Linking: the edges of the search graph, from one configuration to its neighbours.
//!
//! From a configuration x = (i, q, ψ) of slice i (see [`super::slices`]):
//! - **Load** (to slice i + 1) and **back-off** (to slice i − 1): one minimum-norm
//!   Levenberg–Marquardt run ([`IkSolver::track`]) from q to the neighbouring slice's pose at the
//!   same roll ψ. Minimum-norm steps follow the self-motion curve continuously, so the tracked
//!   point is the continuation of x's piece of the valid set. Where that step fails (no
//!   convergence, or a joint step over the bound) the move is **bridged**: the s-interval is
//!   halved (at most `planner.bridge_halvings` times, the ladder's refinement) and crossed by a
//!   chain of such tracks through the intermediate poses, each end checked against its own rod
//!   and each segment against the rod of the larger s; the chain is part of the edge. The runs
//!   start undamped
//!   ([`crate::robot::IkParams::tracking`]): from a neighbouring slice's solution the
//!   Gauss–Newton step converges quadratically.
//! - **Landing** (7-DOF arms): where a load or back-off track converges within the bound but
//!   its end y is in collision (scene, self or rod), the self-motion curve of y's slice
//!   through y is walked on both sides in predictor–corrector sub-steps of
//!   `LANDING_SUB_FRACTION`·`planner.max_joint_step`, each point checked, up to the first valid
//!   point while it stays within the joint-step bound of x ([`Linker::landing`]). The edge is
//!   x → that point, a joint-linear segment checked like any load step; the walk through the
//!   invalid stretch is not driven. A walk that meets a known node stops: that stretch is
//!   reached already. The minimum-norm track picks one point of the next slice's curve near x;
//!   the landing makes the valid points beside it, a narrow valid arc next to a collision,
//!   edges too (on Baxter's right arm, 39 collision primitives, a search without landings
//!   reaches 1–4 slices less than the ladder on 13 of 100 rays).
//! - **Walk** (inside slice i, roll held; 7-DOF arms): a step of h = `planner.search_step`
//!   along the self-motion curve of the held pose in either direction. Within
//!   `WALK_SUB_FRACTION`·`planner.max_joint_step` it is one predictor–corrector step,
//!   predictor `q ± h·n̂` (n̂ the cofactor null direction of the Jacobian, max-norm 1), halved
//!   at most `WALK_HALVINGS` times when the corrector jumps or does not move forward (the rule
//!   of [`crate::planning::self_motion`]): a walk stops within h/8 of where its curve leaves the
//!   valid set (a joint limit, a fold), 0.005 rad with the seed rig's sub-steps of 0.04 rad (a
//!   predictor line that leaves the joint limits within a quarter of h/8 is not tracked: every
//!   trial would be clamped onto the limit that close and refused); a
//!   longer h is a chain of equal sub-steps within that
//!   bound, each one such step from the last with its end and segment checked, the chain
//!   ending at its last accepted point ([`Linker::walk`]).
//! - **Roll** (inside slice i, roll `motor` only): ψ ± `ROLL_STEP` tracked from q at the same
//!   rod-end pose (the motor turns the other way, m = ω/c − ψ). The last joint turns by about
//!   the roll step, sometimes a little more: where the single track exceeds
//!   `planner.max_joint_step` (on the seed rig about one roll step in nine at its bound 0.05
//!   rad, and every one at 0.03 rad) or does not converge, the move is a chain of up to
//!   `ROLL_MAX_SUB` equal sub-rolls, each within `WALK_SUB_FRACTION` of the bound where the
//!   single step's joint motion is spread evenly, its end and segment checked
//!   ([`Linker::roll_chain`]), so a joint-step bound below the roll step keeps the roll.
//!
//! A load or roll move whose predictor — the track's first trial ([`IkSolver::predict`], one
//! Jacobian and one 6×6 solve; the track's end is second-order close to it) — lies on a known
//! node is not tracked: that stretch is already sampled, as for a walk whose predictor does.
//! In a 2-D roll `motor` piece nine roll steps in ten and most loads end on nodes made another
//! way (a quarter less CPU on such rays); in roll `fixed` most nodes are made by back-off
//! steps, which are tracked as they are.
//!
//! Every edge x → y needs: y converged to 1e-10 m / rad, every joint step ≤
//! `planner.max_joint_step` (max-norm), y valid (limits, motor range, collisions), and the
//! joint-linear segment collision-free (against the rod of the larger s). A rejected edge is
//! counted under its cause (no IK, joint limit, the collision kind, or `discontinuity` for the
//! step bound): the blocking cause of a ray is the dominant one at its farthest slice.

use super::slices::{check_rod, segment_rod, tip_of, Slices};
use crate::math::{Real, Vec3};
use crate::planning::cause::BlockCause;
use crate::planning::planner::Planner;
use crate::planning::pose_path::Waypoint;
use crate::planning::self_motion::{self, null_direction, Held, Q};
use crate::robot::{CollisionWorkspace, IkSolver, IkTarget, Jacobian};

/// Longest sub-step of a walk, as a fraction of `planner.max_joint_step` ([`Linker::walk`]).
pub(crate) const WALK_SUB_FRACTION: Real = 0.8;

/// Halvings of a walk step whose corrector fails ([`Linker::walk`]): the step tried is h, h/2,
/// h/4, h/8. Halving further only moves the end of a walk closer to where its curve leaves the
/// valid set, well inside the self-motion resolution, at a track per halving.
const WALK_HALVINGS: usize = 3;

/// Sub-step of a landing walk ([`Linker::landing`]), as a fraction of `planner.max_joint_step`:
/// a valid arc of the landing curve narrower than this (0.0125 rad at the seed rig's bound) can
/// be stepped over. Half the bound stepped over such an arc on one of 100 rays of Baxter's
/// right arm.
pub(crate) const LANDING_SUB_FRACTION: Real = 0.25;

/// Most sub-steps of a landing walk: each moves at least a quarter of a sub-step, so this
/// covers 4·`planner.max_joint_step` of curve, more than the bound lets a landing go.
const LANDING_MAX_STEPS: usize = 16;

/// Roll step of the moves inside a slice in roll `motor` (rad).
pub(crate) const ROLL_STEP: Real = 0.05;

/// Most sub-rolls of a chained roll move ([`Linker::roll_chain`]): a roll step that turns the
/// joints by more than this many times `WALK_SUB_FRACTION`·`planner.max_joint_step` is refused
/// as a discontinuity.
const ROLL_MAX_SUB: usize = 4;

/// Least |det A| (m³: three rows of `J` in m) at which [`fast_null_direction`] trusts its one
/// solve; nearer singular it defers to the seven minors.
const FAST_NULL_MIN_DET: Real = 1e-6;

/// A move from one configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Move {
    /// To the next slice.
    Load,
    /// To the previous slice.
    Backoff,
    /// Along the self-motion curve, sign ±1.
    Walk(i8),
    /// Roll step, sign ±1.
    Roll(i8),
}

/// A configuration: slice, joints, arm roll.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Config {
    /// Slice index.
    pub slice: u32,
    /// Joints (the first `dof` entries).
    pub q: Q,
    /// Arm roll ψ (0 in roll `fixed`).
    pub psi: Real,
}

/// Per-ray linking state: the solver, collision scratch and Jacobian.
pub(crate) struct Linker<'a> {
    planner: &'a Planner,
    slices: &'a Slices,
    solver: IkSolver<'a>,
    ws: CollisionWorkspace,
    /// The Jacobian at `jac_at` (the end of the last successful track, or the last
    /// configuration whose null direction was computed); `jac_at` is NaN when it holds none.
    jac: Jacobian,
    jac_at: Q,
    /// The arm's joint limits.
    lower: Q,
    upper: Q,
    step: Real,
    /// The last walked configuration and its null direction: a node's two walks (±) share it.
    null: Option<(Q, Q)>,
    /// The intermediate poses, configurations and arm rolls of the last bridged move
    /// ([`Linker::propose`] returned [`Proposal::Bridged`]), from its start's side; rod scratch
    /// of a pose between slices, and of the pose before it.
    pub bridge: Vec<(Waypoint, Q, Real)>,
    rod: Vec<Vec3>,
    rod_prev: Vec<Vec3>,
    /// Accept a walk step only where it can be resampled within the hold tolerance
    /// ([`Linker::resample_walk`]): the search's second pass where the path of the first has a
    /// walk that cannot (parent module docs, "Walks that hold the pose").
    pub check_holds: bool,
    /// A bridge's intermediate s still to reach, innermost last (at most
    /// `planner.bridge_halvings`).
    pending: Vec<Real>,
}

/// A move's end configuration, before or after its collision tests.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Proposal {
    /// One step: the caller checks it ([`Linker::accept`]).
    Step(Config),
    /// Across slices through intermediate poses ([`Linker::bridge`]), every configuration and
    /// segment already checked; the chain is in [`Linker::bridge`].
    Bridged(Config),
}

impl<'a> Linker<'a> {
    /// A linker for the slices of one ray.
    pub fn new(planner: &'a Planner, slices: &'a Slices) -> crate::Result<Linker<'a>> {
        Ok(Linker {
            planner,
            slices,
            solver: IkSolver::new(&planner.model, planner.ik.clone().tracking())?,
            ws: planner.collision.workspace(),
            jac: Jacobian::zeros(),
            jac_at: [Real::NAN; crate::robot::MAX_DOF],
            lower: planner.model.lower(),
            upper: planner.model.upper(),
            step: planner.rig.planner.search_step,
            null: None,
            bridge: Vec::new(),
            check_holds: false,
            rod: vec![Vec3::zeros(); planner.rig.planner.rod_capsules + 1],
            rod_prev: vec![Vec3::zeros(); planner.rig.planner.rod_capsules + 1],
            pending: Vec::with_capacity(planner.rig.planner.bridge_halvings),
        })
    }

    /// One track from `seed`; its Jacobian at the end is kept ([`Linker::null_hint`]).
    fn track(&mut self, target: &IkTarget, seed: &Q) -> Option<Q> {
        let dof = self.planner.dof;
        let Some(sol) = self
            .solver
            .track_with_jacobian(target, &seed[..dof], None, &mut self.jac)
        else {
            self.jac_at[0] = Real::NAN;
            return None;
        };
        let mut q = [0.0; crate::robot::MAX_DOF];
        q[..dof].copy_from_slice(sol.joints());
        self.jac_at = q;
        Some(q)
    }

    fn max_step(&self, a: &Q, b: &Q) -> Real {
        (0..self.planner.dof)
            .map(|j| (a[j] - b[j]).abs())
            .fold(0.0, Real::max)
    }

    /// The configuration reached from `x` by `mv`, before the collision tests: `Err` with the
    /// cause when the move has no target (first/last slice, a walk on a non-redundant arm), the
    /// track fails, the step exceeds the bound or the motor leaves its range. `Ok(None)` when
    /// the move does not exist (no cause to count).
    /// A walk, load or roll whose predictor already lies on a known node (`known`) is not
    /// corrected (`Ok(None)`).
    pub fn propose(
        &mut self,
        x: &Config,
        mv: Move,
        known: &dyn Fn(&Config) -> bool,
    ) -> std::result::Result<Option<Proposal>, BlockCause> {
        let i = x.slice as usize;
        let bound = self.planner.rig.planner.max_joint_step;
        let (slice, psi) = match mv {
            Move::Load if i + 1 < self.slices.len() => (i + 1, x.psi),
            Move::Backoff if i > 0 => (i - 1, x.psi),
            Move::Roll(sign) => (i, x.psi + Real::from(sign) * ROLL_STEP),
            Move::Walk(_) => (i, x.psi),
            _ => return Ok(None),
        };
        let target = self.slices.target(self.planner, slice, psi);
        if let Move::Walk(sign) = mv {
            return Ok(self.walk(&target, x, Real::from(sign), known));
        }
        if let Move::Roll(_) | Move::Load = mv {
            // The predictor on a known node: that stretch is sampled (module docs).
            let dof = self.planner.dof;
            if let Some(p) = self.solver.predict(&target, &x.q[..dof]) {
                let pred = Config {
                    slice: slice as u32,
                    q: p,
                    psi,
                };
                if known(&pred) {
                    return Ok(None);
                }
            }
        }
        let q = {
            let tracked = self.track(&target, &x.q);
            match tracked {
                Some(q) if self.max_step(&x.q, &q) <= bound => q,
                _ => {
                    // No single step across slices: through poses between them, or the cause.
                    if matches!(mv, Move::Load | Move::Backoff) {
                        if let Some(y) = self.bridge(x, slice, psi) {
                            return Ok(Some(Proposal::Bridged(y)));
                        }
                    }
                    if let Move::Roll(_) = mv {
                        let single = tracked.map(|q| self.max_step(&x.q, &q));
                        return self.roll_chain(x, psi, single);
                    }
                    if tracked.is_some() {
                        return Err(BlockCause::Discontinuity);
                    }
                    return Err(self.failed_track_cause(&x.q));
                }
            }
        };
        if self.max_step(&x.q, &q) > bound {
            return Err(BlockCause::Discontinuity);
        }
        if !self.planner.motor_ok(self.slices.motor(slice, psi)) {
            return Err(BlockCause::JointLimit);
        }
        Ok(Some(Proposal::Step(Config {
            slice: slice as u32,
            q,
            psi,
        })))
    }

    /// The cause of a track from `q` that did not converge: a joint limit when a joint is within
    /// the joint-step bound of one, else no IK.
    fn failed_track_cause(&self, q: &Q) -> BlockCause {
        let bound = self.planner.rig.planner.max_joint_step;
        let (lo, hi) = (&self.lower, &self.upper);
        let near = (0..self.planner.dof).any(|j| q[j] - lo[j] < bound || hi[j] - q[j] < bound);
        if near {
            BlockCause::JointLimit
        } else {
            BlockCause::NoIk
        }
    }

    /// A roll move from `x` to `psi_end` whose single track did not converge or exceeded the
    /// joint-step bound (its joint step `single`, `None` when it did not converge), as a chain
    /// of k equal sub-rolls, k = ⌈`single` / (`WALK_SUB_FRACTION`·bound)⌉ (2 without a
    /// step), at least 2 and at most `ROLL_MAX_SUB`: each tracked from the last, within the
    /// bound, its motor angle in range, its end valid and its segment collision-free. Like a
    /// chained walk it ends at its last accepted point ([`Proposal::Bridged`], the intermediate
    /// configurations in [`Linker::bridge`]); `Err` with the first sub-roll's cause when none is
    /// accepted.
    fn roll_chain(
        &mut self,
        x: &Config,
        psi_end: Real,
        single: Option<Real>,
    ) -> std::result::Result<Option<Proposal>, BlockCause> {
        let bound = self.planner.rig.planner.max_joint_step;
        let sub_max = WALK_SUB_FRACTION * bound;
        let k = single
            .map_or(2.0, |step| (step / sub_max).ceil())
            .clamp(2.0, ROLL_MAX_SUB as Real) as usize;
        let i = x.slice as usize;
        self.bridge.clear();
        let mut cur = *x;
        for m in 1..=k {
            let psi = x.psi + (psi_end - x.psi) * m as Real / k as Real;
            let target = self.slices.target(self.planner, i, psi);
            let refused = match self.track(&target, &cur.q) {
                None => Some(self.failed_track_cause(&cur.q)),
                Some(q) if self.max_step(&cur.q, &q) > bound => Some(BlockCause::Discontinuity),
                Some(_) if !self.planner.motor_ok(self.slices.motor(i, psi)) => {
                    Some(BlockCause::JointLimit)
                }
                Some(q) => {
                    let y = Config { q, psi, ..*x };
                    match self.accept(&cur, &y) {
                        Ok(()) => {
                            self.bridge.push((self.slices.wps[i].clone(), q, psi));
                            cur = y;
                            None
                        }
                        Err(cause) => Some(cause),
                    }
                }
            };
            match refused {
                Some(cause) if m == 1 => return Err(cause),
                Some(_) => break,
                None => {}
            }
        }
        // The first sub-roll was accepted (a refused one returned above).
        let Some((_, q, psi)) = self.bridge.pop() else {
            return Ok(None);
        };
        Ok(Some(Proposal::Bridged(Config { q, psi, ..*x })))
    }

    /// A move from `x` to slice `to` through intermediate poses: the s-interval is halved where
    /// a step fails (at most `planner.bridge_halvings` times in all, like the ladder's
    /// refinement; the first halving is the interval's midpoint, the direct step having failed), each
    /// step one minimum-norm track within the joint-step bound, its end valid against its own
    /// rod (and the motor range) and its segment collision-free against the rod of the larger
    /// s. The chain (intermediate poses and configurations) is left in `self.bridge`; `None`
    /// when no chain is found.
    fn bridge(&mut self, x: &Config, to: usize, psi: Real) -> Option<Config> {
        let bound = self.planner.rig.planner.max_joint_step;
        let max_halvings = self.planner.rig.planner.bridge_halvings;
        if max_halvings == 0 {
            return None;
        }
        let planner = self.planner;
        let slices = self.slices;
        self.bridge.clear();
        let (s_goal, s_from) = (slices.wps[to].s, slices.wps[x.slice as usize].s);
        let mut cur = x.q;
        let mut s_cur = s_from;
        // The rod of the current end (`rod_prev`), for segments toward smaller s.
        self.rod_prev
            .copy_from_slice(&slices.rods[x.slice as usize]);
        // The direct step failed: start at the interval's midpoint.
        self.pending.clear();
        self.pending.push(0.5 * (s_from + s_goal));
        let mut halvings = 1;
        loop {
            let inner = self.pending.last().copied();
            let (target, wp) = match inner {
                Some(sm) => {
                    let w = slices.between(planner, sm, &mut self.rod).ok()?;
                    (IkTarget::Pose(tip_of(planner, &w, psi)), Some(w))
                }
                None => {
                    self.rod.copy_from_slice(&slices.rods[to]);
                    (slices.target(planner, to, psi), None)
                }
            };
            let s_t = inner.unwrap_or(s_goal);
            let motor = wp.as_ref().map_or(slices.motor(to, psi), |w| w.motor - psi);
            let ok = self.track(&target, &cur).filter(|q| {
                self.max_step(&cur, q) <= bound
                    && planner.motor_ok(motor)
                    && check_rod(planner, &self.rod, &q[..planner.dof], &mut self.ws).is_ok()
                    && {
                        let seg_rod = if s_t > s_cur {
                            &self.rod
                        } else {
                            &self.rod_prev
                        };
                        segment_rod(planner, seg_rod, &cur, q, &mut self.ws).is_ok()
                    }
            });
            match ok {
                Some(q) => {
                    if inner.is_none() {
                        return Some(Config {
                            slice: to as u32,
                            q,
                            psi,
                        });
                    }
                    self.pending.pop();
                    self.bridge
                        .push((wp.expect("an intermediate pose"), q, psi));
                    cur = q;
                    s_cur = s_t;
                    std::mem::swap(&mut self.rod, &mut self.rod_prev);
                }
                None if halvings < max_halvings => {
                    self.pending.push(0.5 * (s_cur + s_t));
                    halvings += 1;
                }
                None => return None,
            }
        }
    }

    /// Where the one-step load or back-off from `x` lands at `y` and `y` is in collision: the
    /// nearest valid configuration of `y`'s slice along its self-motion curve on the side
    /// `sign`, within the joint-step bound of `x` (sub-steps of `LANDING_SUB_FRACTION` of the
    /// bound, each corrected onto the slice's pose, at most `LANDING_MAX_STEPS`; module docs,
    /// "Landing"). The walk itself is not driven: the edge is x → the point found, a
    /// joint-linear segment like any load (the caller checks it). `None` on a non-redundant
    /// arm, at a singularity, where the curve leaves the bound, the limits or the step count
    /// first, or where the walk meets a known node (`known`).
    pub fn landing(
        &mut self,
        x: &Config,
        y: &Config,
        sign: Real,
        known: &dyn Fn(&Config) -> bool,
    ) -> Option<Config> {
        let dof = self.planner.dof;
        if dof != 7 {
            return None;
        }
        let bound = self.planner.rig.planner.max_joint_step;
        let h = LANDING_SUB_FRACTION * bound;
        let target = self.slices.target(self.planner, y.slice as usize, y.psi);
        let mut n = self.null_at(&y.q)?;
        let mut cur = y.q;
        for _ in 0..LANDING_MAX_STEPS {
            let p = self.corrector(&target, &cur, sign, &n, h)?;
            if self.max_step(&x.q, &p) > bound {
                return None;
            }
            let c = Config { q: p, ..*y };
            if known(&c) {
                return None;
            }
            if self.accept_end(&c).is_ok() {
                return Some(c);
            }
            n = self.null_along(&p, &n)?;
            cur = p;
        }
        None
    }

    /// The collision tests of the edge x → y: y itself, then the joint-linear segment.
    pub fn accept(&mut self, x: &Config, y: &Config) -> std::result::Result<(), BlockCause> {
        self.accept_end(y)?;
        self.accept_segment(x, y)
    }

    /// The collision test of an edge's end y.
    pub fn accept_end(&mut self, y: &Config) -> std::result::Result<(), BlockCause> {
        let dof = self.planner.dof;
        self.slices
            .check(self.planner, y.slice as usize, &y.q[..dof], &mut self.ws)
    }

    /// The collision test of the interior of the joint-linear segment x → y, against the rod
    /// of the larger slice.
    pub fn accept_segment(
        &mut self,
        x: &Config,
        y: &Config,
    ) -> std::result::Result<(), BlockCause> {
        let i = x.slice.max(y.slice) as usize;
        self.slices
            .segment(self.planner, i, &x.q, &y.q, &mut self.ws)
    }

    /// Whether a start configuration of slice 0 is valid (collisions; limits and the motor
    /// range are the start set's).
    pub fn start_valid(&mut self, x: &Config) -> bool {
        let dof = self.planner.dof;
        self.planner
            .motor_ok(self.slices.motor(x.slice as usize, x.psi))
            && self
                .slices
                .check(self.planner, x.slice as usize, &x.q[..dof], &mut self.ws)
                .is_ok()
    }

    /// The null direction of the Jacobian at `q` (cofactor orientation, max-norm 1); `None` at
    /// a singularity.
    fn null_at(&mut self, q: &Q) -> Option<Q> {
        let dof = self.planner.dof;
        if self.jac_at != *q {
            self.planner
                .model
                .chain()
                .jacobian(&q[..dof], &mut self.jac);
            self.jac_at = *q;
        }
        fast_null_direction(&self.jac, dof).or_else(|| null_direction(&self.jac, dof))
    }

    /// The null direction at `q` oriented along `prev` (the one of the previous point of a
    /// walk: a non-negative dot product); `None` at a singularity.
    fn null_along(&mut self, q: &Q, prev: &Q) -> Option<Q> {
        let dof = self.planner.dof;
        let mut n = self.null_at(q)?;
        if (0..dof).map(|j| n[j] * prev[j]).sum::<Real>() < 0.0 {
            for v in n.iter_mut() {
                *v = -*v;
            }
        }
        Some(n)
    }

    /// The null direction at `y` when the last track ended there (its Jacobian is at hand:
    /// no evaluation), for the caller to keep until `y`'s walks ([`Linker::prime_null`]);
    /// `None` otherwise, or at a singularity.
    pub fn null_hint(&mut self, y: &Config) -> Option<Q> {
        if self.jac_at == y.q {
            self.null_at(&y.q)
        } else {
            None
        }
    }

    /// The null direction at `q`, kept from [`Linker::null_hint`], for the walks from `q`.
    pub fn prime_null(&mut self, q: &Q, n: Q) {
        self.null = Some((*q, n));
    }

    /// One predictor–corrector step of at most `h` from `q` along the null direction `n`
    /// (orientation `sign`): predictor `q ± h·n`, corrected by a minimum-norm track onto
    /// `target`, halved at most `WALK_HALVINGS` times until the corrected point moves forward along
    /// `n`, by at least a quarter of the predictor's step and within the joint-step bound.
    ///
    /// Where the line `q ± t·n` leaves the joint limits at t below a quarter of the smallest
    /// step tried (h / 2^`WALK_HALVINGS` / 4), nothing is tracked: every trial would be
    /// clamped onto the limit within that distance of `q` and refused as too short.
    fn corrector(&mut self, target: &IkTarget, q: &Q, sign: Real, n: &Q, h: Real) -> Option<Q> {
        let dof = self.planner.dof;
        let shortest = 0.25 * h / (1u32 << WALK_HALVINGS) as Real;
        if limit_exit(&self.lower, &self.upper, q, sign, n, dof) < shortest {
            return None;
        }
        self.halving_steps(target, q, sign, n, h)
    }

    /// The trials of [`Linker::corrector`]: h, h/2, …, h/2^`WALK_HALVINGS`, the first accepted.
    fn halving_steps(&mut self, target: &IkTarget, q: &Q, sign: Real, n: &Q, h: Real) -> Option<Q> {
        let dof = self.planner.dof;
        let bound = self.planner.rig.planner.max_joint_step;
        let mut h = h;
        for _ in 0..=WALK_HALVINGS {
            let mut pred = *q;
            for j in 0..dof {
                pred[j] += sign * h * n[j];
            }
            if let Some(p) = self.track(target, &pred) {
                let step = self.max_step(&p, q);
                let along: Real = (0..dof).map(|j| (p[j] - q[j]) * sign * n[j]).sum();
                if along > 0.0 && step <= bound && step >= 0.25 * h {
                    return Some(p);
                }
            }
            h *= 0.5;
        }
        None
    }

    /// The walk move from `x` along the self-motion curve of `target` (module docs): `None` on
    /// a non-redundant arm, at a singularity, when the first sub-step is not accepted, or when
    /// the full-step predictor `q ± h·n̂` lies on a known node (the predictor is within O(h²)
    /// of the curve: that stretch is already sampled).
    ///
    /// A step `h` = `planner.search_step` within `WALK_SUB_FRACTION` of the joint-step bound
    /// is one corrected step, checked by the caller ([`Proposal::Step`]). A longer step is a
    /// chain of k = ⌈h / (`WALK_SUB_FRACTION`·bound)⌉ equal sub-steps, each corrected from the
    /// last (its null direction oriented along the previous one), its end valid and its
    /// joint-linear segment collision-free ([`Linker::accept`]); the chain stops at the first
    /// sub-step that fails and ends at the last accepted point ([`Proposal::Bridged`], the
    /// intermediate points in [`Linker::bridge`]). A walk edge of any `search_step` is thus
    /// checked as finely as one of `WALK_SUB_FRACTION`·`planner.max_joint_step`.
    fn walk(
        &mut self,
        target: &IkTarget,
        x: &Config,
        sign: Real,
        known: &dyn Fn(&Config) -> bool,
    ) -> Option<Proposal> {
        let q = &x.q;
        let dof = self.planner.dof;
        let n0 = match self.null {
            Some((at, n)) if at == *q => n,
            _ => {
                let n = self.null_at(q)?;
                self.null = Some((*q, n));
                n
            }
        };
        let h = self.step;
        let mut pred = *q;
        for j in 0..dof {
            pred[j] += sign * h * n0[j];
        }
        if known(&Config { q: pred, ..*x }) {
            return None;
        }
        let sub_max = WALK_SUB_FRACTION * self.planner.rig.planner.max_joint_step;
        if h <= sub_max {
            let p = self.corrector(target, q, sign, &n0, h)?;
            if self.check_holds && self.resample_walk(x, &p).is_none() {
                return None;
            }
            return Some(Proposal::Step(Config { q: p, ..*x }));
        }
        let k = (h / sub_max).ceil();
        let sub = h / k;
        let wp = &self.slices.wps[x.slice as usize];
        self.bridge.clear();
        let (mut cur, mut n) = (*q, n0);
        for m in 0..k as usize {
            if m > 0 {
                let Some(nm) = self.null_along(&cur, &n) else {
                    break;
                };
                n = nm;
            }
            let Some(p) = self.corrector(target, &cur, sign, &n, sub) else {
                break;
            };
            let (a, b) = (Config { q: cur, ..*x }, Config { q: p, ..*x });
            if self.accept(&a, &b).is_err() {
                break;
            }
            if self.check_holds && self.resample_walk(&a, &p).is_none() {
                break;
            }
            self.bridge.push((wp.clone(), p, x.psi));
            cur = p;
        }
        let (_, end, _) = self.bridge.pop()?;
        Some(Proposal::Bridged(Config { q: end, ..*x }))
    }

    /// The walk step from `a` to `b` (a configuration of `a`'s slice at `a`'s roll) resampled
    /// so that the rod end stays within [`self_motion::HOLD_TOLERANCE`] of the held pose on
    /// every joint-linear chord ([`self_motion::refine`]), every sample valid and every chord
    /// collision-free: the samples after `a` (the last is `b`). `None` where the bisection
    /// does not converge (`b` is not on `a`'s arc of the self-motion: the corrector stepped
    /// onto a neighbouring branch, near a fold) or a resampled chord collides.
    pub fn resample_walk(&mut self, a: &Config, b: &Q) -> Option<Vec<Q>> {
        let held = Held {
            chain: self.planner.model.chain(),
            solver: &self.solver,
            tip: self.slices.tip(self.planner, a.slice as usize, a.psi),
            dof: self.planner.dof,
        };
        let fine = self_motion::refine(&held, &[a.q, *b])?;
        let mut prev = *a;
        for q in &fine {
            let y = Config { q: *q, ..*a };
            self.accept(&prev, &y).ok()?;
            prev = y;
        }
        Some(fine)
    }
}

/// The first t ≥ 0 at which `q + t·sign·n` reaches a joint limit (`Real::INFINITY` when it
/// never does); 0 when `q` is at a limit and `n` points out through it.
fn limit_exit(lower: &Q, upper: &Q, q: &Q, sign: Real, n: &Q, dof: usize) -> Real {
    (0..dof)
        .map(|j| {
            let v = sign * n[j];
            if v > 0.0 {
                ((upper[j] - q[j]) / v).max(0.0)
            } else if v < 0.0 {
                ((q[j] - lower[j]) / -v).max(0.0)
            } else {
                Real::INFINITY
            }
        })
        .fold(Real::INFINITY, Real::min)
}

/// The cofactor null direction of [`null_direction`] from one LU solve: with `A` the first six
/// columns of `J` and `b` the seventh, `n = det(A)·[−A⁻¹b; 1]` (Cramer's rule gives the same
/// cofactors), scaled to max-norm 1. `None` when `A` is (numerically) singular: then the
/// caller falls back to the seven minors. The elimination (partial pivoting) runs on the rows of
/// `[A | b]` with constant loop bounds, so the compiler unrolls it: it costs about a third of a
/// general LU factorization of `A` and its solve.
fn fast_null_direction(jac: &Jacobian, dof: usize) -> Option<Q> {
    if dof != 7 {
        return None;
    }
    let mut m = [[0.0; 7]; 6];
    for (r, row) in m.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = jac[(r, c)];
        }
    }
    let mut det: Real = 1.0;
    for k in 0..6 {
        let mut p = k;
        for r in k + 1..6 {
            if m[r][k].abs() > m[p][k].abs() {
                p = r;
            }
        }
        if p != k {
            m.swap(p, k);
            det = -det;
        }
        let pivot = m[k][k];
        det *= pivot;
        if pivot == 0.0 || pivot.is_nan() {
            return None;
        }
        let inv = 1.0 / pivot;
        for r in k + 1..6 {
            let f = m[r][k] * inv;
            for c in k + 1..7 {
                m[r][c] -= f * m[k][c];
            }
        }
    }
    if det.is_nan() || det.abs() <= FAST_NULL_MIN_DET {
        return None;
    }
    // A·x = −b by back substitution.
    let mut x = [0.0; 6];
    for k in (0..6).rev() {
        let mut v = -m[k][6];
        for c in k + 1..6 {
            v -= m[k][c] * x[c];
        }
        x[k] = v / m[k][k];
    }
    let mut n = [0.0; crate::robot::MAX_DOF];
    for k in 0..6 {
        n[k] = det * x[k];
    }
    n[6] = det;
    let scale = n.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    for v in n.iter_mut() {
        *v /= scale;
    }
    Some(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planning::rig::RollMode;
    use crate::robot::RobotModel;

    /// A walk of `search_step` 0.16 rad on the seed rig (joint-step bound 0.05) is a chain of
    /// four equal sub-steps: every point holds the slice's pose (1e-9 m / rad), every sub-step
    /// is within the joint-step bound and at least a quarter of its predictor, every point is
    /// collision-free against the slice's rod (a collision model of the test's own), and the
    /// chain ends farther from its start than the merge radius (it is a new sample). From
    /// starts spread over every start component, both directions.
    #[test]
    fn a_long_walk_is_a_chain_of_checked_sub_steps() {
        let (rig, planner, slices, cm) =
            super::super::slices::seed_ray_100(|rig| rig.planner.search_step = 0.16);
        let bound = rig.planner.max_joint_step;
        let mut linker = Linker::new(&planner, &slices).unwrap();
        let mut ws = cm.workspace();
        let rod = rig.rod_geometry(&slices.rods[0]);
        let target = slices.target(&planner, 0, 0.0);
        let set = planner.start(RollMode::Fixed).unwrap();
        let (mut chains, mut full) = (0, 0);
        for comp in &set.comps {
            for n in comp.iter().step_by(7).take(4) {
                let x = Config {
                    slice: 0,
                    q: n.q,
                    psi: 0.0,
                };
                for sign in [1, -1] {
                    let y = match linker.propose(&x, Move::Walk(sign), &|_| false) {
                        Ok(Some(Proposal::Bridged(y))) => y,
                        Ok(Some(Proposal::Step(_))) => panic!("a 0.16 rad walk in one step"),
                        _ => continue,
                    };
                    let mut chain = vec![x.q];
                    chain.extend(linker.bridge.iter().map(|(_, q, _)| *q));
                    chain.push(y.q);
                    chains += 1;
                    full += usize::from(chain.len() == 5);
                    assert!(chain.len() <= 5, "{} points", chain.len());
                    for w in chain.windows(2) {
                        let step = linker.max_step(&w[0], &w[1]);
                        assert!(step <= bound && step >= 0.25 * 0.04 - 1e-12, "{step}");
                    }
                    for q in &chain[1..] {
                        let (dp, dr) = target.errors(&planner.model().chain().tool_pose(&q[..7]));
                        assert!(dp < 1e-9 && dr < 1e-9, "{dp:e} {dr:e}");
                        assert!(cm.check(&q[..7], &mut ws, Some(&rod)).is_none());
                    }
                    if chain.len() == 5 {
                        assert!(
                            linker.max_step(&x.q, &y.q)
                                > super::super::graph::MERGE_FRACTION * 0.16
                        );
                    }
                }
            }
        }
        assert!(
            chains >= 6 && full >= 4,
            "{chains} chains, {full} of four sub-steps"
        );
    }

    /// Roll moves (roll `motor`) within the joint-step bound: on the seed rig, from start
    /// configurations of slice 0 (their arm roll from their motor angle), a roll move in either
    /// direction is one step or a chain of sub-rolls, every link within the bound, every point
    /// holding the slice's pose at its own roll (1e-9 m / rad) and collision-free against the
    /// slice's rod (the test's own collision model), the roll monotone toward ψ ± `ROLL_STEP`.
    /// At the seed's bound 0.05 rad some single steps exceed it (the last joint turns a little
    /// more than the roll) and are chained; at 0.03 rad every one is, and without chains none
    /// would be an edge.
    #[test]
    fn roll_moves_are_chained_within_the_joint_step_bound() {
        for bound in [0.05, 0.03] {
            let (rig, planner, slices, cm) = super::super::slices::seed_ray_100(|rig| {
                rig.planner.max_joint_step = bound;
            });
            let mut linker = Linker::new(&planner, &slices).unwrap();
            let mut ws = cm.workspace();
            let rod = rig.rod_geometry(&slices.rods[0]);
            let set = planner.start(RollMode::Motor).unwrap();
            let (mut tried, mut whole, mut chained) = (0, 0, 0);
            for comp in &set.comps {
                for n in comp.iter().step_by(5).take(6) {
                    // A start node's arm roll: its motor angle is the slice's less the roll.
                    let x = Config {
                        slice: 0,
                        q: n.q,
                        psi: slices.motor(0, 0.0) - n.motor,
                    };
                    for sign in [1, -1] {
                        tried += 1;
                        let mut chain = vec![(x.q, x.psi)];
                        match linker.propose(&x, Move::Roll(sign), &|_| false) {
                            Ok(Some(Proposal::Step(y))) => chain.push((y.q, y.psi)),
                            Ok(Some(Proposal::Bridged(y))) => {
                                chained += 1;
                                chain.extend(linker.bridge.iter().map(|(_, q, p)| (*q, *p)));
                                chain.push((y.q, y.psi));
                            }
                            _ => continue,
                        }
                        let end = chain.last().unwrap().1;
                        whole +=
                            usize::from((end - x.psi - Real::from(sign) * ROLL_STEP).abs() < 1e-12);
                        for w in chain.windows(2) {
                            assert!(linker.max_step(&w[0].0, &w[1].0) <= bound);
                            assert!(Real::from(sign) * (w[1].1 - w[0].1) > 0.0);
                        }
                        for (q, psi) in &chain[1..] {
                            let target = slices.target(&planner, 0, *psi);
                            let (dp, dr) =
                                target.errors(&planner.model().chain().tool_pose(&q[..7]));
                            assert!(dp < 1e-9 && dr < 1e-9, "{dp:e} {dr:e}");
                            assert!(cm.check(&q[..7], &mut ws, Some(&rod)).is_none());
                        }
                    }
                }
            }
            println!("bound {bound}: {whole} whole roll steps of {tried}, {chained} chained");
            assert!(tried >= 40 && whole * 10 >= tried * 9, "{whole} of {tried}");
            assert!(chained >= 1, "no chain at {bound}");
            if bound < ROLL_STEP * WALK_SUB_FRACTION {
                assert!(chained >= whole, "{chained} chained of {whole}");
            }
        }
    }

    /// The corrector skips its trials only where they would all be refused: at configurations
    /// of slice 0 on a joint limit and 0.2, 1 and 4 mrad inside it (tracked with that joint
    /// locked from every other start node, every joint, both limits), walking toward the
    /// limit, [`Linker::corrector`] returns what its trials ([`Linker::halving_steps`]) return,
    /// both where the line leaves the limits within a quarter of the shortest trial step (the
    /// corrector tracks nothing) and beyond.
    #[test]
    fn a_walk_out_through_a_joint_limit_skips_only_refused_trials() {
        let (rig, planner, slices, _) =
            super::super::slices::seed_ray_100(|rig| rig.planner.search_step = 0.16);
        let mut linker = Linker::new(&planner, &slices).unwrap();
        let target = slices.target(&planner, 0, 0.0);
        let h = WALK_SUB_FRACTION * rig.planner.max_joint_step;
        let shortest = 0.25 * h / (1u32 << WALK_HALVINGS) as Real;
        let set = planner.start(RollMode::Fixed).unwrap();
        let (lo, hi) = (planner.model.lower(), planner.model.upper());
        let (mut skipped, mut tracked, mut accepted) = (0, 0, 0);
        for comp in &set.comps {
            for node in comp.iter().step_by(2) {
                for j in 0..7 {
                    // The limit and the direction that points out through it.
                    for (lim, out) in [(lo[j], -1.0), (hi[j], 1.0)] {
                        for inside in [0.0, 2e-4, 1e-3, 4e-3] {
                            let lock = Some((j, lim - out * inside));
                            let Some(sol) = linker.solver.track(&target, &node.q[..7], lock) else {
                                continue;
                            };
                            let mut q = [0.0; crate::robot::MAX_DOF];
                            q[..7].copy_from_slice(sol.joints());
                            let Some(n) = linker.null_at(&q) else {
                                continue;
                            };
                            if n[j].abs() < 0.05 {
                                continue;
                            }
                            let sign = if out * n[j] > 0.0 { 1.0 } else { -1.0 };
                            let got = linker.corrector(&target, &q, sign, &n, h);
                            let want = linker.halving_steps(&target, &q, sign, &n, h);
                            assert_eq!(got, want, "joint {j}, {inside} rad inside {lim}");
                            if limit_exit(&linker.lower, &linker.upper, &q, sign, &n, 7) < shortest
                            {
                                skipped += 1;
                            } else {
                                tracked += 1;
                                accepted += usize::from(want.is_some());
                            }
                        }
                    }
                }
            }
        }
        assert!(
            skipped >= 20 && tracked >= 20 && accepted >= 10,
            "{skipped} skipped, {tracked} tracked ({accepted} accepted)"
        );
    }

    /// The null direction kept from a track's end ([`Linker::null_hint`]) is the one computed
    /// afresh there, bit for bit (the search's node counts do not depend on where it came
    /// from); at another configuration, or after a failed track, there is none.
    #[test]
    fn a_kept_null_direction_is_the_fresh_one() {
        let (_, planner, slices, _) = super::super::slices::seed_ray_100(|_| {});
        let mut linker = Linker::new(&planner, &slices).unwrap();
        let set = planner.start(RollMode::Fixed).unwrap();
        let (mut kept, mut last) = (0, None);
        for node in set.comps.iter().flatten().step_by(3) {
            let x = Config {
                slice: 0,
                q: node.q,
                psi: 0.0,
            };
            let Ok(Some(Proposal::Step(y))) = linker.propose(&x, Move::Load, &|_| false) else {
                continue;
            };
            let hint = linker.null_hint(&y).expect("a track ended at y");
            let mut jac = Jacobian::zeros();
            planner.model.chain().jacobian(&y.q[..7], &mut jac);
            let fresh = fast_null_direction(&jac, 7)
                .or_else(|| null_direction(&jac, 7))
                .unwrap();
            assert_eq!(hint, fresh);
            assert!(linker.null_hint(&x).is_none());
            kept += 1;
            last = Some(y);
        }
        assert!(kept >= 10, "{kept}");
        // A track that fails leaves no Jacobian: not even for the end of the one before.
        let y = last.expect("a load step");
        assert!(linker.null_hint(&y).is_some());
        let mut beyond = slices.tip(&planner, 1, 0.0);
        beyond.pos.x += 10.0;
        assert!(linker.track(&IkTarget::Pose(beyond), &y.q).is_none());
        assert!(linker.null_hint(&y).is_none());
    }

    /// Landings against a constructed collision ([`Linker::landing`]). On the seed rig, from
    /// start configurations x of slice 0 whose load step lands at y (slice 1), a ball is placed
    /// ahead of the link that the self-motion through y moves fastest, its radius set by
    /// bisection so that the arm at y is a set depth inside it. The reference is a separate walk
    /// of y's self-motion curve in 1 mrad steps (each corrected onto slice 1's pose by the
    /// solver's track, not by the landing's corrector), checked with the test's own collision
    /// model (the ball, the scene, the slice's rod) and the joint limits, up to where it leaves
    /// the joint-step bound of x. On each side:
    /// - a landing p holds the pose (1e-9 m / rad), lies on that curve (within 2 mrad of a
    ///   reference point), is valid, is within the bound of x, is no nearer to y than the
    ///   reference's first valid point and at most 1.2 sub-steps into its first valid arc wider
    ///   than 1.5 sub-steps (a narrower arc may be stepped over); with every configuration
    ///   known, there is none;
    /// - no landing: the reference has no valid arc wider than 1.5 sub-steps within the bound.
    ///
    /// The arm is put 0.5, 4 and 15 mm inside the ball: both kinds occur on the sample, and so
    /// do cases with no landing on either side (the ball too deep to leave within the bound).
    #[test]
    fn a_load_that_lands_in_collision_lands_beside_it() {
        use crate::robot::collision::{ObstaclePose, SceneObstacle};
        use crate::robot::Shape;
        let (rig, planner, slices, _) = super::super::slices::seed_ray_100(|_| {});
        let bound = rig.planner.max_joint_step;
        let h = LANDING_SUB_FRACTION * bound;
        let chain = planner.model().chain();
        let mut frames = vec![crate::robot::Frame::default(); chain.n_links()];
        let mut frames2 = frames.clone();
        let mut linker = Linker::new(&planner, &slices).unwrap();
        let target = slices.target(&planner, 1, 0.0);
        let set = planner.start(RollMode::Fixed).unwrap();
        let (mut landed, mut refused, mut cases, mut deep) = (0, 0, 0, 0);
        for node in set.comps.iter().flatten().step_by(5).take(24) {
            let x = Config {
                slice: 0,
                q: node.q,
                psi: 0.0,
            };
            let Ok(Some(Proposal::Step(y))) = linker.propose(&x, Move::Load, &|_| false) else {
                continue;
            };
            // The link the self-motion through y moves fastest, and a ball ahead of it.
            let Some(n) = linker.null_at(&y.q) else {
                continue;
            };
            let mut pred = y.q;
            for j in 0..7 {
                pred[j] += 0.01 * n[j];
            }
            let Some(ahead) = linker.solver.track(&target, &pred[..7], None) else {
                continue;
            };
            chain.link_frames(&y.q[..7], &mut frames);
            chain.link_frames(ahead.joints(), &mut frames2);
            let (link, _) = (0..frames.len())
                .map(|i| (i, (frames2[i].pos - frames[i].pos).norm()))
                .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            let v = (frames2[link].pos - frames[link].pos).normalize();
            let centre = frames[link].pos + 0.25 * v;
            let ball = |radius: Real| {
                let mut r = rig.clone();
                r.obstacles.push(SceneObstacle {
                    name: "probe".into(),
                    shape: Shape::Sphere { radius },
                    pose: ObstaclePose {
                        xyz: [centre.x, centre.y, centre.z],
                        rpy: [0.0; 3],
                    },
                });
                r
            };
            let model_of = |r: &crate::planning::rig::Rig| {
                let mut cm = crate::robot::CollisionModel::for_model(planner.model()).unwrap();
                cm.set_obstacles(&r.obstacles).unwrap();
                cm
            };
            let rod = rig.rod_geometry(&slices.rods[1]);
            let hits = |cm: &crate::robot::CollisionModel, q: &Q| {
                let mut ws = cm.workspace();
                cm.check(&q[..7], &mut ws, Some(&rod)).is_some()
            };
            if hits(&model_of(&rig), &y.q) {
                continue;
            }
            let (mut lo, mut hi) = (0.0, 0.25);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if hits(&model_of(&ball(mid)), &y.q) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            for depth in [5e-4, 4e-3, 1.5e-2] {
                let rig_b = ball(hi + depth);
                let cm = model_of(&rig_b);
                assert!(hits(&cm, &y.q));
                let planner_b = Planner::new(rig_b).unwrap();
                let mut lb = Linker::new(&planner_b, &slices).unwrap();
                let (lower, upper) = (planner.model.lower(), planner.model.upper());
                cases += 1;
                let landed_before = landed;
                for sign in [1.0, -1.0] {
                    // The reference walk: arc length (sum of max-norm steps), point, validity.
                    let mut walk: Vec<(Real, Q, bool)> = vec![(0.0, y.q, false)];
                    let (mut q, mut dir) = (y.q, n);
                    for j in 0..7 {
                        dir[j] *= sign;
                    }
                    while walk.len() < 400 {
                        let mut p = q;
                        for j in 0..7 {
                            p[j] += 1e-3 * dir[j];
                        }
                        let Some(sol) = linker.solver.track(&target, &p[..7], None) else {
                            break;
                        };
                        let mut next = q;
                        next[..7].copy_from_slice(sol.joints());
                        let in_limits = (0..7).all(|j| next[j] >= lower[j] && next[j] <= upper[j]);
                        if !in_limits || linker.max_step(&x.q, &next) > bound {
                            break;
                        }
                        let arc = walk.last().unwrap().0 + linker.max_step(&q, &next);
                        walk.push((arc, next, !hits(&cm, &next)));
                        let Some(m) = linker.null_along(&next, &dir) else {
                            break;
                        };
                        (q, dir) = (next, m);
                    }
                    // Valid arcs of the reference: (start, end) arc lengths.
                    let mut arcs: Vec<(Real, Real)> = Vec::new();
                    let mut open: Option<(Real, Real)> = None;
                    for (a, _, ok) in &walk {
                        if *ok {
                            open = Some(open.map_or((*a, *a), |(start, _)| (start, *a)));
                        } else if let Some(arc) = open.take() {
                            arcs.push(arc);
                        }
                    }
                    arcs.extend(open);
                    let wide = arcs.iter().find(|(a, b)| b - a > 1.5 * h);
                    match lb.landing(&x, &y, sign, &|_| false) {
                        Some(p) => {
                            landed += 1;
                            let (dp, dr) = target.errors(&chain.tool_pose(&p.q[..7]));
                            assert!(dp < 1e-9 && dr < 1e-9, "{dp:e} {dr:e}");
                            assert!(!hits(&cm, &p.q), "the landing is in collision");
                            assert!(linker.max_step(&x.q, &p.q) <= bound);
                            let (gap, at) = walk
                                .iter()
                                .map(|(a, r, _)| (linker.max_step(r, &p.q), *a))
                                .fold((Real::INFINITY, 0.0), |m, v| if v.0 < m.0 { v } else { m });
                            assert!(gap < 2e-3, "the landing is {gap} rad off the curve");
                            let first = arcs.first().expect("the reference finds a valid point");
                            assert!(
                                at >= first.0 - 2e-3,
                                "{at} before the first valid {}",
                                first.0
                            );
                            if let Some((start, _)) = wide {
                                let last = start + 1.2 * h + 2e-3;
                                assert!(
                                    at <= last,
                                    "{at} past {last}, in a valid arc from {start}"
                                );
                            }
                            assert!(lb.landing(&x, &y, sign, &|_| true).is_none());
                        }
                        None => {
                            refused += 1;
                            assert!(
                                wide.is_none(),
                                "a valid arc {wide:?} within the bound missed"
                            );
                        }
                    }
                }
                deep += usize::from(landed == landed_before);
            }
        }
        println!(
            "{cases} cases: {landed} landings, {refused} sides without, {deep} without either"
        );
        assert!(
            cases >= 24 && landed >= 8 && refused >= 8 && deep >= 4,
            "{cases} {landed} {refused} {deep}"
        );
    }

    /// The one-solve null direction equals the seven-minor one (same orientation).
    #[test]
    fn fast_null_direction_matches_cofactors() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let mut j = Jacobian::zeros();
        for k in 0..50 {
            let t = k as Real * 0.37;
            let q = [
                0.3 * t.sin(),
                -0.8 + 0.2 * t.cos(),
                0.2 + 0.1 * t,
                1.4 - 0.05 * t,
                -0.3,
                0.9 * (0.5 * t).cos(),
                0.1,
            ];
            m.chain().jacobian(&q, &mut j);
            let (Some(a), Some(b)) = (fast_null_direction(&j, 7), null_direction(&j, 7)) else {
                continue;
            };
            for i in 0..7 {
                assert!((a[i] - b[i]).abs() < 1e-9, "{k}: {a:?} vs {b:?}");
            }
        }
    }
}
