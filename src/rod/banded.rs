//! Symmetric banded matrices and their LDLᵀ factorization with inertia.
//!
//! faer has no banded solver, and the DER Hessian is banded (half-bandwidth
//! [`HALF_BANDWIDTH`] = 10 with the DOF order `x0, θ0, x1, θ1, …, x_n`), so this module holds a
//! small allocation-free kernel.
//!
//! # Storage
//! [`BandedSym`] stores the lower band column by column: entry `A[i, j]` with `j ≤ i ≤ j + p`
//! lives at `data[j·(p+1) + (i − j)]` (LAPACK's `'L'` band layout, transposed into rows of
//! length `p + 1`). Entries outside the band are zero by definition.
//!
//! # Factorization
//! [`BandedLdlt::factor`] computes `A = L·D·Lᵀ` (unit lower-triangular `L` with the same
//! bandwidth, diagonal `D`) of a contiguous principal sub-block `A[r, r]`, `r = lo..hi`, without
//! pivoting, in `O(m·p²)` flops for `m = hi − lo`. By Sylvester's law of inertia the numbers of
//! positive and negative pivots `d_j` are the numbers of positive and negative eigenvalues of the
//! block, so [`BandedLdlt::inertia`] decides positive definiteness without an eigen-solve.
//! Without pivoting the factorization of an indefinite matrix can meet an exactly zero (or
//! non-finite) pivot; that is reported as [`PivotError`] with its index (the matrix, or that
//! leading minor, is singular). Storage is sized once ([`BandedLdlt::new`]); factor, solve and
//! the inverse iteration allocate nothing.
//!
//! ```
//! use helixreach::rod::banded::{BandedSym, BandedLdlt};
//! // The 1-D Laplacian tridiag(−1, 2, −1) (p = 1) is positive definite.
//! let n = 6;
//! let mut a = BandedSym::zeros(n, 1);
//! for i in 0..n {
//!     a.add(i, i, 2.0);
//!     if i > 0 { a.add(i, i - 1, -1.0); }
//! }
//! let mut f = BandedLdlt::new(n, 1);
//! f.factor(&a, 0..n).unwrap();
//! assert_eq!(f.inertia(), (n, 0));
//! let mut x = vec![1.0; n];
//! f.solve_in_place(&mut x);
//! // A·x = 1 has the solution x_i = (i+1)(n−i)/2.
//! assert!((x[0] - 3.0).abs() < 1e-12 && (x[2] - 6.0).abs() < 1e-12);
//! ```

use crate::math::Real;
use std::ops::Range;

/// Half-bandwidth of the DER Hessian with 4 DOFs per node/edge: a bend/twist stencil couples
/// `x_{i−1}, θ_{i−1}, x_i, θ_i, x_{i+1}`, 11 consecutive DOFs.
pub const HALF_BANDWIDTH: usize = 10;

/// Half-bandwidth of the KKT matrix of the inextensible rod ([`crate::rod::inextensible`]):
/// 5 unknowns per node (x, λ, θ), a bend stencil `x_{i−1} … x_{i+1}` spans 13.
pub const KKT_HALF_BANDWIDTH: usize = 12;

/// A symmetric banded matrix (lower band stored; see the module docs for the layout).
#[derive(Debug, Clone, PartialEq)]
pub struct BandedSym {
    n: usize,
    p: usize,
    data: Vec<Real>,
}

impl BandedSym {
    /// The `n × n` zero matrix with half-bandwidth `p`.
    pub fn zeros(n: usize, p: usize) -> Self {
        BandedSym {
            n,
            p,
            data: vec![0.0; n * (p + 1)],
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Half-bandwidth `p`.
    pub fn half_bandwidth(&self) -> usize {
        self.p
    }

    /// Set every entry to zero (keeps the storage).
    pub fn fill_zero(&mut self) {
        self.data.iter_mut().for_each(|v| *v = 0.0);
    }

    /// `A[i, j]` (either triangle; 0 outside the band).
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Real {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.p || i >= self.n {
            0.0
        } else {
            self.data[j * (self.p + 1) + (i - j)]
        }
    }

    /// `A[i, j] += v` (and `A[j, i]`, by symmetry; call once per unordered pair).
    ///
    /// # Panics
    /// If `(i, j)` lies outside the band or the matrix (an assembly bug, not bad input).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: Real) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        assert!(
            i - j <= self.p && i < self.n,
            "banded add ({i},{j}) outside band"
        );
        self.data[j * (self.p + 1) + (i - j)] += v;
    }

    /// Add the symmetric `k × k` block `h` (row-major, `h[r*k + c]`, only `r ≥ c` read) at
    /// the diagonal offset `o`. Requires `k ≤ p + 1`.
    #[inline]
    pub fn add_block(&mut self, o: usize, k: usize, h: &[Real]) {
        debug_assert!(k <= self.p + 1 && o + k <= self.n);
        for c in 0..k {
            let col = (o + c) * (self.p + 1);
            for r in c..k {
                self.data[col + (r - c)] += h[r * k + c];
            }
        }
    }

    /// `y = A[r, r]·x` on the principal sub-block `r` (`x`, `y` of length `r.len()`).
    pub fn matvec(&self, r: Range<usize>, x: &[Real], y: &mut [Real]) {
        let m = r.len();
        let lo = r.start;
        y[..m].iter_mut().for_each(|v| *v = 0.0);
        for j in 0..m {
            let col = (lo + j) * (self.p + 1);
            y[j] += self.data[col] * x[j];
            for k in 1..=self.p.min(m - 1 - j) {
                let a = self.data[col + k];
                y[j + k] += a * x[j];
                y[j] += a * x[j + k];
            }
        }
    }

    /// The stored lower band (layout in the module docs): entry `A[i, j]`, `j ≤ i ≤ j + p`, at
    /// `j·(p+1) + (i − j)`.
    pub fn band(&self) -> &[Real] {
        &self.data
    }

    /// The stored lower band, writable (same layout as [`BandedSym::band`]).
    pub fn band_mut(&mut self) -> &mut [Real] {
        &mut self.data
    }

    /// The dense copy (tests and diagnostics only: allocates).
    pub fn to_dense(&self) -> nalgebra::DMatrix<Real> {
        nalgebra::DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }

    /// Largest absolute entry.
    pub fn max_abs(&self) -> Real {
        self.data.iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// A zero or non-finite pivot met by the unpivoted LDLᵀ: the leading minor of that order is
/// singular (or the matrix holds NaN/∞).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PivotError {
    /// Index of the pivot within the factored block.
    pub index: usize,
    /// Its value.
    pub pivot: Real,
}

impl std::fmt::Display for PivotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LDLᵀ pivot {} is {}", self.index, self.pivot)
    }
}

/// The LDLᵀ factors of a principal sub-block of a [`BandedSym`], with scratch for solves.
#[derive(Debug, Clone)]
pub struct BandedLdlt {
    cap: usize,
    p: usize,
    m: usize,
    /// Strict lower band of `L` by rows: row `i` at `l[i(p+1) ..]`, slot `t` ↔ column `i − p + t`.
    l: Vec<Real>,
    d: Vec<Real>,
    v: Vec<Real>,
    av: Vec<Real>,
    /// Working copy of the band (column layout, `p` spare columns) for the right-looking
    /// factorization at `p =` [`HALF_BANDWIDTH`].
    work: Vec<Real>,
}

impl BandedLdlt {
    /// Storage for blocks of dimension up to `cap` with half-bandwidth `p`.
    pub fn new(cap: usize, p: usize) -> Self {
        BandedLdlt {
            cap,
            p,
            m: 0,
            l: vec![0.0; cap * (p + 1)],
            d: vec![0.0; cap],
            v: vec![0.0; cap],
            av: vec![0.0; cap],
            work: vec![0.0; (cap + p) * (p + 1)],
        }
    }

    /// Dimension of the last factored block.
    pub fn dim(&self) -> usize {
        self.m
    }

    /// The pivots `D` of the last factorization.
    pub fn pivots(&self) -> &[Real] {
        &self.d[..self.m]
    }

    /// Factor `A[r, r] = L·D·Lᵀ`. On error the factor is unusable (inertia and solves are
    /// meaningless) until the next successful call.
    ///
    /// Row-oriented ("up-looking"): row `i` of `L` is computed from the rows above it by short
    /// contiguous dot products (`L` is stored by rows, `p` entries left of the diagonal).
    ///
    /// # Panics
    /// If `r` exceeds the matrix, the capacity or the bandwidth differs (programming errors).
    pub fn factor(&mut self, a: &BandedSym, r: Range<usize>) -> Result<(), PivotError> {
        let p = self.p;
        assert!(a.p == p && r.end <= a.n && r.len() <= self.cap);
        if p == HALF_BANDWIDTH {
            return self.factor_fixed::<HALF_BANDWIDTH>(a, r);
        }
        if p == KKT_HALF_BANDWIDTH {
            return self.factor_fixed::<KKT_HALF_BANDWIDTH>(a, r);
        }
        let m = r.len();
        let lo_r = r.start;
        self.m = m;
        let pp = p + 1;
        // Row i of L lives in l[i·pp .. i·pp + p]: slot t ↔ column k = i − p + t (slots with
        // k < 0 stay zero); u_k = L_ik·d_k is built in place, then divided by d.
        for i in 0..m {
            let k0 = i.saturating_sub(p);
            let t0 = k0 + p - i; // first used slot
            let row = i * pp;
            for t in 0..t0 {
                self.l[row + t] = 0.0;
            }
            // Gather A[i, k] for k in k0..i (band column k, offset i − k).
            for k in k0..i {
                self.l[row + (k + p - i)] = a.data[(lo_r + k) * pp + (i - k)];
            }
            // u_j = A_ij − Σ_{k<j} u_k L_jk, for j = k0..i, using rows j above.
            for j in k0..i {
                let tj = j + p - i; // slot of column j in row i
                                    // Row j's slots: column k ↔ slot k + p − j. Common columns k ∈ [max(k0, j−p), j).
                let kk0 = k0.max(j.saturating_sub(p));
                let n_common = j - kk0;
                if n_common > 0 {
                    let si = row + (kk0 + p - i);
                    let sj = j * pp + (kk0 + p - j);
                    let (ri, rj) = (&self.l[si..si + n_common], &self.l[sj..sj + n_common]);
                    let mut acc = 0.0;
                    for (x, y) in ri.iter().zip(rj) {
                        acc += x * y;
                    }
                    self.l[row + tj] -= acc;
                }
            }
            // d_i = A_ii − Σ_k u_k² / d_k, then L_ik = u_k / d_k.
            let mut di = a.data[(lo_r + i) * pp];
            for k in k0..i {
                let t = k + p - i;
                let u = self.l[row + t];
                let lik = u / self.d[k];
                di -= u * lik;
                self.l[row + t] = lik;
            }
            if di == 0.0 || !di.is_finite() {
                return Err(PivotError {
                    index: i,
                    pivot: di,
                });
            }
            self.d[i] = di;
        }
        Ok(())
    }

    /// [`BandedLdlt::factor`] for the half-bandwidth `P` known at compile time (the DER
    /// Hessian's, 10, and the inextensible rod's KKT matrix's, 12): the same `L·D·Lᵀ`, computed right-looking ("outer product") on a working copy
    /// of the band, whose fixed-length column updates the compiler unrolls and vectorizes
    /// (≈ 4× faster than the row-oriented loop at `P = 10`). Column `k`: `d_k = W_kk`,
    /// `L_{k+r,k} = W_{k+r,k}/d_k`, then `W_{k+r,k+c} −= L_{k+r,k}·W_{k+c,k}` for `1 ≤ c ≤ r ≤ P`.
    fn factor_fixed<const P: usize>(
        &mut self,
        a: &BandedSym,
        r: Range<usize>,
    ) -> Result<(), PivotError> {
        const { assert!(P == HALF_BANDWIDTH || P == KKT_HALF_BANDWIDTH) };
        let pp = P + 1;
        let m = r.len();
        let lo = r.start;
        self.m = m;
        // Working copy in A's column layout: W[j·pp + t] = A[lo + j + t, lo + j], entries whose
        // row falls outside the block zeroed; P spare columns absorb the updates past the end.
        let w = &mut self.work[..(m + P) * pp];
        for j in 0..m {
            let src = &a.data[(lo + j) * pp..(lo + j + 1) * pp];
            let dst = &mut w[j * pp..(j + 1) * pp];
            let keep = (m - j).min(pp);
            dst[..keep].copy_from_slice(&src[..keep]);
            dst[keep..].iter_mut().for_each(|x| *x = 0.0);
        }
        for k in 0..m {
            // Column k and the P columns it updates: a window of fixed length (no bounds checks
            // once the loops are unrolled).
            let win = &mut w[k * pp..(k + pp) * pp];
            let d = win[0];
            if d == 0.0 || !d.is_finite() {
                return Err(PivotError { index: k, pivot: d });
            }
            self.d[k] = d;
            let inv = 1.0 / d;
            let mut lcol = [0.0; 16];
            for t in 1..=P {
                lcol[t] = win[t] * inv;
            }
            // Columns k+1 … k+P, each with a constant trip count (unrolled and vectorized).
            update_column::<P, 1>(win, &lcol);
            update_column::<P, 2>(win, &lcol);
            update_column::<P, 3>(win, &lcol);
            update_column::<P, 4>(win, &lcol);
            update_column::<P, 5>(win, &lcol);
            update_column::<P, 6>(win, &lcol);
            update_column::<P, 7>(win, &lcol);
            update_column::<P, 8>(win, &lcol);
            update_column::<P, 9>(win, &lcol);
            update_column::<P, 10>(win, &lcol);
            if P > 10 {
                update_column::<P, 11>(win, &lcol);
                update_column::<P, 12>(win, &lcol);
            }
            for t in 1..=P.min(m - 1 - k) {
                self.l[(k + t) * pp + (P - t)] = lcol[t];
            }
        }
        Ok(())
    }

    /// `(positive, negative)` pivot counts = the inertia of the factored block.
    pub fn inertia(&self) -> (usize, usize) {
        let neg = self.d[..self.m].iter().filter(|&&d| d < 0.0).count();
        (self.m - neg, neg)
    }

    /// Solve `A[r, r]·x = b` in place (`b` of length `m`).
    pub fn solve_in_place(&self, b: &mut [Real]) {
        let (m, p, pp) = (self.m, self.p, self.p + 1);
        // L y = b (row i: y_i = b_i − Σ_k L_ik y_k).
        for i in 0..m {
            let k0 = i.saturating_sub(p);
            let row = i * pp + (k0 + p - i);
            let mut s = b[i];
            for (l, y) in self.l[row..row + (i - k0)].iter().zip(&b[k0..i]) {
                s -= l * y;
            }
            b[i] = s;
        }
        for i in 0..m {
            b[i] /= self.d[i];
        }
        // Lᵀ x = z (column sweep from the bottom: x_k −= L_ik x_i).
        for i in (0..m).rev() {
            let k0 = i.saturating_sub(p);
            let row = i * pp + (k0 + p - i);
            let xi = b[i];
            for (l, x) in self.l[row..row + (i - k0)].iter().zip(&mut b[k0..i]) {
                *x -= l * xi;
            }
        }
    }

    /// The eigenvalue of `A[r, r]` of smallest magnitude, estimated by `iters` steps of inverse
    /// iteration (with the factors of the same block) and a Rayleigh quotient. Near a
    /// singular matrix it converges in a few steps (the ratio |λ₁/λ₂| is small). `a` must be
    /// the matrix that was factored. Deterministic start vector.
    pub fn smallest_eigenvalue(&mut self, a: &BandedSym, r: Range<usize>, iters: usize) -> Real {
        self.smallest_eigenvalue_warm(a, r, iters, false)
    }

    /// As [`BandedLdlt::smallest_eigenvalue`], starting from the vector of the previous call
    /// when `warm` (same dimension): along a continuation the eigenvector changes little.
    pub fn smallest_eigenvalue_warm(
        &mut self,
        a: &BandedSym,
        r: Range<usize>,
        iters: usize,
        warm: bool,
    ) -> Real {
        let m = self.m;
        debug_assert_eq!(r.len(), m);
        let mut v = std::mem::take(&mut self.v);
        let mut av = std::mem::take(&mut self.av);
        let usable =
            warm && v[..m].iter().any(|x| *x != 0.0) && v[..m].iter().all(|x| x.is_finite());
        if !usable {
            for (i, x) in v[..m].iter_mut().enumerate() {
                // A smooth, non-symmetric start: overlaps every low mode.
                *x = 1.0 + 0.37 * ((i as Real) * 0.618).sin();
            }
        }
        let mut lam = 0.0;
        for _ in 0..iters.max(1) {
            let nrm = v[..m].iter().map(|x| x * x).sum::<Real>().sqrt();
            v[..m].iter_mut().for_each(|x| *x /= nrm);
            a.matvec(r.clone(), &v, &mut av);
            lam = v[..m].iter().zip(&av[..m]).map(|(x, y)| x * y).sum();
            self.solve_in_place(&mut v[..m]);
        }
        self.v = v;
        self.av = av;
        lam
    }
}

/// The right-looking update of column `k + C` by column `k` in the window of
/// [`BandedLdlt::factor_fixed`] (`win[c·(P+1) + t − c]` is `W[k + t, k + c]`): constant trip count.
#[inline(always)]
fn update_column<const P: usize, const C: usize>(win: &mut [Real], lcol: &[Real; 16]) {
    if C > P {
        return;
    }
    let pp = P + 1;
    let uc = win[C];
    let dst = &mut win[C * pp..C * pp + (P + 1).saturating_sub(C)];
    for (x, l) in dst.iter_mut().zip(&lcol[C..=P]) {
        *x -= l * uc;
    }
}
