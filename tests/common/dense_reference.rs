//! The dense reference of a ray's reachability (roll `fixed`, azimuth 0), independent of the
//! planner's pose path, ladder and search: waypoints uniform in s with poses from the helix
//! module and the rig's frames; at each, fresh IK with j0 locked on a grid plus free restarts;
//! forward reachability with the self-motion closure of each waypoint checked by bisection to
//! the joint-step bound. Shared by `tests/planning_seed.rs` and `examples/seed_reference.rs`
//! (included there by `#[path]`, so it uses nothing of `tests/common` but itself).
//!
//! # Waypoint count
//! A step between consecutive waypoints must stay within `planner.max_joint_step`, so too few
//! uniform waypoints make a ray fail for spacing, not for reachability: choose `n_wp` so that
//! doubling it changes no answer on a sample (`examples/seed_reference.rs --doubling`).
#![allow(dead_code)]

use helixreach::directions::Direction;
use helixreach::helix::{discrete, Helix};
use helixreach::math::{Mat3, Real, Vec3};
use helixreach::planning::planner::Planner;
use helixreach::robot::{CollisionModel, Frame, IkParams, IkSolver, IkTarget, MAX_DOF};

/// P = [e2 e1 −e3] (tool x = d2, y = d1, z = −d3).
pub fn p_matrix() -> Mat3 {
    Mat3::from_columns(&[Vec3::y(), Vec3::x(), -Vec3::z()])
}

/// The continuum s* of `d` (relative tolerance 1e-10).
pub fn s_star(d: &Direction) -> Real {
    helixreach::boundary::continuum::critical_s(d, 1e-10)
        .unwrap()
        .s_star
}

/// How far the dense reference gets along a ray.
#[derive(Debug, Clone)]
pub struct Reach {
    /// Waypoints, uniform in s from 0 to `s_end`.
    pub n_wp: usize,
    /// The ray's end, s*·(1 + margin).
    pub s_end: Real,
    /// The last waypoint with a reachable configuration (`n_wp − 1`: the ray is reached; 0 with
    /// `reach` empty: the straight rod has no valid configuration).
    pub last: usize,
    /// Valid IK solutions found at the first waypoint without a reachable one (empty when that
    /// waypoint has no valid configuration at all, or when the ray is reached).
    pub next_valid: usize,
    /// The reachable configurations at waypoint `last`.
    pub reach: Vec<Vec<Real>>,
}

impl Reach {
    /// The last waypoint is reached.
    pub fn reaches(&self) -> bool {
        self.last + 1 == self.n_wp
    }

    /// The arc length of waypoint `k`.
    pub fn s(&self, k: usize) -> Real {
        self.s_end * k as Real / (self.n_wp - 1) as Real
    }

    /// The arc length of the last waypoint reached.
    pub fn s_reached(&self) -> Real {
        self.s(self.last)
    }
}

/// Dense forward reachability of one ray at azimuth 0, roll `fixed`: whether the last of
/// `n_wp` waypoints is reached ([`reference_reach`]).
pub fn reference_reaches(planner: &Planner, d: &Direction, n_wp: usize, grid: Real) -> bool {
    reference_reach(planner, d, n_wp, grid).reaches()
}

/// Dense forward reachability of one ray at azimuth 0, roll `fixed` (see the module docs).
/// Waypoints uniform in s (poses from the helix module and the rig's frames, not from the
/// planner's pose path); at each, fresh IK with j0 locked on a grid of `grid` rad plus free
/// restarts; a configuration is valid when it is collision-free (self, scene, rod of that
/// waypoint). Reachable set R_{k+1}: valid configurations within one joint step of the
/// self-motion closure of R_k, the joint-linear segment collision-free. The closure joins
/// valid configurations of one waypoint through self-motion: two are joined when bisection
/// (midpoints projected onto the held pose by IK, each valid) reaches pieces no longer than the
/// step bound, every piece's segment collision-free. Every valid configuration of the straight
/// rod (waypoint 0) is a start.
pub fn reference_reach(planner: &Planner, d: &Direction, n_wp: usize, grid: Real) -> Reach {
    let rig = planner.rig();
    let model = planner.model();
    let dof = model.dof();
    let step = rig.planner.max_joint_step;
    let mut cm = CollisionModel::for_model(model).unwrap();
    cm.set_obstacles(&rig.obstacles).unwrap();
    let mut ws = cm.workspace();
    let (lo, hi) = (model.lower(), model.upper());
    let lock_values: Vec<Real> = {
        let n = ((hi[0] - lo[0]) / grid).floor() as usize;
        (0..=n).map(|i| lo[0] + i as Real * grid).collect()
    };
    let solver = IkSolver::new(
        model,
        IkParams {
            redundancy_joint: Some(0),
            lock_values,
            restarts: 60,
            lock_seeds: 6,
            ..IkParams::default()
        },
    )
    .unwrap();
    let s_end = s_star(d) * (1.0 + rig.planner.margin);
    let tool_inv = Frame::from_iso(&rig.tool).inverse();
    let rc = rig.clamp_rotation();
    let oc = rig.clamp.translation.vector;
    let l = rig.rod.length;
    let dist = |a: &[Real], b: &[Real]| (0..dof).map(|j| (a[j] - b[j]).abs()).fold(0.0, Real::max);
    let mut out = Reach {
        n_wp,
        s_end,
        last: 0,
        next_valid: 0,
        reach: Vec::new(),
    };
    for k in 0..n_wp {
        let s = s_end * k as Real / (n_wp - 1) as Real;
        let h = Helix::new(s * d.kappa, s * d.tau, s * d.omega).unwrap();
        let e = h.end_pose(l, rig.rod.nu).unwrap();
        let tool = Frame {
            rot: rc * e.transported * p_matrix(),
            pos: oc + rc * e.position,
        };
        let tip = tool.mul(&tool_inv);
        let target = IkTarget::Pose(tip);
        let nodes: Vec<Vec3> = discrete::nodes(&h, rig.planner.rod_capsules)
            .into_iter()
            .map(|x| oc + rc * (x * l))
            .collect();
        let rod = rig.rod_geometry(&nodes);
        let mut valid = |q: &[Real]| cm.check(q, &mut ws, Some(&rod)).is_none();
        // Fresh IK, seeded also with the reachable set (so its continuations are not missed).
        let seeds: Vec<&[Real]> = out.reach.iter().map(|q| q.as_slice()).collect();
        let cand: Vec<Vec<Real>> = solver
            .solve_all(&target, &seeds)
            .into_iter()
            .map(|s| s.joints().to_vec())
            .filter(|q| valid(q))
            .collect();
        let seg_ok = |a: &[Real], b: &[Real], valid: &mut dyn FnMut(&[Real]) -> bool| {
            let n = (dist(a, b) / 0.01).ceil() as usize;
            (1..n).all(|i| {
                let t = i as Real / n as Real;
                let q: Vec<Real> = (0..dof).map(|j| a[j] + t * (b[j] - a[j])).collect();
                valid(&q)
            })
        };
        // Forward step.
        let mut r: Vec<bool> = if k == 0 {
            vec![true; cand.len()]
        } else {
            cand.iter()
                .map(|q| {
                    out.reach
                        .iter()
                        .any(|p| dist(p, q) <= step && seg_ok(p, q, &mut valid))
                })
                .collect()
        };
        // Self-motion closure at this held pose (fixed point over the candidates).
        let joined = |a: &[Real], b: &[Real], valid: &mut dyn FnMut(&[Real]) -> bool| -> bool {
            let mut stack = vec![(a.to_vec(), b.to_vec(), 0u32)];
            while let Some((x, y, depth)) = stack.pop() {
                let dxy = dist(&x, &y);
                if dxy <= step {
                    if !seg_ok(&x, &y, valid) {
                        return false;
                    }
                    continue;
                }
                if depth > 8 {
                    return false;
                }
                let mid: Vec<Real> = (0..dof).map(|j| 0.5 * (x[j] + y[j])).collect();
                let Some(m) = solver.track(&target, &mid, None) else {
                    return false;
                };
                let m = m.joints().to_vec();
                if !valid(&m) || dist(&m, &x) >= dxy || dist(&m, &y) >= dxy {
                    return false;
                }
                stack.push((m.clone(), y, depth + 1));
                stack.push((x, m, depth + 1));
            }
            true
        };
        loop {
            let mut changed = false;
            for i in 0..cand.len() {
                if r[i] {
                    continue;
                }
                let hit = (0..cand.len()).any(|j| {
                    r[j] && dist(&cand[i], &cand[j]) <= 4.0 * grid.max(step)
                        && joined(&cand[j], &cand[i], &mut valid)
                });
                if hit {
                    r[i] = true;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let n_valid = cand.len();
        let reach: Vec<Vec<Real>> = cand
            .into_iter()
            .zip(r)
            .filter_map(|(q, ok)| ok.then_some(q))
            .collect();
        if reach.is_empty() {
            out.next_valid = n_valid;
            return out;
        }
        assert!(reach.iter().all(|q| q.len() == dof && dof <= MAX_DOF));
        out.last = k;
        out.reach = reach;
    }
    out
}
