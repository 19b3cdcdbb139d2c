//! A planned trajectory as records (`helixreach plan --out/--json`, the demo's `trajectory.csv`
//! and `trajectory.json`).
//!
//! - CSV: one [`TrajectoryRecord`] per sample, columns [`trajectory_header`]:
//!   `t,q0..q{n-1},motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase` (the tool pose in the robot
//!   base frame, the quaternion scalar first; numbers by [`fmt_real`](super::fmt_real)). Read back by
//!   [`read_trajectory`](super::read_trajectory) (the figure),
//!   `plot::render::input::read_trajectory` (the rendering) and
//!   [`crate::planning::check::JointFile`] (`check --joints`), all by the column names
//!   [`joint_column`], [`MOTOR_COLUMN`] and [`POSE_COLUMNS`].
//! - JSON: [`JointTrajectoryDoc`], shaped like ROS `trajectory_msgs/JointTrajectory` (the motor the
//!   last joint); object keys in alphabetical order, as `serde_json` writes its maps.

use super::csv_out;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::trajectory::{RayOutcome, Trajectory, TrajectoryPoint};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The name of joint column `j` (`q0`, `q1`, …).
pub fn joint_column(j: usize) -> String {
    format!("q{j}")
}

/// The motor column.
pub const MOTOR_COLUMN: &str = "motor";

/// The columns after `t,q0..q{n-1}`, in order.
pub const POSE_COLUMNS: [&str; 13] = [
    MOTOR_COLUMN,
    "s",
    "kappa",
    "tau",
    "omega",
    "x",
    "y",
    "z",
    "qw",
    "qx",
    "qy",
    "qz",
    "phase",
];

/// The CSV header of a trajectory with `dof` joints.
pub fn trajectory_header(dof: usize) -> Vec<String> {
    let mut h = vec!["t".to_string()];
    h.extend((0..dof).map(joint_column));
    h.extend(POSE_COLUMNS.iter().map(|s| s.to_string()));
    h
}

/// One sample of a trajectory CSV (columns [`trajectory_header`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrajectoryRecord<'a> {
    /// Time from start (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Joint angles (rad), one column each.
    #[serde(serialize_with = "csv_out::reals")]
    pub q: &'a [Real],
    /// Motor angle (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub motor: Real,
    /// Distance along the ray.
    #[serde(serialize_with = "csv_out::real")]
    pub s: Real,
    /// κ.
    #[serde(serialize_with = "csv_out::real")]
    pub kappa: Real,
    /// τ.
    #[serde(serialize_with = "csv_out::real")]
    pub tau: Real,
    /// ω.
    #[serde(serialize_with = "csv_out::real")]
    pub omega: Real,
    /// Tool position x (m, base frame).
    #[serde(serialize_with = "csv_out::real")]
    pub x: Real,
    /// Tool position y (m).
    #[serde(serialize_with = "csv_out::real")]
    pub y: Real,
    /// Tool position z (m).
    #[serde(serialize_with = "csv_out::real")]
    pub z: Real,
    /// Tool orientation quaternion, scalar part.
    #[serde(serialize_with = "csv_out::real")]
    pub qw: Real,
    /// Quaternion i.
    #[serde(serialize_with = "csv_out::real")]
    pub qx: Real,
    /// Quaternion j.
    #[serde(serialize_with = "csv_out::real")]
    pub qy: Real,
    /// Quaternion k.
    #[serde(serialize_with = "csv_out::real")]
    pub qz: Real,
    /// `load`, `reconfigure`, `hold` or `unload`.
    pub phase: &'static str,
}

impl<'a> From<&'a TrajectoryPoint> for TrajectoryRecord<'a> {
    fn from(p: &'a TrajectoryPoint) -> Self {
        let tr = p.pose.translation.vector;
        let r = p.pose.rotation.quaternion();
        TrajectoryRecord {
            t: p.t,
            q: &p.q,
            motor: p.motor,
            s: p.s,
            kappa: p.kto[0],
            tau: p.kto[1],
            omega: p.kto[2],
            x: tr.x,
            y: tr.y,
            z: tr.z,
            qw: r.w,
            qx: r.i,
            qy: r.j,
            qz: r.k,
            phase: p.phase.as_str(),
        }
    }
}

/// The CSV text of `traj`: [`trajectory_header`], one [`TrajectoryRecord`] per point. Every point
/// must have as many joints as the first (else an error naming the point).
pub fn trajectory_csv(traj: &Trajectory) -> Result<String> {
    let dof = traj
        .points
        .first()
        .map_or(traj.joint_names.len(), |p| p.q.len());
    if let Some((k, p)) = traj
        .points
        .iter()
        .enumerate()
        .find(|(_, p)| p.q.len() != dof)
    {
        return Err(Error::invalid(
            format!("trajectory point {k}"),
            p.q.len(),
            format!("joints, the first point has {dof}"),
        ));
    }
    let rows: Vec<TrajectoryRecord<'_>> = traj.points.iter().map(Into::into).collect();
    let header = trajectory_header(dof);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    csv_out::to_csv_with(&header, &rows)
}

/// The sidecar of a trajectory output `F`: `F.meta.json` (see [`TrajectoryMeta`]).
pub fn meta_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_os_string();
    name.push(".meta.json");
    PathBuf::from(name)
}

/// One run of consecutive points of the same phase (the phase annotation of a trajectory).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseSpan {
    /// `load`, `reconfigure`, `hold` or `unload`.
    pub phase: &'static str,
    /// Index of its first point (0-based).
    pub first_point: usize,
    /// Index of its last point.
    pub last_point: usize,
    /// Time of its first point (s).
    pub t_start: Real,
    /// Time of its last point (s).
    pub t_end: Real,
}

/// The phases of `traj` as runs of points ([`PhaseSpan`]), in time order.
pub fn phase_spans(traj: &Trajectory) -> Vec<PhaseSpan> {
    let mut spans: Vec<PhaseSpan> = Vec::new();
    for (k, p) in traj.points.iter().enumerate() {
        match spans.last_mut() {
            Some(s) if s.phase == p.phase.as_str() => {
                s.last_point = k;
                s.t_end = p.t;
            }
            _ => spans.push(PhaseSpan {
                phase: p.phase.as_str(),
                first_point: k,
                last_point: k,
                t_start: p.t,
                t_end: p.t,
            }),
        }
    }
    spans
}

/// The sidecar `F.meta.json` of every trajectory output `F`: what the trajectory was planned for
/// and how far it goes ([`RayOutcome`]: `direction`, `azimuth`, `s_star`, `s_target`,
/// `s_reached`, `class`, `cause`), its joints and frame, its duration and point count, and the
/// phase annotation (`phases`, [`PhaseSpan`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrajectoryMeta<'a> {
    /// Always `helixreach trajectory`.
    pub format: &'static str,
    /// The ray and how far the trajectory drives it (flattened into this object).
    #[serde(flatten)]
    pub outcome: &'a RayOutcome,
    /// The robot base frame.
    pub frame_id: &'a str,
    /// Arm joint names (URDF), the order of the joint columns.
    pub joint_names: &'a [String],
    /// The rod motor's joint name.
    pub motor_name: &'a str,
    /// Number of points.
    pub points: usize,
    /// Time of the last point (s).
    pub duration: Real,
    /// The phases as runs of points.
    pub phases: Vec<PhaseSpan>,
}

/// The pretty-printed sidecar text of `traj` ([`TrajectoryMeta`]).
pub fn trajectory_meta_json(traj: &Trajectory) -> Result<String> {
    let meta = TrajectoryMeta {
        format: "helixreach trajectory",
        outcome: &traj.outcome,
        frame_id: &traj.frame_id,
        joint_names: &traj.joint_names,
        motor_name: &traj.motor_name,
        points: traj.points.len(),
        duration: traj.duration(),
        phases: phase_spans(traj),
    };
    serde_json::to_string_pretty(&meta)
        .map_err(|e| Error::invalid("trajectory meta json", "", e.to_string()))
}

/// The JSON document of a trajectory (ROS `trajectory_msgs/JointTrajectory` shape).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectoryDoc {
    /// The frame of the poses.
    pub header: JsonHeader,
    /// Arm joints, then the motor.
    pub joint_names: Vec<String>,
    /// One entry per sample.
    pub points: Vec<JsonPoint>,
}

/// `header` of [`JointTrajectoryDoc`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JsonHeader {
    /// The robot base frame name.
    pub frame_id: String,
}

/// One point of [`JointTrajectoryDoc`] (fields in alphabetical order: the key order written).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JsonPoint {
    /// `load`, `reconfigure`, `hold` or `unload`.
    pub phase: &'static str,
    /// Joint angles, then the motor (rad).
    pub positions: Vec<Real>,
    /// Time from start, split as ROS `duration`.
    pub time_from_start: JsonDuration,
    /// Joint and motor velocities (rad/s), [`Trajectory::velocities`].
    pub velocities: Vec<Real>,
}

/// A ROS `duration`: whole seconds and nanoseconds (fields in alphabetical order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct JsonDuration {
    /// Nanoseconds, 0..=999,999,999.
    pub nsecs: i64,
    /// Whole seconds.
    pub secs: i64,
}

impl JsonDuration {
    /// `t` seconds (finite, ≥ 0) as whole seconds and the rounded nanoseconds (at most
    /// 999,999,999, so a time just below a whole second is not written as 10⁹ ns).
    pub fn of(t: Real) -> JsonDuration {
        let secs = t.floor();
        let nsecs = ((t - secs) * 1e9).round().min(999_999_999.0);
        JsonDuration {
            nsecs: nsecs as i64,
            secs: secs as i64,
        }
    }
}

impl JointTrajectoryDoc {
    /// The document of `traj`.
    pub fn new(traj: &Trajectory) -> JointTrajectoryDoc {
        let mut joint_names = traj.joint_names.clone();
        joint_names.push(traj.motor_name.clone());
        let points = traj
            .points
            .iter()
            .zip(traj.velocities())
            .map(|(p, velocities)| {
                let mut positions = p.q.clone();
                positions.push(p.motor);
                JsonPoint {
                    phase: p.phase.as_str(),
                    positions,
                    time_from_start: JsonDuration::of(p.t),
                    velocities,
                }
            })
            .collect();
        JointTrajectoryDoc {
            header: JsonHeader {
                frame_id: traj.frame_id.clone(),
            },
            joint_names,
            points,
        }
    }
}

/// The pretty-printed JSON text of `traj` ([`JointTrajectoryDoc`]).
pub fn trajectory_json(traj: &Trajectory) -> Result<String> {
    serde_json::to_string_pretty(&JointTrajectoryDoc::new(traj))
        .map_err(|e| Error::invalid("trajectory json", "", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Iso3, Quat, Vec3};
    use crate::planning::check::JointFile;
    use crate::planning::trajectory::Phase;

    fn traj() -> Trajectory {
        let phases = [Phase::Load, Phase::Reconfigure, Phase::Hold, Phase::Unload];
        let points = (0..4)
            .map(|k| {
                let x = k as Real / 3.0;
                TrajectoryPoint {
                    t: 0.1 + 1.7 * x,
                    q: vec![x, -2.0 * x + 1e-17, 1.0 / (1.0 + x)],
                    motor: 0.3 * x - 0.7,
                    s: 7.0 * x,
                    kto: [6.0 * x, 2.0 * x, -3.0 * x],
                    pose: Iso3::from_parts(
                        Vec3::new(0.8 + x, -0.15, 0.366 * x).into(),
                        Quat::from_axis_angle(&Vec3::y_axis(), x),
                    ),
                    phase: phases[k],
                }
            })
            .collect();
        Trajectory {
            joint_names: vec!["a".into(), "b".into(), "c".into()],
            motor_name: "rod_motor".into(),
            frame_id: "base".into(),
            points,
            outcome: RayOutcome {
                direction: [0.6, 0.0, 0.8],
                azimuth: 0.0,
                s_star: f64::INFINITY,
                s_target: 7.0,
                s_reached: 7.0,
                class: crate::planning::planner::ReachClass::Testable,
                cause: None,
            },
        }
    }

    /// What the writer writes, helixreach's three trajectory readers read back bit for bit.
    #[test]
    fn the_readers_read_back_what_is_written() {
        let tr = traj();
        let text = trajectory_csv(&tr).unwrap();
        assert!(text.starts_with(
            "t,q0,q1,q2,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase\n0.1,0,0.00000000000000001,1,"
        ));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        std::fs::write(&path, &text).unwrap();

        let rows = super::super::read_trajectory(&path).unwrap();
        let names = tr.joint_names.clone();
        #[cfg(feature = "plots")]
        let rendered = crate::plot::render::input::read_trajectory(&path, &names, "r").unwrap();
        let joints = JointFile::parse(&text, &path, &names).unwrap();
        assert_eq!(joints.format, "csv header: q0..");
        for (k, p) in tr.points.iter().enumerate() {
            assert_eq!(rows[k].q, p.q);
            assert_eq!(rows[k].t.to_bits(), p.t.to_bits());
            assert_eq!(rows[k].s.to_bits(), p.s.to_bits());
            assert_eq!(rows[k].motor.to_bits(), p.motor.to_bits());
            #[cfg(feature = "plots")]
            {
                assert_eq!(rendered[k].q, p.q);
                assert_eq!(rendered[k].kto, p.kto);
                assert_eq!(rendered[k].phase, Some(p.phase));
                assert_eq!(rendered[k].end.unwrap(), p.pose.translation.vector);
            }
            assert_eq!(joints.row(k), p.q.as_slice());
            assert_eq!(
                joints.motor.as_ref().unwrap()[k].to_bits(),
                p.motor.to_bits()
            );
        }
    }

    /// The JSON: key order and values as the ROS message reads them; the time split never
    /// writes 10⁹ ns.
    #[test]
    fn json_shape_and_duration_split() {
        let tr = traj();
        let text = trajectory_json(&tr).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["joint_names"][3], "rod_motor");
        assert_eq!(v["header"]["frame_id"], "base");
        let last = &v["points"][3];
        assert_eq!(last["phase"], "unload");
        // serde_json's reader rounds within an ulp (no `float_roundtrip`); the text is exact.
        let m = tr.points[3].motor;
        assert!((last["positions"][3].as_f64().unwrap() - m).abs() <= m.abs() * Real::EPSILON);
        assert!(text.contains(&format!(" {m}\n")), "{m}");
        assert_eq!(last["time_from_start"]["secs"], 1);
        let i_phase = text.find("\"phase\"").unwrap();
        let i_pos = text.find("\"positions\"").unwrap();
        let i_time = text.find("\"time_from_start\"").unwrap();
        let i_vel = text.find("\"velocities\"").unwrap();
        assert!(i_phase < i_pos && i_pos < i_time && i_time < i_vel);
        assert!(text.find("\"nsecs\"").unwrap() < text.find("\"secs\"").unwrap());
        assert_eq!(
            JsonDuration::of(2.9999999999),
            JsonDuration {
                nsecs: 999_999_999,
                secs: 2
            }
        );
        assert_eq!(
            JsonDuration::of(1.25),
            JsonDuration {
                nsecs: 250_000_000,
                secs: 1
            }
        );
    }

    /// The sidecar names how far the trajectory goes and its phases as runs of points.
    #[test]
    fn sidecar_outcome_and_phase_runs() {
        let mut tr = traj();
        tr.outcome.class = crate::planning::planner::ReachClass::Partial;
        tr.outcome.cause = Some(crate::planning::ladder::BlockCause::NoIk);
        tr.outcome.s_reached = 2.5;
        tr.points[2].phase = Phase::Reconfigure;
        let v: serde_json::Value =
            serde_json::from_str(&trajectory_meta_json(&tr).unwrap()).unwrap();
        assert_eq!(v["class"], "partial");
        assert_eq!(v["cause"], "no_ik");
        assert_eq!(v["s_reached"], 2.5);
        assert_eq!(v["s_target"], 7.0);
        assert!(v["s_star"].is_null());
        assert_eq!(v["joint_names"][2], "c");
        let ph = v["phases"].as_array().unwrap();
        let runs: Vec<(&str, u64, u64)> = ph
            .iter()
            .map(|p| {
                (
                    p["phase"].as_str().unwrap(),
                    p["first_point"].as_u64().unwrap(),
                    p["last_point"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(
            runs,
            [("load", 0, 0), ("reconfigure", 1, 2), ("unload", 3, 3)]
        );
        assert_eq!(
            meta_path(Path::new("a/b.csv")),
            PathBuf::from("a/b.csv.meta.json")
        );
    }

    /// A point with another joint count is an error naming it, not a ragged CSV.
    #[test]
    fn ragged_points_are_refused() {
        let mut tr = traj();
        tr.points[2].q.pop();
        let e = trajectory_csv(&tr).unwrap_err().to_string();
        assert!(e.contains("trajectory point 2"), "{e}");
    }
}
