//! Path extraction: the chain of accepted edges from a start to a node, as planned points with
//! their phases.
//!
//! The chain runs from a start configuration (the last one at slice 0 before the first load
//! step: the arm reaches any valid start before the rod is clamped) through load (`load`),
//! inside-slice (`reconfigure`) and back-off (`backoff`) edges; a bridged edge
//! ([`super::linking::Proposal::Bridged`]) adds its intermediate poses as points of its phase.
//! A walk step inside a slice (each sub-step of a chained walk) is resampled
//! ([`Linker::resample_walk`]) so that the rod end stays within
//! [`crate::planning::self_motion::HOLD_TOLERANCE`] on every joint-linear chord, and every
//! resampled point and chord is checked again against the held rod — also when the points are
//! not wanted: a path with a walk step that cannot be resampled is not returned (the search
//! then runs again with every walk step checked that way, parent module docs). A roll step
//! (roll `motor`) is one chord, or the chain of its sub-rolls, of at most `ROLL_STEP` of arm
//! roll in all, which the motor compensates (each point with its own motor angle).

use super::graph::{Graph, Via};
use super::linking::{Config, Linker};
use super::slices::Slices;
use crate::error::Result;
use crate::math::Real;
use crate::planning::planner::{node_of, PlannedPoint, Planner};
use crate::planning::self_motion::Q;
use crate::planning::trajectory::Phase;

/// An extracted path and its counts.
#[derive(Debug, Clone)]
pub(crate) struct Extracted {
    /// The points (when asked for).
    pub points: Option<Vec<PlannedPoint>>,
    /// Maximal runs of inside-slice moves after the start.
    pub reconfigurations: usize,
    /// Maximal runs of back-off moves.
    pub backoffs: usize,
    /// Edge cost of the path (the ladder's cost: weighted joint step + motor weight).
    pub cost: Real,
    /// Largest joint step (rad).
    pub max_joint_step: Real,
    /// Distinct slices on the path.
    pub slices: usize,
}

/// The path to node `end` of `graph`; `None` when a walk step on it cannot be resampled
/// within the hold tolerance ([`Linker::resample_walk`]): every walk step is resampled, also
/// when the points are not wanted.
pub(crate) fn extract(
    planner: &Planner,
    slices: &Slices,
    graph: &Graph,
    linker: &mut Linker<'_>,
    end: u32,
    want_path: bool,
) -> Result<Option<Extracted>> {
    // Start at the last slice-0 node before the first load step.
    let (chain, first) = graph.chain_to(end);
    let chain = &chain[first.saturating_sub(1)..];
    let dof = planner.dof;
    let mut out = Vec::new();
    let (mut reconf, mut back, mut cost, mut max_step) = (0, 0, 0.0, 0.0);
    let mut prev: Option<(Via, u32)> = None;
    let mut seen = std::collections::BTreeSet::new();
    for &i in chain {
        let n = &graph.nodes[i as usize];
        seen.insert(n.c.slice);
        let phase = match (prev.is_some(), n.via) {
            (false, _) | (_, Via::Load) | (_, Via::Start) => Phase::Load,
            (_, Via::Backoff) => Phase::Backoff,
            (_, Via::Reconfigure) => Phase::Reconfigure,
        };
        if let Some((pv, p)) = prev {
            let pn = &graph.nodes[p as usize].c;
            if n.via != pv {
                match n.via {
                    Via::Reconfigure => reconf += 1,
                    Via::Backoff => back += 1,
                    _ => {}
                }
            }
            // The edge's configurations: the parent, a bridge's intermediate ones, the node.
            let bridge = graph.bridges.get(&i).map_or(&[][..], Vec::as_slice);
            let mut from = node_of(&pn.q, slices.motor(pn.slice as usize, pn.psi));
            let mut from_q = pn.q;
            let ends = bridge
                .iter()
                .map(|(w, q, psi)| (*q, w.motor - psi))
                .chain(std::iter::once((
                    n.c.q,
                    slices.motor(n.c.slice as usize, n.c.psi),
                )));
            for (q, motor) in ends {
                let to = node_of(&q, motor);
                cost += planner.edge_cost(&from, &to).unwrap_or(Real::INFINITY);
                let step = (0..dof)
                    .map(|j| (q[j] - from_q[j]).abs())
                    .fold(0.0, Real::max);
                max_step = Real::max(max_step, step);
                from = to;
                from_q = q;
            }
            let walk = n.via == Via::Reconfigure && n.c.psi == pn.psi;
            if want_path && !walk {
                for (w, q, psi) in bridge {
                    out.push(PlannedPoint {
                        waypoint: w.clone(),
                        q: q[..dof].to_vec(),
                        motor: w.motor - psi,
                        phase,
                    });
                }
            }
            if walk {
                // A walk's sub-steps (a chained walk's intermediate points), each resampled.
                let mut a = Config { q: pn.q, ..n.c };
                for b in bridge
                    .iter()
                    .map(|(_, q, _)| *q)
                    .chain(std::iter::once(n.c.q))
                {
                    let Some(fine) = linker.resample_walk(&a, &b) else {
                        return Ok(None);
                    };
                    if want_path {
                        for q in fine {
                            out.push(point(
                                slices,
                                n.c.slice,
                                &q,
                                n.c.psi,
                                dof,
                                Phase::Reconfigure,
                            ));
                        }
                    }
                    a.q = b;
                }
                prev = Some((n.via, i));
                continue;
            }
        }
        if want_path {
            out.push(point(slices, n.c.slice, &n.c.q, n.c.psi, dof, phase));
        }
        prev = Some((n.via, i));
    }
    Ok(Some(Extracted {
        points: want_path.then_some(out),
        reconfigurations: reconf,
        backoffs: back,
        cost,
        max_joint_step: max_step,
        slices: seen.len(),
    }))
}

fn point(slices: &Slices, slice: u32, q: &Q, psi: Real, dof: usize, phase: Phase) -> PlannedPoint {
    PlannedPoint {
        waypoint: slices.wps[slice as usize].clone(),
        q: q[..dof].to_vec(),
        motor: slices.motor(slice as usize, psi),
        phase,
    }
}
