//! Frames along the helix: Frenet F(s) = exp(s·ŵ), parallel transport (Bishop)
//! Q(s) = F(s)·Rz(−τ s) and material M(s) = Q(s)·Rz((ω/c)·s). All are proper rotations with the
//! directors as columns, in the clamp frame; F(0) = Q(0) = M(0) = I.

use super::Helix;
use crate::math::{Mat3, Real};

/// `m · Rz(a)`: turns the first two columns of `m` by `a` about its third column (cheaper than a
/// full product).
#[inline]
pub(crate) fn mul_rot_z(m: &Mat3, a: Real) -> Mat3 {
    let (s, c) = super::kernel::sin_cos(a);
    let c0 = m.column(0);
    let c1 = m.column(1);
    Mat3::from_columns(&[c * c0 + s * c1, c * c1 - s * c0, m.column(2).into_owned()])
}

impl Helix {
    /// The Frenet frame \[N B T\](s) = exp(s·ŵ), w = (0, κ, τ). At κ = 0 the normal is undefined
    /// geometrically; by convention it stays the clamp frame's x axis turned by τs about T.
    ///
    /// ```
    /// use helixreach::helix::Helix;
    /// let h = Helix::new(3.0, 4.0, 0.0).unwrap();
    /// let f = h.frenet_frame(0.7);
    /// // dT/ds = κ N, checked by a central difference.
    /// let d = 1e-6;
    /// let dt = (h.frenet_frame(0.7 + d).column(2) - h.frenet_frame(0.7 - d).column(2)) / (2.0 * d);
    /// assert!((dt - 3.0 * f.column(0)).norm() < 1e-8);
    /// ```
    #[inline]
    pub fn frenet_frame(&self, s: Real) -> Mat3 {
        self.frenet_and_position(s).0
    }

    /// The parallel-transport (Bishop) frame \[d1 d2 d3\](s) = F(s)·Rz(−τ s): d3 = T, and d1, d2
    /// do not turn about the tangent. Identity at s = 0.
    ///
    /// ```
    /// use helixreach::helix::Helix;
    /// let h = Helix::new(2.0, -1.5, 0.0).unwrap();
    /// // Parallel transport: d1' has no component along d2 (no twist about the tangent).
    /// let d = 1e-6;
    /// let q = h.transported_frame(0.4);
    /// let dd1 = (h.transported_frame(0.4 + d).column(0) - h.transported_frame(0.4 - d).column(0)) / (2.0 * d);
    /// assert!(dd1.dot(&q.column(1)).abs() < 1e-8);
    /// ```
    #[inline]
    pub fn transported_frame(&self, s: Real) -> Mat3 {
        mul_rot_z(&self.frenet_frame(s), -self.tau * s)
    }

    /// The material frame \[m1 m2 t\](s) = Q(s)·Rz((ω/c)·s) for the twist ratio `c` = k_t/k_b
    /// (c = 1/(1+ν), see [`twist_ratio`](super::twist_ratio)). `c` must be finite and > 0;
    /// [`Helix::end_pose`] validates it from ν.
    #[inline]
    pub fn material_frame(&self, s: Real, c: Real) -> Mat3 {
        debug_assert!(c.is_finite() && c > 0.0, "twist ratio c = {c}");
        mul_rot_z(&self.frenet_frame(s), (self.omega / c - self.tau) * s)
    }
}
