//! The boundary survey (`helixreach boundary --out`, the demo's `boundary.csv` and
//! `boundary_omega0.csv`): one [`BoundaryRecord`] per direction, read back by
//! [`read_boundary`](super::read_boundary); and the demo's DER check against it
//! (`der_check.csv`, one [`DerCheckRecord`] per direction and resolution).

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::directions::Direction;
use crate::math::Real;

/// One direction of a boundary CSV: where the ray S̄ leaves the stable set. The boundary point
/// is `s*·S̄` with `∞·0 = 0` (a ray stable to ∞ has no extent along a zero component).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BoundaryRecord {
    /// The direction (`dir_kappa,dir_tau,dir_omega`).
    pub dir: DirColumns,
    /// Critical distance s* (`inf`: stable up to the search limit; empty: refused).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s_star: Real,
    /// κ of the boundary point (empty: refused).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub kappa: Real,
    /// τ of the boundary point (empty: refused).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub tau: Real,
    /// ω of the boundary point (empty: refused).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub omega: Real,
    /// Boundary method (`continuum`, `der`, …).
    pub method: String,
    /// Method resolution (tolerance, n).
    pub resolution: String,
    /// The method's error estimate of s*, in exponent notation (`1.5e-9`).
    #[serde(serialize_with = "csv_out::real_exp_or_empty")]
    pub est_error: Real,
    /// Why the method gave no s* for this direction (empty when it did): the row of a refused
    /// direction has `nan` in `s_star`, `kappa`, `tau`, `omega` and `est_error`, so a sweep
    /// finishes (and resumes) past it and the reason stays with the direction.
    pub refused: String,
}

impl CsvRecord for BoundaryRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star",
        "kappa",
        "tau",
        "omega",
        "method",
        "resolution",
        "est_error",
        "refused",
    ];
}

impl BoundaryRecord {
    /// The record of direction `d` with boundary `s_star`.
    ///
    /// ```
    /// use helixreach::{directions::Direction, records::{boundary::BoundaryRecord, csv_out::fields}};
    /// let d = Direction::new(1.0, 0.0, 0.0).unwrap();
    /// let r = BoundaryRecord::new(&d, f64::INFINITY, "continuum", "1e-10", 0.0);
    /// assert_eq!(fields(&r)?[3..7], ["inf", "inf", "0", "0"]);
    /// # Ok::<(), helixreach::Error>(())
    /// ```
    pub fn new(
        d: &Direction,
        s_star: Real,
        method: &str,
        resolution: &str,
        est_error: Real,
    ) -> Self {
        let scaled = |c: Real| if c == 0.0 { 0.0 } else { s_star * c };
        BoundaryRecord {
            dir: d.into(),
            s_star,
            kappa: scaled(d.kappa),
            tau: scaled(d.tau),
            omega: scaled(d.omega),
            method: method.to_string(),
            resolution: resolution.to_string(),
            est_error,
            refused: String::new(),
        }
    }

    /// The record of a direction the method refused, with the reason (one line).
    pub fn refused(d: &Direction, method: &str, resolution: &str, reason: &str) -> Self {
        let mut r = Self::new(d, Real::NAN, method, resolution, Real::NAN);
        r.refused = reason.replace(['\n', '\r'], " ");
        r
    }
}

/// One (direction, DER resolution) of the demo's DER check against the continuum boundary.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DerCheckRecord {
    /// The direction (`dir_kappa,dir_tau,dir_omega`).
    pub dir: DirColumns,
    /// The continuum s* (the reference).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star_continuum: Real,
    /// DER edges.
    pub n_edges: usize,
    /// The DER s* (NaN: the DER test failed).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star_der: Real,
    /// |s*_DER − s*_continuum| / s*_continuum (NaN when the DER test failed).
    #[serde(serialize_with = "csv_out::real")]
    pub rel_diff: Real,
    /// Seconds the DER test took.
    #[serde(serialize_with = "csv_out::real")]
    pub seconds: Real,
}

impl CsvRecord for DerCheckRecord {
    const HEADER: &'static [&'static str] = &[
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star_continuum",
        "n_edges",
        "s_star_der",
        "rel_diff",
        "seconds",
    ];
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{field_names, fields};

    /// Header == serde fields; `∞·0 = 0`; the error estimate in exponent notation as the
    /// hand-written row had it (`format!("{:e}")`).
    #[test]
    fn boundary_record_fields() {
        let d = Direction::new(1.0, 0.0, 0.0).unwrap();
        let r = BoundaryRecord::new(&d, Real::INFINITY, "continuum", "1e-10", 1.5e-9);
        assert_eq!(field_names(&r).unwrap(), BoundaryRecord::HEADER);
        assert_eq!(
            fields(&r).unwrap(),
            [
                "1",
                "0",
                "0",
                "inf",
                "inf",
                "0",
                "0",
                "continuum",
                "1e-10",
                "1.5e-9",
                ""
            ]
        );
        let r = BoundaryRecord::new(&d, 6.25, "der", "n=100", 0.0);
        assert_eq!(fields(&r).unwrap()[9], format!("{:e}", 0.0));
        let c = DerCheckRecord {
            dir: DirColumns {
                dir_kappa: 0.6,
                dir_tau: 0.8,
                dir_omega: 0.0,
            },
            s_star_continuum: 7.0,
            n_edges: 30,
            s_star_der: Real::NAN,
            rel_diff: Real::NAN,
            seconds: 0.25,
        };
        assert_eq!(field_names(&c).unwrap(), DerCheckRecord::HEADER);
        assert_eq!(
            fields(&c).unwrap(),
            ["0.6", "0.8", "0", "7", "30", "NaN", "NaN", "0.25"]
        );
    }
}
