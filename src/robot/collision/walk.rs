//! The one walk over the checked pairs, shared by the boolean checks and the clearances.
//!
//! Order (it decides which contact a first-hit query reports): self pairs in
//! [`CollisionModel`]'s pair order; then for each obstacle, every robot body; then for each rod
//! segment (outside the ignored ends, clamp first), every robot body and, if asked, every
//! obstacle. A [`Visit`] sees each pair once and may stop the walk: [`FirstHit`] stops at the
//! first intersecting pair, [`Nearest`] keeps the first pair of smallest distance. A boolean
//! visitor ([`Visit::SKIP_DISJOINT`]) is not shown the pairs whose bounding balls are disjoint:
//! the walk tests the balls itself (most pairs of an arm's configuration are far apart), so the
//! pair test is called only for the others.

use super::narrow::{distance, intersects, Part};
use super::{BodyRef, CollisionModel, CollisionWorkspace, Contact, RodGeometry};
use crate::math::{Real, Vec3};
use std::ops::ControlFlow;

/// What a walk does with each pair.
pub(super) trait Visit {
    /// Whether the walk may skip pairs whose bounding balls are disjoint (a boolean test: such
    /// a pair never intersects). Distance queries see every pair.
    const SKIP_DISJOINT: bool = false;
    /// One pair: parties `a`, `b` and their posed parts.
    fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()>;
}

/// Stops at the first intersecting pair.
#[derive(Debug, Default)]
pub(super) struct FirstHit(pub(super) Option<Contact>);

impl Visit for FirstHit {
    const SKIP_DISJOINT: bool = true;

    #[inline]
    fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()> {
        if intersects(x, y) {
            self.0 = Some(Contact {
                a,
                b,
                distance: 0.0,
            });
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// Keeps every intersecting pair.
#[derive(Debug, Default)]
pub(super) struct AllHits(pub(super) Vec<Contact>);

impl Visit for AllHits {
    const SKIP_DISJOINT: bool = true;

    fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()> {
        if intersects(x, y) {
            self.0.push(Contact {
                a,
                b,
                distance: 0.0,
            });
        }
        ControlFlow::Continue(())
    }
}

/// Keeps the first pair of smallest distance.
#[derive(Debug, Default)]
pub(super) struct Nearest(pub(super) Option<Contact>);

impl Visit for Nearest {
    fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()> {
        let d = distance(x, y);
        if self.0.is_none_or(|c| d < c.distance) {
            self.0 = Some(Contact { a, b, distance: d });
        }
        ControlFlow::Continue(())
    }
}

/// Rod segments per bounding-ball chunk of [`CollisionModel::walk_rod`].
const ROD_CHUNK: usize = 6;

/// Slack added to a chunk's bounding-ball radius (m) so that rounding never makes the chunk test
/// stricter than the per-pair test it stands for; not a tolerance of any result.
const CHUNK_SLACK: Real = 1e-9;

/// The rod segments checked: `(index, start, end)`, skipping those within the ignored arc
/// lengths of either end.
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

/// The rod's checked segments and their chunk balls ([`CollisionModel::walk_rod`]), kept in the
/// workspace and rebuilt only when the rod changes (its nodes, radius or ignored ends): the
/// planners check many configurations against one rod. Pose-independent.
#[derive(Clone, Debug, Default)]
pub(super) struct RodChunks {
    /// The rod they were built for: nodes, radius, ignored arc lengths (clamp, tool).
    nodes: Vec<Vec3>,
    params: [Real; 3],
    built: bool,
    /// Checked segments `(index, start, end)` in walk order.
    segments: Vec<(usize, Vec3, Vec3)>,
    /// Per chunk of `ROD_CHUNK` consecutive checked segments: the centre and radius of a ball
    /// holding the chunk's segment balls, and the end of the chunk in `segments`.
    balls: Vec<(Vec3, Real, usize)>,
}

impl RodChunks {
    /// Whether built for `rod`.
    fn holds(&self, rod: &RodGeometry<'_>) -> bool {
        let params = [rod.radius, rod.ignore_near_clamp, rod.ignore_near_tool];
        self.built && self.params == params && self.nodes.as_slice() == rod.nodes
    }

    /// Build for `rod` (no allocation once the buffers have grown to the rod's size).
    fn build(&mut self, rod: &RodGeometry<'_>) {
        let params = [rod.radius, rod.ignore_near_clamp, rod.ignore_near_tool];
        self.nodes.clear();
        self.nodes.extend_from_slice(rod.nodes);
        self.params = params;
        self.segments.clear();
        self.segments.extend(rod_segments(rod));
        self.balls.clear();
        for (k, chunk) in self.segments.chunks(ROD_CHUNK).enumerate() {
            // Centre of the end points' box, radius covering every segment ball (centre at the
            // midpoint, radius r + half the length), plus a rounding slack.
            let (mut lo, mut hi) = (chunk[0].1, chunk[0].1);
            for &(_, a, b) in chunk {
                lo = lo.inf(&a.inf(&b));
                hi = hi.sup(&a.sup(&b));
            }
            let c = 0.5 * (lo + hi);
            let r = chunk
                .iter()
                .map(|&(_, a, b)| (0.5 * (a + b) - c).norm() + 0.5 * (b - a).norm())
                .fold(0.0, Real::max)
                + rod.radius
                + CHUNK_SLACK;
            self.balls.push((c, r, k * ROD_CHUNK + chunk.len()));
        }
        self.built = true;
    }
}

/// The chunks of the last two rods checked: a search step checks a configuration against the
/// rod of its slice and the segment to it against the neighbouring slice's, so one entry would
/// be rebuilt at every step.
#[derive(Clone, Debug, Default)]
pub(super) struct RodCache {
    entries: [RodChunks; 2],
    /// The entry used last.
    last: usize,
}

impl RodCache {
    /// The chunks of `rod`, built into the entry used less recently unless one holds it.
    fn get(&mut self, rod: &RodGeometry<'_>) -> &RodChunks {
        let k = if self.entries[self.last].holds(rod) {
            self.last
        } else if self.entries[1 - self.last].holds(rod) {
            1 - self.last
        } else {
            let k = 1 - self.last;
            self.entries[k].build(rod);
            k
        };
        self.last = k;
        &self.entries[k]
    }
}

impl CollisionModel {
    /// Self pairs.
    pub(super) fn walk_self<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        v: &mut V,
    ) -> ControlFlow<()> {
        for &(i, j) in &self.self_pairs {
            let (i, j) = (i as usize, j as usize);
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            if V::SKIP_DISJOINT {
                // Disjoint bounding balls: the test `intersects` makes first, without the call.
                let r = bi.radius + bj.radius;
                if (ws.posed[i].center - ws.posed[j].center).norm_squared() > r * r {
                    continue;
                }
            }
            v.visit(
                bi.owner.body_ref(),
                &Part::Body(bi, &ws.posed[i]),
                bj.owner.body_ref(),
                &Part::Body(bj, &ws.posed[j]),
            )?;
        }
        ControlFlow::Continue(())
    }

    /// Robot–obstacle pairs.
    pub(super) fn walk_scene<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        v: &mut V,
    ) -> ControlFlow<()> {
        for (o, op) in self.obstacles.iter().zip(&self.obstacle_posed) {
            let y = Part::Body(o, op);
            for (b, p) in self.bodies.iter().zip(&ws.posed) {
                if V::SKIP_DISJOINT {
                    let r = b.radius + o.radius;
                    if (p.center - op.center).norm_squared() > r * r {
                        continue;
                    }
                }
                v.visit(
                    b.owner.body_ref(),
                    &Part::Body(b, p),
                    o.owner.body_ref(),
                    &y,
                )?;
            }
        }
        ControlFlow::Continue(())
    }

    /// Rod-segment pairs (robot bodies, then obstacles if the rod asks for them).
    ///
    /// For a visitor that skips disjoint pairs ([`Visit::SKIP_DISJOINT`]) the segments are taken
    /// `ROD_CHUNK` at a time: a ball holding the chunk's segment balls is tested against each
    /// body's ball once, and the chunk's segments meet only the bodies it overlaps. Skipped
    /// pairs have disjoint balls, which [`intersects`] rejects first, and the visiting order of
    /// the others is unchanged, so the first hit is the same.
    pub(super) fn walk_rod<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        rod: &RodGeometry<'_>,
        v: &mut V,
    ) -> ControlFlow<()> {
        if !V::SKIP_DISJOINT || self.bodies.len() > u64::BITS as usize {
            for (i, a, b) in rod_segments(rod) {
                self.visit_segment(ws, rod, v, i, a, b, u64::MAX)?;
            }
            return ControlFlow::Continue(());
        }
        let mut cache = ws.rod.borrow_mut();
        let prep = cache.get(rod);
        let mut first = 0;
        for &(c, r, end) in &prep.balls {
            let mut mask = 0u64;
            for (k, (bd, p)) in self.bodies.iter().zip(&ws.posed).enumerate() {
                let (cb, rb) = Part::Body(bd, p).bound();
                if (cb - c).norm_squared() <= (r + rb) * (r + rb) {
                    mask |= 1 << k;
                }
            }
            for &(i, a, b) in &prep.segments[first..end] {
                self.visit_segment(ws, rod, v, i, a, b, mask)?;
            }
            first = end;
        }
        ControlFlow::Continue(())
    }

    /// One rod segment against the robot bodies selected by `mask` (bit k: body k; `u64::MAX`:
    /// every body, however many) and, if the rod asks for them, every obstacle.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn visit_segment<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        rod: &RodGeometry<'_>,
        v: &mut V,
        i: usize,
        a: Vec3,
        b: Vec3,
        mask: u64,
    ) -> ControlFlow<()> {
        let x = Part::Segment(a, b, rod.radius);
        if mask == u64::MAX {
            for (bd, p) in self.bodies.iter().zip(&ws.posed) {
                v.visit(BodyRef::Rod(i), &x, bd.owner.body_ref(), &Part::Body(bd, p))?;
            }
        } else {
            // The set bits in increasing order: the bodies' order.
            let mut m = mask;
            while m != 0 {
                let k = m.trailing_zeros() as usize;
                m &= m - 1;
                let (bd, p) = (&self.bodies[k], &ws.posed[k]);
                v.visit(BodyRef::Rod(i), &x, bd.owner.body_ref(), &Part::Body(bd, p))?;
            }
        }
        if rod.against_scene {
            for (o, op) in self.obstacles.iter().zip(&self.obstacle_posed) {
                v.visit(BodyRef::Rod(i), &x, o.owner.body_ref(), &Part::Body(o, op))?;
            }
        }
        ControlFlow::Continue(())
    }

    /// Every pair: self, scene, then rod (if given).
    pub(super) fn walk_all<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        rod: Option<&RodGeometry<'_>>,
        v: &mut V,
    ) -> ControlFlow<()> {
        self.walk_self(ws, v)?;
        self.walk_scene(ws, v)?;
        match rod {
            Some(r) => self.walk_rod(ws, r, v),
            None => ControlFlow::Continue(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::RobotModel;

    /// [`FirstHit`] without the chunk culling: every pair is tested.
    #[derive(Debug, Default)]
    struct FirstHitEveryPair(FirstHit);

    impl Visit for FirstHitEveryPair {
        fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()> {
            self.0.visit(a, x, b, y)
        }
    }

    /// Every pair a walk visits (parties and bounding balls), never stopping.
    #[derive(Debug, Default, PartialEq)]
    struct Record<const SKIP: bool>(Vec<(BodyRef, BodyRef, Vec3, Real, Vec3, Real)>);

    impl<const SKIP: bool> Visit for Record<SKIP> {
        const SKIP_DISJOINT: bool = SKIP;
        fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()> {
            let ((cx, rx), (cy, ry)) = (x.bound(), y.bound());
            self.0.push((a, b, cx, rx, cy, ry));
            ControlFlow::Continue(())
        }
    }

    /// The culled rod walk reports exactly the first hit of the walk over every pair: random
    /// configurations within the limits, rods of 24 segments from a point near a random link
    /// to the tool (so some hit and some miss).
    #[test]
    fn culled_rod_walk_reports_the_same_first_hit() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        let (lo, hi) = (m.lower(), m.upper());
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as Real / (1u64 << 53) as Real
        };
        let (mut hits, mut misses, mut skipped) = (0, 0, 0usize);
        for _ in 0..400 {
            let q: Vec<Real> = (0..7)
                .map(|j| lo[j] + uniform() * (hi[j] - lo[j]))
                .collect();
            cm.update(&q, &mut ws);
            let frames = cm.link_frames(&ws);
            let link = (uniform() * frames.len() as Real) as usize % frames.len();
            let off = Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 0.4;
            let start = frames[link].transform_point(&Vec3::zeros()) + off;
            let end = m.tool_pose(&q).unwrap().pos;
            let bulge = Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 0.6;
            let nodes: Vec<Vec3> = (0..=24)
                .map(|i| {
                    let t = i as Real / 24.0;
                    start + (end - start) * t + bulge * (4.0 * t * (1.0 - t))
                })
                .collect();
            let rod = RodGeometry {
                nodes: &nodes,
                radius: 0.004,
                ignore_near_clamp: 0.0,
                ignore_near_tool: 0.05,
                against_scene: false,
            };
            let culled = CollisionModel::run(|v: &mut FirstHit| cm.walk_rod(&ws, &rod, v)).0;
            let every = CollisionModel::run(|v: &mut FirstHitEveryPair| cm.walk_rod(&ws, &rod, v))
                .0
                 .0;
            assert_eq!(culled, every, "q = {q:?}");
            // Every pair the culled walk skips has disjoint bounding balls (the culling's
            // claim), and the pairs it visits keep their order.
            let all = CollisionModel::run(|v: &mut Record<false>| cm.walk_rod(&ws, &rod, v)).0;
            let kept = CollisionModel::run(|v: &mut Record<true>| cm.walk_rod(&ws, &rod, v)).0;
            let mut k = 0;
            for p in &all {
                if kept.get(k) == Some(p) {
                    k += 1;
                    continue;
                }
                let (cx, rx, cy, ry) = (p.2, p.3, p.4, p.5);
                assert!(
                    (cx - cy).norm_squared() > (rx + ry) * (rx + ry),
                    "skipped a pair with overlapping balls: {:?}–{:?}, q = {q:?}",
                    p.0,
                    p.1
                );
                skipped += 1;
            }
            assert_eq!(k, kept.len(), "the culled walk visited pairs out of order");
            if culled.is_some() {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits >= 40 && misses >= 40, "hits {hits}, misses {misses}");
        assert!(skipped > 0, "nothing culled");
    }

    /// The workspace's rod chunks follow the rod: one buffer rewritten in place between checks
    /// with the same ignored ends, the same nodes with other ignored ends, and rods coming back
    /// after one or two others (the cache's other entry, and its eviction) report the hits of a
    /// fresh workspace (the chunks built anew), over rods some of which hit.
    #[test]
    fn rod_chunks_follow_the_rod() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        let q = [0.0, -0.6, 0.0, 1.2, 0.0, 0.9, 0.0];
        cm.update(&q, &mut ws);
        let mut fresh = cm.workspace();
        cm.update(&q, &mut fresh);
        let tool = m.tool_pose(&q).unwrap().pos;
        let frames = cm.link_frames(&ws).to_vec();
        let mut nodes = vec![Vec3::zeros(); 25];
        let (mut hits, mut misses) = (0, 0);
        // Per rod, whether it hits with each ignored tool end.
        let mut by_end = [[false; 3]; 100];
        let mut check = |k: usize, near_tool: Real, nodes: &mut Vec<Vec3>| {
            // From a clamp point around the tool to the tool, through (odd k) or beside (even
            // k) a wrist link's origin at 80 % of the way (a quadratic Bézier), written into the
            // same buffer: the ignored tool end decides whether the wrist pass is checked.
            let th = 2.399_963 * k as Real;
            let far = tool + Vec3::new(th.cos(), th.sin(), 0.3 * (0.7 * th).sin()) * 0.7;
            let n_links = frames.len();
            let wrist = frames[n_links - 2 - k % 3].pos
                + if k % 2 == 0 {
                    Vec3::new(0.0, 0.0, 0.25)
                } else {
                    Vec3::zeros()
                };
            let c = (wrist - far * 0.04 - tool * 0.64) / 0.32;
            for (i, n) in nodes.iter_mut().enumerate() {
                let t = i as Real / 24.0;
                *n = far * ((1.0 - t) * (1.0 - t)) + c * (2.0 * t * (1.0 - t)) + tool * (t * t);
            }
            let rod = RodGeometry {
                nodes,
                radius: 0.004,
                ignore_near_clamp: 0.0,
                ignore_near_tool: near_tool,
                against_scene: false,
            };
            let kept = CollisionModel::run(|v: &mut FirstHit| cm.walk_rod(&ws, &rod, v)).0;
            *fresh.rod.borrow_mut() = RodCache::default();
            let anew = CollisionModel::run(|v: &mut FirstHit| cm.walk_rod(&fresh, &rod, v)).0;
            assert_eq!(kept, anew, "rod {k}, ignore_near_tool {near_tool}");
            by_end[k][usize::from(near_tool > 0.1) + usize::from(near_tool > 0.3)] = kept.is_some();
            if kept.is_some() {
                hits += 1;
            } else {
                misses += 1;
            }
        };
        // The nodes change, the ignored ends stay.
        for near_tool in [0.05, 0.2, 0.4] {
            for k in 0..100 {
                check(k, near_tool, &mut nodes);
            }
        }
        // The ignored ends change, the nodes stay.
        for k in 0..100 {
            for near_tool in [0.05, 0.2, 0.4] {
                check(k, near_tool, &mut nodes);
            }
        }
        // Rods coming back: after one other rod (held by the other entry), after two (evicted).
        for k in 0..100 {
            let (a, b) = ((k + 37) % 100, (k + 71) % 100);
            for (j, near_tool) in [
                (k, 0.05),
                (a, 0.05),
                (k, 0.05),
                (b, 0.2),
                (a, 0.05),
                (k, 0.4),
            ] {
                check(j, near_tool, &mut nodes);
            }
        }
        assert!(hits >= 30 && misses >= 30, "hits {hits}, misses {misses}");
        // The ignored end decides some rods (so stale chunks would show).
        let decided = by_end.iter().filter(|h| h[0] != h[2]).count();
        assert!(decided >= 10, "{decided} rods depend on the ignored end");
    }
}
