//! Validate an executed (or planned, or imported) joint trajectory against a rig: joint limits,
//! self / scene / rod collision, joint steps and jumps, and — given the ray's direction — how far
//! every row's end pose lies from the ray's pose curve.
//!
//! # Input ([`JointFile`])
//! The joints of every row (with the file's line numbers, and its `motor`, `t` and `s` columns
//! when present), read by `records::trajectory::read_joint_file` — plan CSV, the seed's
//! whitespace files, a MoveIt joint-name CSV; this module imports no file format.
//!
//! # Checks ([`check_trajectory`])
//! - **Limits**: every joint inside its URDF limits (no tolerance: a real robot's controller
//!   does not go past them), the motor inside the rig's motor range.
//! - **Collision** at every row: self (the robot's filtered pairs), scene (the rig's obstacles)
//!   and, with a direction, the rod — the helix of the row's `s` as `rod_capsules` capsules of
//!   radius r + `rod_clearance`, without the last `rod_end_exclusion` metres the motor grips,
//!   exactly as the planner models it. A row counts once in `collisions` whatever it hits; the
//!   colliding pairs are listed with their row counts.
//! - **Steps**: the largest joint change between consecutive rows (max-norm), and how many
//!   exceed [`JUMP`] = 0.2 rad (the seed README's measure of a Descartes jump). The straight
//!   joint-space segment of every step longer than `segment_check_step` is also checked for
//!   self and scene collision at interior samples (reported apart, as `segment_collisions`: how
//!   a controller moves between two rows is not in the file).
//! - **Pose** (with a direction): the row's tool pose T(q) by FK is projected onto the ray's pose
//!   curve s ↦ (p(s), R(s)) ([`crate::planning::pose_path::PoseMap`], the rig's azimuth; or the
//!   frame of the last of `held_edges` edges of a discrete helix): the rows are tracked along
//!   it in file order ([`crate::planning::pose_projection`]; a row's `s` column, when the file
//!   has one, is taken as it is). The position error |p(s) − p| and rotation error θ(s) at that
//!   s are reported per row.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::helix::discrete::fill_nodes;
use crate::helix::Helix;
use crate::math::{rot_z, Mat3, Real, Vec3};
use crate::planning::pose_path::PoseMap;
use crate::planning::pose_projection::{ToolPoseCurve, Tracker};
use crate::planning::rig::{tool_from_director, Rig, RobotSpec};
use crate::robot::collision::{BodyRef, Contact};
use crate::robot::{CollisionModel, CollisionWorkspace, Frame, RobotModel};
use std::path::{Path, PathBuf};

/// A joint step larger than this (rad, any joint) is a jump.
pub const JUMP: Real = 0.2;
/// Largest `held_edges` of [`CheckOptions`].
pub const MAX_HELD_EDGES: usize = 10_000;
/// At most this many entries in each list of the report (limit violations, collision rows).
pub const MAX_LISTED: usize = 50;

/// A joint trajectory read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct JointFile {
    /// The file.
    pub path: PathBuf,
    /// Number of joints per row.
    pub dof: usize,
    /// Joint values, row-major (`rows × dof`).
    pub q: Vec<Real>,
    /// 1-based line number of every row.
    pub lines: Vec<usize>,
    /// Motor angle of every row, when the file has a `motor` column.
    pub motor: Option<Vec<Real>>,
    /// Time of every row (s), when the file has a `t` (or `time`) column: non-decreasing.
    pub t: Option<Vec<Real>>,
    /// The ray's s of every row, when the file has an `s` column (helixreach `plan`): the pose
    /// error of a row is then measured at its own s, not at a projection.
    pub s: Option<Vec<Real>>,
    /// How the file was read (`whitespace`, `csv`, `csv header: joint names`, `csv header: q0..`).
    pub format: String,
}

impl JointFile {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// The joints of row `i`.
    pub fn row(&self, i: usize) -> &[Real] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }
}

/// What to check besides limits, collisions and steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckOptions {
    /// The ray the trajectory drives (enables the pose error and the rod collision check).
    pub direction: Option<Direction>,
    /// Helix azimuth α (rad) of the ray.
    pub azimuth: Real,
    /// Largest s of the pose projection's full scan.
    pub s_max: Real,
    /// Also compute the smallest scene and rod clearance of every row (slower).
    pub clearance: bool,
    /// Which end frame the arm holds: 0 = the continuum end's transported frame (the planner's
    /// [`PoseMap`]); n ≥ 1 = the frame of the last edge of the helix discretized with n edges
    /// (the transported frame at arc length 1 − 1/(2n)), with the end at node n = r(1). The
    /// seed imposed the latter with n = [`SEED_HELD_EDGES`] (its DER's 101 vertices; the paper:
    /// "the material frame on the last edge gives the required rotation matrix").
    pub held_edges: usize,
    /// Step bound (rad): a step of any joint between consecutive rows larger than this is a
    /// finding ([`Finding::Step`]).
    pub max_step: Real,
    /// Fraction of the URDF joint speed limits (and the rig's motor limit) a timed file may use.
    pub velocity_scale: Real,
    /// Fraction of the rig's joint and motor acceleration limits a timed file may use.
    pub acceleration_scale: Real,
    /// Largest position error (m) of a row from the ray's pose curve (with a direction).
    pub position_tolerance: Real,
    /// Largest rotation error (rad) of a row from the ray's pose curve (with a direction).
    pub rotation_tolerance: Real,
}

/// Default [`CheckOptions::position_tolerance`] (m).
pub const POSITION_TOLERANCE: Real = 1e-3;
/// Default [`CheckOptions::rotation_tolerance`] (rad).
pub const ROTATION_TOLERANCE: Real = 1e-2;
/// Relative slack of the velocity and acceleration gates (round-off of the written numbers).
pub const RATE_SLACK: Real = 1e-9;

/// A kind of finding that fails a check; each has its own bit in
/// [`CheckReport::finding_mask`] (the `check` command exits 64 + the mask).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Finding {
    /// A joint (or the motor) outside its limits.
    Limit = 1,
    /// A self, scene or rod collision at a row, or inside an interpolated step.
    Collision = 2,
    /// A joint step over [`CheckOptions::max_step`].
    Step = 4,
    /// A joint or motor speed over its limit (from the `t` column).
    Velocity = 8,
    /// A joint or motor acceleration over its limit (from the `t` column).
    Acceleration = 16,
    /// A row's pose farther from the ray's pose curve than the tolerance.
    Pose = 32,
}

impl Finding {
    /// Every kind, by bit.
    pub const ALL: [Finding; 6] = [
        Finding::Limit,
        Finding::Collision,
        Finding::Step,
        Finding::Velocity,
        Finding::Acceleration,
        Finding::Pose,
    ];

    /// The JSON name.
    pub fn as_str(&self) -> &'static str {
        match self {
            Finding::Limit => "limit",
            Finding::Collision => "collision",
            Finding::Step => "step",
            Finding::Velocity => "velocity",
            Finding::Acceleration => "acceleration",
            Finding::Pose => "pose",
        }
    }
}

/// The seed experiment's `held_edges`: its Descartes targets were the last-edge frames of a
/// 100-edge discrete helix. Its FK agrees with that curve to ≈ 0.1 mm / 0.2 mrad, and with the
/// continuum end frame only to ≈ 3 mm / 2 mrad (`tests/check.rs`).
pub const SEED_HELD_EDGES: usize = 100;

impl Default for CheckOptions {
    /// No direction, azimuth 0, `s_max` 20, no clearance, the continuum end frame, step bound
    /// [`JUMP`], the full speed and acceleration limits, tolerances [`POSITION_TOLERANCE`] and
    /// [`ROTATION_TOLERANCE`].
    fn default() -> Self {
        CheckOptions {
            direction: None,
            azimuth: 0.0,
            s_max: 20.0,
            clearance: false,
            held_edges: 0,
            max_step: JUMP,
            velocity_scale: 1.0,
            acceleration_scale: 1.0,
            position_tolerance: POSITION_TOLERANCE,
            rotation_tolerance: ROTATION_TOLERANCE,
        }
    }
}

/// The check of one row.
#[derive(Debug, Clone, PartialEq)]
pub struct RowCheck {
    /// 1-based line in the file.
    pub line: usize,
    /// s of the row on the ray (projection), when a direction was given.
    pub s: Option<Real>,
    /// |p(s) − p| (m).
    pub position_error: Option<Real>,
    /// Angle of R(s)ᵀ·R (rad).
    pub rotation_error: Option<Real>,
    /// Largest joint step from the previous row (rad; 0 for the first row).
    pub joint_step: Real,
    /// The first joint (or `motor`) outside its limits, if any.
    pub limit: Option<String>,
    /// The colliding pair (`a|b`) of each kind found at this row (self, scene, rod).
    pub contacts: Vec<String>,
    /// Every link pair in self-collision at this row (`linkA|linkB`, URDF link names, the
    /// earlier link on the chain first), in the collision model's walk order; empty when free.
    pub self_pairs: Vec<String>,
    /// Smallest robot–scene distance (m), when clearance was asked.
    pub scene_clearance: Option<Real>,
    /// Smallest rod–robot distance (m, rod radius + clearance included), when clearance was
    /// asked and a direction given.
    pub rod_clearance: Option<Real>,
}

/// A colliding pair and the rows where it collides.
#[derive(Debug, Clone, PartialEq)]
pub struct PairCount {
    /// `self`, `scene` or `rod`.
    pub kind: String,
    /// First body.
    pub a: String,
    /// Second body.
    pub b: String,
    /// Rows with this contact.
    pub rows: usize,
    /// First such row (0-based).
    pub first_row: usize,
}

/// The result of [`check_trajectory`].
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    /// The file.
    pub file: PathBuf,
    /// The rig's name.
    pub rig: String,
    /// The clamp origin used (base frame, m).
    pub clamp: [Real; 3],
    /// Rows.
    pub rows: usize,
    /// Rows with a joint (or the motor) outside its limits.
    pub limit_violations: usize,
    /// Rows with any collision (self, scene or rod).
    pub collisions: usize,
    /// Rows with a self-collision.
    pub self_collisions: usize,
    /// Rows with a scene collision.
    pub scene_collisions: usize,
    /// Rows with a rod collision (0 and unchecked without a direction).
    pub rod_collisions: usize,
    /// Whether the rod was checked (a direction was given).
    pub rod_checked: bool,
    /// Colliding pairs, by kind then first row.
    pub pairs: Vec<PairCount>,
    /// Interpolated joint-space steps between rows that collide (self or scene) inside.
    pub segment_collisions: usize,
    /// Largest joint step (rad) and the row it ends at.
    pub max_joint_step: (Real, usize),
    /// Steps over [`JUMP`].
    pub steps_over_jump: usize,
    /// The step bound checked ([`CheckOptions::max_step`]).
    pub max_step_bound: Real,
    /// Steps over the bound.
    pub steps_over_bound: usize,
    /// Whether the file has a time column (velocity and acceleration checked).
    pub timed: bool,
    /// Rows reached by a segment whose speed exceeds a joint's (or the motor's) limit.
    pub velocity_violations: usize,
    /// Rows whose finite-difference acceleration exceeds a limit.
    pub acceleration_violations: usize,
    /// Largest |velocity| / limit over joints, motor and segments (timed files).
    pub max_velocity_ratio: Option<(Real, usize)>,
    /// Largest |acceleration| / limit (timed files).
    pub max_acceleration_ratio: Option<(Real, usize)>,
    /// Rows whose pose error exceeds a tolerance (with a direction).
    pub pose_violations: usize,
    /// Whether the pose error was measured at every row's own s (an `s` column) rather than a
    /// projection.
    pub pose_at_file_s: bool,
    /// Joint-space path length Σ‖Δq‖₂ (rad).
    pub path_length: Real,
    /// Largest position error (m) and its row, with a direction.
    pub max_position_error: Option<(Real, usize)>,
    /// Largest rotation error (rad) and its row, with a direction.
    pub max_rotation_error: Option<(Real, usize)>,
    /// Largest s reached, with a direction.
    pub s_max_reached: Option<Real>,
    /// Smallest scene clearance (m) and its row, when asked.
    pub min_scene_clearance: Option<(Real, usize)>,
    /// Smallest rod clearance (m) and its row, when asked with a direction.
    pub min_rod_clearance: Option<(Real, usize)>,
    /// The pairs (`a|b`) of the smallest scene and rod clearances.
    pub min_clearance_pairs: [Option<String>; 2],
    /// Every row.
    pub row_checks: Vec<RowCheck>,
}

/// The robot, collision model and pose map a check needs, built once per rig (cheap to reuse
/// over many files with different clamps: see [`Checker::with_rig`]).
///
/// ```
/// use helixreach::planning::check::{CheckOptions, Checker};
/// use helixreach::planning::rig::Rig;
/// use helixreach::records::trajectory::parse_joint_file;
/// let checker = Checker::new(Rig::load("sawyer-seed").unwrap()).unwrap();
/// // Two rows; the second turns right_j6 past its upper limit (4.71 rad).
/// let text = "0 -1 0 1.5 0 -0.5 0\n0 -1 0 1.5 0 -0.5 5.0\n";
/// let traj = parse_joint_file(text, "t.txt".as_ref(), &checker.joint_names()).unwrap();
/// let rep = checker.check(&traj, &CheckOptions::default()).unwrap();
/// assert_eq!((rep.rows, rep.limit_violations, rep.steps_over_jump), (2, 1, 1));
/// assert!((rep.max_joint_step.0 - 5.0).abs() < 1e-12);
/// assert!(rep.row_checks[1].limit.as_ref().unwrap().contains("right_j6"));
/// ```
#[derive(Debug, Clone)]
pub struct Checker {
    rig: Rig,
    model: RobotModel,
    collision: CollisionModel,
    /// Built by [`Checker::for_robot`]: no rig (no scene, rod, motor or pose).
    robot_only: bool,
}

/// The rig around a robot-only check: the robot alone (the clamp, rod and motor are never
/// read, since a robot-only check refuses a direction and a motor column).
const ROBOT_ONLY_RIG: &str = r#"
name = "robot only"
[robot]
urdf = "-"
tip_link = "-"
[clamp]
origin = [0.0, 0.0, 0.0]
d1 = [1.0, 0.0, 0.0]
d3 = [0.0, 0.0, 1.0]
[rod]
length = 1.0
radius = 0.001
youngs_modulus = 1.0
poisson = 0.3
density = 1.0
[motor]
max_velocity = 1.0
"#;

impl Checker {
    /// Load the rig's robot and scene. Errors name the rig file.
    pub fn new(rig: Rig) -> Result<Checker> {
        let model = rig.robot.load_model(&rig.source)?;
        let collision = rig
            .robot
            .collision_model(&model, &rig.obstacles, &rig.source)?;
        Ok(Checker {
            rig,
            model,
            collision,
            robot_only: false,
        })
    }

    /// A checker of the robot alone, without a rig (`helixreach check --robot`): joint limits,
    /// self-collision (the pairs [`RobotSpec::collision_model`] checks: the robot's own
    /// never-colliding list and `spec`'s SRDF skipped, `spec`'s padding), joint steps and the
    /// segments between rows, and for a timed file the URDF speed limits. There is no scene,
    /// rod, motor or pose: [`CheckOptions::direction`] and a `motor` column are refused, and
    /// accelerations are not gated (a URDF has no acceleration limits). Errors name the URDF.
    pub fn for_robot(spec: RobotSpec) -> Result<Checker> {
        let mut rig = Rig::from_toml_str(ROBOT_ONLY_RIG, "robot only", Path::new("."))?;
        let source = format!("robot {}", spec.urdf);
        rig.name = "robot only".into();
        rig.robot = spec;
        rig.source = source;
        let model = rig.robot.load_model(&rig.source)?;
        let collision = rig.robot.collision_model(&model, &[], &rig.source)?;
        Ok(Checker {
            rig,
            model,
            collision,
            robot_only: true,
        })
    }

    /// Whether this checker has no rig ([`Checker::for_robot`]).
    pub fn robot_only(&self) -> bool {
        self.robot_only
    }

    /// The same robot and scene with another rig of the same robot (e.g. the clamp moved by
    /// [`Rig::with_clamp_origin`]; the obstacles are re-read from `rig`).
    pub fn with_rig(&self, rig: Rig) -> Result<Checker> {
        let mut collision = self.collision.clone();
        collision.set_obstacles(&rig.obstacles)?;
        Ok(Checker {
            rig,
            model: self.model.clone(),
            collision,
            robot_only: false,
        })
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The robot.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The robot's joint names, in file order.
    pub fn joint_names(&self) -> Vec<String> {
        self.model.joints().iter().map(|j| j.name.clone()).collect()
    }

    /// Check `traj` (see the module docs).
    pub fn check(&self, traj: &JointFile, opt: &CheckOptions) -> Result<CheckReport> {
        check_trajectory(self, traj, opt)
    }
}

/// Projection of FK poses onto a ray's pose curve (see the module docs).
struct Projector {
    map: PoseMap,
    dir: [Real; 3],
    length: Real,
    s_max: Real,
    /// 0: the continuum end frame; n: the frame of the last of n edges.
    held_edges: usize,
    /// R_c·Rz(α).
    rc: Mat3,
    /// Rz(−α).
    az_inv: Mat3,
    oc: Vec3,
}

impl ToolPoseCurve for Projector {
    fn tool_pose(&self, s: Real) -> Result<(Mat3, Vec3)> {
        let kto = [s * self.dir[0], s * self.dir[1], s * self.dir[2]];
        if self.held_edges == 0 {
            let pose = self.map.end(kto)?.0;
            return Ok((
                pose.rotation.to_rotation_matrix().into_inner(),
                pose.translation.vector,
            ));
        }
        // The seed's target: the end at node n, the frame of the last edge — whose frame is
        // the transported frame at the edge's mid arc length 1 − 1/(2n) to O(1/n²)
        // ([`crate::helix::discrete`]).
        let h = Helix::new(kto[0], kto[1], kto[2])?;
        let d = h.transported_frame(1.0 - 0.5 / self.held_edges as Real);
        let p = self.oc + self.rc * (h.position(1.0) * self.length);
        Ok((self.rc * d * self.az_inv * tool_from_director(), p))
    }

    fn length(&self) -> Real {
        self.length
    }

    fn s_max(&self) -> Real {
        self.s_max
    }
}

fn kind_of(c: &Contact) -> &'static str {
    match (c.a, c.b) {
        (BodyRef::Rod(_), _) | (_, BodyRef::Rod(_)) => "rod",
        (BodyRef::Obstacle(_), _) | (_, BodyRef::Obstacle(_)) => "scene",
        _ => "self",
    }
}

/// Check `traj` on the checker's rig (see the module docs). Errors: a file whose joint count
/// differs from the robot's, a non-finite or negative `s_max`, a helix the helix module rejects.
pub fn check_trajectory(
    checker: &Checker,
    traj: &JointFile,
    opt: &CheckOptions,
) -> Result<CheckReport> {
    let rig = &checker.rig;
    let model = &checker.model;
    let cm = &checker.collision;
    let dof = model.dof();
    if traj.dof != dof {
        return Err(Error::File {
            path: traj.path.clone(),
            reason: format!("{} joints per row, the robot has {dof}", traj.dof),
        });
    }
    if !(opt.s_max.is_finite() && opt.s_max > 0.0 && opt.s_max <= crate::limits::MAX_S) {
        return Err(Error::invalid(
            "s_max",
            opt.s_max,
            format!(
                "must be in (0, {:e}] (helixreach::limits::MAX_S)",
                crate::limits::MAX_S
            ),
        ));
    }
    crate::error::require_finite("azimuth", opt.azimuth)?;
    if checker.robot_only {
        if let Some(d) = opt.direction {
            return Err(Error::invalid(
                "direction",
                format!("({}, {}, {})", d.kappa, d.tau, d.omega),
                "a robot-only check has no rig (no clamp, rod or pose curve): give a rig",
            ));
        }
        if traj.motor.is_some() {
            return Err(Error::File {
                path: traj.path.clone(),
                reason: "has a motor column; a robot-only check has no rig motor to check it \
                         against: give a rig"
                    .into(),
            });
        }
    }
    if opt.held_edges > MAX_HELD_EDGES {
        return Err(Error::invalid(
            "held_edges",
            opt.held_edges,
            format!("must be <= {MAX_HELD_EDGES}"),
        ));
    }
    let projector = opt.direction.map(|d| Projector {
        map: PoseMap::new(rig, opt.azimuth),
        dir: [d.kappa, d.tau, d.omega],
        length: rig.rod.length,
        s_max: opt.s_max,
        held_edges: opt.held_edges,
        rc: rig.clamp_rotation() * rot_z(opt.azimuth),
        az_inv: rot_z(-opt.azimuth),
        oc: rig.clamp.translation.vector,
    });
    let tool = Frame::from_iso(&rig.tool);
    let (lower, upper) = (model.lower(), model.upper());
    let names = checker.joint_names();
    let mut ws: CollisionWorkspace = cm.workspace();
    let mut rod = vec![Vec3::zeros(); rig.planner.rod_capsules + 1];
    let rc = rig.clamp_rotation() * rot_z(opt.azimuth);
    let oc = rig.clamp.translation.vector;
    let mut qi = vec![0.0; dof];

    let mut rows = Vec::with_capacity(traj.rows());
    let mut pairs: Vec<PairCount> = Vec::new();
    let o = rig.clamp.translation.vector;
    let mut rep = CheckReport {
        file: traj.path.clone(),
        rig: rig.name.clone(),
        clamp: [o.x, o.y, o.z],
        rows: traj.rows(),
        limit_violations: 0,
        collisions: 0,
        self_collisions: 0,
        scene_collisions: 0,
        rod_collisions: 0,
        rod_checked: projector.is_some(),
        pairs: Vec::new(),
        segment_collisions: 0,
        max_joint_step: (0.0, 0),
        steps_over_jump: 0,
        max_step_bound: opt.max_step,
        steps_over_bound: 0,
        timed: traj.t.is_some(),
        velocity_violations: 0,
        acceleration_violations: 0,
        max_velocity_ratio: None,
        max_acceleration_ratio: None,
        pose_violations: 0,
        pose_at_file_s: traj.s.is_some() && opt.direction.is_some(),
        path_length: 0.0,
        max_position_error: None,
        max_rotation_error: None,
        s_max_reached: None,
        min_scene_clearance: None,
        min_rod_clearance: None,
        min_clearance_pairs: [None, None],
        row_checks: Vec::new(),
    };
    let mut tracker = Tracker::new();
    let max_of = |cur: &mut Option<(Real, usize)>, v: Real, i: usize| {
        if cur.is_none_or(|(m, _)| v > m) {
            *cur = Some((v, i));
        }
    };
    let min_of = |cur: &mut Option<(Real, usize)>, v: Real, i: usize| {
        let lower = cur.is_none_or(|(m, _)| v < m);
        if lower {
            *cur = Some((v, i));
        }
        lower
    };
    for i in 0..traj.rows() {
        let q = traj.row(i);
        let mut row = RowCheck {
            line: traj.lines[i],
            s: None,
            position_error: None,
            rotation_error: None,
            joint_step: 0.0,
            limit: None,
            contacts: Vec::new(),
            self_pairs: Vec::new(),
            scene_clearance: None,
            rod_clearance: None,
        };
        // Limits.
        for j in 0..dof {
            if !(q[j] >= lower[j] && q[j] <= upper[j]) {
                row.limit = Some(format!(
                    "{} = {} outside [{}, {}]",
                    names[j], q[j], lower[j], upper[j]
                ));
                break;
            }
        }
        if let (None, Some(m)) = (&row.limit, &traj.motor) {
            let (lo, hi) = rig.motor.range;
            if !(m[i] >= lo && m[i] <= hi) {
                row.limit = Some(format!("motor = {} outside [{lo}, {hi}]", m[i]));
            }
        }
        if row.limit.is_some() {
            rep.limit_violations += 1;
        }
        // Steps and the interpolated segment.
        if i > 0 {
            let p = traj.row(i - 1);
            let mut step: Real = 0.0;
            let mut l2 = 0.0;
            for j in 0..dof {
                let d = (q[j] - p[j]).abs();
                step = step.max(d);
                l2 += d * d;
            }
            rep.path_length += l2.sqrt();
            row.joint_step = step;
            if step > rep.max_joint_step.0 {
                rep.max_joint_step = (step, i);
            }
            if step > JUMP {
                rep.steps_over_jump += 1;
            }
            if step > opt.max_step {
                rep.steps_over_bound += 1;
            }
            // At most MAX_SEGMENT_SAMPLES samples: a step that needs more is far over JUMP and
            // fails the check as a jump anyway.
            let n = (step / rig.planner.segment_check_step)
                .ceil()
                .min(crate::limits::MAX_SEGMENT_SAMPLES as Real) as usize;
            for k in 1..n {
                let t = k as Real / n as Real;
                for j in 0..dof {
                    qi[j] = p[j] + t * (q[j] - p[j]);
                }
                cm.update(&qi, &mut ws);
                if cm.self_collision(&ws).is_some() || cm.scene_collision(&ws).is_some() {
                    rep.segment_collisions += 1;
                    break;
                }
            }
        }
        // Pose and the rod of this row.
        let mut rod_geom = None;
        if let Some(pr) = projector.as_ref() {
            let fk = model.chain().tool_pose(q).mul(&tool);
            let (s, dp, dr) = match &traj.s {
                Some(ss) => {
                    let (_, dp, dr) = pr.objective(ss[i], &fk.rot, &fk.pos)?;
                    (ss[i], dp, dr)
                }
                None => {
                    let p = tracker.project(pr, &fk.rot, &fk.pos)?;
                    (p.s, p.position_error, p.rotation_error)
                }
            };
            row.s = Some(s);
            row.position_error = Some(dp);
            row.rotation_error = Some(dr);
            if !(dp <= opt.position_tolerance && dr <= opt.rotation_tolerance) {
                rep.pose_violations += 1;
            }
            max_of(&mut rep.max_position_error, dp, i);
            max_of(&mut rep.max_rotation_error, dr, i);
            rep.s_max_reached = Some(rep.s_max_reached.map_or(s, |m: Real| m.max(s)));
            let h = Helix::new(s * pr.dir[0], s * pr.dir[1], s * pr.dir[2])?;
            fill_nodes(&h, &mut rod);
            for x in rod.iter_mut() {
                *x = oc + rc * (*x * rig.rod.length);
            }
            rod_geom = Some(rig.rod_geometry(&rod));
        }
        // Collisions: the first contact of each kind.
        cm.update(q, &mut ws);
        let found = [
            cm.self_collision(&ws),
            cm.scene_collision(&ws),
            rod_geom.as_ref().and_then(|r| cm.rod_collision(&ws, r)),
        ];
        for c in found.iter().flatten() {
            let kind = kind_of(c);
            let (a, b) = (cm.name(c.a), cm.name(c.b));
            row.contacts.push(format!("{a}|{b}"));
            match pairs
                .iter_mut()
                .find(|p| p.kind == kind && p.a == a && p.b == b)
            {
                Some(p) => p.rows += 1,
                None => pairs.push(PairCount {
                    kind: kind.to_string(),
                    a,
                    b,
                    rows: 1,
                    first_row: i,
                }),
            }
        }
        if let Some(c) = &found[0] {
            let links = model.links();
            row.self_pairs = cm
                .self_collisions(&ws)
                .into_iter()
                .map(|(a, b)| format!("{}|{}", links[a.min(b)].name, links[a.max(b)].name))
                .collect();
            if row.self_pairs.is_empty() {
                row.self_pairs
                    .push(format!("{}|{}", cm.name(c.a), cm.name(c.b)));
            }
        }
        rep.self_collisions += found[0].is_some() as usize;
        rep.scene_collisions += found[1].is_some() as usize;
        rep.rod_collisions += found[2].is_some() as usize;
        rep.collisions += found.iter().any(|c| c.is_some()) as usize;
        if opt.clearance {
            if let Some(c) = cm.scene_clearance(&ws) {
                row.scene_clearance = Some(c.distance);
                if min_of(&mut rep.min_scene_clearance, c.distance, i) {
                    rep.min_clearance_pairs[0] = Some(format!("{}|{}", cm.name(c.a), cm.name(c.b)));
                }
            }
            if let Some(c) = rod_geom.as_ref().and_then(|r| cm.rod_clearance(&ws, r)) {
                row.rod_clearance = Some(c.distance);
                if min_of(&mut rep.min_rod_clearance, c.distance, i) {
                    rep.min_clearance_pairs[1] = Some(format!("{}|{}", cm.name(c.a), cm.name(c.b)));
                }
            }
        }
        rows.push(row);
    }
    if let Some(t) = &traj.t {
        let mut v_lim: Vec<Real> = model
            .joints()
            .iter()
            .map(|j| j.velocity * opt.velocity_scale)
            .collect();
        let mut a_lim: Vec<Real> = rig
            .joint_acceleration_limits(dof)?
            .iter()
            .map(|a| a * opt.acceleration_scale)
            .collect();
        if traj.motor.is_some() {
            v_lim.push(rig.motor.max_velocity * opt.velocity_scale);
            a_lim.push(rig.motor.max_acceleration * opt.acceleration_scale);
        }
        let rates = rate_check(traj, t, &v_lim, &a_lim);
        rep.velocity_violations = rates.velocity_rows;
        rep.acceleration_violations = rates.acceleration_rows;
        rep.max_velocity_ratio = rates.max_velocity;
        rep.max_acceleration_ratio = rates.max_acceleration;
        if checker.robot_only {
            // No acceleration limits without a rig.
            rep.acceleration_violations = 0;
            rep.max_acceleration_ratio = None;
        }
    }
    pairs.sort_by(|x, y| x.kind.cmp(&y.kind).then(x.first_row.cmp(&y.first_row)));
    rep.pairs = pairs;
    rep.row_checks = rows;
    Ok(rep)
}

/// Velocities and accelerations of a timed file by finite differences.
struct Rates {
    velocity_rows: usize,
    acceleration_rows: usize,
    max_velocity: Option<(Real, usize)>,
    max_acceleration: Option<(Real, usize)>,
}

/// The finite-difference rate check of a timed file (module docs, "Rates"): segment k (row k →
/// k+1) moves at `(x_{k+1} − x_k)/(t_{k+1} − t_k)`; row k accelerates by the change of the
/// segment velocity around it over half the two segments' time, `2·(v_k − v_{k−1})/(Δt_{k−1} +
/// Δt_k)`, with the robot at rest before the first row and after the last (a zero-length rest
/// segment). Channels: the joints, then the motor when `limits` has one more entry.
fn rate_check(traj: &JointFile, t: &[Real], v_lim: &[Real], a_lim: &[Real]) -> Rates {
    let n = traj.rows();
    let dof = traj.dof;
    let value = |i: usize, c: usize| -> Real {
        if c < dof {
            traj.row(i)[c]
        } else {
            traj.motor.as_ref().map_or(0.0, |m| m[i])
        }
    };
    let channels = v_lim.len();
    let mut out = Rates {
        velocity_rows: 0,
        acceleration_rows: 0,
        max_velocity: None,
        max_acceleration: None,
    };
    // Velocity of segment k (k in 0..n-1) and channel c; rest outside.
    let seg = |k: usize, c: usize| -> (Real, Real) {
        let dt = t[k + 1] - t[k];
        let dx = value(k + 1, c) - value(k, c);
        let v = if dx == 0.0 {
            0.0
        } else if dt > 0.0 {
            dx / dt
        } else {
            Real::INFINITY
        };
        (v, dt)
    };
    let bump = |cur: &mut Option<(Real, usize)>, r: Real, i: usize| {
        if cur.is_none_or(|(m, _)| r > m) {
            *cur = Some((r, i));
        }
    };
    for i in 0..n {
        let mut v_bad = false;
        let mut a_bad = false;
        for c in 0..channels {
            let (v_in, dt_in) = if i > 0 { seg(i - 1, c) } else { (0.0, 0.0) };
            let (v_out, dt_out) = if i + 1 < n { seg(i, c) } else { (0.0, 0.0) };
            if i > 0 {
                let r = v_in.abs() / v_lim[c];
                bump(&mut out.max_velocity, r, i);
                v_bad |= r.is_nan() || r > 1.0 + RATE_SLACK;
            }
            let half = 0.5 * (dt_in + dt_out);
            let dv = v_out - v_in;
            let r = if dv == 0.0 {
                0.0
            } else if half > 0.0 {
                dv.abs() / half / a_lim[c]
            } else {
                Real::INFINITY
            };
            bump(&mut out.max_acceleration, r, i);
            a_bad |= r.is_nan() || r > 1.0 + RATE_SLACK;
        }
        out.velocity_rows += v_bad as usize;
        out.acceleration_rows += a_bad as usize;
    }
    out
}

impl CheckReport {
    /// Whether the trajectory passed: no limit violation, no collision.
    pub fn passed(&self) -> bool {
        self.limit_violations == 0 && self.collisions == 0
    }

    /// The number of findings of each kind ([`Finding`]): limit rows, colliding rows plus
    /// colliding interpolated steps, steps over the bound, rows over a speed or acceleration
    /// limit, rows over a pose tolerance.
    pub fn findings(&self) -> [(Finding, usize); 6] {
        [
            (Finding::Limit, self.limit_violations),
            (
                Finding::Collision,
                self.collisions + self.segment_collisions,
            ),
            (Finding::Step, self.steps_over_bound),
            (Finding::Velocity, self.velocity_violations),
            (Finding::Acceleration, self.acceleration_violations),
            (Finding::Pose, self.pose_violations),
        ]
    }

    /// The bits ([`Finding`] values) of the kinds found; 0 when the file passes the gate.
    pub fn finding_mask(&self) -> u8 {
        self.findings()
            .iter()
            .filter(|(_, n)| *n > 0)
            .fold(0, |m, (f, _)| m | *f as u8)
    }

    /// The JSON summary (keys: `file`, `rig`, `clamp`, `rows`, `limit_violations`,
    /// `collisions`, `self_collisions`, `scene_collisions`, `rod_collisions`, `rod_checked`,
    /// `colliding_pairs`, `collision_rows`, `limit_rows`, `segment_collisions`,
    /// `max_joint_step`, `max_joint_step_row`, `steps_over_0.2`, `path_length`,
    /// `max_position_error`, `max_position_error_row`, `max_rotation_error`,
    /// `max_rotation_error_row`, `s_max_reached`, `min_scene_clearance`, `min_rod_clearance`).
    /// Rows are 0-based; lists hold at most [`MAX_LISTED`] entries; absent figures are `null`.
    pub fn to_json(&self) -> serde_json::Value {
        let collision_rows: Vec<serde_json::Value> = self
            .row_checks
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.contacts.is_empty())
            .take(MAX_LISTED)
            .map(|(i, r)| serde_json::json!({"row": i, "line": r.line, "contacts": r.contacts}))
            .collect();
        let limit_rows: Vec<serde_json::Value> = self
            .row_checks
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.limit.as_ref().map(|l| (i, r.line, l)))
            .take(MAX_LISTED)
            .map(|(i, line, l)| serde_json::json!({"row": i, "line": line, "limit": l}))
            .collect();
        let pairs: Vec<serde_json::Value> = self
            .pairs
            .iter()
            .map(|p| {
                serde_json::json!({"kind": p.kind, "a": p.a, "b": p.b, "rows": p.rows,
                    "first_row": p.first_row})
            })
            .collect();
        let v = |x: Option<(Real, usize)>| x.map(|(v, _)| v);
        let r = |x: Option<(Real, usize)>| x.map(|(_, r)| r);
        let findings: serde_json::Map<String, serde_json::Value> = self
            .findings()
            .iter()
            .map(|(f, n)| (f.as_str().to_string(), serde_json::json!(n)))
            .collect();
        let gate = serde_json::json!({
            "gate_passed": self.finding_mask() == 0,
            "findings": findings,
            "max_step_bound": self.max_step_bound,
            "steps_over_bound": self.steps_over_bound,
            "timed": self.timed,
            "velocity_violations": self.velocity_violations,
            "acceleration_violations": self.acceleration_violations,
            "max_velocity_ratio": v(self.max_velocity_ratio),
            "max_velocity_ratio_row": r(self.max_velocity_ratio),
            "max_acceleration_ratio": v(self.max_acceleration_ratio),
            "max_acceleration_ratio_row": r(self.max_acceleration_ratio),
            "pose_violations": self.pose_violations,
            "pose_at_file_s": self.pose_at_file_s,
        });
        let mut doc = serde_json::json!({
            "file": self.file.display().to_string(),
            "rig": self.rig,
            "clamp": self.clamp,
            "rows": self.rows,
            "limit_violations": self.limit_violations,
            "collisions": self.collisions,
            "self_collisions": self.self_collisions,
            "scene_collisions": self.scene_collisions,
            "rod_collisions": self.rod_collisions,
            "rod_checked": self.rod_checked,
            "colliding_pairs": pairs,
            "collision_rows": collision_rows,
            "limit_rows": limit_rows,
            "segment_collisions": self.segment_collisions,
            "max_joint_step": self.max_joint_step.0,
            "max_joint_step_row": self.max_joint_step.1,
            "steps_over_0.2": self.steps_over_jump,
            "path_length": self.path_length,
            "max_position_error": v(self.max_position_error),
            "max_position_error_row": r(self.max_position_error),
            "max_rotation_error": v(self.max_rotation_error),
            "max_rotation_error_row": r(self.max_rotation_error),
            "s_max_reached": self.s_max_reached,
            "min_scene_clearance": v(self.min_scene_clearance),
            "min_scene_clearance_row": r(self.min_scene_clearance),
            "min_scene_clearance_pair": self.min_clearance_pairs[0],
            "min_rod_clearance": v(self.min_rod_clearance),
            "min_rod_clearance_row": r(self.min_rod_clearance),
            "min_rod_clearance_pair": self.min_clearance_pairs[1],
        });
        if let (Some(d), serde_json::Value::Object(g)) = (doc.as_object_mut(), gate) {
            d.extend(g);
        }
        doc
    }
}
