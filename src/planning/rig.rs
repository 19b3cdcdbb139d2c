//! Rig files: which robot holds the rod, where the clamp is, the rod, the motor, the roll mode,
//! the helix azimuths, the scene and the planner settings ([architecture §4](crate::architecture)).
//!
//! A rig is a TOML file (see `robots/sawyer-seed.toml`, which documents every field). It is parsed
//! into private raw structs (`deny_unknown_fields`, so a typo is an error) and then validated into
//! a [`Rig`]: every number is checked for its domain, and a failure is an
//! [`Error::InvalidParameter`] whose field names the file and the TOML path, e.g.
//! `robots/my.toml: rod.length = -1: must be finite and > 0`.
//!
//! # Frames
//! - The **base frame** is the URDF root of the robot; every pose in the rig is written in it.
//! - The **clamp frame** `[d1 d2 d3]` has its origin at the clamped end, `d3` the rod tangent there,
//!   `d1` the direction the helix (at azimuth 0) first curls toward, `d2 = d3 × d1`.
//! - The **tool frame** at the rod end has `z = −d3`, `x = d2`, `y = d1` of the rod's
//!   parallel-transported end frame, i.e. `R_tool = D·P` with `P = [e2 e1 −e3]` (columns);
//!   the robot's tip link carries it through the fixed transform `tool` (tip → tool).
//!   For the straight rod the tool sits at `clamp + L·d3` with rotation `R_clamp·P`.
//!
//! # Loading
//! [`Rig::load`] takes a path, or the name of an embedded rig ([`EMBEDDED_RIGS`]) so that
//! `--rig sawyer-seed` works from any directory.
//!
//! ```
//! let rig = helixreach::planning::rig::Rig::load("sawyer-seed").unwrap();
//! assert_eq!(rig.robot.tip_link, "right_motor_tip");
//! assert!((rig.rod.length - 0.51).abs() < 1e-15);
//! // The straight rod's tool pose: clamp + (0, 0, 0.51), rotation diag(−1, 1, −1).
//! let t = rig.straight_tool_pose();
//! assert!((t.translation.vector - nalgebra::Vector3::new(0.85, -0.15, 0.366)).norm() < 1e-12);
//! let r = t.rotation.to_rotation_matrix().into_inner();
//! assert!((r - nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(-1.0, 1.0, -1.0))).norm() < 1e-12);
//! ```

use crate::error::{Error, Result};
use crate::math::{Iso3, Mat3, Real, Vec3, DEG};
use crate::robot::collision::{CollisionKind, CollisionSettings, RodGeometry, MAX_PADDING};
use crate::robot::mesh::MeshSearch;
use crate::robot::SceneObstacle;
use crate::robot::{CollisionModel, DisabledPairs, LoadOptions, RobotModel};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Rigs compiled into the binary, loadable by name: `(name, TOML text)`.
pub const EMBEDDED_RIGS: &[(&str, &str)] = &[
    ("sawyer-seed", include_str!("../../robots/sawyer-seed.toml")),
    ("panda-bench", include_str!("../../robots/panda-bench.toml")),
];

/// Directory the embedded rigs resolve their URDF paths in (the crate's `robots/`).
pub const EMBEDDED_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/robots");

/// How the rod end's roll about its tangent is produced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RollMode {
    /// The arm holds exactly the parallel-transported end frame; the motor adds ω/c
    /// (the seed paper's scheme).
    Fixed,
    /// The arm's roll about the rod tangent is free; the motor makes up the difference.
    Motor,
}

impl RollMode {
    /// The name used in rig files and CSV output (`fixed`, `motor`).
    pub fn as_str(&self) -> &'static str {
        match self {
            RollMode::Fixed => "fixed",
            RollMode::Motor => "motor",
        }
    }
}

impl std::str::FromStr for RollMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "fixed" => Ok(RollMode::Fixed),
            "motor" => Ok(RollMode::Motor),
            _ => Err(Error::invalid("roll mode", s, "must be `fixed` or `motor`")),
        }
    }
}

impl std::fmt::Display for RollMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// How a ray is decided (`planner.search`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SearchMethod {
    /// The ladder: tracked branches, start levels, gates and reconfiguration walks
    /// ([`crate::planning::ladder`]).
    Ladder,
    /// The search of the valid set with a path or a certificate ([`crate::planning::search`]).
    #[default]
    Exact,
}

impl SearchMethod {
    /// The name used in rig files and on the command line (`ladder`, `exact`).
    pub fn as_str(&self) -> &'static str {
        match self {
            SearchMethod::Ladder => "ladder",
            SearchMethod::Exact => "exact",
        }
    }
}

impl std::str::FromStr for SearchMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "ladder" => Ok(SearchMethod::Ladder),
            "exact" => Ok(SearchMethod::Exact),
            _ => Err(Error::invalid(
                "planner.search",
                s,
                "must be `ladder` or `exact`",
            )),
        }
    }
}

/// The robot of a rig.
#[derive(Debug, Clone)]
pub struct RobotSpec {
    /// As written in the rig: a built-in robot name (`sawyer`, `panda`, …) or a URDF path
    /// (relative paths are taken from the rig file's directory).
    pub urdf: String,
    /// The rig file's directory (where relative URDF paths resolve).
    pub dir: PathBuf,
    /// The link whose frame, times [`Rig::tool`], is the rod-end tool frame.
    pub tip_link: String,
    /// Package directories for `package://` mesh names (`[robot] package_paths`, relative to
    /// the rig file), searched before `ROS_PACKAGE_PATH`.
    pub package_paths: Vec<PathBuf>,
    /// Links meant to have no collision geometry (`[robot] no_collision`).
    pub no_collision: Vec<String>,
    /// Padding of the robot's collision bodies (`[robot] padding`, `[robot.link_padding]`) and
    /// what is checked for mesh hulls (`[robot] collision_model`: `hull`, `primitives` or
    /// `primitives_then_hull`, the default; see
    /// [`CollisionKind`]).
    pub collision: CollisionSettings,
    /// A MoveIt SRDF whose `<disable_collisions>` pairs are skipped (`[robot] srdf`, relative
    /// to the rig file), besides the robot's own never-colliding list.
    pub srdf: Option<PathBuf>,
}

impl RobotSpec {
    /// How the robot is loaded: the rig's package paths and `no_collision` links.
    pub fn load_options(&self) -> LoadOptions {
        LoadOptions {
            search: MeshSearch::new(self.package_paths.clone()),
            no_collision: self.no_collision.clone(),
        }
    }

    /// Load the robot; errors name the rig file `rig_source`. The rig's SRDF joins the model's
    /// [`sources`](RobotModel::sources).
    pub fn load_model(&self, rig_source: &str) -> Result<RobotModel> {
        let mut m =
            RobotModel::load_with(&self.source(), Some(&self.tip_link), &self.load_options())
                .map_err(|e| {
                    Error::invalid(
                        format!("{rig_source}: robot"),
                        format!("urdf = {:?}, tip_link = {:?}", self.urdf, self.tip_link),
                        format!("cannot load the robot: {e}"),
                    )
                })?;
        if let Some(p) = &self.srdf {
            let (_, s) = crate::sources::SourceFile::read(p).map_err(|e| {
                Error::invalid(
                    format!("{rig_source}: robot.srdf"),
                    p.display(),
                    e.to_string(),
                )
            })?;
            m.add_source(s);
        }
        Ok(m)
    }

    /// The collision model of `model` (its disabled pairs, the rig's padding) with `obstacles`;
    /// says once on stderr what is checked ([`CollisionModel::announce`]). Errors name the rig.
    pub fn collision_model(
        &self,
        model: &RobotModel,
        obstacles: &[SceneObstacle],
        rig_source: &str,
    ) -> Result<CollisionModel> {
        let mut disabled = DisabledPairs::for_model(model).map_err(|e| {
            Error::invalid(format!("{rig_source}: robot"), &self.urdf, e.to_string())
        })?;
        if let Some(p) = &self.srdf {
            let srdf = DisabledPairs::from_srdf_file(p).map_err(|e| {
                Error::invalid(
                    format!("{rig_source}: robot.srdf"),
                    p.display(),
                    e.to_string(),
                )
            })?;
            disabled = disabled.merged(&srdf);
        }
        let mut cm = CollisionModel::with_settings(model, &disabled, &[], &self.collision)
            .map_err(|e| {
                Error::invalid(format!("{rig_source}: robot"), &self.urdf, e.to_string())
            })?;
        cm.set_obstacles(obstacles)
            .map_err(|e| Error::invalid(format!("{rig_source}: obstacle"), "", e.to_string()))?;
        cm.announce();
        Ok(cm)
    }

    /// What to hand to the robot loader: the resolved path when a file of that (relative) name
    /// exists beside the rig, else the name as written (a built-in robot, or a path the loader
    /// will report as missing).
    pub fn source(&self) -> String {
        let p = Path::new(&self.urdf);
        let resolved = if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.dir.join(p)
        };
        if resolved.is_file() {
            resolved.display().to_string()
        } else {
            self.urdf.clone()
        }
    }
}

/// The rod's material and geometry: the crate's one rod type, [`PhysicalRod`](crate::rod::dynamics::PhysicalRod) (the rig file's
/// `rod.poisson` is its `nu`).
pub use crate::rod::dynamics::PhysicalRod as RodSpec;

/// The end-effector motor that turns the rod end about the tool z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorSpec {
    /// Speed limit (rad/s).
    pub max_velocity: Real,
    /// Acceleration limit (rad/s²; TOML `motor.max_acceleration`, default
    /// [`DEFAULT_MOTOR_ACCELERATION`]).
    pub max_acceleration: Real,
    /// Position range (rad); `(−∞, ∞)` for a motor that turns freely.
    pub range: (Real, Real),
}

/// The motor's acceleration limit when the rig does not state one (rad/s²).
pub const DEFAULT_MOTOR_ACCELERATION: Real = 5.0;

/// Every arm joint's acceleration limit when the rig does not state `planner.joint_acceleration`
/// (rad/s²): URDFs carry no acceleration limits, and this is below every published limit of the
/// embedded arms (Panda: 7.5–20 rad/s²).
pub const DEFAULT_JOINT_ACCELERATION: Real = 2.0;

/// The one rule for a margin M past the boundary — `planner.margin`,
/// `planner.margin_supercritical` and the `--margin` of every command (`plan`, `reach`, `layout`,
/// …): the rod is driven to s*·(1 + M) with 0 ≤ M ≤ 1. 0 drives exactly to the predicted boundary
/// (as the seed experiment did), 1 to twice it.
pub const MARGIN_RULE: &str =
    "must lie in [0, 1] (the rod is driven to s*·(1 + margin); 0: exactly to the predicted boundary)";

/// Whether `m` obeys [`MARGIN_RULE`].
pub fn margin_ok(m: Real) -> bool {
    (0.0..=1.0).contains(&m)
}

/// Planner settings (the `[planner]` table).
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerSettings {
    /// Fraction past the boundary s* to drive the rod ([`MARGIN_RULE`]: 0 ≤ margin ≤ 1; 0 = to
    /// the boundary).
    pub margin: Real,
    /// Fraction past s* for a ray whose loss of stability is supercritical (a gradual
    /// departure: amplitude ∝ √(s − s*), so it must be driven further before it is visible);
    /// `None` = [`PlannerSettings::margin`] (TOML `margin_supercritical`). See
    /// [`PlannerSettings::margin_for`].
    pub margin_supercritical: Option<Real>,
    /// Largest rod-end translation between consecutive waypoints (m).
    pub max_end_step: Real,
    /// Largest rod-end rotation between consecutive waypoints (rad).
    pub max_end_angle: Real,
    /// 0 = adaptive waypoints; N > 0 = N waypoints uniform in s.
    pub waypoints: usize,
    /// Upper bound on the number of waypoints of one ray.
    pub max_waypoints: usize,
    /// Largest step of any joint between two consecutive configurations of a plan (rad): a
    /// ladder step, or a move of the search (its longer walks and roll moves are chains of
    /// sub-steps within it, [`crate::planning::search`]).
    pub max_joint_step: Real,
    /// Diverse fresh IK solutions at the start of a ray (the base rung width).
    pub redundancy_samples: usize,
    /// Densest start sampling, in nodes per connected valid start component: a ray the base
    /// rungs do not make testable is planned again from nested, denser samplings of the whole
    /// valid self-motion set of the straight rod (2R, 4R, … ≤ this, R = `redundancy_samples`;
    /// [`crate::planning::ladder`], "Dense levels"). 0 or ≤ R: no dense levels. Doubling it
    /// never reaches less.
    pub dense_samples: usize,
    /// Joint-space interpolation step for segment collision checks (rad).
    pub segment_check_step: Real,
    /// Number of capsules modelling the rod against the arm.
    pub rod_capsules: usize,
    /// Extra clearance added to the rod radius in the rod-vs-arm check (m).
    pub rod_clearance: Real,
    /// Rod length near the held end excluded from the rod-vs-arm check (m).
    pub rod_end_exclusion: Real,
    /// Quasi-static rod-end speed (m/s).
    pub end_speed: Real,
    /// Fraction of the URDF joint speed limits used by the time parametrization, in (0, 1].
    pub velocity_scale: Real,
    /// Joint acceleration limits (rad/s², one per arm joint; empty = every joint
    /// [`DEFAULT_JOINT_ACCELERATION`]). The time parametrization uses them scaled by
    /// `acceleration_scale`; `check` gates on them unscaled.
    pub joint_acceleration: Vec<Real>,
    /// Fraction of the joint and motor acceleration limits used by the time parametrization, in
    /// (0, 1].
    pub acceleration_scale: Real,
    /// The rod's quasi-static ray speed |ds/dt| (1/s, s the nondimensional distance along the
    /// ray): the largest speed at which DER dynamics (`helixreach simulate`) moves the snap by
    /// less than the fraction the rig file states; ∞ = no limit beyond `end_speed`.
    pub max_ray_speed: Real,
    /// Per-joint weights of the edge cost (empty = all 1).
    pub joint_weights: Vec<Real>,
    /// Weight of the motor step in the edge cost.
    pub motor_weight: Real,
    /// Allow self-motion reconfiguration at a held pose when advancing in s is blocked
    /// ([`crate::planning::self_motion`]). Forbidden, the search's load steps still move along
    /// the self-motion within the joint-step bound where the minimum-norm track lands in
    /// collision ([`crate::planning::search`], "Moves").
    pub allow_reconfiguration: bool,
    /// Largest joint step (max-norm, rad) of the exploration walk along the self-motion manifold
    /// (its sampling resolution) of the ladder and of the start set; the executed
    /// reconfiguration is resampled finer. The search's is `search_step`.
    pub self_motion_step: Real,
    /// Time the rod is held at the end of loading before unloading (s).
    pub hold_time: Real,
    /// How a ray is decided: `exact` (default: [`crate::planning::search`], a path or a
    /// certificate) or `ladder` ([`crate::planning::ladder`]: tracked branches, start levels
    /// and gates).
    pub search: SearchMethod,
    /// Allow driving back along the ray below s* to reconfigure (the search only; phase
    /// `backoff`).
    pub allow_backoff: bool,
    /// Most nodes of one ray's search (≈ 168 bytes each); a ray needing more is `undecided`.
    /// Default 50,000 (≈ 8.4 MB per thread; a ray at the bound costs about 0.25–0.55 s CPU in
    /// roll `fixed`, 0.6–0.8 s in roll `motor` on the seed rig). The roll `fixed` rays of the
    /// seed rig need at most about 31,000 at the default `search_step`; those of the xArm7 rig
    /// `rig init` writes up to about 130,000 (5 of 100 quarter-sphere rays are `undecided` at
    /// the default, partial at 200,000). Large roll `motor` pieces need millions
    /// (`docs/RESULTS.md`): there a larger bound costs about 8 µs CPU per node of every ray
    /// that reaches it, often without deciding it. A study that must decide more raises it.
    pub max_search_nodes: usize,
    /// The search only: most halvings of a slice interval where no single step joins two
    /// slices (a bridge through intermediate poses, like the ladder's refinement; 0: fixed
    /// slices).
    pub bridge_halvings: usize,
    /// The search only: its self-motion resolution (max-norm, rad): samples at most this far
    /// apart along each self-motion curve, two within 0.6 of it one node
    /// ([`crate::planning::search`]). A walk between samples longer than 0.8·`max_joint_step`
    /// is a chain of sub-steps within that, each checked like any edge (every
    /// `segment_check_step`). At most [`crate::planning::search::MAX_SEARCH_STEP`].
    pub search_step: Real,
}

impl PlannerSettings {
    /// The margin past s* for a ray of bifurcation type `kind`: `margin` for a
    /// subcritical ray (it snaps at s*), `margin_supercritical` (default `margin`) for a
    /// supercritical one, and the larger of the two when the type is `degenerate` or not known
    /// (`None`): a ray is then called testable only if the robot can drive it as far as either
    /// type needs.
    ///
    /// ```
    /// use helixreach::bifurcation::BifurcationType as T;
    /// let mut p = helixreach::planning::rig::PlannerSettings::default();
    /// assert!(!p.type_dependent());
    /// p.margin_supercritical = Some(0.25);
    /// assert!(p.type_dependent());
    /// assert_eq!(p.margin_for(Some(T::Subcritical)), 0.10);
    /// assert_eq!(p.margin_for(Some(T::Supercritical)), 0.25);
    /// assert_eq!(p.margin_for(Some(T::Degenerate)), 0.25);
    /// assert_eq!(p.margin_for(None), 0.25);
    /// ```
    pub fn margin_for(&self, kind: Option<crate::bifurcation::BifurcationType>) -> Real {
        use crate::bifurcation::BifurcationType as T;
        let sup = self.margin_supercritical.unwrap_or(self.margin);
        match kind {
            Some(T::Subcritical) => self.margin,
            Some(T::Supercritical) => sup,
            Some(T::Degenerate) | None => self.margin.max(sup),
        }
    }

    /// True when the margin depends on the bifurcation type (`margin_supercritical` set and
    /// different from `margin`): only then does a planner need the type of a ray.
    pub fn type_dependent(&self) -> bool {
        self.margin_supercritical.is_some_and(|m| m != self.margin)
    }
}

impl Default for PlannerSettings {
    /// The defaults (5 mm / 2° waypoints, 0.05 rad joint steps, 10 % margin).
    ///
    /// ```
    /// let p = helixreach::planning::rig::PlannerSettings::default();
    /// assert_eq!(p.max_joint_step, 0.05);
    /// assert_eq!(p.margin, 0.10);
    /// ```
    fn default() -> Self {
        PlannerSettings {
            margin: 0.10,
            margin_supercritical: None,
            max_end_step: 0.005,
            max_end_angle: 2.0 * DEG,
            waypoints: 0,
            max_waypoints: 20_000,
            max_joint_step: 0.05,
            redundancy_samples: 8,
            dense_samples: 32,
            segment_check_step: 0.02,
            rod_capsules: 24,
            rod_clearance: 0.005,
            rod_end_exclusion: 0.05,
            end_speed: 0.01,
            velocity_scale: 0.5,
            joint_acceleration: Vec::new(),
            acceleration_scale: 0.5,
            max_ray_speed: Real::INFINITY,
            joint_weights: Vec::new(),
            motor_weight: 0.0,
            allow_reconfiguration: true,
            self_motion_step: 0.02,
            hold_time: 2.0,
            search: SearchMethod::Exact,
            allow_backoff: true,
            max_search_nodes: 50_000,
            bridge_halvings: 4,
            search_step: 0.16,
        }
    }
}

/// Largest rig `planner.joint_weights` entry: path costs sum weighted joint steps, and a weight
/// this large already makes every other joint's cost vanish next to it.
pub const MAX_JOINT_WEIGHT: Real = 1e6;
/// Smallest rig `planner.end_speed` (m/s): a trajectory's durations are end distances over it.
pub const MIN_END_SPEED: Real = 1e-9;

/// A validated rig.
#[derive(Debug, Clone)]
pub struct Rig {
    /// Rig name.
    pub name: String,
    /// Free-text description.
    pub description: String,
    /// Where it came from (a path, or `<embedded NAME>`), for messages.
    pub source: String,
    /// The robot.
    pub robot: RobotSpec,
    /// Tip link → tool frame.
    pub tool: Iso3,
    /// Base → clamp frame (`[d1 d2 d3]` as the rotation's columns).
    pub clamp: Iso3,
    /// The rod.
    pub rod: RodSpec,
    /// The motor.
    pub motor: MotorSpec,
    /// Roll mode.
    pub roll: RollMode,
    /// Roll seeds per redundancy sample in [`RollMode::Motor`].
    pub roll_samples: usize,
    /// Helix azimuths α (rad) tried per ray.
    pub azimuths: Vec<Real>,
    /// Scene obstacles (base frame), in the robot module's format.
    pub obstacles: Vec<SceneObstacle>,
    /// Planner settings.
    pub planner: PlannerSettings,
}

/// `P = [e2 e1 −e3]`: the tool frame expressed in the rod's `[d1 d2 d3]` frame.
pub fn tool_from_director() -> Mat3 {
    Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)
}

impl Rig {
    /// The arm's joint acceleration limits (rad/s², unscaled) for a robot of `dof` joints:
    /// `planner.joint_acceleration`, or [`DEFAULT_JOINT_ACCELERATION`] for every joint when the
    /// rig lists none. Errors when the list has another length.
    pub fn joint_acceleration_limits(&self, dof: usize) -> Result<Vec<Real>> {
        let a = &self.planner.joint_acceleration;
        if a.is_empty() {
            return Ok(vec![DEFAULT_JOINT_ACCELERATION; dof]);
        }
        if a.len() != dof {
            return Err(Error::invalid(
                format!("{}: planner.joint_acceleration", self.source),
                format!("{a:?}"),
                format!("lists {} values, the robot has {dof} joints", a.len()),
            ));
        }
        Ok(a.clone())
    }

    /// Load a rig from a path, or by the name of an embedded rig (`sawyer-seed`).
    /// A path that exists wins over an embedded name.
    pub fn load(name_or_path: &str) -> Result<Rig> {
        let p = Path::new(name_or_path);
        if p.is_file() {
            return Rig::from_file(p);
        }
        if let Some((name, text)) = EMBEDDED_RIGS.iter().find(|(n, _)| *n == name_or_path) {
            return Rig::from_toml_str(
                text,
                &format!("<embedded {name}>"),
                Path::new(EMBEDDED_DIR),
            );
        }
        let names: Vec<&str> = EMBEDDED_RIGS.iter().map(|(n, _)| *n).collect();
        Err(Error::File {
            path: p.to_path_buf(),
            reason: format!(
                "no such rig file, and not an embedded rig name (embedded: {})",
                names.join(", ")
            ),
        })
    }

    /// Load and validate a rig file.
    pub fn from_file(path: &Path) -> Result<Rig> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Rig::from_toml_str(&text, &path.display().to_string(), dir)
    }

    /// Parse and validate rig TOML. `source` names the file in messages; relative paths in the
    /// rig resolve against `dir`.
    pub fn from_toml_str(text: &str, source: &str, dir: &Path) -> Result<Rig> {
        let raw: RawRig = toml::from_str(text).map_err(|e| Error::File {
            path: PathBuf::from(source),
            reason: format!("not a valid rig file: {e}"),
        })?;
        validate(raw, source, dir)
    }

    /// The clamp frame's rotation `[d1 d2 d3]` in the base frame.
    pub fn clamp_rotation(&self) -> Mat3 {
        self.clamp.rotation.to_rotation_matrix().into_inner()
    }

    /// The rod as the planner checks it for collision: capsules through `nodes` (base frame)
    /// of radius r + `rod_clearance`, the last `rod_end_exclusion` metres at the tool ignored,
    /// against the robot only (the scene is checked against the links).
    pub fn rod_geometry<'a>(&self, nodes: &'a [Vec3]) -> RodGeometry<'a> {
        RodGeometry {
            nodes,
            radius: self.rod.radius + self.planner.rod_clearance,
            ignore_near_tool: self.planner.rod_end_exclusion,
            ignore_near_clamp: 0.0,
            against_scene: false,
        }
    }

    /// Pose of the tool frame for the straight rod: `clamp + L·d3`, rotation `R_clamp·P`.
    pub fn straight_tool_pose(&self) -> Iso3 {
        let r = self.clamp_rotation();
        let p = self.clamp.translation.vector + self.rod.length * r.column(2);
        iso_from(&(r * tool_from_director()), &p)
    }

    /// The same rig with the clamped end moved to `origin` (base frame, m); the clamp's
    /// orientation `[d1 d2 d3]` and everything else are kept. The seed experiment moved its clamp
    /// between runs (`trajectories.csv` gives each run's position); `--clamp x,y,z` uses this.
    ///
    /// Errors: a non-finite coordinate → [`Error::InvalidParameter`] naming the rig, the field
    /// `clamp.origin[i]` and the value.
    ///
    /// ```
    /// use helixreach::planning::rig::Rig;
    /// let rig = Rig::load("sawyer-seed").unwrap();
    /// let moved = rig.with_clamp_origin([0.80, -0.10, -0.15]).unwrap();
    /// let t = moved.straight_tool_pose().translation.vector;
    /// assert!((t - nalgebra::Vector3::new(0.80, -0.10, -0.15 + 0.51)).norm() < 1e-12);
    /// assert_eq!(moved.clamp.rotation, rig.clamp.rotation);
    /// let e = rig.with_clamp_origin([0.8, f64::NAN, 0.0]).unwrap_err().to_string();
    /// assert!(e.contains("clamp.origin[1]") && e.contains("NaN"), "{e}");
    /// ```
    pub fn with_clamp_origin(&self, origin: [Real; 3]) -> Result<Rig> {
        for (i, v) in origin.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::invalid(
                    format!("{}: clamp.origin[{i}] (clamp override)", self.source),
                    v,
                    "must be finite",
                ));
            }
        }
        let mut rig = self.clone();
        rig.clamp.translation = nalgebra::Translation3::new(origin[0], origin[1], origin[2]);
        Ok(rig)
    }

    /// The motor angle making the material frame from the arm's frame: in [`RollMode::Fixed`]
    /// the arm holds the transported frame and the motor angle is `ω·s/c`.
    pub fn twist_ratio(&self) -> Real {
        self.rod.twist_ratio()
    }
}

/// Parse a command-line triple `x,y,z` (e.g. `--clamp 0.85,-0.15,-0.144`) into three numbers.
/// Non-finite values (`nan`, `inf`) parse: the consumer validates them and names the field
/// (e.g. [`Rig::with_clamp_origin`]). Errors name `flag` and the text.
///
/// ```
/// use helixreach::planning::rig::parse_xyz;
/// assert_eq!(parse_xyz("--clamp", "0.85, -0.15,-0.144").unwrap(), [0.85, -0.15, -0.144]);
/// assert!(parse_xyz("--clamp", "1,2").unwrap_err().to_string().contains("--clamp"));
/// ```
pub fn parse_xyz(flag: &str, text: &str) -> Result<[Real; 3]> {
    let bad = || Error::invalid(flag, format!("`{text}`"), "expected three numbers x,y,z");
    let v: Vec<Real> = text
        .split(',')
        .map(|x| x.trim().parse::<Real>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad())?;
    match v.as_slice() {
        [x, y, z] => Ok([*x, *y, *z]),
        _ => Err(bad()),
    }
}

/// An isometry from a rotation matrix (assumed orthonormal) and a translation.
pub fn iso_from(r: &Mat3, p: &Vec3) -> Iso3 {
    let rot = nalgebra::Rotation3::from_matrix_unchecked(*r);
    Iso3::from_parts(
        nalgebra::Translation3::from(*p),
        nalgebra::UnitQuaternion::from_rotation_matrix(&rot),
    )
}

// ---------------------------------------------------------------------------------------------
// Raw TOML structs.

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRig {
    name: String,
    #[serde(default)]
    description: String,
    robot: RawRobot,
    #[serde(default)]
    tool: RawTool,
    clamp: RawClamp,
    rod: RawRod,
    motor: RawMotor,
    #[serde(default)]
    roll: RawRoll,
    #[serde(default)]
    azimuth: RawAzimuth,
    #[serde(default, rename = "obstacle")]
    obstacles: Vec<SceneObstacle>,
    #[serde(default)]
    planner: RawPlanner,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRobot {
    urdf: String,
    tip_link: String,
    #[serde(default)]
    package_paths: Vec<String>,
    #[serde(default)]
    no_collision: Vec<String>,
    #[serde(default)]
    padding: Real,
    #[serde(default)]
    link_padding: std::collections::BTreeMap<String, Real>,
    #[serde(default)]
    srdf: Option<String>,
    #[serde(default)]
    collision_model: Option<String>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawTool {
    #[serde(default, deserialize_with = "crate::math::exact3::deserialize")]
    xyz: [Real; 3],
    #[serde(default, deserialize_with = "crate::math::exact3::deserialize")]
    rpy: [Real; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawClamp {
    #[serde(deserialize_with = "crate::math::exact3::deserialize")]
    origin: [Real; 3],
    #[serde(deserialize_with = "crate::math::exact3::deserialize")]
    d1: [Real; 3],
    #[serde(deserialize_with = "crate::math::exact3::deserialize")]
    d3: [Real; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRod {
    length: Real,
    #[serde(default)]
    diameter: Option<Real>,
    #[serde(default)]
    radius: Option<Real>,
    youngs_modulus: Real,
    poisson: Real,
    density: Real,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMotor {
    max_velocity: Real,
    #[serde(default)]
    max_acceleration: Option<Real>,
    #[serde(default)]
    lower: Option<Real>,
    #[serde(default)]
    upper: Option<Real>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRoll {
    #[serde(default = "default_roll_mode")]
    mode: String,
    #[serde(default = "default_roll_samples")]
    samples: usize,
}

fn default_roll_mode() -> String {
    "fixed".into()
}
fn default_roll_samples() -> usize {
    4
}

impl Default for RawRoll {
    fn default() -> Self {
        RawRoll {
            mode: default_roll_mode(),
            samples: default_roll_samples(),
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAzimuth {
    #[serde(default)]
    choices: Option<Vec<Real>>,
    #[serde(default)]
    count: Option<usize>,
}

impl Default for RawAzimuth {
    fn default() -> Self {
        RawAzimuth {
            choices: Some(vec![0.0]),
            count: None,
        }
    }
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawPlanner {
    margin: Option<Real>,
    margin_supercritical: Option<Real>,
    max_end_step: Option<Real>,
    max_end_angle_deg: Option<Real>,
    waypoints: Option<usize>,
    max_waypoints: Option<usize>,
    max_joint_step: Option<Real>,
    redundancy_samples: Option<usize>,
    dense_samples: Option<usize>,
    segment_check_step: Option<Real>,
    rod_capsules: Option<usize>,
    rod_clearance: Option<Real>,
    rod_end_exclusion: Option<Real>,
    end_speed: Option<Real>,
    velocity_scale: Option<Real>,
    joint_acceleration: Option<Vec<Real>>,
    acceleration_scale: Option<Real>,
    max_ray_speed: Option<Real>,
    joint_weights: Option<Vec<Real>>,
    motor_weight: Option<Real>,
    allow_reconfiguration: Option<bool>,
    self_motion_step: Option<Real>,
    hold_time: Option<Real>,
    search: Option<String>,
    allow_backoff: Option<bool>,
    max_search_nodes: Option<usize>,
    bridge_halvings: Option<usize>,
    search_step: Option<Real>,
}

// ---------------------------------------------------------------------------------------------
// Validation.

struct Ctx<'a> {
    source: &'a str,
}

impl Ctx<'_> {
    fn err(&self, field: &str, value: impl std::fmt::Display, reason: &str) -> Error {
        Error::invalid(format!("{}: {field}", self.source), value, reason)
    }
    fn finite(&self, field: &str, v: Real) -> Result<Real> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, v, "must be finite"))
        }
    }
    fn positive(&self, field: &str, v: Real) -> Result<Real> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, v, "must be finite and > 0"))
        }
    }
    fn non_negative(&self, field: &str, v: Real) -> Result<Real> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, v, "must be finite and >= 0"))
        }
    }
    fn vec3(&self, field: &str, v: [Real; 3]) -> Result<Vec3> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(Vec3::new(v[0], v[1], v[2]))
        } else {
            Err(self.err(field, format!("{v:?}"), "must be three finite numbers"))
        }
    }
    fn count(&self, field: &str, v: usize, min: usize) -> Result<usize> {
        let max = crate::limits::rig_count_max(field);
        if (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(
                field,
                v,
                &format!("must be in {min}..={max} (helixreach::limits)"),
            ))
        }
    }
}

fn rpy_matrix(rpy: &Vec3) -> Mat3 {
    nalgebra::Rotation3::from_euler_angles(rpy.x, rpy.y, rpy.z).into_inner()
}

fn validate(raw: RawRig, source: &str, dir: &Path) -> Result<Rig> {
    let c = Ctx { source };
    if raw.name.trim().is_empty() {
        return Err(c.err("name", "\"\"", "must not be empty"));
    }

    // Robot.
    if raw.robot.tip_link.trim().is_empty() {
        return Err(c.err("robot.tip_link", "\"\"", "must name a link of the URDF"));
    }
    if raw.robot.urdf.trim().is_empty() {
        return Err(c.err("robot.urdf", "\"\"", "must name a URDF file"));
    }

    // Tool transform.
    let txyz = c.vec3("tool.xyz", raw.tool.xyz)?;
    let trpy = c.vec3("tool.rpy", raw.tool.rpy)?;
    let tool = iso_from(&rpy_matrix(&trpy), &txyz);

    // Clamp frame.
    let origin = c.vec3("clamp.origin", raw.clamp.origin)?;
    let d1 = c.vec3("clamp.d1", raw.clamp.d1)?;
    let d3 = c.vec3("clamp.d3", raw.clamp.d3)?;
    for (field, v, raw_v) in [
        ("clamp.d1", d1, raw.clamp.d1),
        ("clamp.d3", d3, raw.clamp.d3),
    ] {
        let n = v.norm();
        if !(n > 0.0 && n.is_finite()) {
            return Err(c.err(
                field,
                format!("{raw_v:?}"),
                &format!("must be non-zero with a finite norm (|v| = {n})"),
            ));
        }
    }
    let (d1, d3) = (d1.normalize(), d3.normalize());
    if d1.dot(&d3).abs() > crate::math::tol::INPUT_ROTATION {
        return Err(c.err(
            "clamp.d1",
            format!("{:?}", raw.clamp.d1),
            &format!(
                "must be perpendicular to clamp.d3 (d1·d3 = {:.3e} after normalizing)",
                d1.dot(&d3)
            ),
        ));
    }
    let d2 = d3.cross(&d1);
    let rc = Mat3::from_columns(&[d1, d2, d3]);
    let clamp = iso_from(&rc, &origin);

    // Rod.
    let length = c.positive("rod.length", raw.rod.length)?;
    let radius = match (raw.rod.diameter, raw.rod.radius) {
        (Some(d), None) => 0.5 * c.positive("rod.diameter", d)?,
        (None, Some(r)) => c.positive("rod.radius", r)?,
        (Some(d), Some(_)) => {
            return Err(c.err(
                "rod.diameter",
                d,
                "give either rod.diameter or rod.radius, not both",
            ))
        }
        (None, None) => {
            return Err(c.err(
                "rod.diameter",
                "(missing)",
                "give rod.diameter or rod.radius",
            ))
        }
    };
    if radius * 20.0 > length {
        return Err(c.err(
            "rod.diameter",
            2.0 * radius,
            &format!("a rod of length {length} m this thick is not slender (need 2r ≤ L/10)"),
        ));
    }
    let youngs_modulus = c.positive("rod.youngs_modulus", raw.rod.youngs_modulus)?;
    let poisson = c.finite("rod.poisson", raw.rod.poisson)?;
    if !(poisson > -1.0 && poisson <= 0.5) {
        return Err(c.err("rod.poisson", poisson, "must lie in (−1, 0.5]"));
    }
    let density = c.positive("rod.density", raw.rod.density)?;
    let rod = RodSpec {
        length,
        radius,
        youngs_modulus,
        nu: poisson,
        density,
    };

    // Motor.
    let max_velocity = c.positive("motor.max_velocity", raw.motor.max_velocity)?;
    let lower = match raw.motor.lower {
        Some(v) => c.finite("motor.lower", v)?,
        None => Real::NEG_INFINITY,
    };
    let upper = match raw.motor.upper {
        Some(v) => c.finite("motor.upper", v)?,
        None => Real::INFINITY,
    };
    if !(lower < 0.0 && upper > 0.0) {
        return Err(c.err(
            "motor.lower",
            format!("[{lower}, {upper}]"),
            "the motor range must contain 0 (the straight rod) in its interior",
        ));
    }
    let max_acceleration = c.positive(
        "motor.max_acceleration",
        raw.motor
            .max_acceleration
            .unwrap_or(DEFAULT_MOTOR_ACCELERATION),
    )?;
    let motor = MotorSpec {
        max_velocity,
        max_acceleration,
        range: (lower, upper),
    };

    // Roll.
    let roll: RollMode = raw
        .roll
        .mode
        .parse()
        .map_err(|_| c.err("roll.mode", &raw.roll.mode, "must be `fixed` or `motor`"))?;
    let roll_samples = c.count("roll.samples", raw.roll.samples, 1)?;

    // Azimuths.
    let azimuths = match (raw.azimuth.choices, raw.azimuth.count) {
        (Some(v), None) => {
            if v.is_empty() {
                return Err(c.err("azimuth.choices", "[]", "must list at least one azimuth"));
            }
            if v.len() > crate::limits::MAX_AZIMUTHS {
                return Err(c.err(
                    "azimuth.choices",
                    format!("{} values", v.len()),
                    &format!(
                        "must list at most {} azimuths (helixreach::limits)",
                        crate::limits::MAX_AZIMUTHS
                    ),
                ));
            }
            for (i, a) in v.iter().enumerate() {
                c.finite(&format!("azimuth.choices[{i}]"), *a)?;
            }
            v
        }
        (None, Some(n)) => azimuth_grid(c.count("azimuth.count", n, 1)?),
        (None, None) => vec![0.0],
        (Some(_), Some(n)) => {
            return Err(c.err(
                "azimuth.count",
                n,
                "give either azimuth.choices or azimuth.count, not both",
            ))
        }
    };

    // Obstacles.
    for (i, o) in raw.obstacles.iter().enumerate() {
        o.validate().map_err(|e| {
            c.err(
                &format!("obstacle[{i}]"),
                format!("{:?}", o.name),
                &e.to_string(),
            )
        })?;
    }
    let obstacles = raw.obstacles;

    // Planner.
    let d = PlannerSettings::default();
    let p = raw.planner;
    let margin = c.finite("planner.margin", p.margin.unwrap_or(d.margin))?;
    if !margin_ok(margin) {
        return Err(c.err("planner.margin", margin, MARGIN_RULE));
    }
    let margin_supercritical = match p.margin_supercritical {
        None => None,
        Some(m) => {
            let m = c.finite("planner.margin_supercritical", m)?;
            if !margin_ok(m) {
                return Err(c.err("planner.margin_supercritical", m, MARGIN_RULE));
            }
            Some(m)
        }
    };
    let max_joint_step = c.positive(
        "planner.max_joint_step",
        p.max_joint_step.unwrap_or(d.max_joint_step),
    )?;
    if max_joint_step > std::f64::consts::PI {
        return Err(c.err("planner.max_joint_step", max_joint_step, "must be ≤ π rad"));
    }
    let max_end_angle = c.positive(
        "planner.max_end_angle_deg",
        p.max_end_angle_deg.unwrap_or(d.max_end_angle / DEG),
    )? * DEG;
    let velocity_scale = c.positive(
        "planner.velocity_scale",
        p.velocity_scale.unwrap_or(d.velocity_scale),
    )?;
    if velocity_scale > 1.0 {
        return Err(c.err(
            "planner.velocity_scale",
            velocity_scale,
            "must lie in (0, 1]",
        ));
    }
    let acceleration_scale = c.positive(
        "planner.acceleration_scale",
        p.acceleration_scale.unwrap_or(d.acceleration_scale),
    )?;
    if acceleration_scale > 1.0 {
        return Err(c.err(
            "planner.acceleration_scale",
            acceleration_scale,
            "must lie in (0, 1]",
        ));
    }
    let joint_acceleration = p.joint_acceleration.unwrap_or_default();
    for (i, a) in joint_acceleration.iter().enumerate() {
        c.positive(&format!("planner.joint_acceleration[{i}]"), *a)?;
    }
    let max_ray_speed = match p.max_ray_speed {
        Some(v) => c.positive("planner.max_ray_speed", v)?,
        None => d.max_ray_speed,
    };
    let joint_weights = p.joint_weights.unwrap_or_default();
    for (i, w) in joint_weights.iter().enumerate() {
        c.positive(&format!("planner.joint_weights[{i}]"), *w)?;
        if *w > MAX_JOINT_WEIGHT {
            return Err(c.err(
                &format!("planner.joint_weights[{i}]"),
                w,
                &format!("must be <= {MAX_JOINT_WEIGHT:e} (path costs sum weighted joint steps)"),
            ));
        }
    }
    let max_waypoints = c.count(
        "planner.max_waypoints",
        p.max_waypoints.unwrap_or(d.max_waypoints),
        2,
    )?;
    let waypoints = p.waypoints.unwrap_or(d.waypoints);
    if waypoints == 1 || waypoints > max_waypoints {
        return Err(c.err(
            "planner.waypoints",
            waypoints,
            &format!("must be 0 (adaptive) or in [2, planner.max_waypoints = {max_waypoints}]"),
        ));
    }
    let rod_end_exclusion = c.non_negative(
        "planner.rod_end_exclusion",
        p.rod_end_exclusion.unwrap_or(d.rod_end_exclusion),
    )?;
    if rod_end_exclusion >= length {
        return Err(c.err(
            "planner.rod_end_exclusion",
            rod_end_exclusion,
            &format!("must be shorter than the rod (rod.length = {length})"),
        ));
    }
    let planner = PlannerSettings {
        margin,
        margin_supercritical,
        max_end_step: c.positive(
            "planner.max_end_step",
            p.max_end_step.unwrap_or(d.max_end_step),
        )?,
        max_end_angle,
        waypoints,
        max_waypoints,
        max_joint_step,
        redundancy_samples: c.count(
            "planner.redundancy_samples",
            p.redundancy_samples.unwrap_or(d.redundancy_samples),
            1,
        )?,
        dense_samples: c.count(
            "planner.dense_samples",
            p.dense_samples.unwrap_or(d.dense_samples),
            0,
        )?,
        segment_check_step: {
            let v = c.positive(
                "planner.segment_check_step",
                p.segment_check_step.unwrap_or(d.segment_check_step),
            )?;
            let min = crate::limits::MIN_SEGMENT_CHECK_STEP;
            if v < min {
                return Err(c.err(
                    "planner.segment_check_step",
                    v,
                    &format!(
                        "must be >= {min} rad (helixreach::limits): every joint step is sampled \
                         every segment_check_step"
                    ),
                ));
            }
            v
        },
        rod_capsules: c.count(
            "planner.rod_capsules",
            p.rod_capsules.unwrap_or(d.rod_capsules),
            1,
        )?,
        rod_clearance: c.non_negative(
            "planner.rod_clearance",
            p.rod_clearance.unwrap_or(d.rod_clearance),
        )?,
        rod_end_exclusion,
        end_speed: {
            let v = c.positive("planner.end_speed", p.end_speed.unwrap_or(d.end_speed))?;
            if v < MIN_END_SPEED {
                return Err(c.err(
                    "planner.end_speed",
                    v,
                    &format!(
                        "must be >= {MIN_END_SPEED:e} m/s (durations are distances over this \
                         speed)"
                    ),
                ));
            }
            v
        },
        velocity_scale,
        joint_acceleration,
        acceleration_scale,
        max_ray_speed,
        joint_weights,
        motor_weight: c.non_negative(
            "planner.motor_weight",
            p.motor_weight.unwrap_or(d.motor_weight),
        )?,
        allow_reconfiguration: p.allow_reconfiguration.unwrap_or(d.allow_reconfiguration),
        self_motion_step: c.positive(
            "planner.self_motion_step",
            p.self_motion_step.unwrap_or(d.self_motion_step),
        )?,
        hold_time: c.non_negative("planner.hold_time", p.hold_time.unwrap_or(d.hold_time))?,
        search: match &p.search {
            None => d.search,
            Some(s) => s
                .parse()
                .map_err(|_| c.err("planner.search", s, "must be `ladder` or `exact`"))?,
        },
        allow_backoff: p.allow_backoff.unwrap_or(d.allow_backoff),
        max_search_nodes: c.count(
            "planner.max_search_nodes",
            p.max_search_nodes.unwrap_or(d.max_search_nodes),
            1,
        )?,
        bridge_halvings: c.count(
            "planner.bridge_halvings",
            p.bridge_halvings.unwrap_or(d.bridge_halvings),
            0,
        )?,
        search_step: c.positive(
            "planner.search_step",
            p.search_step.unwrap_or(d.search_step),
        )?,
    };
    if planner.self_motion_step > max_joint_step {
        return Err(c.err(
            "planner.self_motion_step",
            planner.self_motion_step,
            &format!("must be ≤ planner.max_joint_step = {max_joint_step}"),
        ));
    }
    let max_search_step = crate::planning::search::MAX_SEARCH_STEP;
    if planner.search_step > max_search_step {
        return Err(c.err(
            "planner.search_step",
            planner.search_step,
            &format!(
                "must be ≤ {max_search_step} rad (helixreach::planning::search::MAX_SEARCH_STEP)"
            ),
        ));
    }

    Ok(Rig {
        name: raw.name,
        description: raw.description,
        source: source.to_string(),
        robot: RobotSpec {
            urdf: raw.robot.urdf,
            dir: dir.to_path_buf(),
            tip_link: raw.robot.tip_link,
            package_paths: raw
                .robot
                .package_paths
                .iter()
                .map(|p| dir.join(p))
                .collect(),
            no_collision: raw.robot.no_collision,
            srdf: raw.robot.srdf.map(|p| dir.join(p)),
            collision: {
                let kind = match &raw.robot.collision_model {
                    None => CollisionKind::default(),
                    Some(name) => CollisionKind::from_name(name).ok_or_else(|| {
                        c.err(
                            "robot.collision_model",
                            format!("{name:?}"),
                            &format!(
                                "must be one of {}",
                                CollisionKind::NAMES
                                    .iter()
                                    .map(|n| format!("\"{n}\""))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        )
                    })?,
                };
                let cs = CollisionSettings {
                    padding: raw.robot.padding,
                    link_padding: raw.robot.link_padding.into_iter().collect(),
                    kind,
                };
                for (what, v) in std::iter::once(("robot.padding".to_string(), cs.padding)).chain(
                    cs.link_padding
                        .iter()
                        .map(|(n, v)| (format!("robot.link_padding.{n}"), *v)),
                ) {
                    if !(v.is_finite() && (0.0..=MAX_PADDING).contains(&v)) {
                        return Err(c.err(
                            &what,
                            v,
                            &format!("must be finite, in 0..={MAX_PADDING} m"),
                        ));
                    }
                }
                cs
            },
        },
        tool,
        clamp,
        rod,
        motor,
        roll,
        roll_samples,
        azimuths,
        obstacles,
        planner,
    })
}

/// `n` azimuths equally spaced in [0, 2π), starting at 0.
pub fn azimuth_grid(n: usize) -> Vec<Real> {
    (0..n)
        .map(|i| 2.0 * std::f64::consts::PI * i as Real / n.max(1) as Real)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed_text() -> &'static str {
        EMBEDDED_RIGS[0].1
    }

    fn load_modified(from: &str, to: &str) -> Result<Rig> {
        let t = seed_text();
        assert!(t.contains(from), "fixture lacks `{from}`");
        Rig::from_toml_str(
            &t.replacen(from, to, 1),
            "test.toml",
            Path::new(EMBEDDED_DIR),
        )
    }

    #[test]
    fn seed_rig_frames() {
        let rig = Rig::load("sawyer-seed").unwrap();
        let rc = rig.clamp_rotation();
        // d1 = +y, d2 = −x, d3 = +z.
        assert!((rc.column(0) - Vec3::y()).norm() < 1e-15);
        assert!((rc.column(1) + Vec3::x()).norm() < 1e-15);
        assert!((rc.column(2) - Vec3::z()).norm() < 1e-15);
        assert!((tool_from_director().determinant() - 1.0).abs() < 1e-15);
        assert_eq!(rig.roll, RollMode::Fixed);
        assert!((rig.rod.radius - 0.79375e-3).abs() < 1e-12);
        assert_eq!(rig.obstacles.len(), 1);
        assert!((rig.planner.max_end_angle - 2.0 * DEG).abs() < 1e-15);
    }

    #[test]
    fn errors_name_file_field_and_value() {
        let cases = [
            ("margin = 0.10", "margin = -0.1", "planner.margin"),
            ("length = 0.51", "length = -0.51", "rod.length"),
            ("poisson = 0.33", "poisson = 0.7", "rod.poisson"),
            ("d1 = [0.0, 1.0, 0.0]", "d1 = [0.0, 0.0, 1.0]", "clamp.d1"),
            ("mode = \"fixed\"", "mode = \"wobbly\"", "roll.mode"),
            ("urdf = \"sawyer\"", "urdf = \"\"", "robot.urdf"),
            (
                "max_joint_step = 0.05",
                "max_joint_step = 0.0",
                "planner.max_joint_step",
            ),
            (
                "search_step = 0.16",
                "search_step = 0.5",
                "planner.search_step",
            ),
            (
                "search_step = 0.16",
                "search_step = -0.04",
                "planner.search_step",
            ),
            ("type = \"box\"", "type = \"cone\"", "cone"),
            (
                "half_extents = [0.40,",
                "half_extents = [-0.40,",
                "half_extents[0]",
            ),
            (
                "max_velocity = 3.0",
                "max_velocity = nan",
                "motor.max_velocity",
            ),
        ];
        for (from, to, field) in cases {
            let e = load_modified(from, to).unwrap_err().to_string();
            assert!(e.contains("test.toml") && e.contains(field), "{to}: {e}");
        }
        // Unknown fields are typos, not silently ignored.
        let e = load_modified("margin = 0.10", "marjin = 0.10")
            .unwrap_err()
            .to_string();
        assert!(e.contains("marjin"), "{e}");
        // A missing rig names what it looked for.
        let e = Rig::load("no-such-rig").unwrap_err().to_string();
        assert!(
            e.contains("no-such-rig") && e.contains("sawyer-seed"),
            "{e}"
        );
    }

    #[test]
    fn azimuth_count_and_roll_mode_parse() {
        let rig = load_modified("choices = [0.0]", "count = 4").unwrap();
        assert_eq!(rig.azimuths.len(), 4);
        assert!((rig.azimuths[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!("motor".parse::<RollMode>().unwrap(), RollMode::Motor);
    }
}
