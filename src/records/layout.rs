//! The records of a layout run (`helixreach layout --out DIR`, [`crate::layout`]): the ray sweep
//! `rays.csv` ([`RayRecord`], what the sweep driver checkpoints and `--resume` reads back), and
//! the summaries [`crate::layout::report`] writes: `candidates.csv` ([`CandidateRecord`]),
//! `placements.csv` ([`PlacementRecord`]), `assignment.csv` ([`AssignmentRecord`]),
//! `coverage.csv` ([`CoverageRecord`]) and `reference.csv` ([`ReferenceRecord`]).
//!
//! Positions are metres in the robot base frame, angles of the clamp pose degrees, azimuths
//! radians; numbers by [`fmt_real`](super::fmt_real); a value not known is an empty field.

use super::csv_out::{self, CsvRecord};
use crate::math::Real;

/// One (candidate, direction) ray of `rays.csv`. The key is the first four columns.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RayRecord<'a> {
    /// Candidate index (0-based, `candidates.csv` order).
    pub candidate: usize,
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// `testable`, `partial`, `blocked`, or `unreachable` (decided by the reach bound).
    pub class: &'a str,
    /// Farthest s reached; empty when not known.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_reached: Option<Real>,
    /// Azimuth of the plan (rad); empty when not planned.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub azimuth: Option<Real>,
    /// Blocking cause; empty for testable rays.
    pub cause: &'a str,
    /// The boundary s* of the direction (`inf`: no boundary).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// `planner`, `clamp`, `reach_bound`, `no_boundary` or `end_pose`.
    pub decided_by: &'static str,
}

impl CsvRecord for RayRecord<'_> {
    const HEADER: &'static [&'static str] = &[
        "candidate",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "class",
        "s_reached",
        "azimuth",
        "cause",
        "s_star",
        "decided_by",
    ];
}

/// Number of key columns of [`RayRecord`] (`candidate,dir_kappa,dir_tau,dir_omega`).
pub const RAY_KEY_COLUMNS: usize = 4;

/// One candidate clamp pose of `candidates.csv`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CandidateRecord {
    /// Candidate index.
    pub candidate: usize,
    /// Clamp origin x (m).
    #[serde(serialize_with = "csv_out::real")]
    pub x: Real,
    /// Clamp origin y (m).
    #[serde(serialize_with = "csv_out::real")]
    pub y: Real,
    /// Clamp origin z (m).
    #[serde(serialize_with = "csv_out::real")]
    pub z: Real,
    /// Tilt of the clamp axis (deg).
    #[serde(serialize_with = "csv_out::real")]
    pub tilt_deg: Real,
    /// Heading of the tilt (deg).
    #[serde(serialize_with = "csv_out::real")]
    pub heading_deg: Real,
    /// Clamp tangent d3, x.
    #[serde(serialize_with = "csv_out::real")]
    pub d3_x: Real,
    /// Clamp tangent d3, y.
    #[serde(serialize_with = "csv_out::real")]
    pub d3_y: Real,
    /// Clamp tangent d3, z.
    #[serde(serialize_with = "csv_out::real")]
    pub d3_z: Real,
    /// `grid` or `reference`.
    pub kind: &'static str,
    /// Directions testable from this pose.
    pub covered: usize,
    /// covered / number of directions.
    #[serde(serialize_with = "csv_out::real")]
    pub fraction: Real,
}

impl CsvRecord for CandidateRecord {
    const HEADER: &'static [&'static str] = &[
        "candidate",
        "x",
        "y",
        "z",
        "tilt_deg",
        "heading_deg",
        "d3_x",
        "d3_y",
        "d3_z",
        "kind",
        "covered",
        "fraction",
    ];
}

/// One chosen placement of `placements.csv` (greedy order).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlacementRecord {
    /// Rank, 1-based.
    pub placement: usize,
    /// Candidate index.
    pub candidate: usize,
    /// Clamp origin x (m).
    #[serde(serialize_with = "csv_out::real")]
    pub x: Real,
    /// Clamp origin y (m).
    #[serde(serialize_with = "csv_out::real")]
    pub y: Real,
    /// Clamp origin z (m).
    #[serde(serialize_with = "csv_out::real")]
    pub z: Real,
    /// Tilt of the clamp axis (deg).
    #[serde(serialize_with = "csv_out::real")]
    pub tilt_deg: Real,
    /// Heading of the tilt (deg).
    #[serde(serialize_with = "csv_out::real")]
    pub heading_deg: Real,
    /// Directions testable from this placement.
    pub covered: usize,
    /// Directions it adds to the previous placements.
    pub new: usize,
    /// Directions covered by placements 1..=this.
    pub cumulative: usize,
    /// cumulative / number of directions.
    #[serde(serialize_with = "csv_out::real")]
    pub cumulative_fraction: Real,
    /// The placed rig's file name.
    pub rig_file: String,
}

impl CsvRecord for PlacementRecord {
    const HEADER: &'static [&'static str] = &[
        "placement",
        "candidate",
        "x",
        "y",
        "z",
        "tilt_deg",
        "heading_deg",
        "covered",
        "new",
        "cumulative",
        "cumulative_fraction",
        "rig_file",
    ];
}

/// One direction of `assignment.csv`: the placement that tests it, or (placement empty) the best
/// answer any placement gave.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AssignmentRecord {
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// 1-based placement that tests the direction; empty when none does.
    pub placement: Option<usize>,
    /// Azimuth of that placement's plan (rad); empty when none tests it.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub azimuth: Option<Real>,
    /// Class (the best over the placements when none tests it).
    pub class: String,
    /// Farthest s reached; empty when not known.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_reached: Option<Real>,
}

impl CsvRecord for AssignmentRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "placement",
        "azimuth",
        "class",
        "s_reached",
    ];
}

/// Coverage with k placements, greedy and exact (`coverage.csv`).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct CoverageRecord {
    /// Number of placements.
    pub k: usize,
    /// Directions covered by the greedy choice.
    pub greedy: usize,
    /// Directions covered by the exact search.
    pub exact: usize,
    /// Whether the exact search proved its optimum within its node budget.
    pub exact_proven: bool,
    /// Branch-and-bound nodes of the exact search.
    pub exact_nodes: u64,
    /// Number of directions.
    pub total: usize,
}

impl CsvRecord for CoverageRecord {
    const HEADER: &'static [&'static str] = &[
        "k",
        "greedy",
        "exact",
        "exact_proven",
        "exact_nodes",
        "total",
    ];
}

/// One line of `reference.csv`: a set of clamp positions and how many directions it covers.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct ReferenceRecord {
    /// `reference_own_position`, `reference_union` or `layout_best`.
    pub set: &'static str,
    /// Number of positions in the set.
    pub placements: usize,
    /// Directions covered.
    pub covered: usize,
    /// Directions considered.
    pub total: usize,
}

impl CsvRecord for ReferenceRecord {
    const HEADER: &'static [&'static str] = &["set", "placements", "covered", "total"];
}

#[cfg(test)]
mod tests {
    use super::*;
    use csv_out::{fields, header_matches, to_csv};

    /// Every layout record's header names its serde fields, in order.
    #[test]
    fn headers_name_the_fields_in_order() {
        header_matches(&RayRecord {
            candidate: 3,
            dir_kappa: 0.6,
            dir_tau: 0.8,
            dir_omega: 0.0,
            class: "testable",
            s_reached: Some(7.5),
            azimuth: None,
            cause: "",
            s_star: Real::INFINITY,
            decided_by: "planner",
        });
        header_matches(&CandidateRecord {
            candidate: 0,
            x: 0.8,
            y: -0.1,
            z: 0.3,
            tilt_deg: 0.0,
            heading_deg: 0.0,
            d3_x: 0.0,
            d3_y: 0.0,
            d3_z: 1.0,
            kind: "grid",
            covered: 2,
            fraction: 0.5,
        });
        header_matches(&PlacementRecord {
            placement: 1,
            candidate: 0,
            x: 0.8,
            y: -0.1,
            z: 0.3,
            tilt_deg: 0.0,
            heading_deg: 0.0,
            covered: 2,
            new: 2,
            cumulative: 2,
            cumulative_fraction: 0.5,
            rig_file: "placement_1.toml".into(),
        });
        header_matches(&AssignmentRecord {
            dir_kappa: 1.0,
            dir_tau: 0.0,
            dir_omega: 0.0,
            placement: None,
            azimuth: None,
            class: "blocked".into(),
            s_reached: Some(0.0),
        });
        header_matches(&CoverageRecord {
            k: 1,
            greedy: 2,
            exact: 2,
            exact_proven: true,
            exact_nodes: 10,
            total: 4,
        });
        header_matches(&ReferenceRecord {
            set: "reference_union",
            placements: 5,
            covered: 3,
            total: 4,
        });
    }

    /// The hand-written writers' text: empty fields for unknown values, `inf`, `true`.
    #[test]
    fn fields_as_the_hand_written_writers_wrote_them() {
        let r = RayRecord {
            candidate: 12,
            dir_kappa: 1.0 / 3.0,
            dir_tau: 0.0,
            dir_omega: -0.5,
            class: "unreachable",
            s_reached: None,
            azimuth: None,
            cause: "no_ik",
            s_star: Real::INFINITY,
            decided_by: "reach_bound",
        };
        assert_eq!(
            fields(&r).unwrap(),
            [
                "12",
                &format!("{}", 1.0 / 3.0),
                "0",
                "-0.5",
                "unreachable",
                "",
                "",
                "no_ik",
                "inf",
                "reach_bound"
            ]
        );
        let c = CoverageRecord {
            k: 2,
            greedy: 3,
            exact: 4,
            exact_proven: false,
            exact_nodes: 20_000_000,
            total: 5,
        };
        assert_eq!(
            to_csv(&[c]).unwrap(),
            "k,greedy,exact,exact_proven,exact_nodes,total\n2,3,4,false,20000000,5\n"
        );
    }
}
