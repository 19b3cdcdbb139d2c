//! Why does the planner miss a seed direction the real robot drove? (issue 10)
//!
//! For each run of `../shared/seed-data/trajectories.csv` (or the runs named on the command
//! line) with its own clamp, roll `fixed`, margin 0:
//!
//! 1. our plan: how far it gets (`s_reached` of `s_end` = s*) and why it stops;
//! 2. the seed's run as a **witness**: every loading row projected onto our ray (its s), then
//!    corrected onto our pose at that s by one IK track from the seed's joints (the seed held
//!    the last-edge frame of a 100-edge discrete helix, ≈ 3 mm / 2 mrad from our continuum end
//!    frame). Reported: the seed's own farthest s, the largest correction, the first witness row
//!    that is invalid in our model (limits, self / scene / rod collision), the witness path's
//!    joint steps over the bound (its jumps, with their s);
//! 3. our planner started from the witness's first configuration (`Planner::plan_ray_from`);
//! 4. at our stop s: whether the witness configuration at that s lies on the connected valid
//!    self-motion component of our stopping configuration (a walk at the held pose from ours
//!    passes within half a joint step of it).
//!
//! Run: `cargo run --release --example seed_witness -- [FILE ...] [--all]`

use helixreach::directions::Direction;
use helixreach::helix::{discrete, Helix};
use helixreach::math::{rot_z, Real, Vec3};
use helixreach::planning::check::{CheckOptions, Checker};
use helixreach::planning::planner::{Planner, ReachClass, RigOverrides};
use helixreach::planning::pose_path::PoseMap;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::planning::self_motion::{self, Held, WalkSettings, Q};
use helixreach::robot::{CollisionModel, IkParams, IkSolver, IkTarget, MAX_DOF};
use rayon::prelude::*;
use std::path::PathBuf;

struct Run {
    file: String,
    dir: Direction,
    clamp: [Real; 3],
}

fn read_runs(dir: &std::path::Path) -> anyhow::Result<Vec<Run>> {
    let path = dir.join("trajectories.csv");
    let text = std::fs::read_to_string(&path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let cols = [
        col("dir_kappa"),
        col("dir_tau"),
        col("dir_omega"),
        col("clamp_x"),
        col("clamp_y"),
        col("clamp_z"),
    ];
    let fcol = col("file");
    let mut out = Vec::new();
    for l in lines.filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        let v: Vec<Real> = cols.iter().map(|&c| f[c].parse().unwrap()).collect();
        out.push(Run {
            file: f[fcol].to_string(),
            dir: Direction::new(v[0], v[1], v[2])?,
            clamp: [v[3], v[4], v[5]],
        });
    }
    Ok(out)
}

/// The rod of helix `kto` in the base frame (as the planner models it).
fn rod_nodes(rig: &Rig, kto: [Real; 3]) -> Vec<Vec3> {
    let h = Helix::new(kto[0], kto[1], kto[2]).unwrap();
    let rc = rig.clamp_rotation() * rot_z(0.0);
    let oc = rig.clamp.translation.vector;
    discrete::nodes(&h, rig.planner.rod_capsules)
        .into_iter()
        .map(|x| oc + rc * (x * rig.rod.length))
        .collect()
}

fn max_diff(a: &[Real], b: &[Real]) -> Real {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, Real::max)
}

fn diagnose(run: &Run, seed: &std::path::Path, base: &Rig) -> anyhow::Result<String> {
    let o = RigOverrides {
        margin: Some(0.0),
        clamp: Some(run.clamp),
        allow_reconfiguration: None,
    };
    let rig = o.apply(base)?;
    let planner = Planner::new(rig.clone())?;
    let model = planner.model();
    let dof = model.dof();
    let s_star = helixreach::boundary::continuum::critical_s(&run.dir, 1e-10)?.s_star;
    let plan = planner.plan_ray(&run.dir, s_star, 0.0, RollMode::Fixed, true)?;
    let mut out = format!(
        "== {}  dir ({:.4}, {:.4}, {:.4})  clamp {:?}\n  ours: {} at s = {:.3} of {:.3} ({:?}), {} reconfigurations\n",
        run.file,
        run.dir.kappa,
        run.dir.tau,
        run.dir.omega,
        run.clamp,
        plan.class.as_str(),
        plan.s_reached,
        plan.s_end,
        plan.cause,
        plan.reconfigurations
    );
    // The seed's rows and their s.
    let checker = Checker::new(rig.clone())?;
    let traj = checker.read(&seed.join("trajectories").join(&run.file))?;
    let opt = CheckOptions {
        direction: Some(run.dir),
        ..CheckOptions::default()
    };
    let rep = checker.check(&traj, &opt)?;
    let s_rows: Vec<Real> = rep.row_checks.iter().map(|r| r.s.unwrap()).collect();
    let rep100 = checker.check(
        &traj,
        &CheckOptions {
            held_edges: helixreach::planning::check::SEED_HELD_EDGES,
            ..opt
        },
    )?;
    let far100 = rep100.s_max_reached.unwrap();
    let i_max = (0..s_rows.len())
        .max_by(|&a, &b| s_rows[a].total_cmp(&s_rows[b]))
        .unwrap();
    out += &format!(
        "  seed: {} rows, row 0 at s = {:.4}, farthest s = {:.4} (row {i_max}), pose error ≤ {:.2e} m / {:.2e} rad, {} collisions, {} limit violations\n",
        rep.rows,
        s_rows[0],
        s_rows[i_max],
        rep.max_position_error.unwrap().0,
        rep.max_rotation_error.unwrap().0,
        rep.collisions,
        rep.limit_violations
    );
    // Witness: loading rows corrected onto our pose.
    let map = PoseMap::new(&rig, 0.0);
    let solver = IkSolver::new(
        model,
        IkParams {
            redundancy_joint: None,
            ..IkParams::default()
        },
    )?;
    let mut cm = CollisionModel::for_model(model)?;
    cm.set_obstacles(&rig.obstacles)?;
    let mut ws = cm.workspace();
    let (lo, hi) = (model.lower(), model.upper());
    let step = rig.planner.max_joint_step;
    let mut witness: Vec<(Real, Vec<Real>)> = Vec::new();
    let mut worst_corr: Real = 0.0;
    let mut first_bad: Option<String> = None;
    for i in 0..=i_max {
        // The run starts at the straight rod.
        let s = if i == 0 { 0.0 } else { s_rows[i].min(s_star) };
        let d = &run.dir;
        let kto = [s * d.kappa, s * d.tau, s * d.omega];
        let (tool, _) = map.end(kto)?;
        let tip = planner.tip_target(&tool);
        let Some(sol) = solver.track(&IkTarget::Pose(tip), traj.row(i), None) else {
            first_bad.get_or_insert(format!("row {i} s={s:.3}: IK correction failed"));
            continue;
        };
        let q = sol.joints().to_vec();
        worst_corr = worst_corr.max(max_diff(&q, traj.row(i)));
        let nodes = rod_nodes(&rig, kto);
        let rod = rig.rod_geometry(&nodes);
        if let Some(c) = cm.check(&q, &mut ws, Some(&rod)) {
            first_bad.get_or_insert(format!(
                "row {i} s={s:.3}: {}|{}",
                cm.name(c.a),
                cm.name(c.b)
            ));
        }
        if (0..dof).any(|j| q[j] < lo[j] || q[j] > hi[j]) {
            first_bad.get_or_insert(format!("row {i} s={s:.3}: limit"));
        }
        witness.push((s, q));
        if s >= s_star {
            break;
        }
    }
    let jumps: Vec<String> = witness
        .windows(2)
        .filter_map(|w| {
            let d = max_diff(&w[0].1, &w[1].1);
            (d > step).then(|| format!("s={:.3}:{d:.3}", w[1].0))
        })
        .collect();
    out += &format!(
        "  witness: {} rows to s = {:.4}, correction ≤ {worst_corr:.4} rad, first invalid: {}\n  witness steps > {step}: {} [{}]\n",
        witness.len(),
        witness.last().map_or(0.0, |w| w.0),
        first_bad.as_deref().unwrap_or("none"),
        jumps.len(),
        jumps.iter().take(12).cloned().collect::<Vec<_>>().join(" ")
    );
    // Each witness jump over 0.1 rad: can the two configurations be joined by a self-motion
    // walk at the later row's held pose (same connected valid component)?
    let track_solver = IkSolver::new(model, IkParams::default())?;
    let mut jump_report = Vec::new();
    for w in witness.windows(2) {
        let d = max_diff(&w[0].1, &w[1].1);
        if d <= 0.1 {
            continue;
        }
        let (s1, q1) = (&w[1].0, &w[1].1);
        let kto = [s1 * run.dir.kappa, s1 * run.dir.tau, s1 * run.dir.omega];
        let tip = model.chain().tool_pose(q1);
        let Some(a) = solver.track(&IkTarget::Pose(tip), &w[0].1, None) else {
            jump_report.push(format!("s={s1:.3} {d:.2}: no-track"));
            continue;
        };
        let held = Held {
            chain: model.chain(),
            solver: &track_solver,
            tip,
            dof,
        };
        let nodes = rod_nodes(&rig, kto);
        let rod = rig.rod_geometry(&nodes);
        let mut qa: Q = [0.0; MAX_DOF];
        qa[..dof].copy_from_slice(a.joints());
        let mut ws2 = cm.workspace();
        let mut joined = false;
        let mut stops = Vec::new();
        for sign in [1.0, -1.0] {
            let mut stop = String::from("end");
            let (_, hit) = self_motion::walk(
                &held,
                &qa,
                sign,
                &WalkSettings {
                    max_step: 0.02,
                    min_step: 1e-4,
                    joint_step_bound: step,
                    max_samples: 4000,
                },
                |_, b| match cm.check(&b[..dof], &mut ws2, Some(&rod)) {
                    None => (0..dof).all(|j| b[j] >= lo[j] && b[j] <= hi[j]),
                    Some(c) => {
                        stop = format!("{}|{}", cm.name(c.a), cm.name(c.b));
                        false
                    }
                },
                |q| max_diff(&q[..dof], q1) <= 0.5 * step,
            );
            if hit {
                joined = true;
                break;
            }
            stops.push(stop);
        }
        jump_report.push(format!(
            "s={s1:.3} {d:.2}: {}",
            if joined {
                "joined".to_string()
            } else {
                format!("NOT joined (walks stop: {})", stops.join(", "))
            }
        ));
    }
    out += &format!("  witness jumps > 0.1: {}\n", jump_report.join("; "));
    // Start: the nearest of our start configurations to the witness start.
    let starts = planner.start_configurations(RollMode::Fixed);
    let w0 = &witness[0].1;
    let near = starts
        .iter()
        .map(|q| max_diff(q, w0))
        .fold(Real::INFINITY, Real::min);
    out += &format!(
        "  witness start {:?}\n  our {} start configurations: nearest {near:.3} rad max-norm\n",
        w0.iter()
            .map(|x| (x * 1000.0).round() / 1000.0)
            .collect::<Vec<_>>(),
        starts.len()
    );
    {
        let track_solver = IkSolver::new(model, IkParams::default())?;
        let held = Held {
            chain: model.chain(),
            solver: &track_solver,
            tip: model.chain().tool_pose(w0),
            dof,
        };
        let nodes = rod_nodes(&rig, [0.0; 3]);
        let rod = rig.rod_geometry(&nodes);
        let mut q0: Q = [0.0; MAX_DOF];
        q0[..dof].copy_from_slice(w0);
        let mut ws2 = cm.workspace();
        let t0 = std::time::Instant::now();
        let mut counts = Vec::new();
        for sign in [1.0, -1.0] {
            let (samples, _) = self_motion::walk(
                &held,
                &q0,
                sign,
                &WalkSettings {
                    max_step: 0.05,
                    min_step: 1e-4,
                    joint_step_bound: 0.05,
                    max_samples: 4000,
                },
                |_, b| cm.check(&b[..dof], &mut ws2, Some(&rod)).is_none(),
                |_| false,
            );
            let nearest = starts
                .iter()
                .map(|q| {
                    samples
                        .iter()
                        .map(|w| max_diff(&w[..dof], q))
                        .fold(Real::INFINITY, Real::min)
                })
                .fold(Real::INFINITY, Real::min);
            counts.push(format!(
                "{} samples (nearest start {nearest:.3})",
                samples.len()
            ));
        }
        out += &format!(
            "  witness start component at step 0.05: {} in {:.1} ms\n",
            counts.join(" / "),
            t0.elapsed().as_secs_f64() * 1e3
        );
    }
    let from = planner.plan_ray_from(
        &run.dir,
        s_star,
        0.0,
        RollMode::Fixed,
        false,
        std::slice::from_ref(w0),
    )?;
    out += &format!(
        "  ours from the witness start: {} at s = {:.3} ({:?}), {} reconfigurations\n",
        from.class.as_str(),
        from.s_reached,
        from.cause,
        from.reconfigurations
    );
    out += &format!(
        "  SUMMARY {} s*={:.4} seed_far={:.4} seed_far100={:.4} ours={:.4} {} from_witness={:.4} {}\n",
        run.file,
        s_star,
        s_rows[i_max],
        far100,
        plan.s_reached,
        plan.class.as_str(),
        from.s_reached,
        from.class.as_str()
    );
    // At our stop: is the witness on our component?
    if plan.class != ReachClass::Testable {
        let path = plan.path.as_ref().unwrap();
        let last = path.last().unwrap();
        let s = last.waypoint.s;
        let (sw, qw) = witness
            .iter()
            .min_by(|a, b| (a.0 - s).abs().total_cmp(&(b.0 - s).abs()))
            .unwrap();
        let tip = model.chain().tool_pose(&last.q);
        let qw = solver
            .track(&IkTarget::Pose(tip), qw, None)
            .map(|x| x.joints().to_vec());
        let track_solver = IkSolver::new(model, IkParams::default())?;
        let held = Held {
            chain: model.chain(),
            solver: &track_solver,
            tip,
            dof,
        };
        let nodes = rod_nodes(&rig, last.waypoint.kto);
        let rod = rig.rod_geometry(&nodes);
        let settings = WalkSettings {
            max_step: rig.planner.self_motion_step,
            min_step: 1e-4,
            joint_step_bound: step,
            max_samples: 4000,
        };
        let mut q0: Q = [0.0; MAX_DOF];
        q0[..dof].copy_from_slice(&last.q);
        let mut best = Real::INFINITY;
        let mut desc = String::new();
        if let Some(qw) = &qw {
            let mut ws2 = cm.workspace();
            let valid_w = cm.check(qw, &mut ws2, Some(&rod)).is_none();
            for sign in [1.0, -1.0] {
                let mut stop = String::new();
                let (samples, _) = self_motion::walk(
                    &held,
                    &q0,
                    sign,
                    &settings,
                    |_, b| match cm.check(&b[..dof], &mut ws2, Some(&rod)) {
                        None => true,
                        Some(c) => {
                            stop = format!("{}|{}", cm.name(c.a), cm.name(c.b));
                            false
                        }
                    },
                    |_| false,
                );
                let d = samples
                    .iter()
                    .map(|q| max_diff(&q[..dof], qw))
                    .fold(Real::INFINITY, Real::min);
                best = best.min(d);
                desc += &format!(
                    " walk {sign:+}: {} samples, j0 {:.2}..{:.2}, stop [{stop}];",
                    samples.len(),
                    samples.iter().map(|q| q[0]).fold(Real::INFINITY, Real::min),
                    samples
                        .iter()
                        .map(|q| q[0])
                        .fold(Real::NEG_INFINITY, Real::max)
                );
            }
            out += &format!(
                "  at our stop s = {s:.3}: our q {:?}\n    witness (s = {sw:.3}) q {:?} valid {valid_w}; nearest walk sample {best:.3} rad;{desc}\n",
                last.q.iter().map(|x| (x * 1000.0).round() / 1000.0).collect::<Vec<_>>(),
                qw.iter().map(|x| (x * 1000.0).round() / 1000.0).collect::<Vec<_>>(),
            );
        } else {
            out += "  at our stop: the witness does not track onto our pose\n";
        }
    }
    Ok(out)
}

/// `--levels D1,D2,…`: per run, plan with each `dense_samples` and print reach and CPU time.
fn levels(run: &Run, base: &Rig, ds: &[usize]) -> anyhow::Result<String> {
    let mut out = run.file.clone();
    let s_star = helixreach::boundary::continuum::critical_s(&run.dir, 1e-10)?.s_star;
    for &d in ds {
        let mut rig = RigOverrides {
            margin: Some(0.0),
            clamp: Some(run.clamp),
            allow_reconfiguration: None,
        }
        .apply(base)?;
        rig.planner.dense_samples = d;
        let planner = Planner::new(rig)?;
        let _ = planner.start_configurations(RollMode::Fixed);
        let t0 = helixreach::cpu_time::thread_cpu_seconds()?;
        let p = planner.plan_ray(&run.dir, s_star, 0.0, RollMode::Fixed, false)?;
        let t = helixreach::cpu_time::thread_cpu_seconds()? - t0;
        out += &format!(
            ",{d}:{}:{:.3}:{:.2}s",
            if p.class == ReachClass::Testable {
                "T"
            } else {
                "p"
            },
            p.s_reached,
            t
        );
    }
    Ok(out)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--levels") {
        let ds: Vec<usize> = args[i + 1].split(',').map(|x| x.parse().unwrap()).collect();
        let seed = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/seed-data");
        let runs = read_runs(&seed)?;
        let base = Rig::load("sawyer-seed")?;
        let rows: Vec<anyhow::Result<String>> =
            runs.par_iter().map(|r| levels(r, &base, &ds)).collect();
        for r in rows {
            println!("{}", r?);
        }
        return Ok(());
    }
    let seed = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/seed-data");
    let runs = read_runs(&seed)?;
    let base = Rig::load("sawyer-seed")?;
    let pick: Vec<&Run> = if args.iter().any(|a| a == "--all") || args.is_empty() {
        runs.iter().collect()
    } else {
        runs.iter().filter(|r| args.contains(&r.file)).collect()
    };
    let reports: Vec<anyhow::Result<String>> =
        pick.par_iter().map(|r| diagnose(r, &seed, &base)).collect();
    for r in reports {
        print!("{}", r?);
    }
    Ok(())
}
