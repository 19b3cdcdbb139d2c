//! Arguments shared by several commands, flattened into each command's `Args`: the direction
//! set of the sweeps (`boundary`, `bifurcation`, `reach`, `layout`), the checkpoint interval, the
//! rig overrides of `plan` and `reach`.

use anyhow::bail;
use helixreach::directions::{self, Direction};
use helixreach::limits::{check_size, MAX_CHECKPOINT_SECS, MAX_DIRECTIONS};
use helixreach::planning::planner::RigOverrides;
use helixreach::planning::rig::Rig;
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

/// `--margin M`: one rule for every command
/// ([`MARGIN_RULE`](helixreach::planning::rig::MARGIN_RULE): 0 ≤ M ≤ 1).
pub fn parse_margin(s: &str) -> Result<f64, String> {
    let m: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("`{s}` is not a number ({e})"))?;
    if helixreach::planning::rig::margin_ok(m) {
        Ok(m)
    } else {
        Err(format!("{m} {}", helixreach::planning::rig::MARGIN_RULE))
    }
}

/// Overrides of a rig's settings for one run.
#[derive(Debug, clap::Args)]
pub struct RigOverrideArgs {
    /// Drive the rod to s*·(1 + M), 0 ≤ M ≤ 1 (0: to the boundary); overrides the rig's
    /// `planner.margin`.
    #[arg(long, value_name = "M", value_parser = parse_margin, allow_hyphen_values = true)]
    pub margin: Option<f64>,
    /// Clamp position `x,y,z` in the robot base frame (m), overriding the rig's `clamp.origin`.
    #[arg(long, allow_hyphen_values = true)]
    pub clamp: Option<String>,
    /// Forbid self-motion reconfiguration at a held pose (overrides the rig's
    /// `planner.allow_reconfiguration`).
    #[arg(long)]
    pub no_reconfiguration: bool,
    /// How each ray is decided: `ladder` or `exact` (the search of the valid set; overrides the
    /// rig's `planner.search`).
    #[arg(long)]
    pub search: Option<String>,
    /// Forbid driving back along the ray to reconfigure (the `exact` search; overrides the rig's
    /// `planner.allow_backoff`).
    #[arg(long)]
    pub no_backoff: bool,
}

impl RigOverrideArgs {
    /// `rig` with the overrides applied (errors name the flag).
    pub fn apply(&self, rig: &Rig) -> anyhow::Result<Rig> {
        let o = RigOverrides {
            margin: self.margin,
            clamp: self
                .clamp
                .as_deref()
                .map(|c| helixreach::planning::rig::parse_xyz("--clamp", c))
                .transpose()?,
            allow_reconfiguration: self.no_reconfiguration.then_some(false),
            search: self
                .search
                .as_deref()
                .map(|s| s.parse().map_err(|e| anyhow::anyhow!("--search: {e}")))
                .transpose()?,
            allow_backoff: self.no_backoff.then_some(false),
        };
        o.apply(rig)
            .map_err(|e| anyhow::anyhow!("rig overrides (--margin, --clamp, …): {e}"))
    }
}

/// How a URDF given on the command line is loaded: mesh search paths, links meant to have no
/// collision geometry (`fk`, `ik`, `robot`, `check --robot`, `rig init`).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RobotLoadArgs {
    /// A package directory for `package://NAME/...` mesh names (repeatable; searched before
    /// ROS_PACKAGE_PATH): `DIR/NAME/...`, or `DIR/...` when DIR itself is named NAME.
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
    /// A link meant to have no collision geometry (repeatable); any other link on the arm
    /// without collision geometry is an error.
    #[arg(long = "no-collision", value_name = "LINK")]
    pub no_collision: Vec<String>,
}

impl RobotLoadArgs {
    /// The loader options.
    pub fn options(&self) -> helixreach::robot::LoadOptions {
        helixreach::robot::LoadOptions {
            search: helixreach::robot::mesh::MeshSearch::new(self.package_path.clone()),
            no_collision: self.no_collision.clone(),
        }
    }

    /// Load `robot` (a built-in name or a URDF path) with tool link `tip`.
    pub fn load(
        &self,
        robot: &str,
        tip: Option<&str>,
    ) -> anyhow::Result<helixreach::robot::RobotModel> {
        Ok(helixreach::robot::RobotModel::load_with(
            robot,
            tip,
            &self.options(),
        )?)
    }
}
