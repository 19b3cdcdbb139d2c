//! Exact helix geometry ([architecture §2](crate::architecture)): the centerline, the Frenet, parallel-transport (Bishop)
//! and material frames at any arc length, the end pose the robot and motor must impose, a
//! discrete helix with discrete parallel transport, and the paper's helix error metric.
//!
//! # The helix as the orbit of a constant screw
//! A helix (κ, τ, ω) is nondimensional (rod length L = 1, arc length s ∈ [0, 1]). In the Frenet
//! frame F = [N B T] the Darboux vector is constant, **w = (0, κ, τ)**, and the Frenet–Serret
//! equations read F′ = F·ŵ (ŵ = \[w\]×). With the clamp frame chosen so that F(0) = I
//! (origin at the clamped end, x = N₀, y = B₀, z = T₀, see [`crate::math`] for the matrix
//! conventions):
//!
//! - Frenet frame: F(s) = exp(s·ŵ) (Rodrigues, [`so3_exp`](crate::math::so3_exp)).
//! - Centerline: r(s) = ∫₀ˢ F(u)·e₃ du = s·V(s·w)·e₃ with V the SO(3) left Jacobian
//!   ([`so3_left_jacobian`](crate::math::so3_left_jacobian)). With θ = λs, λ = √(κ²+τ²):
//!
//!   r(s) = ( κ s²·(1−cos θ)/θ²,  κτ s³·(θ−sin θ)/θ³,  s − κ² s³·(θ−sin θ)/θ³ ).
//!
//!   At s = 1 this is [architecture §2](crate::architecture)'s r(1) (the seed paper's printed formula is garbled).
//! - Parallel-transport (Bishop) frame Q = [d1 d2 d3]: Q(s) = F(s)·Rz(−τ s). Its angular
//!   velocity in the body, Rz(τs)·w = κ(−sin τs, cos τs, 0), has no tangent component, which is
//!   the definition of parallel transport; Q(0) = I.
//! - Material frame: M(s) = Q(s)·Rz((ω/c)·s), with c = k_t/k_b = 1/(1+ν) (a uniform twist rate
//!   ω/c relative to the Bishop frame). At the end, M(1) = exp(ŵ)·Rz(ω/c − τ) and the motor
//!   angle is ω/c ([`EndPose`]).
//!
//! # Numerics
//! Every closed form goes through the stable ratios sin θ/θ, (1−cos θ)/θ², (θ−sin θ)/θ³ (the
//! fused [`kernel::screw_ratios`], checked against [`crate::math`]'s `sinc`, `cosc`, `sinc3`),
//! which switch to Taylor series below |θ| = 1.5; there is no branch on κ = 0 or τ = 0. Angles
//! go through [`kernel::sin_cos`] (one shared argument reduction), so an end pose costs three
//! sine–cosine pairs and one division (≈ 70 ns of CPU, `cargo bench --bench helix`).
//! κ = 0 (a straight, twisted rod), τ = 0 (a planar arc) and λ → 0 are ordinary points, with
//! componentwise relative accuracy near λ → 0. Near λ = 2πk the results are accurate to a few
//! ulps in norm (absolute for frame entries, relative to L for positions); individual entries
//! that vanish there, such as sin λ, carry the absolute error of λ itself (≈ 1 ulp of 2πk).
//! Parameters are limited to |κ|, |τ|, |ω| ≤ [`MAX_PARAM`]: beyond it an angle λ carries fewer
//! than ten correct digits.
//!
//! # Map
//! - [`Helix`]: the parameters and the centerline ([`Helix::position`]);
//! - `frames`: [`Helix::frenet_frame`], [`Helix::transported_frame`], [`Helix::material_frame`];
//! - [`end_pose`]: [`EndPose`] and [`Helix::end_pose`] (what the robot and motor impose);
//! - [`discrete`]: nodes, edge tangents and discrete parallel transport;
//! - [`error_metric`]: the paper's error e and its safe form.
//!
//! ```
//! use helixreach::helix::Helix;
//! let h = Helix::new(2.0, 1.0, 0.5).unwrap();
//! let p = h.end_pose(1.0, 0.33).unwrap();
//! // The end tangent (third column) is a unit vector and equals dr/ds at s = 1.
//! let d = 1e-6;
//! let fd = (h.position(1.0 + d) - h.position(1.0 - d)) / (2.0 * d);
//! assert!((fd - p.material.column(2)).norm() < 1e-8);
//! assert!((p.motor_angle - 0.5 * 1.33).abs() < 1e-15);
//! ```

pub mod discrete;
pub mod end_pose;
pub mod error_metric;
mod frames;
pub mod kernel;

pub use end_pose::EndPose;

use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3};

/// Largest accepted |κ|, |τ|, |ω| (nondimensional). At λ = 10⁶ one ulp of λ is 1.2·10⁻¹⁰ rad,
/// so the end angle carries about ten correct digits; beyond it the pose is noise.
pub const MAX_PARAM: Real = 1e6;

/// Default Poisson ratio ν (nitinol, as in the seed paper); c = 1/(1+ν).
pub const DEFAULT_NU: Real = 0.33;

/// A helical rod shape (κ, τ, ω), nondimensional (L = 1).
///
/// Constructed by [`Helix::new`], which validates the parameters; the fields are read through
/// accessors so that a `Helix` is always valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    kappa: Real,
    tau: Real,
    omega: Real,
    lambda: Real,
}

impl Helix {
    /// A helix with curvature `kappa` ≥ 0, torsion `tau` and twisting moment `omega`
    /// (nondimensional, L = 1). Errors ([`Error::InvalidParameter`] naming the field) on NaN or
    /// ±∞, on κ < 0, and on any |value| > [`MAX_PARAM`].
    ///
    /// ```
    /// use helixreach::helix::Helix;
    /// assert!(Helix::new(1.0, -2.0, 3.0).is_ok());
    /// assert!(Helix::new(-1.0, 0.0, 0.0).is_err());
    /// assert!(Helix::new(1.0, f64::NAN, 0.0).is_err());
    /// ```
    pub fn new(kappa: Real, tau: Real, omega: Real) -> Result<Self> {
        for (field, v) in [("kappa", kappa), ("tau", tau), ("omega", omega)] {
            if !v.is_finite() {
                return Err(Error::invalid(field, v, "must be finite"));
            }
            if v.abs() > MAX_PARAM {
                return Err(Error::invalid(
                    field,
                    v,
                    format!("|{field}| must be <= {MAX_PARAM:e} (nondimensional, L = 1)"),
                ));
            }
        }
        if kappa < 0.0 {
            return Err(Error::invalid(
                "kappa",
                kappa,
                "must be >= 0 (curvature is non-negative; rotate the clamp frame instead)",
            ));
        }
        // `+ 0.0` turns a −0.0 curvature into +0.0.
        let kappa = kappa + 0.0;
        Ok(Helix {
            kappa,
            tau,
            omega,
            lambda: kappa.hypot(tau),
        })
    }

    /// The helix s·S̄ at distance `s` ≥ 0 along the ray of the direction `dir` (the experiment's
    /// path through parameter space). Errors as [`Helix::new`], and on negative or non-finite `s`.
    ///
    /// ```
    /// use helixreach::{directions::Direction, helix::Helix};
    /// let d = Direction::new(1.0, 1.0, 1.0).unwrap();
    /// let h = Helix::on_ray(&d, 3.0_f64.sqrt()).unwrap();
    /// assert!((h.kappa() - 1.0).abs() < 1e-15 && (h.omega() - 1.0).abs() < 1e-15);
    /// ```
    pub fn on_ray(dir: &crate::directions::Direction, s: Real) -> Result<Self> {
        if !(s.is_finite() && s >= 0.0) {
            return Err(Error::invalid(
                "s",
                s,
                "distance along the ray must be finite and >= 0",
            ));
        }
        let [k, t, w] = dir.at(s);
        Helix::new(k, t, w)
    }

    /// Curvature κ ≥ 0.
    #[inline]
    pub fn kappa(&self) -> Real {
        self.kappa
    }

    /// Torsion τ.
    #[inline]
    pub fn tau(&self) -> Real {
        self.tau
    }

    /// Twisting moment ω (divided by the bending stiffness, times L).
    #[inline]
    pub fn omega(&self) -> Real {
        self.omega
    }

    /// λ = √(κ² + τ²), the rotation rate of the Frenet frame (rad per unit s).
    #[inline]
    pub fn lambda(&self) -> Real {
        self.lambda
    }

    /// The Darboux vector w = (0, κ, τ) in the Frenet frame [N B T].
    #[inline]
    pub fn darboux(&self) -> Vec3 {
        Vec3::new(0.0, self.kappa, self.tau)
    }

    /// The mirror image (κ, −τ, −ω): the reflection y → −y of the clamp frame maps this helix's
    /// centerline onto the mirror's, with the same stability ([architecture §1](crate::architecture)).
    pub fn mirror(&self) -> Helix {
        Helix {
            tau: -self.tau,
            omega: -self.omega,
            ..*self
        }
    }

    /// The centerline r(s) in the clamp frame (nondimensional; multiply by L for metres).
    /// Any finite `s` is allowed (s ∈ [0, 1] is the rod).
    ///
    /// ```
    /// use helixreach::helix::Helix;
    /// // A planar arc (τ = 0) of curvature π ends at a half circle: r(1) = (2/π, 0, 0).
    /// let h = Helix::new(std::f64::consts::PI, 0.0, 0.0).unwrap();
    /// let r = h.position(1.0);
    /// assert!((r.x - 2.0 / std::f64::consts::PI).abs() < 1e-15 && r.z.abs() < 1e-15);
    /// ```
    #[inline]
    pub fn position(&self, s: Real) -> Vec3 {
        let (k, t) = (self.kappa, self.tau);
        let [_, b, d] = kernel::screw_ratios(self.lambda * s);
        let s2 = s * s;
        let (b, d) = (b * s2, d * s2 * s);
        Vec3::new(k * b, k * t * d, s - k * k * d)
    }

    /// The Frenet frame and the centerline at `s` together (one evaluation of the ratios).
    ///
    /// F = I + a·ŵ + b·ŵ² with a = sin θ/θ·s, b = (1−cos θ)/θ²·s², θ = λs, written out with
    /// ŵ² = w wᵀ − λ² I, so no matrix product is formed.
    #[inline]
    pub fn frenet_and_position(&self, s: Real) -> (Mat3, Vec3) {
        let (k, t) = (self.kappa, self.tau);
        let [a, b, d] = kernel::screw_ratios(self.lambda * s);
        let s2 = s * s;
        let (a, b, d) = (a * s, b * s2, d * s2 * s);
        let (bkk, btt, bkt) = (b * k * k, b * t * t, b * k * t);
        #[rustfmt::skip]
        let f = Mat3::new(
            1.0 - (bkk + btt), -a * t,     a * k,
            a * t,             1.0 - btt,  bkt,
            -a * k,            bkt,        1.0 - bkk,
        );
        (f, Vec3::new(k * b, k * t * d, s - k * k * d))
    }
}

/// The twist ratio c = 1/(1+ν) ([`crate::math::twist_ratio`], re-exported here).
///
/// ```
/// assert_eq!(helixreach::helix::twist_ratio(0.0).unwrap(), 1.0);
/// assert!(helixreach::helix::twist_ratio(0.6).is_err());
/// ```
pub use crate::math::twist_ratio;
