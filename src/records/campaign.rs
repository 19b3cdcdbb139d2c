//! The records of a test campaign (`helixreach campaign --out DIR`,
//! [`crate::planning::campaign`]): the ray sweep `rays.csv` ([`RayRunRecord`], what the sweep
//! driver checkpoints and `--resume` reads back) and the run list `campaign.csv`
//! ([`CampaignRecord`], the runs in execution order, then the rays that are not testable).
//!
//! Positions are metres in the robot base frame, times seconds, angles radians; numbers by
//! [`fmt_real`](super::fmt_real); a value that does not apply is an empty field.

use super::csv_out::{self, CsvRecord};
use crate::math::Real;
use crate::records::columns::{Column, Kind};

/// One planned ray of `rays.csv`. The key is the first four columns.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RayRunRecord {
    /// Placement (1-based; 1 for a single rig).
    pub placement: usize,
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// `testable`, `partial`, `blocked` or `undecided`.
    pub class: String,
    /// Blocking cause; empty for testable rays.
    pub cause: String,
    /// The boundary s* (`inf`: none).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// Farthest s reached.
    #[serde(serialize_with = "csv_out::real")]
    pub s_reached: Real,
    /// Azimuth of the plan (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub azimuth: Real,
    /// Duration of the run (s, the last `t` of its CSV); empty when not testable.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub duration_s: Option<Real>,
    /// Motor angle at the start (rad); empty when not testable.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub motor_start: Option<Real>,
    /// Joints at the start (s = 0), space-separated (rad); empty when not testable.
    pub q_start: String,
    /// Joints at the end (s = 0 again), space-separated (rad); empty when not testable.
    pub q_end: String,
    /// The run's trajectory CSV, relative to the campaign folder; empty when not testable.
    pub file: String,
}

impl CsvRecord for RayRunRecord {
    const HEADER: &'static [&'static str] = &[
        "placement",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "class",
        "cause",
        "s_star",
        "s_reached",
        "azimuth",
        "duration_s",
        "motor_start",
        "q_start",
        "q_end",
        "file",
    ];
}

/// Number of key columns of [`RayRunRecord`] (`placement,dir_kappa,dir_tau,dir_omega`).
pub const RAY_RUN_KEY_COLUMNS: usize = 4;

/// The columns of [`RayRunRecord`] that the shared column table does not define, with their
/// units and rules (for the sweep driver).
pub fn ray_run_columns() -> Vec<Column> {
    vec![
        Column::new("placement", "", Kind::Count, "placement (1-based)"),
        Column::new("class", "", Kind::Text, "reachability class"),
        Column::new(
            "cause",
            "",
            Kind::Text,
            "blocking cause; empty when testable",
        ),
        Column::new(
            "duration_s",
            "s",
            Kind::FiniteOrEmpty,
            "duration of the run (last t of its CSV)",
        ),
        Column::new(
            "motor_start",
            "rad",
            Kind::FiniteOrEmpty,
            "motor angle at the start",
        ),
        Column::new("q_start", "rad", Kind::Text, "joints at the start"),
        Column::new("q_end", "rad", Kind::Text, "joints at the end"),
        Column::new("file", "", Kind::Text, "the run's trajectory CSV"),
    ]
}

/// One ray of `campaign.csv`: a run (in execution order) or a ray that is not testable (order,
/// session and times empty, `cause` says why).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CampaignRecord {
    /// Execution order (1-based); empty for a ray that is not testable.
    pub order: Option<usize>,
    /// Placement (1-based; 1 for a single rig); empty when no placement of a layout tests it.
    pub placement: Option<usize>,
    /// Clamp origin x (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_x: Option<Real>,
    /// Clamp origin y (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_y: Option<Real>,
    /// Clamp origin z (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_z: Option<Real>,
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// The boundary s* (`inf`: none).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// Farthest s reached (the target s*·(1 + margin) for a run).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_reached: Option<Real>,
    /// `testable`, `partial`, `blocked`, `undecided` (or the layout's class).
    pub class: String,
    /// Why the ray is not testable; empty for a run.
    pub cause: String,
    /// Azimuth of the plan (rad); empty when not planned.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub azimuth: Option<Real>,
    /// Duration of the run (s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub duration_s: Option<Real>,
    /// The move into this run: `start`, `none`, `reconfigure_at_straight`, `unclamp_move`,
    /// `clamp_move` or `blocked`.
    pub transition: String,
    /// Robot motion time of that move (s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub transition_s: Option<Real>,
    /// Stated handling time of that move (unclamping, moving the clamp; s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub handling_s: Option<Real>,
    /// Session (1-based).
    pub session: Option<usize>,
    /// Start of the run from the start of its session (s; after its transition).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub start_s: Option<Real>,
    /// The run's trajectory CSV (relative to the campaign folder).
    pub file: String,
    /// The run's ROS 2 `JointTrajectory` JSON.
    pub ros2_file: String,
    /// The move's joint trajectory CSV (`t,q…,motor`), when it moves.
    pub transition_file: String,
}

impl CsvRecord for CampaignRecord {
    const HEADER: &'static [&'static str] = &[
        "order",
        "placement",
        "clamp_x",
        "clamp_y",
        "clamp_z",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star",
        "s_reached",
        "class",
        "cause",
        "azimuth",
        "duration_s",
        "transition",
        "transition_s",
        "handling_s",
        "session",
        "start_s",
        "file",
        "ros2_file",
        "transition_file",
    ];
}

#[cfg(test)]
mod tests {
    use super::*;
    use csv_out::{fields, header_matches};

    #[test]
    fn headers_name_the_fields_in_order() {
        let ray = RayRunRecord {
            placement: 1,
            dir_kappa: 0.6,
            dir_tau: 0.8,
            dir_omega: 0.0,
            class: "testable".into(),
            cause: String::new(),
            s_star: 5.0,
            s_reached: 5.5,
            azimuth: 0.0,
            duration_s: Some(12.5),
            motor_start: Some(0.0),
            q_start: "0 1".into(),
            q_end: "0 1".into(),
            file: "runs/d000.csv".into(),
        };
        header_matches(&ray);
        assert_eq!(fields(&ray).unwrap()[9], "12.5");
        let row = CampaignRecord {
            order: None,
            placement: Some(1),
            clamp_x: Some(0.8),
            clamp_y: Some(0.0),
            clamp_z: Some(0.1),
            dir_kappa: 1.0,
            dir_tau: 0.0,
            dir_omega: 0.0,
            s_star: Real::INFINITY,
            s_reached: Some(0.0),
            class: "blocked".into(),
            cause: "no_ik".into(),
            azimuth: None,
            duration_s: None,
            transition: String::new(),
            transition_s: None,
            handling_s: None,
            session: None,
            start_s: None,
            file: String::new(),
            ros2_file: String::new(),
            transition_file: String::new(),
        };
        header_matches(&row);
        let f = fields(&row).unwrap();
        assert_eq!(
            (f[0].as_str(), f[8].as_str(), f[13].as_str()),
            ("", "inf", "")
        );
    }
}
