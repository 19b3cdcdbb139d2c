//! Writing a [`Rig`] back as rig TOML (the format [`Rig::from_toml_str`] reads), e.g. one rig
//! file per clamp placement chosen by `helixreach layout`.
//!
//! Every field the loader reads is written, so that loading the text gives the same rig: the
//! clamp as `origin`, `d1`, `d3`; the tool as `xyz` + `rpy` (nalgebra's roll-pitch-yaw, the
//! loader's convention); the rod as `radius`; the motor range only where finite; the azimuths as
//! `choices`; the maximum end angle in degrees. Floats are written in shortest round-trip form.
//! A relative URDF path is made absolute (the new file may live elsewhere); a built-in robot
//! name stays a name.
//!
//! ```
//! use helixreach::planning::rig::Rig;
//! let rig = Rig::load("sawyer-seed").unwrap();
//! let text = rig.to_toml().unwrap();
//! let back = Rig::from_toml_str(&text, "copy.toml", std::path::Path::new(".")).unwrap();
//! assert_eq!(back.clamp, rig.clamp);
//! assert_eq!(back.planner, rig.planner);
//! ```

use crate::error::{Error, Result};
use crate::math::{Real, DEG};
use crate::planning::rig::Rig;
use crate::robot::SceneObstacle;
use serde::Serialize;
use std::path::Path;

#[derive(Serialize)]
struct OutRig<'a> {
    name: &'a str,
    description: &'a str,
    robot: OutRobot,
    tool: OutTool,
    clamp: OutClamp,
    rod: OutRod,
    motor: OutMotor,
    roll: OutRoll,
    azimuth: OutAzimuth<'a>,
    planner: OutPlanner<'a>,
    #[serde(rename = "obstacle")]
    obstacles: &'a [SceneObstacle],
}

#[derive(Serialize)]
struct OutRobot {
    urdf: String,
    tip_link: String,
}

#[derive(Serialize)]
struct OutTool {
    xyz: [Real; 3],
    rpy: [Real; 3],
}

#[derive(Serialize)]
struct OutClamp {
    origin: [Real; 3],
    d1: [Real; 3],
    d3: [Real; 3],
}

#[derive(Serialize)]
struct OutRod {
    length: Real,
    radius: Real,
    youngs_modulus: Real,
    poisson: Real,
    density: Real,
}

#[derive(Serialize)]
struct OutMotor {
    max_velocity: Real,
    max_acceleration: Real,
    #[serde(skip_serializing_if = "Option::is_none")]
    lower: Option<Real>,
    #[serde(skip_serializing_if = "Option::is_none")]
    upper: Option<Real>,
}

#[derive(Serialize)]
struct OutRoll {
    mode: &'static str,
    samples: usize,
}

#[derive(Serialize)]
struct OutAzimuth<'a> {
    choices: &'a [Real],
}

#[derive(Serialize)]
struct OutPlanner<'a> {
    margin: Real,
    #[serde(skip_serializing_if = "Option::is_none")]
    margin_supercritical: Option<Real>,
    max_end_step: Real,
    max_end_angle_deg: Real,
    waypoints: usize,
    max_waypoints: usize,
    max_joint_step: Real,
    redundancy_samples: usize,
    dense_samples: usize,
    segment_check_step: Real,
    rod_capsules: usize,
    rod_clearance: Real,
    rod_end_exclusion: Real,
    end_speed: Real,
    velocity_scale: Real,
    #[serde(skip_serializing_if = "<[Real]>::is_empty")]
    joint_acceleration: &'a [Real],
    acceleration_scale: Real,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_ray_speed: Option<Real>,
    #[serde(skip_serializing_if = "<[Real]>::is_empty")]
    joint_weights: &'a [Real],
    motor_weight: Real,
    allow_reconfiguration: bool,
    self_motion_step: Real,
    hold_time: Real,
    search: &'static str,
    allow_backoff: bool,
    max_search_nodes: usize,
    bridge_halvings: usize,
    search_step: Real,
}

fn arr(v: &crate::math::Vec3) -> [Real; 3] {
    [v.x, v.y, v.z]
}

impl Rig {
    /// The rig as TOML text that [`Rig::from_toml_str`] loads back to the same rig (see the
    /// module docs). Errors only if a value cannot be represented (a non-finite number).
    pub fn to_toml(&self) -> Result<String> {
        let rc = self.clamp_rotation();
        let (r, p, y) = self.tool.rotation.euler_angles();
        let urdf = {
            let path = Path::new(&self.robot.urdf);
            let resolved = self.robot.dir.join(path);
            if !path.is_absolute() && resolved.is_file() {
                resolved
                    .canonicalize()
                    .unwrap_or(resolved)
                    .display()
                    .to_string()
            } else {
                self.robot.urdf.clone()
            }
        };
        let finite = |x: Real| x.is_finite().then_some(x);
        let pl = &self.planner;
        let out = OutRig {
            name: &self.name,
            description: &self.description,
            robot: OutRobot {
                urdf,
                tip_link: self.robot.tip_link.clone(),
            },
            tool: OutTool {
                xyz: arr(&self.tool.translation.vector),
                rpy: [r, p, y],
            },
            clamp: OutClamp {
                origin: arr(&self.clamp.translation.vector),
                d1: arr(&rc.column(0).into_owned()),
                d3: arr(&rc.column(2).into_owned()),
            },
            rod: OutRod {
                length: self.rod.length,
                radius: self.rod.radius,
                youngs_modulus: self.rod.youngs_modulus,
                poisson: self.rod.nu,
                density: self.rod.density,
            },
            motor: OutMotor {
                max_velocity: self.motor.max_velocity,
                max_acceleration: self.motor.max_acceleration,
                lower: finite(self.motor.range.0),
                upper: finite(self.motor.range.1),
            },
            roll: OutRoll {
                mode: self.roll.as_str(),
                samples: self.roll_samples,
            },
            azimuth: OutAzimuth {
                choices: &self.azimuths,
            },
            planner: OutPlanner {
                margin: pl.margin,
                margin_supercritical: pl.margin_supercritical,
                max_end_step: pl.max_end_step,
                max_end_angle_deg: pl.max_end_angle / DEG,
                waypoints: pl.waypoints,
                max_waypoints: pl.max_waypoints,
                max_joint_step: pl.max_joint_step,
                redundancy_samples: pl.redundancy_samples,
                dense_samples: pl.dense_samples,
                segment_check_step: pl.segment_check_step,
                rod_capsules: pl.rod_capsules,
                rod_clearance: pl.rod_clearance,
                rod_end_exclusion: pl.rod_end_exclusion,
                end_speed: pl.end_speed,
                velocity_scale: pl.velocity_scale,
                joint_acceleration: &pl.joint_acceleration,
                acceleration_scale: pl.acceleration_scale,
                max_ray_speed: finite(pl.max_ray_speed),
                joint_weights: &pl.joint_weights,
                motor_weight: pl.motor_weight,
                allow_reconfiguration: pl.allow_reconfiguration,
                self_motion_step: pl.self_motion_step,
                hold_time: pl.hold_time,
                search: pl.search.as_str(),
                allow_backoff: pl.allow_backoff,
                max_search_nodes: pl.max_search_nodes,
                bridge_halvings: pl.bridge_halvings,
                search_step: pl.search_step,
            },
            obstacles: &self.obstacles,
        };
        toml::to_string(&out).map_err(|e| Error::invalid("rig", &self.name, e.to_string()))
    }
}
