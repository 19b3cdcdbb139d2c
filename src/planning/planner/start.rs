//! The start set of a roll mode: valid configurations of the straight rod's end pose, grouped by
//! connected valid self-motion component (what the planner's module docs call the start
//! components, [`crate::planning::ladder`], "Rungs" and "Dense levels").
//!
//! # Components
//! - **Roll `fixed`** (1-D self-motion, the full tool pose held): two valid IK solutions share a
//!   component when the self-motion walk ([`crate::planning::self_motion::walk`], step
//!   `planner.self_motion_step`, every sample and joint-linear segment valid) from one passes
//!   within half a joint step (max-norm) of the other.
//! - **Roll `motor`** (2-D: the redundancy joint j0 × the roll ψ about the tool axis): the
//!   solutions of the free-roll IK each have their own roll, so the 1-D walks above (at the
//!   roll of each solution) leave every solution its own component. Two 1-D components at rolls
//!   ψ_A and ψ_B are joined when a **roll walk** connects them: from one of the first
//!   `ROLL_TRIES` points of A's farthest-point order, with j0 locked at its value, full-pose
//!   targets T_A·Rz(δ·i/n), i = 1…n (δ the signed angle from A's roll to B's, |δ| ≤ π, steps of
//!   at most `ROLL_STEP`), each tracked from the previous sample; every sample must be a valid
//!   node (joint and motor limits, self, scene and rod collision against the straight rod),
//!   every step within `planner.max_joint_step` with its joint-linear segment collision-free,
//!   and the walk must land within half a joint step of a sample of B (motor angle continuous,
//!   equal to B's within 1e-6). Roll walks are tried between neighbours in roll order (A to B,
//!   then B to A), and joined components are merged transitively.
//!
//! What is guaranteed: two start solutions share a motor component only if a valid path at the
//! walk resolution joins them in the 2-D valid set (so a component is connected at that
//! resolution). Not the converse: a connection the roll walks miss leaves two components, i.e.
//! more start nodes, never fewer.
//!
//! # Orders
//! Each component's pool (its IK solutions, then its walk samples; in roll `motor` the pools of
//! the merged 1-D components in label order) is put in farthest-point order, of which the dense
//! levels take prefixes ([`farthest_order`]); the first rung is the `redundancy_samples` most
//! diverse solutions ([`farthest_indices`]).

use super::{node, Node, Planner, Scratch, StartSet};
use crate::math::{Iso3, Real, Vec3};
use crate::planning::cause::{BlockCause, CauseCounts};
use crate::planning::pose_path::Waypoint;
use crate::planning::rig::RollMode;
use crate::planning::self_motion::{self, Held};
use crate::robot::{IkParams, IkSolver};

/// Roll step of the walks that join motor start components (rad): half the 0.05 rad of the
/// pointwise gate's roll walks, so that a step rarely exceeds the joint-step bound.
const ROLL_STEP: Real = 0.025;

/// Largest motor-angle difference (rad) at which a roll walk's landing counts as the same
/// motor angle as a sample of the component it lands on (both are computed from the same
/// straight-rod pose; a 2π branch apart is another configuration of the motor).
const SAME_MOTOR: Real = 1e-6;

/// Start points per 1-D component (the first of its farthest-point order) from which roll
/// walks are tried.
const ROLL_TRIES: usize = 4;

impl Planner {
    pub(super) fn compute_start(
        &self,
        roll: RollMode,
    ) -> std::result::Result<StartSet, CauseCounts> {
        let mut sc = self.new_scratch();
        let straight = [0.0; 3];
        let mut causes = CauseCounts::default();
        if self.rod_nodes(straight, 0.0, &mut sc.rod).is_err() {
            causes.add(BlockCause::NoIk);
            return Err(causes);
        }
        let tool = self.rig.straight_tool_pose();
        let w0 = Waypoint {
            s: 0.0,
            kto: straight,
            tool,
            motor: 0.0,
        };
        // All joints free, many random restarts: the self-motion manifold of the start pose is
        // sampled broadly, then thinned to the most diverse `redundancy_samples` valid solutions.
        let params = IkParams {
            redundancy_joint: None,
            restarts: 40
                * self
                    .rig
                    .planner
                    .redundancy_samples
                    .max(self.rig.roll_samples),
            max_iterations: 100,
            ..self.ik.clone()
        };
        let Ok(solver) = IkSolver::new(&self.model, params) else {
            causes.add(BlockCause::NoIk);
            return Err(causes);
        };
        let sols = solver.solve_all(&self.target(&tool, roll), &[]);
        if sols.is_empty() {
            causes.add(BlockCause::NoIk);
        }
        let mut out = Vec::new();
        for s in sols {
            let q = s.joints();
            if let Err(c) = self.check_config(q, &mut sc) {
                causes.add(c);
                continue;
            }
            let motor = self.motor_angle(&w0, q, roll, 0.0);
            if !self.motor_ok(motor) {
                causes.add(BlockCause::JointLimit);
                continue;
            }
            let node = Node::from_joints(q, motor);
            out.push(node);
        }
        if out.is_empty() {
            return Err(causes);
        }
        let k = self.rig.planner.redundancy_samples;
        let first_idx = farthest_indices(&out, k, self.dof);
        // Label the valid solutions by connected valid self-motion component (walks at the
        // straight rod's pose; in roll `motor` also walks about the tool axis between the
        // rolls); components the first rung misses become further start rungs.
        let (label1, walks) = self.components(&out, &mut sc);
        let n1 = label1.iter().copied().max().map_or(0, |m| m + 1);
        // The 1-D pools: each fixed-roll component's IK solutions, then its walk.
        let pools1: Vec<Vec<Node>> = (0..n1)
            .map(|l| {
                (0..out.len())
                    .filter(|&i| label1[i] == l)
                    .map(|i| out[i])
                    .chain(walks[l].iter().copied())
                    .collect()
            })
            .collect();
        let merged = match roll {
            RollMode::Motor if self.dof == 7 => self.join_rolls(&pools1, &w0, &mut sc),
            _ => (0..n1).collect(),
        };
        let label: Vec<usize> = label1.iter().map(|&l| merged[l]).collect();
        let n_labels = merged.iter().copied().max().map_or(0, |m| m + 1);
        // Only the first `dense_samples` of each farthest-point order are ever used.
        let limit = self.rig.planner.dense_samples.max(1);
        let comps: Vec<Vec<Node>> = (0..n_labels)
            .map(|m| {
                let pool: Vec<Node> = (0..n1)
                    .filter(|&l| merged[l] == m)
                    .flat_map(|l| pools1[l].iter().copied())
                    .collect();
                farthest_order(&pool, self.dof, limit)
                    .into_iter()
                    .map(|i| pool[i])
                    .collect()
            })
            .collect();
        let mut others = Vec::new();
        for l in 0..n_labels {
            if first_idx.iter().any(|&i| label[i] == l) {
                continue;
            }
            let comp: Vec<Node> = (0..out.len())
                .filter(|&i| label[i] == l)
                .map(|i| out[i])
                .collect();
            let idx = farthest_indices(&comp, k, self.dof);
            others.push(idx.into_iter().map(|i| comp[i]).collect());
        }
        let solutions = (0..n_labels)
            .map(|l| {
                (0..out.len())
                    .filter(|&i| label[i] == l)
                    .map(|i| out[i])
                    .collect()
            })
            .collect();
        Ok(StartSet {
            solutions,
            first: first_idx.into_iter().map(|i| out[i]).collect(),
            others,
            comps,
        })
    }

    /// Component labels (0, 1, …) of valid configurations that hold one tool pose (`sc.rod`
    /// holds the rod): two share a label when a self-motion walk from one passes
    /// within half a joint step of the other. Without 7 joints every node is its own component.
    fn components(&self, nodes: &[Node], sc: &mut Scratch) -> (Vec<usize>, Vec<Vec<Node>>) {
        let mut label = vec![usize::MAX; nodes.len()];
        let mut walks: Vec<Vec<Node>> = Vec::new();
        let Ok(solver) = IkSolver::new(&self.model, self.ik.clone()) else {
            return ((0..nodes.len()).collect(), vec![Vec::new(); nodes.len()]);
        };
        let settings = self.walk_settings();
        let mut next = 0;
        for i in 0..nodes.len() {
            if label[i] != usize::MAX {
                continue;
            }
            label[i] = next;
            walks.push(Vec::new());
            if self.dof == 7 {
                let held = Held {
                    chain: self.model.chain(),
                    solver: &solver,
                    tip: self.model.chain().tool_pose(&nodes[i].q[..self.dof]),
                    dof: self.dof,
                };
                let motor = nodes[i].motor;
                for sign in [1.0, -1.0] {
                    let (samples, _) = self_motion::walk(
                        &held,
                        &nodes[i].q,
                        sign,
                        &settings,
                        |a, b| {
                            self.check_config(&b[..self.dof], sc).is_ok()
                                && self
                                    .check_segment(&node(*a, motor), &node(*b, motor), sc)
                                    .is_ok()
                        },
                        |_| false,
                    );
                    for (j, n) in nodes.iter().enumerate() {
                        if label[j] == usize::MAX
                            && samples.iter().any(|q| {
                                (0..self.dof).all(|d| {
                                    (q[d] - n.q[d]).abs() <= 0.5 * settings.joint_step_bound
                                })
                            })
                        {
                            label[j] = next;
                        }
                    }
                    walks[next].extend(samples.iter().map(|q| node(*q, motor)));
                }
            }
            next += 1;
        }
        (label, walks)
    }

    /// The merged labels of the roll-`motor` 1-D start components `pools` (each a non-empty
    /// pool of nodes at one roll): `out[l]` is the 2-D component of 1-D component `l`, numbered
    /// by first appearance in `l` order (module docs, "Components").
    fn join_rolls(&self, pools: &[Vec<Node>], w0: &Waypoint, sc: &mut Scratch) -> Vec<usize> {
        let n = pools.len();
        let identity: Vec<usize> = (0..n).collect();
        let Ok(solver) = IkSolver::new(&self.model, self.ik.clone()) else {
            return identity;
        };
        if n < 2 {
            return identity;
        }
        let poses: Vec<Iso3> = pools
            .iter()
            .map(|p| self.tool_pose(&p[0].q[..self.dof]))
            .collect();
        let mut parent: Vec<usize> = (0..n).collect();
        let mut swept = vec![false; n];
        for a in 0..n {
            let ra = root(&mut parent, a);
            if swept[ra] {
                continue;
            }
            // Signed roll from A to every other component, in (−π, π].
            let rolls: Vec<(Real, usize)> = (0..n)
                .filter(|&b| b != a)
                .map(|b| {
                    let m = (poses[a].rotation.inverse() * poses[b].rotation)
                        .to_rotation_matrix()
                        .into_inner();
                    (m[(1, 0)].atan2(m[(0, 0)]), b)
                })
                .collect();
            for i in farthest_order(&pools[a], self.dof, ROLL_TRIES) {
                for sign in [1.0, -1.0] {
                    let mut stops: Vec<(Real, usize)> = rolls
                        .iter()
                        .filter(|(d, _)| sign * d > 0.0)
                        .map(|&(d, b)| (d.abs(), b))
                        .collect();
                    stops.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
                    for b in self.roll_sweep(&solver, pools, &pools[a][i], sign, &stops, w0, sc) {
                        let (x, y) = (root(&mut parent, a), root(&mut parent, b));
                        if x != y {
                            parent[x.max(y)] = x.min(y);
                            swept[x.min(y)] = swept[x] || swept[y];
                        }
                    }
                }
            }
            let ra = root(&mut parent, a);
            swept[ra] = true;
        }
        let mut out = vec![usize::MAX; n];
        let mut next = 0;
        for l in 0..n {
            let r = root(&mut parent, l);
            if out[r] == usize::MAX {
                out[r] = next;
                next += 1;
            }
            out[l] = out[r];
        }
        out
    }

    /// A roll walk (module docs, "Components") from `start` about the tool axis in the sense
    /// `sign`, through the turns `stops` (ascending |δ| ≤ π, each the roll of a pool) to π or
    /// until a step fails; returns the pools it lands on (within half a joint step of one of
    /// their samples, the same motor angle within 1e-6).
    #[allow(clippy::too_many_arguments)]
    fn roll_sweep(
        &self,
        solver: &IkSolver<'_>,
        pools: &[Vec<Node>],
        start: &Node,
        sign: Real,
        stops: &[(Real, usize)],
        w0: &Waypoint,
        sc: &mut Scratch,
    ) -> Vec<usize> {
        let j = self.red_joint;
        let half = 0.5 * self.rig.planner.max_joint_step;
        let pose0 = self.tool_pose(&start.q[..self.dof]);
        let lock = Some((j, start.q[j]));
        let mut prev = *start;
        let mut turned: Real = 0.0;
        let mut landed = Vec::new();
        let end = [(std::f64::consts::PI, usize::MAX)];
        for &(stop, b) in stops.iter().chain(&end) {
            let steps = ((stop - turned) / ROLL_STEP).ceil().max(0.0) as usize;
            for s in 1..=steps {
                let turn = sign * (turned + (stop - turned) * s as Real / steps as Real);
                let pose = pose0 * Iso3::rotation(Vec3::z() * turn);
                let target = self.target(&pose, RollMode::Fixed);
                let Some(sol) = solver.track(&target, &prev.q[..self.dof], lock) else {
                    return landed;
                };
                let q = sol.joints();
                let motor = self.motor_angle(w0, q, RollMode::Motor, prev.motor);
                let next = Node::from_joints(q, motor);
                if !self.motor_ok(motor)
                    || self.edge_cost(&prev, &next).is_none()
                    || self.check_config(q, sc).is_err()
                    || self.check_segment(&prev, &next, sc).is_err()
                {
                    return landed;
                }
                prev = next;
            }
            turned = turned.max(stop);
            if b != usize::MAX
                && pools[b].iter().any(|x| {
                    (x.motor - prev.motor).abs() <= SAME_MOTOR
                        && (0..self.dof).all(|d| (x.q[d] - prev.q[d]).abs() <= half)
                })
            {
                landed.push(b);
            }
        }
        landed
    }
}

/// Union–find root of `i` (path halving).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The first `limit` indices of the farthest-point order of `nodes` (max-norm joint distance)
/// from the first: each next index is the node farthest from those before it (ties: the lowest
/// index). Every prefix is a greedy spread sample, and prefixes are nested (a shorter `limit`
/// gives a prefix of a longer one). O(n·limit).
fn farthest_order(nodes: &[Node], dof: usize, limit: usize) -> Vec<usize> {
    if nodes.is_empty() {
        return Vec::new();
    }
    let dist = |a: &Node, b: &Node| {
        (0..dof)
            .map(|j| (a.q[j] - b.q[j]).abs())
            .fold(0.0, Real::max)
    };
    let mut order = vec![0usize];
    let mut taken = vec![false; nodes.len()];
    taken[0] = true;
    let mut dmin: Vec<Real> = nodes.iter().map(|n| dist(n, &nodes[0])).collect();
    while order.len() < nodes.len().min(limit) {
        let mut best = usize::MAX;
        for i in 0..nodes.len() {
            if !taken[i] && (best == usize::MAX || dmin[i] > dmin[best]) {
                best = i;
            }
        }
        taken[best] = true;
        order.push(best);
        for i in 0..nodes.len() {
            dmin[i] = dmin[i].min(dist(&nodes[i], &nodes[best]));
        }
    }
    order
}

/// Greedy farthest-point selection of `k` nodes (max-norm joint distance), starting from the
/// first: deterministic, and spreads the start rung over the self-motion manifold. Returns
/// sorted indices.
fn farthest_indices(nodes: &[Node], k: usize, dof: usize) -> Vec<usize> {
    if nodes.len() <= k {
        return (0..nodes.len()).collect();
    }
    let dist = |a: &Node, b: &Node| {
        (0..dof)
            .map(|j| (a.q[j] - b.q[j]).abs())
            .fold(0.0, Real::max)
    };
    let mut chosen = vec![0usize];
    let mut dmin: Vec<Real> = nodes.iter().map(|n| dist(n, &nodes[0])).collect();
    while chosen.len() < k {
        let mut best = 0;
        for i in 0..nodes.len() {
            if dmin[i] > dmin[best] {
                best = i;
            }
        }
        chosen.push(best);
        for i in 0..nodes.len() {
            dmin[i] = dmin[i].min(dist(&nodes[i], &nodes[best]));
        }
    }
    chosen.sort_unstable();
    chosen
}
