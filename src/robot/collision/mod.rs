//! Collision checking with parry: the robot's primitive link shapes posed by FK, scene
//! obstacles, and the rod as a chain of thin capsules.
//!
//! ## Map
//! | module | holds |
//! |---|---|
//! | [`scene`] | the rig file's obstacle schema ([`SceneObstacle`]), validation, placement as a [`Shape`](crate::robot::Shape) |
//! | `narrow` | bodies, their owners (link or obstacle) and the exact pair test and distance |
//! | `walk` | the one walk over the checked pairs, shared by the boolean checks and the clearances |
//! | [`disabled`] | which link pairs self-collision skips ([`DisabledPairs`]) |
//! | [`fit`] | the capsule fitted around a mesh's convex hull ([`FittedCapsule`]) and its gap |
//!
//! # Pairs
//! Self-collision is checked between link bodies of different rigid groups (links joined by
//! fixed or frozen joints never move relative to each other), except link pairs joined by a
//! joint (adjacent) and the pairs of a [`DisabledPairs`] list (`helixreach robot --robot R
//! --write-disabled FILE` regenerates it). Every robot body is checked against every scene
//! obstacle, and (outside the ignored ends) every rod segment against every robot body and,
//! optionally, the obstacles.
//!
//! # Speed
//! Each body has a bounding ball; a pair is tested exactly only if the balls overlap. Spheres
//! and capsules (the arms' shapes) are swept spheres: their exact test is a segment–segment
//! distance (closed form, [`segment_distance_squared`]). A box or a cylinder against a swept
//! sphere is decided in closed form too (the segment's distance to the box; the cylinder's
//! lateral surface), except where a cylinder's end disc is the closest feature; those, and
//! box–box, cylinder–box and mesh-hull pairs, go to parry's `query::intersection_test` /
//! `query::closest_points` (module `narrow`). A mesh hull is checked as
//! [`CollisionKind`] says: exactly, as its fitted capsule, or (the default) exactly only where
//! its fitted capsule touches the other part's capsule. Bodies of links that no joint moves
//! (base, pedestal, mounts) are posed once, when the model is built. A [`CollisionWorkspace`]
//! holds the link frames and posed bodies, sized once: no allocation per check.

pub mod disabled;
pub mod fit;
mod narrow;
pub mod scene;
mod walk;

pub use disabled::{collision_toml_path, DisabledPair, DisabledPairs};
pub use fit::FittedCapsule;
pub use narrow::segment_distance_squared;
pub use scene::{ObstaclePose, SceneObstacle};

use super::kinematics::{Chain, Frame};
use super::model::RobotModel;
use crate::error::Result;
use crate::math::{Real, Vec3};
use narrow::{Body, Owner, Posed};
use parry3d_f64::query;
use std::ops::ControlFlow;
use walk::{AllHits, FirstHit, Nearest, Visit};

/// Whether [`CollisionModel::announce`] prints.
static ANNOUNCE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(true);

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

/// Scratch for the checks, sized once per model ([`CollisionModel::workspace`]).
#[derive(Clone, Debug)]
pub struct CollisionWorkspace {
    frames: Vec<Frame>,
    posed: Vec<Posed>,
    /// The last two rods' segments and chunk balls (rebuilt when a third rod comes).
    rod: std::cell::RefCell<walk::RodCache>,
}

/// The collision model of a robot plus its scene (see the module docs). Immutable, `Send + Sync`.
#[derive(Clone, Debug)]
pub struct CollisionModel {
    chain: Chain,
    link_names: Vec<String>,
    /// The robot's bodies (every one [`Owner::Link`]).
    bodies: Vec<Body>,
    /// Each body's pose when its link never moves (`Chain::constant_frame`): copied, not
    /// recomputed, by [`CollisionModel::update`].
    constant_posed: Vec<Option<Posed>>,
    /// The scene's bodies (every one [`Owner::Obstacle`]) and their fixed poses.
    obstacles: Vec<Body>,
    obstacle_posed: Vec<Posed>,
    obstacle_names: Vec<String>,
    /// Body pairs checked for self-collision (indices into `bodies`).
    self_pairs: Vec<(u16, u16)>,
    /// Mesh bodies (convex hulls) among `bodies`.
    n_meshes: usize,
    /// The meshes' fitted capsules (in body order).
    capsules: Vec<LinkCapsule>,
    /// Padding.
    settings: CollisionSettings,
}

/// What is checked for a mesh's convex hull (`[robot] collision_model` of a rig).
///
/// | kind | a mesh is | answer |
/// |---|---|---|
/// | `hull` | its convex hull | exact for the hulls |
/// | `primitives` | its fitted capsule ([`fit`]) | never free where the hulls touch; may report a contact up to the capsule's gap away from the hull |
/// | `primitives_then_hull` (default) | the hull, tested only where the capsules touch | exactly the `hull` answer (the capsule contains the hull), faster |
///
/// Distances ([`CollisionModel::clearance`]) are those of the same shapes: the hulls under
/// `hull` and `primitives_then_hull`, the capsules under `primitives`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CollisionKind {
    /// The exact convex hulls.
    Hull,
    /// The fitted capsules only.
    Primitives,
    /// The capsules as a broad phase before the hulls.
    #[default]
    PrimitivesThenHull,
}

impl CollisionKind {
    /// Every kind, in the order of [`CollisionKind::NAMES`].
    pub const ALL: [CollisionKind; 3] = [
        CollisionKind::Hull,
        CollisionKind::Primitives,
        CollisionKind::PrimitivesThenHull,
    ];
    /// The names a rig may write.
    pub const NAMES: [&'static str; 3] = ["hull", "primitives", "primitives_then_hull"];

    /// The name a rig writes.
    pub fn name(self) -> &'static str {
        match self {
            CollisionKind::Hull => "hull",
            CollisionKind::Primitives => "primitives",
            CollisionKind::PrimitivesThenHull => "primitives_then_hull",
        }
    }

    /// The kind of a name, if it is one of [`CollisionKind::NAMES`].
    pub fn from_name(s: &str) -> Option<CollisionKind> {
        Self::ALL.into_iter().find(|k| k.name() == s)
    }
}

impl std::fmt::Display for CollisionKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Padding of the robot's collision bodies (m) and what is checked for meshes. Every body of a
/// link is grown by the link's padding (`link_padding`, else `padding`): a pair is in contact
/// when the shapes are within the sum of their paddings; a mesh's fitted capsule grows by the
/// same padding as its hull. Scene obstacles and the rod are not padded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CollisionSettings {
    /// Padding of every link (m, ≥ 0).
    pub padding: Real,
    /// Per-link padding (m, ≥ 0), overriding `padding`.
    pub link_padding: Vec<(String, Real)>,
    /// What is checked for mesh hulls.
    pub kind: CollisionKind,
}

/// A mesh's fitted capsule as the model uses it (link frame; radius with the link's padding).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkCapsule {
    /// The link (index into [`RobotModel::links`]).
    pub link: usize,
    /// Segment ends in the link frame.
    pub a: Vec3,
    /// The other end.
    pub b: Vec3,
    /// Radius (m): the fitted radius plus the link's padding.
    pub radius: Real,
    /// Largest gap of the unpadded capsule to its hull (m; [`fit::FittedCapsule::gap`]).
    pub gap: Real,
}

impl CollisionSettings {
    /// The padding of link `name`.
    pub fn pad_of(&self, name: &str) -> Real {
        self.link_padding
            .iter()
            .find(|(n, _)| n == name)
            .map_or(self.padding, |(_, p)| *p)
    }

    /// Finite, ≥ 0, at most [`MAX_PADDING`]; every per-link name is a link of `model`.
    pub fn validate(&self, model: &RobotModel) -> Result<()> {
        let check = |what: String, v: Real| -> Result<()> {
            if v.is_finite() && (0.0..=MAX_PADDING).contains(&v) {
                Ok(())
            } else {
                Err(crate::error::Error::invalid(
                    what,
                    v,
                    format!("must be finite, in 0..={MAX_PADDING} m"),
                ))
            }
        };
        check("padding".into(), self.padding)?;
        for (n, p) in &self.link_padding {
            check(format!("link_padding.{n}"), *p)?;
            if model.link_index(n).is_none() {
                return Err(crate::error::Error::invalid(
                    "link_padding",
                    n,
                    format!("no link of that name in {}", model.source()),
                ));
            }
        }
        Ok(())
    }
}

/// Largest padding accepted (m): more is a typo (millimetres for metres), not a margin.
pub const MAX_PADDING: Real = 0.5;

impl CollisionModel {
    /// Build from a model, its disabled pairs and a scene.
    pub fn new(
        model: &RobotModel,
        disabled: &DisabledPairs,
        obstacles: &[SceneObstacle],
    ) -> Result<CollisionModel> {
        Self::with_settings(model, disabled, obstacles, &CollisionSettings::default())
    }

    /// Build with padding ([`CollisionSettings`]).
    pub fn with_settings(
        model: &RobotModel,
        disabled: &DisabledPairs,
        obstacles: &[SceneObstacle],
        settings: &CollisionSettings,
    ) -> Result<CollisionModel> {
        settings.validate(model)?;
        let links = model.links();
        let mut bodies: Vec<Body> = Vec::new();
        let mut capsules = Vec::new();
        for (li, l) in links.iter().enumerate() {
            let pad = settings.pad_of(&l.name);
            for c in &l.collision {
                bodies.push(Body::new(Owner::Link(li), &c.shape, &c.origin).padded(pad));
            }
            for m in &l.meshes {
                let owner = Owner::Link(li);
                let fit = &m.mesh.capsule;
                let (a, b) = (
                    m.origin.transform_point(&fit.a),
                    m.origin.transform_point(&fit.b),
                );
                capsules.push(LinkCapsule {
                    link: li,
                    a,
                    b,
                    radius: fit.radius + pad,
                    gap: fit.gap,
                });
                let hull =
                    || Body::hull(owner, m.mesh.hull.clone(), &m.mesh.hull_points, &m.origin);
                let body = match settings.kind {
                    CollisionKind::Hull => hull(),
                    CollisionKind::Primitives => Body::capsule(owner, a, b, fit.radius),
                    CollisionKind::PrimitivesThenHull => hull().with_fit((a, b, fit.radius)),
                };
                bodies.push(body.padded(pad));
            }
        }
        if bodies.len() > u16::MAX as usize {
            return Err(crate::error::Error::invalid(
                "collision bodies",
                bodies.len(),
                format!(
                    "{}: at most {} collision elements",
                    model.source(),
                    u16::MAX
                ),
            ));
        }
        let self_pairs = disabled::self_pairs(model, &bodies, disabled)?;
        let chain = model.chain();
        let constant_posed = bodies
            .iter()
            .map(|b| match b.owner {
                Owner::Link(l) => chain.constant_frame(l).map(|f| {
                    let mut p = Posed::default();
                    b.pose(&f, &mut p);
                    p
                }),
                Owner::Obstacle(_) => None,
            })
            .collect();
        let mut cm = CollisionModel {
            chain: chain.clone(),
            constant_posed,
            link_names: links.iter().map(|l| l.name.clone()).collect(),
            n_meshes: links.iter().map(|l| l.meshes.len()).sum(),
            capsules,
            settings: settings.clone(),
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
            let (shape, pose) = o.placed();
            let body = Body::new(Owner::Obstacle(k), &shape, &pose);
            let mut posed = Posed::default();
            body.pose(&Frame::identity(), &mut posed);
            self.obstacles.push(body);
            self.obstacle_posed.push(posed);
            self.obstacle_names.push(o.name.clone());
        }
        Ok(())
    }

    /// A workspace sized for this model.
    pub fn workspace(&self) -> CollisionWorkspace {
        CollisionWorkspace {
            frames: vec![Frame::identity(); self.chain.n_links()],
            posed: vec![Posed::default(); self.bodies.len()],
            rod: Default::default(),
        }
    }

    /// Number of body pairs checked for self-collision.
    pub fn n_self_pairs(&self) -> usize {
        self.self_pairs.len()
    }

    /// Number of robot collision bodies.
    pub fn n_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// Whether [`CollisionModel::announce`] prints (default true; a quiet command turns it off
    /// for the whole process).
    pub fn set_announce(on: bool) {
        ANNOUNCE.store(on, std::sync::atomic::Ordering::Relaxed);
    }

    /// What is checked for mesh hulls.
    pub fn kind(&self) -> CollisionKind {
        self.settings.kind
    }

    /// The fitted capsule of every mesh, in body order (whatever the kind: under `hull` they are
    /// not checked).
    pub fn mesh_capsules(&self) -> &[LinkCapsule] {
        &self.capsules
    }

    /// The largest gap of any mesh's fitted capsule (m; 0 without meshes).
    pub fn largest_gap(&self) -> Real {
        self.capsules.iter().map(|c| c.gap).fold(0.0, Real::max)
    }

    /// Print [`CollisionModel::summary`] on stderr, once per process for each distinct text
    /// (a sweep that builds the same model many times says it once), unless turned off by
    /// [`CollisionModel::set_announce`].
    pub fn announce(&self) {
        if !ANNOUNCE.load(std::sync::atomic::Ordering::Relaxed) {
            return;
        }
        static SAID: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
        let s = self.summary();
        let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
        if !said.contains(&s) {
            eprintln!("{s}");
            said.push(s);
        }
    }

    /// One line saying what is checked: bodies (primitives, mesh hulls), self pairs, scene
    /// obstacles, padding, and for a robot with meshes the collision model
    /// ([`CollisionKind`]). Commands print it once on stderr.
    pub fn summary(&self) -> String {
        let pad = if self.settings.link_padding.is_empty() {
            format!("padding {} m", self.settings.padding)
        } else {
            format!(
                "padding {} m ({} links padded otherwise)",
                self.settings.padding,
                self.settings.link_padding.len()
            )
        };
        let meshes = if self.n_meshes == 0 {
            String::new()
        } else {
            let how = match self.settings.kind {
                CollisionKind::Hull => "checked exactly".to_string(),
                CollisionKind::Primitives => format!(
                    "checked as their fitted capsules (largest gap {:.3} m)",
                    self.largest_gap()
                ),
                CollisionKind::PrimitivesThenHull => {
                    "checked exactly where their fitted capsules touch".to_string()
                }
            };
            format!("; collision_model {}: mesh hulls {how}", self.settings.kind)
        };
        format!(
            "collision: {} robot bodies ({} primitives, {} mesh convex hulls), {} self-collision body pairs, {} scene obstacles, {pad}{meshes}",
            self.bodies.len(),
            self.bodies.len() - self.n_meshes,
            self.n_meshes,
            self.self_pairs.len(),
            self.obstacles.len()
        )
    }

    /// The links of robot bodies `i` and `j`.
    fn body_links(&self, i: usize, j: usize) -> (usize, usize) {
        let link = |b: &Body| match b.owner {
            Owner::Link(l) => l,
            Owner::Obstacle(_) => unreachable!("robot bodies are link bodies"),
        };
        (link(&self.bodies[i]), link(&self.bodies[j]))
    }

    /// The body pairs checked for self-collision, as link indices.
    pub fn self_pair_links(&self) -> Vec<(usize, usize)> {
        self.self_pairs
            .iter()
            .map(|&(i, j)| self.body_links(i as usize, j as usize))
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
        for ((b, p), fixed) in self
            .bodies
            .iter()
            .zip(ws.posed.iter_mut())
            .zip(&self.constant_posed)
        {
            match (fixed, b.owner) {
                (Some(f), _) => *p = *f,
                (None, Owner::Link(l)) => b.pose(&ws.frames[l], p),
                (None, Owner::Obstacle(_)) => {}
            }
        }
    }

    /// The posed frames of every link after [`CollisionModel::update`].
    pub fn link_frames<'w>(&self, ws: &'w CollisionWorkspace) -> &'w [Frame] {
        &ws.frames
    }

    /// Run a visitor over one walk and return what it kept.
    fn run<V: Visit + Default>(walk: impl FnOnce(&mut V) -> ControlFlow<()>) -> V {
        let mut v = V::default();
        let _ = walk(&mut v);
        v
    }

    /// First self-collision at the posed configuration, if any.
    pub fn self_collision(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        Self::run(|v: &mut FirstHit| self.walk_self(ws, v)).0
    }

    /// Every link pair in self-collision at the posed configuration (link indices, each pair
    /// once, in walk order).
    pub fn self_collisions(&self, ws: &CollisionWorkspace) -> Vec<(usize, usize)> {
        let all = Self::run(|v: &mut AllHits| self.walk_self(ws, v)).0;
        let mut out: Vec<(usize, usize)> = Vec::new();
        for c in all {
            if let (BodyRef::Link(a), BodyRef::Link(b)) = (c.a, c.b) {
                if !out.contains(&(a, b)) {
                    out.push((a, b));
                }
            }
        }
        out
    }

    /// First robot–obstacle collision at the posed configuration, if any.
    pub fn scene_collision(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        Self::run(|v: &mut FirstHit| self.walk_scene(ws, v)).0
    }

    /// First rod collision (against robot bodies, and obstacles if asked), if any.
    pub fn rod_collision(&self, ws: &CollisionWorkspace, rod: &RodGeometry<'_>) -> Option<Contact> {
        Self::run(|v: &mut FirstHit| self.walk_rod(ws, rod, v)).0
    }

    /// Pose at `q` and report the first collision (self, scene, rod), if any.
    pub fn check(
        &self,
        q: &[Real],
        ws: &mut CollisionWorkspace,
        rod: Option<&RodGeometry<'_>>,
    ) -> Option<Contact> {
        self.update(q, ws);
        Self::run(|v: &mut FirstHit| self.walk_all(ws, rod, v)).0
    }

    /// Pose at `q`; the smallest distance over every checked pair (self, scene, rod) and that
    /// pair (the first such pair in walk order). `None` if nothing is checked.
    pub fn clearance(
        &self,
        q: &[Real],
        ws: &mut CollisionWorkspace,
        rod: Option<&RodGeometry<'_>>,
    ) -> Option<Contact> {
        self.update(q, ws);
        Self::run(|v: &mut Nearest| self.walk_all(ws, rod, v)).0
    }

    /// Smallest self-collision distance at the posed configuration and its pair.
    pub fn self_clearance(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        Self::run(|v: &mut Nearest| self.walk_self(ws, v)).0
    }

    /// Smallest robot–obstacle distance at the posed configuration and its pair.
    pub fn scene_clearance(&self, ws: &CollisionWorkspace) -> Option<Contact> {
        Self::run(|v: &mut Nearest| self.walk_scene(ws, v)).0
    }

    /// Smallest rod distance (to the robot, and the obstacles if asked) and its pair.
    pub fn rod_clearance(&self, ws: &CollisionWorkspace, rod: &RodGeometry<'_>) -> Option<Contact> {
        Self::run(|v: &mut Nearest| self.walk_rod(ws, rod, v)).0
    }

    /// Reference check by parry alone: every self pair through `query::intersection_test` on
    /// parry shapes posed from the link frames (no bounding balls, no swept-sphere shortcut).
    /// For tests.
    pub fn self_collision_parry(&self, ws: &CollisionWorkspace) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for &(i, j) in &self.self_pairs {
            let (i, j) = (i as usize, j as usize);
            let (li, lj) = self.body_links(i, j);
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            let pi = ws.frames[li].mul(&bi.local).to_iso();
            let pj = ws.frames[lj].mul(&bj.local).to_iso();
            let pad = bi.pad + bj.pad;
            let hit = if pad > 0.0 {
                query::distance(&pi, bi.parry.as_ref(), &pj, bj.parry.as_ref()).unwrap_or(0.0)
                    <= pad
            } else {
                query::intersection_test(&pi, bi.parry.as_ref(), &pj, bj.parry.as_ref())
                    .unwrap_or(true)
            };
            if hit {
                out.push((li, lj));
            }
        }
        out
    }
}
