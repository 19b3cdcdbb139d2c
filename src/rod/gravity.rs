//! When gravity matters for a rod: the gravito-bending length and what it says
//! (`helixreach rod`).
//!
//! The gravito-bending length `L_gb = (h²E/(8ρg))^{1/3}` (the seed paper §III.D, after Jawed et
//! al. 2014; h the cross-section **radius** as the formula is written,
//! [`PhysicalRod::gravito_bending_length`]) compares bending stiffness with weight: the
//! nondimensional weight per unit length is `ρAgL³/k_b = ½(L/L_gb)³`. The seed paper read
//! "gravity becomes negligible when `L_gb/L > 0.6`" ([`SEED_LGB_THRESHOLD`]) off its Fig. 5(c):
//! the helix-error curves of DER dynamics runs along the one direction S̄ = [1, 1, 1]/√3 with the
//! `paper-sim` rod, g varied so that `L_gb/L ∈ {0.2, …, 1.4}`, judged by eye (no tolerance
//! stated, one direction, the clamp orientation not stated). Its own rod's 1.3816 is
//! reproduced only with the diameter in place of h ([`assess`] reports both).
//!
//! helixreach's own measurement (`docs/RESULTS.md`, "Gravity"): DER dynamics along the same
//! direction, rod up (gravity along −d3), n = 30, ray speed 0.01/s, with the s_dyn of the
//! gravity-free run as the reference. A gravity-free run has no imperfection and is delayed
//! past s* by inertia until round-off seeds the critical mode, while gravity seeds it at once,
//! so the dynamic shift overstates the static one. Measured shifts of s_dyn (gravity-free
//! 10.80, resolution 0.01): −0.65 % at `L_gb/L` = 3, −1.02 % at 2 (and more below, see
//! `docs/RESULTS.md`); [`MEASURED_LGB_THRESHOLD`] = 2.1 is the 1 % crossing interpolated
//! between them, rounded up.
//!
//! The static measurement (DER statics with the weight,
//! [`critical_s_gravity`](crate::boundary::der::critical_s_gravity), n = 40, `docs/RESULTS.md`):
//! on the seed's three directions, rod up and rod horizontal, gravity moves s* by 1 % at
//! `L_gb/L` ≈ 1.1 at most (0.41–1.10 by direction and clamp); on the supercritical
//! (1, 1, 1)/√3 any weight moves s* by ≈ +0.4 %, since its s* with gravity is the fold of the
//! buckled branch.

use crate::error::Result;
use crate::math::Real;
use crate::rod::dynamics::PhysicalRod;

/// The seed paper's criterion: gravity negligible when `L_gb/L` is above this (module docs).
pub const SEED_LGB_THRESHOLD: Real = 0.6;

/// helixreach's measured criterion (module docs): along S̄ = [1, 1, 1]/√3, rod up, the DER
/// dynamics instability moves by less than 1 % for `L_gb/L` above this ratio.
pub const MEASURED_LGB_THRESHOLD: Real = 2.1;

/// What the gravito-bending length of a rod says (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GravityAssessment {
    /// Gravity used (m/s²).
    pub gravity: Real,
    /// `L_gb` (m), with the radius as the formula is written.
    pub lgb: Real,
    /// `L_gb/L`.
    pub lgb_over_l: Real,
    /// `L_gb/L` with the diameter in place of the radius (the convention that reproduces the
    /// seed paper's 1.3816 for its nitinol rod).
    pub lgb_over_l_with_diameter: Real,
    /// The nondimensional weight per unit length `ρAgL³/k_b = ½(L/L_gb)³`.
    pub weight_per_length: Real,
    /// [`SEED_LGB_THRESHOLD`].
    pub seed_threshold: Real,
    /// [`MEASURED_LGB_THRESHOLD`].
    pub measured_threshold: Real,
    /// `L_gb/L` ≥ the measured threshold.
    pub negligible: bool,
}

/// Assess `rod` under gravity `g` (m/s², > 0).
///
/// ```
/// use helixreach::rod::dynamics::PhysicalRod;
/// use helixreach::rod::gravity::assess;
/// let a = assess(&PhysicalRod::nitinol(), 9.81).unwrap();
/// assert!((a.lgb_over_l_with_diameter - 1.3816).abs() < 0.015);
/// assert!((a.weight_per_length - 0.5 / a.lgb_over_l.powi(3)).abs() < 1e-12);
/// ```
pub fn assess(rod: &PhysicalRod, g: Real) -> Result<GravityAssessment> {
    let lgb = rod.gravito_bending_length(g)?;
    let with_d = PhysicalRod {
        radius: 2.0 * rod.radius,
        ..*rod
    };
    let ratio = lgb / rod.length;
    Ok(GravityAssessment {
        gravity: g,
        lgb,
        lgb_over_l: ratio,
        lgb_over_l_with_diameter: with_d.gravito_bending_length(g)? / rod.length,
        weight_per_length: rod.linear_density() * g * rod.length.powi(3) / rod.bending_stiffness(),
        seed_threshold: SEED_LGB_THRESHOLD,
        measured_threshold: MEASURED_LGB_THRESHOLD,
        negligible: ratio >= MEASURED_LGB_THRESHOLD,
    })
}

/// The static criterion (`docs/RESULTS.md`, "gravity, DER statics"): above this `L_gb/L`,
/// gravity moves s* by less than 1 % on the seed's three directions, rod up or horizontal (the
/// largest of the six crossings: 1.10 on (1, 1, −1) horizontal).
pub const STATIC_LGB_THRESHOLD: Real = 1.1;

/// The estimated relative shift of s* by gravity at `L_gb/L = ratio` on a snapping direction:
/// 1 % at [`STATIC_LGB_THRESHOLD`], scaled by Koiter's two-thirds law — the weight is an
/// imperfection, `|Δs*|/s* ∝ g^{2/3}`, and the nondimensional weight `½(L/L_gb)³` is linear in
/// g, so `|Δs*|/s* ≈ 0.01·(1.1/ratio)²`. It holds while the loaded branch stays the one that
/// snaps: below [`SEED_LGB_THRESHOLD`] the statics show s* jumping to another branch
/// ((1, 1, 1) horizontal: s* ≈ 22 instead of 10.75), so no estimate is given there.
///
/// ```
/// use helixreach::rod::gravity::estimated_shift;
/// assert!((estimated_shift(1.1) - 0.01).abs() < 1e-15);
/// assert!((estimated_shift(0.55) - 0.04).abs() < 1e-15);
/// ```
pub fn estimated_shift(ratio: Real) -> Real {
    0.01 * (STATIC_LGB_THRESHOLD / ratio).powi(2)
}

/// How a planning command (`reach`, `plan`, `layout`, `campaign`) accounts for gravity: it
/// plans to s*·(1 + margin), so a gravity-free s* serves as long as gravity moves the true s*
/// by less than the margin. The threshold is the seed paper's [`SEED_LGB_THRESHOLD`]: above
/// it the statics move s* by at most ≈ 3.4 % on snapping directions (the
/// [`estimated_shift`] at 0.6) and stay on the snapping branch; below it the commands need a
/// boundary computed with gravity.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "gravity", rename_all = "snake_case")]
pub enum PlanningGravity {
    /// `L_gb/L ≥` [`STATIC_LGB_THRESHOLD`]: gravity moves s* by less than 1 %; the gravity-free
    /// boundary is used.
    Negligible {
        /// `L_gb/L` of the rod.
        lgb_over_l: Real,
    },
    /// [`SEED_LGB_THRESHOLD`] `≤ L_gb/L <` [`STATIC_LGB_THRESHOLD`]: the gravity-free boundary
    /// is used, gravity moving s* by about the [`estimated_shift`]. Within the margin the plan
    /// still passes the snap; past it ([`PlanningGravity::beyond_margin`]) the commands warn
    /// that a plan may stop short of the snap by the difference.
    Estimated {
        /// `L_gb/L` of the rod.
        lgb_over_l: Real,
        /// [`estimated_shift`] (relative).
        shift: Real,
        /// The smallest planning margin of the rig.
        margin: Real,
    },
    /// The boundary was computed with gravity (`boundary --method der --gravity`) at these
    /// azimuths (one file each), which cover every azimuth the command plans at: a ray planned
    /// at an azimuth is planned to that azimuth's s*.
    Included {
        /// Gravity of the boundary (m/s²).
        g: Real,
        /// Its azimuths (rad), one per boundary file.
        azimuths: Vec<Real>,
    },
}

impl PlanningGravity {
    /// Whether gravity may move s* past the margin planned to (a plan on the gravity-free
    /// boundary may then stop short of the snap).
    pub fn beyond_margin(&self) -> bool {
        matches!(*self, PlanningGravity::Estimated { shift, margin, .. } if shift > margin)
    }
}

impl std::fmt::Display for PlanningGravity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            PlanningGravity::Negligible { lgb_over_l } => write!(
                f,
                "L_gb/L = {lgb_over_l:.3} >= {STATIC_LGB_THRESHOLD}: gravity moves s* by < 1 %; \
                 gravity-free boundary"
            ),
            PlanningGravity::Estimated {
                lgb_over_l,
                shift,
                margin,
            } if shift <= margin => write!(
                f,
                "L_gb/L = {lgb_over_l:.3}: gravity moves s* by about {:.1} %, within the margin \
                 {:.1} %; gravity-free boundary",
                100.0 * shift,
                100.0 * margin
            ),
            PlanningGravity::Estimated {
                lgb_over_l,
                shift,
                margin,
            } => write!(
                f,
                "L_gb/L = {lgb_over_l:.3}: gravity moves s* by about {:.1} %, more than the \
                 margin {:.1} %: with the gravity-free boundary a plan may stop short of the \
                 snap by up to {:.1} % (for the boundary with gravity: `helixreach boundary \
                 --method der --gravity`, then `--boundary`)",
                100.0 * shift,
                100.0 * margin,
                100.0 * (shift - margin)
            ),
            PlanningGravity::Included { g, ref azimuths } => {
                let list: Vec<String> = azimuths.iter().map(|a| a.to_string()).collect();
                let (s, each) = if azimuths.len() == 1 {
                    ("", "")
                } else {
                    ("s", ", each ray at each azimuth planned to its own s*")
                };
                write!(
                    f,
                    "boundary computed with gravity g = {g} m/s² at azimuth{s} {} rad{each}",
                    list.join(", ")
                )
            }
        }
    }
}

/// Decide how a planning command on `rod` (the rig `rig`'s, for messages) with the smallest
/// margin `margin` accounts for gravity ([`PlanningGravity`]). `boundary_gravity`: the
/// `(g, azimuth)` of each boundary file computed with gravity, if any are given (a boundary
/// with gravity holds for its own azimuth only); `azimuths`: the azimuths the command plans at.
///
/// Errors (naming the rod's ratio and the way out) when `L_gb/L` is below
/// [`SEED_LGB_THRESHOLD`] — where the [`estimated_shift`] is not trusted, gravity can move s*
/// to another branch — and no boundary with gravity is given, or when an azimuth planned at
/// has no boundary with gravity.
pub fn planning_gravity(
    rod: &PhysicalRod,
    rig: &str,
    margin: Real,
    boundary_gravity: &[(Real, Real)],
    azimuths: &[Real],
) -> Result<PlanningGravity> {
    if let Some(&(g, _)) = boundary_gravity.first() {
        let have: Vec<Real> = boundary_gravity.iter().map(|&(_, a)| a).collect();
        let covered = |a: Real| have.iter().any(|&b| crate::math::same_azimuth(a, b));
        if let Some(a) = azimuths.iter().find(|&&a| !covered(a)) {
            let list: Vec<String> = have.iter().map(|a| a.to_string()).collect();
            return Err(crate::Error::invalid(
                "azimuth",
                a,
                format!(
                    "the boundary was computed with gravity at azimuth {} rad, and gravity \
                     makes s* depend on the azimuth: plan at those azimuths only (--azimuths 1 \
                     plans at 0; or a rig with azimuth.choices), or compute the boundary at \
                     this azimuth too (`helixreach boundary --method der --gravity --azimuth \
                     {a}`) and give each file its own --boundary (`reach`)",
                    list.join(", ")
                ),
            ));
        }
        return Ok(PlanningGravity::Included { g, azimuths: have });
    }
    let ratio = assess(rod, crate::rod::dynamics::presets::STANDARD_GRAVITY)?.lgb_over_l;
    if ratio >= STATIC_LGB_THRESHOLD {
        return Ok(PlanningGravity::Negligible { lgb_over_l: ratio });
    }
    if ratio >= SEED_LGB_THRESHOLD {
        return Ok(PlanningGravity::Estimated {
            lgb_over_l: ratio,
            shift: estimated_shift(ratio),
            margin,
        });
    }
    let why = format!(
        "is below {SEED_LGB_THRESHOLD}, where gravity can move s* to another branch \
         (`helixreach rod --rig {rig}`)"
    );
    Err(crate::Error::invalid(
        format!("rod of rig {rig}: L_gb/L"),
        format!("{ratio:.3}"),
        format!(
            "{why}: the gravity-free boundary would not do. Compute the boundary with gravity, \
             `helixreach boundary --method der --gravity --rig {rig} --azimuth A <directions> \
             --out b.csv`, and pass `--boundary b.csv` (`plan`: `--s-star`), planning at that \
             azimuth"
        ),
    ))
}
