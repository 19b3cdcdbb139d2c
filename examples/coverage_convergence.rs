//! Coverage versus start-sampling density: does the planner's answer stop changing
//! when the sampling of the start's valid self-motion set is refined?
//!
//! Plans a Fibonacci direction set (quarter-sphere by default) once with the densest level
//! `--max D` (default 128) and records at which level each ray became testable
//! (`RayPlan::start_samples`). The dense levels are nested and the planner keeps the farthest
//! plan over them, so a ray is testable for `dense_samples = k` exactly when it is testable at a
//! level ≤ k: one pass gives the coverage at every k = R (the base rungs alone), 2R, 4R, … ≤ D.
//!
//! `--no-gate` switches the pointwise gate before the dense levels off
//! ([`Planner::set_level_gate`]: every level runs) — run with and without it
//! and compare the per-ray CSVs to see what the gate changes.
//!
//! Writes `coverage_density.csv` (one row per direction, with `levels_gated`), `coverage_density.png` / `.svg` (the
//! curve) into `--out DIR` (default `coverage_density/`) and prints a Markdown table.
//!
//! Run: `cargo run --release --example coverage_convergence -- [--directions N] [--max D]
//! [--roll fixed|motor] [--rig RIG] [--no-gate] [--out DIR]`

use helixreach::directions::fibonacci;
use helixreach::math::Real;
use helixreach::planning::planner::{Planner, ReachClass};
use helixreach::planning::rig::{Rig, RollMode};
use plotters::prelude::*;
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One direction: s reached, class, start samples of the plan, CPU seconds, levels gated.
type Row = (Real, ReachClass, usize, Real, bool);

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let n: usize = arg("--directions").map_or(Ok(2000), |x| x.parse())?;
    let dmax: usize = arg("--max").map_or(Ok(128), |x| x.parse())?;
    let roll: RollMode = arg("--roll").unwrap_or_else(|| "fixed".into()).parse()?;
    let out = PathBuf::from(arg("--out").unwrap_or_else(|| "coverage_density".into()));
    helixreach::limits::check_size("--directions", n, helixreach::limits::MAX_DIRECTIONS)?;
    let mut rig = Rig::load(&arg("--rig").unwrap_or_else(|| "sawyer-seed".into()))?;
    rig.planner.dense_samples = dmax;
    let base = rig.planner.redundancy_samples;
    let mut planner = Planner::new(rig)?;
    planner.set_level_gate(!args.iter().any(|a| a == "--no-gate"));
    let dirs = fibonacci(n, true)?;
    let done = AtomicUsize::new(0);
    let t0 = std::time::Instant::now();
    let rows: Vec<helixreach::Result<Row>> = dirs
        .par_iter()
        .map(|d| {
            let s = helixreach::boundary::continuum::critical_s(d, 1e-10)?.s_star;
            let c0 = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(0.0);
            let p = planner.plan_ray(d, s, 0.0, roll, false)?;
            let cpu = helixreach::cpu_time::thread_cpu_seconds().unwrap_or(0.0) - c0;
            let k = done.fetch_add(1, Ordering::Relaxed) + 1;
            if k % 50 == 0 || k == dirs.len() {
                eprintln!(
                    "{k} / {} directions, {:.0} s wall",
                    dirs.len(),
                    t0.elapsed().as_secs_f64()
                );
            }
            Ok((p.s_reached, p.class, p.start_samples, cpu, p.levels_gated))
        })
        .collect();
    let mut csv =
        String::from("kappa,tau,omega,class,s_reached,start_samples,cpu_s,levels_gated\n");
    let mut plans = Vec::with_capacity(rows.len());
    for (d, r) in dirs.iter().zip(rows) {
        let (s, class, k, cpu, gated) = r?;
        csv += &format!(
            "{},{},{},{},{s},{k},{cpu},{gated}\n",
            d.kappa,
            d.tau,
            d.omega,
            class.as_str()
        );
        plans.push((class, k, cpu));
    }
    let mut levels = vec![base];
    let mut k = 2 * base;
    while k <= dmax {
        levels.push(k);
        k *= 2;
    }
    let cover: Vec<(usize, usize)> = levels
        .iter()
        .map(|&k| {
            (
                k,
                plans
                    .iter()
                    .filter(|(c, s, _)| *c == ReachClass::Testable && *s <= k)
                    .count(),
            )
        })
        .collect();
    let cpu_total: Real = plans.iter().map(|p| p.2).sum();
    println!(
        "| start samples per component | testable ({} directions, roll {roll}) |",
        dirs.len()
    );
    println!("|---|---|");
    for (k, c) in &cover {
        let label = if *k == base {
            format!("{k} (base rungs only)")
        } else {
            k.to_string()
        };
        println!(
            "| {label} | {c} ({:.1} %) |",
            100.0 * *c as f64 / dirs.len() as f64
        );
    }
    eprintln!(
        "planning CPU {cpu_total:.1} s ({:.1} ms per direction), {:.0} s wall",
        1e3 * cpu_total / dirs.len() as f64,
        t0.elapsed().as_secs_f64()
    );
    std::fs::create_dir_all(&out)?;
    helixreach::io::write_atomic(&out.join("coverage_density.csv"), csv.as_bytes())?;
    helixreach::plot::style::init_fonts();
    let total = dirs.len();
    let png = out.join("coverage_density.png");
    draw(
        BitMapBackend::new(&png, (1100, 760)).into_drawing_area(),
        &cover,
        total,
        roll,
    )?;
    let svg = out.join("coverage_density.svg");
    draw(
        SVGBackend::new(&svg, (1100, 760)).into_drawing_area(),
        &cover,
        total,
        roll,
    )?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    cover: &[(usize, usize)],
    total: usize,
    roll: RollMode,
) -> anyhow::Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
    let pct: Vec<(f64, f64)> = cover
        .iter()
        .map(|(k, c)| ((*k as f64).log2(), 100.0 * *c as f64 / total as f64))
        .collect();
    let lo = pct.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let hi = pct.iter().map(|p| p.1).fold(0.0, f64::max);
    let x0 = pct[0].0 - 0.3;
    let x1 = pct[pct.len() - 1].0 + 0.3;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Testable directions vs start sampling ({total} directions, roll {roll})"),
            helixreach::plot::style::text(helixreach::plot::style::TITLE),
        )
        .margin(20)
        .x_label_area_size(70)
        .y_label_area_size(90)
        .build_cartesian_2d(x0..x1, (lo - 5.0).max(0.0)..(hi + 5.0).min(100.0))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("start samples per valid start component (log scale)")
        .y_desc("testable (%)")
        .x_label_formatter(&|x| format!("{:.0}", 2f64.powf(*x)))
        .x_labels(pct.len() + 2)
        .label_style(helixreach::plot::style::text(helixreach::plot::style::TICK))
        .axis_desc_style(helixreach::plot::style::text(helixreach::plot::style::AXIS))
        .draw()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let c = helixreach::plot::style::series(0);
    chart
        .draw_series(LineSeries::new(pct.iter().copied(), c.stroke_width(3)))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    chart
        .draw_series(pct.iter().map(|p| Circle::new(*p, 7, c.filled())))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(())
}
