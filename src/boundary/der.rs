//! The DER-statics stability boundary along a ray (DESIGN.md §3, "DER-predicted boundary").
//!
//! For a unit direction S̄ and a distance s, the rod of length 1 is clamped at both ends
//! ([`crate::rod::clamp`]): edge 0 along z with the identity material frame at the origin, edge
//! n−1 at the end of the helix `(κ, τ, ω) = s·S̄` with its tangent and its material frame (the
//! transported frame turned by `ω/c` about the tangent). The equilibrium is found by Newton
//! ([`crate::rod::statics`]) starting from the helix sampled at the nodes — the continuum
//! equilibrium is the helix, so this start is `O(1/n²)` from the discrete equilibrium and no
//! continuation in s is needed (every s is solved independently). The twist angles start at
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
use crate::rod::params::{twist_ratio, DEFAULT_STRETCH};
use crate::rod::statics::{self, NewtonParams};
use crate::rod::{Material, Rod, RodState, Workspace};

/// First stretching stiffness of the continuation in [`DerRay::evaluate`].
const STRETCH_START: Real = 1e4;
/// Growth factor of the stretching stiffness per continuation step.
const STRETCH_STEP: Real = 10.0;

/// Newton iterations allowed from the predicted start before falling back.
const PREDICTED_MAX_ITERS: usize = 5;
/// The seeded search starts this fraction below the continuum s*.
const SEED_BELOW: Real = 0.985;
/// Growth factor per probe of the seeded search.
const SEED_GROWTH: Real = 1.02;
/// First s probed when bracketing s*.
const BRACKET_START: Real = 4.0;
/// Growth factor of s while bracketing.
const BRACKET_GROWTH: Real = 1.5;

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
    /// [`DEFAULT_STRETCH`], straddling clamps, continuum seed.
    fn default() -> Self {
        DerBoundaryParams {
            n_edges: 100,
            nu: 0.33,
            tol_rel: 1e-8,
            s_max: tol::S_MAX,
            stretch: DEFAULT_STRETCH,
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
    /// transverse move δ strains an edge by δ²/2ē²).
    pub fn evaluate(&mut self, s: Real) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        let free = self.rod.free_range_clamped();
        let target = self.params.stretch;
        let mut iterations = 0;
        let mut found = None;
        if self.has_correction {
            // The discrete correction scales like s² (chord shortfall ∝ (λē)², axial strain ∝
            // force ∝ s²).
            let scale = (s / self.correction_s).powi(2);
            let mut st = init.clone();
            for k in free.clone() {
                st.q[k] += scale * self.correction[k];
            }
            if st.update_reference() {
                self.rod.material.stretch = target;
                let quick = NewtonParams {
                    max_iters: PREDICTED_MAX_ITERS,
                    ..self.newton
                };
                let r = statics::solve(&self.rod, &mut st, free.clone(), &mut self.ws, &quick);
                match r {
                    Ok(eq) => {
                        iterations += eq.iterations;
                        found = Some((eq, st));
                    }
                    Err(_) => iterations += PREDICTED_MAX_ITERS,
                }
            }
        }
        let (eq, st) = match found {
            Some(x) => x,
            None => {
                let mut st = init.clone();
                let mut ks = target.min(STRETCH_START);
                loop {
                    self.rod.material.stretch = ks;
                    let r = statics::solve(
                        &self.rod,
                        &mut st,
                        free.clone(),
                        &mut self.ws,
                        &self.newton,
                    );
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
                        break (eq, st);
                    }
                    ks = (ks * STRETCH_STEP).min(target);
                }
            }
        };
        let mu = self
            .ws
            .ldlt
            .smallest_eigenvalue_warm(&self.ws.hess, free, 6, true);
        for (c, (a, b)) in self.correction.iter_mut().zip(st.q.iter().zip(&init.q)) {
            *c = a - b;
        }
        self.has_correction = true;
        self.correction_s = s;
        self.state = Some(st);
        self.evaluations += 1;
        self.newton_iterations += iterations;
        Ok(RayPoint {
            s,
            negative: eq.negative,
            mu,
            iterations,
        })
    }

    /// Stability near s for the root finding: `(s_evaluated, stable, surrogate f, verified)`.
    /// The surrogate is ±|μ| (sign from the inertia).
    ///
    /// If Newton fails at s (a jump too far for its basin, which is small near the buckling of
    /// a nearly straight rod), s is approached by continuation from the last converged s:
    /// steps that fail are halved, steps that succeed grow by 1.5. An unstable intermediate
    /// point is returned in place of s. If the continuation stalls (step < 10⁻⁶·s), the probe
    /// counts as unstable but unverified: when the critical mode is symmetric the
    /// discretization's imperfection turns the bifurcation into a fold, and the helical branch
    /// of the discrete rod ends there — the rod snaps.
    fn probe(&mut self, s: Real) -> Result<(Real, bool, Real, bool)> {
        let classify = |pt: &RayPoint| {
            if pt.negative == 0 {
                (pt.s, true, pt.mu.abs(), true)
            } else {
                (pt.s, false, -pt.mu.abs(), true)
            }
        };
        match self.evaluate(s) {
            Ok(pt) => return Ok(classify(&pt)),
            Err(Error::NotConverged { .. }) => {}
            Err(e) => return Err(e),
        }
        if !self.has_correction {
            // No converged point yet: start the continuation from a small, easy s.
            let s0 = (0.25 * s).min(1.0);
            match self.evaluate(s0) {
                Ok(pt) if pt.negative > 0 => return Ok(classify(&pt)),
                Ok(_) => {}
                Err(Error::NotConverged { .. }) => return Ok((s, false, Real::NAN, false)),
                Err(e) => return Err(e),
            }
        }
        let mut a = self.correction_s;
        let mut step = 0.25 * (s - a);
        loop {
            if step.abs() < 1e-6 * s {
                return Ok((s, false, Real::NAN, false));
            }
            let t = if (s - a).abs() <= step.abs() {
                s
            } else {
                a + step
            };
            match self.evaluate(t) {
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
    if params.continuum_seed {
        if let Ok(c) = super::continuum::critical_s(&ray.dir, 1e-6) {
            if c.s_star.is_finite() && c.s_star < params.s_max {
                return ray.critical_s_from(SEED_BELOW * c.s_star, SEED_GROWTH);
            }
        }
    }
    ray.critical_s()
}
