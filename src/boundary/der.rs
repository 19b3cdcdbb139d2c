//! The DER-statics stability boundary along a ray ([architecture §3](crate::architecture), "DER-predicted boundary").
//!
//! For a unit direction S̄ and a distance s, the rod of length 1 is clamped at both ends
//! ([`crate::rod::clamp`]): edge 0 along z with the identity material frame at the origin, edge
//! n−1 at the end of the helix `(κ, τ, ω) = s·S̄` with its tangent and its material frame (the
//! transported frame turned by `ω/c` about the tangent). The equilibrium of the *inextensible*
//! discrete rod is found by Newton on its KKT system ([`crate::rod::inextensible`]; below a
//! curvature share κ̂ ≈ 10⁻⁶, by Newton ([`crate::rod::statics`]) inside an augmented
//! Lagrangian; see "Inextensibility") and followed along the ray by continuation in s: the first point of
//! a ray is a nearly straight rod (s ≤ 1) started from the helix sampled at the nodes, every
//! later one from the sampled helix plus a prediction of the discrete correction (equilibrium
//! minus sampled helix): the secant through the last two converged points of `correction/s²`
//! (the correction scales like s² away from s*, and the secant also follows the growth of the
//! critical mode near s*). Steps grow by at most ×1.3 and are halved when Newton fails. A cold
//! start from the sampled helix far along the ray is never used by the search: near s* it can
//! converge to another equilibrium (one with two negative eigenvalues, or a stable buckled
//! shape), which made s* 3–126 % wrong near the τ axis. The twist angles start at
//! the uniform twist `θ_j = (ω/c)·s_j` relative to space-parallel reference frames (zero
//! reference twist), and θ_{n−1} is the angle to the imposed end director chosen within π of
//! ω/c: the winding number of the end rotation is the one reached continuously from the
//! straight rod.
//!
//! Stable ⇔ the free Hessian is positive definite on the constraint set (banded LDLᵀ inertia
//! of the KKT matrix, or of the penalty rod's free Hessian; no eigen-solve). The
//! critical distance s* is bracketed by stepping s geometrically (from 4, ×1.5) and then refined
//! by regula falsi (Illinois) on the free Hessian's smallest-magnitude eigenvalue μ(s)
//! (inverse iteration with the LDLᵀ factors; of the KKT matrix, whose eigenvalue nearest 0
//! crosses 0 with the constrained Hessian's), with the *predicate* deciding which end of the
//! bracket moves and a bisection fallback whenever the bracket fails to halve, until the
//! bracket width is ≤ `tol_rel·s`. A ray stable at `s_max` returns `s* = ∞`.
//!
//! Folds: the discrete clamps and sampling perturb the helix slightly (`O(1/n²)`). Where the
//! critical mode is antisymmetric the loss of stability stays a clean bifurcation (an
//! equilibrium with one negative eigenvalue just past s*); where it is symmetric (e.g. near the
//! τ axis, Euler buckling of the compressed, nearly straight rod) the perturbed branch can end
//! at a fold and Newton finds no nearby equilibrium past it. A continuation that stalls where
//! |μ| has fallen below a quarter of its value at the ray's start counts as unstable (the
//! branch ended), anywhere else it is an error; [`DerRay::branch_ended`] reports which case
//! ended the search.
//!
//! # Continuation
//! [`critical_s`] takes these shortcuts where they are safe ([`shortcuts_are_safe`]: the
//! augmented-Lagrangian rod's strain `|n|/10⁶` at most 1 % of the chord shortening δ at the
//! continuum s*, i.e. everywhere but the band near the κ = 0 plane):
//! - the ray's first point is a cold start at 0.7× the first probe's s (≈ 0.69·s*) instead of
//!   s = 1. It is accepted only if its equilibrium is stable and within
//!   `BRANCH_DEVIATION` = 0.02 L of the sampled helix (the helical branch; another branch
//!   is O(L) away); otherwise the ray restarts from s = 1;
//! - (augmented Lagrangian only; with the KKT Newton every step is an equilibrium of the model
//!   itself, and a step past s* is a bracket end) the continuation steps between bracket
//!   points are solved on the augmented-Lagrangian rod
//!   only (the inextensible equilibrium to 10⁻⁸, no relaxation to the penalty rod, μ from 2
//!   warm inverse iterations): a step only predicts the next point. Every bracket point (each
//!   probe's target, and a step whose inertia is negative, re-solved there) is the full
//!   evaluation, so the bracket is decided by the penalty rod's inertia alone, as before. A step
//!   that fails switches the rest of the probe to full evaluations;
//! - μ at a bracket point takes 3 warm inverse iterations instead of 6.
//!
//! (Solving the refinement's short steps by Newton on the penalty rod directly, without the
//! augmented Lagrangian, saved another 15 % of the iterations but made s* at n = 200 on
//! (0.1213, −0.9129, −0.3898) 8·10⁻⁵ wrong — Newton on the stiff rod near s* can slide onto
//! a neighbouring equilibrium — and was dropped.)
//!
//! With the augmented Lagrangian these shortcuts took 12.1 equilibria and 57 Newton
//! iterations per direction instead of 18.3 and 83 on the 2,000-direction half-sphere at
//! n = 100 (0.63× the CPU time), and moved s* by at most 2.5·10⁻⁶
//! relative (median 7·10⁻⁹): the predicate's noise floor, the same equilibria reached
//! differently. The KKT Newton needs ≈ 10.5 equilibria and 22 Newton iterations per direction
//! (`docs/RESULTS.md`, DER statics). [`DerRay::critical_s_from`] (the bifurcation analysis) takes
//! no shortcut unless [`DerRay::allow_shortcuts`] is called. Near the κ = 0 plane the rod of
//! 10⁶ buckles before the penalty rod does (the compression is taken up by the edges rather than
//! the helix), and a far cold start can land on a neighbouring equilibrium of the nearly
//! straight rod ((0.00125, 0.0874, 0.9962): 10.08 instead of 10.24, caught by the continuum
//! check): there every step is a full evaluation from s = 1.
//!
//! [`critical_s`] seeds the bracket search with the continuum s* (`continuum_seed`, default):
//! the DER value differs from it by `O(1/n²)`, so the bracket is found in one or two probes
//! instead of a geometric search from s = 4. The DER predicate alone decides the bracket.
//!
//! The κ = 0 plane: the helix is the straight rod; on the τ axis it is untwisted and unloaded,
//! stable for every s, and `s* = ∞` is returned; with ω ≠ 0 it is the twisted clamped rod.
//!
//! # Inextensibility
//! The continuum reference is inextensible, and so is the rod [`critical_s`] solves: where the
//! direction's curvature share is at least `max(`[`MIN_KAPPA_HAT`]`, `[`MIN_KAPPA_HAT_PER_EDGE`]`·n)`
//! ([`solves_inextensible`]; 5·10⁻⁷ at n = 100) every equilibrium is a stationary point of
//! the bending and twisting energy subject to `|e_j| = ē_j` on every edge with a free node,
//! found by Newton on the KKT system with the edges' axial forces as multipliers
//! ([`crate::rod::inextensible`], [`DerRay::set_inextensible`]), and stability is the
//! constrained Hessian's: the KKT matrix has exactly as many negative eigenvalues as
//! constraints. Newton converges quadratically in positions and forces together, also on the
//! nearly straight, compressed rod of the κ → 0 band, where the augmented Lagrangian below
//! stalled (its multiplier update contracts like `K/(K + k_s)`, K the rod's axial stiffness
//! between the clamps, huge as κ → 0: (0.0018, 0.6084, −0.7936) failed) and where the
//! penalty rod could not carry the helix's compression at all (κ̂ ≲ 3·10⁻³ near the τ axis was
//! refused). Below the κ̂ limit the constraint Jacobian is too close to rank-deficient (a
//! uniform axial force is invisible on a straight rod; its smallest singular value is the
//! edges' turning angle ≈ κ·ē) and the axial force is lost to round-off: at n = 25, 100, 200
//! the τ-axis and (κ̂, 0.6, −0.8) sweeps are clean (within 2.3·10⁻⁶ of the κ̂-independent
//! discretization error) down to κ̂ = 10⁻⁷ and break down (errors, never numbers) at
//! 3·10⁻⁸ or 10⁻⁸; the limit keeps a 5× margin.
//!
//! Below the limit (the κ = 0 plane and a band of width ≈ 10⁻⁶ around it, e.g. the ω axis)
//! the previous method is kept: a stiff stretching penalty (`k_s = 10⁸`) made Newton's basin
//! tiny (a transverse move δ strains an edge by δ²/2ē²), so `k_s` only conditions Newton, which
//! works with `k_s = min(stretch, 10⁶)` ([`DerBoundaryParams::stretch`], default
//! [`BOUNDARY_STRETCH`] = 10⁸): after each solve the stretching rest lengths are shifted,
//! `ē'_j = ē_j/(1 + f_j/k_s)` with `f_j` the edge's axial force
//! ([`crate::rod::Rod::set_stretch_rest_length`]), until every edge has its rest length to
//! [`AL_STRAIN_TOL`] = 10⁻⁷ — the augmented-Lagrangian (method of multipliers) update, with
//! `k_s` raised tenfold when an update is slow. The inextensible equilibrium is then relaxed
//! by Newton to the equilibrium of the penalty rod of stiffness `stretch` with its true rest
//! lengths, whose stability is tested — the DER rod of the dynamics and of the bifurcation
//! analysis ([`DerRay`]'s default), which differs from the inextensible rod by ≈ |n|/k_s
//! relative in s* (≈ 10⁻⁸ … 10⁻⁵ at the default 10⁸). There a direction with
//! `|n|/k_guard > 0.1·δ` at the continuum s* (`|n| = |ω − τ|·√(κ² + τ²)` the helix's internal
//! force, `δ = 1 − |r(1)|` its chord shortening, `k_guard` = [`EXTENSIBILITY_GUARD_STRETCH`]
//! = 10⁸; [`check_extensibility`]) is refused with an error naming both numbers (use the
//! continuum method there); the twisted rod without axial force (the ω axis, ω = τ on
//! κ = 0) is solved.
//!
//! # Resolution
//! The frames of the helix turn by [`rotation_per_edge`] `φ = s*·√(κ̂² + τ̂² + (ω̂/c)²)/(n − 1)`
//! radians per edge; the relative discretization error is ≈ 0.1…0.3·φ² (straddling clamps):
//! 1.4 % at φ = 0.33 (n = 100) but 55 % at φ = 1.36 (n = 25) on (0.175, −0.366, −0.914),
//! s* ≈ 25.5. Above [`MAX_ROTATION_PER_EDGE`] = 0.9 rad per edge (where the `est_error` bound
//! below reaches ≈ 80 %) [`critical_s`] returns an error naming the n needed
//! ([`check_resolution`]). Below it the discrete rod may still be outside its asymptotic
//! regime: on the large-s* band κ̂ ≲ 0.1, |ω̂| ≈ 0.9 (s* = 40…120, where the two
//! wavenumbers of the twisted rod's critical mode nearly coincide and the discretization error
//! of each is amplified) the error at φ ≈ 0.6–1.2 is 12–54 % and can even grow from n = 100 to
//! n = 200 ((0.035, 0.4236, 0.9052), continuum 92.87: 132.9 and 143.5, then 97.5, 93.9, 93.1
//! at n = 400, 800, 1600 — second order only from φ ≈ 0.3). Such results fail the check
//! against the continuum below and are errors.
//!
//! # Gravity
//! [`critical_s_gravity`] loads the rod with its weight: per node `l_i·w`, `l_i` the node's share
//! of the rest length (half an edge at the ends, as the dynamics' lumped masses) and `w` the
//! nondimensional weight per unit length `ρA·g·L³/k_b = ½(L/L_gb)³` times the direction of
//! gravity **in the helix frame** ([`gravity_in_helix_frame`]): for a clamp of rotation
//! `R = [d1 d2 d3]` in the rig's base frame (d3 the rod tangent at the clamp, d1 the direction
//! the helix first curls toward at azimuth 0) and a ray at azimuth α (the robot end's rotation
//! of the whole helix about d3), gravity `g` of the base frame is `Rz(α)ᵀ·Rᵀ·g` there. The
//! potential `−Σ l_i w·x_i` has a constant gradient and no Hessian ([`Workspace::external`]),
//! so the stability test is unchanged (the KKT inertia at the loaded equilibrium). Gravity
//! breaks the isotropy: s* depends on α unless gravity is along d3 (rod vertical).
//!
//! The gravity-free search's shortcuts assume the unloaded helix (the correction ∝ s², the
//! cold start far along the ray checked against `BRANCH_DEVIATION`, the continuum s* as the
//! answer's check). Under gravity none is used: the first point (s = 1) is the gravity-free
//! equilibrium continued in the weight from 0 to w (increments halved on failure), and the
//! branch is then followed forward in s from stable point to stable point
//! ([`DerRay::critical_s_on_branch`], predictor: the secant of the correction itself). s* is
//! where that branch loses stability: an equilibrium with a negative eigenvalue met by a step,
//! or the fold where Newton finds no equilibrium past it, bracketed to `tol_rel`; it counts
//! only where the smallest eigenvalue μ of the last stable point is at most 1 % of its value at
//! the ray's start (a vanishing eigenvalue of the constrained Hessian).
//!
//! What gravity does to the bifurcation: the weight is an imperfection. On a snapping
//! (subcritical) direction the helical branch ends at a fold before the gravity-free s*, and
//! the shift follows Koiter's two-thirds law, `|s*(g) − s*(0)| ∝ g^{2/3}` (measured local order
//! 0.63–0.69 on (1, 1, −1)/√3 and (0.594, 0.698, 0.4) for w from 10⁻⁴ to 2.6·10⁻², `tests/rod.rs`).
//! On a supercritical direction the loaded branch bends smoothly past the gravity-free s* onto
//! the buckled branch, and the search finds where *that* branch loses stability: on
//! (1, 1, 1)/√3 its fold 0.4 % above the gravity-free s* (n = 40), and at larger weights
//! (`L_gb/L` ≲ 0.6) a loss of stability near twice s*. Near the sharp turn of a nearly perfect
//! supercritical bifurcation a step can land on the unstable branch with |μ| still small, so
//! on such directions s*(g) for tiny g may be either the turn or the fold; it is continuous in
//! g only on subcritical directions. A slow dynamic run snaps where the static s* with gravity
//! says (`tests/dynamics.rs`: within 0.5 % at `L_gb/L` = 1, read at the helix error's
//! threshold crossing).
//!
//! # What `est_error` covers
//! The `est_error` of a [`critical_s`] result is the half-width of the final bracket (root
//! finding to `tol_rel`) **plus** an empirical discretization bound
//! `DISCRETIZATION_COEFF·φ²·s*` at the continuum s* ([`DISCRETIZATION_COEFF`] = 1.0; the largest measured
//! |s*_n/s*_∞ − 1|/φ² is 0.26 outside the large-s* band and up to 0.85 on it). The bound is then *checked*: [`critical_s`]
//! computes the continuum s* anyway (the seed), and a DER s* farther from it than `est_error`
//! (plus the continuum's own tolerance) is returned as an error naming both values, never as
//! a number — so every s* written is within its `est_error` of the continuum. `docs/RESULTS.md`
//! counts these errors. [`DerRay::critical_s`] (the ray alone) reports the bracket only
//! and is not checked. The measured discretization error (raw and Richardson-extrapolated,
//! `(4·s*_{2n} − s*_n)/3`) over the half-sphere is in `docs/RESULTS.md`
//! (`examples/der_convergence.rs`).
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
use crate::rod::inextensible::{self, KktWorkspace};
use crate::rod::params::twist_ratio;
use crate::rod::statics::{self, NewtonParams};
use crate::rod::{Material, Rod, RodState, Workspace};

/// The stretching penalty of the Newton solves (augmented Lagrangian, module docs
/// "Inextensibility"): Newton's basin shrinks like `ē/√k_s`.
const NEWTON_STRETCH: Real = 1e6;
/// First stretching stiffness of the continuation in [`DerRay::evaluate`].
const STRETCH_START: Real = 1e6;
/// Growth factor of the stretching stiffness per continuation step.
const STRETCH_STEP: Real = 10.0;
/// The first evaluation of a ray (a cold start) is at `min(s, COLD_START_S)`: a nearly straight
/// rod, where the sampled helix is in Newton's basin of the helical equilibrium.
const COLD_START_S: Real = 1.0;

/// Largest edge strain `|ℓ_j/ē_j − 1|` at which the augmented Lagrangian hands over to the
/// relaxation Newton (module docs, "Inextensibility"). It only has to put that Newton's start
/// inside its basin (a strain error of 10⁻⁷ is a displacement of 10⁻⁷·ē): the equilibrium
/// returned is the penalty rod's, to the Newton tolerance, whatever this value. 10⁻⁷ instead of
/// 10⁻⁹ saves an update on most evaluations (≈ 15 % of the boundary's time); s* moved by
/// ≤ 2·10⁻⁷ relative on 300 directions at n = 100 — the noise floor of the stability predicate
/// (the Hessian holds stretching entries `k_s/ē ≈ 10¹⁰`, so its smallest eigenvalue is known to
/// ≈ 10⁻⁶ absolute).
pub const AL_STRAIN_TOL: Real = 1e-7;
/// The strain floor of the augmented Lagrangian in units of the Newton residual over `k_s`.
const AL_FLOOR_FACTOR: Real = 1e3;
/// An augmented-Lagrangian update that reduces the strain by less than this factor is slow:
/// the penalty is raised tenfold (up to [`AL_MAX_STRETCH`]).
const AL_SLOW: Real = 0.3;
/// Largest penalty the augmented Lagrangian raises `k_s` to.
const AL_MAX_STRETCH: Real = 1e9;
/// Most rest-length updates of the augmented Lagrangian.
const AL_MAX_ITERS: usize = 20;

/// Largest ratio between consecutive s of the continuation along a ray.
const MAX_STEP_RATIO: Real = 1.3;

/// The continuation has stalled when its step ratio has been halved to within this of 1
/// (≈ 18 halvings of [`MAX_STEP_RATIO`] − 1): then one full Newton solve decides.
const MIN_STEP_RATIO_EXCESS: Real = 1e-6;

/// Default relative tolerance on s* ([`DerBoundaryParams::tol_rel`]): the bracket width; far
/// below the discretization error at any usable n, and above the noise of the stability
/// predicate (≈ 1e-6…1e-5 relative, `examples/der_convergence.rs`) only as a search tolerance.
pub const DEFAULT_TOL_REL: Real = 1e-8;

/// Smallest s probed when stepping the bracket down: the straight rod (s = 0) is stable, so a
/// ray still unstable at s = 10⁻³ is reported as a failure of the search, never as an s*.
const MIN_BRACKET_S: Real = 1e-3;

/// Relative tolerance of the continuum s* that seeds the search and checks the result
/// ([`check_against_continuum`], which adds the continuum's own `est_error` to the allowed
/// difference, so a looser continuum widens the check, never falsifies it).
const CONTINUUM_CHECK_TOL_REL: Real = 1e-6;
/// Newton tolerance (step and relative residual) of a continuation step: its equilibrium only
/// predicts the next one, which Newton polishes.
const STEP_NEWTON_TOL: Real = 1e-8;
/// Inverse iterations for μ at a bracket point.
const MU_ITERS: usize = 6;
/// Inverse iterations for μ at a bracket point with the shortcuts (warm start: 3 change the
/// evaluations per direction by < 1 %).
const SHORTCUT_MU_ITERS: usize = 3;
/// Inverse iterations for μ at a continuation step (warm start from the previous point).
const STEP_MU_ITERS: usize = 2;
/// With the shortcuts the first point of a ray is a cold start at
/// `max(COLD_START_S, COLD_FRACTION·s)` for the first probe s (at s itself when that is ≤
/// [`COLD_START_S`]).
const COLD_FRACTION: Real = 0.7;
/// The shortcuts are used where the augmented-Lagrangian rod's strain is at most this fraction
/// of the chord shortening ([`shortcuts_are_safe`]).
pub const SHORTCUT_STRAIN_TO_SHORTENING: Real = 0.01;
/// A cold start beyond [`COLD_START_S`] is accepted only if its equilibrium lies within this
/// distance (units of L, largest node displacement) of the sampled helix; otherwise the ray
/// restarts from the nearly straight rod.
const BRANCH_DEVIATION: Real = 0.02;

/// Smallest increment of the weight (fraction of the full weight) of the gravity ramp of a
/// cold start ([`DerRay::set_gravity`]).
const MIN_GRAVITY_INCREMENT: Real = 1e-3;

/// Largest node displacement (units of L) of a KKT equilibrium from its predicted start
/// before the step counts as failed (left the branch; see [`DerRay::evaluate_predicted`]).
const PREDICTION_DEVIATION: Real = 5e-3;

/// [`PREDICTION_DEVIATION`] under gravity ([`DerRay::critical_s_on_branch`]).
const GRAVITY_PREDICTION_DEVIATION: Real = 0.02;
/// Under gravity an end of the branch counts as the loss of stability only where the smallest
/// eigenvalue |μ| of the last stable point is at most this fraction of its value at the ray's
/// start ([`DerRay::critical_s_on_branch`]).
const SINGULAR_MU_RATIO: Real = 1e-2;
/// Most times [`DerRay::critical_s_on_branch`] forgets an unstable bracket end that was another
/// branch's.
const MAX_BRANCH_RESETS: usize = 8;
/// The step after such a reset, relative to s.
const RESET_STEP: Real = 1e-4;
/// Largest ratio between consecutive s of the continuation under gravity.
const GRAVITY_MAX_STEP_RATIO: Real = 1.1;

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
/// The continuation reaches the inextensible equilibrium with Newton at `min(k_s, 10⁶)`
/// (augmented Lagrangian, module docs "Inextensibility") and relaxes it to the penalty rod of
/// `k_s`, whose stability is tested; the penalty shifts s* by ≈ |n|/k_s relative, `|n| ∝ s²`
/// the helix's internal force.
pub const BOUNDARY_STRETCH: Real = 1e8;

/// The stiffness of the κ → 0 guard ([`check_extensibility`]): a direction is refused where an
/// edge strain `|n|/EXTENSIBILITY_GUARD_STRETCH` is not small against the chord shortening.
pub const EXTENSIBILITY_GUARD_STRETCH: Real = 1e8;

/// A direction is rejected (error, not a silently wrong s*) when at the continuum s* the axial
/// strain `|n|/k_guard` exceeds this fraction of the helix's chord shortening (module docs).
pub const MAX_STRAIN_TO_SHORTENING: Real = 0.1;

/// Smallest curvature share κ̂ of a direction that [`critical_s`] solves as the inextensible
/// rod ([`solves_inextensible`]). Measured on the τ axis and (κ̂, 0.6, −0.8): at
/// n = 25, 100, 200 every κ̂ ≥ 10⁻⁷ is within 2.3·10⁻⁶ of the clean discretization error, and
/// the solve breaks down (errors, never a number) at κ̂ = 3·10⁻⁸ (n = 25, 200) or 10⁻⁸
/// (n = 100): 10× margin.
pub const MIN_KAPPA_HAT: Real = 5e-7;

/// The guard's growth with n: κ̂ ≥ `MIN_KAPPA_HAT_PER_EDGE·n` (the edges' turning angle κ·ē
/// shrinks like 1/n; 10⁻⁹·n is 10× the smallest κ̂·ē that worked, 10⁻⁷/200).
pub const MIN_KAPPA_HAT_PER_EDGE: Real = 1e-9;

/// Largest rotation of the frames per edge (radians, [`rotation_per_edge`]) at the continuum s*
/// for which a DER boundary is computed ([`check_resolution`]): there the discretization bound
/// `DISCRETIZATION_COEFF·φ²` of `est_error` reaches ≈ 80 % of s*; beyond it the discrete rod
/// is not in its asymptotic regime on the large-s* band (27 % off at 1.24 rad per edge).
pub const MAX_ROTATION_PER_EDGE: Real = 0.9;

/// The discretization part of a DER result's `est_error`: `DISCRETIZATION_COEFF·φ²·s*` with φ
/// the [`rotation_per_edge`] at s*. Measured |s*_n/s*_∞ − 1|/φ² on the 2,000-direction
/// half-sphere (φ ≤ [`MAX_ROTATION_PER_EDGE`], n = 100, 200, 400): ≤ 0.43 on all but two
/// directions, the two largest s* of the large-s* band: (0.0053, 0.4238, 0.9057), continuum
/// s* = 107.92: 0.85, 0.71, 0.68 at n = 400, 800, 1600 (and stable past s_max = 200 at
/// n = 200, refused by the check); (0.0413, −0.4323, −0.9008), s* = 114.50: 0.70, 0.57, 0.49,
/// 0.47 at n = 200…1600. Both converge to the continuum at order 2 (the DER root is right, the
/// former coefficient 0.6 was too small). 1.0 covers the largest measured value with margin
/// 1.18; empirical, so [`critical_s`] checks the result against the continuum (module docs).
pub const DISCRETIZATION_COEFF: Real = 1.0;

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
    /// Nondimensional stretching stiffness `k_s L²/k_b` of the penalty rod (the continuum is
    /// inextensible): used by [`DerRay`]'s default model (the bifurcation analysis) and by
    /// [`critical_s`] only below the KKT limit ([`solves_inextensible`]).
    pub stretch: Real,
    /// Clamped-edge placement (default [`ClampPlacement::Straddle`], `O(1/n²)`).
    pub clamp: ClampPlacement,
    /// Start the bracket search at the continuum s* (microseconds to compute), which the DER
    /// value approaches as n grows. Only the work depends on it, not the result: the DER
    /// predicate alone decides the bracket. Default true.
    pub continuum_seed: bool,
}

impl Default for DerBoundaryParams {
    /// n = 100, ν = 0.33, tol_rel = [`DEFAULT_TOL_REL`], s_max = [`tol::S_MAX`], stretch =
    /// [`BOUNDARY_STRETCH`], straddling clamps, continuum seed.
    fn default() -> Self {
        DerBoundaryParams {
            n_edges: 100,
            nu: 0.33,
            tol_rel: DEFAULT_TOL_REL,
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
        if self.s_max > crate::limits::MAX_S {
            return Err(Error::invalid(
                "s_max",
                self.s_max,
                format!(
                    "must be <= {:e} (helixreach::limits::MAX_S)",
                    crate::limits::MAX_S
                ),
            ));
        }
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
    /// Axial forces `k_s(ℓ_j/ē'_j − 1)` of the edges at the last converged point (the
    /// augmented-Lagrangian multipliers, see [`DerRay::solve_inextensible`]).
    axial: Vec<Real>,
    correction_s: Real,
    /// The correction and s of the converged point before the last (secant predictor).
    correction_prev: Vec<Real>,
    correction_prev_s: Real,
    has_correction_prev: bool,
    has_correction: bool,
    branch_ended: bool,
    /// |μ| at the first converged point of the ray and at the last one (fold diagnosis).
    mu_first: Real,
    mu_last: Real,
    /// Whether the search may take the shortcuts (a cold start half-way to the first probe,
    /// continuation steps on the augmented-Lagrangian rod): [`DerRay::allow_shortcuts`].
    shortcuts: bool,
    /// The inextensible rod by KKT Newton ([`DerRay::set_inextensible`]) and its buffers.
    kkt: Option<KktWorkspace>,
    /// The Newton start of the last predicted evaluation (branch check).
    predicted: Vec<Real>,
    /// The weight per unit length in the helix frame ([`DerRay::set_gravity`]; 0: none).
    gravity: Vec3,
}

/// The outcome of a continuation step of [`DerRay::critical_s_on_branch`].
enum Step {
    /// A stable equilibrium on the branch.
    Stable,
    /// An equilibrium with a negative eigenvalue: past s*.
    Unstable,
    /// No convergence, or another branch: a shorter step, or the end of the branch.
    Failed,
}

/// The continuation state of a [`DerRay`] at its last accepted point
/// ([`DerRay::critical_s_on_branch`] returns to it after a rejected step). Buffers allocated
/// once per search.
#[derive(Debug)]
struct BranchPoint {
    correction: Vec<Real>,
    correction_prev: Vec<Real>,
    correction_s: Real,
    correction_prev_s: Real,
    has_correction_prev: bool,
    axial: Vec<Real>,
    state: Option<RodState>,
    mu_last: Real,
}

impl BranchPoint {
    fn new(ray: &DerRay) -> Self {
        BranchPoint {
            correction: ray.correction.clone(),
            correction_prev: ray.correction_prev.clone(),
            correction_s: ray.correction_s,
            correction_prev_s: ray.correction_prev_s,
            has_correction_prev: ray.has_correction_prev,
            axial: ray.axial.clone(),
            state: ray.state.clone(),
            mu_last: ray.mu_last,
        }
    }

    fn store(&mut self, ray: &DerRay) {
        self.correction.copy_from_slice(&ray.correction);
        self.correction_prev.copy_from_slice(&ray.correction_prev);
        self.correction_s = ray.correction_s;
        self.correction_prev_s = ray.correction_prev_s;
        self.has_correction_prev = ray.has_correction_prev;
        self.axial.copy_from_slice(&ray.axial);
        match (&mut self.state, &ray.state) {
            (Some(a), Some(b)) => a.copy_from(b),
            (a, b) => a.clone_from(b),
        }
        self.mu_last = ray.mu_last;
    }

    fn restore(&self, ray: &mut DerRay) {
        ray.correction.copy_from_slice(&self.correction);
        ray.correction_prev.copy_from_slice(&self.correction_prev);
        ray.correction_s = self.correction_s;
        ray.correction_prev_s = self.correction_prev_s;
        ray.has_correction_prev = self.has_correction_prev;
        ray.has_correction = true;
        ray.axial.copy_from_slice(&self.axial);
        match (&mut ray.state, &self.state) {
            (Some(a), Some(b)) => a.copy_from(b),
            (a, b) => a.clone_from(b),
        }
        ray.mu_last = self.mu_last;
    }
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
            axial: vec![0.0; n],
            correction_s: 1.0,
            correction_prev: vec![0.0; 4 * n + 3],
            correction_prev_s: 1.0,
            has_correction_prev: false,
            has_correction: false,
            branch_ended: false,
            mu_first: Real::NAN,
            mu_last: Real::NAN,
            shortcuts: false,
            kkt: None,
            predicted: vec![0.0; 4 * n + 3],
            gravity: Vec3::zeros(),
        })
    }

    /// Load the rod with its weight: `w` is the weight per unit length in the helix frame
    /// (nondimensional, `ρA·g·L³/k_b` times the direction of gravity; [`gravity_in_helix_frame`]),
    /// lumped at the nodes ([`Workspace::set_weight`]). Every equilibrium of the ray is then the
    /// loaded rod's (module docs, "Gravity"). Forgets the continuation.
    pub fn set_gravity(&mut self, w: Vec3) -> Result<()> {
        for (f, v) in [("gravity_x", w.x), ("gravity_y", w.y), ("gravity_z", w.z)] {
            require_finite(f, v)?;
        }
        self.gravity = w;
        self.ws.set_weight(&self.rod, &w);
        self.restart();
        Ok(())
    }

    /// Whether the rod carries its weight ([`DerRay::set_gravity`]).
    pub fn has_gravity(&self) -> bool {
        self.gravity != Vec3::zeros()
    }

    /// Allow the search's shortcuts (module docs, "Continuation"): a cold start at half the
    /// first probe's s and continuation steps solved on the augmented-Lagrangian rod. Off by
    /// default; [`critical_s`] turns them on where [`shortcuts_are_safe`] at the continuum s*.
    pub fn allow_shortcuts(&mut self, on: bool) {
        self.shortcuts = on;
    }

    /// Solve every equilibrium of this ray as the *inextensible* rod, by Newton on the KKT
    /// system ([`crate::rod::inextensible`]), and decide stability by the constrained Hessian
    /// (module docs, "The κ → 0 band"); off (the default): the augmented Lagrangian relaxed to
    /// the penalty rod of `params.stretch`. Forgets the continuation.
    pub fn set_inextensible(&mut self, on: bool) {
        if on && self.kkt.is_none() {
            let free = self.rod.free_range_clamped();
            self.kkt = Some(KktWorkspace::new(&self.rod, free));
        }
        if !on {
            self.kkt = None;
        }
        self.restart();
    }

    /// Whether this ray solves the inextensible rod by KKT Newton ([`DerRay::set_inextensible`]).
    pub fn is_inextensible(&self) -> bool {
        self.kkt.is_some()
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

    /// Equilibrium and stability at distance `s` (module docs: the equilibrium of the
    /// inextensible rod by an augmented Lagrangian, relaxed to the penalty rod of
    /// `params.stretch`, which [`DerRay::rod`] and [`DerRay::state`] hold afterwards).
    ///
    /// Newton starts from the sampled discrete helix plus the predicted discrete correction
    /// (equilibrium minus sampled helix) of the previous evaluations on this ray, which varies
    /// smoothly with s; if that fails (or on the first call) it starts from the sampled helix.
    /// The cold start may land on another branch far from the first evaluation;
    /// [`DerRay::critical_s`] therefore never uses it beyond the first, small s of a ray (it
    /// continues in s instead).
    pub fn evaluate(&mut self, s: Real) -> Result<RayPoint> {
        if self.has_correction {
            match self.evaluate_predicted(s, PREDICTED_MAX_ITERS, true) {
                Err(Error::NotConverged { .. }) => {}
                r => return r,
            }
        }
        self.evaluate_cold(s)
    }

    /// Newton from the predicted start only (sampled helix + correction of the last converged
    /// evaluation, scaled like s²), at most [`PREDICTED_MAX_ITERS`] iterations.
    ///
    /// `full`: relax to the penalty rod of `params.stretch` and estimate μ to
    /// [`MU_ITERS`] inverse iterations (a bracket point); otherwise a continuation step only
    /// (module docs, "Continuation"): the inextensible equilibrium to [`STEP_NEWTON_TOL`], the
    /// inertia of the augmented-Lagrangian rod, μ to [`STEP_MU_ITERS`].
    fn evaluate_predicted(&mut self, s: Real, max_iters: usize, full: bool) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        let free = self.rod.free_range_clamped();
        // The discrete correction scales like s² (chord shortfall ∝ (λē)², axial strain ∝
        // force ∝ s²); under gravity it holds the sag, already O(w) at s = 0: the secant then
        // extrapolates the correction itself.
        let power = if self.has_gravity() { 0 } else { 2 };
        let scale = (s / self.correction_s).powi(power);
        let mut st = init.clone();
        let (s1, s0) = (self.correction_s, self.correction_prev_s);
        if self.has_correction_prev && (s - s1).abs() <= 3.0 * (s1 - s0).abs() && s1 != s0 {
            // Secant on u = correction/s^power through the last two converged points.
            let w = (s - s1) / (s1 - s0);
            let (a1, a0) = (s1.powi(-power), s0.powi(-power));
            let sp = s.powi(power);
            for k in free.clone() {
                let (u1, u0) = (a1 * self.correction[k], a0 * self.correction_prev[k]);
                st.q[k] += sp * (u1 + w * (u1 - u0));
            }
        } else {
            for k in free.clone() {
                st.q[k] += scale * self.correction[k];
            }
        }
        let not_converged = || Error::NotConverged {
            what: "DER Newton from the predicted start".into(),
            iterations: max_iters,
            residual: Real::NAN,
        };
        if !st.update_reference() {
            return Err(not_converged());
        }
        self.predicted.copy_from_slice(&st.q);
        let r = if self.kkt.is_some() {
            let quick = NewtonParams {
                max_iters,
                ..self.newton
            };
            let r = self.solve_kkt(&mut st, &quick, scale);
            // Branch check: Newton on the inextensible rod converges from far; past a
            // bifurcation it can slide from the prediction onto a buckled, stable equilibrium
            // ((0.16825, −0.5312, −0.8304) at n = 50: 2·10⁻² L from the prediction, where the
            // steps along the branch stay below 6.4·10⁻⁴ L). Such a point is a failed step.
            if r.is_ok() && self.prediction_deviation(&st) > self.branch_deviation() {
                Err(not_converged())
            } else {
                r
            }
        } else {
            self.rod.material.stretch = self.newton_stretch();
            self.set_axial_forces(scale)?;
            let quick = if full {
                NewtonParams {
                    max_iters,
                    ..self.newton
                }
            } else {
                NewtonParams {
                    max_iters,
                    step_tol: STEP_NEWTON_TOL,
                    rel_residual_tol: STEP_NEWTON_TOL,
                    ..self.newton
                }
            };
            self.solve_inextensible(&mut st, &quick, full)
        };
        match r {
            Ok(eq) => Ok(self.finish(s, &init, st, eq.negative, eq.iterations, full)),
            Err(Error::NotConverged { .. }) => {
                self.evaluations += 1;
                self.newton_iterations += max_iters;
                Err(not_converged())
            }
            Err(e) => Err(e),
        }
    }

    /// Newton from the sampled helix with a continuation in the stretching stiffness; under
    /// gravity, from the gravity-free equilibrium with a continuation in the weight
    /// ([`DerRay::ramp_gravity`]).
    fn evaluate_cold(&mut self, s: Real) -> Result<RayPoint> {
        if !self.has_gravity() {
            return self.evaluate_cold_unloaded(s);
        }
        self.ws.external.clear();
        let unloaded = self.evaluate_cold_unloaded(s);
        let w = self.gravity;
        self.ws.set_weight(&self.rod, &w);
        unloaded?;
        self.ramp_gravity(s)
    }

    /// Continue the equilibrium of [`DerRay::state`] (gravity-free, at `s`) in the weight from 0
    /// to `self.gravity`: increments of at most the full weight, halved when Newton fails (below
    /// [`MIN_GRAVITY_INCREMENT`] of it: an error), doubled after a success.
    fn ramp_gravity(&mut self, s: Real) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        let Some(mut st) = self.state.take() else {
            unreachable!("ramp_gravity without a converged gravity-free state")
        };
        let w = self.gravity;
        let newton = self.newton;
        let (mut frac, mut inc, mut iterations): (Real, Real, usize) = (0.0, 1.0, 0);
        let mut trial = st.clone();
        let mut axial = self.axial.clone();
        let mut last = None;
        while frac < 1.0 {
            let t = (frac + inc).min(1.0);
            self.ws.set_weight(&self.rod, &(w * t));
            trial.copy_from(&st);
            let r = if self.kkt.is_some() {
                self.solve_kkt(&mut trial, &newton, 1.0)
            } else {
                self.rod.material.stretch = self.newton_stretch();
                self.set_axial_forces(1.0)?;
                self.solve_inextensible(&mut trial, &newton, true)
            };
            match r {
                Ok(eq) => {
                    iterations += eq.iterations;
                    st.copy_from(&trial);
                    axial.copy_from_slice(&self.axial);
                    frac = t;
                    inc = (2.0 * inc).min(1.0);
                    last = Some(eq);
                }
                Err(Error::NotConverged { .. }) if inc > MIN_GRAVITY_INCREMENT => {
                    iterations += newton.max_iters;
                    self.axial.copy_from_slice(&axial);
                    inc *= 0.5;
                }
                Err(e) => {
                    self.ws.set_weight(&self.rod, &w);
                    self.evaluations += 1;
                    self.newton_iterations += iterations;
                    return Err(e);
                }
            }
        }
        let Some(eq) = last else {
            unreachable!("the weight ramp ends with a converged solve")
        };
        // The gravity-free evaluation was counted by `finish`; this one is the ray's first point.
        self.has_correction = false;
        Ok(self.finish(s, &init, st, eq.negative, iterations, true))
    }

    /// [`DerRay::evaluate_cold`] of the rod without its weight.
    fn evaluate_cold_unloaded(&mut self, s: Real) -> Result<RayPoint> {
        let init = self.initial_state(s)?;
        if self.kkt.is_some() {
            // The multipliers start at the continuum helix's axial force (ω − τ)·τ, uniform
            // along the rod: with λ = 0 a cold start far along the ray could converge to
            // another, stable equilibrium ((0.16825, −0.5312, −0.8304) at n = 50: stable to
            // s_max, caught by the continuum check).
            let [_, t, w] = self.dir.at(s);
            self.axial.iter_mut().for_each(|f| *f = (w - t) * t);
            let mut st = init.clone();
            let newton = self.newton;
            return match self.solve_kkt(&mut st, &newton, 1.0) {
                Ok(eq) => Ok(self.finish(s, &init, st, eq.negative, eq.iterations, true)),
                Err(e) => {
                    self.evaluations += 1;
                    self.newton_iterations += newton.max_iters;
                    Err(e)
                }
            };
        }
        let free = self.rod.free_range_clamped();
        let target = self.newton_stretch();
        let mut iterations = 0;
        let mut st = init.clone();
        let mut ks = target.min(STRETCH_START);
        self.rod.reset_stretch_rest_lengths();
        let eq = loop {
            self.rod.material.stretch = ks;
            let r = if ks >= target {
                let newton = self.newton;
                self.solve_inextensible(&mut st, &newton, true)
            } else {
                statics::solve(&self.rod, &mut st, free.clone(), &mut self.ws, &self.newton)
            };
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
        Ok(self.finish(s, &init, st, eq.negative, iterations, true))
    }

    /// The inextensible equilibrium by KKT Newton from `st`, the multipliers starting at
    /// `scale·axial` (the last converged ones, scaled like s²); on success `axial` holds the
    /// new ones. The rod's stretching stiffness is 0 during the solve (the edge lengths are
    /// constraints) and `params.stretch` afterwards.
    fn solve_kkt(
        &mut self,
        st: &mut RodState,
        newton: &NewtonParams,
        scale: Real,
    ) -> Result<statics::Equilibrium> {
        let free = self.rod.free_range_clamped();
        let Some(kkt) = self.kkt.as_mut() else {
            unreachable!("solve_kkt without the KKT workspace")
        };
        for (l, a) in kkt.lambda_mut().iter_mut().zip(&self.axial) {
            *l = scale * a;
        }
        self.rod.reset_stretch_rest_lengths();
        self.rod.material.stretch = 0.0;
        let r = inextensible::solve(&self.rod, st, free, &mut self.ws, kkt, newton);
        self.rod.material.stretch = self.params.stretch;
        if r.is_ok() {
            self.axial.copy_from_slice(kkt.lambda());
        }
        r
    }

    /// The penalty Newton works with: `min(params.stretch, NEWTON_STRETCH)`.
    fn newton_stretch(&self) -> Real {
        self.params.stretch.min(NEWTON_STRETCH)
    }

    /// Set the stretching rest lengths so that edge `j` carries the axial force
    /// `scale·axial[j]` at its rest length `ē_j`: `ē'_j = ē_j/(1 + f_j/k_s)`.
    fn set_axial_forces(&mut self, scale: Real) -> Result<()> {
        let ks = self.rod.material.stretch;
        for j in 0..self.params.n_edges {
            let e = self.rod.rest_length(j);
            self.rod
                .set_stretch_rest_length(j, e / (1.0 + scale * self.axial[j] / ks))?;
        }
        Ok(())
    }

    /// Newton equilibrium of the *inextensible* discrete rod by an augmented Lagrangian: the
    /// penalty `k_s` only conditions Newton, and after each solve the stretching rest lengths
    /// are shifted (`ē'_j = ē_j/(1 + f_j/k_s)` with `f_j` the edge's axial force) until every
    /// edge length is within [`AL_STRAIN_TOL`] of `ē_j`. The equilibrium does not depend on
    /// `k_s`; each outer step is a Newton solve from the previous equilibrium (2–3 iterations).
    ///
    /// Without `relax` the augmented-Lagrangian rod is left as it is (a continuation step):
    /// `self.rod` then holds the shifted rest lengths at the Newton stiffness.
    fn solve_inextensible(
        &mut self,
        st: &mut RodState,
        newton: &NewtonParams,
        relax: bool,
    ) -> Result<statics::Equilibrium> {
        let free = self.rod.free_range_clamped();
        let n = self.params.n_edges;
        let mut iterations = 0;
        let mut worst = Real::NAN;
        let mut previous = Real::INFINITY;
        for _ in 0..AL_MAX_ITERS {
            let eq = statics::solve(&self.rod, st, free.clone(), &mut self.ws, newton)?;
            iterations += eq.iterations;
            let ks = self.rod.material.stretch;
            worst = 0.0;
            for j in 0..n {
                let l = st.edge(j).norm();
                let e = self.rod.rest_length(j);
                worst = worst.max((l / e - 1.0).abs());
                self.axial[j] = ks * (l / self.rod.stretch_rest_length(j) - 1.0);
            }
            // Converged, or at the round-off floor of the strain (the Newton residual over k_s).
            // After a rest-length update that Newton absorbs without an iteration the residual
            // is at its tolerance: the remaining strain is below what the equilibrium resolves
            // (a nearly straight rod, whose axial stiffness between the clamps is huge).
            let absorbed = previous.is_finite() && eq.iterations == 0;
            if worst <= AL_STRAIN_TOL.max(AL_FLOOR_FACTOR * eq.residual / ks) || absorbed {
                if !relax {
                    let mut eq = eq;
                    eq.iterations = iterations;
                    return Ok(eq);
                }
                // Relax to the penalty rod of `params.stretch` with its rest lengths: an axial
                // strain O(f/k_s) away, well inside Newton's basin. The stability test and
                // `self.rod`/`self.state` are that model's (the one of the DER dynamics).
                self.rod.reset_stretch_rest_lengths();
                self.rod.material.stretch = self.params.stretch;
                let mut eq = statics::solve(&self.rod, st, free.clone(), &mut self.ws, newton)?;
                eq.iterations += iterations;
                return Ok(eq);
            }
            // The update contracts like K/(K + k_s), K the rod's axial stiffness between the
            // clamps (large for a nearly straight rod): stiffen the penalty when it is slow.
            if worst > AL_SLOW * previous {
                self.rod.material.stretch = (ks * 10.0).min(AL_MAX_STRETCH);
            }
            previous = worst;
            self.set_axial_forces(1.0)?;
        }
        Err(Error::NotConverged {
            what: format!(
                "DER inextensibility (augmented Lagrangian): edge strain {worst:.3e} after \
                 {AL_MAX_ITERS} updates"
            ),
            iterations,
            residual: worst,
        })
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
        full: bool,
    ) -> RayPoint {
        let free = self.rod.free_range_clamped();
        let iters = match (full, self.shortcuts) {
            (false, _) => STEP_MU_ITERS,
            (true, true) => SHORTCUT_MU_ITERS,
            (true, false) => MU_ITERS,
        };
        let mu = match self.kkt.as_mut() {
            Some(kkt) => {
                let dim = kkt.dim();
                let (a, ldlt) = kkt.kkt();
                ldlt.smallest_eigenvalue_warm(a, 0..dim, iters, true)
            }
            None => self
                .ws
                .ldlt
                .smallest_eigenvalue_warm(&self.ws.hess, free, iters, true),
        };

        std::mem::swap(&mut self.correction, &mut self.correction_prev);
        self.correction_prev_s = self.correction_s;
        self.has_correction_prev = self.has_correction;
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

    /// Forget the continuation (the next probe starts cold).
    fn restart(&mut self) {
        self.has_correction = false;
        self.has_correction_prev = false;
        self.correction_s = 1.0;
        self.correction_prev_s = 1.0;
        self.rod.reset_stretch_rest_lengths();
        self.axial.iter_mut().for_each(|f| *f = 0.0);
    }

    /// The largest displacement from the prediction a continuation step may make before it
    /// counts as having left the branch: [`PREDICTION_DEVIATION`], or
    /// [`GRAVITY_PREDICTION_DEVIATION`] under gravity (the sag makes the first-order predictor
    /// coarser; another branch is still O(0.1 L) away).
    fn branch_deviation(&self) -> Real {
        if self.has_gravity() {
            GRAVITY_PREDICTION_DEVIATION
        } else {
            PREDICTION_DEVIATION
        }
    }

    /// Largest node displacement of `st` from the last Newton start ([`DerRay::predicted`]).
    fn prediction_deviation(&self, st: &RodState) -> Real {
        (0..=self.params.n_edges).fold(0.0, |m: Real, i| {
            (0..3).fold(m, |m, a| {
                m.max((st.q[4 * i + a] - self.predicted[4 * i + a]).abs())
            })
        })
    }

    /// Largest node displacement of the last equilibrium from the sampled helix (units of L).
    fn correction_size(&self) -> Real {
        let free = self.rod.free_range_clamped();
        self.correction[free]
            .iter()
            .enumerate()
            .filter(|(k, _)| (k + 7) % 4 != 3)
            .fold(0.0, |m, (_, c)| m.max(c.abs()))
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
            let s0 = if self.shortcuts {
                s.min(COLD_START_S.max(COLD_FRACTION * s))
            } else {
                s.min(COLD_START_S)
            };
            let far = s0 > COLD_START_S;
            let fallback = match self.evaluate_cold(s0) {
                Ok(pt) if far => pt.negative > 0 || self.correction_size() > BRANCH_DEVIATION,
                Ok(pt) if pt.negative > 0 || s0 == s => return Ok(classify(&pt)),
                Ok(_) => false,
                Err(Error::NotConverged { .. }) if far => true,
                Err(e) => return Err(e),
            };
            if fallback {
                // Not verified on the helical branch (or failed): the nearly straight rod.
                self.restart();
                let s0 = s.min(COLD_START_S);
                match self.evaluate_cold(s0) {
                    Ok(pt) if pt.negative > 0 || s0 == s => return Ok(classify(&pt)),
                    Ok(_) => {}
                    Err(e) => return Err(e),
                }
            }
        }
        // Continuation from the last converged point a towards s: steps of at most
        // MAX_STEP_RATIO in s, halved on failure, grown by 1.5 on success.
        let mut a = self.correction_s;
        let mut ratio = MAX_STEP_RATIO;
        let mut careful = false;
        loop {
            let t = if s > a {
                s.min(a * ratio)
            } else {
                s.max(a / ratio)
            };
            if (ratio - 1.0) < MIN_STEP_RATIO_EXCESS {
                // Stalled: a full Newton solve (line search, 30 iterations) from the prediction.
                match self.evaluate_predicted(s, self.newton.max_iters, true) {
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
            let full = t == s || careful || !self.shortcuts;
            match self.evaluate_predicted(t, PREDICTED_MAX_ITERS, full) {
                Ok(pt) => {
                    if t == s {
                        return Ok(classify(&pt));
                    }
                    // The inextensible rod's steps are the model itself (only μ is rougher).
                    if pt.negative > 0 && (full || self.kkt.is_some()) {
                        return Ok(classify(&pt));
                    }
                    if pt.negative > 0 {
                        // A continuation step past s*: the bracket end is the full evaluation.
                        match self.evaluate_predicted(t, PREDICTED_MAX_ITERS, true) {
                            Ok(pt) => return Ok(classify(&pt)),
                            Err(Error::NotConverged { .. }) => {
                                ratio = 1.0 + 0.5 * (ratio - 1.0);
                                continue;
                            }
                            Err(e) => return Err(e),
                        }
                    }
                    a = t;
                    ratio = 1.0 + ((ratio - 1.0) * 1.5).min(MAX_STEP_RATIO - 1.0);
                }
                Err(Error::NotConverged { .. }) => {
                    // After a failed step the probe continues with full evaluations (the
                    // penalty rod of every bracket point), as robust as before the shortcut.
                    careful = true;
                    ratio = 1.0 + 0.5 * (ratio - 1.0)
                }
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
                if s < MIN_BRACKET_S {
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

    /// s* of the rod under gravity ([`DerRay::set_gravity`]; module docs, "Gravity"): the end
    /// of the stable branch reached from the nearly straight rod. From a cold start at
    /// `min(COLD_START_S, guess)` the branch is followed forward only: a step from the last
    /// stable point `a` to `t` is accepted when Newton from the prediction converges to a stable
    /// equilibrium within `GRAVITY_PREDICTION_DEVIATION` of it (then the step grows by 1.5, at
    /// most to ×1.1 in s, and to `guess` at most while below it). A step to an equilibrium with
    /// a negative eigenvalue makes `t` the upper end `hi` of the bracket, and later steps bisect
    /// `[a, hi]`; a step that fails (no convergence, or another branch) is halved. The search ends
    /// when `min(hi, a + 2·step) − a ≤ tol_rel·a`, with s* the middle of that interval: the
    /// crossing of an eigenvalue through 0 (a negative eigenvalue met) or the fold where the
    /// branch ends (Newton finds no nearby equilibrium past it). The criterion is the smallest
    /// eigenvalue μ of the constrained Hessian (of the KKT matrix, which crosses 0 with it) at
    /// the last stable point `a`: the end is the loss of stability when |μ(a)| ≤
    /// `SINGULAR_MU_RATIO` (10⁻²) of its value at the ray's start. An unstable bracket end met
    /// where |μ(a)| is still larger was an equilibrium of another branch (a step across the
    /// sharp turn of an imperfect supercritical bifurcation lands on its unstable branch): it is
    /// forgotten and the continuation goes on (at most `MAX_BRANCH_RESETS` times). A failed end
    /// with |μ(a)| above `FOLD_MU_RATIO` of its start value is a solver failure (an error),
    /// never an s*.
    pub fn critical_s_on_branch(&mut self, guess: Real) -> Result<CriticalS> {
        let p = self.params;
        require_positive("guess", guess)?;
        self.restart();
        let s0 = COLD_START_S.min(guess).min(p.s_max);
        let first = self.evaluate_cold(s0)?;
        if first.negative > 0 {
            return Err(Error::NotConverged {
                what: format!(
                    "DER continuation under gravity: the first equilibrium (s = {s0}) is \
                     already unstable"
                ),
                iterations: self.newton_iterations,
                residual: Real::NAN,
            });
        }
        let mut saved = BranchPoint::new(self);
        let mut a = s0;
        let mut hi = Real::INFINITY;
        let mut step = a * (GRAVITY_MAX_STEP_RATIO - 1.0);
        let mut met_unstable = false;
        let mut resets = 0;
        loop {
            if a >= p.s_max {
                return Ok(CriticalS {
                    s_star: Real::INFINITY,
                    est_error: 0.0,
                });
            }
            let upper = hi.min(a + 2.0 * step);
            if upper - a <= p.tol_rel * a {
                let singular = self.mu_last <= SINGULAR_MU_RATIO * self.mu_first;
                if met_unstable && !singular && resets < MAX_BRANCH_RESETS {
                    // The unstable end was an equilibrium of another branch (the followed one
                    // is still far from singular there): forget it and continue.
                    resets += 1;
                    met_unstable = false;
                    hi = Real::INFINITY;
                    step = RESET_STEP * a;
                    continue;
                }
                if !singular && self.mu_last > FOLD_MU_RATIO * self.mu_first {
                    return Err(Error::NotConverged {
                        what: format!(
                            "DER continuation under gravity stalled at s = {a} with the \
                             constrained Hessian far from singular (|mu| = {:.3e}, {:.3e} at \
                             the ray's start)",
                            self.mu_last, self.mu_first
                        ),
                        iterations: self.newton_iterations,
                        residual: Real::NAN,
                    });
                }
                return Ok(CriticalS {
                    s_star: 0.5 * (a + upper),
                    est_error: 0.5 * (upper - a),
                });
            }
            // Forward by `step`, to the guess at most while below it, and to the middle of
            // [a, hi] once an unstable point has been met.
            let mut t = (a + step).min(p.s_max);
            if a < guess && t > guess {
                t = guess;
            }
            if hi.is_finite() {
                t = t.min(0.5 * (a + hi));
            }
            let outcome = match self.evaluate_predicted(t, PREDICTED_MAX_ITERS, true) {
                Ok(pt) if pt.negative == 0 => {
                    let state = self.state.as_ref().expect("a converged point has a state");
                    if self.prediction_deviation(state) <= self.branch_deviation() {
                        Step::Stable
                    } else {
                        Step::Failed
                    }
                }
                Ok(_) => Step::Unstable,
                Err(Error::NotConverged { .. }) => Step::Failed,
                Err(e) => return Err(e),
            };
            match outcome {
                Step::Stable => {
                    saved.store(self);
                    step = ((t - a) * 1.5).min(t * (GRAVITY_MAX_STEP_RATIO - 1.0));
                    a = t;
                }
                Step::Unstable => {
                    saved.restore(self);
                    met_unstable = true;
                    hi = t;
                    step = t - a;
                }
                Step::Failed => {
                    saved.restore(self);
                    step = 0.5 * (t - a);
                }
            }
        }
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
/// invalid direction (NaN, zero, κ < 0), a direction too close to the κ = 0 plane (below the
/// KKT limit, [`solves_inextensible`], and failing [`check_extensibility`]) or too
/// coarsely resolved ([`check_resolution`]), a Newton failure, or a
/// result that disagrees with the continuum beyond its `est_error`
/// ([`check_against_continuum`]).
pub fn critical_s(dir: &Direction, params: &DerBoundaryParams) -> Result<CriticalS> {
    critical_s_with_work(dir, params).0
}

/// The DER-statics critical distance s* along `dir` of the rod loaded by its weight `w` per
/// unit length in the helix frame ([`gravity_in_helix_frame`]; module docs, "Gravity").
/// `w = 0` is [`critical_s`]. With gravity the result is not checked against the continuum
/// (which has no weight); its `est_error` is the bracket plus the discretization bound at the
/// s* found.
///
/// Errors: as [`critical_s`] (but the continuum check), a non-finite `w`, and a weight ramp
/// that does not converge at the ray's first point.
pub fn critical_s_gravity(
    dir: &Direction,
    params: &DerBoundaryParams,
    w: Vec3,
) -> Result<CriticalS> {
    let mut ray = DerRay::new(dir, params)?;
    critical_s_on(&mut ray, params, w)
}

/// The weight per unit length of `rod`, nondimensional (`ρA·g·L³/k_b` times the direction of
/// gravity), in the helix frame of a ray at azimuth `azimuth` (rad) on a clamp of rotation
/// `clamp` (`[d1 d2 d3]` as columns in the base frame: d3 the rod tangent at the clamp) under
/// gravity `g_base` (m/s², base frame): `Rz(α)ᵀ·Rᵀ·g·ρAL³/k_b`
/// ([`Placement::to_helix_frame`](crate::rod::dynamics::centerline::Placement::to_helix_frame),
/// the convention of the dynamics).
///
/// ```
/// use helixreach::boundary::der::gravity_in_helix_frame;
/// use helixreach::math::{Mat3, Vec3};
/// use helixreach::rod::dynamics::PhysicalRod;
/// let rod = PhysicalRod::nitinol();
/// // Rod up (d3 = base z): gravity along −z of the helix frame, for every azimuth.
/// let w = gravity_in_helix_frame(&rod, &Mat3::identity(), 1.0, &Vec3::new(0.0, 0.0, -9.81))
///     .unwrap();
/// let size = rod.linear_density() * 9.81 * rod.length.powi(3) / rod.bending_stiffness();
/// assert!((w - Vec3::new(0.0, 0.0, -size)).norm() < 1e-12 * size);
/// ```
pub fn gravity_in_helix_frame(
    rod: &crate::rod::dynamics::PhysicalRod,
    clamp: &crate::math::Mat3,
    azimuth: Real,
    g_base: &Vec3,
) -> Result<Vec3> {
    rod.validate()?;
    let placement = crate::rod::dynamics::centerline::Placement::new(
        Vec3::zeros(),
        *clamp,
        azimuth,
        rod.length,
    )?;
    let scale = rod.linear_density() * rod.length.powi(3) / rod.bending_stiffness();
    Ok(placement.to_helix_frame(g_base) * scale)
}

/// [`critical_s`] with the work it spent, `(evaluations, Newton iterations)` of the ray
/// ([`DerRay::work`]), also when it fails (speed studies: `examples/der_convergence.rs`).
pub fn critical_s_with_work(
    dir: &Direction,
    params: &DerBoundaryParams,
) -> (Result<CriticalS>, (usize, usize)) {
    let mut ray = match DerRay::new(dir, params) {
        Ok(r) => r,
        Err(e) => return (Err(e), (0, 0)),
    };
    let r = critical_s_on(&mut ray, params, Vec3::zeros());
    (r, ray.work())
}

fn critical_s_on(ray: &mut DerRay, params: &DerBoundaryParams, w: Vec3) -> Result<CriticalS> {
    let c = super::continuum::critical_s(&ray.dir, CONTINUUM_CHECK_TOL_REL)?;
    if w != Vec3::zeros() {
        return critical_s_loaded(ray, params, w, &c);
    }
    // The κ → 0 band (module docs): the inextensible rod by KKT Newton, no shortcut.
    let band = c.s_star.is_finite() && !shortcuts_are_safe(&ray.dir, c.s_star)?;
    let kkt = solves_inextensible(&ray.dir, params.n_edges);
    if c.s_star.is_finite() {
        if !kkt {
            check_extensibility(&ray.dir, c.s_star)?;
        }
        check_resolution(&ray.dir, c.s_star, params.n_edges, ray.c)?;
    }
    ray.set_inextensible(kkt);
    ray.allow_shortcuts(c.s_star.is_finite() && !band);
    let mut r = if params.continuum_seed && c.s_star.is_finite() && c.s_star < params.s_max {
        ray.critical_s_from(SEED_BELOW * c.s_star, SEED_GROWTH)?
    } else {
        ray.critical_s()?
    };
    if r.s_star.is_finite() {
        // The resolution at the continuum s* (the DER s* itself may be far off where the rod is
        // unresolved, which the check below catches).
        let s_ref = if c.s_star.is_finite() {
            c.s_star
        } else {
            r.s_star
        };
        let per_edge = rotation_per_edge(&ray.dir, s_ref, params.n_edges, ray.c);
        r.est_error += DISCRETIZATION_COEFF * per_edge * per_edge * s_ref;
    }
    check_against_continuum(&ray.dir, &r, &c, params)?;
    Ok(r)
}

/// [`critical_s_gravity`] with a nonzero weight: the gravity-free guards, the seeded search
/// without shortcuts, no continuum check (module docs, "Gravity").
fn critical_s_loaded(
    ray: &mut DerRay,
    params: &DerBoundaryParams,
    w: Vec3,
    c: &CriticalS,
) -> Result<CriticalS> {
    let kkt = solves_inextensible(&ray.dir, params.n_edges);
    if c.s_star.is_finite() {
        if !kkt {
            check_extensibility(&ray.dir, c.s_star)?;
        }
        check_resolution(&ray.dir, c.s_star, params.n_edges, ray.c)?;
    }
    ray.set_inextensible(kkt);
    ray.set_gravity(w)?;
    ray.allow_shortcuts(false);
    let guess = if params.continuum_seed && c.s_star.is_finite() {
        SEED_BELOW * c.s_star
    } else {
        params.s_max
    };
    let mut r = ray.critical_s_on_branch(guess)?;
    if r.s_star.is_finite() {
        check_resolution(&ray.dir, r.s_star, params.n_edges, ray.c).map_err(|e| {
            Error::invalid(
                "n_edges",
                params.n_edges,
                format!(
                    "under gravity the branch loses stability at s = {}: {e}",
                    r.s_star
                ),
            )
        })?;
        let per_edge = rotation_per_edge(&ray.dir, r.s_star, params.n_edges, ray.c);
        r.est_error += DISCRETIZATION_COEFF * per_edge * per_edge * r.s_star;
    }
    Ok(r)
}

/// The consistency check of a DER result against the continuum s* (module docs, "What
/// `est_error` covers"): the DER s* must lie within `est_error` (plus the continuum's own
/// error) of the continuum, and both must agree on whether the ray loses stability below
/// `s_max`; otherwise the DER result is an error naming both values.
pub fn check_against_continuum(
    dir: &Direction,
    der: &CriticalS,
    continuum: &CriticalS,
    params: &DerBoundaryParams,
) -> Result<()> {
    let (d, c) = (der.s_star, continuum.s_star);
    let c_unstable = c.is_finite() && c < params.s_max;
    let consistent = match (c_unstable, d.is_finite()) {
        (true, true) => (d - c).abs() <= der.est_error + continuum.est_error,
        (false, false) => true,
        // Stable to s_max by one method only: consistent only past s_max on both.
        (true, false) => false,
        (false, true) => c.is_finite() && d + der.est_error >= params.s_max,
    };
    if consistent {
        return Ok(());
    }
    // No iteration failed: the DER answer converged but is not the continuum's to within its
    // error estimate — say that (it is no convergence failure).
    let what = if c_unstable && !d.is_finite() {
        format!(
            "finds the ray stable up to s_max = {} although the continuum loses stability at \
             s* = {c}",
            params.s_max
        )
    } else if !c_unstable {
        format!(
            "gives s* = {d} ± {:.3e} although the continuum finds the ray stable up to \
             s_max = {}",
            der.est_error, params.s_max
        )
    } else {
        format!(
            "gives s* = {d} ± {:.3e}, which misses the continuum s* = {c} ± {:.1e} by {:.3e} \
             (beyond its error estimate)",
            der.est_error,
            continuum.est_error,
            (d - c).abs()
        )
    };
    Err(Error::Inconsistent {
        what: format!(
            "DER statics (n_edges = {}) on direction ({}, {}, {}) {what}: the discrete rod does \
             not resolve this direction; use a larger n_edges or the continuum method",
            params.n_edges, dir.kappa, dir.tau, dir.omega
        ),
    })
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

/// Whether the search's shortcuts ([`DerRay::allow_shortcuts`]) are safe on `dir` with
/// continuum s* `s_star`: the augmented-Lagrangian rod of the continuation steps (stiffness
/// 10⁶) models the inextensible rod only where its axial strain `|n|/k_s` is
/// small against the helix's chord shortening δ (at most [`SHORTCUT_STRAIN_TO_SHORTENING`]·δ);
/// near the κ = 0 plane (a nearly straight, compressed rod) it buckles early and the
/// continuation must solve the penalty rod of every step.
pub fn shortcuts_are_safe(dir: &Direction, s_star: Real) -> Result<bool> {
    let (force, shortening) = force_and_shortening(dir, s_star)?;
    Ok(force / NEWTON_STRETCH <= SHORTCUT_STRAIN_TO_SHORTENING * shortening)
}

/// The helix's internal force `|n| = |ω − τ|·√(κ² + τ²)` and chord shortening `1 − |r(1)|` at
/// distance `s` along `dir`.
fn force_and_shortening(dir: &Direction, s: Real) -> Result<(Real, Real)> {
    let [k, t, w] = dir.at(s);
    let force = (w - t).abs() * (k * k + t * t).sqrt();
    let shortening = 1.0 - Helix::new(k, t, w)?.position(1.0).norm();
    Ok((force, shortening))
}

/// Whether [`critical_s`] solves `dir` at resolution `n_edges` as the inextensible rod by KKT
/// Newton (module docs, "Inextensibility"): where the direction's curvature share is at least
/// `max(`[`MIN_KAPPA_HAT`]`, `[`MIN_KAPPA_HAT_PER_EDGE`]`·n)`. Below it the constraint
/// Jacobian of the edge lengths is too close to rank-deficient (a uniform axial force is
/// invisible on a straight rod; its smallest singular value is the edges' turning angle ≈ κ·ē)
/// and the augmented Lagrangian of the penalty rod is used, with the extensibility guard
/// ([`check_extensibility`]).
pub fn solves_inextensible(dir: &Direction, n_edges: usize) -> bool {
    dir.kappa >= MIN_KAPPA_HAT.max(MIN_KAPPA_HAT_PER_EDGE * n_edges as Real)
}

/// The extensibility guard (module docs): at the continuum s* the helix's internal force
/// `|n| = |ω − τ|·√(κ² + τ²)` would strain a rod of stiffness
/// [`EXTENSIBILITY_GUARD_STRETCH`] by `|n|/k_guard`; unless that is at most
/// [`MAX_STRAIN_TO_SHORTENING`] of the chord shortening `δ = 1 − |r(1)|`, the discrete
/// equilibrium cannot resolve the compression of the nearly straight rod, and the direction is
/// an error naming both numbers.
pub fn check_extensibility(dir: &Direction, s_star: Real) -> Result<()> {
    let (force, shortening) = force_and_shortening(dir, s_star)?;
    let strain = force / EXTENSIBILITY_GUARD_STRETCH;
    if strain > MAX_STRAIN_TO_SHORTENING * shortening {
        return Err(Error::invalid(
            "direction",
            format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
            format!(
                "too close to the kappa = 0 plane for DER statics: at the continuum s* = \
                 {s_star} the helix's chord shortening {shortening:.3e} is below what the \
                 discrete equilibrium resolves (axial force {force:.3e} over the guard \
                 stretch {EXTENSIBILITY_GUARD_STRETCH:e} = {strain:.3e} strain); use the \
                 continuum method"
            ),
        ));
    }
    Ok(())
}

/// Largest n [`critical_s_to_rel_tol`] refines to unless told otherwise.
pub const DEFAULT_MAX_ADAPTIVE_EDGES: usize = 3200;

/// The DER s* of one direction at a requested accuracy ([`critical_s_to_rel_tol`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveS {
    /// s* at the finest resolution computed (`∞`: stable to `s_max` at the last two).
    pub s_star: Real,
    /// Its error estimate: the Richardson estimate `|s*_n − s*_{n/2}|/3` of the discretization
    /// error (order 2) plus the final bracket's half-width.
    pub est_error: Real,
    /// The finest n.
    pub n_edges: usize,
    /// The Richardson estimate relative to s* (≤ the requested tolerance).
    pub richardson_rel: Real,
}

/// s* of `dir` to a requested relative accuracy: [`critical_s`] at `params.n_edges`, then at
/// doubled n until the Richardson estimate of the discretization error of the finer value,
/// `|s*_n − s*_{n/2}|/3` (the DER error is second order in 1/n, `examples/der_convergence.rs`),
/// is at most `rel_tol·s*_n`. A resolution [`critical_s`] refuses (too coarse for the direction,
/// or outside its checked error bound) is skipped by doubling. Reaching `max_edges` without
/// meeting `rel_tol` is an error naming the n the order-2 estimate says is needed, never a
/// silently capped answer.
///
/// Cost: the sum over the levels, dominated by the finest (≈ 2× one [`critical_s`] there).
/// On the large-s* band the discrete rod is pre-asymptotic up to φ ≈ 0.3 rad per edge (module
/// docs, "Resolution"), where two levels can agree by chance; `docs/RESULTS.md` measures the
/// result against the continuum.
pub fn critical_s_to_rel_tol(
    dir: &Direction,
    params: &DerBoundaryParams,
    rel_tol: Real,
    max_edges: usize,
) -> Result<AdaptiveS> {
    critical_s_to_rel_tol_gravity(dir, params, Vec3::zeros(), rel_tol, max_edges)
}

/// [`critical_s_to_rel_tol`] of the rod loaded by its weight `w` ([`critical_s_gravity`]).
pub fn critical_s_to_rel_tol_gravity(
    dir: &Direction,
    params: &DerBoundaryParams,
    w: Vec3,
    rel_tol: Real,
    max_edges: usize,
) -> Result<AdaptiveS> {
    params.validate()?;
    require_positive("rel_tol", rel_tol)?;
    if rel_tol >= 0.5 {
        return Err(Error::invalid("rel_tol", rel_tol, "must be < 0.5"));
    }
    crate::limits::check_size("max_n_edges", max_edges, crate::limits::MAX_N_EDGES)?;
    if max_edges < 2 * params.n_edges {
        return Err(Error::invalid(
            "max_n_edges",
            max_edges,
            format!(
                "must be at least twice the starting n_edges = {} (two resolutions give the \
                 Richardson estimate)",
                params.n_edges
            ),
        ));
    }
    let mut n = params.n_edges;
    let mut prev: Option<Real> = None;
    loop {
        let p = DerBoundaryParams {
            n_edges: n,
            ..*params
        };
        let finer = 2 * n;
        match critical_s_gravity(dir, &p, w) {
            Ok(r) => {
                let bracket = 0.5 * p.tol_rel * r.s_star;
                match prev {
                    Some(sp) if !r.s_star.is_finite() && !sp.is_finite() => {
                        return Ok(AdaptiveS {
                            s_star: Real::INFINITY,
                            est_error: 0.0,
                            n_edges: n,
                            richardson_rel: 0.0,
                        })
                    }
                    Some(sp) if r.s_star.is_finite() && sp.is_finite() => {
                        let est = (r.s_star - sp).abs() / 3.0;
                        let rel = est / r.s_star;
                        if rel <= rel_tol {
                            return Ok(AdaptiveS {
                                s_star: r.s_star,
                                est_error: est + bracket,
                                n_edges: n,
                                richardson_rel: rel,
                            });
                        }
                        if finer > max_edges {
                            let need = (n as Real * (rel / rel_tol).sqrt()).ceil();
                            return Err(Error::invalid(
                                "max_n_edges",
                                max_edges,
                                format!(
                                    "direction ({}, {}, {}): at n_edges = {n} the Richardson \
                                     estimate of the DER error is {rel:.2e} relative (> rel_tol \
                                     {rel_tol:e}); second order needs n_edges ≈ {need} (raise \
                                     max_n_edges or rel_tol, or use the continuum method)",
                                    dir.kappa, dir.tau, dir.omega
                                ),
                            ));
                        }
                    }
                    _ => {}
                }
                prev = Some(r.s_star);
            }
            Err(e) => {
                if finer > max_edges {
                    return Err(Error::invalid(
                        "max_n_edges",
                        max_edges,
                        format!(
                            "direction ({}, {}, {}): still refused at n_edges = {n}, the \
                             largest allowed: {e}",
                            dir.kappa, dir.tau, dir.omega
                        ),
                    ));
                }
                prev = None;
            }
        }
        if finer > max_edges {
            return Err(Error::invalid(
                "max_n_edges",
                max_edges,
                format!(
                    "direction ({}, {}, {}): n_edges = {finer} needed for a second resolution \
                     exceeds it",
                    dir.kappa, dir.tau, dir.omega
                ),
            ));
        }
        n = finer;
    }
}
