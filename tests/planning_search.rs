//! The search of the valid set ([`helixreach::planning::search`], `planner.search = "exact"`):
//!
//! - a brute-force reference (every IK branch on a redundancy grid from many restarts at every
//!   slice — and a roll grid in roll `motor` —, flood fill with self-motion closure checked by
//!   bisection) agrees with it ray by ray, in both roll modes;
//! - monotone per direction: roll `motor` ⊇ `fixed`, more azimuths ⊇ fewer, a finer
//!   self-motion step never reaches less, back-off allowed ⊇ forbidden;
//! - its paths are valid (steps, poses, collisions, phases), a search that hits the node bound
//!   is `undecided`, and a resolution the bound cannot hold is refused naming the setting.
//!
//! All on a coarse resolution of the seed rig (uniform slices, large steps) so that the
//! reference runs in seconds.

use helixreach::directions::{fibonacci, Direction};
use helixreach::math::{rot_z, Real, Vec3};
use helixreach::planning::planner::{PlannedPoint, Planner, RayPlan, ReachClass, RigOverrides};
use helixreach::planning::pose_path::{pose_path, PoseMap, Ray, Spacing};
use helixreach::planning::rig::{Rig, RollMode, SearchMethod};
use helixreach::planning::trajectory::Phase;
use helixreach::robot::{CollisionModel, Frame, IkParams, IkSolver, IkTarget, MAX_DOF};
use rayon::prelude::*;
use std::f64::consts::PI;

fn s_star(d: &Direction) -> Real {
    helixreach::boundary::continuum::critical_s(d, 1e-10)
        .unwrap()
        .s_star
}

/// The seed rig at a coarse resolution: `n` slices uniform in s, joint steps up to 0.3 rad,
/// self-motion step `step`, margin 0.
fn coarse_rig(n: usize, step: Real) -> Rig {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    let p = &mut rig.planner;
    p.search = SearchMethod::Exact;
    // Large enough that the sampled rays are decided in both roll modes (the seed rig's
    // default bound leaves some roll `motor` rays `undecided`).
    p.max_search_nodes = 1_000_000;
    p.margin = 0.0;
    p.waypoints = n;
    p.max_joint_step = 0.3;
    p.self_motion_step = step;
    p.search_step = step;
    p.segment_check_step = 0.05;
    p.rod_capsules = 12;
    rig
}

/// Brute-force reachability of one ray at azimuth 0, forward only (no back-off), reconfiguration
/// allowed: the farthest slice reached. `rolls` are the arm rolls ψ about the rod tangent tried
/// (one value: roll `fixed`; a grid over the circle: roll `motor` with a freely turning motor).
/// The slices are the rig's pose path; at each, for every roll, every IK solution of the pose
/// turned by ψ found with j0 locked on a `grid` rad grid (6 seeds each) and 60 random restarts,
/// seeded also with the previous slice's reachable set; a configuration is valid when
/// collision-free against the slice's rod (capsules from the pose map's centerline).
/// R₀ = every valid configuration of slice 0; R_{k+1} = valid configurations of slice k+1 at the
/// same roll within the step bound of R_k with a collision-free joint-linear segment (with
/// `tracked_loads`, only the one a minimum-norm IK run from each configuration of R_k lands on:
/// the search's load edge), closed under moves inside the slice: two configurations of a slice at the same or neighbouring rolls
/// of the grid are joined when bisection (midpoints projected by IK onto the pose at the mid
/// roll, each valid and between its ends) splits them into pieces within the step bound, every
/// piece's segment collision-free.
/// Seeds per roll from the previous slice's reachable set when [`brute_force_farthest`] tries
/// several rolls.
const MAX_SEEDS: usize = 48;

fn brute_force_farthest(
    rig: &Rig,
    planner: &Planner,
    d: &Direction,
    grid: Real,
    rolls: &[Real],
    tracked_loads: bool,
) -> usize {
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
    let ray = Ray {
        dir: [d.kappa, d.tau, d.omega],
        azimuth: 0.0,
    };
    let s_end = s_star(d) * (1.0 + rig.planner.margin);
    let wps = pose_path(rig, &ray, s_end, &Spacing::of(rig)).unwrap();
    let map = PoseMap::new(rig, 0.0);
    let dist = |a: &[Real], b: &[Real]| (0..dof).map(|j| (a[j] - b[j]).abs()).fold(0.0, Real::max);
    let seg = rig.planner.segment_check_step;
    let tool_inv = Frame::from_iso(&rig.tool).inverse();
    let n_rolls = rolls.len();
    // The roll between two of the grid (halfway along the shorter arc of the circle).
    let mid_roll = |a: usize, b: usize| {
        let tau = std::f64::consts::TAU;
        let mut d = rolls[b] - rolls[a];
        d -= tau * (d / tau).round();
        rolls[a] + 0.5 * d
    };
    let neighbours = |a: usize, b: usize| {
        let k = (a + n_rolls - b) % n_rolls;
        k == 0 || k == 1 || k == n_rolls - 1
    };
    // (roll index, joints)
    let mut reach: Vec<(usize, Vec<Real>)> = Vec::new();
    for (k, w) in wps.iter().enumerate() {
        let target_at = |psi: Real| {
            let tool = Frame::from_iso(&w.tool).mul(&Frame::new(rot_z(-psi), Vec3::zeros()));
            IkTarget::Pose(tool.mul(&tool_inv))
        };
        let nodes: Vec<Vec3> = map.centerline(w.kto, rig.planner.rod_capsules).unwrap();
        let rod = rig.rod_geometry(&nodes);
        let mut valid = |q: &[Real]| cm.check(q, &mut ws, Some(&rod)).is_none();
        let mut cand: Vec<(usize, Vec<Real>)> = Vec::new();
        for (m, &psi) in rolls.iter().enumerate() {
            let near: Vec<&[Real]> = reach
                .iter()
                .filter(|(r, _)| neighbours(*r, m))
                .map(|(_, q)| q.as_slice())
                .collect();
            // With a roll grid, at most `MAX_SEEDS` of them, evenly spread (the reference's
            // cost is quadratic in its candidates, which the roll grid multiplies).
            let cap = if n_rolls > 1 { MAX_SEEDS } else { usize::MAX };
            let seeds: Vec<&[Real]> = near
                .iter()
                .step_by(near.len().div_ceil(cap).max(1))
                .copied()
                .collect();
            cand.extend(
                solver
                    .solve_all(&target_at(psi), &seeds)
                    .into_iter()
                    .map(|s| s.joints().to_vec())
                    .filter(|q| valid(q))
                    .map(|q| (m, q)),
            );
        }
        let seg_ok = |a: &[Real], b: &[Real], valid: &mut dyn FnMut(&[Real]) -> bool| {
            let n = (dist(a, b) / seg).ceil() as usize;
            (1..n).all(|i| {
                let t = i as Real / n as Real;
                let q: Vec<Real> = (0..dof).map(|j| a[j] + t * (b[j] - a[j])).collect();
                valid(&q)
            })
        };
        let mut r: Vec<bool> = if k == 0 {
            vec![true; cand.len()]
        } else if tracked_loads {
            let n0 = cand.len();
            for (rp, p) in &reach {
                if let Some(t) = solver.track(&target_at(rolls[*rp]), p, None) {
                    let t = t.joints().to_vec();
                    if valid(&t) && dist(p, &t) <= step && seg_ok(p, &t, &mut valid) {
                        cand.push((*rp, t));
                    }
                }
            }
            (0..cand.len()).map(|i| i >= n0).collect()
        } else {
            cand.iter()
                .map(|(m, q)| {
                    reach
                        .iter()
                        .any(|(rp, p)| rp == m && dist(p, q) <= step && seg_ok(p, q, &mut valid))
                })
                .collect()
        };
        // Bisection between (a at roll ra) and (b at roll rb): the midpoint at the mid roll.
        let joined = |a: &[Real],
                      b: &[Real],
                      ra: Real,
                      rb: Real,
                      valid: &mut dyn FnMut(&[Real]) -> bool|
         -> bool {
            let mut stack = vec![(a.to_vec(), b.to_vec(), ra, rb, 0u32)];
            while let Some((x, y, rx, ry, depth)) = stack.pop() {
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
                let rm = 0.5 * (rx + ry);
                let Some(m) = solver.track(&target_at(rm), &mid, None) else {
                    return false;
                };
                let m = m.joints().to_vec();
                if !valid(&m) || dist(&m, &x) >= dxy || dist(&m, &y) >= dxy {
                    return false;
                }
                stack.push((m.clone(), y, rm, ry, depth + 1));
                stack.push((x, m, rx, rm, depth + 1));
            }
            true
        };
        loop {
            let mut changed = false;
            for i in 0..cand.len() {
                if r[i] {
                    continue;
                }
                let mi = cand[i].0;
                let hit = (0..cand.len()).any(|j| {
                    let mj = cand[j].0;
                    if !(r[j] && neighbours(mi, mj))
                        || dist(&cand[i].1, &cand[j].1) > 2.0 * grid.max(step)
                    {
                        return false;
                    }
                    // The roll of j, and i's unwrapped next to it.
                    let (rj, ri) = (rolls[mj], 2.0 * mid_roll(mj, mi) - rolls[mj]);
                    joined(&cand[j].1, &cand[i].1, rj, ri, &mut valid)
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
        let next: Vec<(usize, Vec<Real>)> = cand
            .into_iter()
            .zip(r)
            .filter_map(|(c, ok)| ok.then_some(c))
            .collect();
        if next.is_empty() {
            return k.saturating_sub(1);
        }
        assert!(next.iter().all(|(_, q)| q.len() == dof && dof <= MAX_DOF));
        reach = next;
    }
    wps.len() - 1
}

/// The slice index of s on the ray's pose path.
fn slice_of(rig: &Rig, d: &Direction, s: Real) -> usize {
    let ray = Ray {
        dir: [d.kappa, d.tau, d.omega],
        azimuth: 0.0,
    };
    let wps = pose_path(
        rig,
        &ray,
        s_star(d) * (1.0 + rig.planner.margin),
        &Spacing::of(rig),
    )
    .unwrap();
    wps.iter()
        .position(|w| (w.s - s).abs() <= 1e-12 * s.max(1.0))
        .expect("s_reached is a slice")
}

/// Search and brute force agree ray by ray (roll `fixed`, back-off forbidden): same class, and
/// the search reaches at least the brute force's farthest slice (its self-motion closure is a
/// walk along the curve; the reference's bisection between grid points can miss a joint near a
/// fold of j0, so the reference may stop earlier, never later), on every 25th direction of the
/// 200-direction quarter-sphere lattice, 24 slices each; at a self-motion step of 0.05 rad and
/// of 0.36 rad (over 0.8 of the joint-step bound: every walk a chain of two sub-steps).
#[test]
fn search_agrees_with_the_brute_force_reference() {
    let mut rig = coarse_rig(24, 0.05);
    rig.planner.allow_backoff = false;
    // The reference joins neighbouring slices only: the search on the same fixed slices.
    rig.planner.bridge_halvings = 0;
    let mut chained = rig.clone();
    chained.planner.search_step = 0.36;
    let chained = Planner::new(chained).unwrap();
    let planner = Planner::new(rig.clone()).unwrap();
    let dirs: Vec<Direction> = fibonacci(200, true)
        .unwrap()
        .into_iter()
        .step_by(25)
        .collect();
    let res: Vec<(usize, usize, ReachClass, usize, ReachClass)> = dirs
        .par_iter()
        .map(|d| {
            let p = planner
                .plan_ray(d, s_star(d), 0.0, RollMode::Fixed, false)
                .unwrap();
            let c = chained
                .plan_ray(d, s_star(d), 0.0, RollMode::Fixed, false)
                .unwrap();
            let b = brute_force_farthest(&rig, &planner, d, 0.1, &[0.0], false);
            (
                slice_of(&rig, d, p.s_reached),
                b,
                p.class,
                slice_of(&rig, d, c.s_reached),
                c.class,
            )
        })
        .collect();
    let mut testable = 0;
    for (d, &(s, b, class, sc, cc)) in dirs.iter().zip(&res) {
        eprintln!("{d:?}: search slice {s} ({class:?}), chained {sc} ({cc:?}), brute force {b}");
        let b_testable = b == 23;
        for (s, class) in [(s, class), (sc, cc)] {
            assert_eq!(
                class == ReachClass::Testable,
                b_testable,
                "{d:?}: {s} vs {b}"
            );
            assert!(s >= b, "{d:?}: search {s}, brute force {b}");
        }
        testable += usize::from(b_testable);
    }
    assert!(
        testable > 0 && testable < dirs.len(),
        "{testable}: a sample with both classes"
    );
}

/// The same in roll `motor` (the seed rig's motor turns freely): the reference tries the arm
/// roll on a 2π/13 rad grid over the circle, joined between neighbouring rolls by bisection;
/// its load edges are the search's (a minimum-norm IK run from each reachable configuration at
/// the same roll), its cover of each slice its own (IK on the j0 × roll grid from restarts and
/// bisection closure, not walks and roll steps). On the rays of every 25th direction of the
/// 200-direction quarter-sphere lattice that roll `fixed` does not make testable, 24 slices,
/// search step 0.2 rad: the search reaches at least the reference's farthest slice, is testable
/// where the reference is, and on at least one ray both pass the roll-0 reference (the roll
/// moves matter). A reference whose loads take any valid solution within the 0.3 rad step
/// bound reaches farther on direction 100 (slice 8, the search 5): such jumps between
/// solutions are not edges of the search (module docs of `planning::search`, "Resolution").
#[test]
fn motor_search_agrees_with_the_brute_force_reference() {
    let mut rig = coarse_rig(24, 0.2);
    rig.planner.allow_backoff = false;
    rig.planner.bridge_halvings = 0;
    let planner = Planner::new(rig.clone()).unwrap();
    let rolls: Vec<Real> = (0..13)
        .map(|k| k as Real * std::f64::consts::TAU / 13.0)
        .collect();
    let dirs: Vec<Direction> = fibonacci(200, true)
        .unwrap()
        .into_iter()
        .step_by(25)
        .filter(|d| {
            planner
                .plan_ray(d, s_star(d), 0.0, RollMode::Fixed, false)
                .unwrap()
                .class
                != ReachClass::Testable
        })
        .collect();
    let res: Vec<(usize, ReachClass, usize, usize)> = dirs
        .par_iter()
        .map(|d| {
            let p = planner
                .plan_ray(d, s_star(d), 0.0, RollMode::Motor, false)
                .unwrap();
            let b = brute_force_farthest(&rig, &planner, d, 0.1, &rolls, true);
            let bf = brute_force_farthest(&rig, &planner, d, 0.1, &[0.0], true);
            (slice_of(&rig, d, p.s_reached), p.class, b, bf)
        })
        .collect();
    for (d, &(s, class, b, bf)) in dirs.iter().zip(&res) {
        eprintln!("{d:?}: search slice {s} ({class:?}), brute force {b} (roll 0 only: {bf})");
    }
    let mut beyond_roll0 = 0;
    for (d, &(s, class, b, bf)) in dirs.iter().zip(&res) {
        assert!(s >= b, "{d:?}: search {s}, brute force {b}");
        if b == 23 {
            assert_eq!(class, ReachClass::Testable, "{d:?}");
        }
        beyond_roll0 += usize::from(b > bf && s >= b);
    }
    assert!(
        !dirs.is_empty() && beyond_roll0 > 0,
        "{} rays, {beyond_roll0} beyond the roll-0 reference",
        dirs.len()
    );
}

/// Monotone per direction: roll `motor` ⊇ `fixed`; azimuths {0, π/2} ⊇ {0}; self-motion step
/// 0.05 ⊇ 0.1 ⊇ 0.36 (finer never reaches less; at 0.36 every walk is a chain of two
/// sub-steps); back-off allowed ⊇ forbidden. On every 40th direction of the 200-direction
/// quarter-sphere lattice, 24 slices.
#[test]
fn search_is_monotone_per_direction() {
    let coarse = Planner::new(coarse_rig(24, 0.1)).unwrap();
    let fine = Planner::new(coarse_rig(24, 0.05)).unwrap();
    let mut chained = coarse_rig(24, 0.1);
    chained.planner.search_step = 0.36;
    let chained = Planner::new(chained).unwrap();
    let mut no_back = coarse_rig(24, 0.1);
    no_back.planner.allow_backoff = false;
    let no_back = Planner::new(no_back).unwrap();
    let dirs: Vec<Direction> = fibonacci(200, true)
        .unwrap()
        .into_iter()
        .step_by(40)
        .collect();
    let rank = |c: ReachClass| match c {
        ReachClass::Testable => 3,
        ReachClass::Undecided => 2,
        ReachClass::Partial => 1,
        ReachClass::Blocked => 0,
    };
    dirs.par_iter().for_each(|d| {
        let s = s_star(d);
        let fixed = coarse.plan_ray(d, s, 0.0, RollMode::Fixed, false).unwrap();
        let motor = coarse.plan_ray(d, s, 0.0, RollMode::Motor, false).unwrap();
        let two = coarse
            .plan_best(
                d,
                s,
                &[0.0, std::f64::consts::FRAC_PI_2],
                RollMode::Fixed,
                false,
            )
            .unwrap();
        let finer = fine.plan_ray(d, s, 0.0, RollMode::Fixed, false).unwrap();
        let coarser = chained.plan_ray(d, s, 0.0, RollMode::Fixed, false).unwrap();
        let forbidden = no_back.plan_ray(d, s, 0.0, RollMode::Fixed, false).unwrap();
        let ge = |a: &helixreach::planning::planner::RayPlan,
                  b: &helixreach::planning::planner::RayPlan,
                  what: &str| {
            assert!(
                rank(a.class) >= rank(b.class) && a.s_reached >= b.s_reached,
                "{d:?} {what}: {:?} {} vs {:?} {}",
                a.class,
                a.s_reached,
                b.class,
                b.s_reached
            );
        };
        ge(&motor, &fixed, "motor ⊇ fixed");
        ge(&two, &fixed, "two azimuths ⊇ one");
        ge(&finer, &fixed, "step 0.05 ⊇ 0.1");
        ge(&fixed, &coarser, "step 0.1 ⊇ 0.36");
        ge(&fixed, &forbidden, "back-off ⊇ forbidden");
    });
}

/// A testable ray's path: starts at s = 0 and ends at s_end; every step within the joint-step
/// bound; every configuration holds its waypoint's pose (1e-9 m / rad; in roll `motor` its
/// position and rod tangent, the arm's roll ψ about the tangent read from the arm's pose, the
/// point's motor angle the waypoint's less ψ up to whole turns, ψ turning by at most the roll
/// step between points, the motor angle within its range) and is collision-free
/// against its rod (capsules from the pose map's centerline, not the planner's), and so is every
/// joint-linear step between two points, sampled at most `planner.segment_check_step` apart
/// against the rod of the larger s; reconfiguration points keep s; back-off points decrease s,
/// only below s*; the trajectory's phases are those of the plan. Returns the number of interior
/// samples checked.
fn assert_path_valid(planner: &Planner, d: &Direction, s: Real, plan: &RayPlan) -> usize {
    let rig = planner.rig();
    let mut cm = CollisionModel::for_model(planner.model()).unwrap();
    cm.set_obstacles(&rig.obstacles).unwrap();
    let mut ws = cm.workspace();
    let map = PoseMap::new(rig, 0.0);
    let path = plan.path.as_ref().unwrap();
    let mut interior = 0;
    assert_eq!(path[0].waypoint.s, 0.0);
    assert!((path.last().unwrap().waypoint.s - plan.s_end).abs() <= 1e-12 * plan.s_end);
    let mut psi_prev: Option<Real> = None;
    for (k, p) in path.iter().enumerate() {
        if plan.roll == RollMode::Motor {
            let psi = motor_roll_checked(planner, p, k);
            if let Some(prev) = psi_prev {
                let turn = (psi - prev + PI).rem_euclid(2.0 * PI) - PI;
                assert!(
                    turn.abs() <= 0.05 + 1e-9,
                    "{d:?} point {k}: roll turns {turn}"
                );
            }
            psi_prev = Some(psi);
        } else {
            let target = IkTarget::Pose(planner.tip_target(&p.waypoint.tool));
            let (dp, dr) = target.errors(&planner.model().chain().tool_pose(&p.q));
            assert!(dp < 1e-9 && dr < 1e-9, "{d:?} point {k}: {dp:e} {dr:e}");
        }
        let nodes = map
            .centerline(p.waypoint.kto, rig.planner.rod_capsules)
            .unwrap();
        assert!(cm
            .check(&p.q, &mut ws, Some(&rig.rod_geometry(&nodes)))
            .is_none());
        if k == 0 {
            continue;
        }
        let a = &path[k - 1];
        let step = (0..p.q.len())
            .map(|j| (p.q[j] - a.q[j]).abs())
            .fold(0.0, Real::max);
        assert!(
            step <= rig.planner.max_joint_step + 1e-12,
            "{d:?} {k}: {step}"
        );
        let upper = if p.waypoint.s >= a.waypoint.s { p } else { a };
        let rod = map
            .centerline(upper.waypoint.kto, rig.planner.rod_capsules)
            .unwrap();
        let n = (step / rig.planner.segment_check_step).ceil() as usize;
        for m in 1..n {
            let t = m as Real / n as Real;
            let q: Vec<Real> = (0..p.q.len())
                .map(|j| a.q[j] + t * (p.q[j] - a.q[j]))
                .collect();
            let hit = cm.check(&q, &mut ws, Some(&rig.rod_geometry(&rod)));
            assert!(hit.is_none(), "{d:?} step {k} at t = {t}: {hit:?}");
            interior += 1;
        }
        match p.phase {
            Phase::Reconfigure => assert_eq!(p.waypoint.s, a.waypoint.s),
            Phase::Backoff => {
                assert!(p.waypoint.s < a.waypoint.s && a.waypoint.s <= s);
            }
            Phase::Load => assert!(p.waypoint.s > a.waypoint.s),
            other => panic!("{d:?}: phase {other:?} in a plan"),
        }
    }
    let traj = planner.trajectory(plan).unwrap();
    let n_back = traj
        .points
        .iter()
        .filter(|p| p.phase == Phase::Backoff)
        .count();
    assert_eq!(
        n_back,
        path.iter().filter(|p| p.phase == Phase::Backoff).count()
    );
    interior
}

/// A roll `motor` point's pose against its waypoint, from the arm's forward kinematics: the
/// tool position and z axis (the rod tangent) held to 1e-9; the arm's roll ψ about it
/// (`R_toolᵀ·R_arm = Rz(−ψ)`); the point's motor angle `ω/c − ψ` up to whole turns (1e-9) and
/// inside the rig's range. Returns ψ.
fn motor_roll_checked(planner: &Planner, p: &PlannedPoint, k: usize) -> Real {
    let arm = planner.tool_pose(&p.q);
    let w = &p.waypoint.tool;
    let dp = (arm.translation.vector - w.translation.vector).norm();
    let m = (w.rotation.inverse() * arm.rotation)
        .to_rotation_matrix()
        .into_inner();
    let off_axis = [m[(0, 2)], m[(1, 2)], m[(2, 0)], m[(2, 1)]]
        .iter()
        .fold(0.0, |a: Real, v| a.max(v.abs()));
    assert!(
        dp < 1e-9 && off_axis < 1e-9,
        "point {k}: {dp:e} {off_axis:e}"
    );
    let psi = -m[(1, 0)].atan2(m[(0, 0)]);
    let miss = (p.waypoint.motor - psi - p.motor + PI).rem_euclid(2.0 * PI) - PI;
    assert!(
        miss.abs() < 1e-9,
        "point {k}: motor {} vs {}",
        p.motor,
        p.waypoint.motor - psi
    );
    let (lo, hi) = planner.rig().motor.range;
    assert!(
        p.motor >= lo && p.motor <= hi,
        "point {k}: motor {}",
        p.motor
    );
    psi
}

/// Paths of the testable rays of a coarse rig (24 slices: most edges are bridges) are valid
/// ([`assert_path_valid`]), at a self-motion step of 0.1 rad and of 0.36 rad (every walk a
/// chain of two sub-steps, each resampled on the path); with reconfiguration on some of them.
#[test]
fn search_paths_are_valid() {
    let mut chained = coarse_rig(24, 0.1);
    chained.planner.search_step = 0.36;
    for rig in [coarse_rig(24, 0.1), chained] {
        let planner = Planner::new(rig).unwrap();
        let (mut checked, mut reconfigured) = (0, 0);
        for d in fibonacci(200, true).unwrap().into_iter().step_by(20) {
            let s = s_star(&d);
            let plan = planner.plan_ray(&d, s, 0.0, RollMode::Fixed, true).unwrap();
            if plan.class != ReachClass::Testable {
                continue;
            }
            checked += 1;
            reconfigured += usize::from(plan.reconfigurations > 0);
            assert_path_valid(&planner, &d, s, &plan);
        }
        assert!(
            checked >= 3 && reconfigured >= 1,
            "{checked} testable rays checked, {reconfigured} with reconfiguration"
        );
    }
}

/// Paths in roll `motor` are valid ([`assert_path_valid`]: the arm's roll read from its pose is
/// the one the motor makes up, continuous along the path): on the seed run
/// c1_0.59831_c2_0.4564 at its own clamp (margin 0), testable only in roll `motor`, at the
/// rig's joint-step bound 0.05 rad and at 0.04 and 0.03 rad (where most or all roll steps are
/// chains of sub-rolls; node bound 400,000); the path turns the arm about the rod by more
/// than a roll step in all.
#[test]
fn motor_paths_are_valid() {
    let d = Direction::new(0.799035, 0.478071, 0.364680).unwrap();
    let s = s_star(&d);
    for bound in [0.05, 0.04, 0.03] {
        let mut rig = Rig::load("sawyer-seed").unwrap();
        rig.planner.max_joint_step = bound;
        rig.planner.max_search_nodes = 400_000;
        let o = RigOverrides {
            margin: Some(0.0),
            clamp: Some([0.750, -0.350, -0.146]),
            ..Default::default()
        };
        let planner = Planner::new(o.apply(&rig).unwrap()).unwrap();
        let fixed = planner
            .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
            .unwrap();
        let motor = planner.plan_ray(&d, s, 0.0, RollMode::Motor, true).unwrap();
        eprintln!(
            "bound {bound}: fixed {:?} at {:.3}, motor {:?} at {:.3} of {:.3}",
            fixed.class, fixed.s_reached, motor.class, motor.s_reached, s
        );
        assert_eq!(fixed.class, ReachClass::Partial, "bound {bound}");
        assert_eq!(motor.class, ReachClass::Testable, "bound {bound}");
        assert_path_valid(&planner, &d, s, &motor);
        let path = motor.path.as_ref().unwrap();
        let turned = path
            .windows(2)
            .map(|w| (w[1].waypoint.motor - w[1].motor) - (w[0].waypoint.motor - w[0].motor))
            .map(Real::abs)
            .sum::<Real>();
        assert!(
            turned > 0.05,
            "bound {bound}: the arm rolls {turned} rad in all"
        );
    }
}

/// A walk step that cannot be resampled within the hold tolerance (the corrector stepped onto
/// a neighbouring branch of the self-motion near a fold) is not on a returned path: on the seed
/// run c1_0.59831_c2_0.4564 at its own clamp in roll `motor`, at self-motion steps 0.12 and
/// 0.24 rad, the first search's path has such a step; the ray is decided again with every walk
/// step resampled as it is made, and the plan with its path and the decision without it agree
/// (class, `s_reached`), the path valid ([`assert_path_valid`]).
#[test]
fn a_walk_that_does_not_hold_the_pose_is_not_on_a_path() {
    let d = Direction::new(0.799035, 0.478071, 0.364680).unwrap();
    let s = s_star(&d);
    for step in [0.12, 0.24] {
        let mut rig = Rig::load("sawyer-seed").unwrap();
        rig.planner.search_step = step;
        let o = RigOverrides {
            margin: Some(0.0),
            clamp: Some([0.750, -0.350, -0.146]),
            ..Default::default()
        };
        let planner = Planner::new(o.apply(&rig).unwrap()).unwrap();
        let with_path = planner.plan_ray(&d, s, 0.0, RollMode::Motor, true).unwrap();
        let decided = planner
            .plan_ray(&d, s, 0.0, RollMode::Motor, false)
            .unwrap();
        eprintln!(
            "step {step}: {:?} at {:.3} of {:.3} ({} nodes)",
            with_path.class, with_path.s_reached, s, with_path.search_nodes
        );
        assert_eq!(
            (with_path.class, with_path.s_reached),
            (decided.class, decided.s_reached),
            "step {step}"
        );
        if with_path.class == ReachClass::Testable {
            assert_path_valid(&planner, &d, s, &with_path);
        }
    }
}

/// Where no single step joins two slices near a ray's end, the ladder inserts midpoint poses
/// and the search bridges the same interval: on the seed rig's quarter-sphere ray 114 of 200
/// (margin 0.1) the ladder is testable; the search with fixed slices (`bridge_halvings = 0`)
/// stops two slices short with cause `discontinuity`; with bridges it is testable, its path
/// passes through a pose between slices, and the path is valid ([`assert_path_valid`]).
#[test]
fn search_bridges_where_the_ladder_refines() {
    let d = fibonacci(200, true).unwrap()[114];
    let s = s_star(&d);
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.margin = 0.1;
    let ladder = Planner::new(rig.clone()).unwrap();
    let l = ladder.plan_ray(&d, s, 0.0, RollMode::Fixed, false).unwrap();
    assert_eq!(l.class, ReachClass::Testable, "the ladder: {l:?}");
    rig.planner.search = SearchMethod::Exact;
    rig.planner.bridge_halvings = 0;
    let fixed = Planner::new(rig.clone()).unwrap();
    let f = fixed.plan_ray(&d, s, 0.0, RollMode::Fixed, false).unwrap();
    assert_eq!(f.class, ReachClass::Partial);
    assert_eq!(f.cause.map(|c| c.as_str()), Some("discontinuity"));
    rig.planner.bridge_halvings = 4;
    let bridged = Planner::new(rig.clone()).unwrap();
    let b = bridged.plan_ray(&d, s, 0.0, RollMode::Fixed, true).unwrap();
    assert_eq!(b.class, ReachClass::Testable, "the search: {b:?}");
    let ray = Ray {
        dir: [d.kappa, d.tau, d.omega],
        azimuth: 0.0,
    };
    let wps = pose_path(&rig, &ray, b.s_end, &Spacing::of(&rig)).unwrap();
    let path = b.path.as_ref().unwrap();
    let between = path
        .iter()
        .filter(|p| !wps.iter().any(|w| w.s == p.waypoint.s))
        .count();
    assert!(between > 0, "no pose between slices on the path");
    assert_path_valid(&bridged, &d, s, &b);
}

/// The node bound makes a ray `undecided`, never a guessed class, and never makes roll `motor`
/// report less than `fixed`; a self-motion step the bound cannot cover one slice at is refused,
/// naming the setting.
#[test]
fn search_bounds_are_stated() {
    let mut rig = coarse_rig(200, 0.1);
    let free = Planner::new(rig.clone()).unwrap();
    rig.planner.max_search_nodes = 1700;
    let planner = Planner::new(rig.clone()).unwrap();
    // Rays whose unbounded search needs more than 1,700 nodes are undecided under the bound;
    // the others keep their class, or are undecided when the bound cut their far-end search
    // short (never another class).
    let (mut undecided, mut motor_cut) = (0, 0);
    for d in fibonacci(200, true).unwrap().into_iter().step_by(5) {
        let s = s_star(&d);
        let full = free.plan_ray(&d, s, 0.0, RollMode::Fixed, false).unwrap();
        let p = planner
            .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
            .unwrap();
        assert!(p.search_nodes <= 1700);
        // Roll `motor` under the same bound never reports less than `fixed` (a `fixed` path is
        // a `motor` path), also where its own search is cut by the bound.
        let m = planner
            .plan_ray(&d, s, 0.0, RollMode::Motor, false)
            .unwrap();
        assert!(
            m.s_reached >= p.s_reached,
            "{d:?}: motor {m:?} vs fixed {p:?}"
        );
        if m.class == ReachClass::Undecided && p.class == ReachClass::Partial {
            motor_cut += 1;
        }
        if full.search_nodes > 1700 {
            assert_eq!(p.class, ReachClass::Undecided, "{d:?}");
            assert!(p.cause.is_none());
            undecided += 1;
        } else {
            assert!(
                p.class == full.class || p.class == ReachClass::Undecided,
                "{d:?}: {:?} vs {:?}",
                p.class,
                full.class
            );
        }
    }
    assert!(undecided > 0);
    assert!(
        motor_cut > 0,
        "no motor search cut by the bound on a partial fixed ray"
    );
    rig.planner.max_search_nodes = 1000;
    rig.planner.search_step = 0.01;
    let e = Planner::new(rig).unwrap_err().to_string();
    assert!(e.contains("planner.search_step"), "{e}");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let text = std::fs::read_to_string(dir.join("sawyer-seed.toml")).unwrap();
    let bad = text.replacen("search = \"exact\"", "search = \"exhaustive\"", 1);
    let e = Rig::from_toml_str(&bad, "t.toml", &dir)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("planner.search") && e.contains("exhaustive"),
        "{e}"
    );
    let good = text.replacen("search = \"exact\"", "search = \"ladder\"", 1);
    let rig = Rig::from_toml_str(&good, "t.toml", &dir).unwrap();
    assert_eq!(rig.planner.search, SearchMethod::Ladder);
    // Written back and read again, the setting survives.
    let again = Rig::from_toml_str(&rig.to_toml().unwrap(), "t2.toml", &dir).unwrap();
    assert_eq!(again.planner.search, SearchMethod::Ladder);
}

/// A freely turning motor (range (−∞, ∞), the seed rig's) makes the roll a circle: the search
/// merges configurations a whole motor turn apart, so a piece whose loops wind the motor is
/// flooded once. On direction 90 of the 200-direction quarter-sphere lattice (16 slices,
/// self-motion step 0.2 rad, margin 0.1, roll `fixed` partial) the roll `motor` search is then
/// decided within 300,000 nodes — partial, reaching at least the `fixed` s — while the same
/// motor with a bounded range of ±10⁶ rad (windings then count, the roll is unwrapped) floods a
/// copy per winding and stays `undecided` at that bound.
#[test]
fn a_free_motor_is_searched_modulo_whole_turns() {
    let mut rig = coarse_rig(16, 0.2);
    rig.planner.margin = 0.1;
    rig.planner.max_search_nodes = 300_000;
    assert_eq!(rig.motor.range, (Real::NEG_INFINITY, Real::INFINITY));
    let mut wound = rig.clone();
    wound.motor.range = (-1e6, 1e6);
    let d = fibonacci(200, true).unwrap()[90];
    let s = s_star(&d);
    let fixed = Planner::new(rig.clone())
        .unwrap()
        .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
        .unwrap();
    assert_eq!(fixed.class, ReachClass::Partial);
    let (free, bounded) = rayon::join(
        || {
            Planner::new(rig.clone())
                .unwrap()
                .plan_ray(&d, s, 0.0, RollMode::Motor, false)
                .unwrap()
        },
        || {
            Planner::new(wound.clone())
                .unwrap()
                .plan_ray(&d, s, 0.0, RollMode::Motor, false)
                .unwrap()
        },
    );
    let ctx = format!("fixed {fixed:?}\nfree {free:?}\nbounded {bounded:?}");
    assert_eq!(free.class, ReachClass::Partial, "{ctx}");
    assert!(free.s_reached >= fixed.s_reached, "{ctx}");
    assert_eq!(bounded.class, ReachClass::Undecided, "{ctx}");
    assert!(bounded.s_reached >= fixed.s_reached, "{ctx}");
}

/// A pose path cut by `planner.max_waypoints` (here 10) ends before s*·(1 + margin): the search
/// never calls such a ray testable (its path would end there), it is partial with cause
/// `waypoint_limit`.
#[test]
fn search_never_calls_a_cut_ray_testable() {
    use helixreach::planning::cause::BlockCause;
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.search = SearchMethod::Exact;
    rig.planner.max_waypoints = 10;
    let planner = Planner::new(rig).unwrap();
    let mut cut = 0;
    for d in fibonacci(6, true).unwrap() {
        let s = s_star(&d);
        let plan = planner
            .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
            .unwrap();
        let last = plan
            .path
            .as_ref()
            .map_or(plan.s_reached, |p| p.last().unwrap().waypoint.s);
        assert!(
            plan.class != ReachClass::Testable || last >= plan.s_end,
            "{d:?}: testable at {last} < {}",
            plan.s_end
        );
        if plan.cause == Some(BlockCause::WaypointLimit) {
            assert_eq!(plan.class, ReachClass::Partial);
            assert!(plan.s_reached < plan.s_end);
            cut += 1;
        }
    }
    assert!(cut > 0, "no ray reported the waypoint limit");
}
