//! Twisting energy at one interior node, with the reference twist.
//!
//! $$E_t = \frac{k_t}{2\bar l_i}\,m_i^2,\qquad m_i = \theta_i - \theta_{i-1} + m^{ref}_i$$
//!
//! (the seed paper's `E_t`). The reference twist `m^ref_i` depends on the positions through the
//! tangents `a = t_{i−1}`, `b = t_i` (reference frames time-parallel transported from the base,
//! see [`crate::rod::state`]). Its exact derivatives *at the base* are derived from the
//! holonomy of parallel transport: `m^ref(a, b) − m^ref(a₀, b₀)` is minus the signed spherical
//! area of the geodesic quadrilateral `b₀ → a₀ → a → b`, which splits into two triangles with
//! `tan(Ω/2) = p·(q×r)/(1 + p·q + q·r + r·p)` (Van Oosterom–Strackee). Expanding the two
//! `atan2`s to second order at `a = a₀`, `b = b₀` and composing with `a = e⁻/ℓ⁻`, `b = e⁺/ℓ⁺`
//! gives, with `χ = a·b` and `k = (a × b)/(1 + χ) = κb/2`:
//!
//! - `∂m/∂e⁻ = k/ℓ⁻`, `∂m/∂e⁺ = k/ℓ⁺` (Bergou et al. 2008);
//! - `∂²m/∂e⁻² = −[k(b − χa)ᵀ + (b − χa)kᵀ]/(2(1+χ)ℓ⁻²) − (k aᵀ + a kᵀ)/ℓ⁻²`;
//! - `∂²m/∂e⁺² = −[k(a − χb)ᵀ + (a − χb)kᵀ]/(2(1+χ)ℓ⁺²) − (k bᵀ + b kᵀ)/ℓ⁺²`;
//! - `∂²m/∂e⁻∂e⁺ = ([b]× − (a + b)kᵀ)/((1+χ)ℓ⁻ℓ⁺)`.
//!
//! `∂m/∂θ_{i−1} = −1`, `∂m/∂θ_i = +1`; the energy's Hessian is
//! `2w(∇m∇mᵀ + m·∇²m)` with `w = k_t/(2 l̄_i)`. These are checked against finite differences
//! of the transported-frame energy in `tests/rod.rs`.

use super::bend::EdgePairDerivatives;
use crate::math::{hat, Real, Vec3};

/// Derivatives of the reference twist `m^ref` at the base with respect to `(e⁻, e⁺)` (value
/// field `energy` unused = 0).
#[inline]
pub fn reference_twist_derivatives(em: &Vec3, ep: &Vec3) -> EdgePairDerivatives {
    let (lm, lp) = (em.norm(), ep.norm());
    let (a, b) = (em / lm, ep / lp);
    let chi = a.dot(&b);
    let opc = 1.0 + chi;
    let k = a.cross(&b) / opc;
    let u = b - chi * a;
    let v = a - chi * b;
    let h_mm = -(k * u.transpose() + u * k.transpose()) / (2.0 * opc * lm * lm)
        - (k * a.transpose() + a * k.transpose()) / (lm * lm);
    let h_pp = -(k * v.transpose() + v * k.transpose()) / (2.0 * opc * lp * lp)
        - (k * b.transpose() + b * k.transpose()) / (lp * lp);
    let h_mp = (hat(&b) - (a + b) * k.transpose()) / (opc * lm * lp);
    EdgePairDerivatives {
        energy: 0.0,
        g_m: k / lm,
        g_p: k / lp,
        h_mm,
        h_mp,
        h_pp,
    }
}

/// The gradient `(∂m/∂e⁻, ∂m/∂e⁺) = (k/ℓ⁻, k/ℓ⁺)` of the reference twist only (that of
/// [`reference_twist_derivatives`] without its Hessian).
#[inline]
pub fn reference_twist_gradient(em: &Vec3, ep: &Vec3) -> (Vec3, Vec3) {
    let (lm, lp) = (em.norm(), ep.norm());
    let (a, b) = (em / lm, ep / lp);
    let k = a.cross(&b) / (1.0 + a.dot(&b));
    (k / lm, k / lp)
}

/// Energy only: `w·m²`, `w = k_t/(2 l̄)`.
#[inline]
pub fn node_energy(m: Real, w: Real) -> Real {
    w * m * m
}
