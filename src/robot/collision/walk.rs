//! The one walk over the checked pairs, shared by the boolean checks and the clearances.
//!
//! Order (it decides which contact a first-hit query reports): self pairs in
//! [`CollisionModel`]'s pair order; then for each obstacle, every robot body; then for each rod
//! segment (outside the ignored ends, clamp first), every robot body and, if asked, every
//! obstacle. A [`Visit`] sees each pair once and may stop the walk: [`FirstHit`] stops at the
//! first intersecting pair, [`Nearest`] keeps the first pair of smallest distance.

use super::narrow::{distance, intersects, Part};
use super::{BodyRef, CollisionModel, CollisionWorkspace, Contact, RodGeometry};
use crate::math::{Real, Vec3};
use std::ops::ControlFlow;

/// What a walk does with each pair.
pub(super) trait Visit {
    /// One pair: parties `a`, `b` and their posed parts.
    fn visit(&mut self, a: BodyRef, x: &Part<'_>, b: BodyRef, y: &Part<'_>) -> ControlFlow<()>;
}

/// Stops at the first intersecting pair.
#[derive(Debug, Default)]
pub(super) struct FirstHit(pub(super) Option<Contact>);

impl Visit for FirstHit {
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
    pub(super) fn walk_rod<V: Visit>(
        &self,
        ws: &CollisionWorkspace,
        rod: &RodGeometry<'_>,
        v: &mut V,
    ) -> ControlFlow<()> {
        for (i, a, b) in rod_segments(rod) {
            let x = Part::Segment(a, b, rod.radius);
            for (bd, p) in self.bodies.iter().zip(&ws.posed) {
                v.visit(BodyRef::Rod(i), &x, bd.owner.body_ref(), &Part::Body(bd, p))?;
            }
            if rod.against_scene {
                for (o, op) in self.obstacles.iter().zip(&self.obstacle_posed) {
                    v.visit(BodyRef::Rod(i), &x, o.owner.body_ref(), &Part::Body(o, op))?;
                }
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
