//! The simulated rod's centerline and material frames, and their placement on a rig.
//!
//! [`simulate_ray`](super::simulate_ray) with [`SimParams::centerline_stride`](super::SimParams::centerline_stride)
//! `= k > 0` keeps every k-th recorded sample's configuration as a [`Centerline`]: the node
//! positions `x_i` (units of L) and the material frames `[m¹_j m²_j t_j]` of the edges, in the
//! **helix frame** — the clamp frame of [architecture §1](crate::architecture) at azimuth 0:
//! origin at the clamped end, `z` the clamp tangent, `x` the direction the helix first curls
//! toward. The arc length of node i is `(i − ½)·L/(n − 1)` (the straddling clamps put nodes 0
//! and n half an edge outside `[0, L]`); edge j is centred at `j·L/(n − 1)`.
//!
//! A [`Placement`] maps them into a rig's base frame: `X = o + R·Rz(α)·(L·x)` for positions
//! and `R·Rz(α)·M` for frames, with `o` the clamp origin, `R = [d1 d2 d3]` the clamp rotation
//! and α the helix azimuth about `d3`. Gravity, given in the base frame, enters the simulation
//! in the helix frame, `Rz(α)ᵀ·Rᵀ·g` ([`Placement::to_helix_frame`]).
//!
//! ```
//! use helixreach::math::{Mat3, Vec3};
//! use helixreach::rod::dynamics::centerline::Placement;
//! // A clamp at (1, 0, 0) whose rod points along base −x (d3 = −x), curling toward +z.
//! // d2 = d3 × d1 = +y.
//! let r = Mat3::from_columns(&[Vec3::z(), Vec3::y(), -Vec3::x()]);
//! let p = Placement::new(Vec3::new(1.0, 0.0, 0.0), r, 0.0, 0.5).unwrap();
//! // The straight rod's end (0, 0, 1) in the helix frame is 0.5 m along −x from the clamp.
//! assert!((p.point(&Vec3::z()) - Vec3::new(0.5, 0.0, 0.0)).norm() < 1e-15);
//! // Base gravity (0, 0, −g) points along −x of the helix frame (against the curl direction).
//! let g = p.to_helix_frame(&Vec3::new(0.0, 0.0, -9.81));
//! assert!((g - Vec3::new(-9.81, 0.0, 0.0)).norm() < 1e-12);
//! ```

use crate::error::{require_finite, require_positive, Error, Result};
use crate::math::{Mat3, Real, Vec3};

/// Tolerance on `RᵀR = I` and `det R = 1` of a placement's rotation (the rig loader builds it
/// from normalized, orthogonalized axes).
const ROTATION_TOL: Real = 1e-9;

/// One kept configuration of a simulated rod (helix frame, units of L; see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Centerline {
    /// Index of the recorded sample in [`Simulation::samples`](super::Simulation::samples).
    pub sample: usize,
    /// Time (s).
    pub t: Real,
    /// Distance along the ray.
    pub s: Real,
    /// Node positions `x_0 … x_n`.
    pub nodes: Vec<Vec3>,
    /// Material frames `[m¹ m² t]` (columns) of the edges `0 … n−1`.
    pub frames: Vec<Mat3>,
}

/// Where the rod sits in a rig's base frame (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Clamp origin (base frame, m).
    pub origin: Vec3,
    /// `R·Rz(α)`: the helix frame's axes as columns in the base frame.
    pub rotation: Mat3,
    /// Rod length L (m).
    pub length: Real,
}

impl Placement {
    /// The placement of a rod of length `length` (m) clamped at `origin` with clamp rotation
    /// `clamp` (`[d1 d2 d3]` as columns, a rotation matrix) and helix azimuth `azimuth` (rad).
    pub fn new(origin: Vec3, clamp: Mat3, azimuth: Real, length: Real) -> Result<Self> {
        for (f, v) in [
            ("origin_x", origin.x),
            ("origin_y", origin.y),
            ("origin_z", origin.z),
        ] {
            require_finite(f, v)?;
        }
        require_finite("azimuth", azimuth)?;
        require_positive("length", length)?;
        let orth = (clamp.transpose() * clamp - Mat3::identity()).norm();
        if !(orth <= ROTATION_TOL && (clamp.determinant() - 1.0).abs() <= ROTATION_TOL) {
            return Err(Error::invalid(
                "clamp rotation",
                format!("{clamp:?}"),
                "must be a rotation matrix",
            ));
        }
        let rz = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), azimuth).into_inner();
        Ok(Placement {
            origin,
            rotation: clamp * rz,
            length,
        })
    }

    /// The clamp frame itself: origin 0, identity rotation, azimuth 0.
    pub fn clamp_frame(length: Real) -> Result<Self> {
        Placement::new(Vec3::zeros(), Mat3::identity(), 0.0, length)
    }

    /// A point `x` of the helix frame (units of L) in the base frame (m).
    pub fn point(&self, x: &Vec3) -> Vec3 {
        self.origin + self.rotation * (self.length * x)
    }

    /// A frame (columns) of the helix frame in the base frame.
    pub fn frame(&self, m: &Mat3) -> Mat3 {
        self.rotation * m
    }

    /// A vector given in the base frame (e.g. gravity) in the helix frame.
    pub fn to_helix_frame(&self, v: &Vec3) -> Vec3 {
        self.rotation.transpose() * v
    }
}
