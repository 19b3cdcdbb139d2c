//! The reachability survey (`helixreach reach --out`, the demo's `reach_*.csv`): one
//! [`ReachRecord`] per direction, keyed by `dir_kappa,dir_tau,dir_omega`; read back by
//! [`read_reach`](super::read_reach). The last column, `bifurcation`, is the type the margin past
//! s* was chosen for (`any` when the rig's margins do not depend on it, see
//! [`crate::sweep::reach`]).

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::math::Real;
use crate::planning::planner::RayPlan;

/// One planned ray of a reachability CSV.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ReachRecord {
    /// The direction (`dir_kappa,dir_tau,dir_omega`).
    pub dir: DirColumns,
    /// The boundary s* (`inf`: none).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// Farthest s the planner reached.
    #[serde(serialize_with = "csv_out::real")]
    pub s_reached: Real,
    /// `testable`, `partial`, `blocked` or `undecided` ([`crate::planning::planner::ReachClass`]).
    pub class: &'static str,
    /// Blocking cause ([`crate::planning::cause::BlockCause`]); empty for testable rays.
    pub cause: &'static str,
    /// Azimuth of the plan (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub azimuth: Real,
    /// `fixed` or `motor`.
    pub roll_mode: &'static str,
    /// Waypoints of the ray.
    pub n_waypoints: usize,
    /// Path cost of the plan.
    #[serde(serialize_with = "csv_out::real")]
    pub path_cost: Real,
    /// Largest joint step (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub max_joint_step: Real,
    /// Self-motion reconfigurations at a held pose.
    pub reconfigurations: usize,
    /// Back-offs on the path (phase `backoff`; [`crate::planning::search`]).
    pub backoffs: usize,
    /// The bifurcation type the margin was chosen for, or `any`.
    pub bifurcation: &'static str,
}

impl CsvRecord for ReachRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star",
        "s_reached",
        "class",
        "cause",
        "azimuth",
        "roll_mode",
        "n_waypoints",
        "path_cost",
        "max_joint_step",
        "reconfigurations",
        "backoffs",
        "bifurcation",
    ];
}

impl From<&RayPlan> for ReachRecord {
    fn from(p: &RayPlan) -> Self {
        ReachRecord {
            dir: (&p.dir).into(),
            s_star: p.s_star,
            s_reached: p.s_reached,
            class: p.class.as_str(),
            cause: p.cause.map_or("", |c| c.as_str()),
            azimuth: p.azimuth,
            roll_mode: p.roll.as_str(),
            n_waypoints: p.n_waypoints,
            path_cost: p.path_cost,
            max_joint_step: p.max_joint_step,
            reconfigurations: p.reconfigurations,
            backoffs: p.backoffs,
            bifurcation: p.assumed_type.map_or("any", |t| t.name()),
        }
    }
}
