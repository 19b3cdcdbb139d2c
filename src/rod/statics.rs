//! Static equilibrium by Newton's method on the free DOFs, and the stability test.
//!
//! Equilibrium: `∂E/∂q_f = 0` on the free DOFs `f` (a contiguous range, e.g.
//! [`Rod::free_range_clamped`]). Each iteration re-bases the reference frames at the iterate
//! ([`RodState::update_reference`]), assembles the gradient and the banded Hessian
//! ([`energy::energy_gradient_hessian`]), factors the free block `H_ff = L D Lᵀ`
//! ([`BandedLdlt`](super::BandedLdlt)) and steps `Δ = −H_ff⁻¹ g_f`, backtracking (halving) while the residual
//! `‖g_f‖∞` does not decrease. Newton seeks stationary points, not minima, so it converges to
//! unstable equilibria too (which is what a stability test along a branch needs).
//!
//! External load: with a constant force `F` in [`Workspace::external`] (gravity,
//! [`Workspace::set_weight`]) the energy is `E(q) − Fᵀq`: the gradient gains `−F`, the Hessian
//! nothing, so the stability test below is the elastic Hessian's at the loaded equilibrium.
//!
//! Convergence: the Newton step satisfies `‖Δ‖∞ ≤ step_tol`, or the residual is at the
//! round-off floor `‖g_f‖∞ ≤ max(rel_residual_tol·(k_b + ‖g‖∞), 16·k_s·ε)` (the second term is
//! the round-off of a stiff stretching force; near a critical point the Hessian
//! is nearly singular and the step along the critical mode is dominated by round-off, so the
//! residual criterion is the one that ends the iteration there; an iterate within 10³× that
//! tolerance is accepted when the next step fails to reduce the residual).
//!
//! Stability: the equilibrium is stable iff `H_ff` is positive definite, i.e. the LDLᵀ inertia
//! has no negative pivot. The factorization used is the one at the converged iterate (the
//! last Hessian is assembled at the returned state).

use super::banded::PivotError;
use super::energy;
use super::params::Rod;
use super::state::RodState;
use super::workspace::Workspace;
use crate::error::{Error, Result};
use crate::math::Real;
use std::ops::Range;

/// The residual floor accepted when Newton stalls, as a multiple of `rel_residual_tol` (this
/// solver's and [`super::inextensible`]'s).
pub(super) const FLOOR_FACTOR: Real = 1e3;
/// Default Newton step tolerance of a static solve ([`NewtonParams::step_tol`]): the max-norm of
/// the update, nondimensional (positions in units of L, angles in radians).
pub const DEFAULT_STEP_TOL: Real = 1e-11;
/// Default relative residual tolerance of a static solve ([`NewtonParams::rel_residual_tol`]):
/// the free gradient's max-norm relative to `k_b + ‖g‖∞` (module docs, "Convergence").
pub const DEFAULT_REL_RESIDUAL_TOL: Real = 1e-10;
/// Round-off of the stretching force in units of `k_s·ε` counted into the residual floor (a
/// node's gradient sums the forces of two edges, each with a few roundings).
const STRETCH_ROUNDOFF: Real = 16.0;

/// Newton controls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonParams {
    /// Maximum Newton iterations.
    pub max_iters: usize,
    /// Convergence on the step, `‖Δ‖∞` (length units for positions, radians for twists).
    pub step_tol: Real,
    /// Convergence on the residual relative to `k_b + ‖g‖∞` (dimensionless).
    pub rel_residual_tol: Real,
    /// Maximum halvings of a step in the line search.
    pub max_halvings: usize,
}

impl Default for NewtonParams {
    /// `max_iters = 30`, `step_tol = 1e-11`, `rel_residual_tol = 1e-10`, `max_halvings = 12`.
    fn default() -> Self {
        NewtonParams {
            max_iters: 30,
            step_tol: DEFAULT_STEP_TOL,
            rel_residual_tol: DEFAULT_REL_RESIDUAL_TOL,
            max_halvings: 12,
        }
    }
}

/// Outcome of a converged Newton solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Equilibrium {
    /// Iterations used.
    pub iterations: usize,
    /// Final residual `‖g_f‖∞`.
    pub residual: Real,
    /// Elastic energy at the equilibrium.
    pub energy: Real,
    /// Negative eigenvalues of the free Hessian (LDLᵀ inertia); 0 ⇔ stable.
    pub negative: usize,
}

impl Equilibrium {
    /// Stable ⇔ the free Hessian is positive definite.
    pub fn is_stable(&self) -> bool {
        self.negative == 0
    }
}

/// A backtracking trial's assembly in `ws`: the full step (`full`; accepted in almost every
/// iteration, it is the next iteration's assembly) with its energy, gradient and Hessian,
/// a shorter one with the gradient only (energy NaN). Shared by both Newton solvers.
pub(super) fn assemble_trial(rod: &Rod, trial: &RodState, full: bool, ws: &mut Workspace) -> Real {
    if full {
        assemble(rod, trial, ws)
    } else {
        energy::gradient(rod, trial, &mut ws.grad);
        add_external(trial, &ws.external, &mut ws.grad);
        Real::NAN
    }
}

/// Energy, gradient and Hessian at `state` into `ws`, the external load
/// ([`Workspace::external`]) included: its potential `−Fᵀq` in the energy, `−F` in the
/// gradient (the Hessian is the elastic one). Shared by both Newton solvers.
pub(super) fn assemble(rod: &Rod, state: &RodState, ws: &mut Workspace) -> Real {
    let e = energy::energy_gradient_hessian(rod, state, &mut ws.grad, &mut ws.hess);
    e + add_external(state, &ws.external, &mut ws.grad)
}

/// Subtract the external force `f` (empty: none) from the gradient `g`; returns its potential
/// `−fᵀq`.
fn add_external(state: &RodState, f: &[Real], g: &mut [Real]) -> Real {
    let mut v = 0.0;
    for (k, fk) in f.iter().enumerate() {
        g[k] -= fk;
        v -= fk * state.q[k];
    }
    v
}

/// The backtracking rule of both Newton solvers: a trial with residual `r` at step fraction
/// `alpha` is accepted when `r` is finite and below the current residual `res`, or — once
/// `alpha` < 1/1024 and `res` is not yet at its round-off floor — whenever it is finite.
pub(super) fn backtrack_accepts(r: Real, res: Real, alpha: Real, at_floor: bool) -> bool {
    r.is_finite() && (r < res || (alpha < 1.0 / 1024.0 && !at_floor))
}

/// The max norm ‖v‖∞.
pub(crate) fn inf_norm(v: &[Real]) -> Real {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The error of a Newton solve `solver` whose matrix `matrix` has no LDLᵀ.
pub(crate) fn singular(solver: &str, matrix: &str, e: PivotError, iterations: usize) -> Error {
    Error::NotConverged {
        what: format!("{solver} ({e}: singular {matrix})"),
        iterations,
        residual: Real::NAN,
    }
}

/// Solve for the equilibrium on the free DOFs `free`, starting from `state` (whose reference
/// frames must be up to date). On success `state` holds the equilibrium and `ws.ldlt` the
/// LDLᵀ of its free Hessian, `ws.hess` the full Hessian and `ws.grad` the gradient (fixed-DOF
/// entries are the reaction forces).
pub fn solve(
    rod: &Rod,
    state: &mut RodState,
    free: Range<usize>,
    ws: &mut Workspace,
    params: &NewtonParams,
) -> Result<Equilibrium> {
    assert!(ws.fits(rod) && free.end <= rod.n_dofs());
    let m = free.len();
    let mut trial = ws.trial.take().unwrap_or_else(|| state.clone());
    let result = (|| {
        let mut last_res = Real::INFINITY;
        // Whether ws.grad/ws.hess (and `e`) already hold the values at `state`: a full step
        // accepted by the line search was assembled there (one assembly per iteration).
        let mut assembled = false;
        let mut e = Real::NAN;
        for it in 0..params.max_iters {
            if !assembled {
                e = assemble(rod, state, ws);
            }
            assembled = false;
            let res = inf_norm(&ws.grad[free.clone()]);
            // The stretching force k_s(ℓ/ē − 1) carries a round-off of ~k_s·ε per edge (ℓ is
            // known to ε relative): with a stiff penalty that, not rel_residual_tol, is the floor.
            let scale = (rod.material.bend + inf_norm(&ws.grad)).max(
                STRETCH_ROUNDOFF * rod.material.stretch * Real::EPSILON / params.rel_residual_tol,
            );
            ws.ldlt
                .factor(&ws.hess, free.clone())
                .map_err(|er| singular("DER Newton", "free Hessian", er, it))?;
            let e_here = e;
            let done = |negative| Equilibrium {
                iterations: it,
                residual: res,
                energy: e_here,
                negative,
            };
            if res <= params.rel_residual_tol * scale {
                return Ok(done(ws.ldlt.inertia().1));
            }
            for (k, s) in ws.step[..m].iter_mut().enumerate() {
                *s = -ws.grad[free.start + k];
            }
            ws.ldlt.solve_in_place(&mut ws.step[..m]);
            let step = inf_norm(&ws.step[..m]);
            if step <= params.step_tol {
                return Ok(done(ws.ldlt.inertia().1));
            }
            let at_floor = res <= FLOOR_FACTOR * params.rel_residual_tol * scale;
            // Round-off floor: the residual stopped decreasing fast although the step is not
            // tiny (near-singular Hessian): accept if it is already small.
            if it >= 3 && res >= 0.5 * last_res && at_floor {
                return Ok(done(ws.ldlt.inertia().1));
            }
            last_res = res;
            // Backtracking on the residual.
            let mut alpha = 1.0;
            let mut accepted = false;
            for _ in 0..=params.max_halvings {
                trial.copy_from(state);
                for k in 0..m {
                    trial.q[free.start + k] += alpha * ws.step[k];
                }
                if trial.update_reference() {
                    // The full step is assembled with its Hessian (accepted in almost every
                    // iteration, it is the next iteration's assembly); shorter ones need only
                    // the gradient.
                    let full = alpha == 1.0;
                    let e_trial = assemble_trial(rod, &trial, full, ws);
                    let r = inf_norm(&ws.grad[free.clone()]);
                    if backtrack_accepts(r, res, alpha, at_floor) {
                        accepted = true;
                        if full {
                            assembled = true;
                            e = e_trial;
                        }
                        break;
                    }
                }
                alpha *= 0.5;
            }
            if !accepted {
                if at_floor {
                    // Near a singular point the step is round-off along the critical mode
                    // and cannot reduce a residual already at the floor: accept the iterate
                    // (its gradient and Hessian re-assembled: the trials overwrote them).
                    assemble(rod, state, ws);
                    return Ok(done(ws.ldlt.inertia().1));
                }
                return Err(Error::NotConverged {
                    what: "DER Newton line search".into(),
                    iterations: it,
                    residual: res,
                });
            }
            state.copy_from(&trial);
        }
        Err(Error::NotConverged {
            what: "DER Newton equilibrium".into(),
            iterations: params.max_iters,
            residual: last_res,
        })
    })();
    ws.trial = Some(trial);
    result
}

/// Inertia of the free Hessian at `state` (assembles and factors; no Newton).
/// Returns the number of negative eigenvalues.
pub fn negative_eigenvalues(
    rod: &Rod,
    state: &RodState,
    free: Range<usize>,
    ws: &mut Workspace,
) -> Result<usize> {
    energy::hessian(rod, state, &mut ws.hess);
    ws.ldlt
        .factor(&ws.hess, free)
        .map_err(|e| singular("DER Newton", "free Hessian", e, 0))?;
    Ok(ws.ldlt.inertia().1)
}
