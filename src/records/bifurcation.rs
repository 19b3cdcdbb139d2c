//! The bifurcation survey (`helixreach bifurcation --out`, the demo's `bifurcation.csv`): one row
//! per direction, columns [`BifurcationRecord::HEADER`]. Values not computed (NaN) are empty
//! fields; `reason` is empty unless the type is `degenerate`.

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::bifurcation::Bifurcation;
use crate::directions::Direction;
use crate::math::Real;

/// One direction's bifurcation type and its numbers.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BifurcationRecord {
    /// The direction (`dir_kappa,dir_tau,dir_omega`).
    pub dir: DirColumns,
    /// DER s* at the survey's resolution.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s_star: Real,
    /// `subcritical`, `supercritical` or `degenerate`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// The normalized post-buckling coefficient (> 0 supercritical).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub coefficient: Real,
    /// Where the rod returns to the helix on unloading (statics).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s_return: Real,
    /// s* − s_return.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub hysteresis: Real,
    /// The resolution, e.g. `n=100`.
    pub resolution: String,
    /// Why the type is `degenerate`.
    pub reason: String,
}

impl CsvRecord for BifurcationRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star",
        "type",
        "coefficient",
        "s_return",
        "hysteresis",
        "resolution",
        "reason",
    ];
}

impl BifurcationRecord {
    /// The record of direction `d` classified as `b` at `resolution`.
    pub fn new(d: &Direction, b: &Bifurcation, resolution: &str) -> Self {
        BifurcationRecord {
            dir: d.into(),
            s_star: b.s_star,
            kind: b.kind.name(),
            coefficient: b.coefficient,
            s_return: b.s_return,
            hysteresis: b.hysteresis(),
            resolution: resolution.to_string(),
            reason: b.reason.clone(),
        }
    }
}
