//! The planner of one ray: a rig's robot, collision model and start set, the validity tests
//! every decision shares, and the decision of a ray by the rig's `planner.search`
//! ([architecture §5](crate::architecture)).
//!
//! [`Planner::plan_ray`] decides one ray at one azimuth: `exact` (the default) by the search
//! of its valid set ([`crate::planning::search`]: a path, a certificate of the farthest s, or
//! `undecided` at the node bound); `ladder` by rungs of tracked IK solutions under dynamic
//! programming ([`crate::planning::ladder`]: a path when one is found, no certificate of a
//! stop). [`Planner::plan_best`] keeps the best over azimuths; [`Planner::trajectory`] times a
//! plan's path.
//!
//! # Shared by both decisions
//! - **Start set** (`planner/start.rs`): the straight rod's valid IK solutions in each roll
//!   mode (the same pose for every ray and azimuth), computed once and cached, grouped by
//!   connected valid self-motion component.
//! - **Validity**: a configuration is valid within the joint (and motor) limits and free of
//!   self, scene and rod collision (the current helix as `rod_capsules` capsules of radius
//!   r + `rod_clearance`, without the last `rod_end_exclusion` metres the motor grips); a
//!   joint-linear segment is checked every `segment_check_step` (max-norm) against the rod of
//!   the larger s.
//! - **Roll modes**: `fixed`: the target is the full tool pose (the transported frame), the
//!   motor angle is ω/c. `motor`: the target is the tool position and z axis (roll free); the
//!   arm's roll ψ about d3 relative to the transported frame is read back by FK and the motor
//!   makes up the rest, `m = ω/c − ψ`. Every fixed-roll path is a motor-roll path (ψ = 0), so
//!   both decisions return in roll `motor` at least what they reach in roll `fixed`.
//! - **Moves between runs** (`planner/transition.rs`): a reconfiguration at the straight rod
//!   and a free move with the rod released, for a campaign.
//!
//! # What the planner assumes of the arm
//! - A serial chain from the URDF root to the rig's tip link: revolute, continuous or
//!   prismatic joints (mimic joints follow their leader), at most `MAX_DOF` = 7, with finite
//!   position and velocity limits; any link names and geometry (primitives or meshes).
//! - **7 joints** (Sawyer, Panda, iiwa, xArm7, any 7-joint chain): the straight rod's pose has
//!   a 1-D self-motion. Its redundancy parameter is joint 0 (the IK grids lock it); start
//!   components are found by self-motion walks; reconfiguration at a held pose moves along the
//!   self-motion. Nothing else is assumed of the joint layout (no spherical wrist, no offsets).
//! - **Fewer joints** (6-DOF: UR3/5/10, Jaco2): at a full pose (roll `fixed`) the IK solutions
//!   are isolated branches (and their 2π turns where a joint's range allows). Every valid
//!   solution of the straight rod found by the free IK runs is its own start component, so
//!   every IK branch is a start. There is no self-motion: reconfiguration is impossible
//!   ([`Planner::reconfiguration`]; `plan` and `reach` say so), and a path that would need to
//!   change branch mid-ray stops (`discontinuity`). In roll `motor` a 6-joint arm has the 1-D
//!   roll self-motion at a pose: the search moves along it at a held pose (reconfiguration as
//!   the rig allows it), the ladder only tracks it.
//! - IK is numerical (box-constrained Levenberg–Marquardt from random restarts,
//!   [`crate::robot::ik`]): a branch none of the restarts converges to is missed.
//!
//! # Result
//! The farthest s reached, the class (testable: the whole path to s*·(1 + margin); partial:
//! stopped after s = 0; blocked: cannot leave the straight rod; undecided: the search's node
//! bound), the blocking cause (the dominant rejection where the ray stops), and the
//! reconfigurations and back-offs on the path.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::helix::Helix;
use crate::math::{rot_z, Iso3, Mat3, Real, Vec3};
use crate::planning::cause::{BlockCause, CauseCounts};
use crate::planning::pose_path::Waypoint;
use crate::planning::rig::{tool_from_director, Rig, RollMode, SearchMethod};
use crate::planning::self_motion::{self, WalkSettings};
use crate::planning::trajectory::{Phase, Trajectory};
use crate::robot::collision::{BodyRef, Contact, RodGeometry};
use crate::robot::{
    CollisionModel, CollisionWorkspace, Frame, IkParams, IkTarget, RobotModel, MAX_DOF,
};
use std::sync::OnceLock;

mod start;
mod transition;

/// Most samples of one self-motion walk (one direction from one node).
pub(crate) const MAX_WALK_SAMPLES: usize = 2_000;

/// Whether a planner may reconfigure the arm at a held pose ([`Planner::reconfiguration`]).
///
/// The held pose is the rod end's: a full pose in roll `fixed` (6 constraints), a position and
/// the rod tangent in roll `motor` (5: the arm's roll about the tangent is free, the motor turns
/// the other way). The arm has a self-motion there when it has more joints than constraints: a
/// 7-joint arm in either mode, a 6-joint arm in roll `motor` only (its roll).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reconfiguration {
    /// The arm has a self-motion at the held pose and the rig allows moving along it.
    Allowed,
    /// The arm has a self-motion at the held pose; the rig (or `--no-reconfiguration`)
    /// forbids it.
    Forbidden,
    /// No self-motion at the held pose in this roll mode (6 joints in roll `fixed`, fewer
    /// joints in either): no plan reconfigures; every IK branch of the straight rod is a start
    /// instead.
    Impossible {
        /// The arm's joints.
        dof: usize,
        /// The roll mode.
        roll: RollMode,
    },
    /// A 6-joint arm in roll `motor` decided by the ladder (`planner.search = "ladder"`): the
    /// arm's roll is a self-motion, which only the search of the valid set (`"exact"`) moves
    /// along at a held pose.
    NotByLadder {
        /// The arm's joints.
        dof: usize,
    },
}

impl std::fmt::Display for Reconfiguration {
    /// `allowed`, `forbidden by the rig`, `impossible (6 joints in roll fixed: no self-motion;
    /// every IK branch of the straight rod is a start)`, or `not made by the ladder (6 joints:
    /// the search, planner.search = "exact", rolls the arm at a held pose)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Reconfiguration::Allowed => f.write_str("allowed"),
            Reconfiguration::Forbidden => f.write_str("forbidden by the rig"),
            Reconfiguration::Impossible { dof, roll } => write!(
                f,
                "impossible ({dof} joints in roll {roll}: no self-motion; every IK branch of the \
                 straight rod is a start)"
            ),
            Reconfiguration::NotByLadder { dof } => write!(
                f,
                "not made by the ladder ({dof} joints: the search, planner.search = \"exact\", \
                 rolls the arm at a held pose)"
            ),
        }
    }
}

/// Reachability class of a ray. The one class type: records read and write it by serde (the
/// [`ReachClass::as_str`] names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReachClass {
    /// The whole path to s*·(1 + margin) is feasible.
    Testable,
    /// The path stops at some 0 < s < s*·(1 + margin).
    Partial,
    /// The path cannot leave the straight rod.
    Blocked,
    /// The search hit its node bound (`planner.max_search_nodes`) before deciding the ray
    /// ([`crate::planning::search`]); `s_reached` is the farthest s found.
    Undecided,
}

impl ReachClass {
    /// Order of preference when two decisions of a ray are compared: testable, undecided
    /// (the search's bound: it may still pass), partial, blocked.
    pub(crate) fn rank(self) -> u8 {
        match self {
            ReachClass::Testable => 3,
            ReachClass::Undecided => 2,
            ReachClass::Partial => 1,
            ReachClass::Blocked => 0,
        }
    }

    /// The CSV name.
    pub fn as_str(&self) -> &'static str {
        match self {
            ReachClass::Testable => "testable",
            ReachClass::Partial => "partial",
            ReachClass::Blocked => "blocked",
            ReachClass::Undecided => "undecided",
        }
    }
}

/// One planned configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedPoint {
    /// The waypoint (pose path).
    pub waypoint: Waypoint,
    /// Joint values.
    pub q: Vec<Real>,
    /// Motor angle (rad): the rod's turn about d3 relative to the frame the arm holds.
    pub motor: Real,
    /// `Load`, or `Reconfigure` for a self-motion sample at the previous point's pose.
    pub phase: Phase,
}

/// The plan of one ray.
#[derive(Debug, Clone, PartialEq)]
pub struct RayPlan {
    /// Direction.
    pub dir: Direction,
    /// Boundary s* (∞ when stable up to [`crate::math::tol::S_MAX`]).
    pub s_star: Real,
    /// Target s of the path.
    pub s_end: Real,
    /// Farthest s reached.
    pub s_reached: Real,
    /// Class.
    pub class: ReachClass,
    /// Why the path stopped (`None` when testable).
    pub cause: Option<BlockCause>,
    /// Helix azimuth used.
    pub azimuth: Real,
    /// Roll mode used.
    pub roll: RollMode,
    /// Waypoints of the pose path (to s_end).
    pub n_waypoints: usize,
    /// Waypoints reached (distinct s; reconfiguration samples not counted).
    pub n_reached: usize,
    /// Self-motion reconfigurations at a held pose on the path.
    pub reconfigurations: usize,
    /// Back-offs on the path (maximal runs of phase `backoff`; the search only).
    pub backoffs: usize,
    /// Nodes the search created ([`crate::planning::search`]; 0 for the ladder).
    pub search_nodes: usize,
    /// Start nodes: the search's start configurations (every valid one of the start set); the
    /// ladder's per start component of the level that produced this plan, the base width
    /// `redundancy_samples` or k of a dense level ([`crate::planning::ladder`], "Dense
    /// levels": a ray testable at level k is testable for every `dense_samples` ≥ k).
    pub start_samples: usize,
    /// The ladder's dense levels were skipped: the base plan was partial and the pointwise gate
    /// found no valid configuration at the first regular waypoint beyond `s_reached`
    /// ([`crate::planning::ladder`], "Pointwise gate"). Always `false` for the search.
    pub levels_gated: bool,
    /// Cost of the path to `s_reached`: the sum over its edges of ‖W·Δq‖ + w_m·|Δm| (the
    /// rig's joint weights and motor weight; the ladder minimizes it, the search reports it).
    pub path_cost: Real,
    /// Largest joint step on the path (rad).
    pub max_joint_step: Real,
    /// The path to `s_reached` (when asked for).
    pub path: Option<Vec<PlannedPoint>>,
    /// The bifurcation type the margin past s* was chosen for
    /// ([`PlannerSettings::margin_for`](crate::planning::rig::PlannerSettings::margin_for));
    /// `None` when the margin is the same for every type (no type assumed).
    pub assumed_type: Option<crate::bifurcation::BifurcationType>,
}

/// Overrides of a rig's settings, as `plan` and `reach` take them on the command line
/// (`--margin`, `--clamp`, `--no-reconfiguration`, `--search`, `--no-backoff`).
///
/// ```
/// use helixreach::planning::{planner::RigOverrides, rig::Rig};
/// let rig = Rig::load("sawyer-seed").unwrap();
/// let o = RigOverrides { margin: Some(0.0), clamp: Some([0.85, -0.1, -0.146]), ..Default::default() };
/// let r = o.apply(&rig).unwrap();
/// assert_eq!(r.planner.margin, 0.0);
/// assert_eq!(r.clamp.translation.vector.y, -0.1);
/// let bad = RigOverrides { clamp: Some([0.85, f64::NAN, -0.146]), ..Default::default() };
/// assert!(bad.apply(&rig).unwrap_err().to_string().contains("clamp.origin[1]"));
/// let bad = RigOverrides { margin: Some(-0.1), ..Default::default() };
/// assert!(bad.apply(&rig).unwrap_err().to_string().contains("margin"));
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigOverrides {
    /// `planner.margin` ([`MARGIN_RULE`](crate::planning::rig::MARGIN_RULE)).
    pub margin: Option<Real>,
    /// `clamp.origin` (base frame, m), see [`Rig::with_clamp_origin`].
    pub clamp: Option<[Real; 3]>,
    /// `planner.allow_reconfiguration`.
    pub allow_reconfiguration: Option<bool>,
    /// `planner.search`.
    pub search: Option<SearchMethod>,
    /// `planner.allow_backoff`.
    pub allow_backoff: Option<bool>,
}

impl RigOverrides {
    /// The rig with these overrides; errors name the field and the value.
    pub fn apply(&self, rig: &Rig) -> Result<Rig> {
        let mut rig = match self.clamp {
            Some(c) => rig.with_clamp_origin(c)?,
            None => rig.clone(),
        };
        if let Some(m) = self.margin {
            if !crate::planning::rig::margin_ok(m) {
                return Err(Error::invalid(
                    "margin (override)",
                    m,
                    crate::planning::rig::MARGIN_RULE,
                ));
            }
            rig.planner.margin = m;
        }
        if let Some(a) = self.allow_reconfiguration {
            rig.planner.allow_reconfiguration = a;
        }
        if let Some(m) = self.search {
            rig.planner.search = m;
        }
        if let Some(a) = self.allow_backoff {
            rig.planner.allow_backoff = a;
        }
        Ok(rig)
    }
}

/// The start rungs of one roll mode: the diverse first rung, and one rung per further connected
/// valid self-motion component of the straight rod's pose that the first rung does not touch.
#[derive(Debug, Clone)]
pub(crate) struct StartSet {
    pub(crate) first: Vec<Node>,
    pub(crate) others: Vec<Vec<Node>>,
    /// Every connected valid start component, densely sampled (its IK solutions and the
    /// self-motion walk through it), in farthest-point order: any prefix is spread over the
    /// component and a longer prefix contains a shorter one (the dense levels).
    pub(crate) comps: Vec<Vec<Node>>,
    /// The valid IK solutions of the straight rod, grouped by the same components (in the
    /// order of `comps`).
    solutions: Vec<Vec<Node>>,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct Node {
    pub(crate) q: [Real; MAX_DOF],
    pub(crate) motor: Real,
}

impl Node {
    /// The node of joints `q` (the first `q.len()` entries; the rest 0) and motor angle `motor`.
    pub(crate) fn from_joints(q: &[Real], motor: Real) -> Node {
        let mut n = Node {
            q: [0.0; MAX_DOF],
            motor,
        };
        n.q[..q.len()].copy_from_slice(q);
        n
    }
}

/// A planner for one rig: the robot, its collision model with the rig's scene, and the cached
/// start rungs. `Send + Sync`; per-ray scratch lives in the calls.
#[derive(Debug)]
pub struct Planner {
    pub(crate) rig: Rig,
    pub(crate) model: RobotModel,
    pub(crate) collision: CollisionModel,
    pub(crate) ik: IkParams,
    tool_inv: Frame,
    pub(crate) dof: usize,
    pub(crate) red_joint: usize,
    weights: [Real; MAX_DOF],
    start_fixed: OnceLock<std::result::Result<StartSet, CauseCounts>>,
    start_motor: OnceLock<std::result::Result<StartSet, CauseCounts>>,
    /// Whether the pointwise gate may skip the dense levels ([`Planner::set_level_gate`]).
    pub(crate) level_gate: bool,
    /// The same rig driven to `margin_supercritical` (made on first use by
    /// [`Planner::plan_best_typed`]; the error text when it cannot be made).
    other_margin: OnceLock<std::result::Result<Box<Planner>, String>>,
}

pub(crate) fn cause_of(c: &Contact) -> BlockCause {
    match (c.a, c.b) {
        (BodyRef::Rod(_), _) | (_, BodyRef::Rod(_)) => BlockCause::RodCollision,
        (_, BodyRef::Obstacle(_)) | (BodyRef::Obstacle(_), _) => BlockCause::SceneCollision,
        _ => BlockCause::SelfCollision,
    }
}

/// Per-ray scratch.
pub(crate) struct Scratch {
    pub(crate) ws: CollisionWorkspace,
    pub(crate) rod: Vec<Vec3>,
    qi: [Real; MAX_DOF],
}

impl Planner {
    /// The self-motion walk settings of this rig (resolution `planner.self_motion_step`, steps
    /// within `planner.max_joint_step`).
    pub(crate) fn walk_settings(&self) -> WalkSettings {
        let p = &self.rig.planner;
        WalkSettings {
            max_step: p.self_motion_step,
            min_step: crate::planning::witness::WALK_MIN_STEP,
            joint_step_bound: p.max_joint_step,
            max_samples: MAX_WALK_SAMPLES,
        }
    }

    /// Load the rig's robot and scene. Errors name the rig file: a robot that cannot be loaded,
    /// a missing tip link, joint weights of the wrong length, an unreachable clamp (no
    /// collision-free IK solution for the straight rod in the rig's roll mode).
    pub fn new(rig: Rig) -> Result<Planner> {
        let model = rig.robot.load_model(&rig.source)?;
        let dof = model.dof();
        let w = &rig.planner.joint_weights;
        if !w.is_empty() && w.len() != dof {
            return Err(Error::invalid(
                format!("{}: planner.joint_weights", rig.source),
                format!("{w:?}"),
                format!("needs one weight per joint ({dof})"),
            ));
        }
        let mut weights = [1.0; MAX_DOF];
        for (k, x) in w.iter().enumerate() {
            weights[k] = *x;
        }
        let collision = rig
            .robot
            .collision_model(&model, &rig.obstacles, &rig.source)?;
        let ik = IkParams {
            redundancy_joint: Some(0),
            samples: rig.planner.redundancy_samples,
            restarts: 6,
            max_iterations: 60,
            ..IkParams::default()
        };
        if rig.planner.search == SearchMethod::Exact {
            crate::planning::search::check_resolution(&rig.planner, &rig.source)?;
        }
        let tool_inv = Frame::from_iso(&rig.tool).inverse();
        let planner = Planner {
            rig,
            model,
            collision,
            ik,
            tool_inv,
            dof,
            red_joint: 0,
            weights,
            start_fixed: OnceLock::new(),
            start_motor: OnceLock::new(),
            level_gate: true,
            other_margin: OnceLock::new(),
        };
        // Unreachable clamp: no valid start in the rig's roll mode.
        if let Err(causes) = planner.start(planner.rig.roll) {
            let o = planner.rig.clamp.translation.vector;
            let dominant = causes.dominant().map_or("no_ik", |c| c.as_str());
            // A URDF without its never-colliding pair list checks every non-adjacent link pair:
            // say so, naming the file that was looked for.
            let missing_pairs = planner
                .model
                .sources()
                .iter()
                .find(|s| s.digest().is_none() && s.path().ends_with(".collision.toml"))
                .filter(|_| dominant == "self_collision")
                .map_or(String::new(), |s| {
                    format!(
                        "; the robot has no never-colliding pair list ({} does not exist), so \
                         every non-adjacent link pair is checked: write one with `helixreach \
                         robot --robot URDF --write-disabled FILE`",
                        s.path()
                    )
                });
            return Err(Error::invalid(
                format!("{}: clamp.origin", planner.rig.source),
                format!("[{}, {}, {}]", o.x, o.y, o.z),
                format!(
                    "unreachable clamp: the straight rod's end pose has no valid IK solution \
                     (dominant cause: {dominant}){missing_pairs}"
                ),
            ));
        }
        Ok(planner)
    }

    /// Switch the ladder's pointwise gate before the dense levels on (the default) or off
    /// ([`crate::planning::ladder`], "Pointwise gate"; off, every level runs: for
    /// comparisons).
    pub fn set_level_gate(&mut self, on: bool) {
        self.level_gate = on;
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// Whether this rig's plans in roll mode `roll` may reconfigure at a held pose
    /// ([`Reconfiguration`]; module docs, "What the planner assumes of the arm"): impossible
    /// where the arm has no self-motion at the held pose (fewer than 7 joints in roll `fixed`,
    /// fewer than 6 in roll `motor`); not made by the ladder on a 6-joint arm in roll `motor`;
    /// else as the rig's `planner.allow_reconfiguration` says.
    ///
    /// ```
    /// use helixreach::planning::planner::{Planner, Reconfiguration};
    /// use helixreach::planning::rig::{Rig, RollMode};
    /// let planner = Planner::new(Rig::load("sawyer-seed").unwrap()).unwrap();
    /// assert_eq!(planner.reconfiguration(RollMode::Fixed), Reconfiguration::Allowed);
    /// ```
    pub fn reconfiguration(&self, roll: RollMode) -> Reconfiguration {
        let constraints = match roll {
            RollMode::Fixed => 6,
            RollMode::Motor => 5,
        };
        if self.dof <= constraints {
            Reconfiguration::Impossible {
                dof: self.dof,
                roll,
            }
        } else if self.dof != 7 && self.rig.planner.search == SearchMethod::Ladder {
            Reconfiguration::NotByLadder { dof: self.dof }
        } else if self.rig.planner.allow_reconfiguration {
            Reconfiguration::Allowed
        } else {
            Reconfiguration::Forbidden
        }
    }

    /// The collision model (robot + the rig's scene).
    pub fn collision(&self) -> &CollisionModel {
        &self.collision
    }

    /// The tip-link pose that puts the tool frame at `tool` (base frame).
    pub fn tip_target(&self, tool: &Iso3) -> Frame {
        Frame::from_iso(tool).mul(&self.tool_inv)
    }

    /// The tool frame (rod end) pose of the arm at `q`, by FK.
    pub fn tool_pose(&self, q: &[Real]) -> Iso3 {
        self.model
            .chain()
            .tool_pose(q)
            .mul(&Frame::from_iso(&self.rig.tool))
            .to_iso()
    }

    pub(crate) fn target(&self, tool: &Iso3, roll: RollMode) -> IkTarget {
        let t = IkTarget::Pose(self.tip_target(tool));
        match roll {
            RollMode::Fixed => t,
            RollMode::Motor => t.free_roll(),
        }
    }

    /// The rod capsules of the helix `kto` (base frame) into `out`.
    pub(crate) fn rod_nodes(&self, kto: [Real; 3], azimuth: Real, out: &mut [Vec3]) -> Result<()> {
        let h = Helix::new(kto[0], kto[1], kto[2])?;
        crate::helix::discrete::fill_nodes(&h, out);
        let rc = self.rig.clamp_rotation() * rot_z(azimuth);
        let oc = self.rig.clamp.translation.vector;
        let l = self.rig.rod.length;
        for x in out.iter_mut() {
            *x = oc + rc * (*x * l);
        }
        Ok(())
    }

    fn rod_geometry<'a>(&self, nodes: &'a [Vec3]) -> RodGeometry<'a> {
        self.rig.rod_geometry(nodes)
    }

    pub(crate) fn check_config(
        &self,
        q: &[Real],
        sc: &mut Scratch,
    ) -> std::result::Result<(), BlockCause> {
        let rod = self.rod_geometry(&sc.rod);
        match self.collision.check(q, &mut sc.ws, Some(&rod)) {
            None => Ok(()),
            Some(c) => Err(cause_of(&c)),
        }
    }

    /// Motor angle of an arm configuration realising waypoint `w`: ω/c in roll mode `fixed`;
    /// `ω/c − ψ` in roll mode `motor`, ψ the arm's roll about d3 relative to the transported
    /// frame, unwrapped to the branch nearest `near`.
    pub(crate) fn motor_angle(&self, w: &Waypoint, q: &[Real], roll: RollMode, near: Real) -> Real {
        match roll {
            RollMode::Fixed => w.motor,
            RollMode::Motor => {
                let arm = self.tool_pose(q);
                let m = (w.tool.rotation.inverse() * arm.rotation)
                    .to_rotation_matrix()
                    .into_inner();
                // R_toolᵀ·R_arm = P·Rz(ψ)·P = Rz(−ψ).
                let psi = -m[(1, 0)].atan2(m[(0, 0)]);
                let raw = w.motor - psi;
                let two_pi = 2.0 * std::f64::consts::PI;
                raw + two_pi * ((near - raw) / two_pi).round()
            }
        }
    }

    pub(crate) fn motor_ok(&self, m: Real) -> bool {
        let (lo, hi) = self.rig.motor.range;
        m >= lo && m <= hi
    }

    pub(crate) fn new_scratch(&self) -> Scratch {
        Scratch {
            ws: self.collision.workspace(),
            rod: vec![Vec3::zeros(); self.rig.planner.rod_capsules + 1],
            qi: [0.0; MAX_DOF],
        }
    }

    /// The start rung (straight rod) for `roll`, cached; `Err` with the rejection counts when no
    /// start configuration is valid.
    pub(crate) fn start(&self, roll: RollMode) -> std::result::Result<&StartSet, CauseCounts> {
        let cell = match roll {
            RollMode::Fixed => &self.start_fixed,
            RollMode::Motor => &self.start_motor,
        };
        cell.get_or_init(|| self.compute_start(roll))
            .as_ref()
            .map_err(|c| *c)
    }

    pub(crate) fn edge_cost(&self, a: &Node, b: &Node) -> Option<Real> {
        let mut c2 = 0.0;
        for j in 0..self.dof {
            let d = (b.q[j] - a.q[j]).abs();
            if d > self.rig.planner.max_joint_step {
                return None;
            }
            c2 += (self.weights[j] * d).powi(2);
        }
        Some(c2.sqrt() + self.rig.planner.motor_weight * (b.motor - a.motor).abs())
    }

    pub(crate) fn check_segment(
        &self,
        a: &Node,
        b: &Node,
        sc: &mut Scratch,
    ) -> std::result::Result<(), BlockCause> {
        let mut dmax: Real = 0.0;
        for j in 0..self.dof {
            dmax = dmax.max((b.q[j] - a.q[j]).abs());
        }
        let n = (dmax / self.rig.planner.segment_check_step).ceil() as usize;
        for k in 1..n {
            let t = k as Real / n as Real;
            for j in 0..self.dof {
                sc.qi[j] = a.q[j] + t * (b.q[j] - a.q[j]);
            }
            let qi = sc.qi;
            self.check_config(&qi[..self.dof], sc)?;
        }
        Ok(())
    }

    /// Decide one ray at one azimuth in one roll mode by the rig's `planner.search` (module
    /// docs); `want_path` keeps the joint path. `s_star` is the boundary along the ray (∞ =
    /// stable up to [`crate::math::tol::S_MAX`], then the path ends at `S_MAX`). The path goes
    /// to `s_star·(1 + margin)` (the rig's `planner.margin`). In roll mode `motor` the result
    /// reaches at least as far as roll mode `fixed` (module docs).
    pub fn plan_ray(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuth: Real,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        if self.rig.planner.search == SearchMethod::Exact {
            return self.decide_ray(dir, s_star, azimuth, roll, want_path);
        }
        self.plan_ladder(dir, s_star, azimuth, roll, want_path)
    }

    /// The start configurations (straight rod) of roll mode `roll`: the first start rung, then
    /// each further start component's rung ([`crate::planning::ladder`], "Rungs"). Empty when the clamp is
    /// unreachable in that mode.
    pub fn start_configurations(&self, roll: RollMode) -> Vec<Vec<Real>> {
        let Ok(set) = self.start(roll) else {
            return Vec::new();
        };
        set.first
            .iter()
            .chain(set.others.iter().flatten())
            .map(|n| n.q[..self.dof].to_vec())
            .collect()
    }

    /// The straight rod's valid IK solutions in roll mode `roll`, grouped by connected valid
    /// start component (roll `fixed`: of the 1-D self-motion; roll `motor`: of the 2-D set
    /// j0 × roll, joined by walks about the tool axis; `planner/start.rs` module docs). Two
    /// solutions share a group only if a valid path at the walk resolution joins them. Empty
    /// when the clamp is unreachable in that mode.
    pub fn start_components(&self, roll: RollMode) -> Vec<Vec<Vec<Real>>> {
        let Ok(set) = self.start(roll) else {
            return Vec::new();
        };
        set.solutions
            .iter()
            .map(|c| c.iter().map(|n| n.q[..self.dof].to_vec()).collect())
            .collect()
    }

    /// Plan a ray over the azimuths of `azimuths` (in order) and keep the best: testable before
    /// partial before blocked, then the farthest s, then the lowest cost, then the first azimuth.
    /// The first testable azimuth ends the search (a sweep needs a testable azimuth, not the
    /// cheapest one; pass a single azimuth to compare costs).
    pub fn plan_best(
        &self,
        dir: &Direction,
        s_star: Real,
        azimuths: &[Real],
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        self.plan_best_at(
            dir,
            &AzimuthTargets::Same(s_star, azimuths),
            roll,
            want_path,
        )
    }

    /// [`Planner::plan_best`] with a boundary s* per azimuth ([`AzimuthTargets`]): each azimuth
    /// is planned to its own s*, and the best plan is kept by the same order — testable before
    /// partial before blocked, then the farthest s, then the lowest cost, then the first
    /// azimuth. A boundary with gravity depends on the azimuth (gravity breaks the isotropy of
    /// the gravity-free rod), so a sweep over azimuths compares each with its own s*.
    pub fn plan_best_at(
        &self,
        dir: &Direction,
        targets: &AzimuthTargets<'_>,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let mut best: Option<RayPlan> = None;
        for (a, s_star) in targets.iter() {
            let p = self.plan_ray(dir, s_star, a, roll, want_path)?;
            let better = match &best {
                None => true,
                Some(b) => (p.class.rank(), p.s_reached, -p.path_cost)
                    .partial_cmp(&(b.class.rank(), b.s_reached, -b.path_cost))
                    .is_some_and(|o| o.is_gt()),
            };
            if better {
                let done = p.class == ReachClass::Testable;
                best = Some(p);
                if done {
                    break;
                }
            }
        }
        best.ok_or_else(|| Error::invalid("azimuths", "[]", "need at least one azimuth"))
    }

    /// [`Planner::plan_best`] driven past s* by the margin for the ray's bifurcation type
    /// `kind` ([`PlannerSettings::margin_for`](crate::planning::rig::PlannerSettings::margin_for):
    /// `margin` when subcritical, `margin_supercritical` when supercritical, the larger when
    /// degenerate or unknown); the plan records the type in `assumed_type` (`None` when the
    /// rig's margin does not depend on it).
    pub fn plan_best_typed(
        &self,
        dir: &Direction,
        s_star: Real,
        kind: Option<crate::bifurcation::BifurcationType>,
        azimuths: &[Real],
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let targets = AzimuthTargets::Same(s_star, azimuths);
        self.plan_best_typed_at(dir, &targets, kind, roll, want_path)
    }

    /// [`Planner::plan_best_typed`] with a boundary s* per azimuth
    /// ([`Planner::plan_best_at`]).
    pub fn plan_best_typed_at(
        &self,
        dir: &Direction,
        targets: &AzimuthTargets<'_>,
        kind: Option<crate::bifurcation::BifurcationType>,
        roll: RollMode,
        want_path: bool,
    ) -> Result<RayPlan> {
        let settings = &self.rig.planner;
        let margin = settings.margin_for(kind);
        let mut plan = if margin == settings.margin {
            self.plan_best_at(dir, targets, roll, want_path)?
        } else {
            let other = self.other_margin.get_or_init(|| {
                let mut rig = self.rig.clone();
                rig.planner.margin = margin;
                rig.planner.margin_supercritical = None;
                Planner::new(rig).map(Box::new).map_err(|e| e.to_string())
            });
            match other {
                Ok(p) => p.plan_best_at(dir, targets, roll, want_path)?,
                Err(e) => {
                    return Err(Error::invalid(
                        format!("{}: planner.margin_supercritical", self.rig.source),
                        margin,
                        e.clone(),
                    ))
                }
            }
        };
        plan.assumed_type = if settings.type_dependent() {
            kind
        } else {
            None
        };
        Ok(plan)
    }

    /// The time-parametrized trajectory of a plan with a path:
    /// [`crate::planning::trajectory::of_plan`] (the seed's protocol — load along the path to
    /// the farthest s reached, hold, unload along the same joint path reversed).
    pub fn trajectory(&self, plan: &RayPlan) -> Result<Trajectory> {
        crate::planning::trajectory::of_plan(self, plan)
    }
}

/// The azimuths a ray is planned at, each with the boundary s* it is planned to
/// ([`Planner::plan_best_at`]).
#[derive(Debug, Clone, Copy)]
pub enum AzimuthTargets<'a> {
    /// One s* for every azimuth (a gravity-free boundary: s* does not depend on the azimuth).
    Same(Real, &'a [Real]),
    /// `(azimuth, s*)` pairs (a boundary with gravity, one per azimuth).
    Each(&'a [(Real, Real)]),
}

impl AzimuthTargets<'_> {
    /// The `(azimuth, s*)` pairs, in order.
    pub fn iter(&self) -> impl Iterator<Item = (Real, Real)> + '_ {
        let n = match self {
            AzimuthTargets::Same(_, a) => a.len(),
            AzimuthTargets::Each(e) => e.len(),
        };
        (0..n).map(move |i| match self {
            AzimuthTargets::Same(s, a) => (a[i], *s),
            AzimuthTargets::Each(e) => e[i],
        })
    }
}

/// The rod end's material frame (base frame) realised by an arm tool rotation `r_arm` and a motor
/// angle `m`: `R_c·A·Rz(m)` with `A = R_cᵀ·R_arm·P` the arm's frame in the `[d1 d2 d3]` convention.
pub fn material_from_arm(rig: &Rig, r_arm: &Mat3, m: Real) -> Mat3 {
    let rc = rig.clamp_rotation();
    let p = tool_from_director();
    rc * (rc.transpose() * r_arm * p.transpose()) * rot_z(m)
}

/// `q` padded to `MAX_DOF` entries with zeros.
pub(crate) fn pad(q: &[Real]) -> [Real; MAX_DOF] {
    let mut out = [0.0; MAX_DOF];
    out[..q.len()].copy_from_slice(q);
    out
}

/// The ladder node of joints `q` and motor angle `motor`.
pub(crate) fn node_of(q: &self_motion::Q, motor: Real) -> Node {
    node(*q, motor)
}

pub(crate) fn node(q: self_motion::Q, motor: Real) -> Node {
    Node { q, motor }
}
