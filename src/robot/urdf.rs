//! Loading: URDF text → `urdf_rs::Robot` → [`RobotModel`] (validated, compiled).
//!
//! Parsing is delegated to urdf-rs (the parser k uses). This module checks what the compiled
//! chain relies on and reports clear errors naming the file and the joint or link: a missing or
//! malformed file, an unknown tool link, a cycle or a second root, a non-finite origin, a zero
//! axis, inverted limits, a planar/floating joint on the chain, a mimic joint on the chain or a
//! mimic cycle, more than [`MAX_DOF`] joints.
//!
//! # What the robot layer assumes of the arm
//! - A tree with one root; the arm is the path from the root to the tool link, with 1 to
//!   [`MAX_DOF`] actuated joints (revolute, continuous — limited to `[−π, π]` —, or prismatic,
//!   e.g. a linear rail). 6-DOF arms have finitely many IK solutions per pose (no self-motion);
//!   7-DOF arms a one-parameter family.
//! - Movable joints off that path (grippers, a head, the other arm) are frozen at 0 clamped
//!   into their limits; an off-path mimic joint follows its source (`m·q + o`).
//! - Every collision element is loaded: primitives as they are, meshes (STL, COLLADA, OBJ, with
//!   `scale`) through [`crate::robot::mesh`] as their convex hulls. An element that cannot be
//!   loaded is an error naming the file, the link and the element. Each rigid group of links on
//!   the path (the root's, and each actuated joint's child's) must have collision geometry,
//!   unless [`LoadOptions::no_collision`] names one of its links: a link with nothing to check
//!   is never a silent gap.
//!
//! The robots shipped in `robots/` are embedded in the library ([`builtin`]), so the default rig
//! works from any directory.

use super::kinematics::{Chain, Frame, LinkMotion, LinkStep, MAX_DOF};
use super::mesh::{self, MeshCache, MeshSearch};
use super::model::MeshGeometry;
use super::model::{CollisionGeometry, JointInfo, LinkInfo, RobotModel, Shape};
use crate::error::{Error, Result};
use crate::math::{Real, Vec3};
use crate::sources::SourceFile;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// How a URDF is loaded: where its meshes are looked for, which links may lack collision
/// geometry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// Mesh file search (`--package-path`, `ROS_PACKAGE_PATH`).
    pub search: MeshSearch,
    /// Links that are meant to have no collision geometry (the rig's `no_collision`).
    pub no_collision: Vec<String>,
}

impl LoadOptions {
    /// Package directories `dirs` (then `ROS_PACKAGE_PATH`), every link required to have
    /// collision geometry.
    pub fn with_package_paths(dirs: Vec<PathBuf>) -> LoadOptions {
        LoadOptions {
            search: MeshSearch::new(dirs),
            no_collision: Vec::new(),
        }
    }
}

/// A robot shipped with helixreach: its URDF and its never-colliding pair list.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// Name (`sawyer`, `panda`, `iiwa14`).
    pub name: &'static str,
    /// The URDF text (`robots/<name>.urdf`).
    pub urdf: &'static str,
    /// The never-colliding pair list (`robots/<name>.collision.toml`).
    pub collision: &'static str,
    /// The default tool link.
    pub tip: &'static str,
}

/// The built-in robots.
pub const BUILTINS: [Builtin; 3] = [
    Builtin {
        name: "sawyer",
        urdf: include_str!("../../robots/sawyer.urdf"),
        collision: include_str!("../../robots/sawyer.collision.toml"),
        tip: "right_motor_tip",
    },
    Builtin {
        name: "panda",
        urdf: include_str!("../../robots/panda.urdf"),
        collision: include_str!("../../robots/panda.collision.toml"),
        tip: "fer_link8",
    },
    Builtin {
        name: "iiwa14",
        urdf: include_str!("../../robots/iiwa14.urdf"),
        collision: include_str!("../../robots/iiwa14.collision.toml"),
        tip: "tool0",
    },
];

/// The built-in robot called `name`, if any.
///
/// ```
/// assert!(helixreach::robot::builtin("sawyer").is_some());
/// assert!(helixreach::robot::builtin("r2d2").is_none());
/// ```
pub fn builtin(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}

impl RobotModel {
    /// Load a URDF file; `tip_link` = the tool link (default: the leaf link with the most
    /// actuated joints above it).
    /// Meshes are searched through `ROS_PACKAGE_PATH` and relative to the file.
    pub fn from_urdf_file(path: impl AsRef<Path>, tip_link: Option<&str>) -> Result<RobotModel> {
        Self::from_urdf_file_with(path, tip_link, &LoadOptions::with_package_paths(Vec::new()))
    }

    /// [`RobotModel::from_urdf_file`] with explicit options.
    pub fn from_urdf_file_with(
        path: impl AsRef<Path>,
        tip_link: Option<&str>,
        opts: &LoadOptions,
    ) -> Result<RobotModel> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let robot = parse(&text, &path.display().to_string())?;
        let mut model = build(
            &robot,
            &text,
            &path.display().to_string(),
            tip_link,
            opts,
            Some(path.parent().unwrap_or(Path::new("."))),
        )?;
        let pairs = super::collision::collision_toml_path(&model.source);
        let (_, pairs) = SourceFile::read_optional(&pairs)?;
        model.sources.insert(1, pairs);
        Ok(model)
    }

    /// Parse URDF text; `source` names it in errors. Relative mesh paths resolve against the
    /// working directory.
    pub fn from_urdf_str(text: &str, source: &str, tip_link: Option<&str>) -> Result<RobotModel> {
        Self::from_urdf_str_with(
            text,
            source,
            tip_link,
            &LoadOptions::with_package_paths(Vec::new()),
        )
    }

    /// [`RobotModel::from_urdf_str`] with explicit options.
    pub fn from_urdf_str_with(
        text: &str,
        source: &str,
        tip_link: Option<&str>,
        opts: &LoadOptions,
    ) -> Result<RobotModel> {
        build(&parse(text, source)?, text, source, tip_link, opts, None)
    }

    /// A built-in robot by name (`sawyer`, `panda`, `iiwa14`) or else a URDF file path.
    ///
    /// ```
    /// let m = helixreach::robot::RobotModel::load("sawyer", None).unwrap();
    /// assert_eq!(m.tip_link(), "right_motor_tip");
    /// assert_eq!(m.dof(), 7);
    /// let e = helixreach::robot::RobotModel::load("kuka", None).unwrap_err().to_string();
    /// assert!(e.contains("kuka") && e.contains("sawyer, panda, iiwa14"), "{e}");
    /// ```
    pub fn load(name_or_path: &str, tip_link: Option<&str>) -> Result<RobotModel> {
        Self::load_with(
            name_or_path,
            tip_link,
            &LoadOptions::with_package_paths(Vec::new()),
        )
    }

    /// [`RobotModel::load`] with explicit options.
    pub fn load_with(
        name_or_path: &str,
        tip_link: Option<&str>,
        opts: &LoadOptions,
    ) -> Result<RobotModel> {
        match builtin(name_or_path) {
            Some(b) => {
                let mut model = Self::from_urdf_str_with(
                    b.urdf,
                    &format!("builtin:{}", b.name),
                    Some(tip_link.unwrap_or(b.tip)),
                    opts,
                )?;
                model.sources.insert(
                    1,
                    SourceFile::from_bytes(
                        &format!("builtin:{}.collision.toml", b.name),
                        b.collision.as_bytes(),
                    ),
                );
                Ok(model)
            }
            None if !Path::new(name_or_path).exists() => Err(Error::File {
                path: name_or_path.into(),
                reason: format!(
                    "no such URDF file, and not a built-in robot (built-in: {})",
                    BUILTINS.map(|b| b.name).join(", ")
                ),
            }),
            None => Self::from_urdf_file_with(name_or_path, tip_link, opts),
        }
    }
}

fn parse(text: &str, source: &str) -> Result<urdf_rs::Robot> {
    super::xml_depth::check_depth(text, source)?;
    urdf_rs::read_from_string(text).map_err(|e| Error::File {
        path: source.into(),
        reason: format!("malformed URDF: {e}"),
    })
}

fn bad(source: &str, what: String, value: impl std::fmt::Display, reason: &str) -> Error {
    Error::invalid(format!("{source}: {what}"), value, reason)
}

fn finite3(source: &str, what: String, v: &[f64; 3]) -> Result<()> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(bad(source, what, format!("{v:?}"), "must be finite"))
    }
}

/// A collision element: a primitive, or a mesh (its filename and scale).
enum Element<'a> {
    Primitive(Shape),
    Mesh(&'a str, [Real; 3]),
}

fn shape_of<'a>(source: &str, link: &str, g: &'a urdf_rs::Geometry) -> Result<Element<'a>> {
    let pos = |what: &str, v: f64| -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(bad(
                source,
                format!("link {link} collision {what}"),
                v,
                "must be finite and > 0",
            ))
        }
    };
    Ok(Element::Primitive(match g {
        urdf_rs::Geometry::Sphere { radius } => Shape::Sphere {
            radius: pos("sphere radius", *radius)?,
        },
        urdf_rs::Geometry::Box { size } => Shape::Box {
            half_extents: Vec3::new(
                pos("box size x", size[0])? * 0.5,
                pos("box size y", size[1])? * 0.5,
                pos("box size z", size[2])? * 0.5,
            ),
        },
        urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder {
            radius: pos("cylinder radius", *radius)?,
            half_length: pos("cylinder length", *length)? * 0.5,
        },
        urdf_rs::Geometry::Capsule { radius, length } => Shape::Capsule {
            radius: pos("capsule radius", *radius)?,
            half_length: {
                let l = *length;
                if !(l.is_finite() && l >= 0.0) {
                    return Err(bad(
                        source,
                        format!("link {link} collision capsule length"),
                        l,
                        "must be finite and ≥ 0",
                    ));
                }
                0.5 * l
            },
        },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let s = scale.as_ref().map(|v| **v).unwrap_or([1.0; 3]);
            return Ok(Element::Mesh(filename, s));
        }
    }))
}

fn is_movable(t: &urdf_rs::JointType) -> bool {
    matches!(
        t,
        urdf_rs::JointType::Revolute
            | urdf_rs::JointType::Continuous
            | urdf_rs::JointType::Prismatic
    )
}

/// Build the model from a parsed URDF (`text`, for its digest); `urdf_dir` is where relative
/// mesh paths resolve.
fn build(
    robot: &urdf_rs::Robot,
    text: &str,
    source: &str,
    tip_link: Option<&str>,
    opts: &LoadOptions,
    urdf_dir: Option<&Path>,
) -> Result<RobotModel> {
    let link_names: HashMap<&str, usize> = robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect();
    if link_names.len() != robot.links.len() {
        return Err(bad(source, "links".into(), "", "two links share a name"));
    }
    let mut joint_names: HashMap<&str, usize> = HashMap::new();
    for (ji, j) in robot.joints.iter().enumerate() {
        if joint_names.insert(j.name.as_str(), ji).is_some() {
            return Err(bad(
                source,
                format!("joint {}", j.name),
                "",
                "two joints share this name",
            ));
        }
    }
    // child link → joint index; parent link → joint indices.
    let mut joint_of_child: HashMap<&str, usize> = HashMap::new();
    let mut children: HashMap<&str, Vec<usize>> = HashMap::new();
    for (ji, j) in robot.joints.iter().enumerate() {
        for (role, l) in [("parent", &j.parent.link), ("child", &j.child.link)] {
            if !link_names.contains_key(l.as_str()) {
                return Err(bad(
                    source,
                    format!("joint {} {role}", j.name),
                    l,
                    "no link of that name",
                ));
            }
        }
        if joint_of_child.insert(&j.child.link, ji).is_some() {
            return Err(bad(
                source,
                format!("link {}", j.child.link),
                "",
                "is the child of two joints",
            ));
        }
        children.entry(&j.parent.link).or_default().push(ji);
        finite3(
            source,
            format!("joint {} origin xyz", j.name),
            &j.origin.xyz,
        )?;
        finite3(
            source,
            format!("joint {} origin rpy", j.name),
            &j.origin.rpy,
        )?;
        if let Some(m) = &j.mimic {
            for (what, v) in [("multiplier", m.multiplier), ("offset", m.offset)] {
                if v.is_some_and(|x| !x.is_finite()) {
                    return Err(bad(
                        source,
                        format!("joint {} mimic {what}", j.name),
                        v.unwrap_or_default(),
                        "must be finite",
                    ));
                }
            }
        }
        if is_movable(&j.joint_type) {
            finite3(source, format!("joint {} axis", j.name), &j.axis.xyz)?;
            let a = Vec3::from(*j.axis.xyz);
            if !(a.norm() >= crate::math::tol::ZERO_VECTOR && a.norm().is_finite()) {
                return Err(bad(
                    source,
                    format!("joint {} axis", j.name),
                    format!("{:?}", *j.axis.xyz),
                    "must be non-zero with a finite norm",
                ));
            }
            if j.joint_type != urdf_rs::JointType::Continuous
                && !(j.limit.lower.is_finite()
                    && j.limit.upper.is_finite()
                    && j.limit.lower <= j.limit.upper)
            {
                return Err(bad(
                    source,
                    format!("joint {} limit", j.name),
                    format!("[{}, {}]", j.limit.lower, j.limit.upper),
                    "need finite lower ≤ upper",
                ));
            }
            // urdf-rs reads a missing <limit> as all zeros: a revolute joint frozen at 0.
            let l = &j.limit;
            if j.joint_type == urdf_rs::JointType::Revolute
                && [l.lower, l.upper, l.effort, l.velocity] == [0.0; 4]
            {
                return Err(bad(
                    source,
                    format!("joint {} limit", j.name),
                    "none",
                    "a revolute joint needs <limit lower=… upper=… velocity=… effort=…/>",
                ));
            }
            if !(l.velocity >= 0.0 && l.velocity.is_finite()) {
                return Err(bad(
                    source,
                    format!("joint {} limit velocity", j.name),
                    l.velocity,
                    "must be finite and >= 0 (rad/s; 0 = none given)",
                ));
            }
        }
    }
    let roots: Vec<&str> = robot
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|n| !joint_of_child.contains_key(n))
        .collect();
    if roots.len() != 1 {
        return Err(bad(
            source,
            "root link".into(),
            roots.join(","),
            "the URDF must have exactly one root link",
        ));
    }
    // Topological order (BFS from the root).
    let mut order: Vec<&str> = vec![roots[0]];
    let mut k = 0;
    while k < order.len() {
        if let Some(js) = children.get(order[k]) {
            for &ji in js {
                order.push(&robot.joints[ji].child.link);
            }
        }
        k += 1;
    }
    if order.len() != robot.links.len() {
        return Err(bad(
            source,
            "links".into(),
            robot.links.len() - order.len(),
            "links not connected to the root (cycle?)",
        ));
    }
    let index: HashMap<&str, usize> = order.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let parent_of = |l: &str| -> Option<(usize, &urdf_rs::Joint)> {
        joint_of_child.get(l).map(|&ji| {
            (
                index[robot.joints[ji].parent.link.as_str()],
                &robot.joints[ji],
            )
        })
    };

    // Mimic chains: every mimic names an existing joint, and following them never loops.
    let joint_index: HashMap<&str, usize> = robot
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.name.as_str(), i))
        .collect();
    for (ji, j) in robot.joints.iter().enumerate() {
        let mut seen = vec![ji];
        let mut cur = j;
        while let Some(m) = &cur.mimic {
            let Some(&src) = joint_index.get(m.joint.as_str()) else {
                return Err(bad(
                    source,
                    format!("joint {} mimic", cur.name),
                    &m.joint,
                    "no joint of that name",
                ));
            };
            if seen.contains(&src) {
                let names: Vec<&str> = seen
                    .iter()
                    .chain([&src])
                    .map(|&k| robot.joints[k].name.as_str())
                    .collect();
                return Err(bad(
                    source,
                    format!("joint {} mimic", j.name),
                    names.join(" → "),
                    "mimic cycle",
                ));
            }
            seen.push(src);
            cur = &robot.joints[src];
        }
    }

    // Count actuated joints above each link to choose the default tip.
    let movable_above = |l: &str| -> usize {
        let mut n = 0;
        let mut cur = joint_of_child.get(l).copied();
        while let Some(ji) = cur {
            let j = &robot.joints[ji];
            n += usize::from(is_movable(&j.joint_type));
            cur = joint_of_child.get(j.parent.link.as_str()).copied();
        }
        n
    };
    let tip: String = match tip_link {
        Some(t) => {
            if !index.contains_key(t) {
                return Err(Error::invalid(
                    "tip_link",
                    t,
                    format!(
                        "no link of that name in {source} (links: {})",
                        order.join(", ")
                    ),
                ));
            }
            t.to_string()
        }
        None => {
            let leaves: Vec<&str> = order
                .iter()
                .copied()
                .filter(|l| !children.contains_key(l))
                .collect();
            let best = leaves.iter().map(|l| movable_above(l)).max().unwrap_or(0);
            let cands: Vec<&str> = leaves
                .into_iter()
                .filter(|l| movable_above(l) == best)
                .collect();
            if cands.len() != 1 {
                return Err(Error::invalid(
                    "tip_link",
                    "(none given)",
                    format!(
                        "{source}: several candidate tool links ({}); name one",
                        cands.join(", ")
                    ),
                ));
            }
            cands[0].to_string()
        }
    };

    // Path root → tip (joint indices, root first).
    let mut path_joints = Vec::new();
    {
        let mut l: &str = &tip;
        while let Some(&ji) = joint_of_child.get(l) {
            path_joints.push(ji);
            l = &robot.joints[ji].parent.link;
        }
        path_joints.reverse();
    }
    let mut dof_of_joint: HashMap<usize, usize> = HashMap::new();
    let mut joints = Vec::new();
    let mut path = Vec::new();
    for &ji in &path_joints {
        let j = &robot.joints[ji];
        let origin = Frame::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy);
        if let Some(m) = &j.mimic {
            return Err(bad(
                source,
                format!("joint {} mimic", j.name),
                &m.joint,
                "a mimic joint on the path from the root to the tool link is not supported (mimic joints are supported off that path, e.g. in a gripper)",
            ));
        }
        match j.joint_type {
            urdf_rs::JointType::Fixed => path.push((origin, None)),
            urdf_rs::JointType::Revolute
            | urdf_rs::JointType::Continuous
            | urdf_rs::JointType::Prismatic => {
                let axis = Vec3::from(*j.axis.xyz).normalize();
                let (lower, upper) = if j.joint_type == urdf_rs::JointType::Continuous {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                } else {
                    (j.limit.lower, j.limit.upper)
                };
                dof_of_joint.insert(ji, joints.len());
                joints.push(JointInfo {
                    name: j.name.clone(),
                    parent_link: j.parent.link.clone(),
                    child_link: j.child.link.clone(),
                    lower,
                    upper,
                    continuous: j.joint_type == urdf_rs::JointType::Continuous,
                    velocity: if j.limit.velocity.is_finite() {
                        j.limit.velocity
                    } else {
                        0.0
                    },
                    axis,
                });
                path.push((
                    origin,
                    Some((axis, j.joint_type == urdf_rs::JointType::Prismatic)),
                ));
            }
            ref t => {
                return Err(bad(
                    source,
                    format!("joint {} type", j.name),
                    format!("{t:?}"),
                    "only revolute, continuous, prismatic and fixed joints are supported on the path to the tool link",
                ));
            }
        }
    }
    if joints.len() > MAX_DOF {
        return Err(bad(
            source,
            format!("chain to {tip}"),
            joints.len(),
            "more actuated joints than supported (7): choose a tool link closer to the root",
        ));
    }
    if joints.is_empty() {
        return Err(Error::invalid(
            "tip_link",
            &tip,
            format!("{source}: no actuated joint between the root and this link"),
        ));
    }

    for l in &opts.no_collision {
        if !index.contains_key(l.as_str()) {
            return Err(Error::invalid(
                "no_collision",
                l,
                format!("no link of that name in {source}"),
            ));
        }
    }
    // The value of an off-path movable joint: `Err(v)`, a constant (0 clamped into its limits,
    // or for a mimic joint `m·v(source) + o`), or `Ok((dof, m, o))` for a mimic (through any
    // chain of mimics) of actuated joint `dof`.
    let off_path_value = |ji: usize| -> std::result::Result<(usize, Real, Real), Real> {
        let (mut mul, mut off) = (1.0, 0.0);
        let mut cur = ji;
        loop {
            if let Some(&dof) = dof_of_joint.get(&cur) {
                return Ok((dof, mul, off));
            }
            let j = &robot.joints[cur];
            match &j.mimic {
                Some(m) => {
                    off += mul * m.offset.unwrap_or(0.0);
                    mul *= m.multiplier.unwrap_or(1.0);
                    cur = joint_index[m.joint.as_str()];
                }
                None => {
                    let v0 = if j.joint_type == urdf_rs::JointType::Continuous {
                        0.0
                    } else {
                        0.0_f64.clamp(j.limit.lower, j.limit.upper.max(j.limit.lower))
                    };
                    return Err(mul * v0 + off);
                }
            }
        }
    };

    // Links: compiled steps, rigid groups, collision geometry.
    let mut frozen = Vec::new();
    let mut ignored = Vec::new();
    let mut sources = vec![SourceFile::from_bytes(source, text.as_bytes())];
    let mut cache = MeshCache::new();
    let mut steps = Vec::with_capacity(order.len());
    let mut links: Vec<LinkInfo> = Vec::with_capacity(order.len());
    for (i, name) in order.iter().enumerate() {
        let ul = &robot.links[link_names[name]];
        let (parent, joint_name, step) = match parent_of(name) {
            None => (
                None,
                None,
                LinkStep {
                    parent: None,
                    origin: Frame::identity(),
                    motion: LinkMotion::Fixed,
                },
            ),
            Some((p, j)) => {
                let mut origin = Frame::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy);
                let ji = joint_of_child[name];
                let motion = if let Some(&dof) = dof_of_joint.get(&ji) {
                    let axis = joints[dof].axis;
                    if j.joint_type == urdf_rs::JointType::Prismatic {
                        LinkMotion::Prismatic { dof, axis }
                    } else {
                        LinkMotion::Revolute {
                            dof,
                            axis,
                            is_z: (axis - Vec3::z()).norm() < crate::math::tol::PARALLEL,
                        }
                    }
                } else {
                    let prismatic = j.joint_type == urdf_rs::JointType::Prismatic;
                    match j.joint_type {
                        urdf_rs::JointType::Revolute
                        | urdf_rs::JointType::Continuous
                        | urdf_rs::JointType::Prismatic => {
                            let axis = Vec3::from(*j.axis.xyz).normalize();
                            match off_path_value(ji) {
                                Ok((dof, multiplier, offset)) => LinkMotion::Mimic {
                                    dof,
                                    axis,
                                    multiplier,
                                    offset,
                                    prismatic,
                                },
                                Err(v) => {
                                    frozen.push((j.name.clone(), v));
                                    if prismatic {
                                        origin.pos += origin.rot * (axis * v);
                                    } else {
                                        origin.rot *= super::kinematics::axis_rotation(&axis, v);
                                    }
                                    LinkMotion::Fixed
                                }
                            }
                        }
                        urdf_rs::JointType::Fixed => LinkMotion::Fixed,
                        ref t => {
                            // Off the chain: frozen at its origin.
                            frozen.push((format!("{} ({t:?})", j.name), 0.0));
                            LinkMotion::Fixed
                        }
                    }
                };
                (
                    Some(p),
                    Some(j.name.clone()),
                    LinkStep {
                        parent: Some(p),
                        origin,
                        motion,
                    },
                )
            }
        };
        let group = match (parent, step.motion) {
            (Some(p), LinkMotion::Fixed) => links[p].group,
            _ => i,
        };
        let mut collision = Vec::new();
        let mut meshes = Vec::new();
        for (ei, c) in ul.collision.iter().enumerate() {
            let what = format!("link {name} collision[{ei}]");
            finite3(source, format!("{what} origin xyz"), &c.origin.xyz)?;
            finite3(source, format!("{what} origin rpy"), &c.origin.rpy)?;
            let origin = Frame::from_xyz_rpy(*c.origin.xyz, *c.origin.rpy);
            match shape_of(source, name, &c.geometry)? {
                Element::Primitive(shape) => collision.push(CollisionGeometry { origin, shape }),
                Element::Mesh(filename, scale) => {
                    let what = format!("{source}: {what}");
                    let path = opts.search.resolve(filename, urdf_dir, &what)?;
                    let mesh = mesh::load_cached(&mut cache, &path, scale, &what)?;
                    if !sources.contains(&mesh.source) {
                        sources.push(mesh.source.clone());
                    }
                    meshes.push(MeshGeometry {
                        origin,
                        filename: filename.to_string(),
                        scale,
                        mesh,
                    });
                }
            }
        }
        steps.push(step);
        links.push(LinkInfo {
            name: name.to_string(),
            parent,
            joint: joint_name,
            group,
            collision,
            meshes,
        });
    }
    for l in &opts.no_collision {
        let li = index[l.as_str()];
        if links[li].has_collision() {
            return Err(Error::invalid(
                "no_collision",
                l,
                format!("{source}: the link has collision geometry; remove it from no_collision"),
            ));
        }
    }
    // Every rigid group on the path to the tool must have something to check.
    let mut on_path: Vec<usize> = vec![index[tip.as_str()]];
    while let Some(p) = links[*on_path.last().expect("non-empty")].parent {
        on_path.push(p);
    }
    let mut groups_seen = HashSet::new();
    for &li in on_path.iter().rev() {
        let g = links[li].group;
        if !groups_seen.insert(g) {
            continue;
        }
        let members: Vec<&LinkInfo> = links.iter().filter(|l| l.group == g).collect();
        if members.iter().any(|l| l.has_collision()) {
            continue;
        }
        let allowed: Vec<&str> = members
            .iter()
            .map(|l| l.name.as_str())
            .filter(|n| opts.no_collision.iter().any(|x| x == n))
            .collect();
        let lead = &links[g];
        if allowed.is_empty() {
            let names: Vec<&str> = members.iter().map(|l| l.name.as_str()).collect();
            return Err(bad(
                source,
                format!("link {} collision", lead.name),
                "(none)",
                &format!(
                    "no collision geometry on this link{} (rigidly joined links: {}): collisions of it would never be checked. Add a <collision> element, or list the link in the rig's no_collision = [...] if that is intended",
                    lead.joint
                        .as_ref()
                        .map(|j| format!(", moved by joint {j}"))
                        .unwrap_or_default(),
                    names.join(", ")
                ),
            ));
        }
        ignored.push(format!(
            "{}: no collision geometry (no_collision)",
            allowed.join(", ")
        ));
    }
    let chain = Chain::compile(&path, steps);
    Ok(RobotModel {
        name: robot.name.clone(),
        source: source.to_string(),
        tip_index: index[tip.as_str()],
        tip_link: tip,
        joints,
        links,
        frozen,
        ignored,
        sources,
        chain,
        urdf: robot.clone(),
    })
}
