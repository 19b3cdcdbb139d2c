//! A planned trajectory as records (`helixreach plan --out/--json`, the demo's `trajectory.csv`
//! and `trajectory.json`).
//!
//! - CSV: one [`TrajectoryRecord`] per sample, columns [`trajectory_header`]:
//!   `t,<joint names>,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase`, then `v_<joint>..,v_motor`
//!   and `a_<joint>..,a_motor` (the joints by their URDF names, as in the JSON and the sidecar;
//!   the tool pose in the robot base frame, the quaternion scalar first; numbers by
//!   [`fmt_real`](super::fmt_real)). Read back by the one trajectory reader
//!   ([`read_trajectory_file`], below) for the figure ([`read_trajectory`](super::read_trajectory)),
//!   the rendering (`plot::render::input::read_trajectory`) and the check ([`read_joint_file`],
//!   `check --trajectory`, the campaign's run files, the seed's runs), all by the column names
//!   ([`joint_columns`], [`MOTOR_COLUMN`], [`POSE_COLUMNS`]). Every reader also accepts the
//!   index header, which names the joints `q0..q{n-1}` ([`joint_column`]).
//! - JSON / YAML: [`JointTrajectoryMsg`], exactly ROS 2 `trajectory_msgs/msg/JointTrajectory`
//!   (fields in the message's order; `time_from_start {sec, nanosec}`; positions, velocities,
//!   accelerations, an empty effort), for the arm alone ([`Channels::Arm`], URDF joint names)
//!   or the rod motor alone ([`Channels::Motor`]). No extra keys: what the trajectory was planned
//!   for and its phases are in the sidecar `F.meta.json` ([`TrajectoryMeta`]).
//!
//! # The trajectory reader ([`read_trajectory_file`])
//! One configuration per line, in any of three forms (blank lines and `#` comment lines are
//! skipped; a UTF-8 byte-order mark is ignored):
//! - **whitespace numbers**, exactly one per joint (the seed's `trajectories/*.txt`);
//! - **CSV without header**, exactly one number per joint;
//! - **CSV with a header** (a first line with a field that is not a number): the joints by the
//!   robot's joint names (any order; a MoveIt export, `plan`'s CSV) or `q0..q{n-1}` (the index
//!   header); `t` (or `time`, non-decreasing), `motor`, `s` (≥ 0), `kappa,tau,omega` (κ̂ ≥ 0),
//!   `x,y,z`, `azimuth` and `phase` are read when present, other columns ignored. A column
//!   named twice is refused.
//!
//! Without a robot (`joint_names` empty) a header is required and the joints are `q0, q1, …` or
//! the columns before `motor` but `t`/`time`. Every row has as many fields as the header (or
//! as joints); every value read is a finite number. At most
//! [`MAX_TRAJECTORY_ROWS`] rows. Errors name the file, the
//! 1-based line, the column and the text. Cost: one pass over the text, O(rows × columns).

use super::csv_out;
use crate::error::{Error, Result};
use crate::limits::MAX_TRAJECTORY_ROWS;
use crate::math::{Real, Vec3};
use crate::planning::check::JointFile;
use crate::planning::trajectory::{Phase, RayOutcome, Trajectory, TrajectoryPoint};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The earlier name of joint column `j` (`q0`, `q1`, …), before the header named the joints;
/// still read everywhere.
pub fn joint_column(j: usize) -> String {
    format!("q{j}")
}

/// Which header named the joint columns ([`joint_columns`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointHeader {
    /// The robot's joint names (what [`trajectory_csv`] writes).
    Names,
    /// `q0, q1, …` (the index header).
    Indexed,
    /// No robot given: the columns before `motor`, `t` (or `time`) aside.
    BeforeMotor,
}

/// The columns of the joints in a trajectory CSV `header`, in joint order.
///
/// With `joint_names` (the robot's, in chain order): every name found → those columns;
/// otherwise `q0, q1, …` up to the first missing index (the caller compares the count with the
/// robot's). Without (`&[]`): `q0, q1, …`; otherwise the columns before `motor` but `t`/`time`.
/// `None` when nothing matches.
pub fn joint_columns(
    header: &[impl AsRef<str>],
    joint_names: &[String],
) -> Option<(Vec<usize>, JointHeader)> {
    let find = |name: &str| header.iter().position(|h| h.as_ref() == name);
    if !joint_names.is_empty() {
        if let Some(c) = joint_names
            .iter()
            .map(|n| find(n))
            .collect::<Option<Vec<_>>>()
        {
            return Some((c, JointHeader::Names));
        }
    }
    let mut indexed = Vec::new();
    while let Some(c) = find(&joint_column(indexed.len())) {
        indexed.push(c);
    }
    if !indexed.is_empty() {
        return Some((indexed, JointHeader::Indexed));
    }
    if !joint_names.is_empty() {
        return None;
    }
    let motor = find(MOTOR_COLUMN)?;
    let before: Vec<usize> = (0..motor)
        .filter(|&c| !matches!(header[c].as_ref(), "t" | "time"))
        .collect();
    (!before.is_empty()).then_some((before, JointHeader::BeforeMotor))
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

/// The CSV header of a trajectory of the joints `joint_names` (URDF names, chain order): `t`,
/// the joints, [`POSE_COLUMNS`], then the velocities `v_<joint>..,v_motor` (rad/s) and the
/// accelerations `a_<joint>..,a_motor` (rad/s²).
///
/// A name that cannot be a column is an error naming it: empty, with a comma, quote or line
/// break or surrounding spaces, a name the header has already (`t`, `motor`, `s`, `x`, … or
/// another joint's), or `q<k>` at another index than `k` (the index header's name of joint k).
pub fn trajectory_header(joint_names: &[String]) -> Result<Vec<String>> {
    let mut h = vec!["t".to_string()];
    h.extend(joint_names.iter().cloned());
    h.extend(POSE_COLUMNS.iter().map(|s| s.to_string()));
    for prefix in ["v_", "a_"] {
        h.extend(joint_names.iter().map(|n| format!("{prefix}{n}")));
        h.push(format!("{prefix}{MOTOR_COLUMN}"));
    }
    for (j, n) in joint_names.iter().enumerate() {
        let field = format!("joint {j} name");
        if n.is_empty() || n.trim() != n || n.contains([',', '"', '\n', '\r']) {
            return Err(Error::invalid(
                field,
                format!("{n:?}"),
                "cannot be a CSV column name (empty, spaces around it, or a comma, quote or line break)",
            ));
        }
        if h.iter().filter(|c| *c == n).count() > 1 {
            return Err(Error::invalid(
                field,
                n,
                "is also another column of the trajectory CSV header",
            ));
        }
        if let Some(k) = n.strip_prefix('q').and_then(|k| k.parse::<usize>().ok()) {
            if k != j {
                return Err(Error::invalid(
                    field,
                    n,
                    format!("is the earlier header's name of joint {k}: ambiguous"),
                ));
            }
        }
    }
    Ok(h)
}

/// One sample of a trajectory CSV (columns [`trajectory_header`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrajectoryRecord<'a> {
    /// Time from start (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Joint angles (rad), one column each (named by the joints).
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
    /// Joint velocities, then the motor's (rad/s).
    #[serde(serialize_with = "csv_out::reals")]
    pub velocity: &'a [Real],
    /// Joint accelerations, then the motor's (rad/s²).
    #[serde(serialize_with = "csv_out::reals")]
    pub acceleration: &'a [Real],
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
            velocity: &p.velocity,
            acceleration: &p.acceleration,
        }
    }
}

/// The CSV text of `traj`: [`trajectory_header`] of its joint names, one [`TrajectoryRecord`]
/// per point. Every point must have as many joints as the first and as `traj.joint_names` (else
/// an error naming the point).
pub fn trajectory_csv(traj: &Trajectory) -> Result<String> {
    let dof = traj
        .points
        .first()
        .map_or(traj.joint_names.len(), |p| p.q.len());
    if let Some((k, p)) = traj.points.iter().enumerate().find(|(_, p)| {
        p.q.len() != dof || p.velocity.len() != dof + 1 || p.acceleration.len() != dof + 1
    }) {
        return Err(Error::invalid(
            format!("trajectory point {k}"),
            p.q.len(),
            format!("joints (and velocities, accelerations: one more, the motor), the first point has {dof}"),
        ));
    }
    if traj.joint_names.len() != dof {
        return Err(Error::invalid(
            "trajectory joint names",
            traj.joint_names.len(),
            format!("names for {dof} joints"),
        ));
    }
    let rows: Vec<TrajectoryRecord<'_>> = traj.points.iter().map(Into::into).collect();
    let header = trajectory_header(&traj.joint_names)?;
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    csv_out::to_csv_with(&header, &rows)
}

/// The sidecar of a trajectory output `F`: `F.meta.json` (see [`TrajectoryMeta`]).
pub fn meta_path(path: &Path) -> PathBuf {
    crate::io::sidecar_path(path)
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

/// Which joints a [`JointTrajectoryMsg`] carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channels {
    /// The arm's joints (URDF names): what an arm's `FollowJointTrajectory` controller accepts.
    Arm,
    /// The rod motor alone (its own joint name).
    Motor,
}

/// ROS 2 `trajectory_msgs/msg/JointTrajectory`: exactly the message's fields, in its order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectoryMsg {
    /// `std_msgs/Header`.
    pub header: HeaderMsg,
    /// The joints, in the order of every point's arrays.
    pub joint_names: Vec<String>,
    /// One per sample.
    pub points: Vec<PointMsg>,
}

/// ROS 2 `std_msgs/msg/Header`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeaderMsg {
    /// `builtin_interfaces/Time` (zero: "start now" for a controller).
    pub stamp: DurationMsg,
    /// The robot base frame.
    pub frame_id: String,
}

/// ROS 2 `trajectory_msgs/msg/JointTrajectoryPoint`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointMsg {
    /// Positions (rad).
    pub positions: Vec<Real>,
    /// Velocities (rad/s).
    pub velocities: Vec<Real>,
    /// Accelerations (rad/s²).
    pub accelerations: Vec<Real>,
    /// Efforts: empty (not commanded).
    pub effort: Vec<Real>,
    /// Time from the start of the trajectory.
    pub time_from_start: DurationMsg,
}

/// ROS 2 `builtin_interfaces/msg/Duration` (and `Time`): whole seconds and nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct DurationMsg {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, 0..=999,999,999.
    pub nanosec: u32,
}

impl DurationMsg {
    /// `t` seconds (finite, ≥ 0, < 2³¹ s) as whole seconds and the rounded nanoseconds (at most
    /// 999,999,999, so a time just below a whole second is not written as 10⁹ ns).
    pub fn of(t: Real) -> DurationMsg {
        let secs = t.floor();
        let nanosec = ((t - secs) * 1e9).round().min(999_999_999.0);
        DurationMsg {
            sec: secs as i32,
            nanosec: nanosec as u32,
        }
    }

    /// Seconds.
    pub fn seconds(&self) -> Real {
        self.sec as Real + self.nanosec as Real * 1e-9
    }
}

impl JointTrajectoryMsg {
    /// The message of `traj`'s arm joints or of its motor. Errors when a time does not fit
    /// `int32` seconds.
    pub fn new(traj: &Trajectory, channels: Channels) -> Result<JointTrajectoryMsg> {
        let dof = traj.joint_names.len();
        let (joint_names, range) = match channels {
            Channels::Arm => (traj.joint_names.clone(), 0..dof),
            Channels::Motor => (vec![traj.motor_name.clone()], dof..dof + 1),
        };
        let mut points = Vec::with_capacity(traj.points.len());
        for (k, p) in traj.points.iter().enumerate() {
            if !(p.t >= 0.0 && p.t < i32::MAX as Real) {
                return Err(Error::invalid(
                    format!("trajectory point {k} time"),
                    p.t,
                    "must lie in [0, 2^31) s",
                ));
            }
            let pos = |c: usize| if c < dof { p.q[c] } else { p.motor };
            points.push(PointMsg {
                positions: range.clone().map(pos).collect(),
                velocities: p.velocity[range.clone()].to_vec(),
                accelerations: p.acceleration[range.clone()].to_vec(),
                effort: Vec::new(),
                time_from_start: DurationMsg::of(p.t),
            });
        }
        Ok(JointTrajectoryMsg {
            header: HeaderMsg {
                stamp: DurationMsg { sec: 0, nanosec: 0 },
                frame_id: traj.frame_id.clone(),
            },
            joint_names,
            points,
        })
    }
}

/// The pretty-printed JSON text of `traj`'s arm message ([`JointTrajectoryMsg`], [`Channels::Arm`]).
pub fn trajectory_json(traj: &Trajectory) -> Result<String> {
    message_json(&JointTrajectoryMsg::new(traj, Channels::Arm)?)
}

/// The pretty-printed JSON text of a message.
pub fn message_json(msg: &JointTrajectoryMsg) -> Result<String> {
    serde_json::to_string_pretty(msg)
        .map_err(|e| Error::invalid("trajectory json", "", e.to_string()))
}

/// A YAML float PyYAML (YAML 1.1, what `ros2 topic pub` reads) takes as a float: the shortest
/// round-trip decimal, never in exponent notation, with a `.0` when integral.
fn yaml_real(x: Real) -> String {
    let s = format!("{x}");
    if s.contains('.') {
        s
    } else {
        format!("{s}.0")
    }
}

fn yaml_list(v: &[Real]) -> String {
    let items: Vec<String> = v.iter().map(|x| yaml_real(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// The YAML of a message as `ros2 topic pub TOPIC trajectory_msgs/msg/JointTrajectory "$(cat F)"`
/// reads it; with `goal` = true, nested under `trajectory:` as a
/// `control_msgs/action/FollowJointTrajectory` goal (`ros2 action send_goal`) takes it.
pub fn message_yaml(msg: &JointTrajectoryMsg, goal: bool) -> String {
    let ind = if goal { "  " } else { "" };
    let mut y = String::new();
    if goal {
        y.push_str("trajectory:\n");
    }
    y.push_str(&format!(
        "{ind}header:\n{ind}  stamp: {{sec: 0, nanosec: 0}}\n{ind}  frame_id: \"{}\"\n",
        msg.header.frame_id
    ));
    let names: Vec<String> = msg.joint_names.iter().map(|n| format!("\"{n}\"")).collect();
    y.push_str(&format!(
        "{ind}joint_names: [{}]\n{ind}points:\n",
        names.join(", ")
    ));
    for p in &msg.points {
        y.push_str(&format!(
            "{ind}  - positions: {}\n{ind}    velocities: {}\n{ind}    accelerations: {}\n\
             {ind}    effort: []\n{ind}    time_from_start: {{sec: {}, nanosec: {}}}\n",
            yaml_list(&p.positions),
            yaml_list(&p.velocities),
            yaml_list(&p.accelerations),
            p.time_from_start.sec,
            p.time_from_start.nanosec
        ));
    }
    y
}

/// A trajectory file as read by [`read_trajectory_file`] (module docs): the joints of every row
/// and the other columns the file has.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryTable {
    /// The file.
    pub path: PathBuf,
    /// How it was read (`whitespace`, `csv`, `csv header: joint names`, `csv header: q0..`,
    /// `csv header: columns before motor`).
    pub format: String,
    /// The name of every joint column (the header's, or the robot's without a header).
    pub joint_names: Vec<String>,
    /// Joint values, row-major (`rows × joint_names.len()`).
    pub q: Vec<Real>,
    /// 1-based line of every row.
    pub lines: Vec<usize>,
    /// `t` (or `time`) of every row (s), non-decreasing.
    pub t: Option<Vec<Real>>,
    /// `motor` of every row (rad).
    pub motor: Option<Vec<Real>>,
    /// `s` of every row.
    pub s: Option<Vec<Real>>,
    /// `kappa,tau,omega` of every row.
    pub kto: Option<Vec<[Real; 3]>>,
    /// `x,y,z` of every row (the rod end in the base frame).
    pub end: Option<Vec<Vec3>>,
    /// `azimuth` of every row.
    pub azimuth: Option<Vec<Real>>,
    /// `phase` of every row.
    pub phase: Option<Vec<Phase>>,
}

impl TrajectoryTable {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// The joints of row `i`.
    pub fn row(&self, i: usize) -> &[Real] {
        let n = self.joint_names.len();
        &self.q[i * n..(i + 1) * n]
    }

    /// A [`Error::File`] naming this file.
    pub fn file_error(&self, reason: String) -> Error {
        Error::File {
            path: self.path.clone(),
            reason,
        }
    }
}

/// Read the trajectory file `path` for a robot whose joints are `joint_names` (`robot` names it
/// in errors; `&[]`: no robot), module docs.
pub fn read_trajectory_file(
    path: &Path,
    joint_names: &[String],
    robot: &str,
) -> Result<TrajectoryTable> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_trajectory_file(&text, path, joint_names, robot)
}

/// [`read_trajectory_file`] on text already read; `path` names it in errors.
pub fn parse_trajectory_file(
    text: &str,
    path: &Path,
    joint_names: &[String],
    robot: &str,
) -> Result<TrajectoryTable> {
    let robot = if robot.is_empty() {
        "the robot".to_string()
    } else {
        format!("robot {robot}")
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let bad = |line: usize, field: &str, reason: String| Error::BadLine {
        path: path.to_path_buf(),
        line,
        field: field.to_string(),
        reason,
    };
    let file_err = |reason: String| Error::File {
        path: path.to_path_buf(),
        reason,
    };
    let mut content = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .peekable();
    let Some(&(first_line, first)) = content.peek() else {
        return Err(file_err("empty file: no joint rows".into()));
    };
    let comma = first.contains(',');
    let unquote = |f: &str| -> String {
        let f = f.trim();
        match f.strip_prefix('"').and_then(|x| x.strip_suffix('"')) {
            Some(inner) => inner.to_string(),
            None => f.to_string(),
        }
    };
    let split = |l: &str| -> Vec<String> {
        if comma {
            l.split(',').map(unquote).collect()
        } else {
            l.split_whitespace().map(str::to_string).collect()
        }
    };
    let head = split(first);
    let has_header = head.iter().any(|f| f.parse::<Real>().is_err());
    let dof = joint_names.len();
    // Joint columns, their names, the named columns, the field count and the format.
    let (cols, names, header, n_fields, format) = if has_header {
        content.next();
        for (i, h) in head.iter().enumerate() {
            if let Some(j) = head.iter().take(i).position(|g| g == h) {
                return Err(bad(
                    first_line,
                    "header",
                    format!(
                        "column `{h}` appears twice (columns {} and {}): which one holds the \
                         values is ambiguous",
                        j + 1,
                        i + 1
                    ),
                ));
            }
        }
        let (cols, kind) = match joint_columns(&head, joint_names) {
            Some((c, k)) if dof == 0 || c.len() == dof => (c, k),
            Some((c, _)) => {
                return Err(file_err(format!(
                    "has {} joint columns (q0..q{}) but {robot} has {dof} joints ({}): the \
                     trajectory is for another robot",
                    c.len(),
                    c.len().saturating_sub(1),
                    joint_names.join(",")
                )))
            }
            None if dof == 0 => {
                return Err(file_err(format!(
                    "no joint columns: neither q0, q1, … nor joint columns before \
                     `{MOTOR_COLUMN}` (header: {})",
                    head.join(",")
                )))
            }
            None => {
                return Err(bad(
                    first_line,
                    "header",
                    format!(
                        "`{first}` names neither the {dof} joints of {robot} ({}) nor \
                         q0..q{}: the trajectory is for another robot",
                        joint_names.join(","),
                        dof.saturating_sub(1)
                    ),
                ))
            }
        };
        let format = match kind {
            JointHeader::Names => "csv header: joint names",
            JointHeader::Indexed => "csv header: q0..",
            JointHeader::BeforeMotor => "csv header: columns before motor",
        };
        let names: Vec<String> = cols.iter().map(|&c| head[c].clone()).collect();
        (cols, names, head.clone(), head.len(), format)
    } else if dof == 0 {
        return Err(bad(
            first_line,
            "header",
            "no header: without the robot the joint columns are found by name".into(),
        ));
    } else {
        let format = if comma { "csv" } else { "whitespace" };
        (
            (0..dof).collect(),
            joint_names.to_vec(),
            Vec::new(),
            dof,
            format,
        )
    };
    let find = |name: &str| header.iter().position(|h| h == name);
    let t_col = find("t").or_else(|| find("time"));
    let t_name = t_col.map_or("t", |c| header[c].as_str());
    let motor_col = find(MOTOR_COLUMN);
    let s_col = find("s");
    let kto_cols = match (find("kappa"), find("tau"), find("omega")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        _ => None,
    };
    let end_cols = match (find("x"), find("y"), find("z")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        _ => None,
    };
    let az_col = find("azimuth");
    let phase_col = find("phase");
    let mut out = TrajectoryTable {
        path: path.to_path_buf(),
        format: format.to_string(),
        joint_names: names,
        q: Vec::new(),
        lines: Vec::new(),
        t: t_col.map(|_| Vec::new()),
        motor: motor_col.map(|_| Vec::new()),
        s: s_col.map(|_| Vec::new()),
        kto: kto_cols.map(|_| Vec::new()),
        end: end_cols.map(|_| Vec::new()),
        azimuth: az_col.map(|_| Vec::new()),
        phase: phase_col.map(|_| Vec::new()),
    };
    for (line, l) in content {
        if out.lines.len() >= MAX_TRAJECTORY_ROWS {
            return Err(bad(
                line,
                "rows",
                format!("more than {MAX_TRAJECTORY_ROWS} rows: not a trajectory this tool reads"),
            ));
        }
        let f = split(l);
        if f.len() != n_fields {
            return Err(bad(
                line,
                "columns",
                format!(
                    "{} fields, expected {n_fields} ({})",
                    f.len(),
                    if has_header {
                        "as many as the header".to_string()
                    } else {
                        format!("one per joint: {}", joint_names.join(" "))
                    }
                ),
            ));
        }
        let num = |col: usize, name: &str| -> Result<Real> {
            let s = &f[col];
            let v = s
                .parse::<Real>()
                .map_err(|_| bad(line, name, format!("`{s}` is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad(line, name, format!("`{s}` is not a finite value")))
            }
        };
        for (j, &c) in cols.iter().enumerate() {
            out.q.push(num(c, &out.joint_names[j])?);
        }
        if let (Some(c), Some(v)) = (t_col, out.t.as_mut()) {
            let t = num(c, t_name)?;
            if let Some(&prev) = v.last() {
                if t < prev {
                    return Err(bad(
                        line,
                        t_name,
                        format!("time {t} is before the previous row's {prev}"),
                    ));
                }
            }
            v.push(t);
        }
        if let (Some(c), Some(v)) = (motor_col, out.motor.as_mut()) {
            v.push(num(c, MOTOR_COLUMN)?);
        }
        if let (Some(c), Some(v)) = (s_col, out.s.as_mut()) {
            let s = num(c, "s")?;
            if s < 0.0 {
                return Err(bad(line, "s", format!("`{s}` must be >= 0")));
            }
            v.push(s);
        }
        if let (Some([a, b, c]), Some(v)) = (kto_cols, out.kto.as_mut()) {
            let k = [num(a, "kappa")?, num(b, "tau")?, num(c, "omega")?];
            if k[0] < 0.0 {
                return Err(bad(line, "kappa", format!("`{}` must be >= 0", k[0])));
            }
            v.push(k);
        }
        if let (Some([a, b, c]), Some(v)) = (end_cols, out.end.as_mut()) {
            v.push(Vec3::new(num(a, "x")?, num(b, "y")?, num(c, "z")?));
        }
        if let (Some(c), Some(v)) = (az_col, out.azimuth.as_mut()) {
            v.push(num(c, "azimuth")?);
        }
        if let (Some(c), Some(v)) = (phase_col, out.phase.as_mut()) {
            let text = f[c].as_str();
            v.push(Phase::parse(text).ok_or_else(|| {
                bad(
                    line,
                    "phase",
                    format!("`{text}`: expected load, reconfigure, hold or unload"),
                )
            })?);
        }
        out.lines.push(line);
    }
    if out.lines.is_empty() {
        return Err(file_err(
            "no data rows after the header: no joint rows to read".into(),
        ));
    }
    Ok(out)
}

/// Read a joint trajectory for `helixreach check` (and the campaign's run files, the seed's
/// runs) for a robot whose joints are `joint_names`: [`read_trajectory_file`] as a
/// [`JointFile`].
pub fn read_joint_file(path: &Path, joint_names: &[String]) -> Result<JointFile> {
    read_trajectory_file(path, joint_names, "").map(joint_file)
}

/// [`read_joint_file`] on text already read; `path` names it in errors.
pub fn parse_joint_file(text: &str, path: &Path, joint_names: &[String]) -> Result<JointFile> {
    parse_trajectory_file(text, path, joint_names, "").map(joint_file)
}

/// The joints, motor, time and s of a table, as the check takes them.
fn joint_file(t: TrajectoryTable) -> JointFile {
    JointFile {
        path: t.path,
        dof: t.joint_names.len(),
        q: t.q,
        lines: t.lines,
        motor: t.motor,
        t: t.t,
        s: t.s,
        format: t.format,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Iso3, Quat, Vec3};
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
                    velocity: vec![0.1 * x, -0.2, 0.3, 0.4 * x],
                    acceleration: vec![1.0, -x, 0.0, 2.5],
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
            "t,a,b,c,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase,v_a,v_b,v_c,v_motor,a_a,a_b,a_c,a_motor\n0.1,0,0.00000000000000001,1,"
        ));
        // The index header (q0..), and the joint columns in another order: the same rows.
        let indexed = text.replacen(
            "t,a,b,c,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase,v_a,v_b,v_c,v_motor,a_a,a_b,a_c,",
            "t,q0,q1,q2,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase,v_q0,v_q1,v_q2,v_motor,a_q0,a_q1,a_q2,",
            1,
        );
        assert_ne!(indexed, text);
        let dir = tempfile::tempdir().unwrap();
        for (file, text, format) in [
            ("named.csv", &text, "csv header: joint names"),
            ("indexed.csv", &indexed, "csv header: q0.."),
        ] {
            let path = dir.path().join(file);
            std::fs::write(&path, text).unwrap();
            read_back(&tr, &path, text, format, true);
        }
        // The readers that know the robot find its joint columns by name, wherever they are.
        let swapped: String = text
            .lines()
            .map(|l| {
                let mut f: Vec<&str> = l.split(',').collect();
                f.swap(1, 3);
                f.join(",") + "\n"
            })
            .collect();
        assert!(swapped.starts_with("t,c,b,a,motor"));
        let path = dir.path().join("swapped.csv");
        std::fs::write(&path, &swapped).unwrap();
        read_back(&tr, &path, &swapped, "csv header: joint names", false);
    }

    /// Every reader reads `tr` back from `path` (the robot-less figure reader only when `all`:
    /// it takes the columns before `motor` in file order).
    fn read_back(tr: &Trajectory, path: &Path, text: &str, format: &str, all: bool) {
        let rows = if all {
            super::super::read_trajectory(path).unwrap()
        } else {
            Vec::new()
        };
        let names = tr.joint_names.clone();
        #[cfg(feature = "plots")]
        let rendered = crate::plot::render::input::read_trajectory(path, &names, "r").unwrap();
        let joints = parse_joint_file(text, path, &names).unwrap();
        assert_eq!(joints.format, format);
        assert_eq!(rows.len(), if all { tr.points.len() } else { 0 });
        for (k, p) in tr.points.iter().enumerate() {
            if let Some(r) = rows.get(k) {
                assert_eq!(r.q, p.q);
                assert_eq!(r.t.to_bits(), p.t.to_bits());
                assert_eq!(r.s.to_bits(), p.s.to_bits());
                assert_eq!(r.motor.to_bits(), p.motor.to_bits());
            }
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

    /// The JSON: exactly the ROS 2 message's fields, in its order; the arm and the motor apart;
    /// the time split never writes 10⁹ ns.
    #[test]
    fn json_is_the_ros2_message() {
        let tr = traj();
        let text = trajectory_json(&tr).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let keys = |o: &serde_json::Value| -> Vec<String> {
            let mut k: Vec<String> = o.as_object().unwrap().keys().cloned().collect();
            k.sort();
            k
        };
        assert_eq!(keys(&v), ["header", "joint_names", "points"]);
        assert_eq!(keys(&v["header"]), ["frame_id", "stamp"]);
        assert_eq!(
            keys(&v["points"][0]),
            [
                "accelerations",
                "effort",
                "positions",
                "time_from_start",
                "velocities"
            ]
        );
        assert_eq!(keys(&v["points"][0]["time_from_start"]), ["nanosec", "sec"]);
        assert_eq!(v["joint_names"], serde_json::json!(["a", "b", "c"]));
        let last = &v["points"][3];
        assert_eq!(last["positions"].as_array().unwrap().len(), 3);
        assert_eq!(last["accelerations"][1], -1.0);
        assert_eq!(last["time_from_start"]["sec"], 1);
        assert_eq!(last["time_from_start"]["nanosec"], 800_000_000);
        // The message order: positions, velocities, accelerations, effort, time_from_start.
        let at = |k: &str| text.find(k).unwrap();
        assert!(at("\"positions\"") < at("\"velocities\""));
        assert!(at("\"velocities\"") < at("\"accelerations\""));
        assert!(at("\"accelerations\"") < at("\"effort\""));
        assert!(at("\"effort\"") < at("\"time_from_start\""));
        let motor = JointTrajectoryMsg::new(&tr, Channels::Motor).unwrap();
        assert_eq!(motor.joint_names, ["rod_motor"]);
        assert_eq!(motor.points[3].positions, [tr.points[3].motor]);
        assert_eq!(motor.points[3].velocities, [0.4]);
        assert_eq!(
            DurationMsg::of(2.9999999999),
            DurationMsg {
                sec: 2,
                nanosec: 999_999_999
            }
        );
        assert_eq!(DurationMsg::of(1.25).nanosec, 250_000_000);
        let mut bad = traj();
        bad.points[1].t = 3e9;
        assert!(trajectory_json(&bad).is_err());
    }

    /// The YAML: floats PyYAML reads as floats (a `.0` when integral, no exponent), the goal
    /// form nested under `trajectory:`.
    #[test]
    fn yaml_for_ros2_topic_pub() {
        let msg = JointTrajectoryMsg::new(&traj(), Channels::Arm).unwrap();
        let y = message_yaml(&msg, false);
        assert!(y.starts_with("header:\n  stamp: {sec: 0, nanosec: 0}\n  frame_id: \"base\"\n"));
        assert!(y.contains("joint_names: [\"a\", \"b\", \"c\"]\npoints:\n  - positions: [0.0, 0.00000000000000001, 1.0]\n"), "{y}");
        assert!(
            !y.contains('e'.to_string().as_str()) || !y.contains("e-"),
            "{y}"
        );
        let g = message_yaml(&msg, true);
        assert!(g.starts_with("trajectory:\n  header:\n"));
        assert_eq!(g.lines().count(), y.lines().count() + 1);
    }

    /// The sidecar names how far the trajectory goes and its phases as runs of points.
    #[test]
    fn sidecar_outcome_and_phase_runs() {
        let mut tr = traj();
        tr.outcome.class = crate::planning::planner::ReachClass::Partial;
        tr.outcome.cause = Some(crate::planning::cause::BlockCause::NoIk);
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
