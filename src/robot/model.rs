//! The immutable robot model: links with their primitive collision geometry, the actuated
//! joints from the root to the tool link with their limits, and the compiled [`Chain`].
//!
//! A model is built once from a URDF ([`RobotModel::from_urdf_file`],
//! [`RobotModel::from_urdf_str`], [`RobotModel::load`] for the built-in robots) and is then
//! shared read-only (it is `Send + Sync`); every kinematic function is a pure function of the
//! model and a joint vector.
//!
//! # Conventions
//! - The joint vector holds the actuated (revolute/continuous) joints on the path from the
//!   URDF root to the tool link, root first. Movable joints off that path (the Sawyer's
//!   `head_pan`) are frozen at 0 (clamped into their limits).
//! - Every pose is in the URDF root frame; orientation tolerance in rad, position in m.
//! - Cylinders and capsules are along the local z axis of their collision origin (URDF).

use super::kinematics::{Chain, Frame, Jacobian, MAX_DOF};
use crate::error::{Error, Result};
use crate::math::{Quat, Real, Vec3};

/// An actuated joint of the chain.
#[derive(Clone, Debug, PartialEq)]
pub struct JointInfo {
    /// URDF joint name.
    pub name: String,
    /// Parent link name.
    pub parent_link: String,
    /// Child link name.
    pub child_link: String,
    /// Lower position limit (rad).
    pub lower: Real,
    /// Upper position limit (rad).
    pub upper: Real,
    /// A URDF `continuous` joint: no limits in the URDF, modelled here as `[−π, π]` (one turn,
    /// so the joint space stays bounded); a path that would turn it past ±π stops at that
    /// bound (cause `joint_limit`).
    pub continuous: bool,
    /// Velocity limit (rad/s; 0 when the URDF gives none).
    pub velocity: Real,
    /// Unit axis in the joint frame.
    pub axis: Vec3,
}

/// A primitive collision shape in its own frame (cylinders and capsules along local z): the one
/// shape type of the crate — URDF link geometry, rig-file scene obstacles (`shape = { type =
/// "box", half_extents = [x, y, z] }`, `{ type = "cylinder", radius, half_length }`,
/// `{ type = "capsule", radius, half_length }`, `{ type = "sphere", radius }`; a cylinder's
/// `half_height` is read as `half_length`), collision and drawing.
///
/// ```
/// use helixreach::robot::Shape;
/// let s: Shape = toml::from_str("type = \"cylinder\"\nradius = 0.1\nhalf_height = 0.5").unwrap();
/// assert_eq!(s, Shape::Cylinder { radius: 0.1, half_length: 0.5 });
/// assert!(s.validate("post").is_ok());
/// assert!(Shape::Sphere { radius: -1.0 }.validate("post").unwrap_err().to_string().contains("post: radius"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// Ball.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
    /// Box.
    Box {
        /// Half extents along x, y, z (m).
        #[serde(with = "crate::math::vec3_array")]
        half_extents: Vec3,
    },
    /// Cylinder along z, centred at the origin.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Half of the length (m).
        #[serde(alias = "half_height")]
        half_length: Real,
    },
    /// Capsule along z: the points within `radius` of the segment `z ∈ [−half_length, half_length]`.
    Capsule {
        /// Radius (m).
        radius: Real,
        /// Half of the segment length (m).
        half_length: Real,
    },
}

impl Shape {
    /// Check the sizes: finite, radii and half extents > 0, a capsule's half length ≥ 0 (0 is a
    /// ball). Errors name `what` and the field (`post: radius`).
    pub fn validate(&self, what: &str) -> Result<()> {
        let check = |field: &str, v: Real, zero_ok: bool| -> Result<()> {
            if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
                Ok(())
            } else {
                Err(Error::invalid(
                    format!("{what}: {field}"),
                    v,
                    if zero_ok {
                        "must be finite and >= 0"
                    } else {
                        "must be finite and > 0"
                    },
                ))
            }
        };
        match *self {
            Shape::Sphere { radius } => check("radius", radius, false),
            Shape::Box { half_extents } => {
                for (i, v) in half_extents.iter().enumerate() {
                    check(&format!("half_extents[{i}]"), *v, false)?;
                }
                Ok(())
            }
            Shape::Cylinder {
                radius,
                half_length,
            } => {
                check("radius", radius, false)?;
                check("half_length", half_length, false)
            }
            Shape::Capsule {
                radius,
                half_length,
            } => {
                check("radius", radius, false)?;
                check("half_length", half_length, true)
            }
        }
    }

    /// Radius of a ball centred at the shape's origin that encloses it.
    pub fn bounding_radius(&self) -> Real {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Box { half_extents } => half_extents.norm(),
            Shape::Cylinder {
                radius,
                half_length,
            } => radius.hypot(half_length),
            Shape::Capsule {
                radius,
                half_length,
            } => radius + half_length,
        }
    }
}

/// One collision element of a link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionGeometry {
    /// Pose of the shape in the link frame.
    pub origin: Frame,
    /// The shape.
    pub shape: Shape,
}

/// One mesh collision element of a link: the mesh (scaled) and its pose.
#[derive(Clone, Debug)]
pub struct MeshGeometry {
    /// Pose of the mesh frame in the link frame.
    pub origin: Frame,
    /// The filename as the URDF writes it.
    pub filename: String,
    /// The `scale` attribute (per axis).
    pub scale: [Real; 3],
    /// The loaded mesh and its hull (shared between elements naming the same file and scale).
    pub mesh: std::sync::Arc<super::mesh::LoadedMesh>,
}

impl PartialEq for MeshGeometry {
    fn eq(&self, o: &Self) -> bool {
        self.origin == o.origin
            && self.filename == o.filename
            && self.scale == o.scale
            && self.mesh.file == o.mesh.file
    }
}

/// A link of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkInfo {
    /// URDF link name.
    pub name: String,
    /// Index of the parent link (`None` for the root).
    pub parent: Option<usize>,
    /// Name of the joint that places the link (`None` for the root).
    pub joint: Option<String>,
    /// Index of the rigid group: links joined by fixed (or frozen) joints share it; it is the
    /// index of the group's first link.
    pub group: usize,
    /// Primitive collision geometry.
    pub collision: Vec<CollisionGeometry>,
    /// Mesh collision geometry.
    pub meshes: Vec<MeshGeometry>,
}

impl LinkInfo {
    /// Whether the link has any collision geometry.
    pub fn has_collision(&self) -> bool {
        !(self.collision.is_empty() && self.meshes.is_empty())
    }
}

/// The immutable robot model (see the module docs).
#[derive(Clone, Debug)]
pub struct RobotModel {
    pub(crate) name: String,
    pub(crate) source: String,
    pub(crate) tip_link: String,
    pub(crate) tip_index: usize,
    pub(crate) joints: Vec<JointInfo>,
    pub(crate) links: Vec<LinkInfo>,
    pub(crate) frozen: Vec<(String, Real)>,
    pub(crate) ignored: Vec<String>,
    pub(crate) chain: Chain,
    pub(crate) urdf: urdf_rs::Robot,
    pub(crate) sources: Vec<crate::sources::SourceFile>,
}

impl RobotModel {
    /// The robot's URDF name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Where the model came from (a path or `builtin:<name>`).
    pub fn source(&self) -> &str {
        &self.source
    }
    /// Every file read while loading the model, with a digest of its contents, in load order:
    /// the URDF (`builtin:<name>` for a built-in robot), then its never-colliding pair list
    /// (`<urdf stem>.collision.toml`, recorded as absent when there is none), then any other
    /// file the loader read (each mesh file once, in the order of the links). A sweep records these in its settings
    /// ([`crate::sources::sources_setting`]) so `--resume` and `merge` refuse rows computed from
    /// a different robot.
    ///
    /// ```
    /// let m = helixreach::robot::RobotModel::load("sawyer", None).unwrap();
    /// let names: Vec<&str> = m.sources().iter().map(|s| s.name()).collect();
    /// assert_eq!(names, ["builtin:sawyer", "builtin:sawyer.collision.toml"]);
    /// ```
    pub fn sources(&self) -> &[crate::sources::SourceFile] {
        &self.sources
    }
    /// Record one more file the model depends on (a rig's SRDF).
    pub(crate) fn add_source(&mut self, s: crate::sources::SourceFile) {
        if !self.sources.contains(&s) {
            self.sources.push(s);
        }
    }
    /// The root link name.
    pub fn root_link(&self) -> &str {
        &self.links[0].name
    }
    /// The tool link name.
    pub fn tip_link(&self) -> &str {
        &self.tip_link
    }
    /// Index of the tool link in [`RobotModel::links`].
    pub fn tip_index(&self) -> usize {
        self.tip_index
    }
    /// Number of actuated joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }
    /// The actuated joints, root first.
    pub fn joints(&self) -> &[JointInfo] {
        &self.joints
    }
    /// Every link, in topological order (root first); the order of [`Chain::link_frames`].
    pub fn links(&self) -> &[LinkInfo] {
        &self.links
    }
    /// Index of a link by name.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
    /// Movable joints off the chain and the value they are frozen at.
    pub fn frozen_joints(&self) -> &[(String, Real)] {
        &self.frozen
    }
    /// Links without collision geometry that the loader was told to accept (`no_collision`),
    /// as `link: reason`.
    pub fn ignored_geometry(&self) -> &[String] {
        &self.ignored
    }
    /// The compiled chain (hot paths).
    pub fn chain(&self) -> &Chain {
        &self.chain
    }
    /// The parsed URDF (for the k cross-check).
    pub fn urdf(&self) -> &urdf_rs::Robot {
        &self.urdf
    }
    /// Lower limits, one per joint.
    pub fn lower(&self) -> [Real; MAX_DOF] {
        let mut a = [0.0; MAX_DOF];
        for (x, j) in a.iter_mut().zip(&self.joints) {
            *x = j.lower;
        }
        a
    }
    /// Upper limits, one per joint.
    pub fn upper(&self) -> [Real; MAX_DOF] {
        let mut a = [0.0; MAX_DOF];
        for (x, j) in a.iter_mut().zip(&self.joints) {
            *x = j.upper;
        }
        a
    }

    /// Check a user joint vector: right length, finite. Limits are not checked (see
    /// [`RobotModel::within_limits`]).
    pub fn check_joints(&self, q: &[Real]) -> Result<()> {
        if q.len() != self.dof() {
            let names: Vec<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
            return Err(Error::invalid(
                "joints",
                format!("{} values", q.len()),
                format!(
                    "{} ({} → {}) has {} joints: {}",
                    self.name,
                    self.root_link(),
                    self.tip_link,
                    self.dof(),
                    names.join(",")
                ),
            ));
        }
        for (v, j) in q.iter().zip(&self.joints) {
            if !v.is_finite() {
                return Err(Error::invalid(
                    format!("joints[{}]", j.name),
                    v,
                    "must be finite",
                ));
            }
        }
        Ok(())
    }

    /// Whether every joint is within its limits (inclusive, with slack `eps` rad).
    pub fn within_limits(&self, q: &[Real], eps: Real) -> bool {
        q.iter()
            .zip(&self.joints)
            .all(|(v, j)| *v >= j.lower - eps && *v <= j.upper + eps)
    }

    /// Checked tool pose.
    ///
    /// ```
    /// let m = helixreach::robot::RobotModel::load("sawyer", None).unwrap();
    /// let p = m.tool_pose(&[0.0; 7]).unwrap();
    /// // right_hand at (1.0155, 0.1603, 0.3170) (reference), the motor tip 0.171 m further along +x.
    /// assert!((p.pos.x - (1.0155 + 0.171)).abs() < 2e-3);
    /// assert!(m.tool_pose(&[0.0; 6]).is_err());
    /// ```
    pub fn tool_pose(&self, q: &[Real]) -> Result<Frame> {
        self.check_joints(q)?;
        Ok(self.chain.tool_pose(q))
    }

    /// Checked tool pose and Jacobian.
    pub fn jacobian(&self, q: &[Real]) -> Result<(Frame, Jacobian)> {
        self.check_joints(q)?;
        let mut j = Jacobian::zeros();
        let f = self.chain.jacobian(q, &mut j);
        Ok((f, j))
    }

    /// Checked frames of every link (order of [`RobotModel::links`]).
    pub fn link_frames(&self, q: &[Real]) -> Result<Vec<Frame>> {
        self.check_joints(q)?;
        let mut out = vec![Frame::identity(); self.links.len()];
        self.chain.link_frames(q, &mut out);
        Ok(out)
    }

    /// A uniformly random configuration within the limits.
    pub fn random_config<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> [Real; MAX_DOF] {
        let mut q = [0.0; MAX_DOF];
        for (x, j) in q.iter_mut().zip(&self.joints) {
            *x = rng.random_range(j.lower..=j.upper);
        }
        q
    }
}

/// The pose `f` as `x, y, z, qw, qx, qy, qz` (metres; unit quaternion, scalar first, with
/// `qw ≥ 0`): the one pose format of the command line, read back by [`pose_from_xyz_wxyz`].
///
/// ```
/// use helixreach::robot::{pose_from_xyz_wxyz, pose_to_xyz_wxyz};
/// let v = [0.5, -0.1, 0.3, 0.0, 1.0, 0.0, 0.0];
/// let back = pose_to_xyz_wxyz(&pose_from_xyz_wxyz(&v).unwrap());
/// assert!(back.iter().zip(v).all(|(a, b)| (a - b).abs() < 1e-15));
/// ```
pub fn pose_to_xyz_wxyz(f: &Frame) -> [Real; 7] {
    let q = Quat::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(f.rot));
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [
        f.pos.x,
        f.pos.y,
        f.pos.z,
        s * q.w,
        s * q.i,
        s * q.j,
        s * q.k,
    ]
}

/// A pose from its 4×4 homogeneous matrix, 16 values row by row (`R t; 0 0 0 1`, metres),
/// validated: finite values, last row `0 0 0 1` (each within 1e-9), `‖RᵀR − I‖ ≤ 1e-6` (the
/// quaternion's tolerance, so a matrix printed to 7 digits reads) and `det R > 0`. `R` is then
/// replaced by the nearest rotation.
///
/// ```
/// use helixreach::robot::pose_from_matrix;
/// let m = [0.0, -1.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 0.0, 0.0, 1.0];
/// let f = pose_from_matrix(&m).unwrap();
/// assert_eq!((f.pos.x, f.rot[(1, 0)]), (0.5, 1.0));
/// let mut mirror = m;
/// mirror[10] = -1.0;
/// assert!(pose_from_matrix(&mirror).unwrap_err().to_string().contains("det"));
/// ```
pub fn pose_from_matrix(v: &[Real]) -> Result<Frame> {
    if v.len() != 16 {
        return Err(Error::invalid(
            "pose matrix",
            format!("{} values", v.len()),
            "expected 16: the 4×4 homogeneous matrix, row by row",
        ));
    }
    for (k, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::invalid(
                format!("pose matrix[{}][{}]", k / 4, k % 4),
                x,
                "must be finite",
            ));
        }
    }
    for (c, want) in [0.0, 0.0, 0.0, 1.0].into_iter().enumerate() {
        if (v[12 + c] - want).abs() > 1e-9 {
            return Err(Error::invalid(
                format!("pose matrix[3][{c}]"),
                v[12 + c],
                "the last row must be 0 0 0 1",
            ));
        }
    }
    let r = crate::math::Mat3::new(v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]);
    let ortho = (r.transpose() * r - crate::math::Mat3::identity()).norm();
    if ortho > crate::math::tol::UNIT_QUATERNION {
        return Err(Error::invalid(
            "pose matrix rotation",
            format!("‖RᵀR − I‖ = {ortho:e}"),
            format!(
                "must be orthonormal (‖RᵀR − I‖ ≤ {:e})",
                crate::math::tol::UNIT_QUATERNION
            ),
        ));
    }
    let det = r.determinant();
    if det <= 0.0 {
        return Err(Error::invalid(
            "pose matrix rotation",
            format!("det {det}"),
            "must be a rotation (det > 0), not a reflection",
        ));
    }
    // Started from R itself (within 1e-6 of a rotation): converges in a few iterations.
    let nearest = nalgebra::Rotation3::from_matrix_eps(
        &r,
        1e-15,
        100,
        nalgebra::Rotation3::from_matrix_unchecked(r),
    );
    Ok(Frame::new(*nearest.matrix(), Vec3::new(v[3], v[7], v[11])))
}

/// A pose from `x, y, z, qw, qx, qy, qz` (metres; unit quaternion), validated: finite values
/// and `|‖q‖ − 1| ≤ 1e-6` (the quaternion is then normalized).
///
/// ```
/// use helixreach::robot::pose_from_xyz_wxyz;
/// assert!(pose_from_xyz_wxyz(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]).is_ok());
/// let e = pose_from_xyz_wxyz(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0]).unwrap_err();
/// assert!(e.to_string().contains("quaternion"));
/// ```
pub fn pose_from_xyz_wxyz(v: &[Real]) -> Result<Frame> {
    if v.len() != 7 {
        return Err(Error::invalid(
            "pose",
            format!("{} values", v.len()),
            "expected 7: x,y,z,qw,qx,qy,qz",
        ));
    }
    const NAMES: [&str; 7] = ["x", "y", "z", "qw", "qx", "qy", "qz"];
    for (x, n) in v.iter().zip(NAMES) {
        if !x.is_finite() {
            return Err(Error::invalid(format!("pose.{n}"), x, "must be finite"));
        }
    }
    let q = nalgebra::Quaternion::new(v[3], v[4], v[5], v[6]);
    let n = q.norm();
    if (n - 1.0).abs() > crate::math::tol::UNIT_QUATERNION {
        return Err(Error::invalid(
            "pose quaternion (qw,qx,qy,qz)",
            format!("norm {n}"),
            format!(
                "must be a unit quaternion (|norm − 1| ≤ {:e})",
                crate::math::tol::UNIT_QUATERNION
            ),
        ));
    }
    let uq = Quat::from_quaternion(q);
    Ok(Frame::new(
        *uq.to_rotation_matrix().matrix(),
        Vec3::new(v[0], v[1], v[2]),
    ))
}
