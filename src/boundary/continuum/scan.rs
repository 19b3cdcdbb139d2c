//! First conjugate time of the constant-coefficient Jacobi equation: a step scan with exact
//! (matrix-exponential) propagation, sign-change and hidden-pair detection, and a safeguarded
//! Newton refinement on a Taylor expansion of the frame.

use super::kernel::{
    apply, col_norm_product, det, expm, initial_frame, lu, norm_inf, orthonormalize, taylor_terms,
    top, trace_inv_mul, Block, Frame, Gen,
};
use crate::math::Real;

/// Most Taylor terms used inside one refinement window.
const MAX_TERMS: usize = 40;

/// The golden-section search for a hidden minimum of the ratio stops when its bracket is below
/// `MIN_BRACKET_REL · max(tol_rel, TOL_REL_FLOOR) · t` (or after 80 steps): a bracket a thousandth
/// of the root tolerance wide (dimensionless).
const MIN_BRACKET_REL: Real = 1e-3;

/// Floor of `tol_rel` in that bracket width (dimensionless), so that `tol_rel = 0` still stops.
const TOL_REL_FLOOR: Real = 1e-12;

/// A normalized `|det J|` (Hadamard ratio of the top block of a near-orthonormal frame) below
/// this counts as a zero: a double root (tangency) of `det J` resolved to machine precision.
pub(crate) const TANGENCY: Real = 1e-13;

/// Below this arc length (of the unit-direction helix) no sign of `det J` is trusted: there
/// `det J ~ t^p` with a large `p` (≈ 1e-21 at t = 0.1) and its computed sign is rounding noise.
/// No conjugate point can occur there: for a unit direction `|m|, |n| ≤ √2`, and a clamped rod
/// shorter than ~π/(2√2) ≈ 1.1 is stiffer than these loads by Wirtinger's inequality; the
/// smallest s* on the 58,352-direction lattice is far above it (see the tests).
pub(crate) const T_QUIET: Real = 1.0;

/// The result of one scan: first conjugate time (∞ if none up to `t_max`), an estimate of its
/// absolute error, and how it was found.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Conjugate {
    pub t: Real,
    pub err: Real,
}

/// The Taylor expansion `Z(t_a + δ) = Σ_j δ^j A^j Z(t_a)/j!` of the frame on a window, reduced
/// to its top 6×6 blocks (only `J` enters the test).
struct Window {
    t0: Real,
    len: Real,
    terms: usize,
    coef: [Block; MAX_TERMS + 1],
}

impl Window {
    fn new(a: &Gen, z: &Frame, t0: Real, len: Real) -> Self {
        let terms = taylor_terms(norm_inf(a) * len, MAX_TERMS);
        let mut coef = [[[0.0; 6]; 6]; MAX_TERMS + 1];
        let mut p = *z;
        coef[0] = top(&p);
        for j in 1..=terms {
            p = apply(a, &p);
            let inv = 1.0 / j as Real;
            for r in p.iter_mut() {
                for x in r.iter_mut() {
                    *x *= inv;
                }
            }
            coef[j] = top(&p);
        }
        Window {
            t0,
            len,
            terms,
            coef,
        }
    }

    /// `J(t0 + δ)` and `J'(t0 + δ)`.
    fn eval(&self, d: Real) -> (Block, Block) {
        let mut j = self.coef[self.terms];
        let mut jp = [[0.0; 6]; 6];
        for k in (0..self.terms).rev() {
            // jp ← jp·d + j ; j ← j·d + c_k   (Horner for the value and its derivative)
            for r in 0..6 {
                for c in 0..6 {
                    jp[r][c] = jp[r][c] * d + j[r][c];
                    j[r][c] = j[r][c] * d + self.coef[k][r][c];
                }
            }
        }
        (j, jp)
    }

    /// The scale-free value `det J / Π‖J cols‖` at `δ`.
    fn ratio(&self, d: Real) -> Real {
        let (j, _) = self.eval(d);
        let p = col_norm_product(&j);
        if p > 0.0 {
            det(&j) / p
        } else {
            0.0
        }
    }

    /// The root of `det J` in `(lo, hi)` (a sign change is known), to relative accuracy
    /// `tol_rel` in `t`, by Newton on `det J` (`(det J)'/det J = tr(J⁻¹J')`), safeguarded by
    /// bisection.
    fn root(&self, mut lo: Real, mut hi: Real, tol_rel: Real) -> Conjugate {
        let sign_lo = self.ratio(lo).signum();
        let mut x = 0.5 * (lo + hi);
        let mut last = hi - lo;
        for _ in 0..200 {
            let (j, jp) = self.eval(x);
            let mut f = j;
            let (d, piv) = lu(&mut f);
            if d == 0.0 {
                return Conjugate {
                    t: self.t0 + x,
                    err: 4.0 * Real::EPSILON * (self.t0 + x),
                };
            }
            if d.signum() == sign_lo {
                lo = x;
            } else {
                hi = x;
            }
            let g = trace_inv_mul(&f, &piv, &jp);
            let step = if g.is_finite() && g != 0.0 {
                -1.0 / g
            } else {
                Real::NAN
            };
            let cand = x + step;
            let target = tol_rel * (self.t0 + x);
            if cand.is_finite() && cand > lo && cand < hi {
                // Newton step inside the bracket.
                let converged = step.abs() <= 0.25 * target;
                last = step.abs();
                x = cand;
                if converged {
                    break;
                }
            } else {
                last = hi - lo;
                x = 0.5 * (lo + hi);
            }
            if hi - lo <= target {
                x = 0.5 * (lo + hi);
                last = 0.5 * (hi - lo);
                break;
            }
        }
        let t = self.t0 + x;
        Conjugate {
            t,
            err: last.max(4.0 * Real::EPSILON * t),
        }
    }

    /// Look for a hidden pair of roots (or a tangency) of `det J` in the window, where the sampled
    /// `|det J|` has a local minimum without a sign change. Golden-section search for the minimum
    /// of `sgn·ratio`; a negative value brackets the first root, a value below [`TANGENCY`] is a
    /// double root.
    fn hidden(&self, sgn: Real, tol_rel: Real) -> Option<Conjugate> {
        let g = |d: Real| sgn * self.ratio(d);
        let phi = 0.5 * (5.0_f64.sqrt() - 1.0);
        let (mut a, mut b) = (0.0, self.len);
        let mut c = b - phi * (b - a);
        let mut d = a + phi * (b - a);
        let (mut gc, mut gd) = (g(c), g(d));
        for _ in 0..80 {
            if gc <= 0.0 || gd <= 0.0 {
                let x = if gc <= 0.0 { c } else { d };
                if g(x) == 0.0 {
                    return Some(Conjugate {
                        t: self.t0 + x,
                        err: 4.0 * Real::EPSILON * (self.t0 + x),
                    });
                }
                return Some(self.root(0.0, x, tol_rel));
            }
            if gc < gd {
                b = d;
                d = c;
                gd = gc;
                c = b - phi * (b - a);
                gc = g(c);
            } else {
                a = c;
                c = d;
                gc = gd;
                d = a + phi * (b - a);
                gd = g(d);
            }
            if b - a <= MIN_BRACKET_REL * tol_rel.max(TOL_REL_FLOOR) * (self.t0 + a) {
                break;
            }
        }
        let (x, gx) = if gc < gd { (c, gc) } else { (d, gd) };
        if gx <= TANGENCY {
            Some(Conjugate {
                t: self.t0 + x,
                err: (b - a).max(4.0 * Real::EPSILON * (self.t0 + x)),
            })
        } else {
            None
        }
    }
}

/// The first `t > 0` where `det J(t) = 0` for the generator `a`, scanning with step `h` up to
/// `t_max`; `t = ∞` if there is none.
///
/// Each step propagates the orthonormalized frame exactly (`Z ← exp(hA)·Z`, then Gram–Schmidt,
/// which keeps the sign and zeros of `det J`) and samples `q_k = det J(t_k)` (∈ [−1, 1] for an
/// orthonormal frame). A sign change brackets a root; a local minimum of `|q|` without a sign
/// change triggers a search of the two steps around it for a hidden pair or a tangency.
pub(crate) fn first_conjugate(a: &Gen, h: Real, t_max: Real, tol_rel: Real) -> Conjugate {
    let e = expm(a, h);
    let mut z_prev2 = initial_frame();
    let mut z_prev = initial_frame();
    let mut q_prev2: Real = 0.0;
    let mut q_prev: Real = 0.0;
    let mut k: usize = 0;
    loop {
        k += 1;
        let t_prev = (k - 1) as Real * h;
        if t_prev >= t_max {
            return Conjugate {
                t: Real::INFINITY,
                err: 0.0,
            };
        }
        let mut z = apply(&e, &z_prev);
        orthonormalize(&mut z);
        let q = det(&top(&z));
        if t_prev >= T_QUIET + h {
            if q == 0.0 || q.signum() != q_prev.signum() {
                let w = Window::new(a, &z_prev, t_prev, h);
                return w.root(0.0, h, tol_rel);
            }
            if q_prev.abs() < q_prev2.abs() && q_prev.abs() <= q.abs() {
                let w = Window::new(a, &z_prev2, t_prev - h, 2.0 * h);
                if let Some(c) = w.hidden(q_prev.signum(), tol_rel) {
                    return c;
                }
            }
        }
        z_prev2 = z_prev;
        z_prev = z;
        q_prev2 = q_prev;
        q_prev = q;
    }
}
