//! Bending energy at one interior node (isotropic, naturally straight rod).
//!
//! With `a = e_{i−1}/|e_{i−1}|`, `b = e_i/|e_i|`, `χ = a·b = cos φ_i` (φ_i the turning angle)
//! the curvature binormal is `κb = 2 a×b/(1 + χ)`, `|κb| = 2 tan(φ/2)`, and
//!
//! $$E_b = \frac{k_b}{2\bar l_i}\,|\kappa b|^2 = \frac{k_b}{2\bar l_i}\;g(\chi),\qquad
//!   g(\chi) = 4\,\frac{1-\chi}{1+\chi}$$
//!
//! (the seed paper's `E_b` with `φ⁰ = 0`; for an isotropic rod the material frame drops out).
//! Everything is a function of χ alone, so with `g' = −8/(1+χ)²`, `g'' = 16/(1+χ)³`,
//! `∂χ/∂e⁻ = (b − χa)/ℓ⁻`, `∂χ/∂e⁺ = (a − χb)/ℓ⁺`,
//! `∂²χ/∂e⁻² = −[b aᵀ + a bᵀ + χ(I − 3aaᵀ)]/ℓ⁻²` (and symmetrically for `e⁺`),
//! `∂²χ/∂e⁻∂e⁺ = (I − aaᵀ)(I − bbᵀ)/(ℓ⁻ℓ⁺)`, the Hessian is
//! `w·(g''·∇χ∇χᵀ + g'·∇²χ)` with `w = k_b/(2 l̄_i)`.

use crate::math::{Mat3, Real, Vec3};

/// Derivatives at one node with respect to `(e⁻, e⁺)`.
#[derive(Debug, Clone, Copy)]
pub struct EdgePairDerivatives {
    /// The energy.
    pub energy: Real,
    /// ∂E/∂e⁻.
    pub g_m: Vec3,
    /// ∂E/∂e⁺.
    pub g_p: Vec3,
    /// ∂²E/∂e⁻².
    pub h_mm: Mat3,
    /// ∂²E/∂e⁻∂e⁺.
    pub h_mp: Mat3,
    /// ∂²E/∂e⁺².
    pub h_pp: Mat3,
}

/// `|κb|² = 4(1 − χ)/(1 + χ)` of two edges.
#[inline]
pub fn curvature_sq(em: &Vec3, ep: &Vec3) -> Real {
    let chi = em.dot(ep) / (em.norm() * ep.norm());
    4.0 * (1.0 - chi) / (1.0 + chi)
}

/// Energy only, with weight `w = k_b/(2 l̄)`.
#[inline]
pub fn node_energy(em: &Vec3, ep: &Vec3, w: Real) -> Real {
    w * curvature_sq(em, ep)
}

/// Energy and gradient `(E, ∂E/∂e⁻, ∂E/∂e⁺)` only (the gradient of [`node`] without its
/// Hessian: line searches need no second derivatives), weight `w = k_b/(2 l̄)`.
#[inline]
pub fn node_gradient(em: &Vec3, ep: &Vec3, w: Real) -> (Real, Vec3, Vec3) {
    let (lm, lp) = (em.norm(), ep.norm());
    let (a, b) = (em / lm, ep / lp);
    let chi = a.dot(&b);
    let opc = 1.0 + chi;
    let g = 4.0 * (1.0 - chi) / opc;
    let g1 = -8.0 / (opc * opc);
    let dm = (b - chi * a) / lm;
    let dp = (a - chi * b) / lp;
    (w * g, w * g1 * dm, w * g1 * dp)
}

/// Energy, gradient and Hessian with respect to `(e⁻, e⁺)`, weight `w = k_b/(2 l̄)`.
#[inline]
pub fn node(em: &Vec3, ep: &Vec3, w: Real) -> EdgePairDerivatives {
    let (lm, lp) = (em.norm(), ep.norm());
    let (a, b) = (em / lm, ep / lp);
    let chi = a.dot(&b);
    let opc = 1.0 + chi;
    let g = 4.0 * (1.0 - chi) / opc;
    let g1 = -8.0 / (opc * opc);
    let g2 = 16.0 / (opc * opc * opc);
    let dm = (b - chi * a) / lm;
    let dp = (a - chi * b) / lp;
    let id = Mat3::identity();
    let aat = a * a.transpose();
    let bbt = b * b.transpose();
    let abt = a * b.transpose();
    let bat = abt.transpose();
    let hmm = -(bat + abt + chi * (id - 3.0 * aat)) / (lm * lm);
    let hpp = -(abt + bat + chi * (id - 3.0 * bbt)) / (lp * lp);
    let hmp = (id - aat - bbt + chi * abt) / (lm * lp);
    EdgePairDerivatives {
        energy: w * g,
        g_m: w * g1 * dm,
        g_p: w * g1 * dp,
        h_mm: w * (g2 * dm * dm.transpose() + g1 * hmm),
        h_mp: w * (g2 * dm * dp.transpose() + g1 * hmp),
        h_pp: w * (g2 * dp * dp.transpose() + g1 * hpp),
    }
}
