//! Allocation-free fixed-size kernels for the constant-coefficient Jacobi equation:
//! the 12×12 generator `A`, its exponential, the 12×6 Lagrangian frame and 6×6 determinants.
//!
//! All matrices are plain row-major arrays so that the hot loop (one `E·Z`, one Gram–Schmidt and
//! one 6×6 LU per step) compiles to straight-line, vectorizable code with no allocation.

use crate::math::Real;

/// The 12×12 generator, row-major.
pub(crate) type Gen = [[Real; 12]; 12];
/// A 12×6 frame (the columns are the six Jacobi fields), row-major.
pub(crate) type Frame = [[Real; 6]; 12];
/// A 6×6 block, row-major.
pub(crate) type Block = [[Real; 6]; 6];

/// Write `[v]×` into the 3×3 block of `a` at (`r0`, `c0`), scaled by `f`, adding.
fn add_hat(a: &mut Gen, r0: usize, c0: usize, v: [Real; 3], f: Real) {
    let [x, y, z] = v;
    let h = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            a[r0 + i][c0 + j] += f * h[i][j];
        }
    }
}

/// The generator `A` of the Jacobi equation `z' = A z`, `z = (α, β, δm, δn)`, written in the
/// Frenet frame of the helix (κ, τ, ω) with twisting stiffness `c` (bending stiffness 1):
///
/// ```text
/// α'  = −[w]× α + K⁻¹ δm                  w = (0, κ, τ)          (Darboux vector)
/// β'  = −[e3]× α − [w]× β                 m = (0, κ, ω)          (internal moment)
/// δm' = ([m]× K⁻¹ − [w]×) δm − [e3]× δn   n = (ω − τ)(0, κ, τ)   (internal force)
/// δn' = [n]× K⁻¹ δm − [w]× δn             K = diag(1, 1, c)
/// ```
pub(crate) fn generator(kappa: Real, tau: Real, omega: Real, c: Real) -> Gen {
    let mut a = [[0.0; 12]; 12];
    let w = [0.0, kappa, tau];
    let m = [0.0, kappa, omega];
    let f = omega - tau;
    let n = [0.0, f * kappa, f * tau];
    let e3 = [0.0, 0.0, 1.0];
    let kinv = [1.0, 1.0, 1.0 / c];
    // α row block
    add_hat(&mut a, 0, 0, w, -1.0);
    for i in 0..3 {
        a[i][6 + i] = kinv[i];
    }
    // β row block
    add_hat(&mut a, 3, 0, e3, -1.0);
    add_hat(&mut a, 3, 3, w, -1.0);
    // δm row block: [m]× K⁻¹ − [w]×, −[e3]×
    let mut mh = [[0.0; 12]; 12];
    add_hat(&mut mh, 0, 0, m, 1.0);
    for i in 0..3 {
        for j in 0..3 {
            a[6 + i][6 + j] += mh[i][j] * kinv[j];
        }
    }
    add_hat(&mut a, 6, 6, w, -1.0);
    add_hat(&mut a, 6, 9, e3, -1.0);
    // δn row block: [n]× K⁻¹, −[w]×
    let mut nh = [[0.0; 12]; 12];
    add_hat(&mut nh, 0, 0, n, 1.0);
    for i in 0..3 {
        for j in 0..3 {
            a[9 + i][6 + j] += nh[i][j] * kinv[j];
        }
    }
    add_hat(&mut a, 9, 9, w, -1.0);
    a
}

/// Index of `β_z` (axial displacement) in `z = (α, β, δm, δn)`.
pub(crate) const BETA_Z: usize = 5;
/// Index of `δn_z` (axial force) in `z`.
pub(crate) const DN_Z: usize = 11;

/// The generator of the **κ-balanced** Jacobi system: `S·A·S⁻¹` with
/// `S = diag(1, …, 1, 1/κ at β_z, 1, …, 1, κ at δn_z)`, i.e. the variables `β_z/κ` and `κ·δn_z`.
///
/// Why: as κ → 0 the helix tends to a straight rod, on which an axial force does not change the
/// shape and the end cannot move axially to first order: the `δn_z` column and the `β_z` row of
/// `J` are both `O(κ)`, so `det J = O(κ²)` — below the smallest normal number for κ ≲ 1e-154
/// (the sign and the tangency test then read rounding noise or zero). In the balanced variables
/// every entry of the generator is bounded as κ → 0 and the limit system is nondegenerate, so
/// `det J_S = det J/κ²` (same sign, same zeros: `S` is positive diagonal and the initial frame
/// `[0; S]` is `[0; I]` up to a positive column scaling) is `O(1)` for every representable κ > 0.
///
/// The entries that `S` changes are written with the powers of κ cancelled analytically (no
/// division by κ, which would overflow for subnormal κ): row `β_z` (`β_z' = κβ_x`) becomes
/// `(β_z/κ)' = β_x`; column `β_z` (`β_x' ∋ −κβ_z`) becomes `−κ²·(β_z/κ)`; row `δn_z`
/// (`δn_z' = −fκ δm_x + κ δn_x`, `f = ω − τ`) becomes `−fκ² δm_x + κ² δn_x`; column `δn_z`
/// (`δn_x' ∋ −κ δn_z`) becomes `−(κ δn_z)`. No other entry of these rows/columns is nonzero
/// (checked against `S·A·S⁻¹` in the unit tests).
pub(crate) fn generator_balanced(kappa: Real, tau: Real, omega: Real, c: Real) -> Gen {
    let mut a = generator(kappa, tau, omega, c);
    let f = omega - tau;
    let k2 = kappa * kappa;
    a[BETA_Z][3] = 1.0;
    a[3][BETA_Z] = -k2;
    a[DN_Z][6] = -f * k2;
    a[DN_Z][9] = k2;
    a[9][DN_Z] = -1.0;
    a
}

/// Infinity norm (max absolute row sum).
pub(crate) fn norm_inf(a: &Gen) -> Real {
    a.iter()
        .map(|r| r.iter().map(|x| x.abs()).sum::<Real>())
        .fold(0.0, Real::max)
}

/// The bound on the Taylor remainder of `exp` at which [`taylor_terms`] stops (absolute, on a
/// term of size ≤ 1: below the f64 resolution of the unit-size sum, ≈ 1.1e-16).
const TAYLOR_REMAINDER: Real = 1e-18;

/// The number of Taylor terms N such that the remainder bound `x^{N+1}/(N+1)!` of
/// `exp` at `‖hA‖ = x` is below [`TAYLOR_REMAINDER`] (at most `cap`).
pub(crate) fn taylor_terms(x: Real, cap: usize) -> usize {
    let mut term = 1.0;
    for k in 1..=cap {
        term *= x / k as Real;
        if term < TAYLOR_REMAINDER {
            return k;
        }
    }
    cap
}

fn gen_mul(a: &Gen, b: &Gen) -> Gen {
    let mut c = [[0.0; 12]; 12];
    for i in 0..12 {
        for k in 0..12 {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..12 {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// `exp(h·A)` by a Taylor series in Horner form with scaling and squaring so that the scaled
/// argument has norm ≤ 0.5 (remainder below 1e-18 per term count from [`taylor_terms`]).
pub(crate) fn expm(a: &Gen, h: Real) -> Gen {
    let x = norm_inf(a) * h.abs();
    let mut squarings = 0;
    let mut hs = h;
    let mut xs = x;
    while xs > 0.5 {
        xs *= 0.5;
        hs *= 0.5;
        squarings += 1;
    }
    let n = taylor_terms(xs, 30);
    let mut b = [[0.0; 12]; 12];
    for i in 0..12 {
        for j in 0..12 {
            b[i][j] = a[i][j] * hs;
        }
    }
    // Horner: E = I + B(I + B/2(I + B/3(…)))
    let mut e = identity();
    for k in (1..=n).rev() {
        let mut t = gen_mul(&b, &e);
        let inv = 1.0 / k as Real;
        for i in 0..12 {
            for j in 0..12 {
                t[i][j] *= inv;
            }
            t[i][i] += 1.0;
        }
        e = t;
    }
    for _ in 0..squarings {
        e = gen_mul(&e, &e);
    }
    e
}

fn identity() -> Gen {
    let mut e = [[0.0; 12]; 12];
    for (i, r) in e.iter_mut().enumerate() {
        r[i] = 1.0;
    }
    e
}

/// `A·Z`.
#[inline]
pub(crate) fn apply(a: &Gen, z: &Frame) -> Frame {
    let mut out = [[0.0; 6]; 12];
    for i in 0..12 {
        let ai = &a[i];
        let oi = &mut out[i];
        for k in 0..12 {
            let aik = ai[k];
            let zk = &z[k];
            for j in 0..6 {
                oi[j] += aik * zk[j];
            }
        }
    }
    out
}

/// The initial frame `Z(0) = [0; I]` (J(0) = 0, M(0) = I).
pub(crate) fn initial_frame() -> Frame {
    let mut z = [[0.0; 6]; 12];
    for j in 0..6 {
        z[6 + j][j] = 1.0;
    }
    z
}

/// Orthonormalize the columns of `z` in place by one pass of modified Gram–Schmidt (called every
/// step, so the frame is always close to orthonormal and one pass keeps it so).
/// This is `Z ← Z·R⁻¹` with `R` upper triangular with a positive diagonal, so `det J` keeps its
/// sign and its zeros: the conjugate-point test depends only on the column span of `Z`.
#[inline]
pub(crate) fn orthonormalize(z: &mut Frame) {
    {
        for j in 0..6 {
            for k in 0..j {
                let mut d = 0.0;
                for i in 0..12 {
                    d += z[i][j] * z[i][k];
                }
                for i in 0..12 {
                    z[i][j] -= d * z[i][k];
                }
            }
            let mut nn = 0.0;
            for i in 0..12 {
                nn += z[i][j] * z[i][j];
            }
            let inv = 1.0 / nn.sqrt();
            for i in 0..12 {
                z[i][j] *= inv;
            }
        }
    }
}

/// The top 6×6 block `J` of a frame.
#[inline]
pub(crate) fn top(z: &Frame) -> Block {
    let mut j = [[0.0; 6]; 6];
    j.copy_from_slice(&z[..6]);
    j
}

/// LU factorization with partial pivoting in place; returns the determinant and the pivots.
#[inline]
pub(crate) fn lu(m: &mut Block) -> (Real, [usize; 6]) {
    let mut det = 1.0;
    let mut piv = [0usize; 6];
    for k in 0..6 {
        let mut p = k;
        let mut best = m[k][k].abs();
        for i in k + 1..6 {
            if m[i][k].abs() > best {
                best = m[i][k].abs();
                p = i;
            }
        }
        piv[k] = p;
        if p != k {
            m.swap(p, k);
            det = -det;
        }
        let d = m[k][k];
        det *= d;
        if d == 0.0 {
            continue;
        }
        let inv = 1.0 / d;
        for i in k + 1..6 {
            let l = m[i][k] * inv;
            m[i][k] = l;
            if l != 0.0 {
                for j in k + 1..6 {
                    m[i][j] -= l * m[k][j];
                }
            }
        }
    }
    (det, piv)
}

/// Determinant of a 6×6 block.
#[inline]
pub(crate) fn det(m: &Block) -> Real {
    let mut w = *m;
    lu(&mut w).0
}

/// `tr(J⁻¹ J')` from the LU factors of `J` (= (det J)'/det J).
pub(crate) fn trace_inv_mul(lu_j: &Block, piv: &[usize; 6], jp: &Block) -> Real {
    let mut tr = 0.0;
    for col in 0..6 {
        // Solve J x = jp[:, col]; we need x[col].
        let mut x = [0.0; 6];
        for i in 0..6 {
            x[i] = jp[i][col];
        }
        for k in 0..6 {
            x.swap(k, piv[k]);
        }
        for i in 0..6 {
            for k in 0..i {
                x[i] -= lu_j[i][k] * x[k];
            }
        }
        for i in (0..6).rev() {
            for k in i + 1..6 {
                x[i] -= lu_j[i][k] * x[k];
            }
            x[i] /= lu_j[i][i];
        }
        tr += x[col];
    }
    tr
}

/// Product of the column norms of the top block (for the scale-free Hadamard ratio).
pub(crate) fn col_norm_product(m: &Block) -> Real {
    let mut p = 1.0;
    for j in 0..6 {
        let mut s = 0.0;
        for i in 0..6 {
            s += m[i][j] * m[i][j];
        }
        p *= s.sqrt();
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expm_matches_repeated_small_steps_and_inverse() {
        let a = generator(0.6, -0.5, 0.62, 0.75);
        let e = expm(&a, 1.3);
        let ei = expm(&a, -1.3);
        let p = gen_mul(&e, &ei);
        for i in 0..12 {
            for j in 0..12 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((p[i][j] - want).abs() < 1e-12, "{i},{j}: {}", p[i][j]);
            }
        }
        // exp(1.3A) = exp(0.13A)^10
        let s = expm(&a, 0.13);
        let mut q = identity();
        for _ in 0..10 {
            q = gen_mul(&q, &s);
        }
        for i in 0..12 {
            for j in 0..12 {
                assert!((q[i][j] - e[i][j]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn balanced_generator_is_the_similarity_transform() {
        for &(k, t, w, c) in &[
            (0.37, -0.8, 0.47, 0.75),
            (0.9, 0.1, -0.42, 0.8),
            (1e-3, 1.0, 0.0, 0.75),
        ] {
            let a = generator(k, t, w, c);
            let b = generator_balanced(k, t, w, c);
            let mut s = [1.0; 12];
            s[BETA_Z] = 1.0 / k;
            s[DN_Z] = k;
            for i in 0..12 {
                for j in 0..12 {
                    let want = s[i] * a[i][j] / s[j];
                    assert!(
                        (b[i][j] - want).abs() <= 1e-15 * want.abs().max(1.0),
                        "({i},{j}): {} vs {want}",
                        b[i][j]
                    );
                }
            }
        }
    }

    #[test]
    fn lu_det_and_trace() {
        let m: Block = [
            [4.0, 1.0, 0.0, 0.0, 2.0, 0.0],
            [1.0, 3.0, 1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 5.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0, 2.0, 1.0, 0.0],
            [2.0, 0.0, 0.0, 1.0, 6.0, 1.0],
            [0.0, 0.0, 1.0, 0.0, 1.0, 3.0],
        ];
        // tr(J⁻¹ J') with J' = J is 6; det of a permuted matrix flips sign.
        let mut f = m;
        let (d, piv) = lu(&mut f);
        assert!((trace_inv_mul(&f, &piv, &m) - 6.0).abs() < 1e-12);
        let mut sw = m;
        sw.swap(0, 3);
        assert!((det(&sw) + d).abs() < 1e-9 * d.abs());
        // Finite-difference check of (det)'/det = tr(J⁻¹J') along J + εI.
        let mut id = [[0.0; 6]; 6];
        for i in 0..6 {
            id[i][i] = 1.0;
        }
        let eps = 1e-6;
        let mut mp = m;
        let mut mm = m;
        for i in 0..6 {
            mp[i][i] += eps;
            mm[i][i] -= eps;
        }
        let fd = (det(&mp) - det(&mm)) / (2.0 * eps) / d;
        assert!((fd - trace_inv_mul(&f, &piv, &id)).abs() < 1e-7);
    }
}
