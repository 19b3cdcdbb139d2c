//! The Lyapunov–Schmidt / Koiter reduction of the DER energy at a critical equilibrium.
//!
//! Given an equilibrium `q₀` of the clamped rod (free gradient ≈ 0) whose free Hessian `H` has
//! one eigenvalue `λ` near zero with unit eigenvector `φ` (Euclidean norm on the free DOFs),
//! [`reduce`] returns the coefficients of the reduced energy along the mode
//!
//! `E_red(x) = min_{y ⊥ φ} E(q₀ + xφ + y) − E(q₀) = ½λx² + (a/6)x³ + (b/24)x⁴ + O(x⁵)`,
//!
//! whose minimizer is `y = x²w + O(x³)` with `w = −½·H⊥⁻¹·r⊥` the second-order correction (`r = E‴[φ, φ, ·]`, `⊥` the complement of
//! φ), so that `b = E⁗[φ,φ,φ,φ] − 3·r⊥ᵀH⊥⁻¹r⊥` is the post-buckling (Koiter) coefficient.
//!
//! # Numerics
//! - The critical pair (λ, φ) comes from inverse iteration with the banded LDLᵀ of the free
//!   Hessian (near s* the ratio λ/λ₂ is tiny, so a few steps converge to round-off).
//! - `r = E‴[φ, φ, ·]` is the second central difference of the analytic gradient along φ,
//!   and `w` the projected solve above; they only provide a good start (below).
//! - **b is not taken from energy values along the quadratic path** `q₀ + xφ + x²w`: with the
//!   stiff stretching (`k_s L²/k_b = 10⁶`) the O(x³) residual stretch of that path costs
//!   `k_s·x⁶`, which swamps `b·x⁴/24` at every amplitude above round-off. Instead the reduced
//!   energy is computed as the Lyapunov–Schmidt reduction itself: the minimum of E over the
//!   hyperplane `cᵀ(x − x₀) = ξ` (c the node-position part of φ, normalized; `α = |φ_x|`),
//!   by Newton on the bordered system, continued in ξ from the previous amplitude with the
//!   quadratic path `xφ + x²w` (`x = ξ/α`) as predictor. Its even
//!   part is `f_e(ξ) = ½λ(ξ/α)²(1 + O(λ)) + (b/24)(ξ/α)⁴ + O(ξ⁶)` with every stiff direction
//!   relaxed. (For an odd mode `cᵀw = 0` by the symmetry, so the amplitude ξ = αx + O(x³),
//!   which changes the x⁴ coefficient only by a multiple of λ ≈ 0.)
//! - `f_e` is fitted by `Aξ² + Bξ⁴ + Cξ⁶` at ξ = (1,2,3)h' and at (1,2,4)h'; `b = 24Bα⁴` from the
//!   first, and the difference of the two is the reported error. The amplitude: the largest
//!   node moves [`AMPLITUDE`]·L at ξ = h'. The odd part gives `a` (Richardson over h', 2h').
//! - The constraint is on node positions only, so it does not depend on the chart of the
//!   twist angles; the energy at the constrained minimum is that of a physical configuration.

use crate::error::{Error, Result};
use crate::math::Real;
use crate::rod::energy;
use crate::rod::{Rod, RodState, Workspace};
use std::ops::Range;

/// Largest node displacement (units of L) of the finite-difference amplitude h.
pub const AMPLITUDE: Real = 1.5e-2;
/// Inverse-iteration steps for the critical mode.
const INVERSE_ITERS: usize = 8;

/// The critical eigenpair of the free Hessian at a state.
#[derive(Debug, Clone)]
pub struct CriticalMode {
    /// The eigenvalue of smallest magnitude (Rayleigh quotient).
    pub lambda: Real,
    /// Its unit eigenvector on the full DOF vector (zero on the clamped DOFs).
    pub phi: Vec<Real>,
    /// Largest node displacement of φ (max over nodes of |φ_xᵢ|).
    pub max_node: Real,
}

/// The coefficients of the reduced energy (see the module docs).
#[derive(Debug, Clone)]
pub struct Reduction {
    /// The critical mode.
    pub mode: CriticalMode,
    /// Cubic coefficient `a = E‴[φ,φ,φ]` (0 for a mode odd under the rod's Z2 symmetry).
    pub a: Real,
    /// Quartic (Koiter) coefficient `b = E⁗[φ⁴] − 3 r⊥ᵀH⊥⁻¹r⊥`.
    pub b: Real,
    /// `|b(h) − b(2h)|`-type estimate of the finite-difference error of b.
    pub b_error: Real,
    /// The amplitude h used (Euclidean norm of the free DOFs).
    pub h: Real,
    /// The second-order correction `w` (full DOF vector, zero on clamped DOFs).
    pub w: Vec<Real>,
}

/// The eigenpair of smallest magnitude of the free Hessian at `state` (inverse iteration on
/// the banded LDLᵀ; `ws` is overwritten).
pub fn critical_mode(
    rod: &Rod,
    state: &RodState,
    free: Range<usize>,
    ws: &mut Workspace,
) -> Result<CriticalMode> {
    energy::hessian(rod, state, &mut ws.hess);
    ws.ldlt
        .factor(&ws.hess, free.clone())
        .map_err(|e| Error::NotConverged {
            what: format!("critical mode: singular free Hessian ({e})"),
            iterations: 0,
            residual: e.pivot,
        })?;
    let m = free.len();
    let mut v: Vec<Real> = (0..m)
        .map(|i| 1.0 + 0.37 * ((i as Real) * 0.618).sin() + 0.21 * ((i as Real) * 0.0917).cos())
        .collect();
    let mut av = vec![0.0; m];
    for _ in 0..INVERSE_ITERS {
        normalize(&mut v);
        ws.ldlt.solve_in_place(&mut v);
    }
    normalize(&mut v);
    ws.hess.matvec(free.clone(), &v, &mut av);
    let lambda: Real = v.iter().zip(&av).map(|(x, y)| x * y).sum();
    if !lambda.is_finite() {
        return Err(Error::NotConverged {
            what: "critical mode (inverse iteration)".into(),
            iterations: INVERSE_ITERS,
            residual: lambda,
        });
    }
    let mut phi = vec![0.0; rod.n_dofs()];
    phi[free.clone()].copy_from_slice(&v);
    let max_node = (0..=rod.n_edges())
        .map(|i| {
            let o = 4 * i;
            (phi[o] * phi[o] + phi[o + 1] * phi[o + 1] + phi[o + 2] * phi[o + 2]).sqrt()
        })
        .fold(0.0, Real::max);
    Ok(CriticalMode {
        lambda,
        phi,
        max_node,
    })
}

fn normalize(v: &mut [Real]) {
    let n = v.iter().map(|x| x * x).sum::<Real>().sqrt();
    v.iter_mut().for_each(|x| *x /= n);
}

fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `base` moved by `dq` (full DOF vector), frames transported in one step from `base`.
fn perturbed(base: &RodState, dq: &[Real], out: &mut RodState) -> Result<()> {
    out.copy_from(base);
    for (q, d) in out.q.iter_mut().zip(dq) {
        *q += d;
    }
    if !out.update_reference() {
        return Err(Error::invalid(
            "amplitude",
            "",
            "the perturbed rod has a zero-length edge",
        ));
    }
    Ok(())
}

/// Euclidean norm of the node-position part of a DOF vector.
fn position_norm(v: &[Real], n_edges: usize) -> Real {
    (0..=n_edges)
        .map(|i| v[4 * i] * v[4 * i] + v[4 * i + 1] * v[4 * i + 1] + v[4 * i + 2] * v[4 * i + 2])
        .sum::<Real>()
        .sqrt()
}

/// Newton iterations of the constrained minimization.
const CONSTRAINED_ITERS: usize = 40;
/// Step halvings of the constrained Newton's line search.
const CONSTRAINED_HALVINGS: usize = 20;
/// Convergence of the constrained Newton on its step (length units / radians).
const CONSTRAINED_STEP_TOL: Real = 1e-13;
/// Convergence of the constrained Newton on the projected residual, relative to
/// `k_b + ‖g‖∞` (as [`crate::rod::statics::NewtonParams::rel_residual_tol`], tighter: the
/// energies differ by ~b·x⁴/24 only).
const CONSTRAINED_REL_RESIDUAL: Real = 1e-12;
/// Round-off of the stretching force in units of `k_s·ε` (as in [`crate::rod::statics`]).
const STRETCH_ROUNDOFF: Real = 16.0;
/// An iterate whose residual is within this factor of the round-off floor is accepted when
/// the line search can no longer reduce it.
const FLOOR_FACTOR: Real = 1e3;

/// The rod's equilibrium under one linear constraint on the node positions,
/// `cᵀ(x − x₀) = ξ` (`c` a unit vector on the position DOFs): the minimum of E over that
/// hyperplane. Newton on the bordered system `[H c; cᵀ 0]` by block elimination with the
/// banded LDLᵀ of H (`dq = H⁻¹(−g) − μH⁻¹c`, `μ` so that `cᵀdq = 0`), reference frames
/// updated after every iterate, as in [`crate::rod::statics::solve`]. The constraint is on
/// positions only, so it does not depend on the reference-frame chart of the twist angles.
///
/// Convergence is judged, as in [`crate::rod::statics::solve`], on the residual projected
/// onto the constraint hyperplane, `r = g − (cᵀg)c` (at the constrained minimum `g ∥ c`),
/// with the round-off floor `16·k_s·ε` of the stiff stretching force: a criterion on the step
/// alone never holds when that round-off, divided by a soft eigenvalue, exceeds it (it made
/// the reduction abort a quarter-sphere sweep at (0.535, 0.07, −0.842)). Every step
/// backtracks (halving) until the projected residual decreases.
struct ConstrainedMin {
    st: Option<RodState>,
    trial: Option<RodState>,
    u: Vec<Real>,
    v: Vec<Real>,
    free: Range<usize>,
    /// Newton iterations of the last solve.
    iterations: usize,
}

/// `‖g − (cᵀg)c‖∞` over the free DOFs.
fn projected_residual(g: &[Real], c: &[Real], free: Range<usize>) -> Real {
    let cg: Real = free.clone().map(|k| c[k] * g[k]).sum();
    free.map(|k| (g[k] - cg * c[k]).abs()).fold(0.0, Real::max)
}

impl ConstrainedMin {
    fn new(rod: &Rod, free: Range<usize>) -> Self {
        let m = free.len();
        let _ = rod;
        ConstrainedMin {
            st: None,
            trial: None,
            u: vec![0.0; m],
            v: vec![0.0; m],
            free,
            iterations: 0,
        }
    }

    /// The constrained minimum at amplitude `xi` (left in `out`), starting from `start` moved
    /// by `dx·φ + dx2·w` (the predictor), then projected onto the constraint. Returns its
    /// energy.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        rod: &Rod,
        base: &RodState,
        start: &RodState,
        (phi, dx): (&[Real], Real),
        (w, dx2): (&[Real], Real),
        c: &[Real],
        xi: Real,
        ws: &mut Workspace,
        out: &mut RodState,
    ) -> Result<Real> {
        let free = self.free.clone();
        let mut st = self.st.take().unwrap_or_else(|| base.clone());
        let mut trial = self.trial.take().unwrap_or_else(|| base.clone());
        st.copy_from(start);
        let mut off = 0.0;
        for k in free.clone() {
            st.q[k] += dx * phi[k] + dx2 * w[k];
        }
        if !st.update_reference() {
            return Err(Error::invalid(
                "amplitude",
                xi,
                "degenerate constrained rod",
            ));
        }
        for k in free.clone() {
            off += c[k] * (st.q[k] - base.q[k]);
        }
        for k in free.clone() {
            st.q[k] += (xi - off) * c[k];
        }
        if !st.update_reference() {
            return Err(Error::invalid(
                "amplitude",
                xi,
                "degenerate constrained rod",
            ));
        }
        let result = self.newton(rod, &mut st, &mut trial, c, ws);
        self.iterations = match &result {
            Ok(it) => *it,
            Err(_) => CONSTRAINED_ITERS,
        };
        let result = result.map(|_| {
            out.copy_from(&st);
            energy::energy(rod, &st)
        });
        self.st = Some(st);
        self.trial = Some(trial);
        result
    }

    /// Newton iterations from `st` (on the constraint) to the constrained minimum; returns the
    /// iterations spent.
    fn newton(
        &mut self,
        rod: &Rod,
        st: &mut RodState,
        trial: &mut RodState,
        c: &[Real],
        ws: &mut Workspace,
    ) -> Result<usize> {
        let free = self.free.clone();
        let not_converged = |it, res, what: &str| Error::NotConverged {
            what: format!("constrained minimization along the critical mode: {what}"),
            iterations: it,
            residual: res,
        };
        let mut last_res = Real::INFINITY;
        for it in 0..CONSTRAINED_ITERS {
            energy::energy_gradient_hessian(rod, st, &mut ws.grad, &mut ws.hess);
            let res = projected_residual(&ws.grad, c, free.clone());
            let gmax = ws.grad.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
            let scale = (rod.material.bend + gmax).max(
                STRETCH_ROUNDOFF * rod.material.stretch * Real::EPSILON / CONSTRAINED_REL_RESIDUAL,
            );
            if !res.is_finite() {
                return Err(not_converged(it, res, "non-finite residual"));
            }
            if res <= CONSTRAINED_REL_RESIDUAL * scale {
                return Ok(it);
            }
            let at_floor = res <= FLOOR_FACTOR * CONSTRAINED_REL_RESIDUAL * scale;
            if it >= 3 && res >= 0.5 * last_res && at_floor {
                return Ok(it);
            }
            last_res = res;
            ws.ldlt
                .factor(&ws.hess, free.clone())
                .map_err(|e| not_converged(it, e.pivot, &format!("singular Hessian ({e})")))?;
            for (i, k) in free.clone().enumerate() {
                self.u[i] = -ws.grad[k];
                self.v[i] = c[k];
            }
            ws.ldlt.solve_in_place(&mut self.u);
            ws.ldlt.solve_in_place(&mut self.v);
            let cu: Real = free
                .clone()
                .enumerate()
                .map(|(i, k)| c[k] * self.u[i])
                .sum();
            let cv: Real = free
                .clone()
                .enumerate()
                .map(|(i, k)| c[k] * self.v[i])
                .sum();
            let mu = cu / cv;
            let mut step: Real = 0.0;
            for i in 0..free.len() {
                self.u[i] -= mu * self.v[i];
                step = step.max(self.u[i].abs());
            }
            if !step.is_finite() {
                return Err(not_converged(it, res, "non-finite step"));
            }
            if step <= CONSTRAINED_STEP_TOL {
                return Ok(it);
            }
            // Backtracking on the projected residual (the step keeps cᵀq fixed for any length).
            let mut alpha = 1.0;
            let mut accepted = false;
            for _ in 0..=CONSTRAINED_HALVINGS {
                trial.copy_from(st);
                for (i, k) in free.clone().enumerate() {
                    trial.q[k] += alpha * self.u[i];
                }
                if trial.update_reference() {
                    energy::gradient(rod, trial, &mut ws.grad);
                    let r = projected_residual(&ws.grad, c, free.clone());
                    if r.is_finite() && r < res {
                        accepted = true;
                        break;
                    }
                }
                alpha *= 0.5;
            }
            if !accepted {
                if at_floor {
                    return Ok(it);
                }
                return Err(not_converged(it, res, "line search"));
            }
            st.copy_from(trial);
        }
        // Out of iterations with the residual at the round-off floor (slow, not stalled):
        // as good as the stall exit above.
        let scale = STRETCH_ROUNDOFF * rod.material.stretch * Real::EPSILON;
        if last_res <= FLOOR_FACTOR * scale.max(CONSTRAINED_REL_RESIDUAL * rod.material.bend) {
            return Ok(CONSTRAINED_ITERS);
        }
        Err(not_converged(CONSTRAINED_ITERS, last_res, "iterations"))
    }
}

/// The Koiter reduction at the equilibrium `base` (see the module docs), with the
/// finite-difference amplitude [`AMPLITUDE`].
pub fn reduce(
    rod: &Rod,
    base: &RodState,
    free: Range<usize>,
    ws: &mut Workspace,
) -> Result<Reduction> {
    reduce_with_amplitude(rod, base, free, ws, AMPLITUDE)
}

/// [`reduce`] with the largest node displacement of the first finite-difference amplitude
/// given (units of L; [`AMPLITUDE`] by default; the fits use up to 4× it).
pub fn reduce_with_amplitude(
    rod: &Rod,
    base: &RodState,
    free: Range<usize>,
    ws: &mut Workspace,
    amplitude: Real,
) -> Result<Reduction> {
    if !(amplitude > 0.0 && amplitude <= 0.1) {
        return Err(Error::invalid(
            "amplitude",
            amplitude,
            "must lie in (0, 0.1]",
        ));
    }
    let mode = critical_mode(rod, base, free.clone(), ws)?;
    let nd = rod.n_dofs();
    let phi = &mode.phi;
    let h = amplitude / mode.max_node.max(crate::math::tol::TINY);
    let mut scratch = base.clone();
    let mut dq = vec![0.0; nd];
    // r = E'''[φ, φ, ·] on the free DOFs.
    let mut g0 = vec![0.0; nd];
    energy::gradient(rod, base, &mut g0);
    let mut r = vec![0.0; nd];
    let mut g = vec![0.0; nd];
    for sign in [1.0, -1.0] {
        for (d, p) in dq.iter_mut().zip(phi) {
            *d = sign * h * p;
        }
        perturbed(base, &dq, &mut scratch)?;
        energy::gradient(rod, &scratch, &mut g);
        for k in free.clone() {
            r[k] += g[k];
        }
    }
    for k in free.clone() {
        r[k] = (r[k] - 2.0 * g0[k]) / (h * h);
    }
    // w = −½ H⊥⁻¹ r⊥ (project, solve with the factors of H from critical_mode, project).
    let rp = dot(&r, phi);
    let mut rhs: Vec<Real> = free.clone().map(|k| r[k] - rp * phi[k]).collect();
    ws.ldlt.solve_in_place(&mut rhs);
    let phif = &phi[free.clone()];
    let c = dot(&rhs, phif);
    let mut w = vec![0.0; nd];
    for (i, k) in free.clone().enumerate() {
        w[k] = -0.5 * (rhs[i] - c * phif[i]);
    }
    // The reduced energy by constrained minimization at amplitudes ξ = h, 2h, 3h along the
    // position part c of φ (see the module docs).
    let alpha = position_norm(phi, rod.n_edges());
    let mut c = vec![0.0; nd];
    for i in 0..=rod.n_edges() {
        for a in 0..3 {
            c[4 * i + a] = phi[4 * i + a] / alpha;
        }
    }
    let e0 = energy::energy(rod, base);
    let mut cm = ConstrainedMin::new(rod, free.clone());
    let mut fe = [0.0; 4];
    let mut fo = [0.0; 4];
    // Continuation in the amplitude on each side: the previous minimum plus the change of
    // the quadratic path is the predictor.
    let mut prev = [base.clone(), base.clone()];
    let mut next = base.clone();
    for (k, m) in [1.0, 2.0, 3.0, 4.0].into_iter().enumerate() {
        let mut e = [0.0; 2];
        for (side, sign) in [1.0, -1.0].into_iter().enumerate() {
            let x = sign * m * h;
            let xp = sign * (m - 1.0) * h;
            let ek = cm.solve(
                rod,
                base,
                &prev[side],
                (phi, x - xp),
                (&w, x * x - xp * xp),
                &c,
                x * alpha,
                ws,
                &mut next,
            )?;
            prev[side].copy_from(&next);
            e[side] = ek - e0;
        }
        fe[k] = 0.5 * (e[0] + e[1]);
        fo[k] = 0.5 * (e[0] - e[1]);
    }
    // f_e(ξ) = Aξ² + Bξ⁴ + Cξ⁶ + O(ξ⁸), fitted at ξ = (1, 2, 3)·h' and at (1, 2, 4)·h'
    // (h' = hα); B converted to the amplitude x = ξ/α of the unit mode: b = 24·B·α⁴. The two
    // fits differ by their O(ξ⁸) truncation: the error estimate.
    let hp = h * alpha;
    let fit = |ms: [usize; 3]| -> Real {
        let row = |m: usize| {
            let t = ((m + 1) as Real).powi(2);
            [t, t * t, t * t * t]
        };
        let (r0, r1, r2) = (row(ms[0]), row(ms[1]), row(ms[2]));
        let mat = nalgebra::Matrix3::new(
            r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2],
        );
        let rhs = nalgebra::Vector3::new(fe[ms[0]], fe[ms[1]], fe[ms[2]]);
        mat.lu()
            .solve(&rhs)
            .map_or(Real::NAN, |v| v[1] / hp.powi(4))
    };
    let (b_a, b_b) = (fit([0, 1, 2]), fit([0, 1, 3]));
    let b = 24.0 * b_a * alpha.powi(4);
    let b_error = 24.0 * (b_a - b_b).abs() * alpha.powi(4);
    // f_o(ξ) = (a/6)(ξ/α)³ + O(ξ⁵): Richardson over h', 2h'.
    let a = (32.0 * fo[0] - fo[1]) / (4.0 * h.powi(3));
    Ok(Reduction {
        mode,
        a,
        b,
        b_error,
        h,
        w,
    })
}
