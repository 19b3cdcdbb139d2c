//! The distance s of each sample along the ray: the measured tool pose projected onto the ray's
//! pose curve, and the run split into loading and unloading.
//!
//! # Pose curve
//! With the clamp at `o_c` (rotation `R_c`, the rig's `[d1 d2 d3]`) and the helix azimuth α, the
//! tool pose at distance s along the unit direction S̄ is ([`crate::planning::pose_path`])
//! `p(s) = o_c + R_c·Rz(α)·r(1; s·S̄)·L` and `R(s) = R_c·Rz(α)·D(1; s·S̄)·Rz(−α)·P`, with `r`, `D`
//! the helix end position and parallel-transported end frame and `P = [e2 e1 −e3]`.
//!
//! # Projection
//! A sample's s minimizes `f(s) = |p(s) − p|²/L² + θ(s)²` (θ the angle of `R(s)ᵀ·R`, the same
//! objective as `helixreach check`). A [`Tracker`] follows a run sample by sample: each sample
//! scans a window of ±max(4·|Δs|, [`MIN_WINDOW`]) around the previous sample's s on 9 points
//! (Δs the previous step). The best point is refined by successive parabolic steps through
//! three points around it, the spacing shrunk 8-fold each round, down to [`S_TOL`] (the
//! objective is smooth and locally quadratic in s).
//!
//! The track is **lost**, and `[0, s_max]` is scanned every [`SCAN_STEP`] (the better of the
//! two minima kept), at the first sample and when the window's minimum
//! - lies on an edge of the window that is not an end of `[0, s_max]` (the minimum may lie
//!   beyond it), or
//! - is worse than [`LOST`] (≈ 16 mm on a 0.5 m rod, or 32 mrad: about where the detector
//!   calls a sample off the path, [`super::DetectOptions::max_position_error`]).
//!
//! A real rig's tool follows the ray within millimetres, not exactly: on the seed's runs a
//! sixth of the samples lie more than 5 mm (f > 1e-4) from the continuum pose curve. That is
//! the residual's level, not a lost track, and is not rescanned.
//!
//! Cost: 9 to 21 pose evaluations per sample (the window and its refinement), and
//! `s_max`/[`SCAN_STEP`] + 1 more per full scan ([`Tracker::full_scans`]).
//!
//! # Phases
//! Loading runs from the first sample to the sample of largest s (the reversal), unloading from
//! there to the end. A run whose s falls back by more than [`MONOTONE_TOL`]·s_reversal while
//! loading (or rises by as much while unloading) is not a load-and-unload run (a permuted or
//! concatenated file): [`split_phases`] refuses it, naming both lines and values.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::helix::Helix;
use crate::math::{rot_z, rotation_angle, Mat3, Real, Vec3};
use crate::planning::rig::{tool_from_director, Rig};
use std::path::Path;

/// Grid step in s of a full scan.
pub const SCAN_STEP: Real = 0.05;
/// Smallest half-width of the local window.
pub const MIN_WINDOW: Real = 0.02;
/// A window's minimum of `f` above this (≈ 16 mm on a 0.5 m rod, or 32 mrad) triggers a full
/// scan.
pub const LOST: Real = 1e-3;
/// Spacing of the last parabolic step in s.
pub const S_TOL: Real = 1e-6;
/// Largest fall of s during loading (rise during unloading), as a fraction of the largest s.
pub const MONOTONE_TOL: Real = 0.05;

/// The ray's tool-pose curve for one clamp position.
#[derive(Debug, Clone)]
pub struct PoseCurve {
    /// `R_c·Rz(α)`.
    rca: Mat3,
    /// `Rz(−α)·P`.
    tail: Mat3,
    /// Clamp origin (m).
    pub origin: Vec3,
    /// Rod length (m).
    pub length: Real,
    /// The unit direction.
    pub dir: [Real; 3],
    /// Largest s scanned.
    pub s_max: Real,
}

impl PoseCurve {
    /// The curve of `dir` on `rig` (its clamp orientation and rod) with the clamp at `origin`, at
    /// helix azimuth `azimuth`, searched on `[0, s_max]`.
    pub fn new(rig: &Rig, dir: &Direction, origin: Vec3, azimuth: Real, s_max: Real) -> Self {
        PoseCurve {
            rca: rig.clamp_rotation() * rot_z(azimuth),
            tail: rot_z(-azimuth) * tool_from_director(),
            origin,
            length: rig.rod.length,
            dir: [dir.kappa, dir.tau, dir.omega],
            s_max,
        }
    }

    /// The helix at s.
    pub fn helix(&self, s: Real) -> Result<Helix> {
        Helix::new(s * self.dir[0], s * self.dir[1], s * self.dir[2])
    }

    /// The helix end relative to the clamp, in the base frame's orientation: `R_c·Rz(α)·r(1)·L`
    /// and the tool rotation `R(s)`.
    pub fn end_relative(&self, s: Real) -> Result<(Vec3, Mat3)> {
        let e = self.helix(s)?.end_pose_unchecked(self.length, 1.0);
        Ok((self.rca * e.position, self.rca * e.transported * self.tail))
    }

    /// The point at arc length `sigma` (fraction of the rod from the clamp) of the helix at s,
    /// base frame (m).
    pub fn point(&self, s: Real, sigma: Real) -> Result<Vec3> {
        let h = self.helix(s)?;
        Ok(self.origin + self.rca * (h.position(sigma) * self.length))
    }

    /// `f(s)` and the position and rotation errors for the tool pose `(rot, pos)`.
    pub fn objective(&self, s: Real, rot: &Mat3, pos: &Vec3) -> Result<(Real, Real, Real)> {
        let (p, r) = self.end_relative(s)?;
        let dp = (self.origin + p - pos).norm();
        let dr = rotation_angle(&(r.transpose() * rot));
        Ok(((dp / self.length).powi(2) + dr * dr, dp, dr))
    }

    /// The minimum of `f` on `[lo, hi]`: the best of `n + 1` even points, refined (module
    /// docs); with whether that point was the first or the last.
    fn search(&self, lo: Real, hi: Real, n: usize, rot: &Mat3, pos: &Vec3) -> Result<Minimum> {
        let h = (hi - lo) / n as Real;
        let (mut best, mut fbest, mut kbest) = (lo, (Real::INFINITY, 0.0, 0.0), 0);
        let mut f = [0.0; 3];
        let mut prev = [Real::INFINITY; 2];
        for k in 0..=n {
            let s = lo + h * k as Real;
            let fk = self.objective(s, rot, pos)?;
            if fk.0 < fbest.0 {
                (best, fbest, kbest) = (s, fk, k);
                f = [prev[1], fk.0, Real::INFINITY];
            } else if k == kbest + 1 {
                f[2] = fk.0;
            }
            prev = [prev[1], fk.0];
        }
        // Successive parabolic steps through three points around the best, the spacing shrunk
        // 8-fold each round; a step that does not improve ends the refinement.
        let (mut c, mut fc, mut step) = (best, fbest, h);
        let (mut fl, mut fr) = (f[0], f[2]);
        for _ in 0..4 {
            if !(fl.is_finite() && fr.is_finite()) {
                fl = if c - step >= lo {
                    self.objective(c - step, rot, pos)?.0
                } else {
                    Real::INFINITY
                };
                fr = if c + step <= hi {
                    self.objective(c + step, rot, pos)?.0
                } else {
                    Real::INFINITY
                };
                if !(fl.is_finite() && fr.is_finite()) {
                    break;
                }
            }
            let den = fl - 2.0 * fc.0 + fr;
            if den <= 0.0 {
                break;
            }
            let x = (c + 0.5 * step * (fl - fr) / den).clamp(c - step, c + step);
            let fx = self.objective(x, rot, pos)?;
            if fx.0 > fc.0 {
                break;
            }
            (c, fc) = (x, fx);
            step /= 8.0;
            if step < S_TOL {
                break;
            }
            fl = Real::NAN;
            fr = Real::NAN;
        }
        Ok(Minimum {
            s: c,
            f: fc.0,
            position_error: fc.1,
            rotation_error: fc.2,
            at_first: kbest == 0,
            at_last: kbest == n,
        })
    }

    /// The minimum of `f` over `[0, s_max]` (a full scan).
    fn scan(&self, rot: &Mat3, pos: &Vec3) -> Result<Minimum> {
        let n_full = (self.s_max / SCAN_STEP).ceil().max(1.0) as usize;
        self.search(0.0, self.s_max, n_full, rot, pos)
    }
}

/// A minimum of the objective found by [`PoseCurve::search`].
#[derive(Debug, Clone, Copy)]
struct Minimum {
    s: Real,
    f: Real,
    position_error: Real,
    rotation_error: Real,
    /// The best grid point was the first (the last) of the interval.
    at_first: bool,
    at_last: bool,
}

/// The projection of a run's samples in time order (module docs, "Projection"): the previous
/// sample's s and step, and the number of full scans made.
#[derive(Debug, Clone, Copy, Default)]
pub struct Tracker {
    /// s and |Δs| of the last projected sample.
    prev: Option<(Real, Real)>,
    full_scans: usize,
}

impl Tracker {
    /// A tracker before the first sample.
    pub fn new() -> Self {
        Self::default()
    }

    /// Full scans of `[0, s_max]` made so far (the first sample's included).
    pub fn full_scans(&self) -> usize {
        self.full_scans
    }

    /// Project the tool pose `(rot, pos)` of the next sample onto `curve`.
    pub fn project(&mut self, curve: &PoseCurve, rot: &Mat3, pos: &Vec3) -> Result<Projected> {
        let m = match self.prev {
            None => {
                self.full_scans += 1;
                curve.scan(rot, pos)?
            }
            Some((s0, ds)) => {
                let w = (4.0 * ds).max(MIN_WINDOW);
                let (lo, hi) = ((s0 - w).max(0.0), (s0 + w).min(curve.s_max));
                let local = curve.search(lo, hi, 8, rot, pos)?;
                let edge = (local.at_first && lo > 0.0) || (local.at_last && hi < curve.s_max);
                if edge || local.f > LOST {
                    self.full_scans += 1;
                    let global = curve.scan(rot, pos)?;
                    if global.f < local.f {
                        global
                    } else {
                        local
                    }
                } else {
                    local
                }
            }
        };
        let ds = self.prev.map_or(0.0, |(s0, _)| (m.s - s0).abs());
        self.prev = Some((m.s, ds));
        Ok(Projected {
            s: m.s,
            position_error: m.position_error,
            rotation_error: m.rotation_error,
        })
    }
}

/// One sample's projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    /// Distance along the ray (NaN for a sample without joints).
    pub s: Real,
    /// Tool position error at s (m).
    pub position_error: Real,
    /// Tool rotation error at s (rad).
    pub rotation_error: Real,
}

/// Project every tool pose (`None`: a sample without joints) onto `curve`, in order, with one
/// [`Tracker`].
pub fn project_all(curve: &PoseCurve, poses: &[Option<(Mat3, Vec3)>]) -> Result<Vec<Projected>> {
    let mut tracker = Tracker::new();
    poses
        .iter()
        .map(|p| match p {
            Some((rot, pos)) => tracker.project(curve, rot, pos),
            None => Ok(Projected {
                s: Real::NAN,
                position_error: Real::NAN,
                rotation_error: Real::NAN,
            }),
        })
        .collect()
}

/// The index of the reversal (largest s; loading is `..=rev`, unloading `rev..`), after checking
/// the run is load-then-unload (module docs). `lines` are the file's lines, for the message.
pub fn split_phases(s: &[Real], lines: &[usize], path: &Path) -> Result<usize> {
    let mut rev = None;
    for (i, &x) in s.iter().enumerate() {
        if x.is_finite() && rev.is_none_or(|r: usize| x > s[r]) {
            rev = Some(i);
        }
    }
    let Some(rev) = rev else {
        return Err(Error::File {
            path: path.to_path_buf(),
            reason: "no sample has finite joint angles".into(),
        });
    };
    let tol = MONOTONE_TOL * s[rev].max(1.0);
    let err = |a: usize, b: usize, what: &str| Error::BadLine {
        path: path.to_path_buf(),
        line: lines[b],
        field: "s".into(),
        reason: format!(
            "not a load-then-unload run: s {what} from {:.4} (line {}) to {:.4} while {}",
            s[a],
            lines[a],
            s[b],
            if b <= rev { "loading" } else { "unloading" }
        ),
    };
    // Loading: s never falls more than tol below its running maximum.
    let mut top: Option<usize> = None;
    for i in 0..=rev {
        if !s[i].is_finite() {
            continue;
        }
        if let Some(t) = top {
            if s[i] < s[t] - tol {
                return Err(err(t, i, "falls"));
            }
        }
        if top.is_none_or(|t| s[i] > s[t]) {
            top = Some(i);
        }
    }
    // Unloading: s never rises more than tol above its running minimum.
    let mut low: Option<usize> = None;
    for i in rev..s.len() {
        if !s[i].is_finite() {
            continue;
        }
        if let Some(m) = low {
            if s[i] > s[m] + tol {
                return Err(err(m, i, "rises"));
            }
        }
        if low.is_none_or(|m| s[i] < s[m]) {
            low = Some(i);
        }
    }
    Ok(rev)
}
