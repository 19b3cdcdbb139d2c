//! The compiled, allocation-free kinematic chain: forward kinematics of the tool and of every
//! link, and the 6×n geometric Jacobian.
//!
//! # Math
//! A URDF joint `i` places its child link at `T_parent · O_i · Rot(a_i, q_i)`, with `O_i` the
//! joint origin (`xyz`, then `rpy` as fixed-axis roll–pitch–yaw: `R = Rz(y)·Ry(p)·Rx(r)`) and
//! `a_i` the unit joint axis in the joint frame. Compilation folds every fixed joint and every
//! frozen off-chain joint into the neighbouring constant transforms and turns every axis into
//! `+z`: with a constant rotation `A_i` that maps `e_z` onto `a_i`,
//! `Rot(a_i, q) = A_i · Rz(q) · A_iᵀ`, so `A_i` joins `O_i` and `A_iᵀ` joins the next constant.
//! The tool pose is then
//!
//! `T_tool(q) = C_0 · Rz(q_0) · C_1 · Rz(q_1) ⋯ C_{n−1} · Rz(q_{n−1}) · C_tool`,
//!
//! and `R · Rz(q)` is two column combinations (no matrix product). Each step costs one
//! sine–cosine pair (`libm::sincos`, the Rust port of musl's: under 1 ulp, without the rounding
//! mode save and restore of the platform's), one 3×3 product and one matrix–vector product. A prismatic joint (a linear rail)
//! is the translation `Tz(q)` instead of `Rz(q)` (`q` in metres).
//!
//! The geometric Jacobian `J(q)` (6×n, root frame) maps joint rates to the tool twist
//! `[v; ω]`, `v` the velocity of the tool origin: column `i` is `[z_i × (p_tool − p_i); z_i]`
//! with `z_i`, `p_i` the world axis and origin of joint `i`; a prismatic joint's column is
//! `[z_i; 0]`.
//!
//! A mimic joint (URDF `<mimic joint="s" multiplier="m" offset="o"/>`) off the path to the tool
//! takes the value `m·q_s + o` of its actuated source joint in [`Chain::link_frames`].
//!
//! Link frames (for collision and for the cross-check against k) are computed in the URDF's own
//! convention, link by link in topological order, into a caller buffer.
//!
//! # Conventions
//! Frames are [`Frame`] (a rotation matrix and a translation): the hot paths avoid quaternions.
//! At most [`MAX_DOF`] joints; a [`Jacobian`] is a fixed 6×[`MAX_DOF`] matrix whose columns past
//! the chain's dof are zero.

use crate::math::{Iso3, Mat3, Quat, Real, Vec3};
use nalgebra::SMatrix;

/// Largest number of actuated joints a compiled chain supports.
pub const MAX_DOF: usize = 7;

/// Geometric Jacobian: rows 0..3 linear velocity of the tool origin, rows 3..6 angular
/// velocity, both in the root frame; columns past the chain's dof are zero.
pub type Jacobian = SMatrix<Real, 6, MAX_DOF>;

/// A rigid transform stored as a rotation matrix and a translation (`x ↦ rot·x + pos`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Rotation (columns: the frame's axes in the parent frame).
    pub rot: Mat3,
    /// Origin in the parent frame.
    pub pos: Vec3,
}

impl Default for Frame {
    fn default() -> Self {
        Self::identity()
    }
}

impl Frame {
    /// The identity transform.
    pub fn identity() -> Self {
        Frame {
            rot: Mat3::identity(),
            pos: Vec3::zeros(),
        }
    }

    /// From a rotation and a translation.
    pub fn new(rot: Mat3, pos: Vec3) -> Self {
        Frame { rot, pos }
    }

    /// From a URDF origin: `xyz` and fixed-axis `rpy` (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`).
    ///
    /// ```
    /// use helixreach::robot::Frame;
    /// let f = Frame::from_xyz_rpy([1.0, 0.0, 0.0], [0.0, 0.0, std::f64::consts::FRAC_PI_2]);
    /// let p = f.transform_point(&helixreach::math::Vec3::new(1.0, 0.0, 0.0));
    /// assert!((p - helixreach::math::Vec3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
    /// ```
    pub fn from_xyz_rpy(xyz: [Real; 3], rpy: [Real; 3]) -> Self {
        let q = Quat::from_euler_angles(rpy[0], rpy[1], rpy[2]);
        Frame {
            rot: *q.to_rotation_matrix().matrix(),
            pos: Vec3::new(xyz[0], xyz[1], xyz[2]),
        }
    }

    /// From an isometry.
    pub fn from_iso(iso: &Iso3) -> Self {
        Frame {
            rot: *iso.rotation.to_rotation_matrix().matrix(),
            pos: iso.translation.vector,
        }
    }

    /// To an isometry (the rotation is re-orthonormalized through a quaternion).
    pub fn to_iso(&self) -> Iso3 {
        let rot = nalgebra::Rotation3::from_matrix_unchecked(self.rot);
        Iso3::from_parts(self.pos.into(), Quat::from_rotation_matrix(&rot))
    }

    /// Composition `self · other`.
    #[inline]
    pub fn mul(&self, other: &Frame) -> Frame {
        Frame {
            rot: self.rot * other.rot,
            pos: self.pos + self.rot * other.pos,
        }
    }

    /// The inverse transform.
    #[inline]
    pub fn inverse(&self) -> Frame {
        let rt = self.rot.transpose();
        Frame {
            rot: rt,
            pos: -(rt * self.pos),
        }
    }

    /// `rot·p + pos`.
    #[inline]
    pub fn transform_point(&self, p: &Vec3) -> Vec3 {
        self.pos + self.rot * p
    }
}

/// `m · Rz(q)` given `(sin q, cos q)`: a combination of the first two columns.
#[inline(always)]
fn mul_rot_z(m: &Mat3, s: Real, c: Real) -> Mat3 {
    let c0 = m.column(0);
    let c1 = m.column(1);
    let n0 = c0 * c + c1 * s;
    let n1 = c1 * c - c0 * s;
    Mat3::from_columns(&[n0, n1, m.column(2).into_owned()])
}

/// Rotation about the unit axis `a` by `q` (Rodrigues).
#[inline]
pub(crate) fn axis_rotation(a: &Vec3, q: Real) -> Mat3 {
    let (s, c) = q.sin_cos();
    let k = crate::math::hat(a);
    Mat3::identity() + k * s + (k * k) * (1.0 - c)
}

/// A rotation `A` with `A·e_z = a` (unit `a`); the identity when `a = e_z`.
pub(crate) fn z_to_axis(a: &Vec3) -> Mat3 {
    let z = Vec3::z();
    let c = z.dot(a);
    if (c - 1.0).abs() < crate::math::tol::PARALLEL {
        return Mat3::identity();
    }
    if (c + 1.0).abs() < crate::math::tol::PARALLEL {
        return Mat3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
    }
    let axis = z.cross(a);
    let s = axis.norm();
    axis_rotation(&(axis / s), s.atan2(c))
}

/// How a link frame moves with the joint that places it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkMotion {
    /// Rigidly attached (fixed joint, frozen joint or the root).
    Fixed,
    /// Turned by actuated joint `dof` about the unit `axis` (joint frame).
    Revolute {
        /// Index of the joint in the chain's joint vector.
        dof: usize,
        /// Unit axis in the joint frame.
        axis: Vec3,
        /// Whether the axis is `+z` (fast path).
        is_z: bool,
    },
    /// Translated by actuated joint `dof` (m) along the unit `axis` (joint frame).
    Prismatic {
        /// Index of the joint in the chain's joint vector.
        dof: usize,
        /// Unit axis in the joint frame.
        axis: Vec3,
    },
    /// A mimic joint: moved by `multiplier · q[dof] + offset` about (or along, if `prismatic`)
    /// the unit `axis`.
    Mimic {
        /// Index of the source joint in the chain's joint vector.
        dof: usize,
        /// Unit axis in the joint frame.
        axis: Vec3,
        /// The URDF multiplier.
        multiplier: Real,
        /// The URDF offset (rad or m).
        offset: Real,
        /// A translation (prismatic) rather than a rotation.
        prismatic: bool,
    },
}

/// One link of the compiled tree: `F_link = F_parent · origin · motion(q)`.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkStep {
    /// Index of the parent link (`None` for the root).
    pub parent: Option<usize>,
    /// Constant transform from the parent link frame to the joint frame.
    pub origin: Frame,
    /// Motion of the joint.
    pub motion: LinkMotion,
}

/// The compiled chain (see the module docs). Immutable, `Send + Sync`.
#[derive(Clone, Debug)]
pub struct Chain {
    dof: usize,
    /// `C_i`: constant transform before joint `i` (axis folded to `+z`).
    pre: Vec<Frame>,
    /// Whether joint `i` is prismatic (a translation along its axis).
    prismatic: [bool; MAX_DOF],
    /// `C_tool`.
    tool: Frame,
    /// Every link in topological order.
    links: Vec<LinkStep>,
    /// The frame of each link that no joint moves (it and its ancestors fixed): the base,
    /// pedestals, mounts. [`Chain::link_frames`] copies these.
    constant: Vec<Option<Frame>>,
}

impl Chain {
    /// Compile a chain. `path` lists, from the root to the tool link, each step's constant origin
    /// and optional unit joint axis (`Some` for actuated joints, in order); `links` is the whole
    /// tree in topological order. The flag says the joint is prismatic.
    pub(crate) fn compile(path: &[(Frame, Option<(Vec3, bool)>)], links: Vec<LinkStep>) -> Chain {
        let mut pre = Vec::new();
        let mut prismatic = [false; MAX_DOF];
        let mut acc = Frame::identity();
        for (origin, axis) in path {
            acc = acc.mul(origin);
            if let Some((a, p)) = axis {
                let a_rot = z_to_axis(a);
                if pre.len() < MAX_DOF {
                    prismatic[pre.len()] = *p;
                }
                pre.push(acc.mul(&Frame::new(a_rot, Vec3::zeros())));
                acc = Frame::new(a_rot.transpose(), Vec3::zeros());
            }
        }
        let mut constant: Vec<Option<Frame>> = Vec::with_capacity(links.len());
        for step in &links {
            let parent = match step.parent {
                Some(p) => constant.get(p).copied().flatten(),
                None => Some(Frame::identity()),
            };
            let f = match (parent, step.motion) {
                (Some(f), LinkMotion::Fixed) => Some(f.mul(&step.origin)),
                _ => None,
            };
            constant.push(f);
        }
        Chain {
            dof: pre.len(),
            pre,
            prismatic,
            tool: acc,
            links,
            constant,
        }
    }

    /// The frame of link `i` when no joint moves it (root frame), else `None`.
    pub fn constant_frame(&self, i: usize) -> Option<Frame> {
        self.constant.get(i).copied().flatten()
    }

    /// Whether actuated joint `i` is prismatic.
    pub fn is_prismatic(&self, i: usize) -> bool {
        self.prismatic.get(i).copied().unwrap_or(false)
    }

    /// Number of actuated joints.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Number of link frames ([`Chain::link_frames`] writes this many).
    pub fn n_links(&self) -> usize {
        self.links.len()
    }

    /// The compiled link tree.
    pub fn links(&self) -> &[LinkStep] {
        &self.links
    }

    /// Tool pose in the root frame. `q.len()` must be [`Chain::dof`] (only checked in debug
    /// builds: validate user input with [`crate::robot::RobotModel::check_joints`]).
    #[inline]
    pub fn tool_pose(&self, q: &[Real]) -> Frame {
        debug_assert_eq!(q.len(), self.dof);
        // The sines are independent of the product chain: compute them first so that they overlap.
        let mut sc = [(0.0, 1.0); MAX_DOF];
        for (x, &qi) in sc.iter_mut().zip(q) {
            *x = libm::sincos(qi);
        }
        let mut rot = Mat3::identity();
        let mut pos = Vec3::zeros();
        for (i, (c, &(s, co))) in self.pre.iter().zip(&sc[..self.dof]).enumerate() {
            pos += rot * c.pos;
            let m = rot * c.rot;
            if self.prismatic[i] {
                rot = m;
                pos += rot.column(2) * q[i];
            } else {
                rot = mul_rot_z(&m, s, co);
            }
        }
        Frame {
            pos: pos + rot * self.tool.pos,
            rot: rot * self.tool.rot,
        }
    }

    /// Tool pose and geometric Jacobian (see the module docs) at `q`.
    #[inline]
    pub fn jacobian(&self, q: &[Real], jac: &mut Jacobian) -> Frame {
        debug_assert_eq!(q.len(), self.dof);
        let mut axes = [Vec3::zeros(); MAX_DOF];
        let mut origins = [Vec3::zeros(); MAX_DOF];
        let mut rot = Mat3::identity();
        let mut pos = Vec3::zeros();
        for (i, (c, &qi)) in self.pre.iter().zip(q).enumerate() {
            pos += rot * c.pos;
            let m = rot * c.rot;
            if self.prismatic[i] {
                rot = m;
                pos += rot.column(2) * qi;
            } else {
                let (s, co) = libm::sincos(qi);
                rot = mul_rot_z(&m, s, co);
            }
            axes[i] = rot.column(2).into_owned();
            origins[i] = pos;
        }
        let tool = Frame {
            pos: pos + rot * self.tool.pos,
            rot: rot * self.tool.rot,
        };
        for i in 0..MAX_DOF {
            if i < self.dof {
                let z = axes[i];
                if self.prismatic[i] {
                    jac.fixed_view_mut::<3, 1>(0, i).copy_from(&z);
                    jac.fixed_view_mut::<3, 1>(3, i).fill(0.0);
                } else {
                    let v = z.cross(&(tool.pos - origins[i]));
                    jac.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
                    jac.fixed_view_mut::<3, 1>(3, i).copy_from(&z);
                }
            } else {
                jac.column_mut(i).fill(0.0);
            }
        }
        tool
    }

    /// Every link frame (root frame), in the order of [`Chain::links`], written into `out`
    /// (`out.len()` must be [`Chain::n_links`]). The frames of links that no joint moves are
    /// composed once, when the chain is compiled, and copied here.
    pub fn link_frames(&self, q: &[Real], out: &mut [Frame]) {
        debug_assert_eq!(q.len(), self.dof);
        debug_assert_eq!(out.len(), self.links.len());
        for (i, step) in self.links.iter().enumerate() {
            if let Some(f) = self.constant[i] {
                out[i] = f;
                continue;
            }
            let parent = match step.parent {
                Some(p) => out[p],
                None => Frame::identity(),
            };
            let mut f = parent.mul(&step.origin);
            match step.motion {
                LinkMotion::Fixed => {}
                LinkMotion::Revolute { dof, axis, is_z } => {
                    if is_z {
                        let (s, c) = libm::sincos(q[dof]);
                        f.rot = mul_rot_z(&f.rot, s, c);
                    } else {
                        f.rot *= axis_rotation(&axis, q[dof]);
                    }
                }
                LinkMotion::Prismatic { dof, axis } => {
                    f.pos += f.rot * (axis * q[dof]);
                }
                LinkMotion::Mimic {
                    dof,
                    axis,
                    multiplier,
                    offset,
                    prismatic,
                } => {
                    let v = multiplier * q[dof] + offset;
                    if prismatic {
                        f.pos += f.rot * (axis * v);
                    } else {
                        f.rot *= axis_rotation(&axis, v);
                    }
                }
            }
            out[i] = f;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_to_axis_maps_z_and_is_a_rotation() {
        for a in [
            Vec3::z(),
            -Vec3::z(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let r = z_to_axis(&a);
            assert!((r * Vec3::z() - a).norm() < 1e-15);
            assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-15);
            assert!((r.determinant() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn folded_axis_equals_rodrigues() {
        // Rot(a, q) = A Rz(q) Aᵀ, the identity the compilation relies on.
        let a = Vec3::new(0.3, -1.0, 0.2).normalize();
        let ar = z_to_axis(&a);
        for q in [-2.0, 0.1, 1.3] {
            let lhs = axis_rotation(&a, q);
            let rhs = ar * crate::math::rot_z(q) * ar.transpose();
            assert!((lhs - rhs).norm() < 1e-15);
        }
    }
}
