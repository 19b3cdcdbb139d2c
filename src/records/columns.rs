//! The columns of every sweep output: name, unit, meaning and the values a field may hold — one
//! table ([`COLUMNS`]), used to write the units into an output's sidecar (`F.meta.json`) and to
//! validate every row read back (`--resume`, `merge`) and every row computed, by the same rule.
//!
//! Units: the helix parameters and the distance s along a ray are nondimensional (rod length
//! L = 1, see the design notes), written `1`; angles are in rad; counts have no unit.
//!
//! Field rules ([`Kind`]): numbers parse as `f64` and are never NaN; which of ±∞ and the empty
//! field a column admits is its kind's; counts are non-negative integers; choice columns hold one
//! of their listed words. A row whose field breaks its column's rule is refused, naming the
//! column and the text.
//!
//! ```
//! use helixreach::records::columns::{check_row, column};
//! assert_eq!(column("s_star").unwrap().unit, "1");
//! let header = ["dir_kappa", "dir_tau", "dir_omega", "s_star"];
//! assert!(check_row(&header, &["1", "0", "0", "inf"]).is_ok());
//! let e = check_row(&header, &["1", "0", "0", "NaN"]).unwrap_err();
//! assert!(e.contains("s_star") && e.contains("NaN"), "{e}");
//! assert!(check_row(&header, &["1", "0", "0", "6.2x"]).is_err());
//! ```

use serde::Serialize;

/// The values a column's fields may hold (never NaN, never text in a number column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A finite number.
    Finite,
    /// A finite number, or empty (not computed).
    FiniteOrEmpty,
    /// A finite number ≥ 0.
    NonNegative,
    /// A number ≥ 0 or `inf` (a distance that may be unbounded, e.g. `s_star`), or empty (not
    /// computed).
    Distance,
    /// A finite number or ±`inf` (e.g. `s*·S̄` when s* = ∞).
    Extended,
    /// A finite number, ±`inf`, or empty (not computed).
    ExtendedOrEmpty,
    /// A non-negative integer.
    Count,
    /// `true` or `false`.
    Bool,
    /// One of the listed words.
    Choice(&'static [&'static str]),
    /// Any text (possibly empty).
    Text,
    /// No rule known: refused by every writer and reader (give the column a rule).
    Unknown,
}

/// One column of a sweep output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Column {
    /// Its name in the header.
    pub name: &'static str,
    /// Its unit (`1`: nondimensional; empty: text or a count).
    pub unit: &'static str,
    /// What it holds.
    pub meaning: &'static str,
    /// The values it may hold.
    #[serde(skip)]
    pub kind: Kind,
}

const fn col(name: &'static str, unit: &'static str, kind: Kind, meaning: &'static str) -> Column {
    Column::new(name, unit, kind, meaning)
}

impl Column {
    /// A column `name` in `unit` holding `kind` values (for a sweep whose columns are not in
    /// [`COLUMNS`], given to [`crate::sweep::driver::SweepOptions::column`]).
    pub const fn new(
        name: &'static str,
        unit: &'static str,
        kind: Kind,
        meaning: &'static str,
    ) -> Column {
        Column {
            name,
            unit,
            meaning,
            kind,
        }
    }
}

/// The reachability classes (`unreachable`: decided by a layout pre-check).
const CLASSES: &[&str] = &["testable", "partial", "blocked", "undecided", "unreachable"];

/// Every column of every sweep output (`boundary`, `reach`, `layout` rays, `bifurcation`,
/// `detect --runs`).
pub const COLUMNS: &[Column] = &[
    col(
        "dir_kappa",
        "1",
        Kind::Finite,
        "κ̂ of the unit search direction S̄",
    ),
    col(
        "dir_tau",
        "1",
        Kind::Finite,
        "τ̂ of the unit search direction S̄",
    ),
    col(
        "dir_omega",
        "1",
        Kind::Finite,
        "ω̂ of the unit search direction S̄",
    ),
    col(
        "s_star",
        "1",
        Kind::Distance,
        "critical distance s* along S̄ (inf: stable up to the search limit; empty: not computed)",
    ),
    col(
        "kappa",
        "1",
        Kind::ExtendedOrEmpty,
        "κ of the boundary point s*·S̄ (curvature × L)",
    ),
    col(
        "tau",
        "1",
        Kind::ExtendedOrEmpty,
        "τ of the boundary point s*·S̄ (torsion × L)",
    ),
    col(
        "omega",
        "1",
        Kind::ExtendedOrEmpty,
        "ω of the boundary point s*·S̄ (twisting moment × L / bending stiffness)",
    ),
    col("method", "", Kind::Text, "boundary method (continuum, der)"),
    col(
        "resolution",
        "",
        Kind::Text,
        "method resolution (tolerance or number of edges)",
    ),
    col(
        "est_error",
        "1",
        Kind::ExtendedOrEmpty,
        "the method's error estimate of s* (empty: refused)",
    ),
    col(
        "s_reached",
        "1",
        Kind::Distance,
        "farthest s the planner reached along the ray",
    ),
    col(
        "class",
        "",
        Kind::Choice(CLASSES),
        "testable, partial, blocked, undecided (search stopped at its node bound) or unreachable (decided before planning)",
    ),
    col(
        "cause",
        "",
        Kind::Text,
        "what stopped the ray (empty when testable)",
    ),
    col(
        "azimuth",
        "rad",
        Kind::FiniteOrEmpty,
        "helix azimuth α about the clamp tangent (empty: not planned)",
    ),
    col(
        "roll_mode",
        "",
        Kind::Choice(&["fixed", "motor"]),
        "end roll: fixed, or driven by the motor",
    ),
    col(
        "n_waypoints",
        "",
        Kind::Count,
        "waypoints of the ray's plan",
    ),
    col(
        "path_cost",
        "rad",
        Kind::NonNegative,
        "weighted joint-space path length of the plan",
    ),
    col(
        "max_joint_step",
        "rad",
        Kind::NonNegative,
        "largest joint step between waypoints",
    ),
    col(
        "reconfigurations",
        "",
        Kind::Count,
        "self-motion reconfigurations at a held pose",
    ),
    col(
        "backoffs",
        "",
        Kind::Count,
        "back-off moves (unloading to change configuration) in the plan",
    ),
    col(
        "bifurcation",
        "",
        Kind::Text,
        "bifurcation type the margin past s* was chosen for (any: type-independent)",
    ),
    col(
        "candidate",
        "",
        Kind::Count,
        "index of the candidate clamp pose",
    ),
    col(
        "decided_by",
        "",
        Kind::Text,
        "which stage decided the ray (planner, clamp, end-pose check, …)",
    ),
    col(
        "type",
        "",
        Kind::Choice(&["subcritical", "supercritical", "degenerate"]),
        "bifurcation type at the DER s*",
    ),
    col(
        "coefficient",
        "1",
        Kind::ExtendedOrEmpty,
        "normalized post-buckling coefficient (> 0: supercritical)",
    ),
    col(
        "s_return",
        "1",
        Kind::ExtendedOrEmpty,
        "where the rod returns to the helix on unloading (statics)",
    ),
    col("hysteresis", "1", Kind::ExtendedOrEmpty, "s* − s_return"),
    col("reason", "", Kind::Text, "why: bifurcation, why the type is degenerate (empty otherwise); detect, the outcome (snap, gradual, noise, …)"),
    col("observations", "", Kind::Text, "the observation file of a recorded run, as the run list names it"),
    col("s_measured", "1", Kind::Distance, "where the measured error jumped on loading (empty: no snap seen)"),
    col("confidence", "", Kind::Choice(&["high", "low", "none"]), "confidence of the detected snap"),
    col("s_reversal", "1", Kind::ExtendedOrEmpty, "largest s of the recorded run"),
    col("s_predicted", "1", Kind::Distance, "the continuum s* of the direction"),
    col("marker_arc", "1", Kind::ExtendedOrEmpty, "fitted marker arc length (fraction of the rod from the clamp)"),
    col("fit_rms", "m", Kind::ExtendedOrEmpty, "RMS residual of the camera extrinsics fit"),
    col("clamp_x", "m", Kind::Finite, "clamp position x (robot base frame)"),
    col("clamp_y", "m", Kind::Finite, "clamp position y (robot base frame)"),
    col("clamp_z", "m", Kind::Finite, "clamp position z (robot base frame)"),
    col("samples", "", Kind::Count, "samples in the observation file"),
    col("flagged", "", Kind::Count, "samples not used (dropped marker, outlier, off the pose curve)"),
    col("notes", "", Kind::Text, "notes that do not change the outcome (;-separated)"),
    col("refused", "", Kind::Text, "why the boundary method gave no s* for the direction (empty when it did)"),
];

/// The column named `name`, if it is one of [`COLUMNS`].
pub fn column(name: &str) -> Option<&'static Column> {
    COLUMNS.iter().find(|c| c.name == name)
}

/// The columns of `header` from [`COLUMNS`]; a name not there gets [`Kind::Unknown`] (refused
/// when a row is checked).
pub fn columns_of(header: &[impl AsRef<str>]) -> Vec<Column> {
    header
        .iter()
        .map(|h| {
            column(h.as_ref()).copied().unwrap_or(Column {
                name: "",
                unit: "",
                meaning: "",
                kind: Kind::Unknown,
            })
        })
        .collect()
}

/// An error naming the first column of `cols` without a rule (`header` gives the names).
pub fn check_known(header: &[impl AsRef<str>], cols: &[Column]) -> Result<(), String> {
    match header
        .iter()
        .zip(cols)
        .find(|(_, c)| c.kind == Kind::Unknown)
    {
        Some((h, _)) => Err(format!(
            "column `{}` has no unit and rule (helixreach::records::columns)",
            h.as_ref()
        )),
        None => Ok(()),
    }
}

/// Check one field against its column's rule; the error quotes the field.
pub fn check_field(c: &Column, s: &str) -> Result<(), String> {
    check_value(c.kind, s).map_err(|e| format!("{}: {e}", c.name))
}

/// Check one field against a kind of values; the error quotes the field.
fn check_value(kind: Kind, s: &str) -> Result<(), String> {
    let bad = |what: &str| Err(format!("`{s}` {what}"));
    let number = |s: &str| -> Result<f64, String> {
        match s.parse::<f64>() {
            Ok(v) if v.is_nan() => Err(format!("`{s}` is NaN")),
            Ok(v) => Ok(v),
            Err(_) => Err(format!("`{s}` is not a number")),
        }
    };
    match kind {
        Kind::Text => Ok(()),
        Kind::Unknown => bad("is in a column without a rule"),
        Kind::Choice(words) => {
            if words.contains(&s) {
                Ok(())
            } else {
                bad(&format!("is not one of {}", words.join(", ")))
            }
        }
        Kind::Bool => match s {
            "true" | "false" => Ok(()),
            _ => bad("is not true or false"),
        },
        Kind::Count => match s.parse::<u64>() {
            Ok(_) => Ok(()),
            Err(_) => bad("is not a non-negative integer"),
        },
        Kind::Distance | Kind::ExtendedOrEmpty | Kind::FiniteOrEmpty if s.is_empty() => Ok(()),
        Kind::Finite | Kind::FiniteOrEmpty => match number(s)? {
            v if v.is_finite() => Ok(()),
            _ => bad("is not finite"),
        },
        Kind::NonNegative => match number(s)? {
            v if v.is_finite() && v >= 0.0 => Ok(()),
            _ => bad("is not a finite number >= 0"),
        },
        Kind::Distance => match number(s)? {
            v if v >= 0.0 => Ok(()),
            _ => bad("is negative"),
        },
        Kind::Extended | Kind::ExtendedOrEmpty => number(s).map(|_| ()),
    }
}

/// Check a row against `header` (its length and every field's rule from [`COLUMNS`]).
pub fn check_row(header: &[impl AsRef<str>], row: &[impl AsRef<str>]) -> Result<(), String> {
    check_row_with(header, &columns_of(header), row)
}

/// Check a row against `header` with the rules `cols` (one per header name).
pub fn check_row_with(
    header: &[impl AsRef<str>],
    cols: &[Column],
    row: &[impl AsRef<str>],
) -> Result<(), String> {
    if row.len() != header.len() {
        return Err(format!(
            "has {} fields, the header has {}",
            row.len(),
            header.len()
        ));
    }
    for ((h, c), f) in header.iter().zip(cols).zip(row) {
        check_value(c.kind, f.as_ref()).map_err(|e| format!("{}: {e}", h.as_ref()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::CsvRecord;

    /// Every sweep output's header is covered by the table, once per name.
    #[test]
    fn every_sweep_column_has_a_rule() {
        for header in [
            crate::records::BOUNDARY_HEADER,
            crate::records::REACH_HEADER,
            crate::records::bifurcation::BifurcationRecord::HEADER,
            crate::records::layout::RayRecord::HEADER,
            crate::records::detect::DetectRunRecord::HEADER,
        ] {
            check_known(header, &columns_of(header)).unwrap();
        }
        let mut names: Vec<_> = COLUMNS.iter().map(|c| c.name).collect();
        names.sort_unstable();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n, "a column is listed twice");
    }

    #[test]
    fn fields_by_kind() {
        let c = |n| column(n).unwrap();
        assert!(check_field(c("s_star"), "").is_ok());
        assert!(check_field(c("s_star"), "inf").is_ok());
        assert!(check_field(c("s_star"), "-1").is_err());
        assert!(check_field(c("s_star"), "nan").is_err());
        assert!(check_field(c("kappa"), "-inf").is_ok());
        assert!(check_field(c("kappa"), "").is_ok());
        assert!(check_field(c("dir_kappa"), "").is_err());
        assert!(check_field(c("dir_kappa"), "inf").is_err());
        assert!(check_field(c("class"), "testable").is_ok());
        assert!(check_field(c("class"), "maybe").is_err());
        assert!(check_field(c("n_waypoints"), "3.5").is_err());
        assert!(check_field(c("n_waypoints"), "12").is_ok());
        assert!(check_row(&["s_star"], &["1", "2"]).is_err());
    }
}
