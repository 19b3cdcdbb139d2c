//! The pointwise gate before the dense levels: the sampled test "does this waypoint have a valid
//! configuration?" in both roll modes. What it samples and what it guarantees is stated in the
//! parent module's docs ([`crate::planning::ladder`], "Pointwise gate").

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{Iso3, Real, Vec3};
use crate::planning::planner::{Node, Planner, RayPlan, ReachClass, Scratch};
use crate::planning::pose_path::{pose_path, PoseMap, Ray, Spacing, Waypoint};
use crate::planning::rig::RollMode;
use crate::robot::{IkParams, IkSolver, MAX_DOF};

/// Redundancy-joint grid of the pointwise gate (rad): finer than the densest default level's
/// start spacing (≈ 0.18 rad of self-motion at `dense_samples` = 32) and equal to the dense
/// reference's grid in `tests/planning_seed.rs`.
pub(super) const GATE_GRID: Real = 0.05;

/// Roll step of the motor-mode gate's walks about the tool axis (rad): the same resolution as
/// the redundancy grid.
pub(super) const GATE_ROLL_STEP: Real = 0.05;

/// Free random restarts of the pointwise gate (all joints free), per pose.
pub(super) const GATE_RESTARTS: usize = 60;

/// Seeds tracked per locked redundancy value by the pointwise gate (the nearest in that joint).
pub(super) const GATE_LOCK_SEEDS: usize = 6;

impl Planner {
    /// The sampled pointwise test at arc length `s` of the ray `dir` (helix azimuth `azimuth`):
    /// does the rod end's pose there have a valid configuration in roll mode `roll` — IK, joint
    /// and motor limits, self, scene and rod collision? The test the gate before the dense
    /// levels uses (module docs of [`crate::planning::ladder`], "Pointwise gate"), here without
    /// seeds from a plan. `false` means none was found. Errors: `s` not finite or negative, a
    /// helix the rod model refuses.
    ///
    /// ```
    /// use helixreach::directions::Direction;
    /// use helixreach::planning::{planner::Planner, rig::{Rig, RollMode}};
    /// let p = Planner::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    /// let d = Direction::new(0.3, 0.4, 0.8).unwrap();
    /// // The straight rod (s = 0) is where every plan starts.
    /// assert!(p.pointwise_valid_at(&d, 0.0, 0.0, RollMode::Fixed).unwrap());
    /// assert!(p.pointwise_valid_at(&d, f64::NAN, 0.0, RollMode::Fixed).is_err());
    /// ```
    pub fn pointwise_valid_at(
        &self,
        dir: &Direction,
        s: Real,
        azimuth: Real,
        roll: RollMode,
    ) -> Result<bool> {
        if !(s.is_finite() && s >= 0.0) {
            return Err(Error::invalid("s", s, "must be finite and >= 0"));
        }
        crate::error::require_finite("azimuth", azimuth)?;
        let kto = [s * dir.kappa, s * dir.tau, s * dir.omega];
        let (tool, motor) = PoseMap::new(&self.rig, azimuth).end(kto)?;
        let w = Waypoint {
            s,
            kto,
            tool,
            motor,
        };
        let mut sc = self.new_scratch();
        let free = self.gate_solver()?;
        self.pointwise_valid(&w, azimuth, roll, &[], &free, &mut sc)
    }

    /// The gate's sampled pointwise test (module docs, "Pointwise gate") at the **last**
    /// waypoint of the ray `dir` at `azimuth` (s = s*·(1 + margin), the planner's own pose path)
    /// in roll mode `fixed`, seeded by the straight rod's start configurations. A testable plan
    /// accepts that waypoint with a node, i.e. a configuration this test looks for, so
    /// `Some(false)` (none found) means no `fixed` plan at this azimuth is testable — with the
    /// gate's guarantee: provided the sampled test finds a valid configuration whenever one
    /// exists. `Some(true)`: one was found. `None`: the test does not apply (not 7 joints, s*
    /// infinite, no valid start configuration).
    pub fn end_pose_valid(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
    ) -> Result<Option<bool>> {
        if self.dof != 7 || !s_star.is_finite() {
            return Ok(None);
        }
        let Ok(set) = self.start(RollMode::Fixed) else {
            return Ok(None);
        };
        let ray = Ray {
            dir: [dir.kappa, dir.tau, dir.omega],
            azimuth,
        };
        let s_end = s_star * (1.0 + self.rig.planner.margin);
        let wps = pose_path(&self.rig, &ray, s_end, &Spacing::of(&self.rig))?;
        let Some(w_end) = wps.last() else {
            return Ok(None);
        };
        let seeds: Vec<Node> = set
            .first
            .iter()
            .chain(set.others.iter().flatten())
            .copied()
            .collect();
        let free = self.gate_solver()?;
        let mut sc = self.new_scratch();
        Ok(Some(self.pointwise_valid(
            w_end,
            azimuth,
            RollMode::Fixed,
            &seeds,
            &free,
            &mut sc,
        )?))
    }

    /// The IK solver of the pointwise tests: all joints free, `GATE_RESTARTS` restarts.
    fn gate_solver(&self) -> Result<IkSolver<'_>> {
        IkSolver::new(
            &self.model,
            IkParams {
                redundancy_joint: None,
                restarts: GATE_RESTARTS,
                max_iterations: 100,
                ..self.ik.clone()
            },
        )
    }

    /// The pointwise gate before the dense levels (module docs, "Pointwise gate"): `true` when
    /// `base` (a partial plan whose last rung is `base_last`) stopped in a regular waypoint
    /// interval whose end has no valid configuration in the sampled pointwise test of its roll
    /// mode ([`Planner::pointwise_valid`]), so no start level
    /// can pass that end.
    pub(super) fn levels_cannot_pass(&self, base: &RayPlan, base_last: &[Node]) -> Result<bool> {
        if base.class != ReachClass::Partial || self.dof != 7 {
            return Ok(false);
        }
        let ray = Ray {
            dir: [base.dir.kappa, base.dir.tau, base.dir.omega],
            azimuth: base.azimuth,
        };
        let wps = pose_path(&self.rig, &ray, base.s_end, &Spacing::of(&self.rig))?;
        let s_b = base.s_reached;
        let Some(i) = wps.iter().rposition(|w| w.s <= s_b) else {
            return Ok(false);
        };
        let Some(w_fail) = wps.get(i + 1) else {
            return Ok(false);
        };
        let mut sc = self.new_scratch();
        let free = self.gate_solver()?;
        let valid =
            self.pointwise_valid(w_fail, base.azimuth, base.roll, base_last, &free, &mut sc)?;
        Ok(!valid)
    }

    /// The gate's sampled pointwise test of waypoint `w` in roll mode `roll` (module docs,
    /// "Pointwise gate"): is there a configuration that holds its pose (roll `fixed`: the full
    /// tool pose; roll `motor`: the rod end's position and tangent, the roll about it free),
    /// inside the joint and motor limits, free of self, scene and rod collision? One search in
    /// both modes; roll `motor` adds the walk about the tool axis (its set is 2-dimensional,
    /// redundancy joint × roll):
    /// 1. candidates: tracks from `seeds` and `GATE_RESTARTS` random restarts (all joints free,
    ///    the mode's target);
    /// 2. the redundancy joint locked on a `GATE_GRID` grid over its whole range, each value
    ///    tracked from the `GATE_LOCK_SEEDS` candidates nearest in that joint;
    /// 3. roll `motor` only: from each distinct solution of 2 (none within `GATE_ROLL_STEP` of
    ///    a sample walked at this value) a walk about the tool axis with the joint still locked:
    ///    full-pose targets at roll offsets ±`GATE_ROLL_STEP`, ±2·`GATE_ROLL_STEP`, … around the
    ///    whole circle, each tracked from the previous sample (the walk ends where a track fails:
    ///    a joint limit or a singularity ends that piece of the curve).
    ///
    /// The first valid configuration ends the test. Sampled: `false` means none was found.
    pub(super) fn pointwise_valid(
        &self,
        w: &Waypoint,
        azimuth: Real,
        roll: RollMode,
        seeds: &[Node],
        free: &IkSolver<'_>,
        sc: &mut Scratch,
    ) -> Result<bool> {
        let walk = roll == RollMode::Motor;
        if !walk && !self.motor_ok(w.motor) {
            return Ok(false);
        }
        self.rod_nodes(w.kto, azimuth, &mut sc.rod)?;
        let target = self.target(&w.tool, roll);
        let valid = |q: &[Real], sc: &mut Scratch| {
            (!walk || self.motor_reachable(w, q)) && self.check_config(q, sc).is_ok()
        };
        // The seeds themselves also seed the locked runs.
        let mut cand: Vec<[Real; MAX_DOF]> = seeds.iter().map(|n| n.q).collect();
        for n in seeds {
            if let Some(sol) = free.track(&target, &n.q[..self.dof], None) {
                cand.push(pad(sol.joints()));
                if valid(sol.joints(), sc) {
                    return Ok(true);
                }
            }
        }
        for sol in free.solve_all(&target, &[]) {
            cand.push(pad(sol.joints()));
            if valid(sol.joints(), sc) {
                return Ok(true);
            }
        }
        // No self-motion at this target (a 6-DOF arm in roll `fixed`): the free runs found
        // the isolated IK branches; a locked joint would leave too few joints.
        if cand.is_empty() || self.dof <= target.dimension() {
            return Ok(false);
        }
        let j = self.red_joint;
        let (lo, hi) = (self.model.lower()[j], self.model.upper()[j]);
        let n = ((hi - lo) / GATE_GRID).floor() as usize;
        let mut order: Vec<usize> = (0..cand.len()).collect();
        // Samples of the roll walks at the current locked value (dedup of branches).
        let mut walked: Vec<[Real; MAX_DOF]> = Vec::new();
        let near = |a: &[Real; MAX_DOF], b: &[Real; MAX_DOF]| {
            (0..self.dof).all(|d| (a[d] - b[d]).abs() <= GATE_ROLL_STEP)
        };
        for g in 0..=n {
            let v = lo + g as Real * GATE_GRID;
            order.sort_by(|&a, &b| (cand[a][j] - v).abs().total_cmp(&(cand[b][j] - v).abs()));
            walked.clear();
            for &c in order.iter().take(GATE_LOCK_SEEDS) {
                let seed = cand[c];
                let Some(sol) = free.track(&target, &seed[..self.dof], Some((j, v))) else {
                    continue;
                };
                let q0 = pad(sol.joints());
                if walk && walked.iter().any(|x| near(x, &q0)) {
                    continue;
                }
                if valid(&q0[..self.dof], sc) {
                    return Ok(true);
                }
                if walk && self.roll_walk_finds(&q0, (j, v), free, &mut walked, &valid, sc) {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    }

    /// Step 3 of [`Planner::pointwise_valid`]: the walk about the tool axis from `q0` (valid
    /// or not), the redundancy joint locked by `lock`; `true` at the first sample `valid`
    /// accepts. Every sample, `q0` first, goes into `walked`.
    #[allow(clippy::too_many_arguments)]
    fn roll_walk_finds(
        &self,
        q0: &[Real; MAX_DOF],
        lock: (usize, Real),
        free: &IkSolver<'_>,
        walked: &mut Vec<[Real; MAX_DOF]>,
        valid: &impl Fn(&[Real], &mut Scratch) -> bool,
        sc: &mut Scratch,
    ) -> bool {
        walked.push(*q0);
        let pose0 = self.tool_pose(&q0[..self.dof]);
        // The + walk covers (0, reach]; the − walk the rest of the circle.
        let mut reach = 0.0;
        for sign in [1.0, -1.0] {
            let span = if sign > 0.0 {
                std::f64::consts::PI
            } else {
                std::f64::consts::TAU - reach
            };
            let mut q = *q0;
            let mut k = 1;
            while (k as Real) * GATE_ROLL_STEP < span + 0.5 * GATE_ROLL_STEP {
                let turn = sign * (k as Real * GATE_ROLL_STEP).min(span);
                let pose = pose0 * Iso3::rotation(Vec3::z() * turn);
                let t = self.target(&pose, RollMode::Fixed);
                let Some(s) = free.track(&t, &q[..self.dof], Some(lock)) else {
                    break;
                };
                q = pad(s.joints());
                if valid(&q[..self.dof], sc) {
                    return true;
                }
                walked.push(q);
                if sign > 0.0 {
                    reach = turn;
                }
                k += 1;
            }
        }
        false
    }

    /// Whether some motor angle that realises waypoint `w` with the arm at `q` lies in the
    /// motor's range: `ω/c − ψ + 2πk` for any integer k (the ladder's unwrapping picks one k;
    /// accepting any keeps the gate on the safe side).
    fn motor_reachable(&self, w: &Waypoint, q: &[Real]) -> bool {
        let (lo, hi) = self.rig.motor.range;
        if hi - lo >= std::f64::consts::TAU {
            return true;
        }
        let m = self.motor_angle(w, q, RollMode::Motor, 0.0);
        let k = ((lo - m) / std::f64::consts::TAU).ceil();
        m + std::f64::consts::TAU * k <= hi
    }
}

/// `q` zero-padded to `MAX_DOF`.
fn pad(q: &[Real]) -> [Real; MAX_DOF] {
    Node::from_joints(q, 0.0).q
}
