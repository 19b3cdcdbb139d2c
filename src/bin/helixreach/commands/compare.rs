//! `helixreach compare`: measured snap points versus a simulated boundary
//! (`helixreach::compare`). The simulated values come from a boundary CSV (`--boundary`,
//! written by `helixreach boundary`, matched by direction) or are computed here for the measured
//! directions (`--method continuum|der`, in parallel). Writes `--out` (columns
//! `dir_kappa,dir_tau,dir_omega,s_measured,s_sim,err,signed_diff`, rows in the order of the
//! measured file) and prints the JSON summary (count, mean, max, population std of err, mean
//! signed difference, and the directions without a simulated value) on stdout. Notes about
//! normalized directions and missing values go to stderr. A `--boundary` file that holds none
//! of the measured directions (a boundary computed on another direction set) is refused,
//! naming both files: boundary values are never interpolated between directions.

use anyhow::bail;
use helixreach::boundary::{continuum, der};
use helixreach::compare::{self, Measured};
use helixreach::io::Output;
use helixreach::math::Real;
use helixreach::plot::records::read_boundary;
use std::path::PathBuf;

/// Which simulated boundary: the library's one [`helixreach::boundary::Method`].
pub use helixreach::boundary::Method;

/// Arguments of `helixreach compare`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ printf 'dir_kappa,dir_tau,dir_omega,s_measured\\n1,0,0,6.3\\n0.6,0.8,0,7.1\\n' > measured.csv",
    "$ helixreach compare --measured measured.csv --method continuum --out comparison.csv",
    "$ helixreach boundary --directions measured.csv --out boundary.csv",
    "$ helixreach compare --measured measured.csv --boundary boundary.csv --out -"
))]
#[command(group(clap::ArgGroup::new("sim").required(true).args(["boundary", "method"])))]
pub struct Args {
    /// Measured snap points: CSV with columns dir_kappa,dir_tau,dir_omega,s_measured.
    #[arg(long)]
    pub measured: PathBuf,
    /// A boundary CSV (helixreach boundary) holding the measured directions.
    #[arg(long)]
    pub boundary: Option<PathBuf>,
    /// Compute the boundary of the measured directions with this method.
    #[arg(long, value_enum)]
    pub method: Option<Method>,
    /// Number of DER edges (method der).
    #[arg(long, default_value_t = 100)]
    pub n_edges: usize,
    /// Output CSV (`-`: standard output, before the JSON summary).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing output file (never one of this command's inputs).
    #[arg(long)]
    pub force: bool,
}

fn simulate(m: &[Measured], method: Method, n_edges: usize) -> anyhow::Result<Vec<Option<Real>>> {
    if !(4..=2000).contains(&n_edges) {
        bail!("invalid --n-edges {n_edges}: must be in 4..=2000");
    }
    let p = der::DerBoundaryParams {
        n_edges,
        ..der::DerBoundaryParams::default()
    };
    let par = helixreach::par::Par::from_option(super::global().threads)?;
    let s: Vec<helixreach::Result<Real>> = par.map(m, |x| match method {
        Method::Continuum => {
            continuum::critical_s(&x.dir, helixreach::math::tol::S_STAR_REL).map(|c| c.s_star)
        }
        Method::Der => der::critical_s(&x.dir, &p).map(|c| c.s_star),
    })?;
    s.into_iter()
        .zip(m)
        .map(|(r, x)| {
            r.map(|v| v.is_finite().then_some(v)).map_err(|e| {
                anyhow::anyhow!(
                    "line {} direction ({}, {}, {}): {e}",
                    x.line,
                    x.dir.kappa,
                    x.dir.tau,
                    x.dir.omega
                )
            })
        })
        .collect()
}

/// Run `helixreach compare`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let mut out = Output::new(&a.out).force(a.force).input(&a.measured);
    if let Some(b) = &a.boundary {
        out = out.input(b);
    }
    out.check()?;
    let set = helixreach::records::compare::read_measured(&a.measured)?;
    for n in &set.notes {
        eprintln!("note: {n}");
    }
    let mut missing_reason: Vec<String> = Vec::new();
    let sim = match (&a.boundary, a.method) {
        (Some(b), _) => {
            let rows = read_boundary(b)?;
            let pairs: Vec<_> = rows.iter().map(|r| (r.dir, r.s_star)).collect();
            let dirs: Vec<_> = rows.iter().map(|r| r.dir).collect();
            let on = compare::boundary_rows_on(&set.rows, &dirs);
            if !on.iter().any(|&(o, _)| o) {
                let (m, (_, nearest)) = (&set.rows[0], on[0]);
                bail!(
                    "{} holds none of the {} directions of {}: it was computed on other \
                     directions (the first measured one, line {} ({}, {}, {}), is {:.3}° from the \
                     nearest row; same ray = every component within {:e}). Compute the \
                     boundary on the measured directions (`helixreach boundary --directions {} \
                     --out B.csv`) or use `--method continuum|der`",
                    b.display(),
                    set.rows.len(),
                    a.measured.display(),
                    m.line,
                    m.dir.kappa,
                    m.dir.tau,
                    m.dir.omega,
                    nearest.to_degrees(),
                    compare::MATCH_TOL,
                    a.measured.display()
                );
            }
            missing_reason = on
                .iter()
                .map(|&(o, _)| {
                    if o {
                        format!("s* is infinite in {}", b.display())
                    } else {
                        format!("not in {}", b.display())
                    }
                })
                .collect();
            compare::match_boundary(&set.rows, &pairs)
        }
        (None, Some(m)) => simulate(&set.rows, m, a.n_edges)?,
        (None, None) => bail!("give --boundary FILE.csv or --method continuum|der"),
    };
    let c = compare::compare(&set.rows, &sim);
    for &i in &c.missing {
        let m = &set.rows[i];
        let why = missing_reason
            .get(i)
            .map_or(String::new(), |r| format!(" ({r})"));
        eprintln!(
            "note: {}:{}: no simulated boundary for direction ({}, {}, {}){why}; row kept with \
             empty s_sim",
            a.measured.display(),
            m.line,
            m.dir.kappa,
            m.dir.tau,
            m.dir.omega
        );
    }
    out.write(helixreach::records::compare::comparison_csv(&c)?.as_bytes())?;
    println!(
        "{}",
        serde_json::to_string_pretty(&c.summary_json(&set.rows))?
    );
    Ok(())
}
