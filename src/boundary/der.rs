//! The DER-statics stability boundary along a ray ([architecture §3](crate::architecture), "DER-predicted boundary").
//!
//! For a unit direction S̄ and a distance s, the rod of length 1 is clamped at both ends
//! ([`crate::rod::clamp`]): edge 0 along z with the identity material frame at the origin, edge
//! n−1 at the end of the helix `(κ, τ, ω) = s·S̄` with its tangent and its material frame (the
//! transported frame turned by `ω/c` about the tangent). The equilibrium is found by Newton
//! ([`crate::rod::statics`]) and followed along the ray by continuation in s: the first point
//! of a ray is a nearly straight rod (s ≤ 1) started from the helix sampled at the nodes, every
//! later one from the sampled helix plus the previous discrete correction scaled like s². A cold
//! start from the sampled helix far along the ray is never used by the search: near s* it can
//! converge to another equilibrium (one with two negative eigenvalues, or a stable buckled
//! shape), which made s* 3–126 % wrong near the τ axis (issue 13). The twist angles start at
//! the uniform twist `θ_j = (ω/c)·s_j` relative to space-parallel reference frames (zero
//! reference twist), and θ_{n−1} is the angle to the imposed end director chosen within π of
//! ω/c: the winding number of the end rotation is the one reached continuously from the
//! straight rod.
//!
//! Stable ⇔ the free Hessian is positive definite (banded LDLᵀ inertia, no eigen-solve). The
//! critical distance s* is bracketed by stepping s geometrically (from 4, ×1.6) and then refined
//! by regula falsi (Illinois) on the free Hessian's smallest-magnitude eigenvalue μ(s)
//! (inverse iteration with the LDLᵀ factors), with the *predicate* deciding which end of the
//! bracket moves and a bisection fallback whenever the bracket fails to halve, until the
//! bracket width is ≤ `tol_rel·s`. A ray stable at `s_max` returns `s* = ∞`.
//!
//! Folds: the discrete clamps and sampling perturb the helix slightly (`O(1/n²)`). Where the
//! critical mode is antisymmetric the loss of stability stays a clean bifurcation (an
//! equilibrium with one negative eigenvalue just past s*); where it is symmetric (e.g. near the
//! τ axis, Euler buckling of the compressed, nearly straight rod) the perturbed branch ends at
//! a fold and Newton finds no nearby equilibrium past it. A Newton failure therefore counts as
//! unstable, and [`DerRay::branch_ended`] reports which case ended the search.
//!
//! [`critical_s`] seeds the bracket search with the continuum s* (`continuum_seed`, default):
//! the DER value differs from it by `O(1/n²)`, so the bracket is found in one or two probes
//! instead of a geometric search from s = 4. The result does not depend on the seed.
//!
//! The κ = 0 plane: the helix is the straight rod; on the τ axis it is untwisted and unloaded,
//! stable for every s, and `s* = ∞` is returned; with ω ≠ 0 it is the twisted clamped rod.
//!
//! # Extensibility
//! The DER rod is extensible with the penalty stiffness `k_s` ([`DerBoundaryParams::stretch`],
//! default [`BOUNDARY_STRETCH`] = 10⁸), the continuum is not. The helix's internal force
//! `|n| = |ω − τ|·√(κ² + τ²)` (∝ s²) strains the rod by `|n|/k_s`, which shifts s* by about
//! that relative amount; with the physical `k_s = 10⁶` this was ~10⁻⁵ … 5·10⁻⁴, above the
//! discretization error at n = 200 on many directions, so the error stopped decreasing with n.
//! Near the κ = 0 plane the end is brought closer to the clamp only by the chord shortening of
//! the helix, `δ = 1 − |r(1)| ≈ κ̂²/2`: when `|n|/k_s` is not small against δ the penalized rod
//! stays straight and compressed instead of buckling (s* = ∞ was returned at (8.6e-6, 1, 0),
//! where the continuum gives the Euler column 2π). [`critical_s`] therefore refuses a
//! direction with `|n|/k_s > 0.1·δ` at the continuum s* ([`check_extensibility`],
//! [`MAX_STRAIN_TO_SHORTENING`]) with an error naming both numbers: with the default `k_s` that
//! is κ̂ ≲ 3·10⁻³ on the τ axis (use the continuum method there, or a larger `stretch`).
//!
//! # Resolution
//! The frames of the helix turn by [`rotation_per_edge`] `φ = s*·√(κ̂² + τ̂² + (ω̂/c)²)/(n − 1)`
//! radians per edge; the relative discretization error is ≈ 0.1…0.3·φ² (straddling clamps):
//! 1.4 % at φ = 0.33 (n = 100) but 55 % at φ = 1.36 (n = 25) on (0.175, −0.366, −0.914),
//! s* ≈ 25.5. Above [`MAX_ROTATION_PER_EDGE`] = 1.5 rad per edge [`critical_s`] returns an error
//! naming the n needed ([`check_resolution`]).
//!
//! # What `est_error` covers
//! The `est_error` of a [`critical_s`] result is the half-width of the final bracket (root
//! finding to `tol_rel`) **plus** an empirical discretization bound
//! `DISCRETIZATION_COEFF·φ²·s*` ([`DISCRETIZATION_COEFF`] = 0.3). It is **not** a guarantee:
//! on the 2,000-direction half-sphere it covered the actual error on all but 8, 13 and 9
//! directions at n = 50, 100, 200 (the README's DER section names the outliers: the κ → 0 band
//! with |ω̂| ≈ 0.9 and directions near the τ axis where the discrete branch folds).
//! [`DerRay::critical_s`] (the ray
//! alone) reports the bracket only. The measured discretization error (raw and
//! Richardson-extrapolated, `(4·s*_{2n} − s*_n)/3`) over the half-sphere is the README's DER
//! table (`examples/der_convergence.rs`).
//!
//! ```
//! use helixreach::boundary::der::{critical_s, DerBoundaryParams};
//! use helixreach::directions::Direction;
//! // The κ axis: the arc closes into a circle at s* = 2π (continuum); n = 16 is within 2 %.
//! let p = DerBoundaryParams { n_edges: 16, tol_rel: 1e-6, ..Default::default() };
//! let r = critical_s(&Direction::new(1.0, 0.0, 0.0).unwrap(), &p).unwrap();
//! assert!((r.s_star / std::f64::consts::TAU - 1.0).abs() < 0.02, "{}", r.s_star);
//! ```

use crate::directions::Direction;
use crate::error::{require_finite, require_positive, Error, Result};
use crate::helix::Helix;
use crate::math::{tol, Real, Vec3};
use crate::rod::clamp::{clamp_nodes, ClampPlacement, End};
use crate::rod::params::twist_ratio;
use crate::rod::statics::{self, NewtonParams};
use crate::rod::{Material, Rod, RodState, Workspace};

/// First stretching stiffness of the continuation in [`DerRay::evaluate`].
const STRETCH_START: Real = 1e4;
/// Growth factor of the stretching stiffness per continuation step.
const STRETCH_STEP: Real = 10.0;
/// The first evaluation of a ray (a cold start) is at `min(s, COLD_START_S)`: a nearly straight
/// rod, where the sampled helix is in Newton's basin of the helical equilibrium.
const COLD_START_S: Real = 1.0;

/// Newton iterations allowed from the predicted start before falling back.
const PREDICTED_MAX_ITERS: usize = 10;
/// The seeded search starts this fraction below the continuum s*.
const SEED_BELOW: Real = 0.985;
/// Growth factor per probe of the seeded search.
const SEED_GROWTH: Real = 1.02;
/// A stalled continuation counts as a fold (the branch ends: unstable) only if |μ| at the last
/// converged point is below this fraction of |μ| at the ray's first point; otherwise it is an
/// error.
const FOLD_MU_RATIO: Real = 0.25;
/// First s probed when bracketing s*.
const BRACKET_START: Real = 4.0;
/// Growth factor of s while bracketing.
const BRACKET_GROWTH: Real = 1.5;

/// Default stretching stiffness `k_s L²/k_b` of the boundary ([`DerBoundaryParams::stretch`]).
///
/// The continuum reference is inextensible; the penalty `k_s` shifts s* by `O(|n|/k_s)` where
/// `|n| ∝ s²` is the helix's internal force (≈ 5·10⁻⁴ relative at s* ≈ 25 with the physical
/// `k_s = 10⁶` of [`crate::rod::params::DEFAULT_STRETCH`], above the discretization error at
/// n = 200), and near the κ = 0 plane the helix's chord shortening `δ ≈ κ̂²/2` must exceed the
/// axial strain `|n|/k_s` for the compressed rod to buckle at all (module docs,
/// "Extensibility"). 10⁸ keeps the shift below ~10⁻⁶ relative; larger values (10¹⁰ was tried)
/// reach further into the κ → 0 band but Newton then stalls on the stretching force's
/// round-off at n = 200 and on large s*.
pub const BOUNDARY_STRETCH: Real = 1e8;

/// A direction is rejected (error, not a silently wrong s*) when at the continuum s* the axial
/// strain `|n|/k_s` exceeds this fraction of the helix's chord shortening (module docs).
pub const MAX_STRAIN_TO_SHORTENING: Real = 0.1;

/// Largest rotation of the frames per edge (radians, [`rotation_per_edge`]) at the continuum s*
/// for which a DER boundary is computed ([`check_resolution`]); the discretization error there
/// is tens of percent (55 % at 1.36 rad per edge).
pub const MAX_ROTATION_PER_EDGE: Real = 1.5;

/// The discretization part of a DER result's `est_error`: `DISCRETIZATION_COEFF·φ²·s*` with φ
/// the [`rotation_per_edge`] at s*. Measured |s*_n/s*_∞ − 1| on (0.175, −0.366, −0.914):
/// 0.55 at φ = 1.36, 0.064 at 0.67, 0.014 at 0.33 (≈ 0.13…0.3·φ²). Empirical, not rigorous:
/// it failed to cover 8–13 of the 2,000 half-sphere directions per n (README, DER section).
pub const DISCRETIZATION_COEFF: Real = 0.3;

pub use super::continuum::CriticalS;

/// Parameters of the DER-statics boundary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerBoundaryParams {
    /// Number of edges n (≥ 4).
    pub n_edges: usize,
    /// Poisson's ratio ν ∈ (−1, 0.5]; c = 1/(1+ν).
    pub nu: Real,
    /// Relative tolerance on s* (bracket width / s), > 0.
    pub tol_rel: Real,
    /// Largest s searched; beyond it the ray is reported stable (`s* = ∞`).
    pub s_max: Real,
    /// Nondimensional stretching stiffness `k_s L²/k_b` (the continuum is inextensible).
    pub stretch: Real,
    /// Clamped-edge placement (default [`ClampPlacement::Straddle`], `O(1/n²)`).
    pub clamp: ClampPlacement,
    /// Start the bracket search at the continuum s* (microseconds to compute), which the DER
    /// value approaches as n grows. Only the work depends on it, not the result: the DER
    /// predicate alone decides the bracket. Default true.
    pub continuum_seed: bool,
}

impl Default for DerBoundaryParams {
    /// n = 100, ν = 0.33, tol_rel = 1e-8, s_max = [`tol::S_MAX`], stretch =
    /// [`BOUNDARY_STRETCH`], straddling clamps, continuum seed.
    fn default() -> Self {
        DerBoundaryParams {
            n_edges: 100,
            nu: 0.33,
            tol_rel: 1e-8,
            s_max: tol::S_MAX,
            stretch: BOUNDARY_STRETCH,
            clamp: ClampPlacement::Straddle,
            continuum_seed: true,
        }
    }
}

impl DerBoundaryParams {
    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        if self.n_edges < 4 {
            return Err(Error::invalid(
                "n_edges",
                self.n_edges,
                "the DER boundary needs at least 4 edges",
            ));
        }
        crate::limits::check_size("n_edges", self.n_edges, crate::limits::MAX_N_EDGES)?;
        twist_ratio(self.nu)?;
        require_positive("tol_rel", self.tol_rel)?;
        if self.tol_rel >= 0.5 {
            return Err(Error::invalid("tol_rel", self.tol_rel, "must be < 0.5"));
        }
        require_positive("s_max", self.s_max)?;
        require_positive("stretch", self.stretch)?;
        Ok(())
    }
}

/// The DER rod of one ray, with its buffers (reused across the s evaluations of the ray).
#[derive(Debug)]
pub struct DerRay {
    dir: Direction,
    params: DerBoundaryParams,
    c: Real,
    rod: Rod,
    ws: Workspace,
    newton: NewtonParams,
    nodes: Vec<Vec3>,
    theta: Vec<Real>,
    state: Option<RodState>,
    evaluations: usize,
    newton_iterations: usize,
    correction: Vec<Real>,
    correction_s: Real,
    has_correction: bool,
    branch_ended: bool,
    /// |μ| at the first converged point of the ray and at the last one (fold diagnosis).
    mu_first: Real,
    mu_last: Real,
}

/// The outcome of one evaluation along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayPoint {
    /// The distance s.
    pub s: Real,
    /// Negative eigenvalues of the free Hessian at the equilibrium (0 ⇔ stable).
    pub negative: usize,
    /// Estimate of the free Hessian's eigenvalue of smallest magnitude.
    pub mu: Real,
    /// Newton iterations.
    pub iterations: usize,
}

impl DerRay {
    /// Set up the rod for direction `dir`.
    pub fn new(dir: &Direction, params: &DerBoundaryParams) -> Result<Self> {
        params.validate()?;
        for (f, v) in [
            ("dir_kappa", dir.kappa),
            ("dir_tau", dir.tau),
            ("dir_omega", dir.omega),
        ] {
            require_finite(f, v)?;
        }
        let dir = Direction::new(dir.kappa, dir.tau, dir.omega)?;
        let n = params.n_edges;
        let c = twist_ratio(params.nu)?;
        let h = params.clamp.edge_length(n, 1.0);
        let rod = Rod::uniform(n, h, Material::nondimensional(params.nu, params.stretch)?)?;
        let ws = Workspace::new(&rod);
        Ok(DerRay {
            dir,
            params: *params,
            c,
            rod,
            ws,
            newton: NewtonParams::default(),
            nodes: vec![Vec3::zeros(); n + 1],
            theta: vec![0.0; n],
            state: None,
            evaluations: 0,
            newton_iterations: 0,
            correction: vec![0.0; 4 * n + 3],
            correction_s: 1.0,
            has_correction: false,
            branch_ended: false,
            mu_first: Real::NAN,
            mu_last: Real::NAN,
        })
    }

    /// The rod model.
    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    /// `(evaluations, Newton iterations)` spent so far on this ray.
    pub fn work(&self) -> (usize, usize) {
        (self.evaluations, self.newton_iterations)
    }

    /// The last equilibrium computed by [`DerRay::evaluate`].
    pub fn state(&self) -> Option<&RodState> {
        self.state.as_ref()
    }

    /// The discrete helix at distance `s` with the clamps imposed: the Newton start.
    pub fn initial_state(&mut self, s: Real) -> Result<RodState> {
        let [k, t, w] = self.dir.at(s);
        let hx = Helix::new(k, t, w)?;
        let twist_rate = w / self.c;
        let n = self.params.n_edges;
        let pl = self.params.clamp;
        let h = pl.edge_length(n, 1.0);
        let [a, b] = clamp_nodes(pl, End::Start, &Vec3::zeros(), &Vec3::z(), h);
        self.nodes[0] = a;
        self.nodes[1] = b;
        for i in 2..n - 1 {
            self.nodes[i] = hx.position(pl.node_arclength(n, i, 1.0));
        }
        let end_frame = hx.material_frame(1.0, self.c);
        let t_end: Vec3 = end_frame.column(2).into();
        let [a, b] = clamp_nodes(pl, End::End, &hx.position(1.0), &t_end, h);
        self.nodes[n - 1] = a;
        self.nodes[n] = b;
        for j in 0..n {
            self.theta[j] = twist_rate * pl.edge_arclength(n, j, 1.0);
        }
        self.theta[0] = 0.0;
        let mut st =
            RodState::from_nodes(&self.nodes, &self.theta, &Vec3::x()).ok_or_else(|| {
                Error::invalid("s", s, "degenerate discrete helix (coincident nodes)")
            })?;
        let m1: Vec3 = end_frame.column(0).into();
        let th = st.theta_for_director(n - 1, &m1, twist_rate);
        st.set_theta(n - 1, th);
        Ok(st)
    }

    /// Equilibrium and stability at distance `s`.
    ///
    /// Newton starts from the sampled discrete helix plus the discrete correction (equilibrium
    /// minus sampled helix) of the previous evaluation on this ray, which varies smoothly with
    /// s; if that fails (or on the first call) it starts from the sampled helix with a
    /// continuation in the stretching stiffness (Newton's basin shrinks like ē/√k_s: a
    /// transverse move δ strains an edge by δ²/2ē²). The cold start may land on another branch
    /// far from the first evaluation; [`DerRay::critical_s`] therefore never uses it beyond the
    /// first, small s of a ray (it continues in s instead).
    pub fn evaluate(&mut self, s: Real) -> Result<RayPoint> {
        if self.has_correction {
            match self.evaluate_predicted(s, PREDICTED_MAX_ITERS) {
                Err(Error::NotConverged { .. }) => {}
                r => return r,
            }
        }
        self.evaluate_cold(s)
    }

    /// Newton from the predicted start only (sampled helix + correction of the last converged
    /// evaluation, scaled like s²), at most [`PREDICTED_MAX_ITERS`] iterations.
    fn evaluate_predicted(&mut self, s: Real, max_iters: usize) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        let free = self.rod.free_range_clamped();
        // The discrete correction scales like s² (chord shortfall ∝ (λē)², axial strain ∝
        // force ∝ s²).
        let scale = (s / self.correction_s).powi(2);
        let mut st = init.clone();
        for k in free.clone() {
            st.q[k] += scale * self.correction[k];
        }
        let not_converged = || Error::NotConverged {
            what: "DER Newton from the predicted start".into(),
            iterations: max_iters,
            residual: Real::NAN,
        };
        if !st.update_reference() {
            return Err(not_converged());
        }
        self.rod.material.stretch = self.params.stretch;
        let quick = NewtonParams {
            max_iters,
            ..self.newton
        };
        match statics::solve(&self.rod, &mut st, free, &mut self.ws, &quick) {
            Ok(eq) => Ok(self.finish(s, &init, st, eq.negative, eq.iterations)),
            Err(Error::NotConverged { .. }) => {
                self.evaluations += 1;
                self.newton_iterations += max_iters;
                Err(not_converged())
            }
            Err(e) => Err(e),
        }
    }

    /// Newton from the sampled helix with a continuation in the stretching stiffness.
    fn evaluate_cold(&mut self, s: Real) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        let free = self.rod.free_range_clamped();
        let target = self.params.stretch;
        let mut iterations = 0;
        let mut st = init.clone();
        let mut ks = target.min(STRETCH_START);
        let eq = loop {
            self.rod.material.stretch = ks;
            let r = statics::solve(&self.rod, &mut st, free.clone(), &mut self.ws, &self.newton);
            let eq = match r {
                Ok(eq) => eq,
                Err(e) => {
                    self.evaluations += 1;
                    self.newton_iterations += iterations;
                    return Err(e);
                }
            };
            iterations += eq.iterations;
            if ks >= target {
                break eq;
            }
            ks = (ks * STRETCH_STEP).min(target);
        };
        Ok(self.finish(s, &init, st, eq.negative, iterations))
    }

    /// Record a converged evaluation (correction for the next prediction, work counters) and
    /// estimate the smallest-magnitude eigenvalue of its free Hessian.
    fn finish(
        &mut self,
        s: Real,
        init: &RodState,
        st: RodState,
        negative: usize,
        iterations: usize,
    ) -> RayPoint {
        let free = self.rod.free_range_clamped();
        let mu = self
            .ws
            .ldlt
            .smallest_eigenvalue_warm(&self.ws.hess, free, 6, true);
        for (c, (a, b)) in self.correction.iter_mut().zip(st.q.iter().zip(&init.q)) {
            *c = a - b;
        }
        if !self.has_correction {
            self.mu_first = mu.abs();
        }
        self.mu_last = mu.abs();
        self.has_correction = true;
        self.correction_s = s;
        self.state = Some(st);
        self.evaluations += 1;
        self.newton_iterations += iterations;
        RayPoint {
            s,
            negative,
            mu,
            iterations,
        }
    }

    /// Stability near s for the root finding: `(s_evaluated, stable, surrogate f, verified)`.
    /// The surrogate is ±|μ| (sign from the inertia).
    ///
    /// The equilibrium is followed along the ray by continuation in s, never by a cold start
    /// far from the last converged point (a cold start near s* may converge to another
    /// equilibrium, e.g. one with two negative eigenvalues, or a stable buckled shape): the first
    /// point of a ray is a cold start at `s₀ = min(s, COLD_START_S)` (a nearly straight rod),
    /// and every later one starts from the prediction of the last converged point. If Newton
    /// fails at s, s is approached from the last converged point: steps that fail are halved,
    /// steps that succeed grow by 1.5. An unstable intermediate point is returned in place of s.
    /// If the continuation stalls (step < 10⁻⁶·s), the probe counts as unstable but unverified:
    /// when the critical mode is symmetric the discretization's imperfection turns the
    /// bifurcation into a fold, and the helical branch of the discrete rod ends there — the rod
    /// snaps.
    fn probe(&mut self, s: Real) -> Result<(Real, bool, Real, bool)> {
        let classify = |pt: &RayPoint| {
            if pt.negative == 0 {
                (pt.s, true, pt.mu.abs(), true)
            } else {
                (pt.s, false, -pt.mu.abs(), true)
            }
        };
        if !self.has_correction {
            let s0 = s.min(COLD_START_S);
            match self.evaluate_cold(s0) {
                Ok(pt) if pt.negative > 0 || s0 == s => return Ok(classify(&pt)),
                Ok(_) => {}
                Err(Error::NotConverged { .. }) => return Ok((s, false, Real::NAN, false)),
                Err(e) => return Err(e),
            }
        }
        match self.evaluate_predicted(s, PREDICTED_MAX_ITERS) {
            Ok(pt) => return Ok(classify(&pt)),
            Err(Error::NotConverged { .. }) => {}
            Err(e) => return Err(e),
        }
        let mut a = self.correction_s;
        let mut step = 0.25 * (s - a);
        loop {
            if step.abs() < 1e-6 * s {
                // Stalled: a full Newton solve (line search, 30 iterations) from the prediction.
                match self.evaluate_predicted(s, self.newton.max_iters) {
                    Ok(pt) => return Ok(classify(&pt)),
                    Err(Error::NotConverged { .. }) => {}
                    Err(e) => return Err(e),
                }
                // A fold ends the branch only where the smallest eigenvalue has nearly vanished;
                // anywhere else the stall is a solver failure, reported, never read as "unstable".
                if self.mu_last > FOLD_MU_RATIO * self.mu_first {
                    return Err(Error::NotConverged {
                        what: format!(
                            "DER continuation along the ray stalled at s = {a} towards {s} with \
                             the free Hessian far from singular (|mu| = {:.3e}, {:.3e} at the \
                             ray's start)",
                            self.mu_last, self.mu_first
                        ),
                        iterations: self.newton_iterations,
                        residual: Real::NAN,
                    });
                }
                return Ok((s, false, Real::NAN, false));
            }
            let t = if (s - a).abs() <= step.abs() {
                s
            } else {
                a + step
            };
            match self.evaluate_predicted(t, PREDICTED_MAX_ITERS) {
                Ok(pt) => {
                    if pt.negative > 0 || t == s {
                        return Ok(classify(&pt));
                    }
                    a = t;
                    step *= 1.5;
                }
                Err(Error::NotConverged { .. }) => step *= 0.5,
                Err(e) => return Err(e),
            }
        }
    }

    /// Locate s* on this ray (see the module docs).
    pub fn critical_s(&mut self) -> Result<CriticalS> {
        self.critical_s_from(BRACKET_START, BRACKET_GROWTH)
    }

    /// Locate s* starting the bracket search at `guess` (e.g. the continuum s*, which the DER
    /// value approaches as n grows) and growing/shrinking by `growth` > 1 per probe. The result
    /// does not depend on the guess beyond the tolerance; only the work does.
    pub fn critical_s_from(&mut self, guess: Real, growth: Real) -> Result<CriticalS> {
        let p = self.params;
        require_positive("guess", guess)?;
        if growth.is_nan() || growth <= 1.0 || !growth.is_finite() {
            return Err(Error::invalid("growth", growth, "must be finite and > 1"));
        }
        // Exactly on the τ axis the rod stays straight and unloaded: stable for every s.
        if self.dir.kappa == 0.0 && self.dir.omega == 0.0 {
            return Ok(CriticalS {
                s_star: Real::INFINITY,
                est_error: 0.0,
            });
        }
        // Bracket: [lo, hi] with lo stable (or 0) and hi unstable.
        let (mut lo, mut f_lo) = (0.0, Real::NAN);
        let (mut hi, mut f_hi, mut hi_ok);
        let mut s = guess.min(p.s_max);
        loop {
            let (t, stable, f, ok) = self.probe(s)?;
            if !stable {
                (hi, f_hi, hi_ok) = (t, f, ok);
                break;
            }
            (lo, f_lo) = (t, f);
            if s >= p.s_max {
                return Ok(CriticalS {
                    s_star: Real::INFINITY,
                    est_error: 0.0,
                });
            }
            s = (growth * s).min(p.s_max);
        }
        if lo == 0.0 {
            // Unstable at the first probe: step down.
            let mut s = hi / growth;
            loop {
                let (t, stable, f, ok) = self.probe(s)?;
                if stable {
                    (lo, f_lo) = (t, f);
                    break;
                }
                (hi, f_hi, hi_ok) = (t, f, ok);
                s /= growth;
                if s < 1e-3 {
                    return Err(Error::NotConverged {
                        what: "DER boundary bracketing (unstable as s → 0)".into(),
                        iterations: self.evaluations,
                        residual: s,
                    });
                }
            }
        }
        // Refine: Illinois regula falsi on f with a bisection safeguard.
        let mut side = 0i8;
        let mut width_before = hi - lo;
        let mut iters = 0;
        while hi - lo > p.tol_rel * lo {
            iters += 1;
            if iters > 200 {
                return Err(Error::NotConverged {
                    what: "DER boundary refinement".into(),
                    iterations: iters,
                    residual: hi - lo,
                });
            }
            let w = hi - lo;
            let mut s = if f_lo > 0.0 && f_hi < 0.0 {
                lo + w * f_lo / (f_lo - f_hi)
            } else {
                0.5 * (lo + hi)
            };
            if iters % 2 == 0 {
                if w > 0.5 * width_before {
                    s = 0.5 * (lo + hi);
                }
                width_before = w;
            }
            let margin = (0.25 * p.tol_rel * lo).min(0.25 * w);
            s = s.clamp(lo + margin, hi - margin);
            let (t, stable, f, ok) = self.probe(s)?;
            if stable {
                (lo, f_lo) = (t, f);
                if side == -1 {
                    f_hi *= 0.5;
                }
                side = -1;
            } else {
                (hi, f_hi, hi_ok) = (t, f, ok);
                if side == 1 {
                    f_lo *= 0.5;
                }
                side = 1;
            }
        }
        self.branch_ended = !hi_ok;
        Ok(CriticalS {
            s_star: 0.5 * (lo + hi),
            est_error: 0.5 * (hi - lo),
        })
    }

    /// Whether the last [`DerRay::critical_s`] ended at a fold: no helical equilibrium was found
    /// just past s* (Newton failed there), rather than an equilibrium with a negative eigenvalue.
    pub fn branch_ended(&self) -> bool {
        self.branch_ended
    }
}

/// The DER-statics critical distance s* along `dir` (see the module docs).
///
/// Errors: invalid parameters (n < 4, ν ∉ (−1, 0.5], tol_rel ≤ 0, non-finite values), an
/// invalid direction (NaN, zero, κ < 0), or a Newton failure.
pub fn critical_s(dir: &Direction, params: &DerBoundaryParams) -> Result<CriticalS> {
    let mut ray = DerRay::new(dir, params)?;
    let c = super::continuum::critical_s(&ray.dir, 1e-6)?;
    if c.s_star.is_finite() {
        check_extensibility(&ray.dir, c.s_star, params.stretch)?;
        check_resolution(&ray.dir, c.s_star, params.n_edges, ray.c)?;
    }
    let mut r = if params.continuum_seed && c.s_star.is_finite() && c.s_star < params.s_max {
        ray.critical_s_from(SEED_BELOW * c.s_star, SEED_GROWTH)?
    } else {
        ray.critical_s()?
    };
    if r.s_star.is_finite() {
        let per_edge = rotation_per_edge(&ray.dir, r.s_star, params.n_edges, ray.c);
        r.est_error += DISCRETIZATION_COEFF * per_edge * per_edge * r.s_star;
    }
    Ok(r)
}

/// The rotation of the frames per edge, `s·√(κ̂² + τ̂² + (ω̂/c)²)/(n − 1)` radians (bending,
/// torsion and the material twist `ω/c` of the helix at distance s, shared by `n − 1` edges).
pub fn rotation_per_edge(dir: &Direction, s: Real, n_edges: usize, c: Real) -> Real {
    s * (dir.kappa * dir.kappa + dir.tau * dir.tau + (dir.omega / c) * (dir.omega / c)).sqrt()
        / (n_edges as Real - 1.0)
}

/// The resolution guard (module docs): above [`MAX_ROTATION_PER_EDGE`] radians per edge
/// ([`rotation_per_edge`] at the continuum s*) the discrete rod is no model of the continuum:
/// an error naming the rotation and the smallest adequate n.
pub fn check_resolution(dir: &Direction, s_star: Real, n_edges: usize, c: Real) -> Result<()> {
    let per_edge = rotation_per_edge(dir, s_star, n_edges, c);
    if per_edge > MAX_ROTATION_PER_EDGE {
        let need = (per_edge * (n_edges as Real - 1.0) / MAX_ROTATION_PER_EDGE).ceil() as usize + 1;
        return Err(Error::invalid(
            "n_edges",
            n_edges,
            format!(
                "too coarse for direction ({}, {}, {}): at the continuum s* = {s_star:.4} the \
                 frames turn {per_edge:.2} rad per edge (> {MAX_ROTATION_PER_EDGE}); use \
                 n_edges >= {need}",
                dir.kappa, dir.tau, dir.omega
            ),
        ));
    }
    Ok(())
}

/// The extensibility guard (module docs): at the continuum s* the helix's internal force
/// `|n| = |ω − τ|·√(κ² + τ²)` strains the penalized rod by `|n|/k_s`; unless that is at most
/// [`MAX_STRAIN_TO_SHORTENING`] of the chord shortening `δ = 1 − |r(1)|`, the DER rod does not
/// model the inextensible one (near the κ = 0 plane it stays straight and compressed instead of
/// buckling) and the direction is an error naming both numbers.
pub fn check_extensibility(dir: &Direction, s_star: Real, stretch: Real) -> Result<()> {
    let [k, t, w] = dir.at(s_star);
    let force = (w - t).abs() * (k * k + t * t).sqrt();
    let shortening = 1.0 - Helix::new(k, t, w)?.position(1.0).norm();
    let strain = force / stretch;
    if strain > MAX_STRAIN_TO_SHORTENING * shortening {
        return Err(Error::invalid(
            "direction",
            format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
            format!(
                "too close to the kappa = 0 plane for DER statics with stretch {stretch:e}: at the \
                 continuum s* = {s_star} the axial strain |n|/k_s = {strain:.3e} is not small \
                 against the helix's chord shortening {shortening:.3e} (the penalized rod would \
                 stay straight and compressed); use the continuum method or a larger stretch"
            ),
        ));
    }
    Ok(())
}
