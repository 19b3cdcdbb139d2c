//! The scene schema: obstacles as a rig file writes them (shape, pose in the robot's root
//! frame, name), validated, and placed as a primitive [`Shape`] at a [`Frame`].

use crate::error::{Error, Result};
use crate::math::{Real, Vec3};
use crate::robot::kinematics::{z_to_axis, Frame};
use crate::robot::model::Shape;
use serde::{Deserialize, Serialize};

/// Shape of a scene obstacle (in the obstacle frame; cylinders along z).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ObstacleShape {
    /// Box with the given half extents (m).
    Box {
        /// Half extents along x, y, z (m).
        half_extents: [Real; 3],
    },
    /// Cylinder along z, centred at the origin.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Half of the height (m).
        half_height: Real,
    },
    /// Capsule: the points within `radius` of the segment `a`–`b`.
    Capsule {
        /// First end (m).
        a: [Real; 3],
        /// Second end (m).
        b: [Real; 3],
        /// Radius (m).
        radius: Real,
    },
    /// Ball centred at the origin.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
}

/// Pose of an obstacle in the robot's root frame: translation and fixed-axis roll–pitch–yaw
/// (URDF convention, `R = Rz(y)·Ry(p)·Rx(r)`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstaclePose {
    /// Translation (m).
    #[serde(default)]
    pub xyz: [Real; 3],
    /// Roll, pitch, yaw (rad).
    #[serde(default)]
    pub rpy: [Real; 3],
}

/// A scene obstacle, as a rig file embeds it:
///
/// ```
/// let o: helixreach::robot::collision::SceneObstacle = toml::from_str(r#"
///     name = "table"
///     shape = { type = "box", half_extents = [0.4, 0.6, 0.02] }
///     pose = { xyz = [0.85, 0.0, -0.164] }
/// "#).unwrap();
/// assert_eq!(o.name, "table");
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObstacle {
    /// Name (reported in collisions).
    pub name: String,
    /// Shape.
    pub shape: ObstacleShape,
    /// Pose in the robot root frame.
    #[serde(default)]
    pub pose: ObstaclePose,
}

impl SceneObstacle {
    /// Validate sizes (finite, > 0) and the pose (finite); errors name the obstacle and field.
    pub fn validate(&self) -> Result<()> {
        let f = |field: &str, v: Real, positive: bool| -> Result<()> {
            if v.is_finite() && (!positive || v > 0.0) {
                Ok(())
            } else {
                Err(Error::invalid(
                    format!("obstacle {}: {field}", self.name),
                    v,
                    if positive {
                        "must be finite and > 0"
                    } else {
                        "must be finite"
                    },
                ))
            }
        };
        for (i, v) in self.pose.xyz.iter().enumerate() {
            f(&format!("pose.xyz[{i}]"), *v, false)?;
        }
        for (i, v) in self.pose.rpy.iter().enumerate() {
            f(&format!("pose.rpy[{i}]"), *v, false)?;
        }
        match &self.shape {
            ObstacleShape::Box { half_extents } => {
                for (i, v) in half_extents.iter().enumerate() {
                    f(&format!("half_extents[{i}]"), *v, true)?;
                }
            }
            ObstacleShape::Cylinder {
                radius,
                half_height,
            } => {
                f("radius", *radius, true)?;
                f("half_height", *half_height, true)?;
            }
            ObstacleShape::Capsule { a, b, radius } => {
                for (i, v) in a.iter().chain(b).enumerate() {
                    f(&format!("a/b[{i}]"), *v, false)?;
                }
                f("radius", *radius, true)?;
            }
            ObstacleShape::Sphere { radius } => f("radius", *radius, true)?,
        }
        Ok(())
    }
}

impl SceneObstacle {
    /// The obstacle as a primitive shape and its pose in the robot's root frame (call
    /// [`SceneObstacle::validate`] first). A capsule `a`–`b` becomes a capsule along the local z
    /// axis of a frame at its midpoint.
    pub fn placed(&self) -> (Shape, Frame) {
        let pose = Frame::from_xyz_rpy(self.pose.xyz, self.pose.rpy);
        match self.shape {
            ObstacleShape::Box { half_extents } => (
                Shape::Box {
                    half_extents: Vec3::from(half_extents),
                },
                pose,
            ),
            ObstacleShape::Cylinder {
                radius,
                half_height,
            } => (
                Shape::Cylinder {
                    radius,
                    half_length: half_height,
                },
                pose,
            ),
            ObstacleShape::Sphere { radius } => (Shape::Sphere { radius }, pose),
            ObstacleShape::Capsule { a, b, radius } => {
                let (a, b) = (Vec3::from(a), Vec3::from(b));
                let axis = b - a;
                let len = axis.norm();
                let rot = if len > 0.0 {
                    z_to_axis(&(axis / len))
                } else {
                    crate::math::Mat3::identity()
                };
                (
                    Shape::Capsule {
                        radius,
                        half_length: 0.5 * len,
                    },
                    pose.mul(&Frame::new(rot, 0.5 * (a + b))),
                )
            }
        }
    }
}
