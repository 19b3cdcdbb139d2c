//! Arguments shared by the sweep commands (`boundary`, `bifurcation`, `reach`, `layout`),
//! flattened into each command's `Args`.

use anyhow::bail;
use helixreach::directions::{self, Direction};
use helixreach::limits::{check_size, MAX_CHECKPOINT_SECS, MAX_DIRECTIONS};
use std::path::PathBuf;

/// The direction set: `--directions FILE` or `--fibonacci N [--quarter]`.
#[derive(Debug, clap::Args)]
pub struct DirectionArgs {
    /// Directions from a CSV with columns dir_kappa,dir_tau,dir_omega.
    #[arg(long, conflicts_with = "fibonacci")]
    pub directions: Option<PathBuf>,
    /// A Fibonacci lattice of N directions on the half-sphere κ ≥ 0 (N at most
    /// helixreach::limits::MAX_DIRECTIONS).
    #[arg(long)]
    pub fibonacci: Option<usize>,
    /// With --fibonacci: only the quarter κ ≥ 0, τ > 0 (the experiment's).
    #[arg(long, requires = "fibonacci")]
    pub quarter: bool,
}

impl DirectionArgs {
    /// The directions the arguments select (at most [`MAX_DIRECTIONS`]).
    pub fn load(&self) -> anyhow::Result<Vec<Direction>> {
        let dirs = match (&self.directions, self.fibonacci) {
            (Some(p), None) => directions::read_csv(p)?,
            (None, Some(n)) => {
                directions::fibonacci(check_size("--fibonacci", n, MAX_DIRECTIONS)?, self.quarter)?
            }
            _ => bail!("give exactly one of --directions FILE.csv or --fibonacci N"),
        };
        check_size("directions", dirs.len(), MAX_DIRECTIONS)?;
        Ok(dirs)
    }
}

/// The checkpoint interval of `--checkpoint-secs`, checked against
/// [`MAX_CHECKPOINT_SECS`].
pub fn checkpoint_interval(secs: f64) -> anyhow::Result<std::time::Duration> {
    if !(secs.is_finite() && (0.0..=MAX_CHECKPOINT_SECS).contains(&secs)) {
        bail!(
            "invalid --checkpoint-secs {}: must be in 0..={MAX_CHECKPOINT_SECS} (helixreach::limits)",
            helixreach::error::fmt_num(secs)
        );
    }
    Ok(std::time::Duration::from_secs_f64(secs))
}
