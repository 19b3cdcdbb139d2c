//! The seed's direction set against the dense reference: for each direction of the
//! quarter-sphere Fibonacci lattice (173 directions: the seed's set), margin 0, roll `fixed`,
//! azimuth 0, the dense reference (`tests/common/dense_reference.rs`: fresh IK on a j0 grid at
//! uniform waypoints, bisection self-motion closure), the search (`planner.search = "exact"`)
//! and the ladder, each with its thread CPU. One thread; each ray's s* from the continuum test.
//!
//! ```text
//! cargo run --release --example seed_reference -- [--directions 173] [--every 1] [--only k]
//!     [--n-wp 384] [--grid 0.05] [--no-reference] [--csv out.csv]
//! cargo run --release --example seed_reference -- --doubling [--every 8] [--n-wp 384]
//! cargo run --release --example seed_reference -- --seed-runs [--step rad] [--max-nodes N] [--csv out.csv]
//! ```
//! Default: one CSV row per direction (`--csv`, else stdout), the counts on stderr; where the
//! reference stops, it is run again at twice the waypoints (`ref2_*`).
//! `--doubling`: the reference at `n_wp` and `2·n_wp` waypoints on the sample (the waypoint
//! count is adequate when doubling it changes no answer).
//! `--seed-runs`: the seed's 58 executed runs, each at its own clamp, margin 0: the search and
//! the ladder in roll `fixed` and `motor`; for each run the search does not find testable, the
//! seed's own trajectory as a witness ([`helixreach::planning::witness`]).

#[path = "../tests/common/dense_reference.rs"]
mod dense_reference;
#[path = "../tests/common/seed.rs"]
mod seed;

use dense_reference::{reference_reach, s_star};
use helixreach::directions::{fibonacci, Direction};
use helixreach::math::Real;
use helixreach::planning::planner::{Planner, RayPlan, ReachClass, RigOverrides};
use helixreach::planning::rig::{Rig, RollMode, SearchMethod};
use helixreach::planning::witness::{self, SeedRun, WitnessEnd};
use helixreach::records::clamp_runs::read_seed_runs;
use helixreach::records::trajectory::read_joint_file;

fn cpu() -> f64 {
    helixreach::cpu_time::thread_cpu_seconds().expect("thread CPU clock")
}

/// `f`'s value and its thread CPU seconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let c0 = cpu();
    let v = f();
    (v, cpu() - c0)
}

/// The kind of a witness's end (the CSV field).
fn end_tag(e: &WitnessEnd) -> &'static str {
    match e {
        WitnessEnd::Target => "target",
        WitnessEnd::Short => "short",
        WitnessEnd::Invalid(_) => "invalid",
        WitnessEnd::Disjoint { .. } => "disjoint",
    }
}

fn cause(p: &RayPlan) -> String {
    p.cause.map_or(String::new(), |c| format!("{c:?}"))
}

/// The ladder and the search planners on `rig`.
fn planners(rig: &Rig) -> helixreach::Result<(Planner, Planner)> {
    let mut exact = rig.clone();
    exact.planner.search = SearchMethod::Exact;
    let mut ladder = rig.clone();
    ladder.planner.search = SearchMethod::Ladder;
    Ok((Planner::new(exact)?, Planner::new(ladder)?))
}

struct Args(Vec<String>);

impl Args {
    fn get<T: std::str::FromStr>(&self, k: &str, default: T) -> T {
        self.0
            .iter()
            .position(|a| a == k)
            .and_then(|i| self.0.get(i + 1))
            .map_or(default, |v| {
                v.parse().unwrap_or_else(|_| panic!("{k}: bad value {v}"))
            })
    }
    fn has(&self, k: &str) -> bool {
        self.0.iter().any(|a| a == k)
    }
}

fn main() -> helixreach::Result<()> {
    let args = Args(std::env::args().skip(1).collect());
    let mut rig = Rig::load("sawyer-seed")?;
    rig.planner.margin = 0.0;
    rig.planner.search_step = args.get("--step", rig.planner.search_step);
    rig.planner.max_search_nodes = args.get("--max-nodes", rig.planner.max_search_nodes);
    if args.has("--seed-runs") {
        return seed_runs(&args, &rig);
    }
    let n: usize = args.get("--directions", 173);
    let every: usize = args.get("--every", 1);
    let only: Option<usize> = args.get("--only", usize::MAX).into();
    let only = only.filter(|&k| k != usize::MAX);
    let n_wp: usize = args.get("--n-wp", 384);
    let grid: Real = args.get("--grid", 0.05);
    let lattice = fibonacci(n, true)?;
    let picked: Vec<(usize, Direction)> = lattice
        .into_iter()
        .enumerate()
        .step_by(every.max(1))
        .filter(|(k, _)| only.is_none_or(|o| o == *k))
        .collect();
    let (exact, ladder) = planners(&rig)?;
    if args.has("--doubling") {
        return doubling(&ladder, &picked, n_wp, grid);
    }
    // Start sets are shared by every ray (computed once per planner): warm them.
    let warm = &picked[0].1;
    let _ = exact.plan_ray(warm, 1.0, 0.0, RollMode::Fixed, false)?;
    let _ = ladder.plan_ray(warm, 1.0, 0.0, RollMode::Fixed, false)?;
    let with_ref = !args.has("--no-reference");
    let mut rows = String::from(
        "index,kappa,tau,omega,s_star,ref_reaches,ref_s,ref_cpu,ref2_reaches,ref2_s,search_class,search_s,\
         search_cause,search_nodes,search_cpu,ladder_class,ladder_s,ladder_cause,ladder_cpu\n",
    );
    let mut counts = [0usize; 3];
    let mut gaps = Vec::new();
    for (k, d) in &picked {
        let s = s_star(d);
        let (r, t_r) = if with_ref {
            let (r, t) = timed(|| reference_reach(&ladder, d, n_wp, grid));
            (Some(r), t)
        } else {
            (None, 0.0)
        };
        // Where the reference stops, the same at twice the waypoints (a stop for spacing, not
        // reachability, would pass there).
        let r2 = r
            .as_ref()
            .filter(|r| !r.reaches())
            .map(|_| reference_reach(&ladder, d, 2 * n_wp, grid));
        let (e, t_e) = timed(|| exact.plan_ray(d, s, 0.0, RollMode::Fixed, false));
        let e = e?;
        let (l, t_l) = timed(|| ladder.plan_ray(d, s, 0.0, RollMode::Fixed, false));
        let l = l?;
        let r_ok = r.as_ref().is_some_and(|r| r.reaches());
        counts[0] += r_ok as usize;
        counts[1] += (e.class == ReachClass::Testable) as usize;
        counts[2] += (l.class == ReachClass::Testable) as usize;
        if r_ok && e.class != ReachClass::Testable {
            gaps.push(*k);
        }
        eprintln!(
            "{k} ({:.4},{:.4},{:.4}) s*={s:.4}: reference {} (s {:.4}, {t_r:.2} s){}; search {} \
             s={:.4} {} ({} nodes, {t_e:.4} s); ladder {} s={:.4} {} ({t_l:.4} s)",
            d.kappa,
            d.tau,
            d.omega,
            r.as_ref().map_or("-".into(), |r| r.reaches().to_string()),
            r.as_ref().map_or(Real::NAN, |r| r.s_reached()),
            r2.as_ref().map_or(String::new(), |r| format!(
                ", at {} waypoints {} (s {:.4})",
                r.n_wp,
                r.reaches(),
                r.s_reached()
            )),
            e.class.as_str(),
            e.s_reached,
            cause(&e),
            e.search_nodes,
            l.class.as_str(),
            l.s_reached,
            cause(&l),
        );
        rows += &format!(
            "{k},{},{},{},{s},{},{},{t_r:.6},{},{},{},{},{},{},{t_e:.6},{},{},{},{t_l:.6}\n",
            d.kappa,
            d.tau,
            d.omega,
            r.as_ref()
                .map_or(String::new(), |r| r.reaches().to_string()),
            r.as_ref()
                .map_or(String::new(), |r| r.s_reached().to_string()),
            r2.as_ref()
                .map_or(String::new(), |r| r.reaches().to_string()),
            r2.as_ref()
                .map_or(String::new(), |r| r.s_reached().to_string()),
            e.class.as_str(),
            e.s_reached,
            cause(&e),
            e.search_nodes,
            l.class.as_str(),
            l.s_reached,
            cause(&l),
        );
    }
    match args.0.iter().position(|a| a == "--csv") {
        Some(i) => std::fs::write(&args.0[i + 1], rows).expect("write --csv"),
        None => print!("{rows}"),
    }
    eprintln!(
        "{} directions of {n} (quarter-sphere, every {every}), margin 0, roll fixed, azimuth 0: \
         testable: reference {} (n_wp {n_wp}, grid {grid}), search {}, ladder {}; reference \
         reaches and search does not: {gaps:?}",
        picked.len(),
        if with_ref {
            counts[0].to_string()
        } else {
            "-".into()
        },
        counts[1],
        counts[2]
    );
    Ok(())
}

/// The reference at `n_wp` and `2·n_wp` waypoints per direction.
fn doubling(
    planner: &Planner,
    picked: &[(usize, Direction)],
    n_wp: usize,
    grid: Real,
) -> helixreach::Result<()> {
    let mut changed = Vec::new();
    for (k, d) in picked {
        let (a, ta) = timed(|| reference_reach(planner, d, n_wp, grid));
        let (b, tb) = timed(|| reference_reach(planner, d, 2 * n_wp, grid));
        eprintln!(
            "{k}: n_wp {n_wp}: {} (s {:.4}, {ta:.2} s); n_wp {}: {} (s {:.4}, {tb:.2} s)",
            a.reaches(),
            a.s_reached(),
            2 * n_wp,
            b.reaches(),
            b.s_reached(),
        );
        if a.reaches() != b.reaches() {
            changed.push(*k);
        }
    }
    eprintln!(
        "{} directions: doubling n_wp {n_wp} -> {} changes the answer on {changed:?}",
        picked.len(),
        2 * n_wp
    );
    Ok(())
}

/// The seed's 58 runs at their own clamps (margin 0): search and ladder, roll `fixed` and
/// `motor`, and the witness of each run the search misses.
fn seed_runs(args: &Args, base: &Rig) -> helixreach::Result<()> {
    let dir = seed::unpack(&std::env::temp_dir().join("helixreach-seed-data"));
    let runs: Vec<SeedRun> = read_seed_runs(&dir.join("trajectories.csv"))?;
    let mut rows = String::from(
        "file,kappa,tau,omega,s_star,search_fixed,search_fixed_s,search_motor,search_motor_s,\
         ladder_fixed,ladder_fixed_s,ladder_motor,ladder_motor_s,witness_extent,witness_end,\
         search_cpu_fixed,search_cpu_motor\n",
    );
    let mut counts = [0usize; 4];
    // One pair of planners per distinct clamp (their start sets are computed once).
    let mut by_clamp: Vec<([Real; 3], (Planner, Planner))> = Vec::new();
    for r in &runs {
        if !by_clamp.iter().any(|(c, _)| *c == r.clamp) {
            let rig = RigOverrides {
                margin: Some(0.0),
                clamp: Some(r.clamp),
                ..Default::default()
            }
            .apply(base)?;
            by_clamp.push((r.clamp, planners(&rig)?));
        }
        let (exact, ladder) = &by_clamp.iter().find(|(c, _)| *c == r.clamp).unwrap().1;
        let s = s_star(&r.dir);
        let plan = |p: &Planner, roll| timed(|| p.plan_ray(&r.dir, s, 0.0, roll, false));
        let (ef, tef) = plan(exact, RollMode::Fixed);
        let (em, tem) = plan(exact, RollMode::Motor);
        let (lf, _) = plan(ladder, RollMode::Fixed);
        let (lm, _) = plan(ladder, RollMode::Motor);
        let (ef, em, lf, lm) = (ef?, em?, lf?, lm?);
        for (i, p) in [&ef, &em, &lf, &lm].iter().enumerate() {
            counts[i] += (p.class == ReachClass::Testable) as usize;
        }
        let miss = [&ef, &em, &lf, &lm]
            .iter()
            .any(|p| p.class != ReachClass::Testable);
        let w = if miss {
            let names: Vec<String> = exact
                .model()
                .joints()
                .iter()
                .map(|j| j.name.clone())
                .collect();
            let traj = read_joint_file(&dir.join("trajectories").join(&r.file), &names)?;
            Some(witness::witness(exact, &traj, &r.dir)?.verdict)
        } else {
            None
        };
        let show = |p: &RayPlan| format!("{} s={:.4} {}", p.class.as_str(), p.s_reached, cause(p));
        eprintln!(
            "{} s*={s:.4}: search fixed {} ({tef:.2} s), motor {} ({tem:.2} s); ladder fixed {}, \
             motor {}{}",
            r.file,
            show(&ef),
            show(&em),
            show(&lf),
            show(&lm),
            w.as_ref().map_or(String::new(), |w| format!(
                "; the seed's run is a witness to s = {:.4}, then {:?}",
                w.extent, w.end
            ))
        );
        rows += &format!(
            "{},{},{},{},{s},{},{},{},{},{},{},{},{},{},{},{tef:.6},{tem:.6}\n",
            r.file,
            r.dir.kappa,
            r.dir.tau,
            r.dir.omega,
            ef.class.as_str(),
            ef.s_reached,
            em.class.as_str(),
            em.s_reached,
            lf.class.as_str(),
            lf.s_reached,
            lm.class.as_str(),
            lm.s_reached,
            w.as_ref().map_or(String::new(), |w| w.extent.to_string()),
            w.as_ref().map_or("", |w| end_tag(&w.end)),
        );
    }
    match args.0.iter().position(|a| a == "--csv") {
        Some(i) => std::fs::write(&args.0[i + 1], rows).expect("write --csv"),
        None => print!("{rows}"),
    }
    eprintln!(
        "the seed's {} runs at their own clamps, margin 0, azimuth 0: testable: search fixed {} \
         / motor {}; ladder fixed {} / motor {}",
        runs.len(),
        counts[0],
        counts[1],
        counts[2],
        counts[3]
    );
    Ok(())
}
