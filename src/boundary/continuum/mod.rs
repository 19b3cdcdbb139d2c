//! Continuum (Kirchhoff rod) conjugate-point stability test: the exact reference boundary.
//!
//! # Model
//! An inextensible, unshearable, isotropic, initially straight Kirchhoff rod of length 1, bending
//! stiffness 1 and twisting stiffness `c = 1/(1+ν)`, clamped at both ends. Its equilibria are
//! solutions of (body frame, arc length t)
//!
//! ```text
//! R' = R [u]×,  r' = R e3,  m' = −u × m − e3 × n,  n' = −u × n,  u = K⁻¹ m,  K = diag(1, 1, c)
//! ```
//!
//! with `(m, n)` the internal wrench. Following Bretl & McCarthy (IJRR 2014, "Quasi-static
//! manipulation of a Kirchhoff elastic rod based on a geometric analysis of equilibrium
//! configurations") the equilibria are parametrized by the base wrench `a = (m(0), n(0))`; the
//! variational (Jacobi) equations give `M(t) = ∂(m, n)(t)/∂a` (`M(0) = I`) and
//! `J(t) = ∂(pose)(t)/∂a` (`J(0) = 0`), both 6×6. With pose perturbations written in the body frame,
//! `R → R(I + [α]×)`, `r → r + Rβ`:
//!
//! ```text
//! α'  = −u × α + K⁻¹ δm          δm' = m × K⁻¹δm − u × δm − e3 × δn
//! β'  = α × e3 − u × β           δn' = n × K⁻¹δm − u × δn
//! ```
//!
//! The equilibrium is stable iff `det J(t) ≠ 0` for all `t ∈ (0, 1]` (no conjugate point);
//! Borum & Bretl (PRL 2020, "Geometric analysis of the stability of helical rods") apply this to
//! helices and show the stable set is star-convex in (κ, τ, ω) and independent of `c`.
//!
//! # Helices: constant coefficients in the Frenet frame
//! The helix (κ, τ, ω) has, in its Frenet frame `[N B T]`, the constant Darboux vector
//! `w = (0, κ, τ)`, moment `m = κB + ωT = (0, κ, ω)` and force `n = (ω − τ)(0, κ, τ)` (which solves
//! `m' + T × n = 0`, `n' = 0`). The material frame is the Frenet frame turned about `T` by
//! `θ(t) = (ω/c − τ)t`; rotating every vector of the Jacobi system into the Frenet frame
//! (`v_F = R_z(θ) v_D`, a change of variables of determinant 1, which commutes with `K` because
//! the rod is isotropic) turns `u` into `w` and gives **constant** coefficients:
//! `z' = A z`, `z = (α, β, δm, δn)` (see `kernel::generator`). Hence `Z(t) = exp(tA)·[0; I]`.
//!
//! # Balancing for κ → 0
//! On a straight rod an axial force does not change the shape and the end cannot move axially
//! to first order, so the `δn_z` column and the `β_z` row of `J` are `O(κ)` and `det J = O(κ²)`:
//! for κ ≲ 1e-154 it leaves the normal range and its sign and size are rounding noise (unbalanced,
//! the direction `1e-160, 1, 0` gives s* = 1.3 instead of the limit 2π). The scan therefore
//! propagates the balanced variables `β_z/κ` and `κ·δn_z` (`kernel::generator_balanced`, a
//! positive diagonal similarity that keeps the sign and zeros of `det J`), whose generator is
//! bounded with a nondegenerate limit as κ → 0: every representable κ̂ > 0 is resolved, and
//! s* → the κ → 0⁺ limit continuously (tested down to the smallest subnormal).
//!
//! # Scaling: one propagation per direction, no bisection on s
//! The helix `s·S̄` on `[0, t]` is the helix `S̄` on `[0, s·t]` shrunk by `s` (curvatures scale
//! as `s`, moments as `s`, forces as `s²`; the equations are homogeneous). So the first conjugate
//! time of `s·S̄` is `t_c(S̄)/s`, and the critical distance along a unit direction is
//! `s* = t_c(S̄)`: the first zero of `det J` of the **unit-direction** helix continued past
//! `t = 1`. [`critical_s`] computes that zero; [`is_stable`] compares `|(κ, τ, ω)|` with it.
//!
//! # Detecting every zero of det J
//! `det J` may touch zero without changing sign (a double root: the conjugate-point kernel is
//! two-dimensional when the helix has a rotational symmetry) or have two roots closer than a step.
//! The scan therefore
//! 1. propagates exactly with `E = exp(hA)` (Taylor series with scaling and squaring, error
//!    ≲ 1e-16) and re-orthonormalizes the 12×6 frame every step (Gram–Schmidt, `Z ← Z·R⁻¹` with
//!    `det R > 0`: the sign and zeros of `det J` are those of the column span), so the sampled
//!    `q(t_k) = det J(t_k)` is scale-free in `[−1, 1]` and never overflows;
//! 2. brackets a root at every sign change of `q`;
//! 3. at every local minimum of `|q_k|` without a sign change, searches the two surrounding steps
//!    (golden section on the Taylor expansion of the frame) for a negative value (a hidden pair:
//!    the first root is then bracketed) or a value below `1e-13` (a tangency: a double root);
//! 4. refines the first root by Newton on `det J` (`(det J)'/det J = tr(J⁻¹J')`, with `J` and `J'`
//!    from a Taylor expansion of `exp(δA)` around the last sample), safeguarded by bisection, to the
//!    caller's relative tolerance.
//!
//! The step `h` (default [`DEFAULT_STEP`] = 0.2) resolves the oscillations of `det J`: over one
//! step `det J` is smooth enough that a pair of roots always leaves a local minimum of `|q_k|`
//! (tests compare with a 16× finer step and with direct RK integration).
//!
//! # The κ = 0 plane
//! Exactly on κ = 0 the rod is straight, twisted by the moment ω. Torsion is undefined for a
//! straight line, and because the rod is inextensible its axial force is indeterminate (and
//! `det J ≡ 0`: an axial force does not change the shape, and the end cannot move axially to first
//! order). helixreach takes the physical tension-free state (the end held one rod length from the
//! clamp): Greenhill's clamped twisted rod, stable iff `|ω| < 2x₁`, `tan x₁ = x₁`
//! (`2x₁ ≈ 8.9868`). So on κ̂ = 0 (the only branch on κ) `s* = 2x₁/|ω̂|`, and `s* = ∞` on the
//! τ axis (straight, untwisted rod). This is discontinuous: as κ̂ → 0⁺ the helix keeps the axial
//! force `(ω − τ)τ` and `s*` tends to the buckling load of that column (`2π` on the τ axis; the
//! ω axis, where the force vanishes, is continuous).
//!
//! ```
//! use helixreach::boundary::continuum::{critical_s, is_stable};
//! use helixreach::directions::Direction;
//! // The κ axis: the arc closes into a circle at s = 2π.
//! let r = critical_s(&Direction::new(1.0, 0.0, 0.0)?, 1e-10)?;
//! assert!((r.s_star - 2.0 * std::f64::consts::PI).abs() < 1e-8);
//! assert!(is_stable(6.0, 0.0, 0.0)? && !is_stable(6.5, 0.0, 0.0)?);
//! // Exactly on the τ axis the rod is straight and untwisted: never unstable.
//! assert!(critical_s(&Direction::new(0.0, 1.0, 0.0)?, 1e-10)?.s_star.is_infinite());
//! # Ok::<(), helixreach::Error>(())
//! ```

mod kernel;
mod scan;

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{tol, Real};

/// The first root `x₁ ≈ 4.4934` of `tan x = x` on `(π, 3π/2)`; the clamped twisted rod (no axial
/// force) buckles at the twisting moment `ω = 2x₁`.
pub const GREENHILL_X1: Real = 4.493_409_457_909_064;

/// Default scan step in arc length of the unit-direction helix.
pub const DEFAULT_STEP: Real = 0.2;

/// [`is_stable`] scans to `s·(1 + IS_STABLE_SLACK)`, just past the point asked about, so that a
/// conjugate time at `s` itself is inside the scan (relative).
const IS_STABLE_SLACK: Real = 1e-9;

/// The critical distance along a ray and its estimated error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalS {
    /// Distance `s*` from the origin along the unit direction at which the helix loses stability;
    /// `f64::INFINITY` if it is stable up to the search limit ([`tol::S_MAX`] by default).
    pub s_star: Real,
    /// Estimated absolute error of `s_star` (same units; 0 when `s_star` is infinite or exact).
    pub est_error: Real,
}

/// Parameters of the continuum test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuumParams {
    /// Poisson's ratio ν ∈ (−1, 0.5]; the twisting stiffness is `c = 1/(1+ν)`. The boundary does
    /// not depend on it (checked by the tests); it is a parameter so that this can be shown.
    pub nu: Real,
    /// Relative tolerance on `s*` (> 0, < 1).
    pub tol_rel: Real,
    /// Scan step in arc length of the unit-direction helix (> 0, ≤ 0.5).
    pub step: Real,
    /// Largest `s` searched; beyond it a ray is reported stable (`s* = ∞`).
    pub s_max: Real,
}

impl Default for ContinuumParams {
    /// ν = 0.33, tolerance [`tol::S_STAR_REL`], step [`DEFAULT_STEP`], `s_max` [`tol::S_MAX`].
    fn default() -> Self {
        ContinuumParams {
            nu: 0.33,
            tol_rel: tol::S_STAR_REL,
            step: DEFAULT_STEP,
            s_max: tol::S_MAX,
        }
    }
}

impl ContinuumParams {
    /// Check every field; errors name the field and value.
    pub fn validate(&self) -> Result<()> {
        crate::math::twist_ratio(self.nu)?;
        if !(self.tol_rel.is_finite() && self.tol_rel > 0.0 && self.tol_rel < 1.0) {
            return Err(Error::invalid(
                "tol",
                self.tol_rel,
                "relative tolerance must be in (0, 1)",
            ));
        }
        let min_step = crate::limits::MIN_CONTINUUM_STEP;
        if !(self.step.is_finite() && self.step >= min_step && self.step <= 0.5) {
            return Err(Error::invalid(
                "step",
                self.step,
                format!("must be in [{min_step:e}, 0.5] (helixreach::limits)"),
            ));
        }
        let max_s = crate::limits::MAX_S;
        if !(self.s_max.is_finite() && self.s_max > 0.0 && self.s_max <= max_s) {
            return Err(Error::invalid(
                "s_max",
                self.s_max,
                format!("must be in (0, {max_s:e}] (helixreach::limits::MAX_S)"),
            ));
        }
        Ok(())
    }
}

/// Check a direction given as a struct literal: finite, κ̂ ≥ 0, unit norm.
fn check_direction(dir: &Direction) -> Result<()> {
    for (name, v) in [
        ("dir_kappa", dir.kappa),
        ("dir_tau", dir.tau),
        ("dir_omega", dir.omega),
    ] {
        if !v.is_finite() {
            return Err(Error::invalid(name, v, "must be finite"));
        }
    }
    if dir.kappa < 0.0 {
        return Err(Error::invalid(
            "dir_kappa",
            dir.kappa,
            "must be >= 0 (curvature is non-negative)",
        ));
    }
    let n = dir.norm();
    if n.is_nan() || (n - 1.0).abs() > tol::UNIT_DIRECTION {
        return Err(Error::invalid(
            "direction",
            format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
            format!("must be a unit vector (norm {n}); build it with Direction::new"),
        ));
    }
    Ok(())
}

/// The critical distance `s*` along the unit direction `dir` (ν = 0.33, default step and
/// `s_max`), to relative tolerance `tol_rel`. See [`critical_s_with`].
///
/// ```
/// use helixreach::boundary::continuum::critical_s;
/// use helixreach::directions::Direction;
/// let d = Direction::new(1.0, 1.0, -1.0)?;
/// let r = critical_s(&d, 1e-10)?;
/// assert!(r.s_star.is_finite() && r.est_error <= 1e-10 * r.s_star);
/// # Ok::<(), helixreach::Error>(())
/// ```
pub fn critical_s(dir: &Direction, tol_rel: Real) -> Result<CriticalS> {
    critical_s_with(
        dir,
        &ContinuumParams {
            tol_rel,
            ..ContinuumParams::default()
        },
    )
}

/// The critical distance `s*` along the unit direction `dir` with explicit parameters: the first
/// conjugate time of the unit-direction helix (module docs). Errors on a non-finite, non-unit or
/// κ̂ < 0 direction and on invalid parameters.
pub fn critical_s_with(dir: &Direction, p: &ContinuumParams) -> Result<CriticalS> {
    check_direction(dir)?;
    p.validate()?;
    if dir.kappa == 0.0 {
        // Straight twisted rod, tension-free (module docs, "The κ = 0 plane").
        let s = 2.0 * GREENHILL_X1 / dir.omega.abs();
        return Ok(if s <= p.s_max {
            CriticalS {
                s_star: s,
                est_error: 4.0 * Real::EPSILON * s,
            }
        } else {
            CriticalS {
                s_star: Real::INFINITY,
                est_error: 0.0,
            }
        });
    }
    let c = crate::math::twist_ratio(p.nu)?;
    let a = kernel::generator_balanced(dir.kappa, dir.tau, dir.omega, c);
    let r = scan::first_conjugate(&a, p.step, p.s_max, p.tol_rel);
    Ok(if r.t <= p.s_max {
        CriticalS {
            s_star: r.t,
            est_error: r.err,
        }
    } else {
        CriticalS {
            s_star: Real::INFINITY,
            est_error: 0.0,
        }
    })
}

/// Whether the helix (κ, τ, ω) is stable: no conjugate point on `(0, 1]`, i.e.
/// `|(κ, τ, ω)| < s*` along its direction (the origin, the straight unloaded rod, is stable).
/// A point exactly on the boundary (to 1e-10 relative) is not stable. Beyond [`tol::S_MAX`] a ray
/// with no conjugate point counts as stable.
///
/// ```
/// // The straight rod twisted just below / above Greenhill's critical moment 2x₁ ≈ 8.9868.
/// use helixreach::boundary::continuum::is_stable;
/// assert!(is_stable(0.0, 0.0, 8.98)?);
/// assert!(!is_stable(0.0, 0.0, 8.99)?);
/// # Ok::<(), helixreach::Error>(())
/// ```
pub fn is_stable(kappa: Real, tau: Real, omega: Real) -> Result<bool> {
    for (name, v) in [("kappa", kappa), ("tau", tau), ("omega", omega)] {
        if !v.is_finite() {
            return Err(Error::invalid(name, v, "must be finite"));
        }
    }
    if kappa < 0.0 {
        return Err(Error::invalid(
            "kappa",
            kappa,
            "must be >= 0 (curvature is non-negative)",
        ));
    }
    let s = (kappa * kappa + tau * tau + omega * omega).sqrt();
    if s == 0.0 {
        return Ok(true);
    }
    let dir = Direction::new(kappa, tau, omega)?;
    let p = ContinuumParams {
        // Scan only as far as needed: a conjugate time beyond s does not matter.
        s_max: (s * (1.0 + IS_STABLE_SLACK)).min(tol::S_MAX),
        ..ContinuumParams::default()
    };
    let r = critical_s_with(&dir, &p)?;
    Ok(r.s_star > s)
}
