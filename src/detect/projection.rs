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
//! objective as `helixreach check`). The first sample, and any sample whose local minimum is
//! worse than [`LOST`], scans `[0, s_max]` every [`SCAN_STEP`]; the others scan a window of
//! ±max(4·|Δs|, [`MIN_WINDOW`]) around the previous sample's s on 9 points. The best point is
//! refined by successive parabolic steps through three points around it, the spacing shrunk
//! 8-fold each round, down to [`S_TOL`] (the objective is smooth and locally quadratic in s).
//! Cost: ≈ 15 pose evaluations (≈ 2 µs) per sample.
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
/// A local minimum of `f` above this (≈ 5 mm on a 0.5 m rod, or 10 mrad) triggers a full scan.
pub const LOST: Real = 1e-4;
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

    fn search(&self, lo: Real, hi: Real, n: usize, rot: &Mat3, pos: &Vec3) -> Result<(Real, Real)> {
        let h = (hi - lo) / n as Real;
        let (mut best, mut fbest, mut kbest) = (lo, Real::INFINITY, 0);
        let mut f = [0.0; 3];
        let mut prev = [Real::INFINITY; 2];
        for k in 0..=n {
            let s = lo + h * k as Real;
            let fk = self.objective(s, rot, pos)?.0;
            if fk < fbest {
                (best, fbest, kbest) = (s, fk, k);
                f = [prev[1], fk, Real::INFINITY];
            } else if k == kbest + 1 {
                f[2] = fk;
            }
            prev = [prev[1], fk];
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
            let den = fl - 2.0 * fc + fr;
            if den <= 0.0 {
                break;
            }
            let x = (c + 0.5 * step * (fl - fr) / den).clamp(c - step, c + step);
            let fx = self.objective(x, rot, pos)?.0;
            if fx > fc {
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
        Ok((c, fc))
    }

    /// The s of the tool pose `(rot, pos)`, continuing from `prev = (s, |Δs|)` when given; with
    /// the objective at that s.
    pub fn project(
        &self,
        rot: &Mat3,
        pos: &Vec3,
        prev: Option<(Real, Real)>,
    ) -> Result<(Real, Real)> {
        let n_full = (self.s_max / SCAN_STEP).ceil().max(1.0) as usize;
        let Some((s0, ds)) = prev else {
            return self.search(0.0, self.s_max, n_full, rot, pos);
        };
        let w = (4.0 * ds).max(MIN_WINDOW);
        let local = self.search((s0 - w).max(0.0), (s0 + w).min(self.s_max), 8, rot, pos)?;
        if local.1 <= LOST {
            return Ok(local);
        }
        let global = self.search(0.0, self.s_max, n_full, rot, pos)?;
        Ok(if global.1 < local.1 { global } else { local })
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

/// Project every tool pose (`None`: a sample without joints) onto `curve`, in order.
pub fn project_all(curve: &PoseCurve, poses: &[Option<(Mat3, Vec3)>]) -> Result<Vec<Projected>> {
    let mut out = Vec::with_capacity(poses.len());
    let mut prev: Option<(Real, Real)> = None;
    for p in poses {
        let Some((rot, pos)) = p else {
            out.push(Projected {
                s: Real::NAN,
                position_error: Real::NAN,
                rotation_error: Real::NAN,
            });
            continue;
        };
        let (s, _) = curve.project(rot, pos, prev)?;
        let (_, dp, dr) = curve.objective(s, rot, pos)?;
        prev = Some((s, prev.map_or(0.0, |(s0, _)| (s - s0).abs())));
        out.push(Projected {
            s,
            position_error: dp,
            rotation_error: dr,
        });
    }
    Ok(out)
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
