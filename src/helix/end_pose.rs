//! The pose of the rod's held end: what the robot (position + transported frame) and the motor
//! (the extra turn ω/c about the end tangent) must impose so that a clamped–clamped rod of
//! length L takes the helical shape (κ, τ, ω).
//!
//! With F(1) = exp(ŵ), w = (0, κ, τ), and c = 1/(1+ν):
//! - position L·r(1), r(1) = (κ(1−cos λ)/λ², κτ(λ−sin λ)/λ³, 1 − κ²(λ−sin λ)/λ³);
//! - transported (Bishop) frame Q(1) = F(1)·Rz(−τ): the frame the robot holds (the paper's
//!   "intermediate" frame, zero twist relative to the clamp);
//! - material frame M(1) = F(1)·Rz(ω/c − τ) = Q(1)·Rz(ω/c);
//! - motor angle ω/c.
//!
//! All in the clamp frame (origin at the clamped end, z = T₀, x = N₀).

use super::frames::mul_rot_z;
use super::{twist_ratio, Helix};
use crate::error::{require_positive, Result};
use crate::math::{Iso3, Mat3, Quat, Real, Vec3};

/// The pose of the rod's held end, in the clamp frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndPose {
    /// End position L·r(1) (same unit as the length passed to [`Helix::end_pose`]).
    pub position: Vec3,
    /// Parallel-transport frame [d1 d2 d3] at the end (d3 the end tangent): what the robot holds.
    pub transported: Mat3,
    /// Material frame [m1 m2 t] at the end: `transported` turned by `motor_angle` about d3.
    pub material: Mat3,
    /// The motor angle ω/c (rad), c = 1/(1+ν).
    pub motor_angle: Real,
}

impl EndPose {
    /// The end's material pose as a rigid transform (clamp frame → end).
    pub fn material_iso(&self) -> Iso3 {
        iso(&self.position, &self.material)
    }

    /// The end's parallel-transport pose as a rigid transform (what the robot must hold when a
    /// motor supplies `motor_angle`).
    pub fn transported_iso(&self) -> Iso3 {
        iso(&self.position, &self.transported)
    }
}

fn iso(p: &Vec3, r: &Mat3) -> Iso3 {
    let rot = Quat::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(*r));
    Iso3::from_parts(nalgebra::Translation3::from(*p), rot)
}

impl Helix {
    /// The end pose of a rod of length `length` (> 0, in any unit: the position comes out in it)
    /// with Poisson ratio `nu` ∈ (−1, 0.5] (c = 1/(1+ν)). Errors name the offending field.
    ///
    /// ```
    /// use helixreach::helix::Helix;
    /// // A straight rod twisted by ω: the end is at (0, 0, L) and the motor turns ω(1+ν).
    /// let p = Helix::new(0.0, 0.0, 2.0).unwrap().end_pose(0.5, 0.25).unwrap();
    /// assert_eq!(p.position, nalgebra::Vector3::new(0.0, 0.0, 0.5));
    /// assert!((p.material[(0, 0)] - 2.5f64.cos()).abs() < 1e-15);
    /// assert!(Helix::new(1.0, 1.0, 1.0).unwrap().end_pose(0.0, 0.3).is_err());
    /// ```
    pub fn end_pose(&self, length: Real, nu: Real) -> Result<EndPose> {
        let length = require_positive("length", length)?;
        let c = twist_ratio(nu)?;
        Ok(self.end_pose_unchecked(length, c))
    }

    /// [`Helix::end_pose`] for an already validated `length` > 0 and twist ratio `c` > 0
    /// (hot loops that validate once).
    #[inline]
    pub fn end_pose_unchecked(&self, length: Real, c: Real) -> EndPose {
        let (f, r) = self.frenet_and_position(1.0);
        let motor_angle = self.omega / c;
        EndPose {
            position: r * length,
            transported: mul_rot_z(&f, -self.tau),
            material: mul_rot_z(&f, motor_angle - self.tau),
            motor_angle,
        }
    }
}
