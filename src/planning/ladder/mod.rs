//! The ladder: a ray decided by rungs of tracked IK solutions under dynamic programming
//! (Descartes-style: pose path → rungs → DP → joint + motor path), `planner.search = "ladder"`.
//!
//! The search of the valid set ([`crate::planning::search`], the default) decides a ray
//! exactly at a stated resolution, with a path or a certificate (or reports it `undecided` at
//! its node bound). The ladder finds a path when
//! its stages find one and gives no certificate of a stop: a ray it calls partial may be
//! testable. It is kept as `--search ladder` and as the peer of the search's speed and
//! coverage figures (`docs/RESULTS.md`). Submodules: [`dp`] (the layered graph and its forward
//! dynamic programming), `gate` (the pointwise gate).
//!
//! # Rungs
//! - **Start** (s = 0, the straight rod — the same pose for every ray and azimuth): a diverse set
//!   of fresh IK solutions, [`IkSolver::solve_all`] with the redundancy joint locked at
//!   `redundancy_samples` values, computed once per roll mode and cached. The valid solutions
//!   are grouped by connected valid self-motion component (walks at the held straight-rod pose,
//!   [`crate::planning::self_motion`]); the first rung is the `redundancy_samples` most diverse
//!   solutions, and every component it misses gets its own start rung (the start set and its
//!   components: `planner/start.rs` module docs; in roll `motor` the components are
//!   those of the 2-D valid set, joined by walks about the tool axis). A ray that is not
//!   testable from the first rung is planned again from each further component, and the
//!   farthest plan is kept.
//! - **Waypoint k+1**: every node of rung k is tracked to the new pose by one Levenberg–Marquardt
//!   run seeded at its joints ([`IkSolver::track`]: minimum-norm steps, so the track follows the
//!   self-motion manifold continuously). When the rung is thinner than `redundancy_samples`, new
//!   nodes are spawned next to the cheapest surviving ones by tracking with the redundancy joint
//!   locked half a joint step away, so the rung keeps its diversity.
//! - The targets of the roll modes are the planner's ([`crate::planning::planner`], "Shared by
//!   both decisions"); in roll `motor` the motor angle is unwrapped continuously along the
//!   track. Each node is pruned by: no IK (the track does not converge), or not valid (the
//!   planner's validity: limits, self, scene and rod collision).
//!
//! # Dense levels: the whole valid self-motion set of the start
//! Which point of the start's self-motion set the ladder starts from decides which rays it
//! drives: tracks are continuous, and a reconfiguration only walks the component of the nodes it
//! holds at the pose where it is blocked. The seed experiment shows it: 7 of its 58 runs start on
//! the same start component as our rungs (within 0.01 rad of a walk through it) but at a point
//! our 8 base nodes miss, and only from there is the ray testable. So every connected valid
//! component of the straight rod's pose is sampled densely — its IK solutions plus the
//! self-motion walk through it at `self_motion_step` — and ordered farthest-point first (each
//! prefix is spread over the component; a longer prefix contains a shorter one). A ray that the
//! base rungs do not make testable is planned again from the first k nodes of every component,
//! k = 2R, 4R, … ≤ `planner.dense_samples` (R = `redundancy_samples`; rung width k per
//! component), and the farthest plan is kept; the first testable level ends the search.
//!
//! **Monotone in sampling**: the levels for `dense_samples` D are a subset of those for 2D, so
//! doubling D never reaches less. (The base width R is not such a knob: raising it changes
//! every level.) The pointwise gate below depends on the base plan only, so it acts alike for
//! every D.
//!
//! **Resolution**: level k samples each start component at k points, about L/k apart along it
//! (L ≈ 5.7 rad max-norm for the seed rig's start loop: 227 walk samples at 0.05 rad), so
//! `dense_samples` = 32 puts a start node every ≈ 0.18 rad of self-motion. Measured on the
//! seed's 58 runs (`cargo run --release --example seed_witness -- --levels 8,16,32,64,128,256`):
//! every answer is the same from k = 16 to 256 (52 testable; 45 without dense levels). On 200
//! quarter-sphere directions (margin 0.1, `examples/coverage_convergence.rs`) the testable
//! fraction is 54.5 / 76.5 / 76.5 / 78.0 / 78.0 % at k = 8 (base) / 16 / 32 / 64 / 128:
//! converged at 64; the default 32 is 1.5 points short. Cost: a ray testable from the
//! base rungs costs nothing more; a ray the levels run for pays every level (≈ 0.4 s at k = 16,
//! 1 s at 32, 5 s at 128 CPU for a ray blocked near its end, release, under load).
//!
//! # Pointwise gate (before the dense levels; code in `ladder/gate.rs`)
//! Every level is a full re-plan with rungs k × (components) wide, so a ray no level can
//! improve would pay all of them for nothing. The gate decides that for rays the base plan
//! leaves **partial**: the base stopped inside the regular waypoint interval (w_i, w_{i+1}] (at
//! w_i or at one of its refinement midpoints). If the end w_{i+1} has no valid configuration —
//! IK, joint and motor limits, self, scene and rod collision, the same tests as a ladder node —
//! then no level can accept w_{i+1} (every node of a rung is such a configuration), so no level
//! is testable and the levels are skipped (`RayPlan::levels_gated`). The same test runs again
//! after each dense level that gets farther than the plans before it, at the interval where
//! that level stopped: when that interval's end has no valid configuration the denser levels
//! are skipped (each is a full re-plan, and could only add refinement midpoints inside that
//! interval; same guarantee as below).
//!
//! The valid set of a pose is sampled:
//! - **Roll `fixed`** (1-D self-motion): tracks from the base plan's last rung, 60 random
//!   restarts, and the redundancy joint j0 locked on a 0.05 rad grid over its whole range (each
//!   value seeded from the 6 candidates nearest in j0) — finer than the 0.18 rad start spacing of
//!   the default level 32 and equal to the dense reference's grid.
//! - **Roll `motor`** (2-D: j0 × the roll ψ about the rod tangent): the same candidates with the
//!   roll free, then j0 locked on the same 0.05 rad grid, each value tracked (roll free) from
//!   the 6 nearest candidates, and from each distinct solution a walk about the tool axis with
//!   j0 still locked, full-pose targets every 0.05 rad of ψ around the whole circle, each tracked
//!   from the previous sample (a walk ends where its track fails: a limit or a singularity). The
//!   motor angle passes when any 2π-branch of `ω/c − ψ` lies in the motor's range. The grid is
//!   0.05 rad (j0) × 0.05 rad (ψ), ≈ 122 × 126 points per IK branch for the Sawyer; a rung of
//!   a motor level holds at most k ≤ 32 tracked nodes per start component.
//!
//! What is guaranteed, and what is not:
//! - **Class**: unchanged, provided the pointwise test finds a valid configuration whenever one
//!   exists. A valid piece of the set narrower than the grid, or on an IK branch none of the
//!   nearest seeds converges to, could be missed.
//! - **s reached**: a level could still accept refinement midpoints inside (s_reached, w_{i+1})
//!   (at most `MAX_REFINE` = 4 halvings per interval: the 1/16 points of the interval), so a
//!   gated ray may report an s_reached short of what the levels would reach, by less than one
//!   waypoint interval. Measured on 200 quarter-sphere directions (roll `fixed`, margin 0.1): all
//!   200 classes identical with and without the gate; 2 of the 22 gated rays reach less, by
//!   0.0045 and 0.0015 (0.06 % and 0.05 % of s).
//! - Cost: a gated ray pays the base plan and one pointwise test (≈ 15 ms instead of ≈ 0.3 s for
//!   a ray blocked early in roll `fixed`, release, under load). Rays whose base plan stops at a
//!   pose with valid configurations (a discontinuity, typically blocked near their end) still
//!   run every level.
//!
//! # Edges
//! `i → j` exists when every joint step is ≤ `max_joint_step`; its cost is `‖W·Δq‖ +
//! w_m·|Δm|`. The straight joint-space segment is checked for collision at interior samples no
//! more than `segment_check_step` apart (max-norm), against the rod of the later waypoint. The DP
//! is [`dp::Ladder`].
//!
//! # Reconfiguration at a held pose
//! When no node of the next rung can be joined even after `MAX_REFINE` halvings of the s-step,
//! and the rig allows it (`planner.allow_reconfiguration`), the arm may move along the
//! self-motion manifold of the **held** rod-end pose ([`crate::planning::self_motion`]): for
//! each reachable node of the last rung (cheapest first, one walk per connected component) the
//! valid component is walked in both directions at resolution `planner.self_motion_step`
//! (every sample: limits, self/scene/rod collision against the held rod, joint-linear segment
//! checked every `segment_check_step`); at every sample the step to the next waypoint is tried
//! (track, step bound, collision). The first sample that advances ends the search; the walk to it
//! is resampled so that the rod end stays within 1e-6 m / 1e-6 rad on every joint-linear chord,
//! re-checked, and becomes a `reconfigure` piece of the path (s constant). The ladder then
//! restarts from that configuration. Reconfiguration only acts where the plan without it stops,
//! so allowing it never makes a ray's class worse (every one of 500 quarter-sphere rays, both
//! roll modes). The farthest s is monotone up to the pointwise gate's bound (less
//! than one waypoint interval): in roll `motor` 8 of the 2,000 quarter-sphere rays (all partial)
//! reach up to 0.029 less with reconfiguration than without. All 8 are the gate:
//! with reconfiguration the first motor plan stops at a discontinuity where the gate skips every
//! further stage; without it that plan stops elsewhere and the levels run on. With the gates off
//! both reach the same s (test `reconfiguration_reaches_less_only_by_the_gates_bound`). The walk
//! covers the connected valid component of each node at the walk resolution; it does not search
//! components no reachable node lies on.
//!
//! # Roll mode `motor` contains `fixed`
//! Every fixed-roll path is a motor-roll path (roll ψ = 0, motor ω/c), so a ray in roll mode
//! `motor` returns the farther of its motor plan and its whole `fixed` plan: `motor` never
//! reaches less than `fixed`. The order is cheapest first, and the first testable plan ends it:
//! 1. the motor plan from the first start rung;
//! 2. the whole `fixed` plan (base, gate, levels; labelled roll `motor`);
//! 3. the pointwise gate (roll `motor`) at the end of the interval where plan 1 stopped: when it
//!    finds no valid configuration, no further motor start can pass it, and 4–5 are skipped;
//! 4. the motor plans from the further start components: components of the 2-D valid set
//!    (j0 × roll), found by walks about the tool axis between the rolls of the straight rod's
//!    free-roll IK solutions (`planner/start.rs` module docs). For the seed rig its 78
//!    solutions lie on 73 fixed-roll (1-D) components, which the roll walks join into 11; the
//!    first rung touches 8 of them, so 3 further motor plans;
//! 5. the gate again where the farthest of them stopped, and the motor dense levels: the first
//!    k points of each 2-D component (11·k nodes wide for the seed rig; 73·k before the roll
//!    walks joined the components).
//!
//! The class is the same as planning every stage (the gate's sampling caveat aside); a
//! testable ray may get the `fixed` path where the motor levels would also have found one; a
//! ray gated at 3 may reach less than stage 4 would, by less than one waypoint interval.
//!
//! Sampling the 2-D components with k points each (instead of k per roll) is a coarser start
//! set, not a subset of the per-roll one; measured against k per roll (every stage run) on the
//! demo lattice (`reach --fibonacci 100 --quarter --roll motor`) all 100 classes
//! are identical (80 testable); 14 of the 20 partial rays reach a different s (5 farther by
//! ≤ 0.003, 9 less: by ≤ 0.05 except two by 0.55 and 0.47, 10 % of their s), 7 report another
//! cause. CPU 268 → 47 s (`--threads 1`, user + sys, same load).
//!

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{tol, Real};
use crate::planning::cause::{BlockCause, CauseCounts};
use crate::planning::planner::{node, Node, PlannedPoint, Planner, RayPlan, ReachClass, Scratch};
use crate::planning::pose_path::{pose_path, PoseMap, Ray, Spacing, Waypoint};
use crate::planning::rig::RollMode;
use crate::planning::self_motion::{self, Held};
use crate::planning::trajectory::Phase;
use crate::robot::{IkSolver, IkTarget};

pub mod dp;
mod gate;

use dp::Ladder;

/// Halvings of the s-step allowed at one waypoint when its rung cannot be joined.
const MAX_REFINE: u32 = 4;

/// Most reconfigurations of one ray.
const MAX_RECONFIGURATIONS: usize = 64;

impl Planner {
    /// The ladder's decision of one ray (module docs): in roll `fixed` the base plan, the gate
    /// and the dense levels; in roll `motor` the stages of "Roll mode `motor` contains `fixed`".
    pub(crate) fn plan_ladder(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        if roll == RollMode::Fixed {
            return self.plan_ray_in(dir, s_star, azimuth, roll, want_path);
        }
        // Roll `motor` (module docs, "Roll mode `motor` contains `fixed`"): the plan from the
        // first start rung; the whole `fixed` plan; the gate; the further start components; the
        // gate and the dense levels.
        let (first, first_last) = self.plan_first(dir, s_star, azimuth, roll, want_path)?;
        if first.class == ReachClass::Testable {
            return Ok(first);
        }
        let mut fixed = self.plan_ray_in(dir, s_star, azimuth, RollMode::Fixed, want_path)?;
        fixed.roll = RollMode::Motor;
        if fixed.class == ReachClass::Testable {
            return Ok(fixed);
        }
        let farther = |native: RayPlan| {
            if fixed.s_reached > native.s_reached {
                fixed.clone()
            } else {
                native
            }
        };
        if self.level_gate && self.levels_cannot_pass(&first, &first_last)? {
            let mut first = first;
            first.levels_gated = true;
            return Ok(farther(first));
        }
        let (base, base_last) = self.plan_others(first, first_last, want_path)?;
        if base.class == ReachClass::Testable {
            return Ok(base);
        }
        let native = self.plan_levels(base, &base_last, want_path)?;
        Ok(farther(native))
    }

    /// [`Planner::plan_ray`] from the caller's start configurations instead of the cached start
    /// rungs (each must hold the straight rod's end pose to 1e-6 m / rad, else an error; one in
    /// collision or outside the limits is dropped): how far the
    /// ladder gets from a given start, e.g. the start of an executed trajectory. Roll mode as
    /// given (no `fixed` fallback). Errors: a configuration of the wrong length.
    pub fn plan_ray_from(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
        start: &[Vec<Real>],
    ) -> Result<RayPlan> {
        let mut sc = self.new_scratch();
        let straight = [0.0; 3];
        self.rod_nodes(straight, azimuth, &mut sc.rod)?;
        let w0 = Waypoint {
            s: 0.0,
            kto: straight,
            tool: self.rig.straight_tool_pose(),
            motor: 0.0,
        };
        let target = self.target(&w0.tool, roll);
        let mut nodes = Vec::with_capacity(start.len());
        for q in start {
            if q.len() != self.dof {
                return Err(Error::invalid(
                    "start configuration",
                    format!("{q:?}"),
                    format!("needs {} joints", self.dof),
                ));
            }
            let (dp, dr) = target.errors(&self.model.chain().tool_pose(q));
            if !(dp <= tol::TRAJ_POSITION && dr <= tol::TRAJ_ANGLE) {
                return Err(Error::invalid(
                    "start configuration",
                    format!("{q:?}"),
                    format!(
                        "does not hold the straight rod's end pose ({dp:.3e} m, {dr:.3e} rad off)"
                    ),
                ));
            }
            let motor = self.motor_angle(&w0, q, roll, 0.0);
            if self.check_config(q, &mut sc).is_err() || !self.motor_ok(motor) {
                continue;
            }
            let n = Node::from_joints(q, motor);
            nodes.push(n);
        }
        let width = self.rig.planner.redundancy_samples;
        let mut last = Vec::new();
        self.plan_from(
            dir, s_star, azimuth, roll, want_path, &nodes, width, &mut last,
        )
    }

    /// [`Planner::plan_base`], then (when that is not testable) the gate and the dense levels
    /// ([`Planner::plan_levels`]).
    fn plan_ray_in(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let (best, best_last) = self.plan_base(dir, s_star, azimuth, roll, want_path)?;
        self.plan_levels(best, &best_last, want_path)
    }

    /// Plan from the first start rung; when that is not testable, from each further start
    /// component in turn, keeping the farthest (the first testable ends the search). Returns
    /// the plan and the last rung it reached.
    fn plan_base(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<(RayPlan, Vec<Node>)> {
        let (first, first_last) = self.plan_first(dir, s_star, azimuth, roll, want_path)?;
        self.plan_others(first, first_last, want_path)
    }

    /// The plan from the first start rung, and the last rung it reached.
    fn plan_first(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<(RayPlan, Vec<Node>)> {
        let set = self.start(roll).ok();
        let width = self.rig.planner.redundancy_samples;
        let first = set.map_or(&[][..], |s| &s.first[..]);
        let mut last = Vec::new();
        let plan = self.plan_from(
            dir, s_star, azimuth, roll, want_path, first, width, &mut last,
        )?;
        Ok((plan, last))
    }

    /// After the plan from the first start rung (`best`, last rung `best_last`): unless it is
    /// testable, the plans from each further start component in turn, keeping the farthest (the
    /// first testable ends the search).
    fn plan_others(
        &self,
        mut best: RayPlan,
        mut best_last: Vec<Node>,
        want_path: bool,
    ) -> Result<(RayPlan, Vec<Node>)> {
        let (dir, s_star, azimuth, roll) = (best.dir, best.s_star, best.azimuth, best.roll);
        let set = self.start(roll).ok();
        let width = self.rig.planner.redundancy_samples;
        let mut last = Vec::new();
        for group in set.map_or(&[][..], |s| &s.others[..]) {
            if best.class == ReachClass::Testable {
                break;
            }
            let p = self.plan_from(
                &dir, s_star, azimuth, roll, want_path, group, width, &mut last,
            )?;
            if p.s_reached > best.s_reached {
                best = p;
                std::mem::swap(&mut best_last, &mut last);
            }
        }
        Ok((best, best_last))
    }

    /// The dense levels after the base plan `base` (last rung `base_last`; module docs), unless
    /// it is testable or the pointwise gate shows that no level can pass the end of the waypoint
    /// interval it stopped in. Returns the farthest plan.
    fn plan_levels(&self, base: RayPlan, base_last: &[Node], want_path: bool) -> Result<RayPlan> {
        let mut best = base;
        let width = self.rig.planner.redundancy_samples;
        if best.class == ReachClass::Testable || 2 * width > self.rig.planner.dense_samples {
            return Ok(best);
        }
        if self.level_gate && self.levels_cannot_pass(&best, base_last)? {
            best.levels_gated = true;
            return Ok(best);
        }
        let (dir, s_star, azimuth, roll) = (best.dir, best.s_star, best.azimuth, best.roll);
        let set = self.start(roll).ok();
        let mut last = Vec::new();
        let mut best_last = base_last.to_vec();
        // Dense levels: nested, denser samplings of every start component.
        let comps = set.map_or(&[][..], |s| &s.comps[..]);
        let mut k = 2 * width;
        while k <= self.rig.planner.dense_samples && best.class != ReachClass::Testable {
            let start: Vec<Node> = comps
                .iter()
                .flat_map(|c| c.iter().take(k).copied())
                .collect();
            let mut p = self.plan_from(
                &dir,
                s_star,
                azimuth,
                roll,
                want_path,
                &start,
                start.len(),
                &mut last,
            )?;
            p.start_samples = k;
            let gate_after = p.s_reached > best.s_reached;
            if gate_after {
                best = p;
                std::mem::swap(&mut best_last, &mut last);
            }
            if comps.iter().all(|c| c.len() <= k) {
                break;
            }
            // The gate again where this level got farther: no denser level can pass the end
            // of the interval it stopped in when that end has no valid configuration.
            if gate_after
                && self.level_gate
                && best.class != ReachClass::Testable
                && self.levels_cannot_pass(&best, &best_last)?
            {
                best.levels_gated = true;
                break;
            }
            k *= 2;
        }
        Ok(best)
    }

    fn plan_from(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
        start: &[Node],
        width: usize,
        last_rung: &mut Vec<Node>,
    ) -> Result<RayPlan> {
        last_rung.clear();
        if s_star.is_nan() || s_star <= 0.0 {
            return Err(Error::invalid("s_star", s_star, "must be > 0 (or +inf)"));
        }
        crate::error::require_finite("azimuth", azimuth)?;
        let s_end = if s_star.is_finite() {
            s_star * (1.0 + self.rig.planner.margin)
        } else {
            tol::S_MAX
        };
        let ray = Ray {
            dir: [dir.kappa, dir.tau, dir.omega],
            azimuth,
        };
        let wps = pose_path(&self.rig, &ray, s_end, &Spacing::of(&self.rig))?;
        let mut plan = RayPlan {
            dir: *dir,
            s_star,
            s_end,
            s_reached: 0.0,
            class: ReachClass::Blocked,
            cause: None,
            azimuth,
            roll,
            n_waypoints: wps.len(),
            n_reached: 0,
            reconfigurations: 0,
            backoffs: 0,
            search_nodes: 0,
            start_samples: width,
            levels_gated: false,
            path_cost: 0.0,
            max_joint_step: 0.0,
            path: None,
            assumed_type: None,
        };
        if let Err(c) = self.start(roll) {
            plan.cause = Some(c.dominant().unwrap_or(BlockCause::NoIk));
            return Ok(plan);
        }
        let mut sc = self.new_scratch();
        // Rungs, advances and self-motion walks only track from nearby configurations.
        let solver = IkSolver::new(&self.model, self.ik.clone().tracking())?;
        let mut ladder: Ladder<Node> = Ladder::new();
        ladder.push_first(start.to_vec());
        let map = PoseMap::new(&self.rig, azimuth);
        // Finished pieces of the path (before the current ladder): nodes with their waypoints
        // and phases, and their cost.
        let mut done: Vec<(Node, Waypoint, Phase)> = Vec::new();
        let mut done_cost = 0.0;
        let mut reached_before = 0usize;
        let mut accepted: Vec<Waypoint> = Vec::with_capacity(wps.len());
        accepted.push(wps[0].clone());
        // Targets still to reach before wps[next]: refinements (midpoints), innermost last.
        let mut pending: Vec<Waypoint> = Vec::new();
        let mut next = 1;
        let mut depth = 0u32;
        let mut inserted = 0usize;
        let mut stop_cause = None;
        let mut order: Vec<usize> = Vec::new();
        let mut reconfigured_at: Option<Real> = None;
        while next < wps.len() {
            let w = pending.last().unwrap_or(&wps[next]).clone();
            match self.push_rung(
                &mut ladder,
                &w,
                azimuth,
                roll,
                &solver,
                &mut sc,
                &mut order,
                width,
            )? {
                None => {
                    accepted.push(w);
                    if pending.pop().is_none() {
                        next += 1;
                        depth = 0;
                    }
                }
                Some(cause) => {
                    // Refine: a closer pose gives smaller joint steps and easier tracking.
                    let s0 = accepted.last().map_or(0.0, |a| a.s);
                    if depth < MAX_REFINE {
                        let sm = 0.5 * (s0 + w.s);
                        let kto = [sm * dir.kappa, sm * dir.tau, sm * dir.omega];
                        let (tool, motor) = map.end(kto)?;
                        pending.push(Waypoint {
                            s: sm,
                            kto,
                            tool,
                            motor,
                        });
                        depth += 1;
                        inserted += 1;
                        continue;
                    }
                    // Reconfigure at the held pose (once per held waypoint).
                    let held = accepted.last().expect("non-empty").clone();
                    if self.rig.planner.allow_reconfiguration
                        && plan.reconfigurations < MAX_RECONFIGURATIONS
                        && reconfigured_at != Some(held.s)
                    {
                        reconfigured_at = Some(held.s);
                        if let Some((i, walk, walk_cost)) =
                            self.reconfigure(&ladder, &held, &w, azimuth, roll, &solver)?
                        {
                            let (path, cost) = ladder.path_to(i).expect("node of the last rung");
                            let skip = usize::from(!done.is_empty());
                            for (n, wp) in path.iter().zip(&accepted).skip(skip) {
                                done.push((**n, wp.clone(), Phase::Load));
                            }
                            reached_before += accepted.len() - skip;
                            for n in &walk {
                                done.push((*n, held.clone(), Phase::Reconfigure));
                            }
                            done_cost += cost + walk_cost;
                            plan.reconfigurations += 1;
                            let last = *walk.last().expect("non-empty walk");
                            ladder.push_first(vec![last]);
                            accepted.clear();
                            accepted.push(held);
                            continue;
                        }
                    }
                    stop_cause = Some(cause);
                    break;
                }
            }
        }
        plan.n_waypoints = wps.len() + inserted;
        // A pose path cut short by `planner.max_waypoints` ends before s_end: whatever the
        // ladder did, the ray was not planned to its end.
        if stop_cause.is_none() && wps.last().is_some_and(|w| w.s < s_end) {
            stop_cause = Some(BlockCause::WaypointLimit);
        }
        last_rung.extend_from_slice(ladder.last().0);
        let skip = usize::from(!done.is_empty());
        let reached = reached_before + ladder.len() - skip;
        plan.n_reached = reached;
        plan.s_reached = accepted[ladder.len() - 1].s;
        plan.cause = stop_cause;
        plan.class = if stop_cause.is_none() {
            if s_star.is_finite() {
                ReachClass::Testable
            } else {
                ReachClass::Partial
            }
        } else if reached > 1 {
            ReachClass::Partial
        } else {
            ReachClass::Blocked
        };
        if let Some((path, cost)) = ladder.best_path() {
            plan.path_cost = done_cost + cost;
            let mut full: Vec<(Node, Waypoint, Phase)> = done;
            for (n, wp) in path.iter().zip(&accepted).skip(skip) {
                full.push((**n, wp.clone(), Phase::Load));
            }
            plan.max_joint_step = full
                .windows(2)
                .map(|p| {
                    (0..self.dof)
                        .map(|j| (p[1].0.q[j] - p[0].0.q[j]).abs())
                        .fold(0.0, Real::max)
                })
                .fold(0.0, Real::max);
            if want_path {
                plan.path = Some(
                    full.into_iter()
                        .map(|(n, waypoint, phase)| PlannedPoint {
                            waypoint,
                            q: n.q[..self.dof].to_vec(),
                            motor: n.motor,
                            phase,
                        })
                        .collect(),
                );
            }
        }
        Ok(plan)
    }

    /// Search the self-motion of the held pose for a configuration from which the next waypoint
    /// `next` can be joined (module docs). Returns the index of the last-rung node it starts
    /// from, the resampled walk (after that node; its last entry advances) and the walk's cost.
    #[allow(clippy::type_complexity)]
    fn reconfigure(
        &self,
        ladder: &Ladder<Node>,
        held: &Waypoint,
        next: &Waypoint,
        azimuth: Real,
        roll: RollMode,
        solver: &IkSolver<'_>,
    ) -> Result<Option<(usize, Vec<Node>, Real)>> {
        if self.dof != 7 {
            return Ok(None);
        }
        let settings = self.walk_settings();
        let mut sh = self.new_scratch(); // held rod
        let mut sn = self.new_scratch(); // next rod
        self.rod_nodes(held.kto, azimuth, &mut sh.rod)?;
        self.rod_nodes(next.kto, azimuth, &mut sn.rod)?;
        let next_target = self.target(&next.tool, roll);
        let (prev, prev_cost) = ladder.last();
        let mut order: Vec<usize> = (0..prev.len()).collect();
        order.sort_by(|&a, &b| prev_cost[a].total_cmp(&prev_cost[b]).then(a.cmp(&b)));
        let mut visited: Vec<self_motion::Q> = Vec::new();
        let near = |a: &self_motion::Q, b: &self_motion::Q| {
            (0..self.dof).all(|j| (a[j] - b[j]).abs() <= 0.5 * settings.joint_step_bound)
        };
        for &i in &order {
            let start = prev[i];
            if visited.iter().any(|v| near(v, &start.q)) {
                continue;
            }
            visited.push(start.q);
            let held_pose = Held {
                chain: self.model.chain(),
                solver,
                tip: self.model.chain().tool_pose(&start.q[..self.dof]),
                dof: self.dof,
            };
            let motor = start.motor;
            for sign in [1.0, -1.0] {
                let mut found: Option<Node> = None;
                let (samples, hit) = self_motion::walk(
                    &held_pose,
                    &start.q,
                    sign,
                    &settings,
                    |a, b| {
                        self.check_config(&b[..self.dof], &mut sh).is_ok()
                            && self
                                .check_segment(&node(*a, motor), &node(*b, motor), &mut sh)
                                .is_ok()
                    },
                    |q| {
                        found = self.advance(
                            &node(*q, motor),
                            next,
                            &next_target,
                            roll,
                            solver,
                            &mut sn,
                        );
                        found.is_some()
                    },
                );
                visited.extend(samples.iter().copied());
                if !hit {
                    continue;
                }
                // Resample, re-check every sample and chord against the held rod.
                let mut coarse = vec![start.q];
                coarse.extend(samples.iter().copied());
                let Some(fine) = self_motion::refine(&held_pose, &coarse) else {
                    continue;
                };
                let mut ok = true;
                let mut prev_q = start.q;
                let mut cost = 0.0;
                for q in &fine {
                    let (a, b) = (node(prev_q, motor), node(*q, motor));
                    match self.edge_cost(&a, &b) {
                        Some(c)
                            if self.check_config(&q[..self.dof], &mut sh).is_ok()
                                && self.check_segment(&a, &b, &mut sh).is_ok() =>
                        {
                            cost += c;
                        }
                        _ => {
                            ok = false;
                            break;
                        }
                    }
                    prev_q = *q;
                }
                if ok && found.is_some() {
                    let walk: Vec<Node> = fine.iter().map(|q| node(*q, motor)).collect();
                    return Ok(Some((i, walk, cost)));
                }
            }
        }
        Ok(None)
    }

    /// The node of waypoint `next` tracked from `from` (unlocked, then with the redundancy joint
    /// half a step either side) that passes every check of a ladder edge, if any.
    fn advance(
        &self,
        from: &Node,
        next: &Waypoint,
        target: &IkTarget,
        roll: RollMode,
        solver: &IkSolver<'_>,
        sc: &mut Scratch,
    ) -> Option<Node> {
        let j = self.red_joint;
        let step = self.rig.planner.max_joint_step;
        let (lower, upper) = (self.model.lower(), self.model.upper());
        let locks = [
            None,
            Some((j, from.q[j] + 0.5 * step)),
            Some((j, from.q[j] - 0.5 * step)),
        ];
        for lock in locks {
            if let Some((_, v)) = lock {
                if !(v > lower[j] && v < upper[j]) {
                    continue;
                }
            }
            let Some(sol) = solver.track(target, &from.q[..self.dof], lock) else {
                continue;
            };
            let q = sol.joints();
            let motor = self.motor_angle(next, q, roll, from.motor);
            if !self.motor_ok(motor) {
                continue;
            }
            let n = Node::from_joints(q, motor);
            if self.edge_cost(from, &n).is_some()
                && self.check_config(q, sc).is_ok()
                && self.check_segment(from, &n, sc).is_ok()
            {
                return Some(n);
            }
        }
        None
    }

    /// Build the rung of waypoint `w` from the ladder's last rung and push it; `None` on
    /// success, else the blocking cause (the ladder is unchanged).
    fn push_rung(
        &self,
        ladder: &mut Ladder<Node>,
        w: &Waypoint,
        azimuth: Real,
        roll: RollMode,
        solver: &IkSolver<'_>,
        sc: &mut Scratch,
        order: &mut Vec<usize>,
        width: usize,
    ) -> Result<Option<BlockCause>> {
        let step = self.rig.planner.max_joint_step;
        let (lower, upper) = (self.model.lower(), self.model.upper());
        self.rod_nodes(w.kto, azimuth, &mut sc.rod)?;
        let target = self.target(&w.tool, roll);
        let (prev, prev_cost) = ladder.last();
        let mut nodes: Vec<Node> = Vec::with_capacity(width.max(prev.len()));
        let mut causes = CauseCounts::default();
        // Cheapest predecessors first (they seed the tracks and the spawns).
        order.clear();
        order.extend(0..prev.len());
        order.sort_by(|&a, &b| prev_cost[a].total_cmp(&prev_cost[b]).then(a.cmp(&b)));
        let mut try_node =
            |seed: &Node, lock: Option<(usize, Real)>, nodes: &mut Vec<Node>, sc: &mut Scratch| {
                let Some(sol) = solver.track(&target, &seed.q[..self.dof], lock) else {
                    let near_limit = (0..self.dof)
                        .any(|j| seed.q[j] - lower[j] < step || upper[j] - seed.q[j] < step);
                    causes.add(if near_limit {
                        BlockCause::JointLimit
                    } else {
                        BlockCause::NoIk
                    });
                    return;
                };
                let q = sol.joints();
                if nodes.iter().any(|n| {
                    (0..self.dof).all(|j| (n.q[j] - q[j]).abs() <= self.ik.dedup_tolerance)
                }) {
                    return;
                }
                let motor = self.motor_angle(w, q, roll, seed.motor);
                if !self.motor_ok(motor) {
                    causes.add(BlockCause::JointLimit);
                    return;
                }
                if let Err(c) = self.check_config(q, sc) {
                    causes.add(c);
                    return;
                }
                let node = Node::from_joints(q, motor);
                nodes.push(node);
            };
        for &i in order.iter() {
            try_node(&prev[i], None, &mut nodes, sc);
        }
        // Spawn next to the cheapest survivors when the rung is thin; only along a self-motion
        // (an arm without one, e.g. 6 joints in roll `fixed`, has no neighbouring solution to
        // spawn, and its failed locked tracks would be counted as causes).
        if nodes.len() < width && self.dof > target.dimension() {
            let j = self.red_joint;
            'spawn: for &i in order.iter() {
                for sign in [1.0, -1.0] {
                    if nodes.len() >= width {
                        break 'spawn;
                    }
                    let v = prev[i].q[j] + sign * 0.5 * step;
                    if v > lower[j] && v < upper[j] {
                        try_node(&prev[i], Some((j, v)), &mut nodes, sc);
                    }
                }
            }
        }
        if nodes.is_empty() {
            return Ok(Some(causes.dominant().unwrap_or(BlockCause::NoIk)));
        }
        let out = ladder.push_rung(
            nodes,
            |a, b| self.edge_cost(a, b),
            |a, b| self.check_segment(a, b, sc),
        );
        Ok(if out.reachable == 0 { out.cause } else { None })
    }
}
