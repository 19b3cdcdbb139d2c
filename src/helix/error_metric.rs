//! The seed paper's helix error metric e and a safe form of it.
//!
//! The paper measures how far a rod's nodes q_i are from the nodes q_iʰ of the predicted helix,
//! averaged and normalized by the helix radius R = κ/(κ² + τ²):
//!
//! e = 1/(n+1) · Σᵢ (κ² + τ²)/κ · |q_i − q_iʰ|      ([`paper_error`]).
//!
//! For a rod of physical length L with nondimensional (κ, τ), R = L·κ/(κ²+τ²).
//!
//! # The safe form
//! 1/R = κ + τ²/κ blows up as κ → 0 at τ ≠ 0 (a straight twisted rod has radius 0), and R → ∞ as
//! κ, τ → 0 along τ = o(κ) (the metric then ignores any deviation: every ray starts there).
//! [`safe_error`] normalizes by the radius **clamped to [ρ_min·L, L]**:
//!
//! e_safe = 1/(n+1) · Σᵢ |q_i − q_iʰ| / ρ,   ρ = L · clamp(κ/(κ²+τ²), ρ_min, 1),
//!
//! with ρ_min = [`RADIUS_FLOOR`] by default. It equals the paper's e whenever
//! ρ_min·L ≤ R ≤ L (every helix near the stability boundaries of the seed experiment), is finite
//! for every valid helix including κ = 0 and κ = τ = 0, and stays sensitive to deviations near
//! the straight rod. It is evaluated without dividing by κ or λ², so it has no branch on zero.

use super::Helix;
use crate::error::{Error, Result};
use crate::math::{Real, Vec3};

/// Default floor ρ_min of the normalizing radius in [`safe_error`], as a fraction of the rod
/// length (dimensionless). 1 % of L: helices in the experiment have R ≳ 0.02 L.
pub const RADIUS_FLOOR: Real = 1e-2;

/// The helix radius R = κ/(κ² + τ²) (nondimensional, L = 1), the exact quotient: 0 at κ = 0,
/// τ ≠ 0, and NaN at κ = τ = 0 (a straight rod has no radius). Prefer [`normalizing_radius`],
/// which is always finite.
pub fn helix_radius(h: &Helix) -> Real {
    h.kappa() / (h.kappa() * h.kappa() + h.tau() * h.tau())
}

/// ρ/L = clamp(κ/(κ²+τ²), `rho_min`, 1), evaluated without forming 0/0: R ≥ 1 ⇔ κ² + τ² ≤ κ.
/// At κ = τ = 0 (the straight untwisted rod, where every ray starts and R → ∞ along any ray with
/// κ̂ > 0) it is 1; at κ = 0 < |τ| it is `rho_min`.
pub fn normalizing_radius(h: &Helix, rho_min: Real) -> Real {
    let (k, t) = (h.kappa(), h.tau());
    let l2 = k * k + t * t;
    let r = if l2 <= k { 1.0 } else { k / l2 };
    r.max(rho_min)
}

fn check(q: &[Vec3], q_helix: &[Vec3]) -> Result<()> {
    if q.is_empty() || q.len() != q_helix.len() {
        return Err(Error::invalid(
            "nodes",
            format!("{} vs {}", q.len(), q_helix.len()),
            "rod and helix need the same non-zero number of nodes",
        ));
    }
    for (name, set) in [("q", q), ("q_helix", q_helix)] {
        if let Some(i) = set.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
            return Err(Error::invalid(
                format!("{name}[{i}]"),
                format!("{:?}", set[i].as_slice()),
                "node coordinates must be finite",
            ));
        }
    }
    Ok(())
}

fn mean_deviation(q: &[Vec3], q_helix: &[Vec3]) -> Real {
    q.iter()
        .zip(q_helix)
        .map(|(a, b)| (a - b).norm())
        .sum::<Real>()
        / q.len() as Real
}

/// The paper's e for nodes `q` against the helix nodes `q_helix` (both in the unit of `length`),
/// for the helix `h` (nondimensional) of a rod of length `length`. Errors on mismatched or
/// non-finite nodes, on `length` ≤ 0, and on κ = 0, where the paper's e is undefined (use
/// [`safe_error`]).
///
/// ```
/// use helixreach::helix::{discrete, error_metric::paper_error, Helix};
/// let h = Helix::new(3.0, 4.0, 0.0).unwrap(); // R = 3/25
/// let q = discrete::nodes(&h, 8);
/// assert_eq!(paper_error(&q, &q, &h, 1.0).unwrap(), 0.0);
/// let shifted: Vec<_> = q.iter().map(|p| p + nalgebra::Vector3::new(0.0, 0.0, 0.012)).collect();
/// assert!((paper_error(&shifted, &q, &h, 1.0).unwrap() - 0.1).abs() < 1e-12);
/// ```
pub fn paper_error(q: &[Vec3], q_helix: &[Vec3], h: &Helix, length: Real) -> Result<Real> {
    check(q, q_helix)?;
    let length = crate::error::require_positive("length", length)?;
    if h.kappa() <= 0.0 {
        return Err(Error::invalid(
            "kappa",
            h.kappa(),
            "the paper's error metric divides by kappa; use safe_error at kappa = 0",
        ));
    }
    let inv_r = (h.kappa() * h.kappa() + h.tau() * h.tau()) / h.kappa() / length;
    Ok(inv_r * mean_deviation(q, q_helix))
}

/// The safe form e_safe (module docs) with the floor `rho_min` ∈ (0, 1] (use
/// [`RADIUS_FLOOR`]). Finite for every valid helix; zero iff every node matches.
///
/// ```
/// use helixreach::helix::{discrete, error_metric::{safe_error, RADIUS_FLOOR}, Helix};
/// let h = Helix::new(0.0, 5.0, 1.0).unwrap(); // straight twisted rod: paper's e undefined
/// let q = discrete::nodes(&h, 4);
/// let moved: Vec<_> = q.iter().map(|p| p + nalgebra::Vector3::new(1e-3, 0.0, 0.0)).collect();
/// let e = safe_error(&moved, &q, &h, 1.0, RADIUS_FLOOR).unwrap();
/// assert!((e - 0.1).abs() < 1e-12); // 1e-3 / (0.01 · L)
/// ```
pub fn safe_error(
    q: &[Vec3],
    q_helix: &[Vec3],
    h: &Helix,
    length: Real,
    rho_min: Real,
) -> Result<Real> {
    check(q, q_helix)?;
    let length = crate::error::require_positive("length", length)?;
    if !(rho_min > 0.0 && rho_min <= 1.0) {
        return Err(Error::invalid("rho_min", rho_min, "must lie in (0, 1]"));
    }
    let rho = normalizing_radius(h, rho_min) * length;
    Ok(mean_deviation(q, q_helix) / rho)
}
