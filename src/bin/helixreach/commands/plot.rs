//! `helixreach plot KIND --input FILE.csv [--input2 FILE] --out FILE.png|svg`: regenerate a
//! figure from saved CSVs (see `helixreach::plot` for the figures and the columns they read).

use anyhow::{bail, Context};
use helixreach::plot::{self, trajectory::TrajectoryOptions};
use std::path::PathBuf;

/// Figure kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Kind {
    /// Boundary surface in κ-τ-ω (input: boundary CSV).
    Boundary3d,
    /// Equal-area map of directions by class and cause (input: reach CSV; input2: marked
    /// directions CSV with dir_kappa,dir_tau,dir_omega).
    Directions,
    /// The ω = 0 section (input: boundary CSV; input2: reach CSV to highlight what is testable).
    Section,
    /// Helix error e versus s (input: one or more `simulate` series CSVs).
    ErrorVsS,
    /// Speed versus error of boundary methods, log-log (input: method,resolution,
    /// time_per_direction_s,max_rel_err,median_rel_err).
    SpeedError,
    /// Joint and motor angles versus s (input: `plan` trajectory CSV; input2: joint limits CSV
    /// with joint,lower,upper).
    Trajectory,
    /// Bifurcation type over the directions with the hysteresis width (input: `bifurcation`
    /// CSV; input2: labelled directions with dir_kappa,dir_tau,dir_omega,type).
    Bifurcation,
    /// Measured snap points and mirror images on the boundary, views along each axis and the
    /// ω = 0 section (input: boundary CSV; input2: measured CSV, required).
    Comparison,
    /// Snap detection of one recorded run: e versus s, loading and unloading (input: the
    /// per-sample CSV of `detect --out`; input2: its JSON summary, for s*, the snap and the
    /// return).
    Detection,
}

/// Arguments of `helixreach plot`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach boundary --fibonacci 60 --out boundary.csv",
    "$ helixreach plot section --input boundary.csv --out section.png",
    "$ helixreach plot boundary3d --input boundary.csv --out boundary.svg"
))]
pub struct Args {
    /// Which figure.
    #[arg(value_enum)]
    pub kind: Kind,
    /// Input CSV (repeat for several series with `error-vs-s`).
    #[arg(long, required = true)]
    pub input: Vec<PathBuf>,
    /// Second input: marked directions (`directions`), reach CSV (`section`), joint limits
    /// (`trajectory`).
    #[arg(long)]
    pub input2: Option<PathBuf>,
    /// Legend name of the `--input2` directions of `directions`.
    #[arg(long, default_value = "experiment's directions")]
    pub marked_label: String,
    /// Legend labels of the `error-vs-s` series, in `--input` order (default: file stems).
    #[arg(long)]
    pub label: Vec<String>,
    /// Output figure; the format follows the extension (.png or .svg).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing output file (never one of this command's inputs).
    #[arg(long)]
    pub force: bool,
}

/// Run `helixreach plot`.
pub fn run(args: Args) -> anyhow::Result<()> {
    // Check the output before reading inputs: a wrong extension should not wait for a big CSV.
    let mut out = helixreach::io::Output::new(&args.out)
        .force(args.force)
        .binary("a figure");
    for i in args.input.iter().chain(&args.input2) {
        out = out.input(i);
    }
    out.check()?;
    plot::Format::from_path(&args.out)?;
    let multi = args.kind == Kind::ErrorVsS;
    if args.input.len() > 1 && !multi {
        bail!(
            "`plot {:?}` takes one --input (got {}); only error-vs-s takes several",
            args.kind,
            args.input.len()
        );
    }
    if !args.label.is_empty() && (!multi || args.label.len() != args.input.len()) {
        bail!("--label is for error-vs-s, one per --input");
    }
    let input = &args.input[0];
    let what = || format!("plotting {:?} into {}", args.kind, args.out.display());
    match args.kind {
        Kind::Boundary3d => {
            if args.input2.is_some() {
                bail!("boundary3d takes no --input2");
            }
            plot::boundary3d::render(&plot::read_boundary(input)?, &args.out)
        }
        Kind::Directions => {
            let marked = match &args.input2 {
                Some(p) => helixreach::directions::read_csv(p)?,
                None => Vec::new(),
            };
            plot::direction_map::render(
                &plot::read_reach(input)?,
                &marked,
                &args.marked_label,
                &args.out,
            )
        }
        Kind::Section => {
            let reach = match &args.input2 {
                Some(p) => plot::read_reach(p)?,
                None => Vec::new(),
            };
            plot::section::render(&plot::read_boundary(input)?, &reach, &args.out)
        }
        Kind::ErrorVsS => {
            if args.input2.is_some() {
                bail!("error-vs-s takes its series as repeated --input, not --input2");
            }
            let mut series = Vec::new();
            for (k, p) in args.input.iter().enumerate() {
                let mut s = plot::read_series(p)?;
                if let Some(l) = args.label.get(k) {
                    s.label = l.clone();
                }
                series.push(s);
            }
            plot::error_vs_s::render(&series, &args.out)
        }
        Kind::SpeedError => {
            if args.input2.is_some() {
                bail!("speed-error takes no --input2");
            }
            plot::speed_error::render(&plot::read_speed_error(input)?, &args.out)
        }
        Kind::Trajectory => {
            let limits = match &args.input2 {
                Some(p) => plot::read_joint_limits(p)?,
                None => Vec::new(),
            };
            let opts = TrajectoryOptions {
                limits,
                ..Default::default()
            };
            plot::trajectory::render(&plot::read_trajectory(input)?, &opts, &args.out)
        }
        Kind::Bifurcation => {
            let labelled = match &args.input2 {
                Some(p) => plot::bifurcation_map::read_labelled(p)?,
                None => Vec::new(),
            };
            plot::bifurcation_map::render(
                &plot::bifurcation_map::read_bifurcation(input)?,
                &labelled,
                &args.out,
            )
        }
        Kind::Comparison => {
            let Some(m) = &args.input2 else {
                bail!("comparison needs the measured CSV as --input2");
            };
            let measured: Vec<_> = helixreach::records::compare::read_measured(m)?
                .rows
                .iter()
                .map(|r| (r.dir, r.s_measured))
                .collect();
            plot::comparison::render(&plot::read_boundary(input)?, &measured, &args.out)
        }
        Kind::Detection => {
            let mut marks = plot::detection::Marks::default();
            if let Some(p) = &args.input2 {
                let text = std::fs::read_to_string(p)
                    .with_context(|| format!("reading {}", p.display()))?;
                let v: serde_json::Value = serde_json::from_str(&text)
                    .with_context(|| format!("{}: not a detect JSON summary", p.display()))?;
                marks.s_predicted = v["s_predicted"].as_f64();
                marks.s_snap = v["s_snap"].as_f64();
                marks.s_return = v["s_return"].as_f64();
            }
            plot::detection::render(
                &helixreach::records::detect::read_detect_samples(input)?,
                &marks,
                &args.out,
            )
        }
    }
    .with_context(what)?;
    status!("wrote {}", args.out.display());
    Ok(())
}
