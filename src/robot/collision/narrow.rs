//! Narrow phase: the exact test and the exact distance between two posed parts.
//!
//! A part is a collision body (a link shape posed by FK, or a scene obstacle) or a rod segment
//! (a capsule of the rod radius between two nodes). Every body has a bounding ball; a pair is
//! tested exactly only if the balls overlap. Spheres and capsules (the arms' shapes, and the rod)
//! are swept spheres — a segment and a radius — and their exact test is a segment–segment
//! distance (closed form, [`segment_distance_squared`]). Any other pair goes to parry:
//! `query::intersection_test` for the test, `query::closest_points` for the distance. A body
//! may carry a capsule that contains it (a mesh hull's fitted capsule, under
//! `primitives_then_hull`): when both parts have a containing capsule (their swept-sphere form,
//! a rod segment, or a fitted capsule), capsules that do not touch prove the pair free before
//! parry is asked, and the answer is the same as without them. A cylinder carries the capsule of
//! its axis and radius (it contains the cylinder). A box first meets a separating-axis test in
//! its own frame: the other part's containing capsule (or bounding ball) is boxed per axis in
//! the box's frame (segment ends ± radius), and if that box misses the (padded) box on one of
//! its three axes the pair is free. A cylinder whose axis capsule touches the other part's
//! capsule is decided without parry in two cases (the **cylinder phase**): the other capsule
//! lies beyond an end plane by more than its radius and the padding (free), or the other part
//! is a swept sphere whose closest point on the axis is interior to it — the two closest points
//! then differ perpendicularly to the axis, so the distance to the cylinder is the segments'
//! distance less the cylinder's radius, and the pair touches exactly when the capsules do. Only a
//! closest feature on an end disc goes to parry. A box and a part with a containing capsule
//! are decided by the segment's distance to the box (the **box phase**, closed form:
//! [`segment_box_distance_squared`]): beyond the capsule's radius and the padding the pair is
//! free; within it a swept sphere touches, and only a hull's fitted capsule goes to parry. These
//! phases never change an answer: every answer equals parry's (tests below, against parry
//! alone).

use super::BodyRef;
use crate::math::{Iso3, Mat3, Real, Vec3};
use crate::robot::kinematics::{z_to_axis, Frame};
use crate::robot::model::Shape;
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};

/// Below this squared length a segment is a point ([`segment_distance_squared`]) (m²).
const DEGENERATE_SEGMENT_SQ: Real = 1e-24;
/// Below this length a swept sphere is a ball (m).
const DEGENERATE_SEGMENT: Real = 1e-15;

/// Who a collision body belongs to, and so which frame poses it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Owner {
    /// A link (index into [`RobotModel::links`](crate::robot::RobotModel::links)), posed by FK.
    Link(usize),
    /// A scene obstacle (index into the obstacles), fixed in the robot's root frame.
    Obstacle(usize),
}

impl Owner {
    /// The party this owner is in a [`Contact`](super::Contact).
    pub(super) fn body_ref(self) -> BodyRef {
        match self {
            Owner::Link(i) => BodyRef::Link(i),
            Owner::Obstacle(k) => BodyRef::Obstacle(k),
        }
    }
}

/// A swept sphere: the points within `radius` of the segment `a`–`b`.
pub(super) type Ssv = (Vec3, Vec3, Real);

/// A collision body: one primitive of a link or one obstacle.
#[derive(Clone, Debug)]
pub(super) struct Body {
    pub(super) owner: Owner,
    /// Shape pose in the owner's frame (the link frame; the root frame for obstacles), parry
    /// convention (cylinders along y).
    pub(super) local: Frame,
    pub(super) parry: SharedShape,
    /// Swept-sphere form (segment ends in the owner's frame and radius), if any.
    pub(super) ssv: Option<Ssv>,
    /// A capsule containing the shape (owner's frame), tested before the shape: the broad
    /// phase of a mesh hull (`primitives_then_hull`).
    pub(super) fit: Option<Ssv>,
    /// Half extents of a box shape (in `local`): the separating-axis broad phase.
    pub(super) cuboid: Option<Vec3>,
    /// Radius of a cylinder shape (its axis is the `fit` segment): the cylinder phase.
    pub(super) cylinder: Option<Real>,
    /// Bounding ball: centre in the owner's frame.
    pub(super) center: Vec3,
    /// Bounding ball radius (padding included).
    pub(super) radius: Real,
    /// Padding (m): the body is the set of points within `pad` of its shape.
    pub(super) pad: Real,
}

/// A body posed in the root frame (by [`Body::pose`]).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Posed {
    /// Shape pose (set for bodies without a swept-sphere form).
    pub(super) pose: Frame,
    /// Swept-sphere segment ends (set for bodies with one, and for the containing capsule of
    /// bodies with a `fit`).
    pub(super) a: Vec3,
    pub(super) b: Vec3,
    /// Bounding-ball centre.
    pub(super) center: Vec3,
}

impl Body {
    /// `shape` at `origin` (in the owner's frame).
    pub(super) fn new(owner: Owner, shape: &Shape, origin: &Frame) -> Body {
        // parry cylinders are along y: turn y onto z.
        let y_to_z = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
        let axis = |h: Real| {
            (
                origin.transform_point(&Vec3::new(0.0, 0.0, -h)),
                origin.transform_point(&Vec3::new(0.0, 0.0, h)),
            )
        };
        let (mut fit, mut cuboid, mut cylinder) = (None, None, None);
        let (parry, local, ssv) = match *shape {
            Shape::Sphere { radius } => (
                SharedShape::new(Ball::new(radius)),
                *origin,
                Some((origin.pos, origin.pos, radius)),
            ),
            Shape::Box { half_extents } => {
                cuboid = Some(half_extents);
                (SharedShape::new(Cuboid::new(half_extents)), *origin, None)
            }
            Shape::Cylinder {
                radius,
                half_length,
            } => {
                // The capsule of the axis and the radius contains the cylinder.
                let (a, b) = axis(half_length);
                fit = Some((a, b, radius));
                cylinder = Some(radius);
                (
                    SharedShape::new(Cylinder::new(half_length, radius)),
                    Frame::new(origin.rot * y_to_z, origin.pos),
                    None,
                )
            }
            Shape::Capsule {
                radius,
                half_length,
            } => {
                let (a, b) = axis(half_length);
                (
                    SharedShape::new(Capsule::new_z(half_length, radius)),
                    *origin,
                    Some((a, b, radius)),
                )
            }
        };
        Body {
            owner,
            local,
            parry,
            ssv,
            fit,
            cuboid,
            cylinder,
            center: origin.pos,
            radius: shape.bounding_radius(),
            pad: 0.0,
        }
    }

    /// The capsule of radius `r` around the segment `a`–`b` (owner's frame).
    pub(super) fn capsule(owner: Owner, a: Vec3, b: Vec3, r: Real) -> Body {
        let len = (b - a).norm();
        let mid = 0.5 * (a + b);
        let rot = if len < DEGENERATE_SEGMENT {
            Mat3::identity()
        } else {
            z_to_axis(&((b - a) / len))
        };
        Body {
            owner,
            local: Frame::new(rot, mid),
            parry: SharedShape::new(Capsule::new_z(0.5 * len, r)),
            ssv: Some((a, b, r)),
            fit: None,
            cuboid: None,
            cylinder: None,
            center: mid,
            radius: 0.5 * len + r,
            pad: 0.0,
        }
    }

    /// The body with a containing capsule `(a, b, r)` (owner's frame) as its broad phase: the
    /// caller guarantees that the capsule contains the shape.
    pub(super) fn with_fit(mut self, fit: Ssv) -> Body {
        self.fit = Some(fit);
        self
    }

    /// A convex hull (`points` its vertices in the shape's frame, `shape` the parry polyhedron)
    /// at `origin` (in the owner's frame).
    pub(super) fn hull(owner: Owner, shape: SharedShape, points: &[Vec3], origin: &Frame) -> Body {
        let (mut lo, mut hi) = (Vec3::repeat(Real::MAX), Vec3::repeat(Real::MIN));
        for p in points {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let c = 0.5 * (lo + hi);
        let r = points.iter().map(|p| (p - c).norm()).fold(0.0, Real::max);
        Body {
            owner,
            local: *origin,
            parry: shape,
            ssv: None,
            fit: None,
            cuboid: None,
            cylinder: None,
            center: origin.transform_point(&c),
            // Rounding slack: the ball must never be tighter than the hull.
            radius: r * (1.0 + 1e-12) + 1e-12,
            pad: 0.0,
        }
    }

    /// The body grown by `pad` metres (`pad ≥ 0`).
    pub(super) fn padded(mut self, pad: Real) -> Body {
        self.pad = pad;
        self.radius += pad;
        self
    }

    /// Pose the body by its owner's frame `f` (root frame) into `p`.
    #[inline]
    pub(super) fn pose(&self, f: &Frame, p: &mut Posed) {
        p.center = f.transform_point(&self.center);
        if let Some((a, b, _)) = self.ssv {
            p.a = f.transform_point(&a);
            p.b = f.transform_point(&b);
        } else {
            p.pose = f.mul(&self.local);
            if let Some((a, b, _)) = self.fit {
                p.a = f.transform_point(&a);
                p.b = f.transform_point(&b);
            }
        }
    }

    /// The parry pose of the posed body (swept spheres are posed by their world segment).
    fn iso(&self, p: &Posed) -> Iso3 {
        match self.ssv {
            Some((a, b, _)) => {
                let len = (b - a).norm();
                if len < DEGENERATE_SEGMENT {
                    Iso3::translation(p.a.x, p.a.y, p.a.z)
                } else {
                    let z = (p.b - p.a) / len;
                    Frame::new(z_to_axis(&z), 0.5 * (p.a + p.b)).to_iso()
                }
            }
            None => p.pose.to_iso(),
        }
    }
}

/// One side of a checked pair, posed in the root frame.
#[derive(Clone, Copy, Debug)]
pub(super) enum Part<'a> {
    /// A collision body and its pose.
    Body(&'a Body, &'a Posed),
    /// A rod segment: the capsule of radius `.2` around `.0`–`.1`.
    Segment(Vec3, Vec3, Real),
}

impl Part<'_> {
    /// Padding (m; 0 for rod segments).
    #[inline]
    fn pad(&self) -> Real {
        match *self {
            Part::Body(b, _) => b.pad,
            Part::Segment(..) => 0.0,
        }
    }

    /// Bounding ball (centre, radius).
    #[inline]
    pub(super) fn bound(&self) -> (Vec3, Real) {
        match *self {
            Part::Body(b, p) => (p.center, b.radius),
            Part::Segment(a, b, r) => (0.5 * (a + b), r + 0.5 * (b - a).norm()),
        }
    }

    /// Swept-sphere form in the root frame, if any.
    #[inline]
    fn ssv(&self) -> Option<Ssv> {
        match *self {
            Part::Body(b, p) => b.ssv.map(|(_, _, r)| (p.a, p.b, r)),
            Part::Segment(a, b, r) => Some((a, b, r)),
        }
    }

    /// A capsule containing the part, in the root frame: its swept-sphere form, or the fitted
    /// capsule of a body with one.
    #[inline]
    fn capsule(&self) -> Option<Ssv> {
        match *self {
            Part::Body(b, p) => b.ssv.or(b.fit).map(|(_, _, r)| (p.a, p.b, r)),
            Part::Segment(a, b, r) => Some((a, b, r)),
        }
    }

    /// Run `f` on the parry pose and shape.
    #[inline]
    fn with_parry<R>(&self, f: impl FnOnce(&Iso3, &dyn parry3d_f64::shape::Shape) -> R) -> R {
        match *self {
            Part::Body(b, p) => f(&b.iso(p), b.parry.as_ref()),
            Part::Segment(a, b, r) => f(&Iso3::identity(), &Capsule::new(a.into(), b.into(), r)),
        }
    }
}

/// Whether two posed parts touch or overlap.
#[inline]
pub(super) fn intersects(x: &Part<'_>, y: &Part<'_>) -> bool {
    let ((cx, rx), (cy, ry)) = (x.bound(), y.bound());
    let r = rx + ry;
    if (cx - cy).norm_squared() > r * r {
        return false;
    }
    let pad = x.pad() + y.pad();
    if box_separates(x, y) || box_separates(y, x) {
        return false;
    }
    if let (Some((a1, b1, r1)), Some((a2, b2, r2))) = (x.capsule(), y.capsule()) {
        // Exact for two swept spheres; else a broad phase (the capsules contain the shapes).
        let rr = r1 + r2 + pad;
        let (sx, ty, d2) = segment_closest(&a1, &b1, &a2, &b2);
        let touch = d2 <= rr * rr;
        if !touch || (x.ssv().is_some() && y.ssv().is_some()) {
            return touch;
        }
        // The capsules touch: the cylinder phase, given the closest point's parameter on each.
        if let Some(touch) =
            cylinder_decides(x, y, pad, sx).or_else(|| cylinder_decides(y, x, pad, ty))
        {
            return touch;
        }
    }
    if let Some(touch) = box_decides(x, y, pad).or_else(|| box_decides(y, x, pad)) {
        return touch;
    }
    if pad > 0.0 {
        x.with_parry(|i1, s1| {
            y.with_parry(|i2, s2| {
                !matches!(
                    query::closest_points(i1, s1, i2, s2, pad),
                    Ok(query::ClosestPoints::Disjoint)
                )
            })
        })
    } else {
        x.with_parry(|i1, s1| {
            y.with_parry(|i2, s2| query::intersection_test(i1, s1, i2, s2).unwrap_or(true))
        })
    }
}

/// The cylinder phase (module docs), for a pair whose capsules touch: when `x` is a cylinder
/// and `y` has a containing capsule, `Some(false)` if `y`'s capsule lies beyond one of the
/// cylinder's end planes by more than its radius and the padding, `Some(true)` if `y` is a
/// swept sphere and `t`, the parameter on the cylinder's axis of the two segments' closest
/// points ([`segment_closest`]), is interior (the closest points then differ perpendicularly to
/// the axis: the segments' distance is the distance to the lateral surface plus the cylinder's
/// radius, so capsules that touch mean shapes that touch), `None` otherwise (the closest feature
/// is an end disc: parry decides). `pad` is both parts' padding.
#[inline]
fn cylinder_decides(x: &Part<'_>, y: &Part<'_>, pad: Real, t: Real) -> Option<bool> {
    let Part::Body(bx, px) = *x else {
        return None;
    };
    bx.cylinder?;
    let (a2, b2, r2) = y.capsule()?;
    let rho = r2 + pad;
    let axis = px.b - px.a;
    let len = axis.norm();
    if len < DEGENERATE_SEGMENT {
        return None;
    }
    let u = axis / len;
    let (h1, h2) = ((a2 - px.a).dot(&u), (b2 - px.a).dot(&u));
    if h1.min(h2) > len + rho || h1.max(h2) < -rho {
        return Some(false);
    }
    y.ssv()?;
    // Interior with a margin: at a clamped end the lateral-surface argument does not hold.
    const INTERIOR: Real = 1e-9;
    (t > INTERIOR && t < 1.0 - INTERIOR).then_some(true)
}

/// The box phase (module docs): when `x` is a box and `y` has a containing capsule,
/// `Some(false)` if the capsule's segment is farther from the box than its radius and the
/// padding, `Some(true)` if it is not and `y` is a swept sphere, `None` otherwise (`y` has no
/// capsule, or only contains a hull in one). `pad` is both parts' padding.
#[inline]
fn box_decides(x: &Part<'_>, y: &Part<'_>, pad: Real) -> Option<bool> {
    let Part::Body(bx, px) = *x else {
        return None;
    };
    let h = bx.cuboid?;
    let (a, b, r) = y.capsule()?;
    let rho = r + pad;
    let rt = px.pose.rot.transpose();
    let (la, lb) = (rt * (a - px.pose.pos), rt * (b - px.pose.pos));
    if segment_box_distance_squared(&la, &lb, &h) > rho * rho {
        return Some(false);
    }
    y.ssv().map(|_| true)
}

/// Squared distance between the segment `a`–`b` and the box `[−h, h]` (same frame).
///
/// The squared distance of `a + t·(b − a)` to the box is Σₖ max(0, |pₖ(t)| − hₖ)²: convex in t
/// and one quadratic between the (at most six) parameters where a coordinate crosses a face
/// plane. Each piece's minimum is in closed form; the smallest over the pieces is the distance.
/// Cost: a sort of ≤ 6 numbers and ≤ 7 quadratics.
pub(super) fn segment_box_distance_squared(a: &Vec3, b: &Vec3, h: &Vec3) -> Real {
    let d = b - a;
    let mut cuts = [0.0; 8];
    let mut n = 1;
    for k in 0..3 {
        if d[k] != 0.0 {
            for face in [-h[k], h[k]] {
                let t = (face - a[k]) / d[k];
                if t > 0.0 && t < 1.0 {
                    cuts[n] = t;
                    n += 1;
                }
            }
        }
    }
    cuts[n] = 1.0;
    n += 1;
    cuts[1..n - 1].sort_unstable_by(Real::total_cmp);
    let dist2 = |t: Real| {
        (0..3)
            .map(|k| {
                let e = (a[k] + t * d[k]).abs() - h[k];
                if e > 0.0 {
                    e * e
                } else {
                    0.0
                }
            })
            .sum::<Real>()
    };
    let mut best = dist2(0.0).min(dist2(1.0));
    for w in cuts[..n].windows(2) {
        let (t0, t1) = (w[0], w[1]);
        let mid = 0.5 * (t0 + t1);
        // The piece's quadratic: Σ over the coordinates outside the box at `mid` of
        // (aₖ ∓ hₖ + t·dₖ)².
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..3 {
            let p = a[k] + mid * d[k];
            let off = if p > h[k] {
                a[k] - h[k]
            } else if p < -h[k] {
                a[k] + h[k]
            } else {
                continue;
            };
            num += off * d[k];
            den += d[k] * d[k];
        }
        let t = if den > 0.0 {
            (-num / den).clamp(t0, t1)
        } else {
            mid
        };
        best = best.min(dist2(t));
    }
    best
}

/// Whether `x` is a box that a separating axis of its own frame parts from `y` (module docs):
/// `y`'s containing capsule, or its bounding ball, boxed in `x`'s frame, misses the box grown
/// by both paddings on one axis. `false` when `x` is not a box.
#[inline]
fn box_separates(x: &Part<'_>, y: &Part<'_>) -> bool {
    let Part::Body(bx, px) = *x else {
        return false;
    };
    let Some(h) = bx.cuboid else {
        return false;
    };
    let (a, b, r) = match y.capsule() {
        Some((a, b, r)) => (a, b, r + y.pad()),
        // The bounding ball's radius includes the padding.
        None => {
            let (c, r) = y.bound();
            (c, c, r)
        }
    };
    let rt = px.pose.rot.transpose();
    let (la, lb) = (rt * (a - px.pose.pos), rt * (b - px.pose.pos));
    (0..3).any(|k| {
        let e = h[k] + bx.pad + r;
        la[k].min(lb[k]) > e || la[k].max(lb[k]) < -e
    })
}

/// Distance between two posed parts (m; 0 when touching or overlapping).
pub(super) fn distance(x: &Part<'_>, y: &Part<'_>) -> Real {
    (shape_distance(x, y) - x.pad() - y.pad()).max(0.0)
}

/// Distance between the unpadded shapes.
fn shape_distance(x: &Part<'_>, y: &Part<'_>) -> Real {
    match (x.ssv(), y.ssv()) {
        (Some((a1, b1, r1)), Some((a2, b2, r2))) => {
            (segment_distance_squared(&a1, &b1, &a2, &b2).sqrt() - r1 - r2).max(0.0)
        }
        // Through parry's closest points, not `query::distance`: in parry 0.25 the
        // cuboid–cuboid `distance` overestimates the gap when the closest features are edges
        // (dimforge/parry#431; pedestal feet to the seed table: 0.2093 m for a true 0.1978 m),
        // while `closest_points` has an exact cuboid–cuboid case.
        _ => x.with_parry(|i1, s1| {
            y.with_parry(
                |i2, s2| match query::closest_points(i1, s1, i2, s2, Real::MAX) {
                    Ok(query::ClosestPoints::WithinMargin(a, b)) => (a - b).norm(),
                    Ok(query::ClosestPoints::Intersecting) => 0.0,
                    _ => query::distance(i1, s1, i2, s2).unwrap_or(0.0),
                },
            )
        }),
    }
}

/// Squared distance between segments `p1q1` and `p2q2` (closest points, clamped; robust for
/// degenerate segments).
#[inline]
pub fn segment_distance_squared(p1: &Vec3, q1: &Vec3, p2: &Vec3, q2: &Vec3) -> Real {
    segment_closest(p1, q1, p2, q2).2
}

/// Closest points of segments `p1q1` and `p2q2`: `(s, t, d²)` with the points `p1 + s·(q1 − p1)`
/// and `p2 + t·(q2 − p2)`, s, t ∈ [0, 1] (Ericson, *Real-Time Collision Detection*, 5.1.9). When
/// t is not clamped to 0 or 1 it is the projection's parameter of the first point on the
/// second segment's line.
#[inline]
fn segment_closest(p1: &Vec3, q1: &Vec3, p2: &Vec3, q2: &Vec3) -> (Real, Real, Real) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    let eps = DEGENERATE_SEGMENT_SQ;
    let (s, t);
    if a <= eps && e <= eps {
        return (0.0, 0.0, r.norm_squared());
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
    (s, t, (c1 - c2).norm_squared())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn random_frame(rng: &mut impl Rng) -> Frame {
        let rot = nalgebra::Rotation3::from_euler_angles(
            rng.random_range(-3.2..3.2),
            rng.random_range(-1.6..1.6),
            rng.random_range(-3.2..3.2),
        )
        .into_inner();
        let pos = Vec3::new(
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.4..0.4),
            rng.random_range(-0.4..0.4),
        );
        Frame::new(rot, pos)
    }

    fn random_shape(rng: &mut impl Rng) -> Shape {
        let d: [Real; 3] = std::array::from_fn(|_| rng.random_range(0.005..0.3));
        match rng.random_range(0..4) {
            0 => Shape::Sphere { radius: d[0] },
            1 => Shape::Box {
                half_extents: Vec3::new(d[0], d[1], 0.2 * d[2]),
            },
            2 => Shape::Cylinder {
                radius: d[0],
                half_length: d[1],
            },
            _ => Shape::Capsule {
                radius: d[0],
                half_length: d[1],
            },
        }
    }

    /// parry alone on the parts (no broad phase): the reference of [`intersects`].
    fn parry_intersects(x: &Part<'_>, y: &Part<'_>) -> bool {
        let pad = x.pad() + y.pad();
        x.with_parry(|i1, s1| {
            y.with_parry(|i2, s2| {
                if pad > 0.0 {
                    !matches!(
                        query::closest_points(i1, s1, i2, s2, pad),
                        Ok(query::ClosestPoints::Disjoint)
                    )
                } else {
                    query::intersection_test(i1, s1, i2, s2).unwrap()
                }
            })
        })
    }

    /// The cylinder phase decides cylinder–capsule pairs near the cylinder (both answers, both
    /// of its cases) exactly as parry does: a cylinder at a random pose, capsules and rod
    /// segments placed within 0.15 m of its surface, padded and not.
    #[test]
    fn the_cylinder_phase_agrees_with_parry() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let (mut free, mut touch, mut ends) = (0, 0, 0);
        for k in 0..20_000 {
            let owner = Owner::Obstacle(0);
            let (radius, half_length) = (rng.random_range(0.01..0.2), rng.random_range(0.01..0.3));
            let cyl = Shape::Cylinder {
                radius,
                half_length,
            };
            let pad = if k % 3 == 0 {
                rng.random_range(0.0..0.03)
            } else {
                0.0
            };
            let at = random_frame(&mut rng);
            let bx = Body::new(owner, &cyl, &Frame::identity()).padded(pad);
            let mut px = Posed::default();
            bx.pose(&at, &mut px);
            // A point near the cylinder (cylinder frame), a short segment through it.
            let reach = radius + 0.15;
            let near = |rng: &mut rand_chacha::ChaCha8Rng| {
                Vec3::new(
                    rng.random_range(-reach..reach),
                    rng.random_range(-reach..reach),
                    rng.random_range(-(half_length + 0.15)..(half_length + 0.15)),
                )
            };
            let (a, b) = (near(&mut rng), near(&mut rng));
            let b = a + 0.3 * (b - a);
            let r = rng.random_range(0.002..0.05);
            let (a, b) = (at.transform_point(&a), at.transform_point(&b));
            let seg = Part::Segment(a, b, r);
            let x = Part::Body(&bx, &px);
            // How the phase decides the pair when the capsules touch (as `intersects` calls it).
            let (t, _, d2) = segment_closest(&px.a, &px.b, &a, &b);
            let rr = radius + r + pad;
            if d2 <= rr * rr {
                match cylinder_decides(&x, &seg, pad, t) {
                    Some(true) => touch += 1,
                    Some(false) => free += 1,
                    None => ends += 1,
                }
            }
            let want = parry_intersects(&x, &seg);
            assert_eq!(
                intersects(&x, &seg),
                want,
                "{k}: r {radius} h {half_length} pad {pad}"
            );
            assert_eq!(intersects(&seg, &x), want, "{k} (swapped)");
        }
        assert!(
            free > 1_000 && touch > 1_000 && ends > 1_000,
            "{free} {touch} {ends}"
        );
    }

    /// The segment–box distance against a brute-force minimum over 20,001 points of the
    /// segment (point–box distance by clamping), on segments through and around random boxes.
    #[test]
    fn segment_box_distance_matches_dense_sampling() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let (mut inside, mut outside) = (0, 0);
        for k in 0..2_000 {
            let h = Vec3::new(
                rng.random_range(0.01..0.3),
                rng.random_range(0.01..0.3),
                rng.random_range(0.001..0.3),
            );
            let mut pt = || Vec3::from_fn(|_, _| rng.random_range(-0.5..0.5));
            let (a, b) = (pt(), pt());
            // Some segments parallel to a face, some degenerate.
            let b = match k % 7 {
                0 => Vec3::new(b.x, b.y, a.z),
                1 => a,
                _ => b,
            };
            let got = segment_box_distance_squared(&a, &b, &h).sqrt();
            let brute = (0..=20_000)
                .map(|i| {
                    let p = a + (i as Real / 20_000.0) * (b - a);
                    (p - p.zip_map(&h, |v, e| v.clamp(-e, e))).norm()
                })
                .fold(Real::MAX, Real::min);
            let step = (b - a).norm() / 20_000.0;
            assert!(got <= brute + 1e-12, "{k}: {got} > {brute}");
            assert!(got >= brute - step, "{k}: {got} < {brute} − {step}");
            if got == 0.0 {
                inside += 1;
            } else {
                outside += 1;
            }
        }
        assert!(inside > 100 && outside > 1_000, "{inside} {outside}");
    }

    /// The box phase decides box–capsule pairs near the box exactly as parry does: a box at a
    /// random pose, capsules and rod segments placed within 0.15 m of it, padded and not.
    #[test]
    fn the_box_phase_agrees_with_parry() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let (mut free, mut touch) = (0, 0);
        for k in 0..20_000 {
            let owner = Owner::Obstacle(0);
            let h = Vec3::new(
                rng.random_range(0.01..0.3),
                rng.random_range(0.01..0.3),
                rng.random_range(0.002..0.3),
            );
            let pad = if k % 3 == 0 {
                rng.random_range(0.0..0.03)
            } else {
                0.0
            };
            let at = random_frame(&mut rng);
            let bx =
                Body::new(owner, &Shape::Box { half_extents: h }, &Frame::identity()).padded(pad);
            let mut px = Posed::default();
            bx.pose(&at, &mut px);
            let mut near = || Vec3::from_fn(|i, _| rng.random_range(-(h[i] + 0.15)..(h[i] + 0.15)));
            let (a, b) = (near(), near());
            let b = a + 0.3 * (b - a);
            let r = rng.random_range(0.002..0.05);
            let seg = Part::Segment(at.transform_point(&a), at.transform_point(&b), r);
            let x = Part::Body(&bx, &px);
            match box_decides(&x, &seg, pad) {
                Some(true) => touch += 1,
                Some(false) => free += 1,
                None => panic!("a swept sphere is decided"),
            }
            let want = parry_intersects(&x, &seg);
            assert_eq!(intersects(&x, &seg), want, "{k}: h {h:?} pad {pad}");
            assert_eq!(intersects(&seg, &x), want, "{k} (swapped)");
        }
        assert!(free > 2_000 && touch > 2_000, "{free} {touch}");
    }

    /// The broad phases (bounding balls, containing capsules of cylinders, the box-frame
    /// separating axes) never change an answer: random boxes, cylinders, capsules, spheres and
    /// rod segments, padded and not, against parry's exact test; both answers occur often.
    #[test]
    fn broad_phases_agree_with_parry() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let (mut hits, mut misses, mut boxed) = (0, 0, 0);
        for k in 0..20_000 {
            let owner = Owner::Obstacle(0);
            let (fx, fy) = (random_frame(&mut rng), random_frame(&mut rng));
            let (sx, sy) = (random_shape(&mut rng), random_shape(&mut rng));
            let pad = if k % 3 == 0 {
                rng.random_range(0.0..0.05)
            } else {
                0.0
            };
            let bx = Body::new(owner, &sx, &fx).padded(pad);
            let by = Body::new(owner, &sy, &fy);
            let at = random_frame(&mut rng);
            let (mut px, mut py) = (Posed::default(), Posed::default());
            bx.pose(&at, &mut px);
            by.pose(&at, &mut py);
            let x = Part::Body(&bx, &px);
            let y = if k % 5 == 0 {
                let a = random_frame(&mut rng).pos;
                Part::Segment(a, a + 0.5 * random_frame(&mut rng).pos, 0.01)
            } else {
                Part::Body(&by, &py)
            };
            boxed += usize::from(bx.cuboid.is_some() || by.cuboid.is_some());
            let want = parry_intersects(&x, &y);
            assert_eq!(intersects(&x, &y), want, "{k}: {sx:?} {sy:?} pad {pad}");
            assert_eq!(intersects(&y, &x), want, "{k} (swapped)");
            if want {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(
            hits > 2_000 && misses > 2_000 && boxed > 5_000,
            "{hits} {misses} {boxed}"
        );
    }
}
