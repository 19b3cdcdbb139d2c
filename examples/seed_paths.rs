//! Path quality on the seed's directions, side by side with the seed's own trajectories:
//! each of the 58 runs in the seed's `trajectories.csv` (`tests/data/seed/`) is planned with its
//! own clamp, roll `fixed`, at margin 0 (as the seed drove) and 0.1, and its load + hold + unload
//! trajectory is compared with the executed one (out and back) on
//!
//! - the largest joint step between consecutive rows (rad),
//! - the number of steps over 0.2 rad,
//! - the joint-space path length Σ‖Δq‖₂ (rad).
//!
//! Prints a Markdown table of the totals and writes one CSV row per run to `--out`
//! (default `seed_paths.csv`).
//!
//! `--roll motor` plans in roll mode `motor` (default `fixed`, as the seed drove), `--azimuths N` tries
//! N azimuths per ray ([`Planner::plan_best`]; default 1, azimuth 0).
//!
//! Run: `cargo run --release --example seed_paths -- [--rig RIG] [--margin M] [--roll fixed|motor]
//! [--azimuths N] [--out FILE]`

#[path = "../tests/common/seed.rs"]
mod seed;

use helixreach::directions::Direction;
use helixreach::math::Real;
use helixreach::planning::planner::{Planner, ReachClass, RigOverrides};
use helixreach::planning::rig::{azimuth_grid, Rig, RollMode};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

struct Run {
    file: String,
    dir: Direction,
    clamp: [Real; 3],
}

/// (largest step, steps over 0.2 rad, path length) of a joint path.
type Quality = (Real, usize, Real);

/// One run's CSV row (and testable flag), our quality and the seed's.
type RunResult = anyhow::Result<(String, Quality, Quality)>;

fn quality(rows: &[Vec<Real>]) -> Quality {
    let mut max: Real = 0.0;
    let mut over = 0;
    let mut len = 0.0;
    for w in rows.windows(2) {
        let d: Vec<Real> = w[0].iter().zip(&w[1]).map(|(a, b)| (b - a).abs()).collect();
        let m = d.iter().copied().fold(0.0, Real::max);
        max = max.max(m);
        over += usize::from(m > 0.2);
        len += d.iter().map(|x| x * x).sum::<Real>().sqrt();
    }
    (max, over, len)
}

fn read_runs(dir: &Path) -> anyhow::Result<Vec<Run>> {
    let path = dir.join("trajectories.csv");
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |n: &str| {
        header
            .iter()
            .position(|h| *h == n)
            .ok_or_else(|| anyhow::anyhow!("{}: no column {n}", path.display()))
    };
    let cols = [
        col("dir_kappa")?,
        col("dir_tau")?,
        col("dir_omega")?,
        col("clamp_x")?,
        col("clamp_y")?,
        col("clamp_z")?,
    ];
    let fcol = col("file")?;
    let mut out = Vec::new();
    for (i, l) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        let mut v = [0.0; 6];
        for (k, &c) in cols.iter().enumerate() {
            v[k] = f.get(c).and_then(|x| x.parse().ok()).ok_or_else(|| {
                anyhow::anyhow!("{} line {}: bad field {}", path.display(), i + 2, header[c])
            })?;
        }
        out.push(Run {
            file: f[fcol].to_string(),
            dir: Direction::new(v[0], v[1], v[2])?,
            clamp: [v[3], v[4], v[5]],
        });
    }
    Ok(out)
}

fn read_joints(path: &Path) -> anyhow::Result<Vec<Vec<Real>>> {
    let text =
        std::fs::read_to_string(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .enumerate()
        .map(|(i, l)| {
            l.split_whitespace()
                .map(|x| x.parse::<Real>())
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| anyhow::anyhow!("{} line {}: {e}", path.display(), i + 1))
        })
        .collect()
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let rig_name = arg("--rig").unwrap_or_else(|| "sawyer-seed".into());
    let margins: Vec<Real> = match arg("--margin") {
        Some(m) => vec![m.parse()?],
        None => vec![0.0, 0.1],
    };
    let out = PathBuf::from(arg("--out").unwrap_or_else(|| "seed_paths.csv".into()));
    let roll: RollMode = arg("--roll").unwrap_or_else(|| "fixed".into()).parse()?;
    let n_az: usize = arg("--azimuths").map_or(Ok(1), |x| x.parse())?;
    anyhow::ensure!(n_az >= 1, "--azimuths: must be at least 1, got 0");
    helixreach::limits::check_size("--azimuths", n_az, 64)?;
    let azimuths = azimuth_grid(n_az);
    let seed = seed::unpack(&std::env::temp_dir().join("helixreach-seed-data"));
    let runs = read_runs(&seed)?;
    let rig = Rig::load(&rig_name)?;
    let mut csv = String::from(
        "file,margin,class,s_reached,s_end,reconfigurations,max_step,steps_over_0.2,path_length,\
         seed_max_step,seed_steps_over_0.2,seed_path_length\n",
    );
    println!("| margin | testable | reconfigurations | largest step (ours / seed) | steps > 0.2 rad (ours / seed) | path length, median (ours / seed) |");
    println!("|---|---|---|---|---|---|");
    for &margin in &margins {
        let mut keys: Vec<[i64; 3]> = runs
            .iter()
            .map(|r| r.clamp.map(|x| (x * 1e6).round() as i64))
            .collect();
        keys.sort();
        keys.dedup();
        let planners: BTreeMap<[i64; 3], Planner> = keys
            .into_par_iter()
            .map(|k| {
                let o = RigOverrides {
                    margin: Some(margin),
                    clamp: Some(k.map(|x| x as Real * 1e-6)),
                    ..Default::default()
                };
                Ok((k, Planner::new(o.apply(&rig)?)?))
            })
            .collect::<helixreach::Result<_>>()?;
        let t0 = std::time::Instant::now();
        let rows: Vec<RunResult> = runs
            .par_iter()
            .map(|r| {
                let p = &planners[&r.clamp.map(|x| (x * 1e6).round() as i64)];
                let s = helixreach::boundary::continuum::critical_s(&r.dir, 1e-10)?.s_star;
                let plan = p.plan_best(&r.dir, s, &azimuths, roll, true)?;
                let traj = p.trajectory(&plan)?;
                let q: Vec<Vec<Real>> = traj.points.iter().map(|x| x.q.clone()).collect();
                let ours = quality(&q);
                let theirs = quality(&read_joints(&seed.join("trajectories").join(&r.file))?);
                let row = format!(
                    "{},{margin},{},{},{},{},{},{},{},{},{},{}",
                    r.file,
                    plan.class.as_str(),
                    plan.s_reached,
                    plan.s_end,
                    plan.reconfigurations,
                    ours.0,
                    ours.1,
                    ours.2,
                    theirs.0,
                    theirs.1,
                    theirs.2
                );
                eprintln!("{row}");
                Ok((
                    format!("{row}\n{}", plan.class == ReachClass::Testable),
                    ours,
                    theirs,
                ))
            })
            .collect();
        let wall = t0.elapsed().as_secs_f64();
        let mut testable = 0;
        let mut reconf = 0usize;
        let (mut om, mut oo, mut tm, mut to) = (0.0 as Real, 0, 0.0 as Real, 0);
        let (mut ol, mut tl) = (Vec::new(), Vec::new());
        for r in rows {
            let (text, o, t) = r?;
            let (row, ok) = text.split_once('\n').unwrap_or((&text, "false"));
            testable += usize::from(ok == "true");
            reconf += row
                .split(',')
                .nth(5)
                .and_then(|x| x.parse::<usize>().ok())
                .unwrap_or(0);
            csv.push_str(row);
            csv.push('\n');
            om = om.max(o.0);
            oo += o.1;
            tm = tm.max(t.0);
            to += t.1;
            ol.push(o.2);
            tl.push(t.2);
        }
        let median = |v: &mut Vec<Real>| {
            v.sort_by(|a, b| a.total_cmp(b));
            v[v.len() / 2]
        };
        println!(
            "| {margin} | {testable} / {} | {reconf} | {om:.3} / {tm:.3} | {oo} / {to} | {:.2} / {:.2} |",
            runs.len(),
            median(&mut ol),
            median(&mut tl)
        );
        eprintln!(
            "margin {margin}: planned {} runs in {wall:.1} s wall",
            runs.len()
        );
    }
    helixreach::io::write_atomic(&out, csv.as_bytes())?;
    Ok(())
}
