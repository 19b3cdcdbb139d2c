//! The numeric vocabulary of the crate: the scalar type, geometric aliases, named tolerances
//! (each with its unit) and the numerically stable elementary ratios every closed form uses.
//!
//! # Conventions
//! - All geometry is `f64` ([`Real`]) and uses nalgebra 0.34 types (the version parry is built on).
//! - Rotations are proper orthonormal 3×3 matrices ([`Mat3`]); a frame `[d1 d2 d3]` is stored with
//!   the directors as **columns**, `d3` the rod tangent.
//! - Rigid transforms are [`Iso3`] (rotation + translation).
//!
//! # Stable ratios
//! Near `x = 0` the ratios `sin x / x`, `(1 − cos x)/x²` and `(x − sin x)/x³` lose all their
//! digits to cancellation if evaluated literally. [`sinc`], [`cosc`] and [`sinc3`] switch to a
//! Taylor series below a threshold chosen so both branches are accurate to about 1 ulp·10.
//!
//! ```
//! use helixreach::math::{sinc, cosc, sinc3};
//! assert_eq!(sinc(0.0), 1.0);
//! assert!((cosc(1e-9) - 0.5).abs() < 1e-16);
//! // (x − sin x)/x³ = 1/6 − x²/120 + x⁴/5040 − …
//! assert!((sinc3(1e-3) - (1.0 / 6.0 - 1e-6 / 120.0 + 1e-12 / 5040.0)).abs() < 1e-16);
//! ```

/// The scalar type of every computation.
pub type Real = f64;
/// A 3-vector.
pub type Vec3 = nalgebra::Vector3<Real>;
/// A 3×3 matrix (rotations and frames: directors as columns).
pub type Mat3 = nalgebra::Matrix3<Real>;
/// A rigid transform.
pub type Iso3 = nalgebra::Isometry3<Real>;
/// A unit quaternion.
pub type Quat = nalgebra::UnitQuaternion<Real>;

/// Read exactly three numbers `[x, y, z]` (rig files): a TOML array of another length is an
/// error naming its length, never truncated or padded.
/// `#[serde(deserialize_with = "crate::math::exact3::deserialize")]`.
///
/// ```
/// #[derive(serde::Deserialize)]
/// struct T {
///     #[serde(deserialize_with = "helixreach::math::exact3::deserialize")]
///     v: [f64; 3],
/// }
/// assert_eq!(toml::from_str::<T>("v = [1.0, 2.0, 3.0]").unwrap().v, [1.0, 2.0, 3.0]);
/// let e = toml::from_str::<T>("v = [1.0, 2.0, 3.0, 4.0]").err().unwrap().to_string();
/// assert!(e.contains("3 numbers") && e.contains("4"), "{e}");
/// ```
pub mod exact3 {
    use super::Real;
    use serde::{Deserialize, Deserializer};
    /// Read `[x, y, z]`, refusing any other length.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[Real; 3], D::Error> {
        let v = Vec::<Real>::deserialize(d)?;
        <[Real; 3]>::try_from(v.as_slice()).map_err(|_| {
            serde::de::Error::custom(format!(
                "expected 3 numbers [x, y, z], got {} ({v:?})",
                v.len()
            ))
        })
    }
}

/// Serde for a [`Vec3`] as the array `[x, y, z]` (rig files, records):
/// `#[serde(with = "crate::math::vec3_array")]`.
pub mod vec3_array {
    use super::Vec3;
    use serde::{Deserializer, Serialize, Serializer};
    /// Write `[x, y, z]`.
    pub fn serialize<S: Serializer>(v: &Vec3, s: S) -> Result<S::Ok, S::Error> {
        [v.x, v.y, v.z].serialize(s)
    }
    /// Read `[x, y, z]`.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec3, D::Error> {
        super::exact3::deserialize(d).map(Vec3::from)
    }
}

/// One millimetre, in metres.
pub const MM: Real = 1e-3;
/// One degree, in radians.
pub const DEG: Real = std::f64::consts::PI / 180.0;

/// Named tolerances, each with its unit. Use these instead of literals.
pub mod tol {
    use super::Real;
    /// Orthonormality of a computed frame, ‖RᵀR − I‖ (dimensionless).
    pub const FRAME_ORTHONORMAL: Real = 1e-14;
    /// Default relative tolerance on a critical distance s* along a ray (dimensionless).
    pub const S_STAR_REL: Real = 1e-10;
    /// IK position tolerance (m).
    pub const IK_POSITION: Real = 1e-10;
    /// IK orientation tolerance (rad).
    pub const IK_ANGLE: Real = 1e-10;
    /// Planned-trajectory pose check, position (m).
    pub const TRAJ_POSITION: Real = 1e-6;
    /// Planned-trajectory pose check, orientation (rad).
    pub const TRAJ_ANGLE: Real = 1e-6;
    /// Two unit vectors with `|a·b ∓ 1|` below this are parallel / antiparallel (dimensionless).
    pub const PARALLEL: Real = 1e-15;
    /// An input axis or direction shorter than this is zero and refused (its unit).
    pub const ZERO_VECTOR: Real = 1e-9;
    /// A user rotation matrix is accepted when `‖RᵀR − I‖` is below this (dimensionless).
    pub const INPUT_ROTATION: Real = 1e-9;
    /// A user quaternion is accepted when `|‖q‖ − 1|` is below this (then normalized).
    pub const UNIT_QUATERNION: Real = 1e-6;
    /// Largest nondimensional distance s searched along a ray before it is declared
    /// stable everywhere (`s* = ∞`).
    pub const S_MAX: Real = 200.0;
    /// A positive floor for a magnitude that is divided by or whose logarithm is taken: at or
    /// below it the value counts as zero (far below any physical quantity of the crate, far above
    /// the subnormals, so its reciprocal is finite).
    pub const TINY: Real = 1e-300;
    /// Two unit directions (κ̂, τ̂, ω̂) whose components all differ by less than this are the
    /// same direction: the seed's files print six decimals.
    pub const DIRECTION_MATCH: Real = 1e-6;
    /// A direction given as unit is accepted when `|‖S̄‖ − 1|` is below this (what
    /// `Direction::new`'s normalization leaves is ~1e-16).
    pub const UNIT_DIRECTION: Real = 1e-12;
    /// A direction with τ̂ ≥ −this counts as on the quarter-sphere τ̂ ≥ 0 (a lattice point's τ̂ is
    /// ≥ 0 up to rounding of its normalization).
    pub const ON_QUARTER: Real = 1e-9;
    /// Two azimuths (rad) closer than this, modulo 2π, are the same azimuth (a boundary's
    /// recorded azimuth against a planned one: both print shortest round-trip).
    pub const AZIMUTH: Real = 1e-9;
}

/// Whether azimuths `a` and `b` (rad) are the same angle, to [`tol::AZIMUTH`] modulo 2π.
///
/// ```
/// use helixreach::math::same_azimuth;
/// assert!(same_azimuth(0.0, std::f64::consts::TAU));
/// assert!(same_azimuth(-1e-12, 0.0));
/// assert!(!same_azimuth(0.0, 1e-6));
/// ```
pub fn same_azimuth(a: Real, b: Real) -> bool {
    let d = (a - b).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d) <= tol::AZIMUTH
}

/// The twist ratio `c = k_t/k_b = 1/(1+ν)` of a circular cross-section, for a Poisson ratio
/// ν ∈ (−1, 0.5] (the range of isotropic elastic solids); errors otherwise, naming `nu`. The
/// one place the ratio is computed (`helix::twist_ratio` and `rod::params::twist_ratio` are
/// this function).
///
/// ```
/// assert_eq!(helixreach::math::twist_ratio(0.0).unwrap(), 1.0);
/// assert!((helixreach::math::twist_ratio(0.33).unwrap() - 1.0 / 1.33).abs() < 1e-16);
/// assert!(helixreach::math::twist_ratio(0.6).is_err());
/// assert!(helixreach::math::twist_ratio(f64::NAN).is_err());
/// ```
pub fn twist_ratio(nu: Real) -> crate::error::Result<Real> {
    use crate::error::Error;
    if !nu.is_finite() {
        return Err(Error::invalid("nu", nu, "must be finite"));
    }
    if !(nu > -1.0 && nu <= 0.5) {
        return Err(Error::invalid(
            "nu",
            nu,
            "Poisson's ratio must lie in (-1, 0.5]",
        ));
    }
    Ok(twist_ratio_unchecked(nu))
}

/// The formula of [`twist_ratio`] alone, for a ν its record already validated (a rig's rod).
#[inline]
pub fn twist_ratio_unchecked(nu: Real) -> Real {
    1.0 / (1.0 + nu)
}

/// `P_{a→b}(d)`: the parallel transport of `d` from the unit vector `a` to the unit vector `b`,
/// i.e. `d` rotated by the minimal rotation taking `a` to `b`. The one parallel transport of the
/// crate (discrete helices, DER reference frames and reference twist).
///
/// - `a·b > −0.9`: Rodrigues about `k = a×b`, `P(d) = (a·b) d + k×d + (k·d)/(1 + a·b) k`, smooth
///   through `a = b` (no division by `|a×b|`).
/// - `a·b ≤ −0.9`: two reflections, through the plane ⊥ `a` and the plane ⊥ `h = a + b`
///   (`S_h S_a` is the minimal rotation and has no `1/(1 + a·b)`).
/// - exactly antiparallel (`h = 0`): no unique transport; the rotation by π about the component
///   of `fallback_axis` perpendicular to `a` (or, if that vanishes, a fixed perpendicular).
///
/// ```
/// use helixreach::math::{parallel_transport, Vec3};
/// let (a, b) = (Vec3::z(), Vec3::x());
/// assert!((parallel_transport(&Vec3::x(), &a, &b, &Vec3::x()) + Vec3::z()).norm() < 1e-15);
/// assert!((parallel_transport(&Vec3::y(), &a, &b, &Vec3::x()) - Vec3::y()).norm() < 1e-15);
/// // Antiparallel: a rotation by π about the fallback axis x.
/// let d = parallel_transport(&Vec3::y(), &a, &-a, &Vec3::x());
/// assert!((d + Vec3::y()).norm() < 1e-15);
/// ```
#[inline]
pub fn parallel_transport(d: &Vec3, a: &Vec3, b: &Vec3, fallback_axis: &Vec3) -> Vec3 {
    let c = a.dot(b);
    if c > -0.9 {
        let k = a.cross(b);
        c * d + k.cross(d) + (k.dot(d) / (1.0 + c)) * k
    } else {
        let h = a + b;
        let hh = h.norm_squared();
        if hh > tol::TINY {
            // S_h S_a d, reflections through the planes ⊥ a and ⊥ h.
            let d1 = d - 2.0 * a.dot(d) * a;
            d1 - (2.0 * h.dot(&d1) / hh) * h
        } else {
            let mut u = fallback_axis - a.dot(fallback_axis) * a;
            // |u|² below this: the fallback axis is (nearly) parallel to a and gives no
            // direction; a fixed perpendicular is used instead.
            const PARALLEL_FALLBACK_SQ: Real = 1e-12;
            if u.norm_squared() < PARALLEL_FALLBACK_SQ {
                let e = if a.x.abs() < 0.6 {
                    Vec3::x()
                } else {
                    Vec3::y()
                };
                u = e - a.dot(&e) * a;
            }
            let u = u.normalize();
            // Rotation by π about u: d ↦ 2(u·d)u − d.
            2.0 * u.dot(d) * u - d
        }
    }
}

/// Below this |x|, [`sinc`] and [`cosc`] use their Taylor series (truncated after x⁶: the
/// remainder is below x⁸/9! ≈ 3e-30 relative, far under one ulp).
const TAYLOR_BELOW: Real = 1e-3;

/// `sin x / x`, accurate near 0.
#[inline]
pub fn sinc(x: Real) -> Real {
    if x.abs() < TAYLOR_BELOW {
        let x2 = x * x;
        1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0))
    } else {
        x.sin() / x
    }
}

/// `(1 − cos x) / x²`, accurate near 0.
#[inline]
pub fn cosc(x: Real) -> Real {
    if x.abs() < TAYLOR_BELOW {
        let x2 = x * x;
        0.5 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0)))
    } else {
        // 1 − cos x = 2 sin²(x/2): no cancellation for moderate x.
        let h = (0.5 * x).sin();
        2.0 * h * h / (x * x)
    }
}

/// `(x − sin x) / x³`, accurate near 0.
#[inline]
pub fn sinc3(x: Real) -> Real {
    // The literal form loses ≈ 6·ε/x² relatively to cancellation, so the series is used up to
    // |x| = 1.5, where 14 terms still reach 1e-17 relative (1.5^28 / 31! ≈ 1e-26).
    if x.abs() < 1.5 {
        // Series: Σ (−1)^k x^{2k} / (2k+3)!.
        let x2 = x * x;
        let mut term = 1.0 / 6.0;
        let mut sum = term;
        for k in 1..14 {
            let kf = k as Real;
            term *= -x2 / ((2.0 * kf + 2.0) * (2.0 * kf + 3.0));
            sum += term;
        }
        sum
    } else {
        (x - x.sin()) / (x * x * x)
    }
}

/// The skew-symmetric matrix `[v]×` with `[v]× u = v × u`.
#[inline]
pub fn hat(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Rotation about the z axis by `a` radians.
#[inline]
pub fn rot_z(a: Real) -> Mat3 {
    let (s, c) = a.sin_cos();
    Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// SO(3) exponential (Rodrigues) of the rotation vector `phi`, stable near 0.
#[inline]
pub fn so3_exp(phi: &Vec3) -> Mat3 {
    let th = phi.norm();
    let k = hat(phi);
    Mat3::identity() + sinc(th) * k + cosc(th) * (k * k)
}

/// SO(3) left Jacobian `V(φ) = I + (1−cos θ)/θ²·[φ]× + (θ−sin θ)/θ³·[φ]×²`, stable near 0.
#[inline]
pub fn so3_left_jacobian(phi: &Vec3) -> Mat3 {
    let th = phi.norm();
    let k = hat(phi);
    Mat3::identity() + cosc(th) * k + sinc3(th) * (k * k)
}

/// Rotation angle of `R` in [0, π], robust near 0 and π (uses both the trace and the skew part).
#[inline]
pub fn rotation_angle(r: &Mat3) -> Real {
    let (s, c) = rotation_sin_cos(r);
    s.atan2(c)
}

/// Sine and cosine of the rotation angle θ of `R`: |skew part| and (tr R − 1)/2, so that
/// θ = atan2(s, c) ([`rotation_angle`]); for comparisons of θ without the arctangent.
#[inline]
pub fn rotation_sin_cos(r: &Mat3) -> (Real, Real) {
    let s = 0.5
        * Vec3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        )
        .norm();
    (s, 0.5 * (r.trace() - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Compare each ratio's series branch with a high-precision evaluation by the
    /// alternating series summed to convergence (an independent formula).
    fn series(x: f64, first_den: u32) -> f64 {
        // Σ_k (−1)^k x^{2k} / (2k+first_den)!
        let mut fact = (1..=first_den).map(f64::from).product::<f64>();
        let mut sum = 0.0;
        let mut p = 1.0;
        for k in 0..40u32 {
            let t = p / fact;
            sum += if k % 2 == 0 { t } else { -t };
            p *= x * x;
            let n = 2 * k + first_den;
            fact *= f64::from(n + 1) * f64::from(n + 2);
        }
        sum
    }

    #[test]
    fn ratios_match_series_across_the_switch() {
        for &x in &[
            1e-12, 1e-6, 9.9e-4, 1.01e-3, 0.05, 0.099, 0.101, 0.5, 1.0, 1.49, 1.51, 2.0,
        ] {
            assert!((sinc(x) - series(x, 1)).abs() < 2e-16, "sinc {x}");
            assert!((cosc(x) - series(x, 2)).abs() < 2e-16, "cosc {x}");
            assert!((sinc3(x) - series(x, 3)).abs() < 2e-16, "sinc3 {x}");
        }
    }

    #[test]
    fn exp_is_orthonormal_and_angle_roundtrips() {
        for &a in &[1e-9, 0.3, 3.0, std::f64::consts::PI - 1e-7] {
            let phi = Vec3::new(1.0, -2.0, 0.5).normalize() * a;
            let r = so3_exp(&phi);
            assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-14);
            assert!((rotation_angle(&r) - a).abs() < 1e-12 * a.max(1.0));
        }
    }
}
