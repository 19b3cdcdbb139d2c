//! A first rig for any URDF arm (`helixreach rig init`): the robot and its tool link, a tool
//! offset, a rod, a clamp placed in front of the robot where the arm can hold the straight rod,
//! padding, the collision model and an empty scene, written as commented rig TOML that
//! [`Rig::from_toml_str`] loads as written.
//!
//! # What is written
//! - `[robot]`: the URDF (absolute path, or a built-in robot name as given), the tip link, the
//!   package directories for `package://` meshes (absolute), the links without collision
//!   geometry, the collision model (`primitives_then_hull`: fitted capsules as a broad phase,
//!   then the exact hulls), the padding of every collision body, the SRDF (if given); a
//!   comment naming the arm's continuous joints, modelled as [−π, π] ([`RigInit::continuous`]).
//! - `[tool]`: the rod end [`RigInitOptions::tool_offset`] metres out of the tip link along its
//!   z axis (no rotation): the flange → motor-tip distance, to be measured on the real tool.
//! - `[rod]`: the seed's nitinol rod (1/16 in diameter, E = 67.5 GPa, ν = 0.33,
//!   ρ = 6450 kg/m³) of length [`RigInitOptions::rod_length`], by default 0.51 m (the seed's)
//!   or 0.4·R when the arm is small (R: the reach radius below), rounded down to the millimetre.
//! - `[clamp]`: the rod tangent `d3` straight up (+z of the base frame), `d1` = +y; the origin
//!   chosen as below.
//! - the planner's defaults ([`PlannerSettings::default`](crate::planning::rig::PlannerSettings)),
//!   roll mode `fixed`, azimuth 0, no obstacle.
//!
//! # Clamp placement
//! "In front of the robot" is +x of the base frame (ROS REP 103: x forward). With `p₀` the
//! first actuated joint's origin and `R` the arm's reach radius from it (the triangle-inequality
//! bound of [`ReachBound`], tool included), the candidates are the 12 clamp origins
//! `(p₀ₓ + f·R, p₀ᵧ, z)` with f ∈ {0.3, 0.4, 0.5, 0.6} and z ∈ {0, −L/4, −L/2} (L the rod
//! length; z = 0 is the robot's mounting plane, the base frame's origin). Each candidate is
//! written as rig text, loaded back, and scored:
//! 1. the planner must find a valid start: a collision-free IK solution inside the joint
//!    limits holding the straight rod ([`Planner::new`]); else the candidate is out;
//! 2. the score is the number of [`SCORE_DIRECTIONS`] quarter-sphere directions (Fibonacci)
//!    whose rod-end pose at s*·(1 + margin) has a valid configuration (the planner's sampled
//!    pointwise test, [`Planner::pointwise_valid_at`], roll `fixed`, azimuth 0): a proxy of
//!    the coverage `reach` will find.
//!
//! The highest score wins; ties go to the earlier candidate (z = 0 first, then nearer the
//! robot). No candidate with a valid start is an error naming the robot and the tip.
//! The chosen rig is the text written, loaded back once more by the caller's check
//! ([`RigInit::rig`]).
//!
//! Cost: 12 planner constructions (the straight rod's IK set) and up to 96 pointwise tests:
//! seconds (candidates run in parallel on [`RigInitOptions::par`]).

use crate::directions::{fibonacci, Direction};
use crate::error::{Error, Result};
use crate::layout::precheck::ReachBound;
use crate::math::Real;
use crate::planning::planner::Planner;
use crate::planning::rig::{Rig, RollMode};
use crate::robot::{LoadOptions, RobotModel};
use std::path::{Path, PathBuf};

/// Quarter-sphere directions whose end pose scores a clamp candidate.
pub const SCORE_DIRECTIONS: usize = 8;

/// The seed's rod length (m), the default when the arm reaches far enough.
pub const SEED_ROD_LENGTH: Real = 0.51;

/// The default tool offset (m) along the tip link's z axis.
pub const DEFAULT_TOOL_OFFSET: Real = 0.10;

/// The default padding of the robot's collision bodies (m).
pub const DEFAULT_PADDING: Real = 0.005;

/// Horizontal distances of the clamp candidates from `p₀`, as fractions of the reach radius.
const REACH_FRACTIONS: [Real; 4] = [0.3, 0.4, 0.5, 0.6];

/// Heights of the clamp candidates below the mounting plane, as fractions of the rod length.
const DEPTH_FRACTIONS: [Real; 3] = [0.0, 0.25, 0.5];

/// What `rig init` is told.
#[derive(Debug, Clone)]
pub struct RigInitOptions {
    /// A URDF path, or a built-in robot name (`sawyer`, `panda`, `iiwa14`).
    pub robot: String,
    /// The tool link.
    pub tip_link: String,
    /// Package directories for `package://` mesh names.
    pub package_paths: Vec<PathBuf>,
    /// Links meant to have no collision geometry.
    pub no_collision: Vec<String>,
    /// A MoveIt SRDF whose disabled pairs are skipped.
    pub srdf: Option<PathBuf>,
    /// The rig's name.
    pub name: String,
    /// Rod end along the tip link's z axis (m, ≥ 0).
    pub tool_offset: Real,
    /// Padding of every collision body (m).
    pub padding: Real,
    /// Rod length (m); `None`: [`SEED_ROD_LENGTH`], or 0.4·R for a small arm (module docs).
    pub rod_length: Option<Real>,
    /// The parallelism of the candidates' scoring.
    pub par: crate::par::Par,
}

/// One scored clamp candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Clamp origin (base frame, m).
    pub origin: [Real; 3],
    /// Valid start configurations of the straight rod (0: the candidate is out).
    pub starts: usize,
    /// Score directions with a valid end pose (of [`SCORE_DIRECTIONS`]).
    pub score: usize,
    /// Why the planner refused the candidate (no valid start), if it did.
    pub refused: Option<String>,
}

/// The rig written by [`rig_init`].
#[derive(Debug, Clone)]
pub struct RigInit {
    /// The rig TOML text (commented).
    pub text: String,
    /// The rig as loaded from `text`.
    pub rig: Rig,
    /// The reach bound used to place the clamp.
    pub reach: ReachBound,
    /// The arm's sampled reach from the bound's centre (m; module docs).
    pub reach_sampled: Real,
    /// Every candidate, in candidate order.
    pub candidates: Vec<Candidate>,
    /// Index of the chosen candidate.
    pub chosen: usize,
    /// Degrees of freedom of the arm.
    pub dof: usize,
    /// The arm's continuous joints (URDF type `continuous`), in chain order: modelled as
    /// `[−π, π]` ([`crate::robot::JointInfo::continuous`]); the rig text says so.
    pub continuous: Vec<String>,
}

fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

fn num(x: Real) -> String {
    let mut s = format!("{x}");
    if !s.contains(['.', 'e', 'E', 'n', 'i']) {
        s.push_str(".0");
    }
    s
}

fn abs_dir(flag: &str, p: &Path) -> Result<String> {
    let c = p
        .canonicalize()
        .map_err(|e| Error::invalid(flag, p.display(), format!("cannot resolve the path: {e}")))?;
    Ok(c.display().to_string())
}

/// What the `[robot]` section of every candidate's rig text names: the URDF, the package
/// directories and the SRDF (absolute), and the arm's continuous joints.
struct RobotLines<'a> {
    urdf: &'a str,
    packages: &'a [String],
    srdf: Option<&'a str>,
    continuous: &'a [String],
}

/// The rig text for `origin` (module docs, "What is written").
fn rig_text(
    o: &RigInitOptions,
    robot: &RobotLines<'_>,
    rod_length: Real,
    origin: [Real; 3],
    note: &str,
) -> String {
    let RobotLines {
        urdf,
        packages,
        srdf,
        continuous,
    } = *robot;
    let list = |v: &[String]| v.iter().map(|s| quoted(s)).collect::<Vec<_>>().join(", ");
    let mut t = String::new();
    t.push_str(&format!(
        "# A rig written by `helixreach rig init` for {robot}, tool link {tip}.\n\
         # Units: SI (m, rad, Pa, kg/m³). Poses in the robot's base frame (the URDF root).\n\
         # Measure and correct: the tool offset, the clamp pose, the rod; add the bench and\n\
         # every fixture as [[obstacle]] (the scene is empty).\n\n",
        robot = urdf,
        tip = o.tip_link
    ));
    t.push_str(&format!("name = {}\n", quoted(&o.name)));
    t.push_str(&format!(
        "description = {}\n\n",
        quoted(&format!(
            "{} holding a {rod_length} m rod, clamp {}",
            o.tip_link,
            note.replace("\n# ", " ")
        ))
    ));
    t.push_str("[robot]\n");
    t.push_str(&format!(
        "# The URDF (absolute path, or a built-in robot name) and the link whose frame, times\n\
         # [tool], is the rod end.\n\
         urdf = {}\ntip_link = {}\n",
        quoted(urdf),
        quoted(&o.tip_link)
    ));
    if !continuous.is_empty() {
        t.push_str(&format!(
            "# Continuous joints (no limits in the URDF), modelled as [-pi, pi]: a path that would\n\
             # turn one past +-pi stops there (cause joint_limit). They are:\n\
             # {}\n",
            continuous.join(", ")
        ));
    }
    t.push_str(&format!(
        "# Where `package://NAME/...` meshes are found (searched before ROS_PACKAGE_PATH).\n\
         package_paths = [{}]\n",
        list(packages)
    ));
    t.push_str(&format!(
        "# Links meant to have no collision geometry (any other link on the arm without one is\n\
         # an error).\n\
         no_collision = [{}]\n",
        list(&o.no_collision)
    ));
    t.push_str(
        "# Collision model: every <collision> element of the URDF, primitives as they are; link\n\
         # pairs joined by a joint are not checked, nor the pairs the SRDF disables. Every body\n\
         # is grown by `padding` (m); per link: [robot.link_padding] NAME = m.\n",
    );
    t.push_str(&format!("padding = {}\n", num(o.padding)));
    t.push_str(&format!(
        "# What is checked for a mesh: `hull` (its exact convex hull), `primitives` (a capsule\n\
         # fitted around the hull: fast, never misses a hull contact, may report more) or\n\
         # `primitives_then_hull` (the capsules first, the hulls only where they touch: the\n\
         # hull model's answer, faster).\n\
         collision_model = {}\n",
        quoted(crate::robot::collision::CollisionKind::default().name())
    ));
    match srdf {
        Some(s) => t.push_str(&format!("srdf = {}\n", quoted(s))),
        None => {
            t.push_str("# srdf = \"/path/to/robot.srdf\"  (MoveIt <disable_collisions> pairs)\n")
        }
    }
    t.push_str(&format!(
        "\n[tool]\n\
         # The rod end (the motor tip) {} m out of {} along its z axis, no rotation.\n\
         xyz = [0.0, 0.0, {}]\n\
         rpy = [0.0, 0.0, 0.0]\n",
        num(o.tool_offset),
        o.tip_link,
        num(o.tool_offset)
    ));
    t.push_str(&format!(
        "\n[clamp]\n\
         # The clamped rod end, {note}.\n\
         # d3: the rod tangent at the clamp (straight up); d1: where the helix first curls.\n\
         origin = [{}, {}, {}]\n\
         d1 = [0.0, 1.0, 0.0]\n\
         d3 = [0.0, 0.0, 1.0]\n",
        num(origin[0]),
        num(origin[1]),
        num(origin[2])
    ));
    t.push_str(&format!(
        "\n[rod]\n\
         # The seed's nitinol rod (1/16 in), {rod_length} m long.\n\
         length = {}\n\
         diameter = 1.5875e-3\n\
         youngs_modulus = 67.5e9\n\
         poisson = 0.33\n\
         density = 6450.0\n",
        num(rod_length)
    ));
    t.push_str(
        "\n[motor]\n\
         # The end-effector motor twisting the rod end (rad/s); add lower/upper for a range.\n\
         max_velocity = 3.0\n\
         \n[roll]\n\
         # fixed: the arm holds the transported frame and the motor adds ω/c (the seed's);\n\
         # motor: the roll about the rod tangent is free.\n\
         mode = \"fixed\"\n\
         \n[azimuth]\n\
         choices = [0.0]\n\
         \n# The scene: none yet. Add the bench, the clamp block and every fixture, e.g.\n\
         # [[obstacle]]\n\
         # name = \"bench\"\n\
         # shape = { type = \"box\", half_extents = [0.4, 0.5, 0.015] }\n\
         # pose = { xyz = [0.5, 0.0, -0.03] }\n\
         \n[planner]\n\
         # Drive each ray to s*·(1 + margin); the other settings are the defaults.\n\
         margin = 0.1\n",
    );
    t
}

/// Write a rig for `opts` (module docs). `out_dir` is the directory the rig will be written to
/// (relative paths of the loaded-back rig resolve there). Errors: the robot cannot be loaded
/// (a bad tip link is named, with the candidate links), an option out of range, no clamp
/// candidate where the arm holds the straight rod.
pub fn rig_init(opts: &RigInitOptions, out_dir: &Path) -> Result<RigInit> {
    if !(opts.tool_offset.is_finite() && (0.0..=1.0).contains(&opts.tool_offset)) {
        return Err(Error::invalid(
            "--tool-offset",
            opts.tool_offset,
            "must be finite, in 0..=1 m",
        ));
    }
    let load = LoadOptions {
        search: crate::robot::mesh::MeshSearch::new(opts.package_paths.clone()),
        no_collision: opts.no_collision.clone(),
    };
    let model = RobotModel::load_with(&opts.robot, Some(&opts.tip_link), &load).map_err(|e| {
        Error::invalid(
            "--tip",
            &opts.tip_link,
            format!("cannot load {} with this tool link: {e}", opts.robot),
        )
    })?;
    let urdf = {
        let p = Path::new(&opts.robot);
        if p.is_file() {
            abs_dir("--robot", p)?
        } else {
            opts.robot.clone()
        }
    };
    let packages = opts
        .package_paths
        .iter()
        .map(|p| abs_dir("--package-path", p))
        .collect::<Result<Vec<_>>>()?;
    let srdf = opts
        .srdf
        .as_deref()
        .map(|p| abs_dir("--srdf", p))
        .transpose()?;
    let continuous: Vec<String> = model
        .joints()
        .iter()
        .filter(|j| j.continuous)
        .map(|j| j.name.clone())
        .collect();
    let robot = RobotLines {
        urdf: &urdf,
        packages: &packages,
        srdf: srdf.as_deref(),
        continuous: &continuous,
    };
    // The reach bound needs a rig for its tool: any candidate's.
    let probe = |rod: Real, origin: [Real; 3], note: &str| -> Result<Rig> {
        let text = rig_text(opts, &robot, rod, origin, note);
        Rig::from_toml_str(&text, "rig init", out_dir)
    };
    let rig0 = probe(SEED_ROD_LENGTH, [0.5, 0.0, 0.0], "probe")?;
    let reach = ReachBound::of(&model, &rig0);
    let reach_sampled = sampled_reach(&model, &rig0, &reach);
    let rod_length = match opts.rod_length {
        Some(l) => {
            if !(l.is_finite() && l > 0.0 && l <= 5.0) {
                return Err(Error::invalid(
                    "--rod-length",
                    l,
                    "must be finite, in (0, 5] m",
                ));
            }
            l
        }
        None => (SEED_ROD_LENGTH.min(0.4 * reach_sampled) * 1000.0).floor() / 1000.0,
    };
    let dirs: Vec<Direction> = fibonacci(SCORE_DIRECTIONS, true)?;
    let s_ends: Vec<Real> = dirs
        .iter()
        .map(|d| crate::sweep::reach::s_star_of(d, None))
        .collect::<Result<_>>()?;
    let mut origins = Vec::new();
    for depth in DEPTH_FRACTIONS {
        for f in REACH_FRACTIONS {
            origins.push([
                reach.centre.x + f * reach_sampled,
                reach.centre.y,
                -depth * rod_length,
            ]);
        }
    }
    let round = |x: Real| (x * 1000.0).round() / 1000.0 + 0.0;
    let origins: Vec<[Real; 3]> = origins.into_iter().map(|o| o.map(round)).collect();
    let note = |o: &[Real; 3]| {
        let depth = if o[2] == 0.0 {
            "on the mounting plane".to_string()
        } else {
            format!("{:.3} m below the mounting plane", -o[2])
        };
        format!(
            "{:.3} m in front of the first joint ({:.2} of the arm's reach), {depth}",
            o[0] - reach.centre.x,
            (o[0] - reach.centre.x) / reach_sampled
        )
    };
    let scored: Vec<Result<Candidate>> = opts.par.map(&origins, |o| {
        let rig = probe(rod_length, *o, &note(o))?;
        let margin = rig.planner.margin;
        let planner = match Planner::new(rig) {
            Ok(p) => p,
            Err(e) => {
                return Ok(Candidate {
                    origin: *o,
                    starts: 0,
                    score: 0,
                    refused: Some(e.to_string()),
                })
            }
        };
        let starts = planner.start_configurations(RollMode::Fixed).len();
        let mut score = 0;
        for (d, s) in dirs.iter().zip(&s_ends) {
            let s_end = if s.is_finite() {
                s * (1.0 + margin)
            } else {
                1.0
            };
            if planner.pointwise_valid_at(d, s_end, 0.0, RollMode::Fixed)? {
                score += 1;
            }
        }
        Ok(Candidate {
            origin: *o,
            starts,
            score,
            refused: None,
        })
    })?;
    let candidates = scored.into_iter().collect::<Result<Vec<_>>>()?;
    let chosen = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.starts > 0)
        .max_by(|(i, a), (j, b)| a.score.cmp(&b.score).then(j.cmp(i)))
        .map(|(i, _)| i)
        .ok_or_else(|| {
            Error::invalid(
                "--robot",
                format!("{} (tip {})", opts.robot, opts.tip_link),
                format!(
                    "no clamp candidate in front of the robot where it holds the straight {rod_length} m \
                     rod without collision ({} tried, {:.3}..{:.3} m in front of the first joint; \
                     the first: {}); try --rod-length, --tool-offset, --padding or --srdf",
                    candidates.len(),
                    REACH_FRACTIONS[0] * reach_sampled,
                    REACH_FRACTIONS[REACH_FRACTIONS.len() - 1] * reach_sampled,
                    candidates[0].refused.as_deref().unwrap_or("-")
                ),
            )
        })?;
    let o = candidates[chosen].origin;
    let text = rig_text(
        opts,
        &robot,
        rod_length,
        o,
        &format!(
            "{};\n# the arm holds the straight rod in {} start configurations and {} of {} \
             quarter-sphere end poses\n# (rig init's score)",
            note(&o),
            candidates[chosen].starts,
            candidates[chosen].score,
            SCORE_DIRECTIONS
        ),
    );
    let rig = Rig::from_toml_str(&text, "rig init", out_dir)?;
    Ok(RigInit {
        text,
        rig,
        reach,
        reach_sampled,
        candidates,
        chosen,
        dof: model.dof(),
        continuous,
    })
}

/// Random configurations of [`sampled_reach`].
const REACH_SAMPLES: usize = 4096;

/// The farthest tool position from the reach bound's centre over [`REACH_SAMPLES`] random
/// in-limit configurations (seeded: deterministic): the arm's reach, at most the bound's
/// radius (which sums every link offset and overestimates an arm with offsets).
fn sampled_reach(model: &RobotModel, rig: &Rig, bound: &ReachBound) -> Real {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let (lo, hi) = (model.lower(), model.upper());
    let tool = crate::robot::Frame::from_iso(&rig.tool);
    let n = model.dof();
    let mut q = vec![0.0; n];
    let mut best: Real = 0.0;
    for _ in 0..REACH_SAMPLES {
        for j in 0..n {
            let a = lo[j].max(-std::f64::consts::PI);
            let b = hi[j].min(std::f64::consts::PI).max(a);
            q[j] = rng.random_range(a..=b);
        }
        let p = model.chain().tool_pose(&q).mul(&tool).pos;
        best = best.max((p - bound.centre).norm());
    }
    best.min(bound.radius)
}
