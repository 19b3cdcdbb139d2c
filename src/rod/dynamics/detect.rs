//! Instability detection from the series of the helix error e(s).
//!
//! While the rod follows the helical branch, e stays small and varies slowly (discretization,
//! inertial lag, jitter); at the instability the rod leaves the helix and e rises by orders of
//! magnitude over a short but finite stretch of s (the unstable mode grows exponentially). The
//! rule, with the defaults of [`DetectParams`]:
//!
//! 1. **Denoise**: ẽ is the centred running median of e over `window` samples (odd): isolated
//!    spikes of up to `(window−1)/2` samples are removed, a monotone rise is kept.
//! 2. **Noise level**: `N = 1.4826·median|e − ẽ|` over the whole series (a robust standard
//!    deviation of the scatter about ẽ; 0 for a smooth series).
//! 3. **Pre-jump level** before sample j: `B_j` = the median of ẽ over the samples with
//!    `s ∈ [s_j/2, s_j·(1 − lead))` (≤ 64 of them, evenly spaced), plus `3N`.
//! 4. **Jump**: the first sample `j` with `ẽ_j ≥ T_j = max(jump, rise·B_j)` that *persists*:
//!    ẽ stays `≥ T_j/2` for the next `persist` samples (or to the end of the series, if that
//!    is shorter but at least `window` samples). So e must both leave the helix in absolute
//!    terms (`jump`, 10 % of the radius) and rise by the factor `rise` over its own recent
//!    level: a slowly growing error (discretization, inertial lag, jitter, whose e grows like
//!    d/R(s) as the helix radius R shrinks along the ray) never counts, and a transient
//!    excursion that returns to the helix does not either. No such sample: no instability.
//! 5. **Onset** (the reported `s_dyn`): walking back from `j`, the last sample `i` at which
//!    ẽ is at most `onset_factor·B_j`. On a sharp jump this is the last sample before the
//!    rise; on a finite jump it is where e has left the helical level by the factor, not
//!    where it crosses the (arbitrary) threshold; the crossing `s_cross` (log-linear
//!    interpolation at level `T_j`) is reported too.
//!
//! The rule is invariant to rescaling e by a constant when `jump` scales with it, uses only
//! ranks (medians) and so tolerates outliers, and never looks at samples after the jump except
//! to confirm persistence.

use crate::error::{Error, Result};
use crate::math::Real;

/// Parameters of [`detect`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectParams {
    /// Absolute level of e that counts as having left the helix (default 0.1: a mean node
    /// deviation of 10 % of the helix radius).
    pub jump: Real,
    /// Running-median window (odd, ≥ 1; default 5).
    pub window: usize,
    /// Samples the jump must persist (default 20).
    pub persist: usize,
    /// Factor by which e must rise over the pre-jump level (default 5).
    pub rise: Real,
    /// Onset factor over the pre-jump level (default 3).
    pub onset_factor: Real,
    /// Fraction of `s_j` excluded before the jump when measuring the pre-jump level
    /// (default 0.1).
    pub lead: Real,
}

impl Default for DetectParams {
    fn default() -> Self {
        DetectParams {
            jump: 0.1,
            window: 5,
            persist: 20,
            rise: 5.0,
            onset_factor: 3.0,
            lead: 0.1,
        }
    }
}

impl DetectParams {
    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        crate::error::require_positive("jump", self.jump)?;
        if self.window == 0 || self.window % 2 == 0 {
            return Err(Error::invalid(
                "window",
                self.window,
                "must be odd and >= 1",
            ));
        }
        crate::error::require_positive("onset_factor", self.onset_factor)?;
        if !(self.rise > 1.0 && self.rise.is_finite()) {
            return Err(Error::invalid("rise", self.rise, "must be finite and > 1"));
        }
        if self.onset_factor <= 1.0 {
            return Err(Error::invalid(
                "onset_factor",
                self.onset_factor,
                "must be > 1",
            ));
        }
        if !(self.lead >= 0.0 && self.lead < 0.5) {
            return Err(Error::invalid("lead", self.lead, "must lie in [0, 0.5)"));
        }
        Ok(())
    }
}

/// A detected instability.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Detection {
    /// The onset of the jump, `s_dyn` (rule step 5).
    pub s_dyn: Real,
    /// Index of the onset sample.
    pub onset_index: usize,
    /// Where the denoised e crosses the threshold T (log-linear interpolation).
    pub s_cross: Real,
    /// Index of the first persistent sample above T.
    pub jump_index: usize,
    /// The threshold T used.
    pub threshold: Real,
    /// The pre-jump level B.
    pub baseline: Real,
    /// The noise level N.
    pub noise: Real,
}

/// At most this many samples (evenly spaced) measure the pre-jump level.
const PRE_SAMPLES: usize = 64;

/// The pre-jump level before sample `j`: the median of `f` over `s ∈ [s_j/2, s_j(1 − lead))`
/// (at most [`PRE_SAMPLES`] evenly spaced samples; the first sample if the window is empty).
fn pre_level(s: &[Real], f: &[Real], j: usize, lead: Real, buf: &mut Vec<Real>) -> Real {
    let (lo, hi) = (0.5 * s[j], s[j] * (1.0 - lead));
    let a = s[..j].partition_point(|&x| x < lo);
    let b = s[..j].partition_point(|&x| x < hi);
    if b <= a {
        return f[..j.max(1)].iter().fold(Real::INFINITY, |m, &v| m.min(v));
    }
    let stride = (b - a).div_ceil(PRE_SAMPLES);
    buf.clear();
    buf.extend((a..b).step_by(stride).map(|k| f[k]));
    median(buf)
}

fn median(v: &mut [Real]) -> Real {
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len();
    if m % 2 == 1 {
        v[m / 2]
    } else {
        0.5 * (v[m / 2 - 1] + v[m / 2])
    }
}

/// The centred running median of `e` over `window` samples (shrunk at the ends).
pub fn running_median(e: &[Real], window: usize) -> Vec<Real> {
    let h = window / 2;
    let mut buf = Vec::with_capacity(window);
    (0..e.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(h), (i + h + 1).min(e.len()));
            // Symmetric window so a monotone series is preserved at the ends too.
            let r = (i - a).min(b - 1 - i);
            buf.clear();
            buf.extend_from_slice(&e[i - r..=i + r]);
            median(&mut buf)
        })
        .collect()
}

/// Detect the instability in the series `(s_k, e_k)` (see the module docs). Errors on
/// mismatched lengths, non-finite or negative e, decreasing s, or invalid parameters.
///
/// ```
/// use helixreach::rod::dynamics::detect::{detect, DetectParams};
/// // A slowly growing error that jumps at s = 7 over a finite width.
/// let s: Vec<f64> = (0..1000).map(|k| k as f64 * 0.01).collect();
/// let e: Vec<f64> = s.iter().map(|&s| 1e-3 * s * s / 49.0 + (((s - 7.0) * 40.0).exp()).min(1.0)).collect();
/// let d = detect(&s, &e, &DetectParams::default()).unwrap().unwrap();
/// // The onset is where the exponential reaches 3× the pre-jump level (s ≈ 6.84), before the
/// // crossing of the threshold 0.1 (s ≈ 6.94).
/// assert!(d.s_dyn > 6.7 && d.s_dyn < 6.9 && d.s_dyn < d.s_cross, "{d:?}");
/// ```
pub fn detect(s: &[Real], e: &[Real], p: &DetectParams) -> Result<Option<Detection>> {
    p.validate()?;
    if s.len() != e.len() {
        return Err(Error::invalid(
            "series",
            format!("{} s vs {} e", s.len(), e.len()),
            "s and e must have the same length",
        ));
    }
    for (k, (&sk, &ek)) in s.iter().zip(e).enumerate() {
        if !(sk.is_finite() && ek.is_finite() && ek >= 0.0) {
            return Err(Error::invalid(
                format!("series[{k}]"),
                format!("s = {sk}, e = {ek}"),
                "s must be finite and e finite and >= 0",
            ));
        }
        if k > 0 && sk < s[k - 1] {
            return Err(Error::invalid(
                format!("s[{k}]"),
                sk,
                "s must be non-decreasing",
            ));
        }
    }
    let len = e.len();
    if len == 0 {
        return Ok(None);
    }
    let f = running_median(e, p.window);
    let mut dev: Vec<Real> = e.iter().zip(&f).map(|(a, b)| (a - b).abs()).collect();
    let noise = 1.4826 * median(&mut dev);
    let min_tail = p.window.min(p.persist);
    let mut buf = Vec::with_capacity(PRE_SAMPLES);
    let mut found = None;
    for j in 0..len {
        if f[j] < p.jump {
            continue;
        }
        let baseline = pre_level(s, &f, j, p.lead, &mut buf) + 3.0 * noise;
        let thr = p.jump.max(p.rise * baseline);
        if f[j] < thr {
            continue;
        }
        let end = (j + 1 + p.persist).min(len);
        let avail = end - (j + 1);
        if avail < p.persist && avail < min_tail {
            // Too few samples after j to confirm.
            break;
        }
        if f[j + 1..end].iter().all(|&v| v >= 0.5 * thr) {
            found = Some((j, thr, baseline));
            break;
        }
    }
    let Some((j, thr, baseline)) = found else {
        return Ok(None);
    };
    let level = p.onset_factor * baseline;
    let mut i = j;
    while i > 0 && f[i] > level {
        i -= 1;
    }
    let s_cross = if j == 0 {
        s[0]
    } else {
        let (a, b) = (f[j - 1].max(crate::math::tol::TINY), f[j]);
        let w = if b > a {
            ((thr.ln() - a.ln()) / (b.ln() - a.ln())).clamp(0.0, 1.0)
        } else {
            1.0
        };
        s[j - 1] + w * (s[j] - s[j - 1])
    };
    Ok(Some(Detection {
        s_dyn: s[i],
        onset_index: i,
        s_cross,
        jump_index: j,
        threshold: thr,
        baseline,
        noise,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_median_removes_spikes_keeps_steps() {
        let mut e = vec![1.0; 20];
        e[5] = 100.0;
        for v in &mut e[12..] {
            *v = 50.0;
        }
        let f = running_median(&e, 5);
        assert_eq!(f[5], 1.0);
        assert_eq!(f[11], 1.0);
        assert_eq!(f[12], 50.0);
    }

    #[test]
    fn transient_excursion_is_not_an_instability() {
        let s: Vec<Real> = (0..200).map(|k| k as Real * 0.05).collect();
        let e: Vec<Real> = s
            .iter()
            .map(|&x| if (4.0..4.5).contains(&x) { 0.5 } else { 1e-3 })
            .collect();
        assert!(detect(&s, &e, &DetectParams::default()).unwrap().is_none());
    }
}
