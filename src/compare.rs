//! Measured versus simulated stability boundaries (the seed paper's comparison, [architecture §7](crate::architecture)).
//!
//! Per measured direction S̄ with measured snap distance `s_measured` and a simulated boundary
//! `s_sim` on the same ray:
//!
//! - `err = |s_measured − s_sim| / s_sim` (the paper's relative error),
//! - `signed_diff = s_measured − s_sim` (> 0: the real rod held on past the prediction).
//!
//! [`Comparison::stats`] gives the count, mean, maximum and **population** standard deviation
//! (divisor N) of `err`, and the mean signed difference, over the directions that have a
//! simulated value. Directions without one (absent from the boundary file, or `s_sim = ∞`)
//! keep their row, with empty simulated fields, and are listed in [`Comparison::missing`].
//!
//! # Input (read by `records::compare::read_measured`; this module imports no file format)
//! `read_measured` reads a CSV with exactly the columns `dir_kappa,dir_tau,dir_omega,s_measured`
//! (any order; an unknown column is an error, so a misspelt column is never silently ignored),
//! or the output of `helixreach detect --runs` (those four and the other columns of
//! `DetectRunRecord`), whose rows with an empty
//! `s_measured` (no snap seen) are skipped with one note.
//! Every value must be finite, `s_measured > 0`, κ̂ ≥ 0. A direction that is not a unit vector
//! is normalized and a note is returned (the caller prints it), as `helixreach boundary` does.
//! Boundary values are matched to measured directions by direction (largest component
//! difference ≤ [`MATCH_TOL`] after normalization).
//!
//! ```
//! use helixreach::compare::{compare, Measured};
//! use helixreach::directions::Direction;
//! let m = vec![
//!     Measured { dir: Direction::new(1.0, 0.0, 0.0)?, s_measured: 6.6, line: 2 },
//!     Measured { dir: Direction::new(0.0, 1.0, 0.0)?, s_measured: 9.0, line: 3 },
//! ];
//! let c = compare(&m, &[Some(6.0), None]);
//! assert!((c.rows[0].err.unwrap() - 0.1).abs() < 1e-12);
//! assert_eq!(c.missing, vec![1]);
//! assert_eq!(c.stats.count, 1);
//! # Ok::<(), helixreach::Error>(())
//! ```

use crate::directions::Direction;
use crate::math::Real;

/// Largest component difference between two unit directions that are the same ray.
pub const MATCH_TOL: Real = 1e-5;
/// A direction whose norm differs from 1 by more than this is reported as normalized.
pub const NORM_NOTE_TOL: Real = 1e-6;

/// One measured snap point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// The unit direction.
    pub dir: Direction,
    /// Where the rod was seen to leave the helix.
    pub s_measured: Real,
    /// 1-based line of the file (header = 1).
    pub line: usize,
}

/// A measured file and the notes made while reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredSet {
    /// Rows in file order.
    pub rows: Vec<Measured>,
    /// Notes (normalized directions), one per affected line.
    pub notes: Vec<String>,
}

/// Whether `a` and `b` are the same ray (largest component difference ≤ [`MATCH_TOL`]).
fn same_ray(a: &Direction, b: &Direction) -> bool {
    (a.kappa - b.kappa)
        .abs()
        .max((a.tau - b.tau).abs())
        .max((a.omega - b.omega).abs())
        <= MATCH_TOL
}

/// For each measured direction, the boundary value of the same direction in `boundary`
/// (`(direction, s*)` pairs), or `None` when absent or infinite.
pub fn match_boundary(measured: &[Measured], boundary: &[(Direction, Real)]) -> Vec<Option<Real>> {
    measured
        .iter()
        .map(|m| {
            boundary
                .iter()
                .find(|(d, _)| same_ray(d, &m.dir))
                .and_then(|(_, s)| s.is_finite().then_some(*s))
        })
        .collect()
}

/// For each measured direction, whether `boundary` has a row on it (whatever its value), and
/// the angle (rad) to the nearest boundary direction: what tells a boundary computed on another
/// direction set (no measured direction in it) from one with infinite or missing values.
pub fn boundary_rows_on(measured: &[Measured], boundary: &[Direction]) -> Vec<(bool, Real)> {
    measured
        .iter()
        .map(|m| {
            let on = boundary.iter().any(|d| same_ray(d, &m.dir));
            let nearest = boundary
                .iter()
                .map(|d| {
                    let dot = d.kappa * m.dir.kappa + d.tau * m.dir.tau + d.omega * m.dir.omega;
                    dot.clamp(-1.0, 1.0).acos()
                })
                .fold(Real::INFINITY, Real::min);
            (on, nearest)
        })
        .collect()
}

/// One row of the comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComparisonRow {
    /// The direction.
    pub dir: Direction,
    /// Measured s.
    pub s_measured: Real,
    /// Simulated s*, if any.
    pub s_sim: Option<Real>,
    /// `|s_measured − s_sim|/s_sim`.
    pub err: Option<Real>,
    /// `s_measured − s_sim`.
    pub signed_diff: Option<Real>,
}

/// Summary statistics of `err` over the rows with a simulated value.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Rows with a simulated value.
    pub count: usize,
    /// Mean of err.
    pub mean: Real,
    /// Maximum of err.
    pub max: Real,
    /// Population standard deviation of err (divisor N).
    pub std: Real,
    /// Mean of `s_measured − s_sim`.
    pub mean_signed_diff: Real,
}

/// The comparison of a measured set with simulated values.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// One row per measured direction, in its order.
    pub rows: Vec<ComparisonRow>,
    /// Statistics over the rows with a simulated value.
    pub stats: Stats,
    /// Indices (into `rows`) of directions without a simulated value.
    pub missing: Vec<usize>,
}

/// Compare `measured` with `sim` (same length and order; `None` = no simulated value).
///
/// # Panics
/// If the lengths differ (a programming error).
pub fn compare(measured: &[Measured], sim: &[Option<Real>]) -> Comparison {
    assert_eq!(
        measured.len(),
        sim.len(),
        "one simulated value per direction"
    );
    let mut rows = Vec::with_capacity(measured.len());
    let mut missing = Vec::new();
    for (i, (m, s)) in measured.iter().zip(sim).enumerate() {
        let s = s.filter(|x| x.is_finite() && *x > 0.0);
        if s.is_none() {
            missing.push(i);
        }
        rows.push(ComparisonRow {
            dir: m.dir,
            s_measured: m.s_measured,
            s_sim: s,
            err: s.map(|x| (m.s_measured - x).abs() / x),
            signed_diff: s.map(|x| m.s_measured - x),
        });
    }
    let errs: Vec<Real> = rows.iter().filter_map(|r| r.err).collect();
    let n = errs.len();
    let (mean, max, std, msd) = if n == 0 {
        (Real::NAN, Real::NAN, Real::NAN, Real::NAN)
    } else {
        let mean = errs.iter().sum::<Real>() / n as Real;
        let var = errs.iter().map(|e| (e - mean).powi(2)).sum::<Real>() / n as Real;
        let msd = rows.iter().filter_map(|r| r.signed_diff).sum::<Real>() / n as Real;
        (
            mean,
            errs.iter().cloned().fold(0.0, Real::max),
            var.sqrt(),
            msd,
        )
    };
    Comparison {
        rows,
        stats: Stats {
            count: n,
            mean,
            max,
            std,
            mean_signed_diff: msd,
        },
        missing,
    }
}

impl Comparison {
    /// The JSON summary: `{count, mean, max, std, std_kind: "population", mean_signed_diff,
    /// missing: [{line, dir_kappa, dir_tau, dir_omega}]}` (`lines` are those of `measured`).
    pub fn summary_json(&self, measured: &[Measured]) -> serde_json::Value {
        let num = |x: Real| {
            if x.is_finite() {
                serde_json::json!(x)
            } else {
                serde_json::Value::Null
            }
        };
        let missing: Vec<serde_json::Value> = self
            .missing
            .iter()
            .map(|&i| {
                let d = self.rows[i].dir;
                serde_json::json!({
                    "line": measured.get(i).map(|m| m.line),
                    "dir_kappa": d.kappa, "dir_tau": d.tau, "dir_omega": d.omega,
                })
            })
            .collect();
        serde_json::json!({
            "count": self.stats.count,
            "mean": num(self.stats.mean),
            "max": num(self.stats.max),
            "std": num(self.stats.std),
            "std_kind": "population",
            "mean_signed_diff": num(self.stats.mean_signed_diff),
            "missing": missing,
        })
    }
}
