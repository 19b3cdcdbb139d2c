//! The per-row table of a trajectory check (`helixreach check --rows-out`,
//! [`check_rows_csv`]): one [`CheckRowRecord`] per row of the
//! checked file; values not computed are empty fields.

use super::csv_out::{self, CsvRecord};
use crate::error::Result;
use crate::math::Real;
use crate::planning::check::CheckReport;

/// One checked row.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CheckRowRecord<'a> {
    /// Row index (0-based).
    pub row: usize,
    /// 1-based line in the checked file.
    pub line: usize,
    /// s of the row on the ray (projection), when a direction was given.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s: Option<Real>,
    /// |p(s) − p| (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub position_error: Option<Real>,
    /// Angle of R(s)ᵀ·R (rad).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub rotation_error: Option<Real>,
    /// Largest joint step from the previous row (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub joint_step: Real,
    /// The first joint (or `motor`) outside its limits; empty when none.
    pub limit: &'a str,
    /// The colliding pairs (`a|b`), separated by `;`.
    pub contacts: String,
    /// Smallest robot–scene distance (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub scene_clearance: Option<Real>,
    /// Smallest rod–robot distance (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub rod_clearance: Option<Real>,
    /// 1 when the robot is in self-collision at this row, else 0.
    pub self_collision: u8,
    /// Every link pair in self-collision (`linkA|linkB`, URDF link names), separated by `;`.
    pub self_pairs: String,
}

impl CsvRecord for CheckRowRecord<'_> {
    const HEADER: &'static [&'static str] = &[
        "row",
        "line",
        "s",
        "position_error",
        "rotation_error",
        "joint_step",
        "limit",
        "contacts",
        "scene_clearance",
        "rod_clearance",
        "self_collision",
        "self_pairs",
    ];
}

/// The per-row CSV: `row,line,s,position_error,rotation_error,joint_step,limit,contacts,
/// scene_clearance,rod_clearance,self_collision,self_pairs` (empty fields where not
/// computed; `self_collision` 0 or 1, `self_pairs` every self-colliding link pair; contacts `a|b`
/// separated by `;`; a [`CheckRowRecord`] each).
pub fn check_rows_csv(report: &CheckReport) -> Result<String> {
    let rows: Vec<CheckRowRecord<'_>> = report
        .row_checks
        .iter()
        .enumerate()
        .map(|(i, r)| CheckRowRecord {
            row: i,
            line: r.line,
            s: r.s,
            position_error: r.position_error,
            rotation_error: r.rotation_error,
            joint_step: r.joint_step,
            limit: r.limit.as_deref().unwrap_or(""),
            contacts: r.contacts.join(";"),
            scene_clearance: r.scene_clearance,
            rod_clearance: r.rod_clearance,
            self_collision: u8::from(!r.self_pairs.is_empty()),
            self_pairs: r.self_pairs.join(";"),
        })
        .collect();
    csv_out::to_csv(&rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{field_names, fields};

    #[test]
    fn header_and_empty_fields() {
        let r = CheckRowRecord {
            row: 3,
            line: 5,
            s: None,
            position_error: Some(1e-7),
            rotation_error: None,
            joint_step: 0.05,
            limit: "",
            contacts: "right_l1|right_l4;rod|table".into(),
            scene_clearance: Some(0.2),
            rod_clearance: None,
            self_collision: 1,
            self_pairs: "right_l1|right_l4;right_l1|right_l5".into(),
        };
        assert_eq!(field_names(&r).unwrap(), CheckRowRecord::HEADER);
        assert_eq!(
            fields(&r).unwrap(),
            [
                "3",
                "5",
                "",
                "0.0000001",
                "",
                "0.05",
                "",
                "right_l1|right_l4;rod|table",
                "0.2",
                "",
                "1",
                "right_l1|right_l4;right_l1|right_l5"
            ]
        );
    }
}
