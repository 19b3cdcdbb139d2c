//! The rig as drawable geometry: the robot's collision primitives posed by forward kinematics,
//! the scene obstacles, the clamp, and the rod's centerline; the clearances of one
//! configuration with the points that realize them.
//!
//! # Geometry
//! Every body is one of four convex solids in the robot base frame ([`Solid`]): the URDF's
//! collision primitives, posed by the link frames of [`RobotModel::link_frames`] (the same
//! frames the collision model uses), and the rig's obstacles posed by their `xyz`/`rpy`. The
//! clamp is drawn as a 30 × 30 × 40 mm block under the clamp origin along `−d3` (a symbol: the
//! rig has no clamp geometry, and it takes no part in the clearances). Links whose name contains
//! `motor` are drawn as the motor.
//!
//! The rod is the exact helix of the row: `o_c + R_c·Rz(α)·r(s)·L` (clamp pose `R_c`, `o_c`,
//! azimuth α, `r` the nondimensional centerline of [`Helix::position`]), sampled at
//! [`ROD_DRAW_EDGES`] edges for drawing.
//!
//! # Clearances
//! The distances and the pairs come from the collision model ([`CollisionModel`]: the pairs it
//! checks, the bodies as it poses them): self (arm against arm, filtered pairs), scene (arm
//! against obstacles) and rod–arm (the rod as `rod_capsules` capsules of the rod's radius, the
//! last `rod_end_exclusion` metres at the tool skipped, as the planner checks it, without the
//! planner's safety inflation `rod_clearance`). The points drawn for a pair are the closest
//! points between the drawn solids of its two bodies (parry's `query::contact`, world frame);
//! their distance equals the collision model's (tested).

use crate::error::Result;
use crate::helix::Helix;
use crate::math::{rot_z, Iso3, Mat3, Real, Vec3};
use crate::planning::rig::Rig;
use crate::robot::collision::{BodyRef, Contact, RodGeometry};
use crate::robot::{CollisionModel, Frame, RobotModel, Shape};
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, Shape as ParryShape};

/// Edges of the drawn rod centerline.
pub const ROD_DRAW_EDGES: usize = 96;

/// What a body belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// A robot link (index into [`RobotModel::links`]).
    Link(usize),
    /// A scene obstacle (index into the rig's obstacles).
    Obstacle(usize),
    /// The clamp symbol.
    Clamp,
}

/// A convex solid in the robot base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Solid {
    /// Ball.
    Sphere {
        /// Centre (m).
        center: Vec3,
        /// Radius (m).
        radius: Real,
    },
    /// Points within `radius` of the segment `a`–`b`.
    Capsule {
        /// First end of the axis (m).
        a: Vec3,
        /// Second end of the axis (m).
        b: Vec3,
        /// Radius (m).
        radius: Real,
    },
    /// Cylinder along the local z axis of `pose`, centred at its origin.
    Cylinder {
        /// Pose in the base frame.
        pose: Frame,
        /// Radius (m).
        radius: Real,
        /// Half length (m).
        half_length: Real,
    },
    /// Box centred at the origin of `pose`.
    Box {
        /// Pose in the base frame.
        pose: Frame,
        /// Half extents (m).
        half_extents: Vec3,
    },
}

/// Points per circle when outlines are sampled.
const CIRCLE: usize = 20;

impl Solid {
    /// `shape` placed by `pose` (base frame).
    pub fn posed(shape: &Shape, pose: &Frame) -> Solid {
        match *shape {
            Shape::Sphere { radius } => Solid::Sphere {
                center: pose.pos,
                radius,
            },
            Shape::Capsule {
                radius,
                half_length,
            } => Solid::Capsule {
                a: pose.transform_point(&Vec3::new(0.0, 0.0, -half_length)),
                b: pose.transform_point(&Vec3::new(0.0, 0.0, half_length)),
                radius,
            },
            Shape::Cylinder {
                radius,
                half_length,
            } => Solid::Cylinder {
                pose: *pose,
                radius,
                half_length,
            },
            Shape::Box { half_extents } => Solid::Box {
                pose: *pose,
                half_extents,
            },
        }
    }

    /// Centre of the solid (m).
    pub fn center(&self) -> Vec3 {
        match self {
            Solid::Sphere { center, .. } => *center,
            Solid::Capsule { a, b, .. } => 0.5 * (a + b),
            Solid::Cylinder { pose, .. } | Solid::Box { pose, .. } => pose.pos,
        }
    }

    /// Append to `out` screen points (metres) whose convex hull is the solid's outline in
    /// `view` (exact for boxes; circles sampled at 20 points, inscribed).
    pub fn outline_points(&self, view: super::View, out: &mut Vec<[Real; 2]>) {
        let circle2 = |c: [Real; 2], r: Real, out: &mut Vec<[Real; 2]>| {
            for k in 0..CIRCLE {
                let (s, co) = (std::f64::consts::TAU * k as Real / CIRCLE as Real).sin_cos();
                out.push([c[0] + r * co, c[1] + r * s]);
            }
        };
        match self {
            Solid::Sphere { center, radius } => circle2(view.project(center), *radius, out),
            Solid::Capsule { a, b, radius } => {
                circle2(view.project(a), *radius, out);
                circle2(view.project(b), *radius, out);
            }
            Solid::Cylinder {
                pose,
                radius,
                half_length,
            } => {
                for z in [-*half_length, *half_length] {
                    for k in 0..CIRCLE {
                        let (s, c) = (std::f64::consts::TAU * k as Real / CIRCLE as Real).sin_cos();
                        let p = pose.transform_point(&Vec3::new(radius * c, radius * s, z));
                        out.push(view.project(&p));
                    }
                }
            }
            Solid::Box { pose, half_extents } => {
                for k in 0..8 {
                    let sx = if k & 1 == 0 { -1.0 } else { 1.0 };
                    let sy = if k & 2 == 0 { -1.0 } else { 1.0 };
                    let sz = if k & 4 == 0 { -1.0 } else { 1.0 };
                    let p = pose.transform_point(&Vec3::new(
                        sx * half_extents.x,
                        sy * half_extents.y,
                        sz * half_extents.z,
                    ));
                    out.push(view.project(&p));
                }
            }
        }
    }

    /// The solid as a parry shape and its pose.
    fn parry(&self) -> (Box<dyn ParryShape>, Iso3) {
        match *self {
            Solid::Sphere { center, radius } => (
                Box::new(Ball::new(radius)),
                Iso3::translation(center.x, center.y, center.z),
            ),
            Solid::Capsule { a, b, radius } => (
                Box::new(Capsule::new(a.into(), b.into(), radius)),
                Iso3::identity(),
            ),
            Solid::Cylinder {
                pose,
                radius,
                half_length,
            } => {
                // parry cylinders are along y: turn y onto z.
                let y_to_z = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
                (
                    Box::new(Cylinder::new(half_length, radius)),
                    Frame::new(pose.rot * y_to_z, pose.pos).to_iso(),
                )
            }
            Solid::Box { pose, half_extents } => {
                (Box::new(Cuboid::new(half_extents)), pose.to_iso())
            }
        }
    }
}

/// The closest points between two solids and their distance (negative when they overlap:
/// the penetration depth). `None` when parry cannot answer for the pair.
pub fn closest_points(s1: &Solid, s2: &Solid) -> Option<(Vec3, Vec3, Real)> {
    let (g1, p1) = s1.parry();
    let (g2, p2) = s2.parry();
    // Separated: parry's closest points (exact; `contact` with a large prediction is not, for
    // box pairs). Overlapping: the contact points (distance = −penetration).
    match query::closest_points(&p1, g1.as_ref(), &p2, g2.as_ref(), 1e3).ok()? {
        query::ClosestPoints::WithinMargin(a, b) => Some((a.coords, b.coords, (a - b).norm())),
        query::ClosestPoints::Intersecting => {
            let c = query::contact(&p1, g1.as_ref(), &p2, g2.as_ref(), 0.0).ok()??;
            Some((c.point1.coords, c.point2.coords, c.dist.min(0.0)))
        }
        query::ClosestPoints::Disjoint => None,
    }
}

/// One body of a snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// What it belongs to.
    pub part: Part,
    /// Its solid (base frame).
    pub solid: Solid,
}

/// The kind of a clearance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClearanceKind {
    /// Arm against arm.
    SelfCollision,
    /// Arm against a scene obstacle.
    Scene,
    /// Rod against arm.
    RodArm,
}

impl ClearanceKind {
    /// Every kind, in report order.
    pub const ALL: [ClearanceKind; 3] = [
        ClearanceKind::SelfCollision,
        ClearanceKind::Scene,
        ClearanceKind::RodArm,
    ];

    /// Short name: `self`, `scene`, `rod-arm`.
    pub fn as_str(&self) -> &'static str {
        match self {
            ClearanceKind::SelfCollision => "self",
            ClearanceKind::Scene => "scene",
            ClearanceKind::RodArm => "rod-arm",
        }
    }
}

/// The smallest clearance of one kind and the pair realizing it.
#[derive(Debug, Clone, PartialEq)]
pub struct Clearance {
    /// Which kind.
    pub kind: ClearanceKind,
    /// Name of the first body (link name, obstacle name or `rod s=…`).
    pub a: String,
    /// Name of the second body.
    pub b: String,
    /// The collision model's distance (m; 0 when touching or overlapping).
    pub distance: Real,
    /// Closest point on the first body (base frame).
    pub point_a: Vec3,
    /// Closest point on the second body (base frame).
    pub point_b: Vec3,
}

/// One configuration to draw: joints, helix, azimuth.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// Joint angles (rad), one per joint of the robot.
    pub q: Vec<Real>,
    /// The rod's helix (κ, τ, ω) (nondimensional).
    pub kto: [Real; 3],
    /// Helix azimuth α (rad) about the clamp tangent.
    pub azimuth: Real,
}

/// Everything drawn for one configuration.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// The configuration.
    pub config: Configuration,
    /// Posed bodies: links (topological order), obstacles, clamp.
    pub bodies: Vec<Body>,
    /// The rod centerline, clamp first ([`ROD_DRAW_EDGES`] edges, base frame).
    pub rod: Vec<Vec3>,
    /// The tool frame's origin (the arm's rod end, by FK).
    pub tool: Vec3,
    /// Smallest clearance of each kind (absent when the kind has no pair, e.g. no obstacles).
    pub clearances: Vec<Clearance>,
    /// Title lines drawn above the frame.
    pub title: Vec<String>,
}

impl Snapshot {
    /// The clearance of `kind`, if any.
    pub fn clearance(&self, kind: ClearanceKind) -> Option<&Clearance> {
        self.clearances.iter().find(|c| c.kind == kind)
    }
}

/// A rig ready to draw: its robot model, collision model and static bodies. Immutable, `Sync`.
#[derive(Debug, Clone)]
pub struct Scene {
    rig: Rig,
    model: RobotModel,
    collision: CollisionModel,
    statics: Vec<Body>,
    motor: Vec<bool>,
}

impl Scene {
    /// Load the rig's robot and build the collision model of robot + scene. Errors name the rig.
    pub fn new(rig: &Rig) -> Result<Scene> {
        let model = rig.robot.load_model(&rig.source)?;
        let collision = rig
            .robot
            .collision_model(&model, &rig.obstacles, &rig.source)?;
        let mut statics = Vec::new();
        for (k, o) in rig.obstacles.iter().enumerate() {
            let pose = Frame::from_xyz_rpy(o.pose.xyz, o.pose.rpy);
            let solid = Solid::posed(&o.shape, &pose);
            statics.push(Body {
                part: Part::Obstacle(k),
                solid,
            });
        }
        let rc = rig.clamp_rotation();
        let oc = rig.clamp.translation.vector;
        statics.push(Body {
            part: Part::Clamp,
            solid: Solid::Box {
                pose: Frame::new(rc, oc - 0.02 * rc.column(2)),
                half_extents: Vec3::new(0.015, 0.015, 0.02),
            },
        });
        let motor = model
            .links()
            .iter()
            .map(|l| l.name.contains("motor"))
            .collect();
        Ok(Scene {
            rig: rig.clone(),
            model,
            collision,
            statics,
            motor,
        })
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The collision model (robot + the rig's obstacles).
    pub fn collision(&self) -> &CollisionModel {
        &self.collision
    }

    /// Whether link `i` is part of the motor (its name contains `motor`).
    pub fn is_motor(&self, i: usize) -> bool {
        self.motor.get(i).copied().unwrap_or(false)
    }

    /// A readable name of a part.
    pub fn part_name(&self, p: Part) -> String {
        match p {
            Part::Link(i) => self.model.links()[i].name.clone(),
            Part::Obstacle(k) => self.rig.obstacles[k].name.clone(),
            Part::Clamp => "clamp".into(),
        }
    }

    /// The rod centerline of `kto` at `azimuth` with `n_edges` edges, base frame, clamp first.
    pub fn rod_nodes(&self, kto: [Real; 3], azimuth: Real, n_edges: usize) -> Result<Vec<Vec3>> {
        let h = Helix::new(kto[0], kto[1], kto[2])?;
        let rc = self.rig.clamp_rotation() * rot_z(azimuth);
        let oc = self.rig.clamp.translation.vector;
        let l = self.rig.rod.length;
        let n = n_edges.max(1);
        Ok((0..=n)
            .map(|i| oc + rc * (h.position(i as Real / n as Real) * l))
            .collect())
    }

    /// Pose everything at `config`, compute the clearances and their points. Errors on a joint
    /// vector of the wrong length or with non-finite values, and on an invalid helix.
    ///
    /// ```
    /// use helixreach::plot::render::{Configuration, Scene, ClearanceKind};
    /// let rig = helixreach::planning::rig::Rig::load("sawyer-seed").unwrap();
    /// let scene = Scene::new(&rig).unwrap();
    /// let q = vec![0.0; 7];
    /// let snap = scene.snapshot(&Configuration { q, kto: [0.0; 3], azimuth: 0.0 }).unwrap();
    /// let c = snap.clearance(ClearanceKind::Scene).unwrap();
    /// assert_eq!(c.b, "table");
    /// // The drawn points are exact closest points: never farther apart than the model says.
    /// assert!((c.point_a - c.point_b).norm() <= c.distance + 1e-6);
    /// ```
    pub fn snapshot(&self, config: &Configuration) -> Result<Snapshot> {
        let frames = self.model.link_frames(&config.q)?;
        crate::error::require_finite("azimuth", config.azimuth)?;
        let mut bodies = Vec::new();
        for (i, (l, f)) in self.model.links().iter().zip(&frames).enumerate() {
            for c in &l.collision {
                bodies.push(Body {
                    part: Part::Link(i),
                    solid: Solid::posed(&c.shape, &f.mul(&c.origin)),
                });
            }
        }
        bodies.extend_from_slice(&self.statics);
        let rod = self.rod_nodes(config.kto, config.azimuth, ROD_DRAW_EDGES)?;
        let tool = frames[self.model.tip_index()]
            .mul(&Frame::from_iso(&self.rig.tool))
            .pos;

        // Clearances from the collision model, the rod as the planner checks it.
        let n_caps = self.rig.planner.rod_capsules.max(1);
        let rod_caps = self.rod_nodes(config.kto, config.azimuth, n_caps)?;
        let geo = RodGeometry {
            nodes: &rod_caps,
            radius: self.rig.rod.radius,
            ignore_near_tool: self.rig.planner.rod_end_exclusion,
            ignore_near_clamp: 0.0,
            against_scene: false,
        };
        let mut ws = self.collision.workspace();
        self.collision.update(&config.q, &mut ws);
        let found = [
            (
                ClearanceKind::SelfCollision,
                self.collision.self_clearance(&ws),
            ),
            (ClearanceKind::Scene, self.collision.scene_clearance(&ws)),
            (
                ClearanceKind::RodArm,
                self.collision.rod_clearance(&ws, &geo),
            ),
        ];
        let mut clearances = Vec::new();
        for (kind, c) in found {
            if let Some(c) = c {
                clearances.push(self.witness(kind, &c, &bodies, &rod_caps));
            }
        }
        Ok(Snapshot {
            config: config.clone(),
            bodies,
            rod,
            tool,
            clearances,
            title: Vec::new(),
        })
    }

    fn solids_of(&self, r: BodyRef, bodies: &[Body], rod: &[Vec3]) -> Vec<Solid> {
        match r {
            BodyRef::Link(i) => bodies
                .iter()
                .filter(|b| b.part == Part::Link(i))
                .map(|b| b.solid)
                .collect(),
            BodyRef::Obstacle(k) => bodies
                .iter()
                .filter(|b| b.part == Part::Obstacle(k))
                .map(|b| b.solid)
                .collect(),
            BodyRef::Rod(i) if i + 1 < rod.len() => vec![Solid::Capsule {
                a: rod[i],
                b: rod[i + 1],
                radius: self.rig.rod.radius,
            }],
            BodyRef::Rod(_) => Vec::new(),
        }
    }

    fn ref_name(&self, r: BodyRef, n_rod_edges: usize) -> String {
        match r {
            BodyRef::Link(i) => self.model.links()[i].name.clone(),
            BodyRef::Obstacle(k) => self.rig.obstacles[k].name.clone(),
            BodyRef::Rod(i) => format!("rod s={:.2}L", (i as Real + 0.5) / n_rod_edges as Real),
        }
    }

    /// The closest points of the pair `c` over the drawn solids of its two bodies.
    fn witness(
        &self,
        kind: ClearanceKind,
        c: &Contact,
        bodies: &[Body],
        rod: &[Vec3],
    ) -> Clearance {
        let sa = self.solids_of(c.a, bodies, rod);
        let sb = self.solids_of(c.b, bodies, rod);
        let mut best: Option<(Vec3, Vec3, Real)> = None;
        for x in &sa {
            for y in &sb {
                if let Some(w) = closest_points(x, y) {
                    if best.is_none_or(|b| w.2 < b.2) {
                        best = Some(w);
                    }
                }
            }
        }
        let (pa, pb) = match best {
            Some((pa, pb, _)) => (pa, pb),
            // parry had no answer for any pair: mark the centres.
            None => (
                sa.first().map_or(Vec3::zeros(), Solid::center),
                sb.first().map_or(Vec3::zeros(), Solid::center),
            ),
        };
        let n = rod.len().saturating_sub(1).max(1);
        Clearance {
            kind,
            a: self.ref_name(c.a, n),
            b: self.ref_name(c.b, n),
            distance: c.distance,
            point_a: pa,
            point_b: pb,
        }
    }
}
