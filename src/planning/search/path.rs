//! Path extraction: the chain of accepted edges from a start to a node, as planned points with
//! their phases.
//!
//! The chain runs from a start configuration (the last one at slice 0 before the first load
//! step: the arm reaches any valid start before the rod is clamped) through load (`load`),
//! inside-slice (`reconfigure`) and back-off (`backoff`) edges; a bridged edge
//! ([`super::linking::Proposal::Bridged`]) adds its intermediate poses as points of its phase.
//! A walk step inside a slice (each sub-step of a chained walk) is resampled
//! ([`self_motion::refine`]) so that the rod end stays within
//! [`self_motion::HOLD_TOLERANCE`] on every joint-linear chord, and every resampled point and
//! chord is checked again against the held rod; a roll step (roll `motor`) is one chord, or
//! the chain of its sub-rolls, of at most `ROLL_STEP` of arm roll in all, which the motor
//! compensates (each point with its own motor angle).

use super::graph::{Graph, Via};
use super::linking::Linker;
use super::slices::Slices;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::planner::{node_of, PlannedPoint, Planner};
use crate::planning::self_motion::{self, Held, Q};
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

/// The path to node `end` of `graph`.
pub(crate) fn extract(
    planner: &Planner,
    slices: &Slices,
    graph: &Graph,
    linker: &mut Linker<'_>,
    end: u32,
    want_path: bool,
) -> Result<Extracted> {
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
            if want_path && walk {
                // A walk's sub-steps (a chained walk's intermediate points), each resampled.
                let mut a = pn.q;
                for b in bridge
                    .iter()
                    .map(|(_, q, _)| *q)
                    .chain(std::iter::once(n.c.q))
                {
                    for q in refine_walk(planner, slices, linker, &a, &b, n.c.slice, n.c.psi)? {
                        out.push(point(
                            slices,
                            n.c.slice,
                            &q,
                            n.c.psi,
                            dof,
                            Phase::Reconfigure,
                        ));
                    }
                    a = b;
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
    Ok(Extracted {
        points: want_path.then_some(out),
        reconfigurations: reconf,
        backoffs: back,
        cost,
        max_joint_step: max_step,
        slices: seen.len(),
    })
}

fn point(slices: &Slices, slice: u32, q: &Q, psi: Real, dof: usize, phase: Phase) -> PlannedPoint {
    PlannedPoint {
        waypoint: slices.wps[slice as usize].clone(),
        q: q[..dof].to_vec(),
        motor: slices.motor(slice as usize, psi),
        phase,
    }
}

/// The walk step a → b at the held pose of `slice`, resampled within the hold tolerance, every
/// sample and chord re-checked; the samples after `a` (the last is `b`).
fn refine_walk(
    planner: &Planner,
    slices: &Slices,
    linker: &mut Linker<'_>,
    a: &Q,
    b: &Q,
    slice: u32,
    psi: Real,
) -> Result<Vec<Q>> {
    let tip = slices.tip(planner, slice as usize, psi);
    let held = Held {
        chain: planner.model.chain(),
        solver: linker.solver(),
        tip,
        dof: planner.dof,
    };
    let fine = self_motion::refine(&held, &[*a, *b]).ok_or_else(|| {
        Error::invalid(
            "reconfiguration",
            format!("slice {slice} (s = {})", slices.wps[slice as usize].s),
            "a self-motion step could not be resampled within the hold tolerance",
        )
    })?;
    let mut prev = *a;
    for q in &fine {
        let x = super::linking::Config {
            slice,
            q: prev,
            psi,
        };
        let y = super::linking::Config { slice, q: *q, psi };
        linker.accept(&x, &y).map_err(|c| {
            Error::invalid(
                "reconfiguration",
                format!("slice {slice} (s = {})", slices.wps[slice as usize].s),
                format!("the resampled self-motion step collides ({c})"),
            )
        })?;
        prev = *q;
    }
    Ok(fine)
}
