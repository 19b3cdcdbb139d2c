//! Report command of the ray decision: the search of the valid set (`planner.search = "exact"`,
//! [`helixreach::planning::search`]) against the ladder planner (the peer) on the same rays in
//! the same run: per-ray thread CPU (median, p99, total), classes and the rays where they
//! differ. One thread; each ray's s* from the continuum test.
//!
//! ```text
//! cargo run --release --example search_report -- [--rig sawyer-seed] [--directions 200] [--full]
//!     [--roll fixed|motor]
//!     [--margin 0.1] [--every 1] [--only k] [--step rad] [--no-peer] [--no-backoff]
//!     [--no-reconfiguration] [--azimuths N] [--max-nodes N] [--csv out.csv]
//! ```
//! `--rig`: an embedded rig or a rig file (`helixreach rig init` writes one for any arm);
//! `--no-backoff`, `--no-reconfiguration`: the rig's `planner.allow_backoff` and
//! `planner.allow_reconfiguration` off; `--azimuths N`: each ray planned at N azimuths (the
//! best kept, [`Planner::plan_best`]) instead of azimuth 0.
//! `--full`: the whole sphere's Fibonacci lattice instead of the quarter-sphere; `--every k`:
//! every k-th direction of the lattice; `--only k`: the k-th of those only; `--step`: the rig's `planner.search_step`;
//! `--max-nodes`: its `planner.max_search_nodes` (a ray needing more is `undecided`); 1,000,000
//! here unless given (the seed rig's bound, 50,000, leaves large roll `motor` pieces undecided).
use helixreach::directions::{fibonacci, Direction};
use helixreach::planning::planner::{Planner, RayPlan, ReachClass};
use helixreach::planning::rig::{azimuth_grid, Rig, RollMode, SearchMethod};

fn cpu() -> f64 {
    helixreach::cpu_time::thread_cpu_seconds().expect("thread CPU clock")
}

fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[((q * s.len() as f64).ceil() as usize).clamp(1, s.len()) - 1]
}

fn main() -> helixreach::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |k: &str| {
        args.iter()
            .position(|a| a == k)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let has = |k: &str| args.iter().any(|a| a == k);
    let n: usize = get("--directions").map_or(200, |v| v.parse().expect("--directions"));
    let every: usize = get("--every").map_or(1, |v| v.parse().expect("--every"));
    let margin: f64 = get("--margin").map_or(0.1, |v| v.parse().expect("--margin"));
    let roll: RollMode = get("--roll").map_or(Ok(RollMode::Fixed), |v| v.parse())?;
    let dirs: Vec<Direction> = fibonacci(n, !has("--full"))?
        .into_iter()
        .step_by(every.max(1))
        .enumerate()
        .filter(|(k, _)| get("--only").is_none_or(|o| o.parse() == Ok(*k)))
        .map(|(_, d)| d)
        .collect();
    let mut rig = Rig::load(get("--rig").as_deref().unwrap_or("sawyer-seed"))?;
    rig.planner.margin = margin;
    rig.planner.allow_backoff = !has("--no-backoff");
    if has("--no-reconfiguration") {
        rig.planner.allow_reconfiguration = false;
    }
    let azimuths = azimuth_grid(get("--azimuths").map_or(1, |v| v.parse().expect("--azimuths")));
    if let Some(v) = get("--step") {
        rig.planner.search_step = v.parse().expect("--step");
    }
    rig.planner.max_search_nodes =
        get("--max-nodes").map_or(1_000_000, |v| v.parse().expect("--max-nodes"));
    let mut exact_rig = rig.clone();
    exact_rig.planner.search = SearchMethod::Exact;
    let exact = Planner::new(exact_rig)?;
    rig.planner.search = SearchMethod::Ladder;
    let ladder = Planner::new(rig)?;
    // Start sets are shared by every ray (computed once per planner): warm them.
    let warm = &dirs[0];
    let _ = exact.plan_ray(warm, 1.0, 0.0, roll, false)?;
    let _ = ladder.plan_ray(warm, 1.0, 0.0, roll, false)?;
    let peer = !has("--no-peer");
    let mut rows = String::from(
        "kappa,tau,omega,s_star,exact_class,exact_s,exact_cpu,nodes,backoffs,ladder_class,ladder_s,ladder_cpu\n",
    );
    let (mut te, mut tl) = (Vec::new(), Vec::new());
    let (mut ce, mut cl) = ([0usize; 4], [0usize; 4]);
    let idx = |c: ReachClass| match c {
        ReachClass::Testable => 0,
        ReachClass::Partial => 1,
        ReachClass::Blocked => 2,
        ReachClass::Undecided => 3,
    };
    for (k, d) in dirs.iter().enumerate() {
        let s_star = helixreach::boundary::continuum::critical_s(d, 1e-10)?.s_star;
        let c0 = cpu();
        let e = exact.plan_best(d, s_star, &azimuths, roll, false)?;
        let t_e = cpu() - c0;
        te.push(t_e);
        ce[idx(e.class)] += 1;
        let (l, t_l): (Option<RayPlan>, f64) = if peer {
            let c0 = cpu();
            let l = ladder.plan_best(d, s_star, &azimuths, roll, false)?;
            let t = cpu() - c0;
            tl.push(t);
            cl[idx(l.class)] += 1;
            (Some(l), t)
        } else {
            (None, 0.0)
        };
        if let Some(l) = &l {
            if l.class != e.class {
                eprintln!(
                    "ray {k} {:.4},{:.4},{:.4}: exact {} s={:.4} ({} nodes), ladder {} s={:.4}",
                    d.kappa,
                    d.tau,
                    d.omega,
                    e.class.as_str(),
                    e.s_reached,
                    e.search_nodes,
                    l.class.as_str(),
                    l.s_reached
                );
            }
        }
        rows += &format!(
            "{},{},{},{},{},{},{:.6},{},{},{},{},{:.6}\n",
            d.kappa,
            d.tau,
            d.omega,
            s_star,
            e.class.as_str(),
            e.s_reached,
            t_e,
            e.search_nodes,
            e.backoffs,
            l.as_ref().map_or("", |l| l.class.as_str()),
            l.as_ref().map_or(f64::NAN, |l| l.s_reached),
            t_l
        );
    }
    if let Some(p) = get("--csv") {
        std::fs::write(&p, rows).expect("write --csv");
    }
    let report = |name: &str, t: &[f64], c: &[usize; 4]| {
        if t.is_empty() {
            return;
        }
        println!(
            "{name}: {} rays, testable {} partial {} blocked {} undecided {}; CPU median {:.1} ms, p99 {:.1} ms, max {:.1} ms, total {:.2} s",
            t.len(),
            c[0],
            c[1],
            c[2],
            c[3],
            1e3 * quantile(t, 0.5),
            1e3 * quantile(t, 0.99),
            1e3 * quantile(t, 1.0),
            t.iter().sum::<f64>()
        );
    };
    println!(
        "{} directions ({}), roll {roll}, margin {margin}, azimuths {:?}, back-off {}, reconfiguration {}",
        dirs.len(),
        if has("--full") {
            "sphere"
        } else {
            "quarter-sphere"
        },
        azimuths,
        exact.rig().planner.allow_backoff,
        exact.rig().planner.allow_reconfiguration
    );
    report("exact", &te, &ce);
    report("ladder", &tl, &cl);
    Ok(())
}
