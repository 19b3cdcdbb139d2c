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
//! Each sample's s, by a [`Tracker`] on this curve ([`crate::planning::pose_projection`]: the
//! objective, the window that follows the run, the full scans where the track is lost).
//!
//! # Phases
//! Loading runs from the first sample to the sample of largest s (the reversal), unloading from
//! there to the end. A run whose s falls back by more than [`MONOTONE_TOL`]·s_reversal while
//! loading (or rises by as much while unloading) is not a load-and-unload run (a permuted or
//! concatenated file): [`split_phases`] refuses it, naming both lines and values.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::helix::Helix;
use crate::math::{Mat3, Real, Vec3};
use crate::planning::pose_path::PoseMap;
use crate::planning::pose_projection::{Projected, ToolPoseCurve, Tracker};
use crate::planning::rig::Rig;
use std::path::Path;

/// Largest fall of s during loading (rise during unloading), as a fraction of the largest s.
pub const MONOTONE_TOL: Real = 0.05;

/// The ray's tool-pose curve for one clamp position.
#[derive(Debug, Clone)]
pub struct PoseCurve {
    /// The rig's helix-to-pose map at the azimuth (its own clamp origin unused).
    map: PoseMap,
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
            map: PoseMap::new(rig, azimuth),
            origin,
            length: rig.rod.length,
            dir: [dir.kappa, dir.tau, dir.omega],
            s_max,
        }
    }

    fn kto(&self, s: Real) -> [Real; 3] {
        [s * self.dir[0], s * self.dir[1], s * self.dir[2]]
    }

    /// The helix at s.
    pub fn helix(&self, s: Real) -> Result<Helix> {
        let [k, t, o] = self.kto(s);
        Helix::new(k, t, o)
    }

    /// The helix end relative to the clamp, in the base frame's orientation: `R_c·Rz(α)·r(1)·L`
    /// and the tool rotation `R(s)` ([`PoseMap::end_offset`]).
    pub fn end_relative(&self, s: Real) -> Result<(Vec3, Mat3)> {
        let (offset, r, _) = self.map.end_offset(self.kto(s))?;
        Ok((offset, r))
    }

    /// The point at arc length `sigma` (fraction of the rod from the clamp) of the helix at s,
    /// base frame (m).
    pub fn point(&self, s: Real, sigma: Real) -> Result<Vec3> {
        Ok(self.origin + self.map.point_offset(&self.helix(s)?, sigma))
    }
}

impl ToolPoseCurve for PoseCurve {
    fn tool_pose(&self, s: Real) -> Result<(Mat3, Vec3)> {
        let (p, r) = self.end_relative(s)?;
        Ok((r, self.origin + p))
    }

    fn length(&self) -> Real {
        self.length
    }

    fn s_max(&self) -> Real {
        self.s_max
    }
}

/// Project every tool pose (`None`: a sample without joints) onto `curve`, in order, with one
/// [`Tracker`].
pub fn project_all(curve: &PoseCurve, poses: &[Option<(Mat3, Vec3)>]) -> Result<Vec<Projected>> {
    let mut tracker = Tracker::new();
    poses
        .iter()
        .map(|p| match p {
            Some((rot, pos)) => tracker.project(curve, rot, pos),
            None => Ok(Projected::NONE),
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
