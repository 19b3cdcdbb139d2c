//! Direction sets: unit vectors S̄ = (κ̂, τ̂, ω̂) on the half-sphere κ̂ ≥ 0 along which the
//! experiment drives the rod, (κ, τ, ω) = s·S̄.
//!
//! - [`fibonacci`]: a deterministic, near-uniform (equal-area) Fibonacci lattice of any size on the
//!   half-sphere κ̂ ≥ 0, or on the quarter κ̂ ≥ 0, τ̂ > 0 used by the experiment.
//!   Half-sphere: point i has κ̂ = (i + ½)/n (uniform in the height above the κ̂ = 0 plane, which is
//!   equal-area by Archimedes) and azimuth ψ = 2π·frac(i/φ) in the τ̂ω̂ plane (φ the golden ratio).
//!   Quarter: the pole is the τ̂ axis instead, τ̂ = (i + ½)/n, and ψ ∈ [−π/2, π/2] with
//!   κ̂ = ρ cos ψ, ω̂ = ρ sin ψ.
//! - [`read_csv`]: directions from a CSV file with columns `dir_kappa,dir_tau,dir_omega` (other
//!   columns are ignored), normalized on read. A zero or non-finite vector, or κ̂ < 0, is an error
//!   naming the line.
//!
//! ```
//! let d = helixreach::directions::fibonacci(1000, false).unwrap();
//! assert_eq!(d.len(), 1000);
//! assert!(d.iter().all(|s| s.kappa >= 0.0 && (s.norm() - 1.0).abs() < 1e-15));
//! ```

use crate::error::{Error, Result};
use crate::math::Real;
use std::path::Path;

/// Below this norm the sum of squares has lost precision to underflow (its terms fall below
/// ~1e-308 when the components are below ~1e-154), so [`Direction::new`] normalizes by the
/// largest component first. A range limit of f64, not a tolerance.
const SQUARES_SAFE_NORM: Real = 1e-150;

/// A unit direction in (κ, τ, ω) space.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Direction {
    /// κ̂ ≥ 0.
    pub kappa: Real,
    /// τ̂.
    pub tau: Real,
    /// ω̂.
    pub omega: Real,
}

impl Direction {
    /// Normalize `(kappa, tau, omega)`; errors on a zero or non-finite vector or κ < 0. Any
    /// finite non-zero vector normalizes, from subnormal components to 1e308.
    ///
    /// ```
    /// use helixreach::directions::Direction;
    /// let d = Direction::new(1e308, 1e308, 0.0).unwrap();
    /// assert!((d.kappa - 0.5f64.sqrt()).abs() < 1e-15 && (d.tau - d.kappa).abs() < 1e-15);
    /// let d = Direction::new(0.0, 5e-324, 0.0).unwrap();
    /// assert_eq!(d.tau, 1.0);
    /// ```
    pub fn new(kappa: Real, tau: Real, omega: Real) -> Result<Self> {
        for (name, v) in [("dir_kappa", kappa), ("dir_tau", tau), ("dir_omega", omega)] {
            if !v.is_finite() {
                return Err(Error::invalid(name, v, "must be finite"));
            }
        }
        if kappa < 0.0 {
            return Err(Error::invalid(
                "dir_kappa",
                kappa,
                "must be >= 0 (curvature is non-negative)",
            ));
        }
        let n = (kappa * kappa + tau * tau + omega * omega).sqrt();
        if n.is_finite() && n >= SQUARES_SAFE_NORM {
            return Ok(Direction {
                kappa: kappa / n,
                tau: tau / n,
                omega: omega / n,
            });
        }
        // The squares overflowed (components near 1e308) or lost precision to underflow (below
        // 1e-154): normalize by the largest component first.
        let m = kappa.abs().max(tau.abs()).max(omega.abs());
        if m == 0.0 {
            let f = crate::error::fmt_num;
            return Err(Error::invalid(
                "direction",
                format!("({}, {}, {})", f(kappa), f(tau), f(omega)),
                "must be a non-zero vector",
            ));
        }
        let (k, t, w) = (kappa / m, tau / m, omega / m);
        let n = (k * k + t * t + w * w).sqrt();
        Ok(Direction {
            kappa: k / n,
            tau: t / n,
            omega: w / n,
        })
    }

    /// Euclidean norm (1 for a normalized direction).
    pub fn norm(&self) -> Real {
        (self.kappa * self.kappa + self.tau * self.tau + self.omega * self.omega).sqrt()
    }

    /// The point s·S̄ as `[κ, τ, ω]`.
    pub fn at(&self, s: Real) -> [Real; 3] {
        [s * self.kappa, s * self.tau, s * self.omega]
    }
}

/// A deterministic Fibonacci lattice of `n` directions on the half-sphere κ̂ ≥ 0, or on the
/// quarter κ̂ ≥ 0, τ̂ > 0 when `quarter` is true. `n = 0` is an error.
pub fn fibonacci(n: usize, quarter: bool) -> Result<Vec<Direction>> {
    if n == 0 {
        return Err(Error::invalid(
            "fibonacci",
            n,
            "the direction set must not be empty",
        ));
    }
    crate::limits::check_size("fibonacci", n, crate::limits::MAX_DIRECTIONS)?;
    let inv_phi = (5.0_f64.sqrt() - 1.0) / 2.0;
    let pi = std::f64::consts::PI;
    Ok((0..n)
        .map(|i| {
            let h = (i as Real + 0.5) / n as Real;
            let rho = (1.0 - h * h).max(0.0).sqrt();
            let frac = (i as Real * inv_phi).fract();
            if quarter {
                let psi = -0.5 * pi + pi * frac;
                Direction {
                    kappa: rho * psi.cos(),
                    tau: h,
                    omega: rho * psi.sin(),
                }
            } else {
                let psi = 2.0 * pi * frac;
                Direction {
                    kappa: h,
                    tau: rho * psi.cos(),
                    omega: rho * psi.sin(),
                }
            }
        })
        .collect())
}

/// Read directions from a CSV file with a header containing `dir_kappa,dir_tau,dir_omega`.
///
/// Two rows that normalize to the same direction (`1,1,1` and `2,2,2`) are an error naming
/// both lines: a sweep keys its rows by the normalized direction, so a repeated direction would
/// be computed twice and could never be resumed or merged.
pub fn read_csv(path: &Path) -> Result<Vec<Direction>> {
    let mut table = crate::io::CsvInput::open(path)?;
    let hint = "header must contain dir_kappa,dir_tau,dir_omega";
    let col = |name: &str| table.column(name, hint);
    let (ik, it, iw) = (col("dir_kappa")?, col("dir_tau")?, col("dir_omega")?);
    let mut out = Vec::new();
    let mut seen: std::collections::HashMap<[u64; 3], usize> = std::collections::HashMap::new();
    for (k, rec) in table.reader.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| crate::io::bad_line(path, line, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, line);
        let get = |i: usize, name: &str| crate::io::parse_field(path, line, &rec, i, name);
        let (a, b, c) = (
            get(ik, "dir_kappa")?,
            get(it, "dir_tau")?,
            get(iw, "dir_omega")?,
        );
        let d = Direction::new(a, b, c)
            .map_err(|e| crate::io::bad_line(path, line, "direction", e.to_string()))?;
        if out.len() == crate::limits::MAX_DIRECTIONS {
            return Err(table.file_error(format!(
                "more than {} directions (helixreach::limits::MAX_DIRECTIONS)",
                crate::limits::MAX_DIRECTIONS
            )));
        }
        // -0 and 0 are one direction.
        let bits = |x: Real| (x + 0.0).to_bits();
        if let Some(first) = seen.insert([bits(d.kappa), bits(d.tau), bits(d.omega)], line) {
            return Err(crate::io::bad_line(
                path,
                line,
                "direction",
                format!(
                    "({}, {}, {}) normalizes to the direction of line {first}: each direction \
                     may appear once",
                    rec.get(ik).unwrap_or(""),
                    rec.get(it).unwrap_or(""),
                    rec.get(iw).unwrap_or("")
                ),
            ));
        }
        out.push(d);
    }
    if out.is_empty() {
        return Err(table.file_error("no directions (the direction set must not be empty)".into()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_is_equal_area() {
        // Equal-area ⇒ the fraction of points in a cap κ̂ > h is 1 − h (Archimedes).
        let d = fibonacci(20_000, false).unwrap();
        for &h in &[0.2, 0.5, 0.9] {
            let f = d.iter().filter(|s| s.kappa > h).count() as f64 / d.len() as f64;
            assert!((f - (1.0 - h)).abs() < 1e-3, "cap {h}: {f}");
        }
        // And the hemisphere halves ω̂ > 0 / ω̂ < 0 are balanced.
        let pos = d.iter().filter(|s| s.omega > 0.0).count() as f64 / d.len() as f64;
        assert!((pos - 0.5).abs() < 2e-3);
    }

    #[test]
    fn quarter_is_in_quarter() {
        let d = fibonacci(5000, true).unwrap();
        assert!(d.iter().all(|s| s.kappa >= 0.0 && s.tau > 0.0));
        let f = d.iter().filter(|s| s.kappa > 0.5).count() as f64 / d.len() as f64;
        // Area of {κ̂ > 0.5} within the quarter sphere κ̂>0, τ̂>0: the cap κ̂>0.5 is half the
        // κ̂>0 hemisphere's 2π·(1−0.5) = π, halved by τ̂>0: π/2, over the quarter's π: 0.5.
        assert!((f - 0.5).abs() < 2e-3, "{f}");
    }

    #[test]
    fn bad_directions_are_errors() {
        assert!(Direction::new(0.0, 0.0, 0.0).is_err());
        assert!(Direction::new(-0.1, 1.0, 0.0).is_err());
        assert!(Direction::new(f64::NAN, 1.0, 0.0).is_err());
        assert!(fibonacci(0, false).is_err());
    }

    #[test]
    fn csv_errors_name_the_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("d.csv");
        std::fs::write(&p, "dir_kappa,dir_tau,dir_omega\n1,2,2\n-1,0,0\n").unwrap();
        let e = read_csv(&p).unwrap_err().to_string();
        assert!(e.contains(":3:") && e.contains("dir_kappa"), "{e}");
        std::fs::write(&p, "dir_kappa,dir_tau,dir_omega\n1,2,2\n").unwrap();
        let d = read_csv(&p).unwrap();
        assert!((d[0].kappa - 1.0 / 3.0).abs() < 1e-16);
    }
}
