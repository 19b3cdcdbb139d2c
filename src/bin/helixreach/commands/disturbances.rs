//! `helixreach disturbances`: the seed paper's Fig. 5 study along S̄ = [1,1,1]/√3 (thin glue
//! over [`helixreach::rod::dynamics::study`]). For each factor (ν, E, L_gb/L, speed, jitter)
//! writes `DIR/<factor>.csv` with the s–e curve of every value and `DIR/summary.csv` (the
//! records of [`helixreach::records::disturbances`]); prints the summary as JSON.

use helixreach::math::Real;
use helixreach::records::csv_out;
use helixreach::records::disturbances::{sample_records, DisturbanceSummaryRecord};
use helixreach::rod::dynamics::presets::Preset;
use helixreach::rod::dynamics::study::{run_study, Factor};
use helixreach::rod::dynamics::SimParams;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `helixreach disturbances`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach disturbances --quick --factors nu --out disturbances",
    "> helixreach disturbances --out disturbances"
))]
pub struct Args {
    /// Output directory (created).
    #[arg(long)]
    out: PathBuf,
    /// Coarse and fast (n = 16, Δt = 20 ms): about a minute on one core.
    #[arg(long)]
    quick: bool,
    /// Number of edges (default 30, or 16 with --quick).
    #[arg(long)]
    n_edges: Option<usize>,
    /// Time step at the base speed (s; default 10 ms, or 20 ms with --quick).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<Real>,
    /// Base ray speed ds/dt (1/s).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    speed: Real,
    /// Rod preset (`paper-sim`, the paper's study, or `nitinol`).
    #[arg(long, default_value = "paper-sim")]
    preset: String,
    /// Only these factors (comma-separated names: nu, youngs_modulus, lgb_over_l, speed, jitter).
    #[arg(long, value_delimiter = ',')]
    factors: Option<Vec<String>>,
}

/// Run `helixreach disturbances`.
pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(n) = args.n_edges {
        helixreach::limits::check_size("--n-edges", n, helixreach::limits::MAX_N_EDGES)?;
    }
    let base = SimParams {
        rod: Preset::parse(&args.preset)?.rod(),
        n_edges: args.n_edges.unwrap_or(if args.quick { 16 } else { 30 }),
        dt: args.dt.unwrap_or(if args.quick { 0.02 } else { 0.01 }),
        speed: args.speed,
        s_max: 30.0,
        record_ds: 0.01,
        ..SimParams::default()
    };
    base.validate()?;
    let factors: Vec<Factor> = match &args.factors {
        None => Factor::ALL.to_vec(),
        Some(names) => names
            .iter()
            .map(|n| {
                Factor::ALL
                    .into_iter()
                    .find(|f| f.name() == n)
                    .ok_or_else(|| {
                        helixreach::Error::invalid(
                            "factors",
                            n,
                            "expected nu, youngs_modulus, lgb_over_l, speed or jitter",
                        )
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    let total: usize = factors.iter().map(|f| f.values(&base).len()).sum();
    let bar = indicatif::ProgressBar::new(total as u64);
    bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} runs ({elapsed}, eta {eta})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let started = std::time::Instant::now();
    let par = helixreach::par::Par::from_option(super::global().threads)?;
    let runs = run_study(&base, &factors, par, &|| bar.inc(1))?;
    bar.finish_and_clear();
    std::fs::create_dir_all(&args.out).map_err(|source| helixreach::Error::Io {
        path: args.out.clone(),
        source,
    })?;
    let base_s = runs
        .iter()
        .find(|r| r.factor == Factor::Jitter && r.value == 0.0)
        .or_else(|| {
            runs.iter()
                .find(|r| r.factor == Factor::Nu && r.value == base.rod.nu)
        })
        .and_then(|r| r.sim.as_ref().ok())
        .map(|s| s.s_dyn());
    let mut summary = Vec::new();
    let mut json_rows = Vec::new();
    for f in &factors {
        let runs_f: Vec<_> = runs.iter().filter(|r| r.factor == *f).collect();
        let csv = csv_out::to_csv(&sample_records(runs_f.iter().copied()))?;
        helixreach::io::write_atomic(&args.out.join(format!("{}.csv", f.name())), csv.as_bytes())?;
        for r in runs_f {
            let m = DisturbanceSummaryRecord::new(r, base_s);
            json_rows.push(serde_json::json!({
                "factor": m.factor, "value": finite(m.value),
                "s_dyn": m.s_dyn,
                "s_cross": m.s_cross,
                "error": r.sim.as_ref().err(),
                "shift_rel": m.shift_rel,
            }));
            summary.push(m);
        }
    }
    helixreach::io::write_atomic(
        &args.out.join("summary.csv"),
        csv_out::to_csv(&summary)?.as_bytes(),
    )?;
    let json = serde_json::json!({
        "direction": [1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()],
        "preset": args.preset,
        "n_edges": base.n_edges, "dt": base.dt, "base_speed": base.speed,
        "speed_convention": "ray speed ds/dt (1/s)",
        "base_s_dyn": base_s.and_then(finite),
        "runs": json_rows,
        "wall_time_s": started.elapsed().as_secs_f64(),
    });
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    serde_json::to_writer_pretty(&mut out, &json)?;
    writeln!(out)?;
    out.flush()?;
    Ok(())
}

fn finite(x: Real) -> Option<Real> {
    x.is_finite().then_some(x)
}
