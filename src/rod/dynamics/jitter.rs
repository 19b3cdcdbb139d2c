//! Seeded jitter of the imposed end: a smooth random path of deviations of magnitude `d`.
//!
//! Knots are placed every `period` (time units of the caller); knot 0 is zero (the run starts
//! on the commanded pose) and knot k ≥ 1 is `d·u_k` with `u_k` uniform on the unit sphere
//! (ChaCha8 seeded with `seed`, drawn in order, so a run is reproducible and independent of the
//! time step). Between knots the deviation is the smoothstep blend
//! `K_k + (K_{k+1} − K_k)·(3u² − 2u³)`, `u` the fraction of the period: continuous with a
//! continuous velocity (zero at the knots), `|deviation| ≤ d`, speed `≤ 3d/period`.
//! A robot's tracking error is of this kind (it follows way-points with bounded velocity);
//! white noise per time step would instead depend on the step size.

use crate::math::{Real, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The jitter path (see the module docs).
#[derive(Debug, Clone)]
pub struct Jitter {
    magnitude: Real,
    period: Real,
    rng: ChaCha8Rng,
    knots: Vec<Vec3>,
}

impl Jitter {
    /// A path of magnitude `magnitude` ≥ 0 with knots every `period` > 0 (validated by the
    /// caller), seeded by `seed`.
    pub fn new(magnitude: Real, period: Real, seed: u64) -> Self {
        Jitter {
            magnitude,
            period,
            rng: ChaCha8Rng::seed_from_u64(seed),
            knots: vec![Vec3::zeros()],
        }
    }

    fn knot(&mut self, k: usize) -> Vec3 {
        while self.knots.len() <= k {
            // Uniform on the sphere: z uniform in [−1, 1], azimuth uniform.
            let z: Real = self.rng.random_range(-1.0..=1.0);
            let phi: Real = self.rng.random_range(0.0..std::f64::consts::TAU);
            let r = (1.0 - z * z).max(0.0).sqrt();
            self.knots
                .push(self.magnitude * Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        self.knots[k]
    }

    /// The deviation at time `t` ≥ 0.
    pub fn at(&mut self, t: Real) -> Vec3 {
        if self.magnitude == 0.0 {
            return Vec3::zeros();
        }
        let x = (t / self.period).max(0.0);
        let k = x.floor() as usize;
        let u = x - k as Real;
        let (a, b) = (self.knot(k), self.knot(k + 1));
        a + (b - a) * (u * u * (3.0 - 2.0 * u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_continuous_and_reproducible() {
        let mut j = Jitter::new(0.02, 0.1, 7);
        let mut k = Jitter::new(0.02, 0.1, 7);
        let mut last = j.at(0.0);
        assert_eq!(last, Vec3::zeros());
        for i in 1..2000 {
            let t = i as Real * 1e-3;
            let p = j.at(t);
            assert!(p.norm() <= 0.02 * (1.0 + 1e-12));
            // |dp/dt| ≤ 3d/period = 0.6.
            assert!((p - last).norm() <= 0.6 * 1e-3 * 1.0001);
            last = p;
        }
        assert!(
            (j.at(0.5).norm() - 0.02).abs() < 1e-12,
            "knots have magnitude d"
        );
        assert_eq!(j.at(0.73), k.at(0.73));
    }
}
