//! Sine and cosine of a joint angle, for forward kinematics and Jacobians.
//!
//! # Maths
//! x = n·π/2 + r with n the nearest integer to x·2/π and |r| ≤ π/4 (plus rounding); then
//! (sin x, cos x) is (sin r, cos r) turned by n quarter turns: (s, c), (c, −s), (−s, −c), (−c, s)
//! for n mod 4 = 0, 1, 2, 3. The reduction is Cody–Waite with π/2 split in three parts
//! (`PIO2_1` holds 33 significant bits, so n·`PIO2_1` is exact for |n| < 2²⁰ and x − n·`PIO2_1` is
//! exact by Sterbenz's lemma); n is rounded by adding and subtracting 1.5·2⁵² (round to nearest,
//! exact for |x·2/π| < 2⁵¹), whose low bits are n mod 4. On the reduced interval sin and cos
//! are the minimax polynomials of fdlibm's kernels (degree 13 and 14; their error is below
//! 2⁻⁵⁸ relative), evaluated without the tail term of the reduction.
//!
//! # Resolution and domain
//! For |x| ≤ [`FAST_RANGE`] (joint angles are a few radians) both results are within 2 ulp of
//! the correctly rounded values (test against `libm::sincos` over ±64 rad and at the multiples
//! of π/2, where r is smallest); outside it, and for non-finite x, the call is `libm::sincos`
//! (full-range Payne–Hanek reduction). NaN in gives NaN out.
//!
//! # Why not a crate
//! `libm::sincos` (the Rust port of musl) is exact over all of f64: its reduction tests the
//! argument's exponent and carries a tail term through both kernels, about three times the
//! instructions of this restricted version. Forward kinematics and Jacobians take a sine–cosine
//! pair per joint and dominate the planner's inner loop, where that difference is several
//! percent of a search. `std`'s `sin_cos` calls glibc, which saves and restores the rounding
//! mode on every call.
//!
//! # Cost
//! About 40 instructions; inside [`FAST_RANGE`] the branches are the range test, zero and the
//! quadrant (a four-way match: cheaper than selecting by bit masks).

// The constants are written as fdlibm publishes them (more digits than a double holds).
#![allow(clippy::excessive_precision)]

use crate::math::Real;

/// Largest |x| (rad) reduced here; beyond it, `libm::sincos`.
pub const FAST_RANGE: Real = 64.0;

/// 2/π.
const TWO_OVER_PI: Real = std::f64::consts::FRAC_2_PI;
/// π/2 in three parts: the first 33 bits, the next 33, the rest.
const PIO2_1: Real = 1.570_796_326_734_125_614_17;
const PIO2_2: Real = 6.077_100_506_303_965_976_6e-11;
const PIO2_3: Real = 2.022_266_248_795_950_631_54e-21;
/// 1.5·2⁵²: adding it rounds to an integer held in the low mantissa bits.
const ROUNDER: Real = 6_755_399_441_055_744.0;

const S1: Real = -1.666_666_666_666_663_243_48e-1;
const S2: Real = 8.333_333_333_322_489_461_24e-3;
const S3: Real = -1.984_126_982_985_794_931_34e-4;
const S4: Real = 2.755_731_370_707_006_767_89e-6;
const S5: Real = -2.505_076_025_340_686_341_95e-8;
const S6: Real = 1.589_690_995_211_550_102_21e-10;

const C1: Real = 4.166_666_666_666_660_190_37e-2;
const C2: Real = -1.388_888_888_887_410_957_49e-3;
const C3: Real = 2.480_158_728_947_672_941_78e-5;
const C4: Real = -2.755_731_435_139_066_330_35e-7;
const C5: Real = 2.087_572_321_298_174_827_90e-9;
const C6: Real = -1.135_964_755_778_819_482_65e-11;

/// (sin x, cos x): see the module docs for the accuracy and the domain.
///
/// ```
/// use helixreach::robot::joint_sincos::sincos;
/// let (s, c) = sincos(1.0);
/// assert!((s - 1.0_f64.sin()).abs() < 1e-15 && (c - 1.0_f64.cos()).abs() < 1e-15);
/// ```
#[inline]
pub fn sincos(x: Real) -> (Real, Real) {
    if x.is_nan() || x.abs() > FAST_RANGE {
        return libm::sincos(x);
    }
    if x == 0.0 {
        // Keeps the sign of zero (the polynomial would return +0 for −0).
        return (x, 1.0);
    }
    let t = x * TWO_OVER_PI + ROUNDER;
    let quadrant = t.to_bits() & 3;
    let n = t - ROUNDER;
    let r = ((x - n * PIO2_1) - n * PIO2_2) - n * PIO2_3;
    let z = r * r;
    let sin_r = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    let poly = z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let cos_r = w + (((1.0 - w) - hz) + poly);
    match quadrant {
        0 => (sin_r, cos_r),
        1 => (cos_r, -sin_r),
        2 => (-sin_r, -cos_r),
        _ => (-cos_r, sin_r),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between `a` and the reference `b` (b's spacing).
    fn ulps(a: Real, b: Real) -> Real {
        let spacing = if b == 0.0 {
            Real::MIN_POSITIVE
        } else {
            let bits = b.abs().to_bits();
            Real::from_bits(bits + 1) - b.abs()
        };
        (a - b).abs() / spacing
    }

    fn worst(xs: impl Iterator<Item = Real>) -> (Real, Real) {
        let (mut ws, mut wc) = (0.0, 0.0);
        for x in xs {
            let (s, c) = sincos(x);
            let (rs, rc) = libm::sincos(x);
            ws = Real::max(ws, ulps(s, rs));
            wc = Real::max(wc, ulps(c, rc));
        }
        (ws, wc)
    }

    #[test]
    fn within_two_ulp_of_libm_over_the_fast_range() {
        // A dense grid over ±64 rad and random points (a fixed LCG).
        let grid = (0..=2_000_000).map(|k| -FAST_RANGE + 2.0 * FAST_RANGE * k as Real / 2e6);
        let (ws, wc) = worst(grid);
        assert!(ws <= 2.0 && wc <= 2.0, "grid: sin {ws} ulp, cos {wc} ulp");
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let random = (0..1_000_000).map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as Real / (1u64 << 53) as Real - 0.5) * 2.0 * FAST_RANGE
        });
        let (ws, wc) = worst(random);
        assert!(ws <= 2.0 && wc <= 2.0, "random: sin {ws} ulp, cos {wc} ulp");
    }

    #[test]
    fn within_two_ulp_next_to_the_multiples_of_a_quarter_turn() {
        // Where the reduced argument is smallest, the reduction's rounding matters most: the
        // doubles nearest k·π/2 and a few hundred ulps either side.
        let mut xs = Vec::new();
        for k in -40..=40 {
            let centre = k as Real * std::f64::consts::FRAC_PI_2;
            let mut x = centre;
            for _ in 0..300 {
                x = Real::from_bits(x.to_bits() + 1);
                xs.push(x);
            }
            let mut x = centre;
            for _ in 0..300 {
                x = Real::from_bits(x.to_bits().saturating_sub(1));
                xs.push(x);
            }
        }
        let (ws, wc) = worst(xs.into_iter().filter(|x| x.abs() <= FAST_RANGE));
        assert!(ws <= 2.0 && wc <= 2.0, "sin {ws} ulp, cos {wc} ulp");
    }

    #[test]
    fn outside_the_fast_range_and_non_finite_it_is_libm() {
        for x in [65.0, -1e5, 1e300, Real::INFINITY, Real::NEG_INFINITY] {
            let (s, c) = sincos(x);
            let (rs, rc) = libm::sincos(x);
            assert!(
                s.to_bits() == rs.to_bits() || (s.is_nan() && rs.is_nan()),
                "{x}"
            );
            assert!(
                c.to_bits() == rc.to_bits() || (c.is_nan() && rc.is_nan()),
                "{x}"
            );
        }
        let (s, c) = sincos(Real::NAN);
        assert!(s.is_nan() && c.is_nan());
        assert_eq!(sincos(0.0), (0.0, 1.0));
        assert_eq!(sincos(-0.0).0.to_bits(), (-0.0 as Real).to_bits());
    }
}
