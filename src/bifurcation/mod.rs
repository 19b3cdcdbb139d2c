//! Snap or gradual departure: the type of the bifurcation at each ray's s* ([architecture §7](crate::architecture)), from
//! DER statics, and the hysteresis of subcritical rays.
//!
//! | module | holds |
//! |---|---|
//! | [`reduction`] | the critical mode and the Koiter coefficients of the DER energy at s* |
//! | [`unloading`] | the post-snap equilibrium followed back down in s (static `s_return`) |
//! | [`contact`] | self-contact and self-crossing of the rod along a motion (the DER has no contact) |
//! | [`survey`] | the type over a set of directions; the seed's 42 labelled directions |
//!
//! # The reduced equation
//! Along a ray the helix `q₀(s)` is an equilibrium for every s (exactly in the continuum; the
//! discrete helix is its `O(1/n²)` neighbour). At s* one eigenvalue λ(s) of the free Hessian
//! crosses zero (`λ' = dλ/ds < 0`: stable before, unstable after), with unit mode φ. Writing
//! the rod as `q = q₀(s) + xφ + y`, `y ⊥ φ`, and eliminating `y` by its own equilibrium
//! (Lyapunov–Schmidt; `y = x²w + …` with `w = −½H⊥⁻¹E‴[φ,φ,·]`) leaves one equation in x,
//!
//! `∂E_red/∂x = λ'·(s − s*)·x + (a/2)·x² + (b/6)·x³ + … = 0`,
//!
//! with `a = E‴[φ,φ,φ]` and the Koiter coefficient `b = E⁗[φ⁴] − 3·E‴[φ,φ,·]ᵀH⊥⁻¹E‴[φ,φ,·]`.
//!
//! **Symmetry.** The clamped–clamped helix is invariant under the rotation by π about its
//! principal normal at mid-length (it swaps the clamps and maps arc length σ ↦ 1 − σ); the
//! straddling DER discretization keeps it exactly. Let `R` be that involution on the DOFs
//! (`E(Rq) = E(q)`, `Rq₀ = q₀`). A simple critical mode is even or odd, `Rφ = ±φ`. For an odd
//! mode `E(q₀ + xφ) = E(q₀ − xφ)`, so `a = 0` and the reduced equation is the pitchfork
//! `x·(λ'(s − s*) + (b/6)x²) = 0`: besides the helix `x = 0`, the branch
//! `x² = 6|λ'|(s − s*)/b` exists for `s > s*` when `b > 0` (**supercritical**: the rod leaves
//! the helix gradually on a stable branch of amplitude ∝ √(s − s*), and unloading retraces it)
//! and for `s < s*` when `b < 0` (**subcritical**: the branch is unstable and bends back; past
//! s* there is no nearby equilibrium and the rod snaps to a far one; it returns to the helix
//! on unloading only where that far branch ends, at `s_return < s*` — hysteresis). An even
//! mode has `a ≠ 0` in general (a transcritical crossing, which the discrete imperfection turns
//! into a fold): reported as `degenerate`.
//!
//! # Reported coefficient and sign convention
//! `coefficient = b / (6·|λ'|·s*·m²)`, where `m` is the largest node displacement of the unit
//! mode φ: then, for `s` near s*, the largest node displacement `d` (units of L) on the
//! bifurcated branch obeys `d² = (s/s* − 1) / coefficient`. It is independent of the
//! normalization of φ and of the stiffness scale; **positive ⇔ supercritical, negative ⇔
//! subcritical**. `degenerate` is reported (with the reason) when
//! - the mode is not odd: the asymmetry `|a|·d₁/|b·d₁²/3|`, with `d₁` the amplitude at
//!   `s/s* − 1 = 1 %`, exceeds [`ASYMMETRY_MAX`];
//! - `|b|` is below three times its finite-difference error (the quartic term does not decide);
//! - no helical equilibrium was found just below s* (the helical branch ends at a fold);
//! - the ray could not be decided numerically: s* not found or refused by the DER boundary
//!   (resolution, extensibility, stable to `s_max`; then `s_star` is NaN), or the reduction's
//!   constrained Newton converged at none of its amplitudes. The reason names the failure;
//!   [`classify`] never fails on a valid direction, so one hard ray never stops a sweep.
//!
//! ```no_run
//! use helixreach::bifurcation::{classify, BifurcationParams, BifurcationType};
//! use helixreach::directions::Direction;
//! let p = BifurcationParams::default();
//! let b = classify(&Direction::new(0.84, 0.54, 0.0)?, &p)?;
//! assert_eq!(b.kind, BifurcationType::Subcritical);
//! # Ok::<(), helixreach::Error>(())
//! ```

pub mod contact;
pub mod reduction;
pub mod survey;
pub mod unloading;

use crate::boundary::der::{DerBoundaryParams, DerRay};
use crate::directions::Direction;
use crate::error::{require_positive, Error, Result};
use crate::math::Real;
use crate::rod::params::twist_ratio;
use crate::rod::Workspace;

/// Largest asymmetry ratio for which the mode counts as odd (see the module docs).
pub const ASYMMETRY_MAX: Real = 0.1;
/// Relative step in s of the one-sided finite difference of λ(s) (second order, two points).
pub const DLAMBDA_STEP: Real = 5e-3;

/// The kind of loss of stability at s*.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BifurcationType {
    /// The rod snaps; hysteresis on unloading.
    Subcritical,
    /// The rod departs gradually; unloading retraces loading.
    Supercritical,
    /// The quartic reduction does not decide (see the reason).
    Degenerate,
}

impl BifurcationType {
    /// `subcritical`, `supercritical` or `degenerate`.
    pub fn name(self) -> &'static str {
        match self {
            BifurcationType::Subcritical => "subcritical",
            BifurcationType::Supercritical => "supercritical",
            BifurcationType::Degenerate => "degenerate",
        }
    }

    /// Parse a name (as written by [`BifurcationType::name`]).
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "subcritical" => Ok(BifurcationType::Subcritical),
            "supercritical" => Ok(BifurcationType::Supercritical),
            "degenerate" => Ok(BifurcationType::Degenerate),
            _ => Err(Error::invalid(
                "type",
                s,
                "must be subcritical, supercritical or degenerate",
            )),
        }
    }
}

/// Parameters of [`classify`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BifurcationParams {
    /// The DER statics (n, ν, tolerance of s*, …).
    pub der: DerBoundaryParams,
    /// Also follow the post-snap equilibrium down to `s_return` (subcritical rays).
    pub statics_return: bool,
    /// Relative resolution of `s_return`.
    pub return_tol_rel: Real,
    /// The rod's diameter (units of L) below which two edges of the followed far branch count
    /// as touching (see [`contact`]).
    pub contact_diameter: Real,
}

/// Relative tolerance of the DER s* when classifying, in [`BifurcationParams::default`] and
/// [`BifurcationParams::planning`] (the DER boundary's own default is 1e-8).
pub const S_STAR_TOL_REL: Real = 1e-7;
/// Default relative resolution of `s_return` ([`BifurcationParams::return_tol_rel`]).
pub const RETURN_TOL_REL: Real = 1e-3;

impl Default for BifurcationParams {
    /// DER n = 100, `tol_rel =` [`S_STAR_TOL_REL`], static return on, resolved to
    /// [`RETURN_TOL_REL`], the contact
    /// diameter of the seed's nitinol rod (1.5875 mm on L = 0.5 m: 3.175·10⁻³).
    fn default() -> Self {
        BifurcationParams {
            der: DerBoundaryParams {
                tol_rel: S_STAR_TOL_REL,
                ..DerBoundaryParams::default()
            },
            statics_return: true,
            return_tol_rel: RETURN_TOL_REL,
            contact_diameter: 2.0 * crate::rod::dynamics::PhysicalRod::nitinol().slenderness(),
        }
    }
}

impl BifurcationParams {
    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        self.der.validate()?;
        require_positive("return_tol_rel", self.return_tol_rel)?;
        if self.return_tol_rel >= 0.1 {
            return Err(Error::invalid(
                "return_tol_rel",
                self.return_tol_rel,
                "must be < 0.1",
            ));
        }
        require_positive("contact_diameter", self.contact_diameter)?;
        if self.contact_diameter >= 0.1 {
            return Err(Error::invalid(
                "contact_diameter",
                self.contact_diameter,
                "must be < 0.1 (units of the rod length)",
            ));
        }
        Ok(())
    }
}

/// DER resolution of the type a planner assumes ([`planning_type`]): the seed's 42 labelled
/// types all agree from n = 24 on (tests/bifurcation.rs, `docs/RESULTS.md`), at a fraction of the cost
/// of n = 100.
pub const PLANNING_N_EDGES: usize = 40;

impl BifurcationParams {
    /// The parameters of [`planning_type`]: DER n = [`PLANNING_N_EDGES`], ν = 0.33, no
    /// static return.
    pub fn planning() -> Self {
        BifurcationParams {
            der: DerBoundaryParams {
                n_edges: PLANNING_N_EDGES,
                tol_rel: S_STAR_TOL_REL,
                ..DerBoundaryParams::default()
            },
            statics_return: false,
            ..BifurcationParams::default()
        }
    }
}

/// The bifurcation type a planner assumes for `dir` when the rig's margin past s* depends on
/// it ([`crate::planning::rig::PlannerSettings::margin_for`]): [`classify`] with
/// [`BifurcationParams::planning`] (`degenerate` when undecided, never an error on a valid
/// direction).
pub fn planning_type(dir: &Direction) -> Result<BifurcationType> {
    Ok(classify(dir, &BifurcationParams::planning())?.kind)
}

/// The bifurcation of one ray.
#[derive(Debug, Clone, PartialEq)]
pub struct Bifurcation {
    /// DER s* at this resolution.
    pub s_star: Real,
    /// The type.
    pub kind: BifurcationType,
    /// Why the type is `degenerate` (empty otherwise).
    pub reason: String,
    /// The normalized post-buckling coefficient (see the module docs; > 0 supercritical).
    pub coefficient: Real,
    /// Koiter coefficient b (unit 2-norm mode).
    pub b: Real,
    /// Finite-difference error estimate of b.
    pub b_error: Real,
    /// Cubic coefficient a.
    pub a: Real,
    /// dλ/ds at s*.
    pub dlambda_ds: Real,
    /// Asymmetry ratio (see the module docs).
    pub asymmetry: Real,
    /// Where the rod returns to the helix on unloading (statics): s* for a supercritical ray,
    /// the end of the far branch for a subcritical one, NaN when not computed.
    pub s_return: Real,
    /// Resolution of `s_return` (the far branch ends in `[s_return − this, s_return]`).
    pub s_return_uncertainty: Real,
    /// The far (post-snap) branch followed down in s (empty when not computed).
    pub far_branch: Vec<unloading::BranchPoint>,
}

impl Bifurcation {
    /// `s* − s_return` (0 for supercritical; NaN when not computed).
    pub fn hysteresis(&self) -> Real {
        self.s_star - self.s_return
    }
}

/// The bifurcation type, coefficient and (optionally) the static return point of the ray
/// `dir` (see the module docs).
///
/// One hard direction never fails a sweep: whatever cannot be decided numerically on this
/// ray — s* not found or refused (resolution, extensibility, stable to `s_max`), no helical
/// equilibrium below s*, a reduction whose constrained Newton does not converge at any of
/// the amplitudes [`reduction::AMPLITUDE`]·(1, ½, ¼) — is a `degenerate` result whose
/// `reason` says what failed (`s_star` is NaN when s* itself was not found).
///
/// Errors: invalid parameters or direction only.
pub fn classify(dir: &Direction, p: &BifurcationParams) -> Result<Bifurcation> {
    p.validate()?;
    let dir = Direction::new(dir.kappa, dir.tau, dir.omega)?;
    let mut s_star = Real::NAN;
    match classify_ray(&dir, p, &mut s_star) {
        Ok(b) => Ok(b),
        Err(e) => Ok(degenerate(
            if s_star.is_nan() {
                format!("no DER s*: {e}")
            } else {
                format!("not decided: {e}")
            },
            s_star,
        )),
    }
}

/// A `degenerate` result with its reason and nothing else known but (perhaps) s* (NaN when
/// unknown): the row of a direction that could not be decided.
pub fn degenerate(reason: String, s_star: Real) -> Bifurcation {
    Bifurcation {
        s_star,
        kind: BifurcationType::Degenerate,
        reason,
        coefficient: Real::NAN,
        b: Real::NAN,
        b_error: Real::NAN,
        a: Real::NAN,
        dlambda_ds: Real::NAN,
        asymmetry: Real::NAN,
        s_return: Real::NAN,
        s_return_uncertainty: Real::NAN,
        far_branch: Vec::new(),
    }
}

/// Amplitudes tried by [`classify`], as fractions of [`reduction::AMPLITUDE`].
const AMPLITUDE_FRACTIONS: [Real; 3] = [1.0, 0.5, 0.25];
/// Relative tolerance of the continuum s* that seeds the DER search (the DER s* is then found
/// on its own; the seed only has to lie within the bracket `[0.985, 1.02]·s*`).
const SEED_S_STAR_REL: Real = 1e-6;
/// The helix equilibrium for dλ/ds is taken at least this far below s* (relative): a DER s*
/// whose error estimate is 0 still leaves a step.
const S_STAR_ERROR_FLOOR: Real = 1e-12;

/// [`classify`] on a validated direction; `s_star_out` receives s* as soon as it is known.
fn classify_ray(
    dir: &Direction,
    p: &BifurcationParams,
    s_star_out: &mut Real,
) -> Result<Bifurcation> {
    let dir = *dir;
    let der = p.der;
    let c = twist_ratio(der.nu)?;
    let mut ray = DerRay::new(&dir, &der)?;
    let crit = match crate::boundary::continuum::critical_s(&dir, SEED_S_STAR_REL) {
        Ok(cs) if der.continuum_seed && cs.s_star.is_finite() && cs.s_star < der.s_max => {
            ray.critical_s_from(0.985 * cs.s_star, 1.02)?
        }
        _ => ray.critical_s()?,
    };
    let s_star = crit.s_star;
    if !s_star.is_finite() {
        return Err(Error::invalid(
            "direction",
            format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
            format!("stable up to s_max = {}: no bifurcation", der.s_max),
        ));
    }
    *s_star_out = s_star;
    // The helix equilibrium just below s* and two more points for dλ/ds.
    let s0 = s_star - 2.0 * crit.est_error.max(S_STAR_ERROR_FLOOR * s_star);
    let free = ray.rod().free_range_clamped();
    let mut ws = Workspace::new(ray.rod());
    let mut lambdas = [0.0; 3];
    let mut base = None;
    for (k, s) in [
        s0,
        s0 * (1.0 - DLAMBDA_STEP),
        s0 * (1.0 - 2.0 * DLAMBDA_STEP),
    ]
    .into_iter()
    .enumerate()
    {
        match ray.evaluate(s) {
            Ok(_) => {}
            Err(Error::NotConverged { .. }) => {
                return Ok(degenerate(
                    format!("no helical equilibrium at s = {s:.6} (the branch ends at a fold)"),
                    s_star,
                ))
            }
            Err(e) => return Err(e),
        }
        let st = ray.state().expect("evaluated").clone();
        if k == 0 {
            base = Some(st);
        } else {
            lambdas[k] = reduction::critical_mode(ray.rod(), &st, free.clone(), &mut ws)?.lambda;
        }
    }
    let base = base.expect("evaluated");
    let mut rod = ray.rod().clone();
    rod.material.stretch = der.stretch;
    let mut red = Err(Error::invalid("amplitude", "", "no amplitude tried"));
    for f in AMPLITUDE_FRACTIONS {
        red = reduction::reduce_with_amplitude(
            &rod,
            &base,
            free.clone(),
            &mut ws,
            f * reduction::AMPLITUDE,
        );
        match &red {
            Err(Error::NotConverged { .. }) => continue,
            _ => break,
        }
    }
    let red = red?;
    lambdas[0] = red.mode.lambda;
    let ds = s0 * DLAMBDA_STEP;
    let dlambda = (3.0 * lambdas[0] - 4.0 * lambdas[1] + lambdas[2]) / (2.0 * ds);
    let m = red.mode.max_node;
    let coefficient = red.b / (6.0 * dlambda.abs() * s_star * m * m);
    // Node amplitude at 1 % past (or before) s*, in mode units.
    let x1 = (6.0 * dlambda.abs() * 0.01 * s_star / red.b.abs()).sqrt();
    let asymmetry = red.a.abs() * x1 / (red.b.abs() * x1 * x1 / 3.0);
    let mut out = Bifurcation {
        s_star,
        kind: BifurcationType::Degenerate,
        reason: String::new(),
        coefficient,
        b: red.b,
        b_error: red.b_error,
        a: red.a,
        dlambda_ds: dlambda,
        asymmetry,
        s_return: Real::NAN,
        s_return_uncertainty: Real::NAN,
        far_branch: Vec::new(),
    };
    if dlambda >= 0.0 {
        out.reason =
            format!("the critical eigenvalue does not decrease through s* (dλ/ds = {dlambda:e})");
    } else if red.b.abs() <= 3.0 * red.b_error {
        out.reason = format!(
            "Koiter coefficient b = {:e} within its finite-difference error {:e}",
            red.b, red.b_error
        );
    } else if asymmetry.is_nan() || asymmetry > ASYMMETRY_MAX {
        out.reason = format!(
            "the critical mode is not odd under the Z2 symmetry (a = {:e}, asymmetry {asymmetry:.3}): transcritical/fold",
            red.a
        );
    } else if red.b > 0.0 {
        out.kind = BifurcationType::Supercritical;
        out.s_return = s_star;
        out.s_return_uncertainty = crit.est_error;
    } else {
        out.kind = BifurcationType::Subcritical;
        if p.statics_return {
            match unloading::static_return(
                &mut ray,
                &dir,
                s_star,
                &red.mode,
                c,
                der.clamp,
                der.stretch,
                p.return_tol_rel,
                p.contact_diameter,
            ) {
                Ok(r) => {
                    if let Some((s, c)) = r.self_contact {
                        out.reason = format!(
                            "no static s_return: at s = {s:.4} the DER rod (no contact model) met itself or the rig: {c}; the real rod's return is not modelled"
                        );
                    } else if let Some((s, d)) = r.linking_change {
                        out.reason = format!(
                            "no static s_return: at s = {s:.4} the linking number of the DER rod (no contact model) changed by {d:+.2}: it passed through itself or over an end between two contact checks; the real rod's return is not modelled"
                        );
                    } else if r.at_floor {
                        out.reason = format!(
                            "no static s_return: the far branch persists down to s = {:.3e} (10⁻³·s*); impossible for a real rod (the snap changed the linking number: contact missed)",
                            r.s_return
                        );
                    } else {
                        out.s_return = r.s_return;
                        out.s_return_uncertainty = r.uncertainty;
                    }
                    out.far_branch = r.branch;
                }
                // The type stands; the return point is reported missing, with the cause.
                Err(Error::NotConverged { what, .. }) => {
                    out.reason = format!("no static s_return: {what}");
                }
                Err(e) => out.reason = format!("no static s_return: {e}"),
            }
        }
    }
    Ok(out)
}
