//! Reachability of one ray by a search of its valid set, with a path or a certificate.
//!
//! # What is decided
//! The configurations that hold the rod end along a ray form a set in (s × self-motion): per
//! waypoint (slice) a union of closed curves per IK branch in roll `fixed` on a 7-DOF arm,
//! a 2-D set (self-motion × arm roll) in roll `motor`, finitely many points on a 6-DOF arm.
//! A ray is **testable** when one connected piece of the valid part (limits, self, scene and
//! rod collision; continuous joint-space edges under `planner.max_joint_step`) contains a
//! configuration of the straight rod (s = 0) and one of `s*·(1 + margin)`.
//!
//! The search (submodule `graph`) floods that piece from every start configuration (the start set of
//! the roll mode: every valid IK solution of the straight rod from many restarts with the
//! redundancy joint locked on a grid, and the self-motion walks through them), best-first
//! toward larger s, after driving a few probe chains (two starts per start component and their
//! load steps, like tracked branches) as far as they go. It returns either a path to the last slice (submodule `path`), or a **certificate**
//! that the ray's `s_reached` (the farthest slice F of the piece reachable from the starts)
//! cannot be passed:
//! - the forward piece exhausted (every node reachable from a start expanded), or
//! - slice F + 1 has no valid configuration on any IK branch found (the redundancy joint locked
//!   on a 0.05 rad grid, 4 seeds each, 40 random restarts, tracks from slice F), or
//! - the **far-end search** is exhausted: once the probe chains are done and every node of
//!   slice F is expanded, a reverse search starts from the valid set of slice F + 1 (the same
//!   IK sampling) along reversed edges, never above F + 1: one expansion per step of the forward
//!   search while it has fewer than `REVERSE_HEAD_START` (256) nodes, then one per
//!   `FORWARD_PER_REVERSE` (63) (on rays with two large pieces the forward search exhausts
//!   first and pays one sixty-fourth more). If it exhausts without meeting a forward node (a
//!   configuration within the merge radius) and without reaching s = 0 (every valid
//!   straight-rod configuration belongs to the start set's components), no path from a start
//!   reaches slice F + 1, so F is final. A dead end behind a small far piece is proven at about
//!   its own cost (64 times it beyond the head start), not the whole strip's. On the seed
//!   rig's 200-direction lattice and a 100-ray sample of its 10,000-direction one, every ray's
//!   forward node count is the one at one reverse expansion per 15 (no far piece is proven
//!   later) and the sample's instructions are 4 % fewer. If it meets
//!   the forward piece, it is dropped and the forward search goes on.
//!
//! # Resolution (what the answer is exact at)
//! - **Slices**: the rig's pose-path waypoints (`planner.max_end_step`,
//!   `planner.max_end_angle`), submodule `slices`.
//! - **Self-motion**: samples at most `planner.search_step` (max-norm, default 0.16 rad) apart
//!   along each self-motion curve; two samples within 0.6 of that step in every joint are one
//!   node (submodule `graph`). The walk between two samples is an edge like any other: one
//!   corrected step when the step is within 0.8·`planner.max_joint_step`, else a chain of
//!   sub-steps within that, each end valid and each segment checked every
//!   `planner.segment_check_step` (submodule `linking`), so a coarser step samples fewer
//!   nodes but walks and checks the curve between them as finely. What a coarser step can
//!   miss is a valid arc shorter than about the step that no sample lands on. On the seed rig
//!   0.04, 0.08, 0.12 and 0.16 rad give the same class on every ray of the 200-direction
//!   quarter-sphere sample (`s_reached` one or two slices less on at most 3 of its 43 partial
//!   rays) and the same answer on every one of the seed's 173 directions; the node count goes
//!   as 1/step and the cost at 0.16 is 0.4 of that at 0.04 (`docs/RESULTS.md`). 0.32 costs 0.3
//!   of 0.04 with the same classes there and on the seed's 58 runs, but with reconfiguration
//!   forbidden (starts sampled on their curves only) it loses a ray of the 50-ray sample that
//!   0.16 reaches: the default is 0.16.
//! - **Roll** (`motor`): steps of `linking::ROLL_STEP`, a chain of sub-rolls where one step
//!   would turn a joint by more than `planner.max_joint_step`; with a freely turning motor the
//!   roll is compared modulo a whole turn (submodule `graph`).
//! - **Edges** (submodule `linking`): a load / back-off step is one minimum-norm track from a node to
//!   the neighbouring slice (where it lands in collision, the nearest valid ones
//!   along the landing's self-motion curve within the joint-step bound, sampled every quarter
//!   of that bound), or a bridge of such tracks through intermediate poses; every step
//!   within the joint-step bound, its end valid and its joint-linear segment collision-free
//!   (checked every `planner.segment_check_step`).
//!
//! At this resolution the answer is exact for the graph these edges span: a ray called partial
//! has no path in it (every node reachable from a start was expanded). A valid connection
//! narrower than the resolution (a gap in a curve shorter than a step, a link between slices
//! that no minimum-norm track from a sample finds) can be missed; the brute-force reference of
//! the tests (every IK branch on a redundancy grid, from many restarts, flood-filled) bounds
//! that on a sample of rays. A load step is the minimum-norm track from a node; where that
//! lands in collision, the nearest valid ones of the landing's self-motion
//! curve within the joint-step bound, one on each side, are load steps too (submodule
//! `linking`, "Landing"). Another valid solution of the next slice within the bound (on
//! another curve, or past a second invalid stretch) is not an edge here unless a move inside
//! the slice joins the two. With a large bound this matters: on a coarse rig (24 slices, bound
//! 0.3 rad) in roll `motor` a reference taking any valid solution within the bound reaches
//! slice 8 of direction 100 (200-direction quarter-sphere lattice) where the search stops at
//! 5; with the search's load edge the reference agrees with it (test
//! `motor_search_agrees_with_the_brute_force_reference`). At the seed rig's bound (0.05 rad)
//! that neighbourhood is about a third of a search step wide. On an arm whose collision model
//! leaves narrow valid arcs the landings matter: on Baxter's right arm (39 collision
//! primitives) a search without them stops 1–4 slices before the ladder on 13 of 100
//! quarter-sphere rays, and with them reaches every slice the ladder reaches (test
//! `the_search_reaches_every_slice_the_ladder_reaches_on_baxter`).
//! Where no single track joins a node to the neighbouring slice
//! within the joint-step bound (a fast stretch of the self-motion, typically near the end of a
//! ray), the edge is bridged through intermediate poses (`planner.bridge_halvings` halvings of
//! the interval at most, as the ladder refines its waypoints): with `bridge_halvings = 0` the
//! slices are fixed and such rays stop with cause `discontinuity`.
//!
//! # Moves
//! - **Reconfiguration** (a move inside a slice: the rod end held) when
//!   `planner.allow_reconfiguration`; always at s = 0, where the rod is not yet clamped. A
//!   landing (Resolution, "Edges") is a load step, not a reconfiguration: with reconfiguration
//!   forbidden the arm still leaves the minimum-norm track, by at most the joint-step bound per
//!   load step, where that track lands in collision (test `an_obstacle_forces_a_reconfiguration`:
//!   such steps steer the arm around a ball of 0.07 m, not one of 0.09 m).
//! - **Back-off** (`planner.allow_backoff`): below s* the rod is stable and its shape depends
//!   on s only, so the arm may drive back along the ray (phase `backoff`), reconfigure and drive
//!   on. Past s* the path only moves forward. Forbidden, the search is monotone in s.
//!
//! # Deferred segment tests
//! An edge made of one step (a load or back-off track, a walk of one corrected step) is kept
//! once its end is valid; the collision test of its segment's interior is deferred. When the
//! search ends (a path to the last slice, the piece exhausted, or the bound), the deferred
//! segments on the path to the node it returns (the goal, or the first node of the farthest
//! slice) are tested; if one is in collision, the ray is searched again with every segment
//! tested as its edge is made. So every edge of a returned path, and of the path to the
//! farthest slice of a certificate, is tested. The deferred graph has every edge the fully
//! tested one keeps, and possibly edges whose interior is in collision: a piece it exhausts, or
//! a far-end search it exhausts without meeting the forward piece, is exhausted with every
//! segment tested too, up to the merge order (as for back-off allowed ⊇ forbidden below). On
//! the seed rig no ray of the 200-direction quarter-sphere sample (at `search_step` 0.04 and
//! 0.16, and in roll `motor`) or of the tests needs the second search, and the 10,000-direction
//! lattice's decisions (class, `s_reached`, cause, counts) are those of the fully tested search;
//! the deferred tests are 12 % of the instructions of a sample of that lattice. Bridged edges
//! (chained walks, bridges between slices) are tested as they are made: where a sub-step fails
//! decides where the chain ends.
//!
//! # Walks that hold the pose
//! A walk step's corrector lands on the held pose, but near a fold of the self-motion it can
//! land on a neighbouring branch: the joint-linear chord then leaves the pose and no
//! resampling brings it within [`crate::planning::self_motion::HOLD_TOLERANCE`]. The walk
//! steps on the path returned (to the goal, or to the farthest slice) are resampled as the
//! trajectory needs them (submodule `path`), also when no path is asked for; where one cannot
//! be, the ray is searched again with every walk step resampled as it is made (an edge only
//! if it can be), so the decision with and without the path is the same and every returned
//! path holds the pose. On the seed rig 3 of the more than 100,000 walk steps the search makes
//! on the 200-direction quarter-sphere sample (roll `fixed`) cannot be resampled; no ray of
//! that sample (roll `fixed` or `motor`) has one on its path, and the seed run
//! c1_0.59831_c2_0.4564 in roll `motor` at `search_step` 0.12 or 0.24 does (test
//! `a_walk_that_does_not_hold_the_pose_is_not_on_a_path`). Resampling the path's walks costs
//! about 3 % of a sweep's CPU.
//!
//! # Monotone by construction
//! - roll `motor` ⊇ `fixed`: a `motor` ray returns the farther of its `fixed` decision and its
//!   own search (a `motor` search that hits its bound is `undecided` at the farther s of the
//!   two);
//! - more azimuths ⊇ fewer: [`Planner::plan_best`] keeps the best over the azimuths;
//!
//! Back-off allowed ⊇ forbidden holds for the reachable sets (every edge of the forbidden graph
//! is an edge of the allowed one); the sampled nodes differ (merging depends on the order), so
//! it is tested per direction rather than built in.
//!
//! A finer `planner.search_step` is **not** monotone by construction: each step samples its
//! own points of the self-motion curves and merges within its own radius, so a valid arc
//! narrower than a step can be met at one step and missed at another. On the seed rig's
//! 10,000-direction quarter-sphere lattice 1 ray is testable at 0.32 and partial at the
//! default 0.16 (and 8 the other way); that ray, 3,232, is testable at 0.04, 0.08, 0.12 and
//! 0.32, partial at 0.16 and 0.24 (`docs/RESULTS.md`). Tests check 0.05 ⊇ 0.1 ⊇ 0.36 per
//! direction on their sample.
//!
//! # Bounds
//! At most `planner.max_search_nodes` nodes per ray (default 50,000; ≈ 168 bytes each, and at most 4 KB of
//! bucket heads per slice a node lies on); a search that needs
//! more reports the ray `undecided` ([`ReachClass::Undecided`]) with the farthest s found, never
//! a guessed class. A rig whose self-motion step would need more nodes than the bound to cover
//! one slice is refused when the planner is made ([`check_resolution`]).
//!
//! # Cost
//! A ray costs its nodes × about 1.25 tracks (3–4 Jacobian evaluations each) and 1.5 collision
//! tests (a node per self-motion step per slice of the pieces it visits, most made by a back-off
//! or load step from the neighbouring slice; the move back to a node's parent slice is its own
//! edge, not tracked). A ray one of whose probe chains passes costs about one node per slice.
//! A partial ray costs its reachable piece, or the far piece if that one is exhausted first:
//! cheap when either is small; when both are large regions of the strip below s* (different
//! self-motion families, separated by joint limits; on the seed rig rays blocked just past
//! s*) about 30,000 nodes at `search_step` 0.16 (≈ 0.14 s, about 4.7 µs per node; the count
//! goes as 1/`search_step`: 116,000 at 0.04), and those few rays dominate a sweep's CPU. In
//! roll `motor` the pieces are 2-D per slice (self-motion × roll, a node per
//! `search_step` × `ROLL_STEP`: up to about 26,000 per slice on the seed rig; about 8 µs per
//! node): there about one quarter-sphere ray in ten exceeds the default bound of 50,000 nodes
//! (0.6–0.8 s each with the `fixed` decision it starts from, `undecided`), and most of those
//! stay undecided at 1,000,000 (≈ 8 s each). Roll `fixed` rays of the seed rig stay within
//! about 31,000 nodes at the default `search_step`, those of the xArm7 rig of `rig init`
//! within about 130,000.
//! Figures: `docs/RESULTS.md`.

pub(crate) mod graph;
pub(crate) mod linking;
pub(crate) mod path;
pub(crate) mod slices;

use crate::directions::Direction as RayDirection;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::cause::BlockCause;
use crate::planning::planner::{Planner, RayPlan, ReachClass};
use crate::planning::rig::{PlannerSettings, RollMode};
use graph::{Direction, Graph, Node, Outcome, RollMerge, Rules, Via, MERGE_FRACTION, NODE_BYTES};
use linking::{Config, Linker};
use slices::Slices;

/// Largest memory one ray's search may use (bytes): `planner.max_search_nodes` is refused
/// above `MAX_SEARCH_BYTES / NODE_BYTES`.
pub const MAX_SEARCH_BYTES: usize = 1 << 30;

/// Largest `planner.search_step` (rad): at this step configurations up to 0.24 rad apart in
/// every joint are one node (`MERGE_FRACTION`).
pub const MAX_SEARCH_STEP: Real = 0.4;

/// Redundancy-joint grid of the far-end slice's IK (rad).
const LOCK_GRID: Real = 0.05;

/// Start configurations per start component whose load chains are probed first.
const PROBES: usize = 2;

/// Forward expansions per expansion of the far-end search.
const FORWARD_PER_REVERSE: u32 = 63;

/// Far-end searches smaller than this many nodes expand at every step of the forward search
/// (a small far piece is proven at once).
const REVERSE_HEAD_START: usize = 256;

/// Random restarts of the far-end slice's IK.
const CERT_RESTARTS: usize = 40;

/// IK branches per slice assumed when sizing one slice's cover (a 6-DOF sub-chain has at most
/// 16 solutions).
const BRANCHES: Real = 16.0;

/// Refuse settings whose memory bound is too large, or whose self-motion step is too fine for
/// the node bound to cover one slice (16 closed curves of max-norm length 2π each, a node per
/// 0.6 step). Errors name the setting.
///
/// ```
/// use helixreach::planning::rig::PlannerSettings;
/// use helixreach::planning::search::check_resolution;
/// let mut p = PlannerSettings::default();
/// assert!(check_resolution(&p, "rig").is_ok());
/// p.search_step = 1e-5;
/// let e = check_resolution(&p, "rig").unwrap_err().to_string();
/// assert!(e.contains("planner.search_step"), "{e}");
/// ```
pub fn check_resolution(p: &PlannerSettings, source: &str) -> Result<()> {
    let max_nodes = MAX_SEARCH_BYTES / NODE_BYTES;
    if p.max_search_nodes > max_nodes {
        return Err(Error::invalid(
            format!("{source}: planner.max_search_nodes"),
            p.max_search_nodes,
            format!(
                "needs {} MB per ray; at most {max_nodes} nodes ({} MB)",
                (p.max_search_nodes * NODE_BYTES) >> 20,
                MAX_SEARCH_BYTES >> 20
            ),
        ));
    }
    let cover = BRANCHES * std::f64::consts::TAU / (MERGE_FRACTION * p.search_step);
    if cover > p.max_search_nodes as Real {
        return Err(Error::invalid(
            format!("{source}: planner.search_step"),
            p.search_step,
            format!(
                "one slice needs up to {cover:.0} nodes at this step, more than \
                 planner.max_search_nodes = {}",
                p.max_search_nodes
            ),
        ));
    }
    Ok(())
}

impl Planner {
    /// The forward search, with the far-end certificate (module docs).
    fn drive(
        &self,
        slices: &Slices,
        linker: &mut Linker<'_>,
        fwd: &mut Graph,
        rules: &Rules,
        roll: RollMode,
        backoff_ok: &dyn Fn(u32) -> bool,
    ) -> Result<Outcome> {
        let last = (slices.len() - 1) as u32;
        // The reverse search from the slice after the farthest one, and the farthest slices
        // whose certificate failed (the reverse search met the forward piece).
        let mut cert: Option<(u32, Graph)> = None;
        let mut failed_at = u32::MAX;
        let mut tick: u32 = 0;
        loop {
            if let Some(o) = fwd.step(linker, rules, last, Direction::Forward, backoff_ok) {
                return Ok(o);
            }
            let f = fwd.farthest;
            if let Some((cf, b)) = &cert {
                let met = fwd
                    .fresh
                    .iter()
                    .any(|&id| b.find(&fwd.nodes[id as usize].c).is_some());
                if met {
                    failed_at = *cf;
                }
                if met || f > *cf {
                    cert = None;
                }
            }
            if cert.is_none()
                && failed_at != f
                && !fwd.probing()
                && fwd.top().is_some_and(|t| t < f)
            {
                let mut b = Graph::new(
                    slices.len(),
                    self.dof,
                    self.red_joint,
                    self.red_range(),
                    fwd.merge_q(),
                    self.roll_merge(roll),
                );
                for c in self.slice_configs(slices, linker, f + 1, roll, fwd)? {
                    if b.find(&c).is_none() {
                        b.insert(Node {
                            c,
                            parent: u32::MAX,
                            via: Via::Start,
                        });
                    }
                }
                if b.nodes.is_empty() {
                    // Slice f + 1 has no valid configuration: nothing passes it.
                    return Ok(Outcome::Exhausted);
                }
                if b.nodes.iter().any(|n| fwd.find(&n.c).is_some()) {
                    failed_at = f;
                } else {
                    cert = Some((f, b));
                }
            }
            tick = tick.wrapping_add(1);
            let turn = tick % FORWARD_PER_REVERSE == 0;
            if let Some((cf, b)) = cert
                .as_mut()
                .filter(|(_, b)| turn || b.nodes.len() < REVERSE_HEAD_START)
            {
                let cap = *cf + 1;
                match b.step(linker, rules, 0, Direction::Reverse { cap }, backoff_ok) {
                    // Nothing of the forward piece reaches slice cap: its farthest is final.
                    Some(Outcome::Exhausted) => return Ok(Outcome::Exhausted),
                    Some(_) => {
                        // Reached slice 0 (every valid straight-rod configuration is in the
                        // start set's components) or hit the bound: no certificate here.
                        failed_at = *cf;
                        cert = None;
                    }
                    None => {
                        if b.fresh
                            .iter()
                            .any(|&id| fwd.find(&b.nodes[id as usize].c).is_some())
                        {
                            failed_at = *cf;
                            cert = None;
                        }
                    }
                }
            }
        }
    }

    /// How the graph's merge rule meets the arm roll: no roll moves in roll `fixed`; in roll
    /// `motor` modulo 2π when the motor turns freely (range (−∞, ∞)), else as it is (module
    /// docs, "Resolution").
    fn roll_merge(&self, roll: RollMode) -> RollMerge {
        let (lo, hi) = self.rig.motor.range;
        match roll {
            RollMode::Fixed => RollMerge::Constant,
            RollMode::Motor if lo == Real::NEG_INFINITY && hi == Real::INFINITY => {
                RollMerge::Periodic(std::f64::consts::TAU)
            }
            RollMode::Motor => RollMerge::Unwrapped,
        }
    }

    /// The limits of the redundancy joint (the search graph's buckets).
    fn red_range(&self) -> (Real, Real) {
        (
            self.model.lower()[self.red_joint],
            self.model.upper()[self.red_joint],
        )
    }

    /// Valid configurations of slice `j` on every IK branch: the redundancy joint locked on a
    /// grid of `LOCK_GRID` rad over its range (4 seeds each), `CERT_RESTARTS` random restarts,
    /// and tracks from the forward nodes of slice j − 1; roll free in roll `motor`.
    fn slice_configs(
        &self,
        slices: &Slices,
        linker: &mut Linker<'_>,
        j: u32,
        roll: RollMode,
        fwd: &Graph,
    ) -> Result<Vec<Config>> {
        let (lo, hi) = (self.model.lower(), self.model.upper());
        let red = self.red_joint;
        let redundant = self.dof == 7;
        let n_lock = ((hi[red] - lo[red]) / LOCK_GRID).floor() as usize;
        let params = crate::robot::IkParams {
            redundancy_joint: redundant.then_some(red),
            lock_values: if redundant {
                (0..=n_lock)
                    .map(|k| lo[red] + k as Real * LOCK_GRID)
                    .collect()
            } else {
                Vec::new()
            },
            lock_seeds: 4,
            restarts: CERT_RESTARTS,
            max_iterations: 60,
            ..crate::robot::IkParams::default()
        };
        let solver = crate::robot::IkSolver::new(&self.model, params)?;
        let base = slices.target(self, j as usize, 0.0);
        let target = match roll {
            RollMode::Fixed => base,
            RollMode::Motor => base.free_roll(),
        };
        let seeds: Vec<&[Real]> = fwd
            .nodes
            .iter()
            .filter(|n| n.c.slice + 1 == j)
            .map(|n| &n.c.q[..self.dof])
            .collect();
        let w = &slices.wps[j as usize];
        let mut out = Vec::new();
        for sol in solver.solve_all(&target, &seeds) {
            let q = sol.joints();
            let psi = match roll {
                RollMode::Fixed => 0.0,
                RollMode::Motor => w.motor - self.motor_angle(w, q, roll, 0.0),
            };
            let c = Config {
                slice: j,
                q: crate::planning::planner::pad(q),
                psi,
            };
            if linker.start_valid(&c) {
                out.push(c);
            }
        }
        Ok(out)
    }

    /// Decide one ray at one azimuth by the search (module docs): the path to
    /// `s*·(1 + margin)`, or the certificate (the farthest s of the exhausted reachable piece),
    /// or `undecided` at the node bound. Roll `motor` returns the farther of the `fixed`
    /// decision and its own.
    pub fn decide_ray(
        &self,
        dir: &RayDirection,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let mut fixed = self.decide_in(dir, s_star, azimuth, RollMode::Fixed, want_path)?;
        fixed.roll = roll;
        if roll == RollMode::Fixed || fixed.class == ReachClass::Testable {
            return Ok(fixed);
        }
        let native = self.decide_in(dir, s_star, azimuth, RollMode::Motor, want_path)?;
        let better =
            (native.class.rank(), native.s_reached) > (fixed.class.rank(), fixed.s_reached);
        Ok(if !better {
            fixed
        } else if native.class == ReachClass::Undecided && fixed.s_reached > native.s_reached {
            // The motor search hit its bound before passing the `fixed` path, which is a
            // `motor` path too: undecided, from the farther s found (that path).
            RayPlan {
                class: ReachClass::Undecided,
                cause: None,
                search_nodes: native.search_nodes,
                ..fixed
            }
        } else {
            native
        })
    }

    fn decide_in(
        &self,
        dir: &RayDirection,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let slices = Slices::new(self, dir, s_star, azimuth)?;
        let mut plan = RayPlan {
            dir: *dir,
            s_star,
            s_end: slices.s_end,
            s_reached: 0.0,
            class: ReachClass::Blocked,
            cause: None,
            azimuth,
            roll,
            n_waypoints: slices.len(),
            n_reached: 0,
            reconfigurations: 0,
            backoffs: 0,
            search_nodes: 0,
            start_samples: 0,
            levels_gated: false,
            path_cost: 0.0,
            max_joint_step: 0.0,
            path: None,
            assumed_type: None,
        };
        let set = match self.start(roll) {
            Ok(s) => s,
            Err(c) => {
                plan.cause = Some(c.dominant().unwrap_or(BlockCause::NoIk));
                return Ok(plan);
            }
        };
        let settings = &self.rig.planner;
        let merge_q = MERGE_FRACTION * settings.search_step;
        let last = (slices.len() - 1) as u32;
        let s_star = slices.s_star;
        let wps_s: Vec<Real> = slices.wps.iter().map(|w| w.s).collect();
        let backoff_ok = move |i: u32| i > 0 && wps_s[i as usize] <= s_star;
        // Segment tests deferred first; where the path found crosses a segment in collision,
        // the search again with every segment tested (module docs, "Deferred segment tests").
        let mut defer_segments = true;
        let mut check_holds = false;
        let (graph, outcome, ex) = loop {
            let mut linker = Linker::new(self, &slices)?;
            linker.check_holds = check_holds;
            let mut graph = Graph::new(
                slices.len(),
                self.dof,
                self.red_joint,
                self.red_range(),
                merge_q,
                self.roll_merge(roll),
            );
            // Probe chains first: the last start (the first expanded) and the first `PROBES` of
            // each start component (spread over it: farthest-point order).
            let n_starts: usize = set.comps.iter().map(Vec::len).sum();
            let mut k = 0;
            for comp in &set.comps {
                for (j, n) in comp.iter().enumerate() {
                    k += 1;
                    let psi = match roll {
                        RollMode::Fixed => 0.0,
                        RollMode::Motor => -n.motor,
                    };
                    let c = Config {
                        slice: 0,
                        q: n.q,
                        psi,
                    };
                    if graph.find(&c).is_none() && linker.start_valid(&c) {
                        let node = Node {
                            c,
                            parent: u32::MAX,
                            via: Via::Start,
                        };
                        if j < PROBES || k == n_starts {
                            graph.insert_probe(node);
                        } else {
                            graph.insert(node);
                        }
                    }
                }
            }
            plan.start_samples = graph.nodes.len();
            if graph.nodes.is_empty() {
                plan.cause = Some(BlockCause::RodCollision);
                return Ok(plan);
            }
            let rules = Rules {
                reconfigure: settings.allow_reconfiguration,
                backoff: settings.allow_backoff,
                roll: roll == RollMode::Motor,
                max_nodes: settings.max_search_nodes,
                defer_segments,
            };
            let outcome = if graph.nodes.iter().any(|n| n.c.slice == last) {
                Outcome::Reached(graph.nodes.len() as u32 - 1)
            } else {
                self.drive(&slices, &mut linker, &mut graph, &rules, roll, &backoff_ok)?
            };
            let end = match outcome {
                Outcome::Reached(id) => id,
                _ => graph
                    .nodes
                    .iter()
                    .position(|n| n.c.slice == graph.farthest)
                    .expect("the farthest slice has a node") as u32,
            };
            if defer_segments && !graph.check_deferred(end, &mut linker) {
                defer_segments = false;
                continue;
            }
            match path::extract(self, &slices, &graph, &mut linker, end, want_path)? {
                Some(ex) => break (graph, outcome, ex),
                None if !check_holds => check_holds = true,
                None => {
                    return Err(Error::invalid(
                        "reconfiguration",
                        format!("direction ({}, {}, {})", dir.kappa, dir.tau, dir.omega),
                        "a walk of the path found with every walk step resampled does not \
                         hold the pose",
                    ))
                }
            }
        };
        let far = graph.farthest as usize;
        plan.s_reached = slices.wps[far].s;
        plan.search_nodes = graph.nodes.len();
        plan.n_reached = ex.slices;
        plan.reconfigurations = ex.reconfigurations;
        plan.backoffs = ex.backoffs;
        plan.path_cost = ex.cost;
        plan.max_joint_step = ex.max_joint_step;
        plan.path = ex.points;
        plan.class = match outcome {
            Outcome::Reached(_) if s_star.is_finite() => ReachClass::Testable,
            Outcome::Reached(_) => ReachClass::Partial,
            Outcome::Bound => ReachClass::Undecided,
            Outcome::Exhausted if far > 0 => ReachClass::Partial,
            Outcome::Exhausted => ReachClass::Blocked,
        };
        // A pose path cut short by `planner.max_waypoints` ends before s_end: its last slice
        // is not the ray's end, so reaching it is not testable.
        let cut = slices.wps.last().is_some_and(|w| w.s < slices.s_end);
        if cut && matches!(outcome, Outcome::Reached(_)) {
            plan.class = ReachClass::Partial;
            plan.cause = Some(BlockCause::WaypointLimit);
        }
        if outcome == Outcome::Exhausted {
            plan.cause = Some(
                graph.causes[far]
                    .dominant()
                    .unwrap_or(BlockCause::Discontinuity),
            );
        }
        Ok(plan)
    }
}
