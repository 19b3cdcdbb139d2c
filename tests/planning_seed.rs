//! Reachability you can trust, planner side:
//!
//! - the seed experiment's 58 executed directions, each with its own clamp, at margin 0 in roll
//!   `fixed` (the real robot drove them all): the testable fraction, by the ladder and the search;
//! - monotone answers per direction (motor ≥ fixed, a superset of azimuths, reconfiguration
//!   allowed never reach less; more start samples is NOT monotone yet — see the test);
//! - an independent dense reference (fresh IK on a fine redundancy grid at every waypoint,
//!   forward reachability with self-motion closure checked by bisection to the step bound,
//!   `tests/common/dense_reference.rs`): the search finds every ray the reference finds.
//!
//! The seed data is read from `tests/data/seed/` (unpacked by `tests/common`).

mod common;
use common::dense_reference::{p_matrix, reference_reaches};
use common::seed_dir;
use helixreach::directions::Direction;
use helixreach::helix::{discrete, Helix};
use helixreach::math::{rot_z, Real, Vec3};
use helixreach::planning::planner::{Planner, RayPlan, ReachClass, RigOverrides};
use helixreach::planning::pose_path::{pose_path, Ray, Spacing};
use helixreach::planning::rig::{azimuth_grid, Rig, RollMode, SearchMethod};
use helixreach::planning::witness::{self, SeedRun, Witness, WitnessEnd};
use helixreach::records::clamp_runs::read_seed_runs;
use helixreach::records::trajectory::read_joint_file;
use helixreach::robot::{CollisionModel, Frame, IkParams, IkSolver, IkTarget};
use rayon::prelude::*;
use std::collections::BTreeMap;

fn seed_runs() -> Vec<SeedRun> {
    read_seed_runs(&seed_dir().join("trajectories.csv")).unwrap()
}

fn s_star(d: &Direction) -> Real {
    helixreach::boundary::continuum::critical_s(d, 1e-10)
        .unwrap()
        .s_star
}

/// The end of the regular waypoint interval (azimuth 0, the rig's pose path) in which `plan`
/// of direction `d` stopped: the first waypoint beyond its s reached.
fn interval_end(rig: &Rig, d: &Direction, plan: &RayPlan) -> Real {
    let ray = Ray {
        dir: [d.kappa, d.tau, d.omega],
        azimuth: 0.0,
    };
    let wps = pose_path(rig, &ray, plan.s_end, &Spacing::of(rig)).unwrap();
    wps.iter().find(|w| w.s > plan.s_reached).unwrap().s
}

/// A planner per distinct clamp position (key: whole micrometres), deciding rays by `search`.
/// The seed rig decided by the ladder (the tests of its gates, start levels and reconfiguration
/// walks).
fn ladder_rig() -> Rig {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    rig.planner.search = SearchMethod::Ladder;
    rig
}

fn planners_by_clamp(
    runs: &[SeedRun],
    margin: Real,
    search: SearchMethod,
    max_search_nodes: Option<usize>,
) -> BTreeMap<[i64; 3], Planner> {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    if let Some(n) = max_search_nodes {
        rig.planner.max_search_nodes = n;
    }
    let mut keys: Vec<[i64; 3]> = runs.iter().map(|r| key(r.clamp)).collect();
    keys.sort();
    keys.dedup();
    keys.into_par_iter()
        .map(|k| {
            let o = RigOverrides {
                margin: Some(margin),
                clamp: Some([
                    k[0] as Real * 1e-6,
                    k[1] as Real * 1e-6,
                    k[2] as Real * 1e-6,
                ]),
                search: Some(search),
                ..Default::default()
            };
            (k, Planner::new(o.apply(&rig).unwrap()).unwrap())
        })
        .collect()
}

fn key(c: [Real; 3]) -> [i64; 3] {
    c.map(|x| (x * 1e6).round() as i64)
}

/// The seed's run `r` as a witness on `planner` (its rig with the run's clamp, margin 0), roll
/// `fixed`, azimuth 0 ([`helixreach::planning::witness`]: projection onto our ray, correction
/// onto our pose, jumps classified by self-motion walks at the held pose).
fn witness(planner: &Planner, r: &SeedRun) -> Witness {
    let names: Vec<String> = planner
        .model()
        .joints()
        .iter()
        .map(|j| j.name.clone())
        .collect();
    let traj = read_joint_file(&seed_dir().join("trajectories").join(&r.file), &names).unwrap();
    witness::witness(planner, &traj, &r.dir).unwrap().verdict
}

/// The seed's runs, each with its own clamp, margin 0, roll `fixed`, azimuth 0, decided by
/// `search`: which are testable, and the files of the misses the seed's own run does not
/// explain. A miss is explained when the planner reaches at least as far as the run is an
/// undisturbed witness (to within `S_SLACK`, about two waypoints) and the witness does not reach
/// our target; each miss is printed with the witness's extent and end.
fn seed_runs_at_own_clamps(runs: &[SeedRun], search: SearchMethod) -> (Vec<bool>, Vec<String>) {
    const S_SLACK: Real = 0.02;
    let planners = planners_by_clamp(runs, 0.0, search, None);
    let plans: Vec<_> = runs
        .par_iter()
        .map(|r| {
            let p = &planners[&key(r.clamp)];
            p.plan_ray(&r.dir, s_star(&r.dir), 0.0, RollMode::Fixed, false)
                .unwrap()
        })
        .collect();
    let testable: Vec<bool> = plans
        .iter()
        .map(|p| p.class == ReachClass::Testable)
        .collect();
    let reconf: usize = plans.iter().map(|p| p.reconfigurations).sum();
    let misses: Vec<(&SeedRun, &_)> = runs
        .iter()
        .zip(&plans)
        .filter(|(_, p)| p.class != ReachClass::Testable)
        .collect();
    let verdicts: Vec<Witness> = misses
        .par_iter()
        .map(|(r, _)| witness(&planners[&key(r.clamp)], r))
        .collect();
    let mut unexplained = Vec::new();
    for ((r, p), v) in misses.iter().zip(&verdicts) {
        eprintln!(
            "{}: {} {} at s = {:.3} of {:.3} (cause {:?}); the seed's run is a witness to \
             s = {:.3}, then {:?}",
            search.as_str(),
            r.file,
            p.class.as_str(),
            p.s_reached,
            p.s_end,
            p.cause,
            v.extent,
            v.end
        );
        if v.end == WitnessEnd::Target || p.s_reached < v.extent - S_SLACK {
            unexplained.push(r.file.clone());
        }
    }
    eprintln!(
        "seed directions (margin 0, roll fixed, own clamps), {}: {} of {} testable, \
         {reconf} reconfigurations",
        search.as_str(),
        testable.iter().filter(|&&t| t).count(),
        runs.len()
    );
    (testable, unexplained)
}

/// The seed's 58 directions, each with its own clamp, margin 0, roll `fixed`: the real robot
/// drove every one of them, so the planner should find (nearly) every one testable, by the
/// ladder and by the search (`planner.search = "exact"`), and every miss must be explained by
/// the seed's own run.
#[test]
fn seed_directions_are_testable_with_their_own_clamps() {
    let runs = seed_runs();
    assert_eq!(runs.len(), 58);
    let (ladder, unexplained_l) = seed_runs_at_own_clamps(&runs, SearchMethod::Ladder);
    let (exact, unexplained_e) = seed_runs_at_own_clamps(&runs, SearchMethod::Exact);
    assert!(
        unexplained_l.is_empty() && unexplained_e.is_empty(),
        "the seed's own run shows a feasible undisturbed path the planner misses: ladder \
         {unexplained_l:?}, search {unexplained_e:?}"
    );
    // The search finds every run the ladder finds.
    for ((r, l), e) in runs.iter().zip(&ladder).zip(&exact) {
        assert!(
            !l || *e,
            "{}: the ladder finds it testable, the search does not",
            r.file
        );
    }
    let n_ladder = ladder.iter().filter(|&&t| t).count();
    let n_exact = exact.iter().filter(|&&t| t).count();
    // The goal is ≥ 95 % (the real robot drove all 58). Measured: the ladder 52 of 58; in
    // each of its 6 misses the seed's run jumps between disjoint self-motion components (it
    // disturbed the rod) or stops short of our s*, before or at our stop. The search: 53 of 58,
    // every run the ladder finds and c1_0.70228_c2_0.33805.txt; its 5 misses (c1_0.35_c2_0,
    // c1_0.53172_c2_0.47577, c1_0.55355_c2_0.20785, c1_0.58961_c2_0.27996, c1_0.59831_c2_0.4564)
    // stop past the seed run's undisturbed extent: there the run jumps between disjoint
    // self-motion components (4) or stops short of our s* (1). These floors catch regressions.
    assert!(
        n_ladder >= 52,
        "ladder: {n_ladder} of {} seed directions testable (floor 52; goal ≥ 95 %)",
        runs.len()
    );
    assert!(
        n_exact >= 53,
        "search: {n_exact} of {} seed directions testable (floor 53; goal ≥ 95 %)",
        runs.len()
    );
}

/// The seed's run c1_0.35_c2_0 (its own clamp, margin 0): in roll `fixed` the search stops at a
/// joint limit near s = 6.04 of 7.76 (the real robot jumped 1.00 rad between disjoint self-motion
/// components at s = 1.34), and in roll `motor` — the seed rig's motor turns freely — it finds a
/// path to s*. That search compares the roll modulo a whole turn; with the roll unwrapped it
/// would flood a copy of the piece per winding and end `undecided` at the 1,000,000-node bound.
/// The motor search needs that bound here (the seed rig's bound, 50,000, leaves the run
/// `undecided`, never partial).
#[test]
fn a_seed_run_is_testable_by_the_motor_roll() {
    let runs = seed_runs();
    let r = runs
        .iter()
        .find(|r| r.file == "c1_0.35_c2_0.txt")
        .expect("the seed run");
    let planners = planners_by_clamp(
        std::slice::from_ref(r),
        0.0,
        SearchMethod::Exact,
        Some(1_000_000),
    );
    let p = &planners[&key(r.clamp)];
    let s = s_star(&r.dir);
    let fixed = p.plan_ray(&r.dir, s, 0.0, RollMode::Fixed, false).unwrap();
    assert_eq!(fixed.class, ReachClass::Partial, "{fixed:?}");
    assert!(fixed.s_reached < 0.8 * s, "{fixed:?}");
    let motor = p.plan_ray(&r.dir, s, 0.0, RollMode::Motor, true).unwrap();
    assert_eq!(motor.class, ReachClass::Testable, "{motor:?}");
    let default = planners_by_clamp(std::slice::from_ref(r), 0.0, SearchMethod::Exact, None);
    let cut = default[&key(r.clamp)]
        .plan_ray(&r.dir, s, 0.0, RollMode::Motor, false)
        .unwrap();
    assert_ne!(cut.class, ReachClass::Partial, "{cut:?}");
    let path = motor.path.as_ref().expect("a path");
    assert_eq!(path[0].waypoint.s, 0.0);
    assert!((path.last().unwrap().waypoint.s - s).abs() <= 1e-9 * s);
}

/// More samples never reach less: doubling `planner.dense_samples` (the start sampling of the
/// dense levels) on the direction where twice the base width reached less
/// ((0.3226, 0.4013, 0.8573), 5.53 with 16 base nodes vs 5.78 with 8), and on every 80th
/// direction of the quarter-sphere lattice. Each level is asserted to contain the previous.
#[test]
fn more_start_samples_never_reach_less() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let mut dirs = vec![Direction::new(0.3226, 0.4013, 0.8573).unwrap()];
    dirs.extend(
        helixreach::directions::fibonacci(400, true)
            .unwrap()
            .into_iter()
            .step_by(80),
    );
    let levels = [0usize, 16, 32, 64];
    let planners: Vec<Planner> = levels
        .iter()
        .map(|&d| {
            let mut r = rig.clone();
            r.planner.dense_samples = d;
            Planner::new(r).unwrap()
        })
        .collect();
    let rows: Vec<Vec<(Real, usize)>> = dirs
        .par_iter()
        .map(|d| {
            let s = s_star(d);
            planners
                .iter()
                .map(|p| {
                    let r = p.plan_ray(d, s, 0.0, RollMode::Fixed, false).unwrap();
                    (r.s_reached, r.start_samples)
                })
                .collect()
        })
        .collect();
    for (d, r) in dirs.iter().zip(&rows) {
        eprintln!("{d:?}: dense_samples {levels:?} reach (s, start samples) {r:?}");
        for k in 1..r.len() {
            assert!(
                r[k].0 >= r[k - 1].0,
                "dense_samples {} reaches less than {}: {d:?}: {r:?}",
                levels[k],
                levels[k - 1]
            );
        }
    }
}

/// The pointwise gate before the dense levels keeps every class: planned with and without it
/// (`Planner::set_level_gate`), on quarter-sphere directions (of the 200-direction lattice) the
/// base rungs leave partial: 1, 5 and 33 are gated (their base plan stops in a waypoint interval
/// whose end has no valid configuration), 16 is not (the levels make it testable). A gated ray
/// reaches at most one waypoint interval less than the levels (module docs, "Pointwise gate").
#[test]
fn pointwise_gate_keeps_the_class() {
    let rig = ladder_rig();
    let gated = Planner::new(rig.clone()).unwrap();
    let mut ungated = Planner::new(rig.clone()).unwrap();
    ungated.set_level_gate(false);
    let lattice = helixreach::directions::fibonacci(200, true).unwrap();
    let cases = [(1usize, true), (5, true), (33, true), (16, false)];
    let rows: Vec<_> = cases
        .par_iter()
        .map(|&(i, _)| {
            let d = lattice[i];
            let s = s_star(&d);
            let g = gated.plan_ray(&d, s, 0.0, RollMode::Fixed, false).unwrap();
            let u = ungated
                .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
                .unwrap();
            (d, g, u)
        })
        .collect();
    for ((i, expect_gated), (d, g, u)) in cases.iter().zip(&rows) {
        let ctx = format!(
            "direction {i} {d:?}: gated {:?} s {} (levels_gated {}), ungated {:?} s {}",
            g.class, g.s_reached, g.levels_gated, u.class, u.s_reached
        );
        eprintln!("{ctx}");
        assert_eq!(g.levels_gated, *expect_gated, "{ctx}");
        assert!(!u.levels_gated, "{ctx}");
        assert_eq!(g.class, u.class, "{ctx}");
        assert!(g.s_reached <= u.s_reached, "{ctx}");
        if *expect_gated {
            // Less by under one regular waypoint interval.
            let next = interval_end(&rig, d, g);
            assert!(u.s_reached < next, "{ctx}: the levels passed {next}");
        } else {
            assert_eq!(
                (g.s_reached, g.start_samples),
                (u.s_reached, u.start_samples),
                "{ctx}"
            );
        }
    }
}

/// The pointwise gate in roll `motor` keeps the class: planned with and without the gates
/// (`Planner::set_level_gate`) on quarter-sphere direction 1 of the 200-direction lattice, whose
/// motor plan stops in a waypoint interval whose end has no valid configuration. Without the
/// gates every stage runs (all motor start components, the motor dense levels); with them the
/// plan is gated, reaches less by under one regular waypoint interval, and is far cheaper.
#[test]
fn motor_gate_keeps_the_class() {
    let rig = ladder_rig();
    let gated = Planner::new(rig.clone()).unwrap();
    let mut ungated = Planner::new(rig.clone()).unwrap();
    ungated.set_level_gate(false);
    let d = helixreach::directions::fibonacci(200, true).unwrap()[1];
    let s = s_star(&d);
    let (g, u) = rayon::join(
        || gated.plan_ray(&d, s, 0.0, RollMode::Motor, false).unwrap(),
        || {
            ungated
                .plan_ray(&d, s, 0.0, RollMode::Motor, false)
                .unwrap()
        },
    );
    let ctx = format!(
        "{d:?}: gated {:?} s {} (levels_gated {}), ungated {:?} s {}",
        g.class, g.s_reached, g.levels_gated, u.class, u.s_reached
    );
    eprintln!("{ctx}");
    assert!(g.levels_gated, "{ctx}");
    assert_eq!(g.class, u.class, "{ctx}");
    assert_eq!(g.class, ReachClass::Partial, "{ctx}");
    assert!(g.s_reached <= u.s_reached, "{ctx}");
    let next = interval_end(&rig, &d, &g);
    assert!(
        u.s_reached < next,
        "{ctx}: the ungated stages passed {next}"
    );
    // The gate's verdict at `next` against an independent brute-force sampling of the 2-D
    // valid set: full-pose targets every 10° of roll about the rod tangent, each solved
    // afresh with j0 locked on a 0.1 rad grid plus random restarts. Neither finds a valid
    // configuration there; both find one halfway along the planned path.
    assert_eq!(rig.motor.range, (Real::NEG_INFINITY, Real::INFINITY));
    assert!(!gated
        .pointwise_valid_at(&d, next, 0.0, RollMode::Motor)
        .unwrap());
    assert!(
        !brute_force_motor_valid(&gated, &d, next),
        "{ctx}: reference found one at {next}"
    );
    let mid = 0.5 * g.s_reached;
    assert!(gated
        .pointwise_valid_at(&d, mid, 0.0, RollMode::Motor)
        .unwrap());
    assert!(brute_force_motor_valid(&gated, &d, mid));
}

/// Roll `motor` start components are components of the 2-D valid set (j0 × roll about the rod
/// tangent), joined by walks about the tool axis (`planner/start.rs`): every free-roll IK
/// solution of the straight rod has its own roll, so a fixed-roll (1-D) grouping leaves
/// (nearly) each its own component, and the motor dense levels were (components) × k nodes
/// wide. Checked: every group member holds the straight rod's end position and tangent; some
/// group joins solutions at different rolls; the groups are far fewer than the solutions. And
/// the rays of the demo lattice (100 quarter-sphere directions) that only roll `motor` makes
/// testable through its dense levels — 20, 46 and 69: roll `fixed` partial — stay testable
/// (they were with the per-roll grouping too; the lattice in roll `motor` took 268 s CPU then,
/// 47 s now, `--threads 1`, same load).
#[test]
fn motor_start_components_are_joined_and_keep_the_motor_only_rays() {
    let rig = ladder_rig();
    let planner = Planner::new(rig.clone()).unwrap();
    let groups = planner.start_components(RollMode::Motor);
    let n: usize = groups.iter().map(|g| g.len()).sum();
    let straight = rig.straight_tool_pose();
    let roll_of = |q: &[Real]| {
        let t = planner.tool_pose(q);
        assert!((t.translation.vector - straight.translation.vector).norm() < 1e-6);
        let (za, zb) = (t.rotation * Vec3::z(), straight.rotation * Vec3::z());
        assert!((za - zb).norm() < 1e-6, "{q:?}: tool axis off");
        let m = (straight.rotation.inverse() * t.rotation)
            .to_rotation_matrix()
            .into_inner();
        m[(1, 0)].atan2(m[(0, 0)])
    };
    let mut mixed = 0;
    for g in &groups {
        let rolls: Vec<Real> = g.iter().map(|q| roll_of(q)).collect();
        let spread = rolls
            .iter()
            .fold(0.0, |a: Real, r| a.max((r - rolls[0]).abs()));
        if spread > 1e-3 {
            mixed += 1;
        }
    }
    eprintln!(
        "{n} motor start solutions in {} groups, {mixed} of them span several rolls",
        groups.len()
    );
    assert!(n >= 40, "{n} solutions");
    assert!(mixed >= 1);
    assert!(
        3 * groups.len() <= n,
        "{} groups for {n} solutions",
        groups.len()
    );
    let lattice = helixreach::directions::fibonacci(100, true).unwrap();
    let rows: Vec<_> = [20usize, 46, 69]
        .par_iter()
        .map(|&i| {
            let d = lattice[i];
            let s = s_star(&d);
            let f = planner
                .plan_ray(&d, s, 0.0, RollMode::Fixed, false)
                .unwrap();
            let m = planner
                .plan_ray(&d, s, 0.0, RollMode::Motor, false)
                .unwrap();
            (i, f, m)
        })
        .collect();
    for (i, f, m) in &rows {
        let ctx = format!(
            "direction {i}: fixed {:?} s {}, motor {:?} s {} (k {})",
            f.class, f.s_reached, m.class, m.s_reached, m.start_samples
        );
        eprintln!("{ctx}");
        assert_eq!(f.class, ReachClass::Partial, "{ctx}");
        assert_eq!(m.class, ReachClass::Testable, "{ctx}");
        assert!(m.start_samples >= 16, "{ctx}: not from a dense level");
    }
}

/// Brute-force pointwise test in roll `motor` at arc length `s` of `d` (azimuth 0): is there a
/// collision-free configuration (self, scene, rod) holding the rod end's position and tangent at
/// any roll? Roll sampled every 10°, each a full pose solved by `IkSolver::solve_all` with j0
/// locked on a 0.1 rad grid (6 seeds each) and 60 restarts. Rod end poses from the helix module
/// and the rig's frames (not the planner's pose path).
fn brute_force_motor_valid(planner: &Planner, d: &Direction, s: Real) -> bool {
    let rig = planner.rig();
    let model = planner.model();
    let mut cm = CollisionModel::for_model(model).unwrap();
    cm.set_obstacles(&rig.obstacles).unwrap();
    let mut ws = cm.workspace();
    let (lo, hi) = (model.lower(), model.upper());
    let n = ((hi[0] - lo[0]) / 0.1).floor() as usize;
    let solver = IkSolver::new(
        model,
        IkParams {
            redundancy_joint: Some(0),
            lock_values: (0..=n).map(|i| lo[0] + i as Real * 0.1).collect(),
            restarts: 60,
            lock_seeds: 6,
            ..IkParams::default()
        },
    )
    .unwrap();
    let tool_inv = Frame::from_iso(&rig.tool).inverse();
    let rc = rig.clamp_rotation();
    let oc = rig.clamp.translation.vector;
    let l = rig.rod.length;
    let h = Helix::new(s * d.kappa, s * d.tau, s * d.omega).unwrap();
    let e = h.end_pose(l, rig.rod.nu).unwrap();
    let nodes: Vec<Vec3> = discrete::nodes(&h, rig.planner.rod_capsules)
        .into_iter()
        .map(|x| oc + rc * (x * l))
        .collect();
    let rod = rig.rod_geometry(&nodes);
    (0..36).any(|k| {
        let psi = k as Real * 10f64.to_radians();
        let tool = Frame {
            rot: rc * e.transported * p_matrix() * rot_z(psi),
            pos: oc + rc * e.position,
        };
        let target = IkTarget::Pose(tool.mul(&tool_inv));
        solver
            .solve_all(&target, &[])
            .iter()
            .any(|q| cm.check(q.joints(), &mut ws, Some(&rod)).is_none())
    })
}

/// Monotone answers, per direction: roll `motor` reaches at least as far as `fixed`; a
/// superset of azimuths, or reconfiguration allowed never reach less.
#[test]
fn answers_are_monotone_per_direction() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let base = Planner::new(rig.clone()).unwrap();
    let mut no_reconf = rig.clone();
    no_reconf.planner.allow_reconfiguration = false;
    let no_reconf = Planner::new(no_reconf).unwrap();
    // Every 40th direction of the quarter-sphere lattice.
    let dirs: Vec<Direction> = helixreach::directions::fibonacci(400, true)
        .unwrap()
        .into_iter()
        .step_by(40)
        .collect();
    let a1 = azimuth_grid(1);
    let a4 = azimuth_grid(4);
    let rows: Vec<[Real; 5]> = dirs
        .par_iter()
        .map(|d| {
            let s = s_star(d);
            let reach = |p: &Planner, az: &[Real], roll| {
                p.plan_best(d, s, az, roll, false).unwrap().s_reached
            };
            [
                reach(&base, &a1, RollMode::Fixed),
                reach(&base, &a1, RollMode::Motor),
                reach(&base, &a4, RollMode::Fixed),
                reach(&no_reconf, &a1, RollMode::Fixed),
                s,
            ]
        })
        .collect();
    for (d, r) in dirs.iter().zip(&rows) {
        let [fixed, motor, az4, norec, _] = *r;
        let ctx = format!("{d:?}: {r:?}");
        assert!(motor >= fixed, "motor < fixed: {ctx}");
        assert!(az4 >= fixed, "4 azimuths < 1: {ctx}");
        assert!(fixed >= norec, "reconfiguration reached less: {ctx}");
    }
}

/// Reconfiguration never reaches less *except by the gates' bound*: on the eight quarter-sphere
/// directions (2,000-direction lattice, indices 6, 23, 48, 80, 99, 135, 137, 166; roll `motor`)
/// where the full 2,000-direction study found s lower with reconfiguration than without (by up to
/// 0.029; the 500-direction study had found 48 and 80), the cause is the pointwise gate: with reconfiguration the first motor plan stops (by a discontinuity) where
/// the gate skips every further stage, without it the plan stops elsewhere and the levels run.
/// With the gates off both reach the same s; with them on the class is the same and the
/// difference is under one regular waypoint interval (the gate's documented bound).
#[test]
fn reconfiguration_reaches_less_only_by_the_gates_bound() {
    let rig = ladder_rig();
    let lattice = helixreach::directions::fibonacci(2000, true).unwrap();
    let planners: Vec<(bool, bool, Planner)> =
        [(true, true), (true, false), (false, true), (false, false)]
            .into_iter()
            .map(|(gate, reconf)| {
                let mut r = rig.clone();
                r.planner.allow_reconfiguration = reconf;
                let mut p = Planner::new(r).unwrap();
                p.set_level_gate(gate);
                (gate, reconf, p)
            })
            .collect();
    let cases: Vec<(usize, usize)> = [6usize, 23, 48, 80, 99, 135, 137, 166]
        .into_iter()
        .flat_map(|i| (0..planners.len()).map(move |k| (i, k)))
        .collect();
    let plans: Vec<_> = cases
        .par_iter()
        .map(|&(i, k)| {
            let d = lattice[i];
            planners[k]
                .2
                .plan_ray(&d, s_star(&d), 0.0, RollMode::Motor, false)
                .unwrap()
        })
        .collect();
    for (pair, chunk) in cases.chunks(4).zip(plans.chunks(4)) {
        let d = lattice[pair[0].0];
        let [gated_rec, gated_norec, free_rec, free_norec] = chunk else {
            unreachable!()
        };
        let ctx = format!(
            "{d:?}: gated rec {} norec {}, ungated rec {} norec {}",
            gated_rec.s_reached, gated_norec.s_reached, free_rec.s_reached, free_norec.s_reached
        );
        eprintln!("{ctx}");
        // Without the gates: monotone, and the same s here.
        assert!(free_rec.s_reached >= free_norec.s_reached, "{ctx}");
        // With them: the same class, less by under one regular waypoint interval.
        assert_eq!(gated_rec.class, gated_norec.class, "{ctx}");
        assert!(gated_rec.levels_gated, "{ctx}");
        let next = interval_end(&rig, &d, gated_rec);
        assert!(
            gated_norec.s_reached < next,
            "{ctx}: beyond the interval end {next}"
        );
    }
}

// ------------------------------------------------------------------------------------------
// The dense reference (`tests/common/dense_reference.rs`).

/// Waypoints of the dense reference: with fewer, consecutive uniform waypoints can be more
/// than `planner.max_joint_step` apart on every branch and the reference stops for spacing,
/// not reachability (at 96 it reaches 1 of 5 sample rays of the seed's lattice, at 192 4, at 384
/// and 768 all 5); at 768 no ray of the seed's 173 where it stops at 384 is reached
/// (`examples/seed_reference.rs`).
const REFERENCE_WAYPOINTS: usize = 384;

/// The search (`planner.search = "exact"`) finds every ray the dense reference finds (roll
/// `fixed`, azimuth 0, the rig's margin 0.1); the ladder's answers are printed (it misses some
/// the reference finds: `docs/RESULTS.md`).
#[test]
fn search_finds_every_ray_the_dense_reference_finds() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let ladder = Planner::new(ladder_rig()).unwrap();
    let mut exact = rig;
    exact.planner.search = SearchMethod::Exact;
    let exact = Planner::new(exact).unwrap();
    let dirs: Vec<Direction> = helixreach::directions::fibonacci(2000, true)
        .unwrap()
        .into_iter()
        .step_by(250)
        .collect();
    let res: Vec<(bool, bool, bool)> = dirs
        .par_iter()
        .map(|d| {
            let r = reference_reaches(&exact, d, REFERENCE_WAYPOINTS, 0.05);
            let testable = |p: &Planner| {
                p.plan_ray(d, s_star(d), 0.0, RollMode::Fixed, false)
                    .unwrap()
                    .class
                    == ReachClass::Testable
            };
            (r, testable(&exact), testable(&ladder))
        })
        .collect();
    let count = |f: fn(&(bool, bool, bool)) -> bool| res.iter().filter(|r| f(r)).count();
    let (n_ref, n_exact, n_ladder) = (count(|r| r.0), count(|r| r.1), count(|r| r.2));
    eprintln!(
        "dense reference: {n_ref} of {} rays; search: {n_exact}; ladder: {n_ladder}",
        dirs.len()
    );
    for (d, (r, e, l)) in dirs.iter().zip(&res) {
        eprintln!("{d:?}: reference {r}, search {e}, ladder {l}");
        assert!(
            !r || *e,
            "{d:?}: the reference reaches it, the search does not"
        );
    }
    assert!(
        n_ref > 0,
        "the reference found no ray: the comparison says nothing"
    );
}
