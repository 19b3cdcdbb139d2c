//! A trajectory as a ROS 2 bag: one MCAP file (profile `ros2`, messages CDR-encoded) that
//! `ros2 bag play`/`ros2 bag info` and any MCAP reader take, written by the `mcap` crate.
//!
//! # Topics
//! - [`ARM_TOPIC`]: the arm's `trajectory_msgs/msg/JointTrajectory` ([`Channels::Arm`], URDF
//!   joint names) — what an arm's `FollowJointTrajectory` controller takes;
//! - [`MOTOR_TOPIC`]: the rod motor's own `JointTrajectory` ([`Channels::Motor`], its own joint
//!   name), for the motor's controller;
//! - [`META_TOPIC`]: a `std_msgs/msg/String` holding the sidecar JSON ([`TrajectoryMeta`](super::trajectory::TrajectoryMeta):
//!   class, cause, s_reached, s_target, the phases as runs of points) — the phase annotation.
//!
//! One message per topic, logged at time 0.
//!
//! # CDR
//! The two message types are fixed and small, so their CDR (little endian, encapsulation
//! `00 01 00 00`, primitives aligned to their size from the end of the encapsulation header,
//! strings as a `uint32` length counting the NUL, then the bytes and the NUL; sequences as a
//! `uint32` count then the elements) is written here directly rather than through a serde CDR
//! crate; CI reads the bag back with an independent reader (Python `mcap` + `rosbags`' ROS 2
//! type store, `.ci/check_bag.py`) and compares it with the CSV.

use super::trajectory::{trajectory_meta_json, Channels, JointTrajectoryMsg};
use crate::error::{Error, Result};
use crate::planning::trajectory::Trajectory;
use std::collections::BTreeMap;
use std::io::Cursor;

/// The arm's trajectory topic.
pub const ARM_TOPIC: &str = "/helixreach/arm/joint_trajectory";
/// The rod motor's trajectory topic.
pub const MOTOR_TOPIC: &str = "/helixreach/rod_motor/joint_trajectory";
/// The annotation topic (the sidecar JSON: outcome and phases).
pub const META_TOPIC: &str = "/helixreach/trajectory_meta";

/// The `ros2msg` schema of `trajectory_msgs/msg/JointTrajectory` with its dependencies.
pub const JOINT_TRAJECTORY_SCHEMA: &str = "std_msgs/Header header
string[] joint_names
JointTrajectoryPoint[] points
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: trajectory_msgs/JointTrajectoryPoint
float64[] positions
float64[] velocities
float64[] accelerations
float64[] effort
builtin_interfaces/Duration time_from_start
================================================================================
MSG: builtin_interfaces/Duration
int32 sec
uint32 nanosec
";

/// The `ros2msg` schema of `std_msgs/msg/String`.
pub const STRING_SCHEMA: &str = "string data\n";

/// A little-endian CDR buffer (see the module docs).
struct Cdr {
    buf: Vec<u8>,
}

impl Cdr {
    fn new() -> Cdr {
        Cdr {
            buf: vec![0x00, 0x01, 0x00, 0x00],
        }
    }
    fn align(&mut self, n: usize) {
        while (self.buf.len() - 4) % n != 0 {
            self.buf.push(0);
        }
    }
    fn u32(&mut self, v: u32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    fn i32(&mut self, v: i32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }
    fn len(&mut self, n: usize) -> Result<()> {
        let n = u32::try_from(n).map_err(|_| Error::invalid("CDR sequence", n, "too long"))?;
        self.u32(n);
        Ok(())
    }
    fn string(&mut self, s: &str) -> Result<()> {
        self.len(s.len() + 1)?;
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
        Ok(())
    }
    fn reals(&mut self, v: &[f64]) -> Result<()> {
        self.len(v.len())?;
        if !v.is_empty() {
            self.align(8);
        }
        for x in v {
            self.buf.extend_from_slice(&x.to_le_bytes());
        }
        Ok(())
    }
}

/// The CDR bytes of a `trajectory_msgs/msg/JointTrajectory`.
pub fn joint_trajectory_cdr(msg: &JointTrajectoryMsg) -> Result<Vec<u8>> {
    let mut c = Cdr::new();
    c.i32(msg.header.stamp.sec);
    c.u32(msg.header.stamp.nanosec);
    c.string(&msg.header.frame_id)?;
    c.len(msg.joint_names.len())?;
    for n in &msg.joint_names {
        c.string(n)?;
    }
    c.len(msg.points.len())?;
    for p in &msg.points {
        c.reals(&p.positions)?;
        c.reals(&p.velocities)?;
        c.reals(&p.accelerations)?;
        c.reals(&p.effort)?;
        c.i32(p.time_from_start.sec);
        c.u32(p.time_from_start.nanosec);
    }
    Ok(c.buf)
}

/// The CDR bytes of a `std_msgs/msg/String`.
pub fn string_cdr(s: &str) -> Result<Vec<u8>> {
    let mut c = Cdr::new();
    c.string(s)?;
    Ok(c.buf)
}

/// The MCAP bytes of `traj` (see the module docs).
pub fn trajectory_bag(traj: &Trajectory) -> Result<Vec<u8>> {
    let err = |e: mcap::McapError| Error::invalid("ROS 2 bag", "mcap", e.to_string());
    let arm = joint_trajectory_cdr(&JointTrajectoryMsg::new(traj, Channels::Arm)?)?;
    let motor = joint_trajectory_cdr(&JointTrajectoryMsg::new(traj, Channels::Motor)?)?;
    let meta = string_cdr(&trajectory_meta_json(traj)?)?;
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .profile("ros2")
        .library("helixreach")
        .create(Cursor::new(Vec::new()))
        .map_err(err)?;
    let traj_schema = w
        .add_schema(
            "trajectory_msgs/msg/JointTrajectory",
            "ros2msg",
            JOINT_TRAJECTORY_SCHEMA.as_bytes(),
        )
        .map_err(err)?;
    let string_schema = w
        .add_schema("std_msgs/msg/String", "ros2msg", STRING_SCHEMA.as_bytes())
        .map_err(err)?;
    let none = BTreeMap::new();
    for (schema, topic, data) in [
        (traj_schema, ARM_TOPIC, &arm),
        (traj_schema, MOTOR_TOPIC, &motor),
        (string_schema, META_TOPIC, &meta),
    ] {
        let channel_id = w.add_channel(schema, topic, "cdr", &none).map_err(err)?;
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id,
                sequence: 0,
                log_time: 0,
                publish_time: 0,
            },
            data,
        )
        .map_err(err)?;
    }
    w.finish().map_err(err)?;
    Ok(w.into_inner().into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CDR layout by hand: header, alignment of the float64 sequences, the NUL-terminated
    /// strings.
    #[test]
    fn cdr_layout() {
        let b = string_cdr("ab").unwrap();
        assert_eq!(b, [0, 1, 0, 0, 3, 0, 0, 0, b'a', b'b', 0]);
        let mut c = Cdr::new();
        c.string("x").unwrap(); // 4 + 2 bytes: offset 6
        c.reals(&[1.5]).unwrap(); // count at 8, the double aligned to 16
        assert_eq!(c.buf.len(), 4 + 16 + 8);
        assert_eq!(&c.buf[4 + 8..4 + 12], &1u32.to_le_bytes());
        assert_eq!(&c.buf[4 + 16..], &1.5f64.to_le_bytes());
    }
}
