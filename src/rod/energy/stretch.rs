//! Stretching energy of one edge.
//!
//! $$E_s = \tfrac12\,k_s\,\bar e\,\Bigl(\frac{\ell}{\bar e} - 1\Bigr)^2,\qquad \ell = |e|,$$
//! (the seed paper's eq. for `E_s`, with rest length `ē`). With `a = e/ℓ`:
//! `∂E/∂e = k_s (ℓ/ē − 1)·a` and
//! `∂²E/∂e² = (k_s/ē)·a aᵀ + k_s (ℓ/ē − 1)/ℓ·(I − a aᵀ)`
//! (the transverse part is negative under compression).

use crate::math::{Mat3, Real, Vec3};

/// Energy, gradient and Hessian with respect to the edge vector `e` of one edge with rest
/// length `rest` and stiffness `ks`.
#[inline]
pub fn edge(e: &Vec3, rest: Real, ks: Real) -> (Real, Vec3, Mat3) {
    let l = e.norm();
    let a = e / l;
    let strain = l / rest - 1.0;
    let energy = 0.5 * ks * rest * strain * strain;
    let grad = ks * strain * a;
    let aat = a * a.transpose();
    let hess = (ks / rest) * aat + (ks * strain / l) * (Mat3::identity() - aat);
    (energy, grad, hess)
}

/// Energy only.
#[inline]
pub fn edge_energy(e: &Vec3, rest: Real, ks: Real) -> Real {
    let strain = e.norm() / rest - 1.0;
    0.5 * ks * rest * strain * strain
}
