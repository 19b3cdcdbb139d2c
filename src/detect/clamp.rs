//! The clamp position fitted from the measured joints: every FK tool pose lies on the ray's pose
//! curve relative to the clamp.
//!
//! # Method
//! The tool rotation `R(s)` does not depend on the clamp origin `c`, and the tool position is
//! `p(s) = c + R_c·Rz(α)·r(1; s·S̄)·L`. Starting from `c₀ = p₀ − L·d3` (the first sample taken as
//! the straight rod), alternate: project the samples onto the curve of the current `c`
//! ([`super::projection`]), then set `c` to the mean of `p_i − R_c·Rz(α)·r(1; s_i·S̄)·L` (the
//! least-squares origin for fixed `s_i`). Stops when `c` moves less than [`TOL`] (m), at most
//! [`MAX_ITER`] rounds. At most [`MAX_FIT_SAMPLES`] evenly spread samples are used.
//! The RMS of the position residual at the end is reported: on the seed's runs ≈ 1–3 mm (the
//! seed held the frame of a 100-edge discrete helix, ≈ 3 mm from the continuum end).

use super::projection::PoseCurve;
use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3};

/// Convergence tolerance on the clamp origin (m).
pub const TOL: Real = 1e-6;
/// Largest number of alternation rounds.
pub const MAX_ITER: usize = 30;
/// Largest number of samples used.
pub const MAX_FIT_SAMPLES: usize = 400;

/// A fitted clamp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClampFit {
    /// The origin (m, base frame).
    pub origin: Vec3,
    /// RMS position residual of the samples used (m).
    pub rms: Real,
    /// Rounds used.
    pub iterations: usize,
}

/// Fit the clamp origin of `curve` (whose `origin` is ignored) to the tool `poses` (samples in
/// time order; `None` where the joints are missing).
pub fn fit_clamp(curve: &PoseCurve, poses: &[Option<(Mat3, Vec3)>]) -> Result<ClampFit> {
    let valid: Vec<&(Mat3, Vec3)> = poses.iter().flatten().collect();
    if valid.is_empty() {
        return Err(Error::invalid(
            "samples",
            0,
            "no sample with joints to fit the clamp",
        ));
    }
    let stride = valid.len().div_ceil(MAX_FIT_SAMPLES).max(1);
    let used: Vec<Option<(Mat3, Vec3)>> = valid.iter().step_by(stride).map(|p| Some(**p)).collect();
    let mut c = curve.clone();
    c.origin = valid[0].1 - c.end_relative(0.0)?.0;
    let mut rms = Real::NAN;
    for it in 1..=MAX_ITER {
        let proj = super::projection::project_all(&c, &used)?;
        let mut sum = Vec3::zeros();
        for (p, q) in proj.iter().zip(&used) {
            let (rel, _) = c.end_relative(p.s)?;
            sum += q.as_ref().map_or(Vec3::zeros(), |q| q.1 - rel);
        }
        let next = sum / used.len() as Real;
        let moved = (next - c.origin).norm();
        c.origin = next;
        let mut ss = 0.0;
        for (p, q) in proj.iter().zip(&used) {
            let (rel, _) = c.end_relative(p.s)?;
            ss += q
                .as_ref()
                .map_or(0.0, |q| (q.1 - c.origin - rel).norm_squared());
        }
        rms = (ss / used.len() as Real).sqrt();
        if moved < TOL {
            return Ok(ClampFit {
                origin: c.origin,
                rms,
                iterations: it,
            });
        }
    }
    Err(Error::NotConverged {
        what: "clamp fit".into(),
        iterations: MAX_ITER,
        residual: rms,
    })
}
