//! The comparison of measured snap points with simulated s* (`helixreach compare --out`): one row
//! per measured direction, in the measured file's order, columns [`ComparisonRecord::HEADER`].
//! Directions without a simulated value have empty `s_sim`, `err`, `signed_diff`.

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::compare::ComparisonRow;
use crate::math::Real;

/// One measured direction against its simulated value.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ComparisonRecord {
    /// The direction (`dir_kappa,dir_tau,dir_omega`).
    pub dir: DirColumns,
    /// Measured s.
    #[serde(serialize_with = "csv_out::real")]
    pub s_measured: Real,
    /// Simulated s*.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_sim: Option<Real>,
    /// `|s_measured − s_sim|/s_sim`.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub err: Option<Real>,
    /// `s_measured − s_sim`.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub signed_diff: Option<Real>,
}

impl CsvRecord for ComparisonRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_measured",
        "s_sim",
        "err",
        "signed_diff",
    ];
}

impl From<&ComparisonRow> for ComparisonRecord {
    fn from(r: &ComparisonRow) -> Self {
        ComparisonRecord {
            dir: (&r.dir).into(),
            s_measured: r.s_measured,
            s_sim: r.s_sim,
            err: r.err,
            signed_diff: r.signed_diff,
        }
    }
}
