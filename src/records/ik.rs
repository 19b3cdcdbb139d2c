//! IK solutions as CSV (`helixreach ik` on stdout): one [`IkSolutionRecord`] per solution,
//! columns [`ik_header`]: the robot's joint names, then `position_error,rotation_error` (m, rad;
//! exponent notation).

use super::csv_out;
use crate::error::Result;
use crate::math::Real;

/// One IK solution.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IkSolutionRecord<'a> {
    /// Joint angles (rad), one column per joint.
    #[serde(serialize_with = "csv_out::reals")]
    pub q: &'a [Real],
    /// Position error by FK (m).
    #[serde(serialize_with = "csv_out::real_exp")]
    pub position_error: Real,
    /// Rotation error by FK (rad).
    #[serde(serialize_with = "csv_out::real_exp")]
    pub rotation_error: Real,
}

/// The header: the joint names, then `position_error,rotation_error`.
pub fn ik_header<'a>(joint_names: &[&'a str]) -> Vec<&'a str> {
    let mut h = joint_names.to_vec();
    h.extend(["position_error", "rotation_error"]);
    h
}

/// The CSV text of `rows` for a robot with `joint_names`.
pub fn ik_csv(joint_names: &[&str], rows: &[IkSolutionRecord<'_>]) -> Result<String> {
    csv_out::to_csv_with(&ik_header(joint_names), rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joints_then_errors_in_exponent_notation() {
        let q = [0.5, -1.0 / 3.0];
        let text = ik_csv(
            &["j0", "j1"],
            &[IkSolutionRecord {
                q: &q,
                position_error: 2.5e-11,
                rotation_error: 0.0,
            }],
        )
        .unwrap();
        assert_eq!(
            text,
            format!(
                "j0,j1,position_error,rotation_error\n0.5,{},2.5e-11,0e0\n",
                -1.0 / 3.0
            )
        );
    }
}
