//! Collision checking with parry: the robot's primitive link shapes posed by FK, scene
//! obstacles, and the rod as a chain of thin capsules.
//!
//! # Pairs
//! Self-collision is checked between link bodies of different rigid groups (links joined by
//! fixed or frozen joints never move relative to each other), except link pairs joined by a
//! joint (adjacent) and the pairs of a [`DisabledPairs`] list: the pairs found never (or always)
//! in collision over many random configurations, computed once by [`DisabledPairs::compute`]
//! and stored beside the URDF as `<robot>.collision.toml` (like an SRDF's disabled collisions;
//! `helixreach robot --robot R --write-disabled FILE` regenerates it). Every robot body is
//! checked against every scene obstacle, and (outside the ignored ends) every rod segment against
//! every robot body and, optionally, the obstacles.
//!
//! # Speed
//! Each body has a bounding ball; a pair is tested exactly only if the balls overlap. Spheres
//! and capsules (the arms' shapes) are swept spheres: their exact test is a segment–segment
//! distance (closed form). Boxes and cylinders go to parry's `query::intersection_test` /
//! `query::distance`. A [`CollisionWorkspace`] holds the link frames and posed bodies, sized once:
//! no allocation per check.

use super::kinematics::{Chain, Frame};
use super::model::{RobotModel, Shape};
use crate::error::{Error, Result};
use crate::math::{Iso3, Mat3, Real, Vec3};
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};
use serde::{Deserialize, Serialize};

/// Shape of a scene obstacle (in the obstacle frame; cylinders along z).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ObstacleShape {
    /// Box with the given half extents (m).
    Box {
        /// Half extents along x, y, z (m).
        half_extents: [Real; 3],
    },
    /// Cylinder along z, centred at the origin.
    Cylinder {
        /// Radius (m).
        radius: Real,
        /// Half of the height (m).
        half_height: Real,
    },
    /// Capsule: the points within `radius` of the segment `a`–`b`.
    Capsule {
        /// First end (m).
        a: [Real; 3],
        /// Second end (m).
        b: [Real; 3],
        /// Radius (m).
        radius: Real,
    },
    /// Ball centred at the origin.
    Sphere {
        /// Radius (m).
        radius: Real,
    },
}

/// Pose of an obstacle in the robot's root frame: translation and fixed-axis roll–pitch–yaw
/// (URDF convention, `R = Rz(y)·Ry(p)·Rx(r)`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstaclePose {
    /// Translation (m).
    #[serde(default)]
    pub xyz: [Real; 3],
    /// Roll, pitch, yaw (rad).
    #[serde(default)]
    pub rpy: [Real; 3],
}

/// A scene obstacle, as a rig file embeds it:
///
/// ```
/// let o: helixreach::robot::collision::SceneObstacle = toml::from_str(r#"
///     name = "table"
///     shape = { type = "box", half_extents = [0.4, 0.6, 0.02] }
///     pose = { xyz = [0.85, 0.0, -0.164] }
/// "#).unwrap();
/// assert_eq!(o.name, "table");
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObstacle {
    /// Name (reported in collisions).
    pub name: String,
    /// Shape.
    pub shape: ObstacleShape,
    /// Pose in the robot root frame.
    #[serde(default)]
    pub pose: ObstaclePose,
}

impl SceneObstacle {
    /// Validate sizes (finite, > 0) and the pose (finite); errors name the obstacle and field.
    pub fn validate(&self) -> Result<()> {
        let f = |field: &str, v: Real, positive: bool| -> Result<()> {
            if v.is_finite() && (!positive || v > 0.0) {
                Ok(())
            } else {
                Err(Error::invalid(
                    format!("obstacle {}: {field}", self.name),
                    v,
                    if positive {
                        "must be finite and > 0"
                    } else {
                        "must be finite"
                    },
                ))
            }
        };
        for (i, v) in self.pose.xyz.iter().enumerate() {
            f(&format!("pose.xyz[{i}]"), *v, false)?;
        }
        for (i, v) in self.pose.rpy.iter().enumerate() {
            f(&format!("pose.rpy[{i}]"), *v, false)?;
        }
        match &self.shape {
            ObstacleShape::Box { half_extents } => {
                for (i, v) in half_extents.iter().enumerate() {
                    f(&format!("half_extents[{i}]"), *v, true)?;
                }
            }
            ObstacleShape::Cylinder {
                radius,
                half_height,
            } => {
                f("radius", *radius, true)?;
                f("half_height", *half_height, true)?;
            }
            ObstacleShape::Capsule { a, b, radius } => {
                for (i, v) in a.iter().chain(b).enumerate() {
                    f(&format!("a/b[{i}]"), *v, false)?;
                }
                f("radius", *radius, true)?;
            }
            ObstacleShape::Sphere { radius } => f("radius", *radius, true)?,
        }
        Ok(())
    }
}

/// The rod as thin capsules between consecutive nodes (robot root frame, clamp end first).
#[derive(Clone, Copy, Debug)]
pub struct RodGeometry<'a> {
    /// Centerline nodes, from the clamp to the tool.
    pub nodes: &'a [Vec3],
    /// Rod radius (m).
    pub radius: Real,
    /// Segments within this arc length (m) of the tool end are not checked (they touch the
    /// collet/gripper).
    pub ignore_near_tool: Real,
    /// Segments within this arc length (m) of the clamp are not checked (they touch the clamp).
    pub ignore_near_clamp: Real,
    /// Also check the rod against the scene obstacles.
    pub against_scene: bool,
}

/// One party of a collision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyRef {
    /// A link (index into [`RobotModel::links`]).
    Link(usize),
    /// A scene obstacle (index into the obstacles).
    Obstacle(usize),
    /// A rod segment (between nodes `i` and `i + 1`).
    Rod(usize),
}

/// Which pair collided (or is closest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// First body.
    pub a: BodyRef,
    /// Second body.
    pub b: BodyRef,
    /// Distance (m; 0 when touching or overlapping). Set by [`CollisionModel::clearance`]; 0
    /// for a boolean collision.
    pub distance: Real,
}

/// Link pairs excluded from self-collision checks (besides same-group and adjacent links).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DisabledPairs {
    /// Random configurations sampled to compute the list.
    #[serde(default)]
    pub samples: usize,
    /// Seed of the sampling.
    #[serde(default)]
    pub seed: u64,
    /// The pairs.
    #[serde(default)]
    pub disabled: Vec<DisabledPair>,
}

/// One excluded link pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DisabledPair {
    /// First link.
    pub a: String,
    /// Second link.
    pub b: String,
    /// `never` (never in collision in the samples) or `always`.
    pub reason: String,
}

#[derive(Clone, Debug)]
struct Body {
    link: usize,
    group: usize,
    /// Shape pose in the link (or root, for obstacles) frame, parry convention.
    local: Frame,
    parry: SharedShape,
    /// Swept-sphere form (segment ends in the local frame and radius), if any.
    ssv: Option<(Vec3, Vec3, Real)>,
    /// Bounding ball: centre in the link frame, radius.
    center: Vec3,
    radius: Real,
}

#[derive(Clone, Copy, Debug, Default)]
struct Posed {
    pose: Frame,
    a: Vec3,
    b: Vec3,
    center: Vec3,
}

/// Scratch for the checks, sized once per model ([`CollisionModel::workspace`]).
#[derive(Clone, Debug)]
pub struct CollisionWorkspace {
    frames: Vec<Frame>,
    posed: Vec<Posed>,
}

/// The collision model of a robot plus its scene (see the module docs). Immutable, `Send + Sync`.
#[derive(Clone, Debug)]
pub struct CollisionModel {
    chain: Chain,
    link_names: Vec<String>,
    bodies: Vec<Body>,
    obstacles: Vec<Body>,
    obstacle_posed: Vec<Posed>,
    obstacle_names: Vec<String>,
    self_pairs: Vec<(u16, u16)>,
}

fn parry_of(shape: &Shape, local: &Frame) -> (SharedShape, Frame, Option<(Vec3, Vec3, Real)>) {
    // parry cylinders are along y: turn y onto z.
    let y_to_z = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
    match *shape {
        Shape::Sphere { radius } => (
            SharedShape::new(Ball::new(radius)),
            *local,
            Some((local.pos, local.pos, radius)),
        ),
        Shape::Box { half_extents } => (SharedShape::new(Cuboid::new(half_extents)), *local, None),
        Shape::Cylinder {
            radius,
            half_length,
        } => (
            SharedShape::new(Cylinder::new(half_length, radius)),
            Frame::new(local.rot * y_to_z, local.pos),
            None,
        ),
        Shape::Capsule {
            radius,
            half_length,
        } => {
            let a = local.transform_point(&Vec3::new(0.0, 0.0, -half_length));
            let b = local.transform_point(&Vec3::new(0.0, 0.0, half_length));
            (
                SharedShape::new(Capsule::new_z(half_length, radius)),
                *local,
                Some((a, b, radius)),
            )
        }
    }
}

fn obstacle_shape(o: &ObstacleShape) -> Shape {
    match *o {
        ObstacleShape::Box { half_extents } => Shape::Box {
            half_extents: Vec3::from(half_extents),
        },
        ObstacleShape::Cylinder {
            radius,
            half_height,
        } => Shape::Cylinder {
            radius,
            half_length: half_height,
        },
        ObstacleShape::Sphere { radius } => Shape::Sphere { radius },
        ObstacleShape::Capsule { radius, .. } => Shape::Sphere { radius }, // replaced below
    }
}

/// Squared distance between segments `p1q1` and `p2q2` (closest points, clamped; robust for
/// degenerate segments).
#[inline]
pub fn segment_distance_squared(p1: &Vec3, q1: &Vec3, p2: &Vec3, q2: &Vec3) -> Real {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    let eps = 1e-24;
    let (s, t);
    if a <= eps && e <= eps {
        return r.norm_squared();
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let c1 = p1 + d1 * s;
    let c2 = p2 + d2 * t;
    (c1 - c2).norm_squared()
}

impl CollisionModel {
    /// Build from a model, its disabled pairs and a scene.
    pub fn new(
        model: &RobotModel,
        disabled: &DisabledPairs,
        obstacles: &[SceneObstacle],
    ) -> Result<CollisionModel> {
        let links = model.links();
        let mut bodies = Vec::new();
        for (li, l) in links.iter().enumerate() {
            for c in &l.collision {
                let (parry, local, ssv) = parry_of(&c.shape, &c.origin);
                bodies.push(Body {
                    link: li,
                    group: l.group,
                    local,
                    parry,
                    ssv,
                    center: c.origin.pos,
                    radius: c.shape.bounding_radius(),
                });
            }
        }
        let mut off = std::collections::HashSet::new();
        for p in &disabled.disabled {
            let ia = model.link_index(&p.a);
            let ib = model.link_index(&p.b);
            match (ia, ib) {
                (Some(a), Some(b)) => {
                    off.insert((a.min(b), a.max(b)));
                }
                _ => {
                    return Err(Error::invalid(
                        "disabled collision pair",
                        format!("{} / {}", p.a, p.b),
                        format!("no such link in {}", model.source()),
                    ))
                }
            }
        }
        let mut self_pairs = Vec::new();
        for (i, bi) in bodies.iter().enumerate() {
            for (j, bj) in bodies.iter().enumerate().skip(i + 1) {
                if Self::candidate(links, bi.link, bj.link)
                    && !off.contains(&(bi.link.min(bj.link), bi.link.max(bj.link)))
                {
                    self_pairs.push((i as u16, j as u16));
                }
            }
        }
        let mut cm = CollisionModel {
            chain: model.chain().clone(),
            link_names: links.iter().map(|l| l.name.clone()).collect(),
            bodies,
            obstacles: Vec::new(),
            obstacle_posed: Vec::new(),
            obstacle_names: Vec::new(),
            self_pairs,
        };
        cm.set_obstacles(obstacles)?;
        Ok(cm)
    }

    /// The model with the never-colliding list of a built-in robot, or of the file beside the
    /// URDF (`<name>.collision.toml`, if present), and no obstacles.
    pub fn for_model(model: &RobotModel) -> Result<CollisionModel> {
        let disabled = DisabledPairs::for_model(model)?;
        Self::new(model, &disabled, &[])
    }

    /// Replace the scene obstacles.
    pub fn set_obstacles(&mut self, obstacles: &[SceneObstacle]) -> Result<()> {
        self.obstacles.clear();
        self.obstacle_posed.clear();
        self.obstacle_names.clear();
        for (k, o) in obstacles.iter().enumerate() {
            o.validate()?;
            let pose = Frame::from_xyz_rpy(o.pose.xyz, o.pose.rpy);
            let body = match o.shape {
                ObstacleShape::Capsule { a, b, radius } => {
                    let (a, b) = (Vec3::from(a), Vec3::from(b));
                    let aw = pose.transform_point(&a);
                    let bw = pose.transform_point(&b);
                    Body {
                        link: k,
                        group: usize::MAX,
                        local: Frame::identity(),
                        parry: SharedShape::new(Capsule::new(aw.into(), bw.into(), radius)),
                        ssv: Some((aw, bw, radius)),
                        center: 0.5 * (aw + bw),
                        radius: radius + 0.5 * (bw - aw).norm(),
                    }
                }
                ref s => {
                    let shape = obstacle_shape(s);
                    let (parry, local, ssv) = parry_of(&shape, &pose);
                    Body {
                        link: k,
                        group: usize::MAX,
                        local,
                        parry,
                        ssv,
                        center: pose.pos,
                        radius: shape.bounding_radius(),
                    }
                }
            };
            let (a, b) = body.ssv.map(|s| (s.0, s.1)).unwrap_or_default();
            self.obstacle_posed.push(Posed {
                pose: body.local,
                a,
                b,
                center: body.center,
            });
            self.obstacles.push(body);
            self.obstacle_names.push(o.name.clone());
        }
        Ok(())
    }

    fn candidate(links: &[super::model::LinkInfo], a: usize, b: usize) -> bool {
        if a == b || links[a].group == links[b].group {
            return false;
        }
        !(links[a].parent == Some(b) || links[b].parent == Some(a))
    }

    /// A workspace sized for this model.
    pub fn workspace(&self) -> CollisionWorkspace {
        CollisionWorkspace {
            frames: vec![Frame::identity(); self.chain.n_links()],
            posed: vec![Posed::default(); self.bodies.len()],
        }
    }

    /// Number of body pairs checked for self-collision.
    pub fn n_self_pairs(&self) -> usize {
        self.self_pairs.len()
    }

    /// The body pairs checked for self-collision, as link indices.
    pub fn self_pair_links(&self) -> Vec<(usize, usize)> {
        self.self_pairs
            .iter()
            .map(|&(i, j)| (self.bodies[i as usize].link, self.bodies[j as usize].link))
            .collect()
    }

    /// A readable name of a body.
    pub fn name(&self, r: BodyRef) -> String {
        match r {
            BodyRef::Link(i) => self.link_names[i].clone(),
            BodyRef::Obstacle(i) => format!("obstacle {}", self.obstacle_names[i]),
            BodyRef::Rod(i) => format!("rod segment {i}"),
        }
    }

    /// Pose every body at `q` (`q.len()` = the chain's dof).
    pub fn update(&self, q: &[Real], ws: &mut CollisionWorkspace) {
        self.chain.link_frames(q, &mut ws.frames);
        for (b, p) in self.bodies.iter().zip(ws.posed.iter_mut()) {
            let f = &ws.frames[b.link];
            p.center = f.transform_point(&b.center);
            if let Some((a, bb, _)) = b.ssv {
                p.a = f.transform_point(&a);
                p.b = f.transform_point(&bb);
            } else {
                p.pose = f.mul(&b.local);
            }
        }
    }

    /// The posed frames of every link after [`CollisionModel::update`].
    pub fn link_frames<'w>(&self, ws: &'w CollisionWorkspace) -> &'w [Frame] {
        &ws.frames
    }

    #[inline]
    fn pair_test(b1: &Body, p1: &Posed, b2: &Body, p2: &Posed) -> bool {
        let r = b1.radius + b2.radius;
        if (p1.center - p2.center).norm_squared() > r * r {
            return false;
        }
        match (b1.ssv, b2.ssv) {
            (Some((_, _, r1)), Some((_, _, r2))) => {
                let rr = r1 + r2;
                segment_distance_squared(&p1.a, &p1.b, &p2.a, &p2.b) <= rr * rr
            }
            _ => {
                let i1 = Self::iso(b1, p1);
                let i2 = Self::iso(b2, p2);
                query::intersection_test(&i1, b1.parry.as_ref(), &i2, b2.parry.as_ref())
                    .unwrap_or(true)
            }
        }
    }

    #[inline]
    fn pair_distance(b1: &Body, p1: &Posed, b2: &Body, p2: &Posed) -> Real {
        match (b1.ssv, b2.ssv) {
            (Some((_, _, r1)), Some((_, _, r2))) => {
                (segment_distance_squared(&p1.a, &p1.b, &p2.a, &p2.b).sqrt() - r1 - r2).max(0.0)
            }
            _ => {
                // Through parry's closest points, not `query::distance`: in parry 0.25 the
                // cuboid–cuboid `distance` overestimates the gap when the closest features are
                // edges (dimforge/parry#431; pedestal feet to the seed table: 0.2093 m for a
                // true 0.1978 m), while `closest_points` has an exact cuboid–cuboid case.
                let i1 = Self::iso(b1, p1);
                let i2 = Self::iso(b2, p2);
                match query::closest_points(
                    &i1,
                    b1.parry.as_ref(),
                    &i2,
                    b2.parry.as_ref(),
                    Real::MAX,
                ) {
                    Ok(query::ClosestPoints::WithinMargin(a, b)) => (a - b).norm(),
                    Ok(query::ClosestPoints::Intersecting) => 0.0,
                    _ => query::distance(&i1, b1.parry.as_ref(), &i2, b2.parry.as_ref())
                        .unwrap_or(0.0),
                }
            }
        }
    }

    /// The parry pose of a posed body (swept spheres are posed by their world segment).
    fn iso(b: &Body, p: &Posed) -> Iso3 {
        match b.ssv {
            // Ball / capsule: rebuild the pose from the world segment.
            Some((a, bb, _)) if b.group != usize::MAX => {
                let local_len = (bb - a).norm();
                if local_len < 1e-15 {
                    Iso3::translation(p.a.x, p.a.y, p.a.z)
                } else {
                    let z = (p.b - p.a) / local_len;
                    let rot = super::kinematics::z_to_axis(&z);
                    let c = 0.5 * (p.a + p.b);
                    Frame::new(rot, c).to_iso()
                }
            }
            _ => p.pose.to_iso(),
        }
    }

    /// First self-collision at the posed configuration, if any.
    pub fn self_collision(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        for &(i, j) in &self.self_pairs {
            let (i, j) = (i as usize, j as usize);
            if Self::pair_test(&self.bodies[i], &ws.posed[i], &self.bodies[j], &ws.posed[j]) {
                return Some(Contact {
                    a: BodyRef::Link(self.bodies[i].link),
                    b: BodyRef::Link(self.bodies[j].link),
                    distance: 0.0,
                });
            }
        }
        None
    }

    /// First robot–obstacle collision at the posed configuration, if any.
    pub fn scene_collision(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        for (k, (o, op)) in self.obstacles.iter().zip(&self.obstacle_posed).enumerate() {
            for (b, p) in self.bodies.iter().zip(&ws.posed) {
                if Self::pair_test(b, p, o, op) {
                    return Some(Contact {
                        a: BodyRef::Link(b.link),
                        b: BodyRef::Obstacle(k),
                        distance: 0.0,
                    });
                }
            }
        }
        None
    }

    fn rod_segments<'r>(rod: &RodGeometry<'r>) -> impl Iterator<Item = (usize, Vec3, Vec3)> + 'r {
        let n = rod.nodes.len();
        let total: Real = rod.nodes.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let (near_clamp, near_tool) = (rod.ignore_near_clamp, rod.ignore_near_tool);
        let nodes = rod.nodes;
        let mut s = 0.0;
        (0..n.saturating_sub(1)).filter_map(move |i| {
            let a = nodes[i];
            let b = nodes[i + 1];
            let s0 = s;
            s += (b - a).norm();
            (s0 >= near_clamp && total - s >= near_tool).then_some((i, a, b))
        })
    }

    /// Whether the rod capsule `a`–`b` (radius `r`) touches a posed body.
    #[inline]
    fn seg_hit(a: &Vec3, b: &Vec3, r: Real, o: &Body, op: &Posed) -> bool {
        let rr = r + 0.5 * (b - a).norm() + o.radius;
        if (0.5 * (a + b) - op.center).norm_squared() > rr * rr {
            return false;
        }
        match o.ssv {
            Some((_, _, r2)) => segment_distance_squared(a, b, &op.a, &op.b) <= (r + r2) * (r + r2),
            None => {
                let cap = Capsule::new((*a).into(), (*b).into(), r);
                query::intersection_test(
                    &Iso3::identity(),
                    &cap,
                    &Self::iso(o, op),
                    o.parry.as_ref(),
                )
                .unwrap_or(true)
            }
        }
    }

    /// Distance (≥ 0) between the rod capsule `a`–`b` (radius `r`) and a posed body.
    fn seg_distance(a: &Vec3, b: &Vec3, r: Real, o: &Body, op: &Posed) -> Real {
        match o.ssv {
            Some((_, _, r2)) => {
                (segment_distance_squared(a, b, &op.a, &op.b).sqrt() - r - r2).max(0.0)
            }
            None => {
                let cap = Capsule::new((*a).into(), (*b).into(), r);
                query::distance(&Iso3::identity(), &cap, &Self::iso(o, op), o.parry.as_ref())
                    .unwrap_or(0.0)
            }
        }
    }

    /// First rod collision (against robot bodies, and obstacles if asked), if any.
    pub fn rod_collision(&self, ws: &CollisionWorkspace, rod: &RodGeometry<'_>) -> Option<Contact> {
        let r = rod.radius;
        for (i, a, b) in Self::rod_segments(rod) {
            for (bd, p) in self.bodies.iter().zip(&ws.posed) {
                if Self::seg_hit(&a, &b, r, bd, p) {
                    return Some(Contact {
                        a: BodyRef::Rod(i),
                        b: BodyRef::Link(bd.link),
                        distance: 0.0,
                    });
                }
            }
            if rod.against_scene {
                for (k, (o, op)) in self.obstacles.iter().zip(&self.obstacle_posed).enumerate() {
                    if Self::seg_hit(&a, &b, r, o, op) {
                        return Some(Contact {
                            a: BodyRef::Rod(i),
                            b: BodyRef::Obstacle(k),
                            distance: 0.0,
                        });
                    }
                }
            }
        }
        None
    }

    /// Pose at `q` and report the first collision (self, scene, rod), if any.
    pub fn check(
        &self,
        q: &[Real],
        ws: &mut CollisionWorkspace,
        rod: Option<&RodGeometry<'_>>,
    ) -> Option<Contact> {
        self.update(q, ws);
        self.self_collision(ws)
            .or_else(|| self.scene_collision(ws))
            .or_else(|| rod.and_then(|r| self.rod_collision(ws, r)))
    }

    /// Pose at `q`; the smallest distance over every checked pair (self, scene, rod) and that
    /// pair. `None` if nothing is checked.
    pub fn clearance(
        &self,
        q: &[Real],
        ws: &mut CollisionWorkspace,
        rod: Option<&RodGeometry<'_>>,
    ) -> Option<Contact> {
        self.update(q, ws);
        [
            self.self_clearance(ws),
            self.scene_clearance(ws),
            rod.and_then(|r| self.rod_clearance(ws, r)),
        ]
        .into_iter()
        .flatten()
        .min_by(|a, b| a.distance.total_cmp(&b.distance))
    }

    /// Smallest self-collision distance at the posed configuration and its pair.
    pub fn self_clearance(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        let mut best: Option<Contact> = None;
        for &(i, j) in &self.self_pairs {
            let (i, j) = (i as usize, j as usize);
            let d =
                Self::pair_distance(&self.bodies[i], &ws.posed[i], &self.bodies[j], &ws.posed[j]);
            if best.is_none_or(|c| d < c.distance) {
                best = Some(Contact {
                    a: BodyRef::Link(self.bodies[i].link),
                    b: BodyRef::Link(self.bodies[j].link),
                    distance: d,
                });
            }
        }
        best
    }

    /// Smallest robot–obstacle distance at the posed configuration and its pair.
    pub fn scene_clearance(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        let mut best: Option<Contact> = None;
        for (k, (o, op)) in self.obstacles.iter().zip(&self.obstacle_posed).enumerate() {
            for (b, p) in self.bodies.iter().zip(&ws.posed) {
                let d = Self::pair_distance(b, p, o, op);
                if best.is_none_or(|c| d < c.distance) {
                    best = Some(Contact {
                        a: BodyRef::Link(b.link),
                        b: BodyRef::Obstacle(k),
                        distance: d,
                    });
                }
            }
        }
        best
    }

    /// Smallest rod distance (to the robot, and the obstacles if asked) and its pair.
    pub fn rod_clearance(&self, ws: &CollisionWorkspace, rod: &RodGeometry<'_>) -> Option<Contact> {
        let mut best: Option<Contact> = None;
        let mut consider = |a: BodyRef, b: BodyRef, d: Real| {
            if best.is_none_or(|c| d < c.distance) {
                best = Some(Contact { a, b, distance: d });
            }
        };
        for (i, a, b) in Self::rod_segments(rod) {
            for (bd, p) in self.bodies.iter().zip(&ws.posed) {
                consider(
                    BodyRef::Rod(i),
                    BodyRef::Link(bd.link),
                    Self::seg_distance(&a, &b, rod.radius, bd, p),
                );
            }
            if rod.against_scene {
                for (k, (o, op)) in self.obstacles.iter().zip(&self.obstacle_posed).enumerate() {
                    consider(
                        BodyRef::Rod(i),
                        BodyRef::Obstacle(k),
                        Self::seg_distance(&a, &b, rod.radius, o, op),
                    );
                }
            }
        }
        best
    }

    /// Reference check by parry alone: every self pair through `query::intersection_test` on
    /// parry shapes posed from the link frames (no bounding balls, no swept-sphere shortcut).
    /// For tests.
    pub fn self_collision_parry(&self, ws: &CollisionWorkspace) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for &(i, j) in &self.self_pairs {
            let (bi, bj) = (&self.bodies[i as usize], &self.bodies[j as usize]);
            let pi = ws.frames[bi.link].mul(&bi.local).to_iso();
            let pj = ws.frames[bj.link].mul(&bj.local).to_iso();
            if query::intersection_test(&pi, bi.parry.as_ref(), &pj, bj.parry.as_ref())
                .unwrap_or(true)
            {
                out.push((bi.link, bj.link));
            }
        }
        out
    }
}

impl DisabledPairs {
    /// Parse a `<robot>.collision.toml`; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<DisabledPairs> {
        toml::from_str(text).map_err(|e| Error::File {
            path: source.into(),
            reason: format!("malformed disabled-pairs file: {e}"),
        })
    }

    /// The list for a model: the built-in one, or `<urdf stem>.collision.toml` beside the URDF
    /// file if it exists, else empty.
    pub fn for_model(model: &RobotModel) -> Result<DisabledPairs> {
        if let Some(name) = model.source().strip_prefix("builtin:") {
            if let Some(b) = super::urdf::builtin(name) {
                return Self::from_toml(b.collision, &format!("builtin:{name}.collision.toml"));
            }
        }
        let p = std::path::Path::new(model.source()).with_extension("collision.toml");
        if p.exists() {
            let text = std::fs::read_to_string(&p).map_err(|source| Error::Io {
                path: p.clone(),
                source,
            })?;
            return Self::from_toml(&text, &p.display().to_string());
        }
        Ok(DisabledPairs::default())
    }

    /// Sample `samples` random in-limit configurations (ChaCha8 stream from `seed`) and list
    /// the candidate link pairs (not same group, not adjacent) that never — or always — collide.
    pub fn compute(model: &RobotModel, samples: usize, seed: u64) -> Result<DisabledPairs> {
        use rand::SeedableRng;
        let cm = CollisionModel::new(model, &DisabledPairs::default(), &[])?;
        let mut ws = cm.workspace();
        let pairs = cm.self_pair_links();
        let mut link_pairs: Vec<(usize, usize)> =
            pairs.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        link_pairs.sort_unstable();
        link_pairs.dedup();
        let mut count = vec![0usize; link_pairs.len()];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let n = model.dof();
        let mut hit = vec![false; link_pairs.len()];
        for _ in 0..samples {
            let q = model.random_config(&mut rng);
            cm.update(&q[..n], &mut ws);
            hit.iter_mut().for_each(|h| *h = false);
            for &(i, j) in &cm.self_pairs {
                let (i, j) = (i as usize, j as usize);
                let (la, lb) = (cm.bodies[i].link, cm.bodies[j].link);
                let k = link_pairs
                    .binary_search(&(la.min(lb), la.max(lb)))
                    .expect("pair listed");
                if !hit[k]
                    && CollisionModel::pair_test(
                        &cm.bodies[i],
                        &ws.posed[i],
                        &cm.bodies[j],
                        &ws.posed[j],
                    )
                {
                    hit[k] = true;
                }
            }
            for (c, h) in count.iter_mut().zip(&hit) {
                *c += usize::from(*h);
            }
        }
        let names = model.links();
        let disabled = link_pairs
            .iter()
            .zip(&count)
            .filter(|(_, &c)| c == 0 || c == samples)
            .map(|(&(a, b), &c)| DisabledPair {
                a: names[a].name.clone(),
                b: names[b].name.clone(),
                reason: if c == 0 { "never" } else { "always" }.into(),
            })
            .collect();
        Ok(DisabledPairs {
            samples,
            seed,
            disabled,
        })
    }

    /// The TOML text (with a header saying how to regenerate it).
    pub fn to_toml(&self, robot: &str) -> String {
        let mut s = format!(
            "# Link pairs of {robot} never checked for self-collision (like an SRDF's disabled\n\
             # collisions), besides links joined by a joint or rigidly attached to each other.\n\
             # \"never\": not in collision in any of the random in-limit samples; \"always\": in all.\n\
             # Regenerate: helixreach robot --robot {robot} --write-disabled FILE [--samples N]\n"
        );
        s.push_str(&toml::to_string(self).unwrap_or_default());
        s
    }
}
