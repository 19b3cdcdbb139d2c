//! Pose paths: a ray (S̄, α) of the experiment as a sequence of rod-end poses in the robot base
//! frame, from the straight rod (s = 0) to `s_end = s*·(1 + margin)`.
//!
//! # Frames
//! At distance s the rod is the helix (κ, τ, ω) = s·S̄ (nondimensional, [`crate::helix`]). In the
//! clamp frame its end sits at `r(1)·L` with parallel-transported frame `D` (= I at the clamp).
//! The azimuth α turns the whole helix about the clamp tangent d3: positions become `Rz(α)·r` and,
//! since the transported frame still starts at the clamp's own frame, the end frame becomes
//! `D_α = Rz(α)·D·Rz(−α)`. In the base frame (clamp pose `R_c`, `o_c`):
//!
//! - tool position `p = o_c + R_c·Rz(α)·r(1)·L`,
//! - transported tool rotation `R_tool = R_c·D_α·P`, `P = [e2 e1 −e3]` (tool x = d2, y = d1, z = −d3),
//! - fixed-mode motor angle `m = ω/c` (the material frame is `D_α` turned by `+ω/c` about d3; the
//!   motor turns the rod about tool z = −d3, so in the tool frame this is a turn of −ω/c about
//!   tool z. The motor angle is reported as the rod's turn about d3: `+ω/c`).
//!
//! # Spacing
//! Adaptive (default): from s, a trial step h is accepted when the rod end moves at most
//! `max_end_step` (m) and its transported frame turns at most `max_end_angle` (the motor
//! angle is left to the time parametrization); otherwise h is halved. After an accepted step h is rescaled toward the bound
//! (`h ← h·min(2, 0.9·bound/move)`), so steps sit just under it. Uniform: N waypoints evenly in s.

use crate::error::{Error, Result};
use crate::helix::Helix;
use crate::math::{rot_z, rotation_angle, Iso3, Mat3, Real, Vec3};
use crate::planning::rig::{iso_from, tool_from_director, Rig};

/// Smallest adaptive waypoint step, relative to `s_end`: a step this short is taken even when
/// its joint-space step ratio exceeds 1 (dimensionless).
const MIN_STEP_REL: Real = 1e-9;

/// Floor of the step ratio in the step-growth rule `h ← h·min(0.9/ratio, 2)` (dimensionless):
/// a nearly zero ratio then grows the step by the cap 2.
const RATIO_FLOOR: Real = 1e-3;

/// One waypoint of a pose path.
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoint {
    /// Distance along the ray (nondimensional).
    pub s: Real,
    /// (κ, τ, ω) = s·S̄.
    pub kto: [Real; 3],
    /// Tool pose for the transported end frame (the fixed-mode arm target), base frame.
    pub tool: Iso3,
    /// Fixed-mode motor angle ω/c (rad).
    pub motor: Real,
}

/// A ray of the experiment on a rig.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Unit direction (κ̂, τ̂, ω̂).
    pub dir: [Real; 3],
    /// Helix azimuth α (rad) about the clamp tangent.
    pub azimuth: Real,
}

/// Maps helices to rod-end poses for one rig.
#[derive(Debug, Clone)]
pub struct PoseMap {
    rc: Mat3,
    oc: Vec3,
    length: Real,
    c: Real,
    az: Mat3,
}

impl PoseMap {
    /// The map for `rig` at helix azimuth `azimuth`.
    pub fn new(rig: &Rig, azimuth: Real) -> Self {
        PoseMap {
            rc: rig.clamp_rotation(),
            oc: rig.clamp.translation.vector,
            length: rig.rod.length,
            c: rig.rod.twist_ratio(),
            az: rot_z(azimuth),
        }
    }

    /// The helix at `kto` and its waypoint data: (tool pose, motor angle).
    pub fn end(&self, kto: [Real; 3]) -> Result<(Iso3, Real)> {
        let (offset, r, motor) = self.end_offset(kto)?;
        Ok((iso_from(&r, &(self.oc + offset)), motor))
    }

    /// The helix end at `kto` relative to the clamp: its offset `R_c·Rz(α)·r(1)·L` from the clamp
    /// origin (base frame, m), the transported tool rotation `R_c·D_α·P` and the fixed-mode
    /// motor angle (rad). A clamp placed elsewhere (a fitted clamp) adds its own origin.
    pub fn end_offset(&self, kto: [Real; 3]) -> Result<(Vec3, Mat3, Real)> {
        let h = Helix::new(kto[0], kto[1], kto[2])?;
        let e = h.end_pose_unchecked(self.length, self.c);
        let d = self.az * e.transported * self.az.transpose();
        let r = self.rc * d * tool_from_director();
        Ok((self.rc * (self.az * e.position), r, e.motor_angle))
    }

    /// The point of `helix` at fraction `sigma` of the rod from the clamp, relative to the clamp
    /// origin (base frame, m).
    pub fn point_offset(&self, helix: &Helix, sigma: Real) -> Vec3 {
        self.rc * (self.az * (helix.position(sigma) * self.length))
    }

    /// The rod centerline at `kto` as `n + 1` points in the base frame (s = i/n along the rod).
    pub fn centerline(&self, kto: [Real; 3], n: usize) -> Result<Vec<Vec3>> {
        let h = Helix::new(kto[0], kto[1], kto[2])?;
        Ok(crate::helix::discrete::nodes(&h, n)
            .into_iter()
            .map(|x| self.oc + self.rc * (self.az * (x * self.length)))
            .collect())
    }
}

/// Spacing settings of [`pose_path`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    /// Largest end translation between waypoints (m).
    pub max_end_step: Real,
    /// Largest end rotation (and motor turn) between waypoints (rad).
    pub max_end_angle: Real,
    /// 0 = adaptive; N ≥ 2 = N waypoints uniform in s.
    pub waypoints: usize,
    /// Cap on the number of waypoints (the path stops early, at a smaller s, when reached).
    pub max_waypoints: usize,
}

/// The waypoints of `ray` on `rig` from s = 0 to `s_end` (inclusive), see the module docs.
///
/// Errors on a non-finite or negative `s_end` or a helix the helix module rejects.
pub fn pose_path(rig: &Rig, ray: &Ray, s_end: Real, sp: &Spacing) -> Result<Vec<Waypoint>> {
    if !(s_end.is_finite() && s_end >= 0.0) {
        return Err(Error::invalid("s_end", s_end, "must be finite and >= 0"));
    }
    let map = PoseMap::new(rig, ray.azimuth);
    let at = |s: Real| -> Result<Waypoint> {
        let kto = [s * ray.dir[0], s * ray.dir[1], s * ray.dir[2]];
        let (tool, motor) = map.end(kto)?;
        Ok(Waypoint {
            s,
            kto,
            tool,
            motor,
        })
    };
    let mut out = Vec::new();
    out.push(at(0.0)?);
    if s_end == 0.0 {
        return Ok(out);
    }
    if sp.waypoints >= 2 {
        let n = sp.waypoints.min(sp.max_waypoints);
        for i in 1..n {
            // The last waypoint is s_end itself (s_end·i/(n − 1) can round below it).
            let s = if i + 1 == n {
                s_end
            } else {
                s_end * i as Real / (n - 1) as Real
            };
            out.push(at(s)?);
        }
        return Ok(out);
    }
    let mut h = s_end / 64.0;
    let h_min = s_end * MIN_STEP_REL;
    while out.len() < sp.max_waypoints {
        let prev = out.last().expect("non-empty");
        if prev.s >= s_end {
            break;
        }
        let s_try = (prev.s + h).min(s_end);
        let w = at(s_try)?;
        let ratio = step_ratio(prev, &w, sp);
        if ratio > 1.0 && h > h_min {
            h *= 0.5_f64.max(0.9 / ratio);
            continue;
        }
        h = (s_try - prev.s) * (0.9 / ratio.max(RATIO_FLOOR)).min(2.0);
        out.push(w);
    }
    Ok(out)
}

/// The largest of (end translation / bound, end rotation / bound). The motor angle is not part
/// of it: the motor turns the rod about the tool axis without moving the arm, and its speed is
/// bounded by the time parametrization.
pub fn step_ratio(a: &Waypoint, b: &Waypoint, sp: &Spacing) -> Real {
    let dp = (b.tool.translation.vector - a.tool.translation.vector).norm();
    let dr = rotation_angle(
        &(a.tool.rotation.inverse() * b.tool.rotation)
            .to_rotation_matrix()
            .into_inner(),
    );
    (dp / sp.max_end_step).max(dr / sp.max_end_angle)
}

impl Spacing {
    /// The spacing of a rig's planner settings.
    pub fn of(rig: &Rig) -> Spacing {
        Spacing {
            max_end_step: rig.planner.max_end_step,
            max_end_angle: rig.planner.max_end_angle,
            waypoints: rig.planner.waypoints,
            max_waypoints: rig.planner.max_waypoints,
        }
    }
}
