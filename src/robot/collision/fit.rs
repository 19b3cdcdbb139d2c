//! A capsule fitted around a convex hull: the fast primitive layer of mesh collision.
//!
//! # Contract
//! [`fit_capsule`] returns a capsule (the points within `radius` of the segment `a`–`b`) that
//! **contains every point it is given** — the hull's vertices and the mesh's vertices — and so,
//! a capsule being convex, the whole convex hull. Containment does not depend on the fit's
//! quality: whatever segment the search ends on, the radius is then set to the largest distance
//! from any given point to that segment (plus [`ROUNDING_SLACK`]). A pair of capsules that do
//! not touch therefore proves that the hulls inside do not touch.
//!
//! # The fit
//! The search minimises the capsule's volume `π r² L + 4/3 π r³`:
//! - **axis**: the best of the three principal axes of the hull's vertices (the eigenvectors of
//!   their covariance), refined by a pattern search over directions (tilts of 0.2 rad halved
//!   down to 2e-3 rad);
//! - **axis line**: through the centre of the smallest circle enclosing the vertices projected
//!   on the plane normal to the axis (Welzl, deterministic order), so the radius is as small as
//!   that axis allows;
//! - **segment and radius**: for a radius `r`, the shortest segment on that line within `r` of
//!   every vertex runs from `max_i (s_i − √(r² − ρ_i²))` back to `min_i (s_i + √(r² − ρ_i²))`
//!   (`s_i` the vertex's position along the axis, `ρ_i` its distance from the line); the volume
//!   is minimised over `r` by a 24-point scan and a golden-section refinement.
//!
//! Cost: O(n) per evaluated axis (n hull vertices), one to two hundred axes, plus the gap below
//! (a few thousand point–hull distances): tens of milliseconds for a hull of a thousand
//! vertices, paid once when the mesh is loaded.
//!
//! # The gap
//! [`FittedCapsule::gap`] is the largest distance from a point of the capsule to the hull (the
//! Hausdorff distance between the two, as the hull lies inside the capsule): how far the
//! primitive layer may report a contact that the hull does not have. It is computed, not
//! estimated, to within [`FittedCapsule::gap_resolution`]:
//! - the distance to a convex set is a convex function, so its largest value over the capsule
//!   (a convex set) is reached at an extreme point, and every extreme point lies on one of the
//!   two spheres of radius `r` around the segment's ends;
//! - each sphere is the radial image of a cube around its centre `e`, cut into square cells. A
//!   cell's image is the part of the sphere inside the cone from `e` over the cell (cube edges
//!   map to great circles), so it lies in the frustum of that cone between the planes
//!   `x·w = r·min_k(c_k·w)` and `x·w = r` (`w` the direction of the cell's centre, `c_k` of its
//!   corners). The frustum is convex, so the distance to the hull over it is largest at one of
//!   its eight vertices: that maximum bounds the cell from above, and it exceeds the values at
//!   the corners (points of the sphere) by at most `r (1/cos θ − 1) ≈ r θ²/2` for a cell of
//!   angular half-diagonal `θ`;
//! - branch and bound over the cells (largest bound first, each split in four) keeps the largest
//!   value reached on the spheres (`gap`, a lower bound) and stops when no cell's bound exceeds
//!   it by more than [`GAP_TOLERANCE`] (or after [`GAP_MAX_CELLS`] cells): the true gap lies in
//!   `[gap, gap + gap_resolution]`.
//!
//! Padding grows the capsule's radius and the hull by the same amount; the padded capsule still
//! contains the padded hull and its gap is at most the unpadded one.

use crate::math::{Mat3, Real, Vec3};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::ConvexPolyhedron;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Added to the fitted radius (m) so that rounding in the posing of the segment and of the hull
/// never puts a hull vertex outside the capsule; not a tolerance of any result.
pub const ROUNDING_SLACK: Real = 1e-12;

/// The gap search stops when every unexplored cell's bound is within this of the best value
/// found (m).
pub const GAP_TOLERANCE: Real = 5e-4;

/// At most this many cells are evaluated per sphere by the gap search (bounds its cost; the
/// stated resolution says how far it got).
pub const GAP_MAX_CELLS: usize = 20_000;

/// A capsule around a convex hull (in the hull's frame) and how loosely it fits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FittedCapsule {
    /// One end of the segment.
    pub a: Vec3,
    /// The other end of the segment (equal to `a` for a sphere).
    pub b: Vec3,
    /// Radius (m): every given point is within it of the segment `a`–`b`.
    pub radius: Real,
    /// Largest distance from a point of the capsule to the hull found (m; ≥ 0). The true
    /// largest distance lies in `[gap, gap + gap_resolution]` (module docs).
    pub gap: Real,
    /// Upper bound on how much the true largest gap may exceed `gap` (m).
    pub gap_resolution: Real,
}

impl FittedCapsule {
    /// Half the segment's length (m).
    pub fn half_length(&self) -> Real {
        0.5 * (self.b - self.a).norm()
    }

    /// The capsule's volume (m³).
    pub fn volume(&self) -> Real {
        let r = self.radius;
        std::f64::consts::PI * r * r * (2.0 * self.half_length() + 4.0 / 3.0 * r)
    }

    /// Distance from `p` to the segment (m): `p` is inside when it is at most `radius`.
    pub fn axis_distance(&self, p: &Vec3) -> Real {
        point_segment_distance(p, &self.a, &self.b)
    }
}

/// Distance from `p` to the segment `a`–`b` (a point when `a = b`).
pub fn point_segment_distance(p: &Vec3, a: &Vec3, b: &Vec3) -> Real {
    let d = b - a;
    let l2 = d.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).norm()
}

/// Fit a capsule around `hull` (its vertices `hull_points`) that also contains every point of
/// `extra` (the mesh's vertices: the hull's construction may drop points within its own
/// tolerance), and state its gap (module docs). `hull_points` must not be empty.
pub fn fit_capsule(hull: &ConvexPolyhedron, hull_points: &[Vec3], extra: &[Vec3]) -> FittedCapsule {
    let (a, b) = fit_segment(hull_points);
    let radius = hull_points
        .iter()
        .chain(extra)
        .map(|p| point_segment_distance(p, &a, &b))
        .fold(0.0, Real::max)
        + ROUNDING_SLACK;
    let (gap, gap_resolution) = largest_gap(hull, &a, &b, radius);
    FittedCapsule {
        a,
        b,
        radius,
        gap,
        gap_resolution,
    }
}

/// The segment of the smallest-volume capsule found around `pts` (module docs).
fn fit_segment(pts: &[Vec3]) -> (Vec3, Vec3) {
    let n = pts.len() as Real;
    let c = pts.iter().sum::<Vec3>() / n;
    let mut cov = Mat3::zeros();
    for p in pts {
        let d = p - c;
        cov += d * d.transpose();
    }
    let eig = cov.symmetric_eigen();
    let mut scratch = Scratch::default();
    // The best principal axis, then refined.
    let mut best: Option<(Vec3, Axis)> = None;
    for k in 0..3 {
        let d0 = eig.eigenvectors.column(k).into_owned();
        let d0 = if d0.norm() > 0.0 && d0.iter().all(|x| x.is_finite()) {
            d0.normalize()
        } else {
            Vec3::new(
                Real::from(u8::from(k == 0)),
                Real::from(u8::from(k == 1)),
                Real::from(u8::from(k == 2)),
            )
        };
        let ax = capsule_along(pts, &d0, &mut scratch);
        if best.as_ref().is_none_or(|(_, b)| ax.volume < b.volume) {
            best = Some((d0, ax));
        }
    }
    let (d0, start) = best.expect("three axes tried");
    let ax = refine_axis(pts, d0, start, &mut scratch);
    (ax.a, ax.b)
}

/// Buffers reused across axis evaluations.
#[derive(Default)]
struct Scratch {
    /// Projections on the plane normal to the axis.
    plane: Vec<[Real; 2]>,
    /// Positions along the axis and distances from the axis line.
    along: Vec<(Real, Real)>,
}

/// The best capsule with a given axis direction.
#[derive(Clone, Copy, Debug)]
struct Axis {
    volume: Real,
    a: Vec3,
    b: Vec3,
}

/// Pattern search over directions from `d0`.
fn refine_axis(pts: &[Vec3], d0: Vec3, start: Axis, s: &mut Scratch) -> Axis {
    let mut d = d0;
    let mut cur = start;
    let mut step: Real = 0.2;
    while step > 2e-3 {
        let (u, v) = basis(&d);
        let t = step.tan();
        let mut improved = false;
        for dir in [u, -u, v, -v, u + v, u - v, -u + v, -u - v] {
            let cand = (d + dir * t).normalize();
            let x = capsule_along(pts, &cand, s);
            if x.volume < cur.volume * (1.0 - 1e-12) {
                cur = x;
                d = cand;
                improved = true;
                break;
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    cur
}

/// Two unit vectors completing `d` (unit) to an orthonormal basis.
fn basis(d: &Vec3) -> (Vec3, Vec3) {
    let helper = if d.x.abs() < 0.6 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = d.cross(&helper).normalize();
    (u, d.cross(&u))
}

/// The smallest-volume capsule with axis direction `d` found (module docs).
fn capsule_along(pts: &[Vec3], d: &Vec3, s: &mut Scratch) -> Axis {
    let (u, v) = basis(d);
    s.plane.clear();
    s.plane.extend(pts.iter().map(|p| [p.dot(&u), p.dot(&v)]));
    let (cx, cy) = enclosing_circle(&s.plane);
    s.along.clear();
    let mut rho_max: Real = 0.0;
    let (mut smin, mut smax) = (Real::MAX, Real::MIN);
    for (p, q) in pts.iter().zip(&s.plane) {
        let rho = ((q[0] - cx).powi(2) + (q[1] - cy).powi(2)).sqrt();
        let t = p.dot(d);
        rho_max = rho_max.max(rho);
        smin = smin.min(t);
        smax = smax.max(t);
        s.along.push((t, rho));
    }
    let h = 0.5 * (smax - smin);
    let (r_lo, r_hi) = (rho_max, (h * h + rho_max * rho_max).sqrt());
    // The segment [t0, t1] for radius r, and the capsule's volume.
    let at = |r: Real| -> (Real, Real, Real) {
        let (mut t1, mut t0) = (Real::MIN, Real::MAX);
        for &(t, rho) in &s.along {
            let w = (r * r - rho * rho).max(0.0).sqrt();
            t1 = t1.max(t - w);
            t0 = t0.min(t + w);
        }
        let (lo, hi) = if t0 <= t1 {
            (t0, t1)
        } else {
            let m = 0.5 * (t0 + t1);
            (m, m)
        };
        let vol = std::f64::consts::PI * r * r * ((hi - lo) + 4.0 / 3.0 * r);
        (vol, lo, hi)
    };
    const SCAN: usize = 24;
    let r_of = |k: usize| r_lo + (r_hi - r_lo) * k as Real / SCAN as Real;
    let mut best_k = 0;
    let mut best_v = Real::MAX;
    for k in 0..=SCAN {
        let (v, _, _) = at(r_of(k));
        if v < best_v {
            best_v = v;
            best_k = k;
        }
    }
    // Golden section on the bracket around the best scanned radius.
    let (mut lo, mut hi) = (r_of(best_k.saturating_sub(1)), r_of((best_k + 1).min(SCAN)));
    let g = 0.5 * (5.0_f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (at(x1).0, at(x2).0);
    for _ in 0..24 {
        if f1 < f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = at(x1).0;
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = at(x2).0;
        }
    }
    let r = if f1 < best_v.min(f2) {
        x1
    } else if f2 < best_v {
        x2
    } else {
        r_of(best_k)
    };
    let (volume, t0, t1) = at(r);
    let base = u * cx + v * cy;
    Axis {
        volume,
        a: base + d * t0,
        b: base + d * t1,
    }
}

/// Centre of the smallest circle enclosing `pts` (Welzl's incremental algorithm, points taken
/// in a fixed pseudo-random order). Only the quality of the fit depends on it.
fn enclosing_circle(pts: &[[Real; 2]]) -> (Real, Real) {
    let n = pts.len();
    if n == 0 {
        return (0.0, 0.0);
    }
    // A fixed permutation (xorshift): expected linear time, deterministic.
    let mut order: Vec<usize> = (0..n).collect();
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    for i in (1..n).rev() {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        order.swap(i, (seed % (i as u64 + 1)) as usize);
    }
    let p = |i: usize| pts[order[i]];
    let inside = |c: (Real, Real, Real), q: [Real; 2]| {
        (q[0] - c.0).powi(2) + (q[1] - c.1).powi(2) <= c.2 * (1.0 + 1e-12) + 1e-30
    };
    // Circles as (cx, cy, r²).
    let two = |a: [Real; 2], b: [Real; 2]| {
        let c = (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]));
        (c.0, c.1, (a[0] - c.0).powi(2) + (a[1] - c.1).powi(2))
    };
    let three = |a: [Real; 2], b: [Real; 2], c: [Real; 2]| {
        let (bx, by) = (b[0] - a[0], b[1] - a[1]);
        let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
        let det = 2.0 * (bx * cy - by * cx);
        let scale = (bx * bx + by * by).max(cx * cx + cy * cy);
        if det.abs() <= 1e-12 * scale {
            // Collinear: the circle on the farthest pair.
            let cands = [two(a, b), two(a, c), two(b, c)];
            return cands
                .into_iter()
                .max_by(|x, y| x.2.total_cmp(&y.2))
                .expect("three candidates");
        }
        let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
        let ux = (cy * b2 - by * c2) / det;
        let uy = (bx * c2 - cx * b2) / det;
        (a[0] + ux, a[1] + uy, ux * ux + uy * uy)
    };
    let mut c = (p(0)[0], p(0)[1], 0.0);
    for i in 1..n {
        if inside(c, p(i)) {
            continue;
        }
        c = (p(i)[0], p(i)[1], 0.0);
        for j in 0..i {
            if inside(c, p(j)) {
                continue;
            }
            c = two(p(i), p(j));
            for k in 0..j {
                if !inside(c, p(k)) {
                    c = three(p(i), p(j), p(k));
                }
            }
        }
    }
    (c.0, c.1)
}

/// A cell of the gap search: a square on a cube face and its bound.
#[derive(Clone, Copy, Debug)]
struct Cell {
    /// Upper bound of the distance to the hull over the cell's image on the sphere.
    bound: Real,
    /// Sphere (0: around `a`, 1: around `b`), cube face (0..6), lower corner (face coordinates
    /// in [-1, 1]) and side (face coordinates).
    sphere: u8,
    face: u8,
    u: Real,
    v: Real,
    side: Real,
}

impl PartialEq for Cell {
    fn eq(&self, o: &Cell) -> bool {
        self.bound.total_cmp(&o.bound) == Ordering::Equal
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, o: &Cell) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cell {
    fn cmp(&self, o: &Cell) -> Ordering {
        self.bound.total_cmp(&o.bound)
    }
}

/// The unit direction of cube face `face` at face coordinates `(u, v)` (cube of half-side 1).
fn cube_dir(face: u8, u: Real, v: Real) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, u, v),
        1 => Vec3::new(-1.0, u, v),
        2 => Vec3::new(u, 1.0, v),
        3 => Vec3::new(u, -1.0, v),
        4 => Vec3::new(u, v, 1.0),
        _ => Vec3::new(u, v, -1.0),
    }
    .normalize()
}

/// The largest distance from the capsule (`a`, `b`, `r`) to `hull`, and the resolution (module
/// docs).
fn largest_gap(hull: &ConvexPolyhedron, a: &Vec3, b: &Vec3, r: Real) -> (Real, Real) {
    let ends = [*a, *b];
    let f = |x: Vec3| hull.distance_to_local_point(&x.into(), true);
    let mut best: Real = 0.0;
    // Evaluate a cell: the values at its corners and centre on the sphere (attained: they raise
    // `best`), and the bound over its frustum's eight vertices (module docs).
    let eval = |best: &mut Real, sphere: u8, face: u8, u: Real, v: Real, side: Real| -> Cell {
        let e = ends[sphere as usize];
        let w = cube_dir(face, u + 0.5 * side, v + 0.5 * side);
        let corners = [
            cube_dir(face, u, v),
            cube_dir(face, u + side, v),
            cube_dir(face, u, v + side),
            cube_dir(face, u + side, v + side),
        ];
        *best = best.max(f(e + w * r));
        let near = corners.iter().map(|c| c.dot(&w)).fold(Real::MAX, Real::min);
        let mut bound: Real = 0.0;
        for c in &corners {
            *best = best.max(f(e + c * r));
            let cw = c.dot(&w);
            bound = bound
                .max(f(e + c * (r / cw)))
                .max(f(e + c * (r * near / cw)));
        }
        Cell {
            bound,
            sphere,
            face,
            u,
            v,
            side,
        }
    };
    let mut heap = BinaryHeap::new();
    let spheres: &[u8] = if (b - a).norm() > 0.0 { &[0, 1] } else { &[0] };
    const START: usize = 2;
    let side = 2.0 / START as Real;
    for &sphere in spheres {
        for face in 0..6u8 {
            for i in 0..START {
                for j in 0..START {
                    let (u, v) = (-1.0 + side * i as Real, -1.0 + side * j as Real);
                    heap.push(eval(&mut best, sphere, face, u, v, side));
                }
            }
        }
    }
    let mut cells = heap.len();
    while let Some(c) = heap.peek().copied() {
        if c.bound <= best + GAP_TOLERANCE || cells + 4 > GAP_MAX_CELLS {
            break;
        }
        heap.pop();
        let h = 0.5 * c.side;
        for (du, dv) in [(0.0, 0.0), (0.0, h), (h, 0.0), (h, h)] {
            heap.push(eval(&mut best, c.sphere, c.face, c.u + du, c.v + dv, h));
            cells += 1;
        }
    }
    let top = heap.peek().map_or(best, |c| c.bound);
    (best, (top - best).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hull_of(pts: &[Vec3]) -> (ConvexPolyhedron, Vec<Vec3>) {
        let p: Vec<_> = pts.iter().map(|v| (*v).into()).collect();
        let h = ConvexPolyhedron::from_convex_hull(&p).unwrap();
        let hp = h.points().iter().map(|p| p.coords).collect();
        (h, hp)
    }

    /// A fine polyhedral capsule (segment along a tilted axis): the fit recovers its segment and
    /// radius closely, and the gap is small (the polyhedron is inscribed in the true capsule).
    #[test]
    fn recovers_a_capsule_from_its_polyhedral_approximation() {
        let (r, half) = (0.05, 0.12);
        let axis = Vec3::new(1.0, 2.0, 0.5).normalize();
        let (u, v) = basis(&axis);
        let c = Vec3::new(0.3, -0.1, 0.2);
        let mut pts = Vec::new();
        // Rings on the cylinder and on the two caps.
        for k in 0..48 {
            let phi = k as Real / 48.0 * std::f64::consts::TAU;
            let rad = u * phi.cos() + v * phi.sin();
            for s in [-half, 0.0, half] {
                pts.push(c + axis * s + rad * r);
            }
            for m in 1..8 {
                let th = m as Real / 8.0 * std::f64::consts::FRAC_PI_2;
                for (sgn, s) in [(1.0, half), (-1.0, -half)] {
                    pts.push(c + axis * (s + sgn * r * th.sin()) + rad * (r * th.cos()));
                }
            }
        }
        pts.push(c + axis * (half + r));
        pts.push(c - axis * (half + r));
        let (h, hp) = hull_of(&pts);
        let f = fit_capsule(&h, &hp, &pts);
        assert!((f.radius - r).abs() < 2e-3, "{f:?}");
        assert!((f.half_length() - half).abs() < 4e-3, "{f:?}");
        assert!(
            f.gap < 3e-3 && f.gap_resolution <= GAP_TOLERANCE + 1e-15,
            "{f:?}"
        );
        for p in &pts {
            assert!(f.axis_distance(p) <= f.radius);
        }
    }

    /// A box of half-extents (0.3, 0.05, 0.05): the capsule's axis is x, and the stated gap
    /// agrees with a brute force over 2 × 80,000 points of the end spheres (where the largest
    /// distance lies) measured to the box by clamping: at most `gap + gap_resolution`, at least
    /// `gap − 1 mm` (the points are at most 1.1 mm apart on spheres of radius ≈ 0.07 m).
    #[test]
    fn box_gap_matches_brute_force() {
        let e = Vec3::new(0.3, 0.05, 0.05);
        let pts: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { -e.x } else { e.x },
                    if i & 2 == 0 { -e.y } else { e.y },
                    if i & 4 == 0 { -e.z } else { e.z },
                )
            })
            .collect();
        let (h, hp) = hull_of(&pts);
        let f = fit_capsule(&h, &hp, &pts);
        let dir = (f.b - f.a).normalize();
        assert!(dir.x.abs() > 0.999, "{f:?}");
        let mut worst: Real = 0.0;
        for i in 0..=200 {
            for j in 0..=400 {
                let th = std::f64::consts::PI * i as Real / 200.0;
                let ph = std::f64::consts::TAU * j as Real / 400.0;
                let n = Vec3::new(th.cos(), th.sin() * ph.cos(), th.sin() * ph.sin());
                for end in [f.a, f.b] {
                    let x = end + n * f.radius;
                    let q = Vec3::new(
                        x.x.clamp(-e.x, e.x),
                        x.y.clamp(-e.y, e.y),
                        x.z.clamp(-e.z, e.z),
                    );
                    worst = worst.max((x - q).norm());
                }
            }
        }
        assert!(
            worst <= f.gap + f.gap_resolution + 1e-12 && worst >= f.gap - 1e-3,
            "brute {worst} vs gap {} ± {}",
            f.gap,
            f.gap_resolution
        );
    }
}
