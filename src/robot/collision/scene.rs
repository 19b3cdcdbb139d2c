//! The scene schema: obstacles as a rig file writes them (name, a primitive [`Shape`], pose in
//! the robot's root frame), validated, and placed as a [`Shape`] at a [`Frame`].

use crate::error::{Error, Result};
use crate::math::Real;
use crate::robot::kinematics::Frame;
use crate::robot::model::Shape;
use serde::{Deserialize, Serialize};

/// Pose of an obstacle in the robot's root frame: translation and fixed-axis roll–pitch–yaw
/// (URDF convention, `R = Rz(y)·Ry(p)·Rx(r)`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstaclePose {
    /// Translation (m).
    #[serde(default, deserialize_with = "crate::math::exact3::deserialize")]
    pub xyz: [Real; 3],
    /// Roll, pitch, yaw (rad).
    #[serde(default, deserialize_with = "crate::math::exact3::deserialize")]
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
    /// Shape (in the obstacle frame; cylinders and capsules along its z axis).
    pub shape: Shape,
    /// Pose in the robot root frame.
    #[serde(default)]
    pub pose: ObstaclePose,
}

impl SceneObstacle {
    /// Validate sizes (finite, > 0) and the pose (finite); errors name the obstacle and field.
    pub fn validate(&self) -> Result<()> {
        let what = format!("obstacle {}", self.name);
        for (field, v) in [("pose.xyz", self.pose.xyz), ("pose.rpy", self.pose.rpy)] {
            for (i, x) in v.iter().enumerate() {
                if !x.is_finite() {
                    return Err(Error::invalid(
                        format!("{what}: {field}[{i}]"),
                        x,
                        "must be finite",
                    ));
                }
            }
        }
        self.shape.validate(&what)
    }

    /// The obstacle's shape and its pose in the robot's root frame (call
    /// [`SceneObstacle::validate`] first).
    pub fn placed(&self) -> (Shape, Frame) {
        (
            self.shape,
            Frame::from_xyz_rpy(self.pose.xyz, self.pose.rpy),
        )
    }
}
