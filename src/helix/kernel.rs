//! Fused scalar kernels of the end pose (the hot path of planning and sweeps).
//!
//! - [`sin_cos`]: sine and cosine with one shared argument reduction (Cody–Waite with a 33-bit
//!   head of π/2, exact for |x| < 2²⁰·π/2 ≈ 1.6·10⁶) and the fdlibm minimax kernels on
//!   [−π/4, π/4] (errors below 1 ulp there). Larger arguments fall back to the standard
//!   library. `f64::sin_cos` calls `sin` and `cos` separately, so this halves the work.
//! - [`screw_ratios`]: sin θ/θ, (1−cos θ)/θ², (θ−sin θ)/θ³ together: Taylor series (Horner, no
//!   division) for |θ| < 1.5 — where the literal forms cancel — else one [`sin_cos`] of θ/2
//!   (sin θ = 2 sin(θ/2) cos(θ/2), 1 − cos θ = 2 sin²(θ/2), so nothing cancels).
//!
//! tests (below) compare both with `std` and with [`crate::math`]'s independent
//! implementations.

use crate::math::Real;

// fdlibm k_sin.c / k_cos.c minimax coefficients (|error| < 2⁻⁵⁸ on [−π/4, π/4]), given by
// their bit patterns as in fdlibm.
const S1: Real = Real::from_bits(0xBFC5_5555_5555_5549); // -0.16666666666666632
const S2: Real = Real::from_bits(0x3F81_1111_1110_F8A6); // 0.00833333333332249
const S3: Real = Real::from_bits(0xBF2A_01A0_19C1_61D5); // -0.0001984126982985795
const S4: Real = Real::from_bits(0x3EC7_1DE3_57B1_FE7D); // 2.7557313707070068e-06
const S5: Real = Real::from_bits(0xBE5A_E5E6_8A2B_9CEB); // -2.5050760253406863e-08
const S6: Real = Real::from_bits(0x3DE5_D93A_5ACF_D57C); // 1.58969099521155e-10
const C1: Real = Real::from_bits(0x3FA5_5555_5555_554C); // 0.0416666666666666
const C2: Real = Real::from_bits(0xBF56_C16C_16C1_5177); // -0.001388888888887411
const C3: Real = Real::from_bits(0x3EFA_01A0_19CB_1590); // 2.480158728947673e-05
const C4: Real = Real::from_bits(0xBE92_7E4F_809C_52AD); // -2.7557314351390663e-07
const C5: Real = Real::from_bits(0x3E21_EE9E_BDB4_B1C4); // 2.087572321298175e-09
const C6: Real = Real::from_bits(0xBDA8_FAE9_BE88_38D4); // -1.1359647557788195e-11
/// 2/π.
const INV_PIO2: Real = Real::from_bits(0x3FE4_5F30_6DC9_C883); // 0.6366197723675814
/// First 33 bits of π/2 (k·PIO2_1 is exact for |k| < 2²⁰).
const PIO2_1: Real = Real::from_bits(0x3FF9_21FB_5440_0000); // 1.5707963267341256
/// π/2 − PIO2_1.
const PIO2_1T: Real = Real::from_bits(0x3DD0_B461_1A62_6331); // 6.077100506506192e-11
/// 1.5·2⁵²: adding and subtracting it rounds |y| < 2⁵¹ to the nearest integer.
const ROUND_MAGIC: Real = 6_755_399_441_055_744.0;
/// Arguments beyond this use `f64::sin_cos` (the reduction above needs |k| < 2²⁰).
const REDUCE_MAX: Real = 1.0e6;

#[inline(always)]
fn k_sin(x: Real) -> Real {
    let z = x * x;
    let v = z * x;
    let r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    x + v * (S1 + z * r)
}

#[inline(always)]
fn k_cos(x: Real) -> Real {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * r)
}

/// `(sin x, cos x)` with one argument reduction; about 1 ulp (see the module docs).
#[inline]
pub fn sin_cos(x: Real) -> (Real, Real) {
    if x.abs() > REDUCE_MAX || !x.is_finite() {
        return x.sin_cos();
    }
    // Round to nearest with the 1.5·2⁵² trick (`f64::round` is a libm call on baseline x86-64).
    let k = (x * INV_PIO2 + ROUND_MAGIC) - ROUND_MAGIC;
    let r = (x - k * PIO2_1) - k * PIO2_1T;
    let (s, c) = (k_sin(r), k_cos(r));
    // Quadrant selection without branches (random angles would mispredict them).
    let q = k as i64;
    let odd = q & 1 != 0;
    let (s1, c1) = (if odd { c } else { s }, if odd { -s } else { c });
    let flip = if q & 2 != 0 { -1.0 } else { 1.0 };
    (flip * s1, flip * c1)
}

/// `Σ_{j<13} (−1)^j x^{2j} / (2j + start)!` coefficients.
const fn series_coeffs(start: u32) -> [Real; 13] {
    let mut out = [0.0; 13];
    let mut fact = 1.0;
    let mut n = 1;
    while n <= start {
        fact *= n as Real;
        n += 1;
    }
    let mut j = 0;
    while j < 13 {
        out[j] = if j % 2 == 0 { 1.0 / fact } else { -1.0 / fact };
        fact *= (n as Real) * ((n + 1) as Real);
        n += 2;
        j += 1;
    }
    out
}

const SINC: [Real; 13] = series_coeffs(1);
const COSC: [Real; 13] = series_coeffs(2);
const SINC3: [Real; 13] = series_coeffs(3);

#[inline(always)]
fn horner(c: &[Real; 13], x2: Real) -> Real {
    let mut acc = c[12];
    let mut j = 12;
    while j > 0 {
        j -= 1;
        acc = acc * x2 + c[j];
    }
    acc
}

/// Below this |θ| the three ratios come from their Taylor series (12 terms reach 1e-19
/// relative at 1.5: 2.25¹²/25! ≈ 1e-21).
const SERIES_MAX: Real = 1.5;

/// `[sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³]`, each to a few ulps relative for every finite θ.
#[inline]
pub fn screw_ratios(theta: Real) -> [Real; 3] {
    if theta.abs() < SERIES_MAX {
        let x2 = theta * theta;
        [horner(&SINC, x2), horner(&COSC, x2), horner(&SINC3, x2)]
    } else {
        let (sh, ch) = sin_cos(0.5 * theta);
        let s = 2.0 * sh * ch;
        let inv = 1.0 / theta;
        let inv2 = inv * inv;
        [s * inv, 2.0 * sh * sh * inv2, (theta - s) * inv2 * inv]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn ulps(a: Real, b: Real) -> Real {
        (a - b).abs() / (b.abs().max(Real::MIN_POSITIVE) * Real::EPSILON)
    }

    #[test]
    fn sin_cos_matches_std() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut worst = 0.0f64;
        for i in 0..200_000 {
            let x: Real = match i % 4 {
                0 => rng.random_range(-4.0..4.0),
                1 => rng.random_range(-100.0..100.0),
                2 => rng.random_range(-2e6..2e6),
                _ => rng.random_range(-1e-6..1e-6),
            };
            let (s, c) = sin_cos(x);
            // Absolute error relative to the unit circle (the frames need absolute accuracy),
            // plus ≤ 2 ulps relative wherever |value| ≥ 1e-3.
            let (es, ec) = ((s - x.sin()).abs(), (c - x.cos()).abs());
            worst = worst.max(es).max(ec);
            assert!(es <= 2.3e-16 && ec <= 2.3e-16, "x = {x:e}: {es:e} {ec:e}");
            if x.sin().abs() > 1e-3 {
                assert!(ulps(s, x.sin()) <= 2.0, "x = {x:e}");
            }
            if x.cos().abs() > 1e-3 {
                assert!(ulps(c, x.cos()) <= 2.0, "x = {x:e}");
            }
        }
        // Exact quadrant points and non-finite input.
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert!(sin_cos(Real::NAN).0.is_nan());
        assert!(worst < 2.3e-16);
    }

    #[test]
    fn ratios_match_math() {
        use crate::math::{cosc, sinc, sinc3};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for i in 0..100_000 {
            let t: Real = match i % 3 {
                0 => rng.random_range(0.0..3.0),
                1 => rng.random_range(1.4..1.6),
                _ => rng.random_range(0.0..200.0),
            } * if i % 2 == 0 { 1.0 } else { -1.0 };
            let [a, b, c] = screw_ratios(t);
            assert!(
                ulps(a, sinc(t)) < 8.0 || (a - sinc(t)).abs() < 4e-16,
                "sinc {t}"
            );
            assert!(ulps(b, cosc(t)) < 8.0, "cosc {t}");
            assert!(ulps(c, sinc3(t)) < 8.0, "sinc3 {t}");
        }
        assert_eq!(screw_ratios(0.0), [1.0, 0.5, 1.0 / 6.0]);
    }
}
