//! Loading: URDF text → `urdf_rs::Robot` → [`RobotModel`] (validated, compiled).
//!
//! Parsing is delegated to urdf-rs (the parser k uses). This module checks what the compiled
//! chain relies on and reports clear errors naming the file and the joint or link: a missing or
//! malformed file, an unknown tool link, a cycle or a second root, a non-finite origin, a zero
//! axis, inverted limits, a prismatic/planar/floating joint on the chain, more than
//! [`MAX_DOF`] joints. Mesh collision geometry is skipped (listed by
//! [`RobotModel::ignored_geometry`]); helixreach works with primitives.
//!
//! The robots shipped in `robots/` are embedded in the library ([`builtin`]), so the default rig
//! works from any directory.

use super::kinematics::{Chain, Frame, LinkMotion, LinkStep, MAX_DOF};
use super::model::{CollisionGeometry, JointInfo, LinkInfo, RobotModel, Shape};
use crate::error::{Error, Result};
use crate::math::{Real, Vec3};
use crate::sources::SourceFile;
use std::collections::HashMap;
use std::path::Path;

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
    pub fn from_urdf_file(path: impl AsRef<Path>, tip_link: Option<&str>) -> Result<RobotModel> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut model = Self::from_urdf_str(&text, &path.display().to_string(), tip_link)?;
        let pairs = super::collision::collision_toml_path(&model.source);
        let (_, pairs) = SourceFile::read_optional(&pairs)?;
        model.sources.push(pairs);
        Ok(model)
    }

    /// Parse URDF text; `source` names it in errors.
    pub fn from_urdf_str(text: &str, source: &str, tip_link: Option<&str>) -> Result<RobotModel> {
        super::xml_depth::check_depth(text, source)?;
        let robot = urdf_rs::read_from_string(text).map_err(|e| Error::File {
            path: source.into(),
            reason: format!("malformed URDF: {e}"),
        })?;
        build(&robot, text, source, tip_link)
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
        match builtin(name_or_path) {
            Some(b) => {
                let mut model = Self::from_urdf_str(
                    b.urdf,
                    &format!("builtin:{}", b.name),
                    Some(tip_link.unwrap_or(b.tip)),
                )?;
                model.sources.push(SourceFile::from_bytes(
                    &format!("builtin:{}.collision.toml", b.name),
                    b.collision.as_bytes(),
                ));
                Ok(model)
            }
            None if !Path::new(name_or_path).exists() => Err(Error::File {
                path: name_or_path.into(),
                reason: format!(
                    "no such URDF file, and not a built-in robot (built-in: {})",
                    BUILTINS.map(|b| b.name).join(", ")
                ),
            }),
            None => Self::from_urdf_file(name_or_path, tip_link),
        }
    }
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

fn shape_of(
    source: &str,
    link: &str,
    g: &urdf_rs::Geometry,
) -> Result<std::result::Result<Shape, String>> {
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
    Ok(Ok(match g {
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
        urdf_rs::Geometry::Mesh { filename, .. } => {
            return Ok(Err(format!("{link}: mesh {filename}")));
        }
    }))
}

fn is_movable(t: &urdf_rs::JointType) -> bool {
    matches!(
        t,
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous
    )
}

/// Build the model from a parsed URDF.
fn build(
    robot: &urdf_rs::Robot,
    text: &str,
    source: &str,
    tip_link: Option<&str>,
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
            return Err(bad(
                source,
                format!("joint {} mimic", j.name),
                &m.joint,
                "mimic joints are not supported",
            ));
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
            if j.joint_type == urdf_rs::JointType::Revolute
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
        match j.joint_type {
            urdf_rs::JointType::Fixed => path.push((origin, None)),
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
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
                    velocity: if j.limit.velocity.is_finite() {
                        j.limit.velocity
                    } else {
                        0.0
                    },
                    axis,
                });
                path.push((origin, Some(axis)));
            }
            ref t => {
                return Err(bad(
                    source,
                    format!("joint {} type", j.name),
                    format!("{t:?}"),
                    "only revolute, continuous and fixed joints are supported on the chain",
                ));
            }
        }
    }
    if joints.len() > MAX_DOF {
        return Err(bad(
            source,
            format!("chain to {tip}"),
            joints.len(),
            "more actuated joints than supported (7)",
        ));
    }
    if joints.is_empty() {
        return Err(Error::invalid(
            "tip_link",
            &tip,
            format!("{source}: no actuated joint between the root and this link"),
        ));
    }

    // Links: compiled steps, rigid groups, collision geometry.
    let mut frozen = Vec::new();
    let mut ignored = Vec::new();
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
                    LinkMotion::Revolute {
                        dof,
                        axis,
                        is_z: (axis - Vec3::z()).norm() < crate::math::tol::PARALLEL,
                    }
                } else {
                    match j.joint_type {
                        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                            let lo = if j.joint_type == urdf_rs::JointType::Continuous {
                                0.0
                            } else {
                                j.limit.lower
                            };
                            let hi = if j.joint_type == urdf_rs::JointType::Continuous {
                                0.0
                            } else {
                                j.limit.upper
                            };
                            let v: Real = 0.0_f64.clamp(lo, hi);
                            frozen.push((j.name.clone(), v));
                            let axis = Vec3::from(*j.axis.xyz).normalize();
                            origin.rot *= super::kinematics::axis_rotation(&axis, v);
                        }
                        urdf_rs::JointType::Fixed => {}
                        ref t => {
                            // Off the chain: frozen at its origin.
                            frozen.push((format!("{} ({t:?})", j.name), 0.0));
                        }
                    }
                    LinkMotion::Fixed
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
        for c in &ul.collision {
            finite3(
                source,
                format!("link {name} collision origin xyz"),
                &c.origin.xyz,
            )?;
            finite3(
                source,
                format!("link {name} collision origin rpy"),
                &c.origin.rpy,
            )?;
            match shape_of(source, name, &c.geometry)? {
                Ok(shape) => collision.push(CollisionGeometry {
                    origin: Frame::from_xyz_rpy(*c.origin.xyz, *c.origin.rpy),
                    shape,
                }),
                Err(what) => ignored.push(what),
            }
        }
        steps.push(step);
        links.push(LinkInfo {
            name: name.to_string(),
            parent,
            joint: joint_name,
            group,
            collision,
        });
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
        chain,
        urdf: robot.clone(),
        sources: vec![SourceFile::from_bytes(source, text.as_bytes())],
    })
}
