//! The two unknowns of a recording: the camera extrinsics (a rigid transform camera → robot
//! base) and the marker's arc length along the rod, fitted on samples where the rod is surely a
//! helix (early loading).
//!
//! # Method
//! For a marker at arc length σ (fraction of the rod from the clamp) the predicted position of
//! sample i is `m_i(σ) = o_c + R_c·Rz(α)·r(σ; s_i·S̄)·L`. For fixed σ the best rigid transform
//! `(R, t)` minimizing `Σ |R·o_i + t − m_i(σ)|²` over the camera positions `o_i` is the
//! Kabsch/Umeyama solution without scale ([`kabsch`]: SVD of the 3 × 3 cross-covariance, the
//! sign of the last singular vector fixed so that `det R = +1`). Its RMS residual `ρ(σ)` is
//! minimized over σ ∈ [[`SIGMA_MIN`], 1] by a grid of step [`SIGMA_GRID`] refined by golden
//! section to [`SIGMA_TOL`]. Then the samples whose residual exceeds
//! max([`TRIM_FACTOR`] × the median residual, [`TRIM_FLOOR`]) are dropped (a marker briefly lost,
//! a wrong blob) and σ and `(R, t)` are fitted again on the rest.
//!
//! A marker near the clamp (σ → 0) barely moves, so σ is identified by how the marker's path
//! curls; the fit set should reach s of a few units (the default: loading samples with
//! s ≤ 0.6 × the reversal s). Cost: ≈ 60 fits of ≤ [`MAX_FIT_SAMPLES`] points, ≈ 2 ms.

use super::projection::PoseCurve;
use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3};

/// Smallest marker arc length searched (fraction of the rod).
pub const SIGMA_MIN: Real = 0.05;
/// Grid step of the arc-length search.
pub const SIGMA_GRID: Real = 0.025;
/// Golden-section tolerance of the arc length.
pub const SIGMA_TOL: Real = 1e-4;
/// A fit sample is dropped when its residual exceeds this multiple of the median residual …
pub const TRIM_FACTOR: Real = 4.0;
/// … and this (m).
pub const TRIM_FLOOR: Real = 2e-3;
/// Largest number of samples in the fit (evenly thinned beyond).
pub const MAX_FIT_SAMPLES: usize = 600;
/// Fewest samples for a fit.
pub const MIN_FIT_SAMPLES: usize = 10;

/// A rigid transform `x ↦ R·x + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rigid {
    /// Rotation.
    pub rotation: Mat3,
    /// Translation (m).
    pub translation: Vec3,
}

impl Rigid {
    /// Apply to a point.
    pub fn apply(&self, x: &Vec3) -> Vec3 {
        self.rotation * x + self.translation
    }
}

/// The rigid transform taking the points `a` onto `b` in least squares, and its RMS residual.
/// Errors when fewer than 3 pairs are given.
///
/// ```
/// use helixreach::detect::extrinsics::kabsch;
/// use helixreach::math::{so3_exp, Vec3};
/// let r = so3_exp(&Vec3::new(0.3, -0.2, 1.1));
/// let t = Vec3::new(0.5, -1.0, 0.2);
/// let a: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f64, (i * i) as f64 * 0.1, (-(i as f64)).exp())).collect();
/// let b: Vec<Vec3> = a.iter().map(|x| r * x + t).collect();
/// let (fit, rms) = kabsch(&a, &b).unwrap();
/// assert!((fit.rotation - r).norm() < 1e-12 && (fit.translation - t).norm() < 1e-12 && rms < 1e-12);
/// ```
pub fn kabsch(a: &[Vec3], b: &[Vec3]) -> Result<(Rigid, Real)> {
    if a.len() != b.len() || a.len() < 3 {
        return Err(Error::invalid(
            "point pairs",
            format!("{} vs {}", a.len(), b.len()),
            "need the same number (>= 3) of points",
        ));
    }
    let n = a.len() as Real;
    let ca = a.iter().sum::<Vec3>() / n;
    let cb = b.iter().sum::<Vec3>() / n;
    let mut h = Mat3::zeros();
    for (x, y) in a.iter().zip(b) {
        h += (x - ca) * (y - cb).transpose();
    }
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let v = vt.transpose();
    let d = (v * u.transpose()).determinant().signum();
    let rotation = v * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, d)) * u.transpose();
    let translation = cb - rotation * ca;
    let fit = Rigid {
        rotation,
        translation,
    };
    let ss: Real = a
        .iter()
        .zip(b)
        .map(|(x, y)| (fit.apply(x) - y).norm_squared())
        .sum();
    Ok((fit, (ss / n).sqrt()))
}

/// The fitted extrinsics and marker arc length.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtrinsicsFit {
    /// Camera → base.
    pub camera_to_base: Rigid,
    /// Marker arc length σ (fraction of the rod from the clamp).
    pub sigma: Real,
    /// RMS residual of the kept fit samples (m).
    pub rms: Real,
    /// Samples kept.
    pub used: usize,
    /// Samples dropped as outliers.
    pub trimmed: usize,
    /// RMS residual with σ moved by ±0.05 (the smaller of the two; m): how sharply σ is
    /// identified.
    pub rms_at_sigma_offset: Real,
}

struct Problem<'a> {
    curve: &'a PoseCurve,
    s: Vec<Real>,
    cam: Vec<Vec3>,
    pred: Vec<Vec3>,
}

impl Problem<'_> {
    fn fit(&mut self, sigma: Real) -> Result<(Rigid, Real)> {
        for (p, &s) in self.pred.iter_mut().zip(&self.s) {
            *p = self.curve.point(s, sigma)?;
        }
        kabsch(&self.cam, &self.pred)
    }

    fn best_sigma(&mut self) -> Result<Real> {
        let n = ((1.0 - SIGMA_MIN) / SIGMA_GRID).round() as usize;
        let h = (1.0 - SIGMA_MIN) / n as Real;
        let (mut best, mut fbest) = (SIGMA_MIN, Real::INFINITY);
        for k in 0..=n {
            let x = SIGMA_MIN + h * k as Real;
            let f = self.fit(x)?.1;
            if f < fbest {
                (best, fbest) = (x, f);
            }
        }
        let (mut a, mut b) = ((best - h).max(SIGMA_MIN), (best + h).min(1.0));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (self.fit(c)?.1, self.fit(d)?.1);
        while b - a > SIGMA_TOL {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - g * (b - a);
                fc = self.fit(c)?.1;
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + g * (b - a);
                fd = self.fit(d)?.1;
            }
        }
        let x = 0.5 * (a + b);
        Ok(if self.fit(x)?.1 <= fbest { x } else { best })
    }
}

/// Fit the extrinsics and σ on the samples `(s_i, o_i)` (s along the ray, `o_i` the marker in the
/// camera frame), on `curve` (its clamp origin is used).
pub fn fit_extrinsics(curve: &PoseCurve, samples: &[(Real, Vec3)]) -> Result<ExtrinsicsFit> {
    if samples.len() < MIN_FIT_SAMPLES {
        return Err(Error::invalid(
            "extrinsics fit samples",
            samples.len(),
            format!("need at least {MIN_FIT_SAMPLES} early-loading samples with a marker"),
        ));
    }
    let stride = samples.len().div_ceil(MAX_FIT_SAMPLES).max(1);
    let chosen: Vec<(Real, Vec3)> = samples.iter().step_by(stride).copied().collect();
    let mut pb = Problem {
        curve,
        s: chosen.iter().map(|x| x.0).collect(),
        cam: chosen.iter().map(|x| x.1).collect(),
        pred: vec![Vec3::zeros(); chosen.len()],
    };
    let sigma = pb.best_sigma()?;
    let (rig, _) = pb.fit(sigma)?;
    let res: Vec<Real> = pb
        .cam
        .iter()
        .zip(&pb.pred)
        .map(|(o, m)| (rig.apply(o) - m).norm())
        .collect();
    let mut sorted = res.clone();
    sorted.sort_by(Real::total_cmp);
    let limit = (TRIM_FACTOR * sorted[sorted.len() / 2]).max(TRIM_FLOOR);
    let keep: Vec<usize> = (0..res.len()).filter(|&i| res[i] <= limit).collect();
    let trimmed = res.len() - keep.len();
    if keep.len() < MIN_FIT_SAMPLES {
        return Err(Error::invalid(
            "extrinsics fit samples",
            keep.len(),
            "too few samples left after dropping outliers",
        ));
    }
    let mut pb = Problem {
        curve,
        s: keep.iter().map(|&i| pb.s[i]).collect(),
        cam: keep.iter().map(|&i| pb.cam[i]).collect(),
        pred: vec![Vec3::zeros(); keep.len()],
    };
    let sigma = if trimmed > 0 { pb.best_sigma()? } else { sigma };
    let lo = pb.fit((sigma - 0.05).max(SIGMA_MIN))?.1;
    let hi = pb.fit((sigma + 0.05).min(1.0))?.1;
    let (camera_to_base, rms) = pb.fit(sigma)?;
    Ok(ExtrinsicsFit {
        camera_to_base,
        sigma,
        rms,
        used: keep.len(),
        trimmed,
        rms_at_sigma_offset: lo.min(hi),
    })
}
