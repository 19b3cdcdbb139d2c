//! The comparison of measured snap points with simulated s* (`helixreach compare --out`): one row
//! per measured direction, in the measured file's order, columns [`ComparisonRecord::HEADER`].
//! Directions without a simulated value have empty `s_sim`, `err`, `signed_diff`.
//!
//! The measured input ([`read_measured`]): a CSV with exactly the columns
//! [`MEASURED_COLUMNS`] (any order; an unknown column is an error), or the output of
//! `helixreach detect --runs` ([`DetectRunRecord`](super::detect::DetectRunRecord)), whose rows
//! with an empty `s_measured` (no snap seen) are skipped with one note. Every value finite,
//! `s_measured > 0`, κ̂ ≥ 0; a direction that is not a unit vector is normalized with a note
//! ([`crate::compare`]'s contract).

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::compare::{Comparison, ComparisonRow, Measured, MeasuredSet, NORM_NOTE_TOL};
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::io::{bad_line, parse_field, CsvInput};
use crate::math::Real;
use std::path::Path;

/// The measured-file columns.
pub const MEASURED_COLUMNS: [&str; 4] = ["dir_kappa", "dir_tau", "dir_omega", "s_measured"];

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

/// Read a measured-boundary CSV (see the module docs); errors name the file, line and field.
pub fn read_measured(path: &Path) -> Result<MeasuredSet> {
    let mut t = CsvInput::open(path)?;
    let headers: Vec<String> = match t.reader.headers() {
        Ok(h) => h.iter().map(str::to_string).collect(),
        Err(e) => return Err(t.file_error(e.to_string())),
    };
    let detect_columns = super::detect::DetectRunRecord::HEADER;
    let is_detect = headers.iter().any(|h| h == "reason");
    for h in &headers {
        if !(MEASURED_COLUMNS.contains(&h.as_str())
            || (is_detect && detect_columns.contains(&h.as_str())))
        {
            return Err(t.file_error(format!(
                "unknown column `{h}` (expected exactly {})",
                MEASURED_COLUMNS.join(",")
            )));
        }
    }
    let hint = "header must be dir_kappa,dir_tau,dir_omega,s_measured";
    let cols = [
        t.column("dir_kappa", hint)?,
        t.column("dir_tau", hint)?,
        t.column("dir_omega", hint)?,
        t.column("s_measured", hint)?,
    ];
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    let mut no_snap = 0;
    for (k, rec) in t.reader.records().enumerate() {
        let rec = rec.map_err(|e| bad_line(path, k + 2, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, k + 2);
        if is_detect && rec.get(cols[3]).is_some_and(str::is_empty) {
            no_snap += 1;
            continue;
        }
        let mut v = [0.0; 4];
        for (i, (&c, name)) in cols.iter().zip(MEASURED_COLUMNS).enumerate() {
            let x = parse_field(path, line, &rec, c, name)?;
            if !x.is_finite() {
                return Err(bad_line(path, line, name, format!("{x} is not finite")));
            }
            v[i] = x;
        }
        if v[3] <= 0.0 {
            return Err(bad_line(
                path,
                line,
                "s_measured",
                format!("{} must be > 0", v[3]),
            ));
        }
        let dir = Direction::new(v[0], v[1], v[2])
            .map_err(|e| bad_line(path, line, "direction", e.to_string()))?;
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if (norm - 1.0).abs() > NORM_NOTE_TOL {
            notes.push(format!(
                "{}:{line}: direction ({}, {}, {}) has norm {norm}; normalized",
                path.display(),
                v[0],
                v[1],
                v[2]
            ));
        }
        rows.push(Measured {
            dir,
            s_measured: v[3],
            line,
        });
    }
    if no_snap > 0 {
        notes.push(format!(
            "{}: {no_snap} runs without a snap (empty s_measured) skipped",
            path.display()
        ));
    }
    if rows.is_empty() {
        return Err(Error::File {
            path: path.to_path_buf(),
            reason: "no measured directions".into(),
        });
    }
    Ok(MeasuredSet { rows, notes })
}

/// The comparison CSV text (header [`ComparisonRecord::HEADER`], one row per measured
/// direction).
pub fn comparison_csv(c: &Comparison) -> Result<String> {
    let rows: Vec<ComparisonRecord> = c.rows.iter().map(Into::into).collect();
    csv_out::to_csv(&rows)
}
