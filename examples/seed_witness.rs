//! Why does the planner miss a seed direction the real robot drove?
//!
//! For each run of the seed's `trajectories.csv` (the repository's `tests/data/seed/`) (or the runs named on the command
//! line) with its own clamp, roll `fixed`, margin 0:
//!
//! 1. our plan: how far it gets (`s_reached` of `s_end` = s*) and why it stops;
//! 2. the seed's run as a **witness** ([`helixreach::planning::witness`], the classification
//!    `tests/planning_seed.rs` asserts): every loading row projected onto our ray, corrected onto
//!    our pose by one IK track, checked (limits, self / scene / rod collision), and every jump
//!    over the joint-step bound tried as a self-motion walk at the held pose. Reported: the
//!    seed's own farthest s (continuum and 100-edge discrete end frame), the largest correction,
//!    the witness extent and why it ends, the jumps;
//! 3. the ladder started from the witness's first configuration (`Planner::plan_ray_from`: how far
//!    tracked branches get from a given start; the search starts from the whole start set);
//! 4. at our stop s: whether the witness configuration at that s lies on the connected valid
//!    self-motion component of our stopping configuration (a walk at the held pose from ours
//!    passes within half a joint step of it).
//!
//! Run: `cargo run --release --example seed_witness -- [FILE ...] [--all]`

#[path = "../tests/common/seed.rs"]
mod seed;

use helixreach::math::{tol, Real};
use helixreach::planning::planner::{Planner, ReachClass, RigOverrides};
use helixreach::planning::pose_path::PoseMap;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::planning::self_motion::{self, Held, WalkSettings, Q};
use helixreach::planning::witness::{self, SeedRun as Run};
use helixreach::records::clamp_runs::read_seed_runs;
use helixreach::robot::{IkParams, IkSolver, IkTarget, MAX_DOF};
use rayon::prelude::*;

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
        ..Default::default()
    };
    let rig = o.apply(base)?;
    let planner = Planner::new(rig.clone())?;
    let model = planner.model();
    let dof = model.dof();
    let s_star = helixreach::boundary::continuum::critical_s(&run.dir, tol::S_STAR_REL)?.s_star;
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
    // The seed's run as a witness.
    let names: Vec<String> = model.joints().iter().map(|j| j.name.clone()).collect();
    let traj = helixreach::records::trajectory::read_joint_file(
        &seed.join("trajectories").join(&run.file),
        &names,
    )?;
    let tr = witness::witness(&planner, &traj, &run.dir)?;
    let s_rows = &tr.s_rows;
    let i_max = tr.far_row;
    let far100 = tr.s_far_discrete;
    out += &format!(
        "  seed: {} rows, row 0 at s = {:.4}, farthest s = {:.4} (row {i_max}; {far100:.4} on the 100-edge end frame)\n",
        s_rows.len(),
        s_rows[0],
        s_rows[i_max],
    );
    let jumps: Vec<String> = tr
        .jumps
        .iter()
        .map(|j| {
            format!(
                "s={:.3} {:.2}: {}",
                j.s,
                j.step,
                if j.joined {
                    "joined".to_string()
                } else {
                    format!("NOT joined (walks stop: {})", j.walks_stop)
                }
            )
        })
        .collect();
    out += &format!(
        "  witness: {} rows to s = {:.4}, correction ≤ {:.4} rad; a witness to s = {:.4}, then {:?}\n  witness jumps > {}: {}\n",
        tr.rows.len(),
        tr.rows.last().map_or(0.0, |w| w.0),
        tr.max_correction,
        tr.verdict.extent,
        tr.verdict.end,
        rig.planner.max_joint_step,
        jumps.join("; ")
    );
    let witness = &tr.rows;
    if witness.is_empty() {
        out += "  the witness has no valid row\n";
        return Ok(out);
    }
    let map = PoseMap::new(&rig, 0.0);
    let solver = IkSolver::new(model, IkParams::without_redundancy())?;
    let cm = planner.collision();
    let step = rig.planner.max_joint_step;
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
        let nodes = map.centerline([0.0; 3], rig.planner.rod_capsules)?;
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
        "  the ladder from the witness start: {} at s = {:.3} ({:?}), {} reconfigurations\n",
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
        let nodes = map.centerline(last.waypoint.kto, rig.planner.rod_capsules)?;
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
    let s_star = helixreach::boundary::continuum::critical_s(&run.dir, tol::S_STAR_REL)?.s_star;
    for &d in ds {
        let mut rig = RigOverrides {
            margin: Some(0.0),
            clamp: Some(run.clamp),
            ..Default::default()
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
        let seed = seed::unpack(&std::env::temp_dir().join("helixreach-seed-data"));
        let runs = read_seed_runs(&seed.join("trajectories.csv"))?;
        let base = Rig::load("sawyer-seed")?;
        let rows: Vec<anyhow::Result<String>> =
            runs.par_iter().map(|r| levels(r, &base, &ds)).collect();
        for r in rows {
            println!("{}", r?);
        }
        return Ok(());
    }
    let seed = seed::unpack(&std::env::temp_dir().join("helixreach-seed-data"));
    let runs = read_seed_runs(&seed.join("trajectories.csv"))?;
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
