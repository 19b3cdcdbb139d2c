//! Self-contact of the DER rod along a motion: the DER energy has no contact term, so a rod
//! driven far from the helix (the snap, the far branch followed down in s) may pass through
//! itself — a motion the real rod cannot make. [`ContactMonitor`] watches a sequence of states
//! of one continuous motion and reports the first
//!
//! - **contact**: two edges that are not neighbours along the rod (index gap ≥
//!   [`MIN_EDGE_GAP`]) closer than the rod's diameter (segment–segment distance,
//!   [`crate::robot::collision::segment_distance_squared`]); or
//! - **crossing**: two such edges whose lines passed through each other between two observed
//!   states. For edges `p₁q₁`, `p₂q₂` (directions `d₁`, `d₂`) the signed volume
//!   `V = (d₁ × d₂)·(p₂ − p₁)` is `|d₁ × d₂|` times the signed distance of the two lines; it
//!   changes sign when the lines meet (or turn through parallel). A sign change between two
//!   states at which the closest points of the lines lie inside both edges, and at which both
//!   edges are within `2δ` of each other (δ the largest node displacement between the states:
//!   edges that met in between cannot be farther apart), is a crossing. A sign change with the
//!   closest points outside an edge is the lines meeting beyond the rod, not the rod.
//!
//! **The rig beyond the ends.** The rod's ends are held by the clamp and by the motor on the arm:
//! a loop of the rod cannot slip over an end. The DER rod is free there, so each end is
//! continued by a rigid segment of length [`END_EXTENSION`] along its end tangent (the clamp
//! body, the motor), checked like an edge: in the reports it is edge `-1` (beyond the clamp) or
//! edge `n` (beyond the held end).
//!
//! Why it matters: a crossing, or a loop slipping over an end, changes the linking number of
//! the clamped rod by ±2, so the state after it lies on an equilibrium branch the real rod
//! cannot reach (e.g. a nearly straight rod with two extra turns of twist, which the far branch
//! of a snap can follow down to s → 0). Such a branch gives no return point. A crossing faster than the observation rate with the closest
//! points leaving an edge in between can be missed: observe every time step.

use crate::math::{Real, Vec3};
use crate::robot::collision::segment_distance_squared;
use crate::rod::RodState;
use std::f64::consts::PI;

/// Edges closer than this along the rod (index difference) are neighbours and never checked.
pub const MIN_EDGE_GAP: usize = 2;
/// Length (units of L) of the rigid continuation of each end (see the module docs).
pub const END_EXTENSION: Real = 1.0;

/// What [`ContactMonitor::observe`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfContact {
    /// The two edges (indices, first < second; `-1` and `n` are the continuations beyond
    /// the clamp and the held end).
    pub edges: (isize, isize),
    /// Their distance at the observed state (units of L).
    pub distance: Real,
    /// The edges passed through each other (else: closer than the diameter).
    pub crossed: bool,
    /// Edges of the rod.
    pub n_edges: usize,
}

impl std::fmt::Display for SelfContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (i, j) = self.edges;
        let a = if i < 0 {
            "the clamp's continuation".to_string()
        } else {
            format!("edge {i}")
        };
        let b = if j as usize == self.n_edges {
            "the held end's continuation".to_string()
        } else {
            format!("edge {j}")
        };
        if self.crossed {
            write!(f, "{a} and {b} passed through each other")
        } else {
            write!(
                f,
                "{a} and {b} {:.2e} apart (closer than the rod's diameter)",
                self.distance
            )
        }
    }
}

/// Watches the states of one continuous motion of a rod of `n` edges (see the module docs).
#[derive(Debug, Clone)]
pub struct ContactMonitor {
    diameter: Real,
    nodes: Vec<Vec3>,
    prev_nodes: Vec<Vec3>,
    /// Per checked pair: the signed volume V when the lines' closest points lie inside both
    /// edges, NaN otherwise or before the first observation.
    volume: Vec<Real>,
    /// Per checked pair: the squared edge distance at the previous observation.
    dist2: Vec<Real>,
    observed: bool,
}

impl ContactMonitor {
    /// A monitor for a rod of `n_edges` edges and the given diameter (units of L).
    pub fn new(n_edges: usize, diameter: Real) -> Self {
        // Points: the clamp's continuation, the n + 1 nodes, the held end's continuation.
        let m = n_edges + 2;
        let pairs = (0..m).map(|i| m.saturating_sub(i + MIN_EDGE_GAP)).sum();
        ContactMonitor {
            diameter,
            nodes: vec![Vec3::zeros(); m + 1],
            prev_nodes: vec![Vec3::zeros(); m + 1],
            volume: vec![Real::NAN; pairs],
            dist2: vec![Real::INFINITY; pairs],
            observed: false,
        }
    }

    /// Forget the previous state (the next observation starts a new motion).
    pub fn reset(&mut self) {
        self.volume.fill(Real::NAN);
        self.dist2.fill(Real::INFINITY);
        self.observed = false;
    }

    /// Observe the next state of the motion; the first contact or crossing found (in pair
    /// order), or `None`.
    pub fn observe(&mut self, st: &RodState) -> Option<SelfContact> {
        let n = st.n_edges();
        assert_eq!(n + 3, self.nodes.len(), "monitor built for another rod");
        std::mem::swap(&mut self.nodes, &mut self.prev_nodes);
        for i in 0..=n {
            self.nodes[i + 1] = st.node(i);
        }
        let t0 = (self.nodes[2] - self.nodes[1]).normalize();
        let t1 = (self.nodes[n + 1] - self.nodes[n]).normalize();
        self.nodes[0] = self.nodes[1] - END_EXTENSION * t0;
        self.nodes[n + 2] = self.nodes[n + 1] + END_EXTENSION * t1;
        let mut delta: Real = 0.0;
        for (x, y) in self.nodes.iter().zip(&self.prev_nodes) {
            delta = delta.max((x - y).norm());
        }
        let m = n + 2;
        if !self.observed {
            delta = Real::INFINITY;
            self.observed = true;
        }
        // Edges that met between the two states are within 2δ of each other at both.
        let reach2 = 4.0 * delta * delta;
        let d2min = self.diameter * self.diameter;
        let mut found = None;
        let mut k = 0;
        for i in 0..m {
            let (p1, q1) = (self.nodes[i], self.nodes[i + 1]);
            let d1 = q1 - p1;
            for j in i + MIN_EDGE_GAP..m {
                let (p2, q2) = (self.nodes[j], self.nodes[j + 1]);
                let d2 = q2 - p2;
                let v = interior_volume(&p1, &d1, &p2, &d2);
                let dist2 = segment_distance_squared(&p1, &q1, &p2, &q2);
                let (prev, prev_d2) = (self.volume[k], self.dist2[k]);
                self.volume[k] = v;
                self.dist2[k] = dist2;
                k += 1;
                if found.is_some() {
                    continue;
                }
                let crossed = prev * v < 0.0 && prev_d2 <= reach2 && dist2 <= reach2;
                if crossed || dist2 < d2min {
                    found = Some(SelfContact {
                        edges: (i as isize - 1, j as isize - 1),
                        distance: dist2.sqrt(),
                        crossed,
                        n_edges: n,
                    });
                }
            }
        }
        found
    }
}

/// Two edges are parallel (no interior closest points) when `|d₁×d₂|² ≤ PARALLEL_EDGES·|d₁|²|d₂|²`
/// (sin² of their angle).
const PARALLEL_EDGES: Real = 1e-12;

/// `V = (d₁ × d₂)·(p₂ − p₁)` when the closest points of the two lines lie inside both edges,
/// NaN otherwise (parallel lines included).
fn interior_volume(p1: &Vec3, d1: &Vec3, p2: &Vec3, d2: &Vec3) -> Real {
    let r = p1 - p2;
    let (a, b, e) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let (c, f) = (d1.dot(&r), d2.dot(&r));
    let denom = a * e - b * b;
    if denom <= PARALLEL_EDGES * a * e {
        return Real::NAN;
    }
    let s = (b * f - c * e) / denom;
    let t = (a * f - b * c) / denom;
    if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
        d1.cross(d2).dot(&(p2 - p1))
    } else {
        Real::NAN
    }
}

/// Length (units of L) of the straight rays that continue both ends in [`linking_number`]
/// (a stand-in for rays to infinity: the writhe they miss falls off like 1/length).
pub const LINKING_RAY: Real = 1e3;

/// The linking number (turns) of the rod's material ribbon, `Lk = Tw + Wr`, with both ends
/// continued by straight rays of length [`LINKING_RAY`] along their end tangents: `Tw` is the
/// sum of the discrete twists `m_i` (material frame against the parallel-transported one) over
/// 2π, `Wr` the Gauss double integral of the continued centerline, summed exactly over pairs of
/// straight segments (Klenin & Langowski 2000: the solid angle of the quadrangle the two
/// segments span, over 4π). For the same end clamps, Lk is unchanged by any motion in which the
/// rod passes neither through itself nor over an end, and jumps by ±2 when it does: comparing
/// Lk before and after a motion, or between neighbouring equilibria of a branch, catches a
/// passage that [`ContactMonitor`] sampled too coarsely to see.
pub fn linking_number(st: &RodState) -> Real {
    let n = st.n_edges();
    let twist: Real = (1..n).map(|i| st.twist(i)).sum::<Real>() / (2.0 * PI);
    let mut pts = Vec::with_capacity(n + 3);
    let t0 = st.tangent(0);
    let t1 = st.tangent(n - 1);
    pts.push(st.node(0) - LINKING_RAY * t0);
    pts.extend((0..=n).map(|i| st.node(i)));
    pts.push(st.node(n) + LINKING_RAY * t1);
    let m = pts.len() - 1;
    let mut wr = 0.0;
    for i in 0..m {
        for j in i + 2..m {
            wr += segment_pair_writhe(&pts[i], &pts[i + 1], &pts[j], &pts[j + 1]);
        }
    }
    twist + 2.0 * wr
}

/// The writhe contribution `Ω/(4π)` of the segment pair `r1r2`, `r3r4` (Klenin & Langowski
/// 2000, eq. 13–15); 0 for (nearly) coplanar pairs.
fn segment_pair_writhe(r1: &Vec3, r2: &Vec3, r3: &Vec3, r4: &Vec3) -> Real {
    let (r13, r14, r23, r24) = (r3 - r1, r4 - r1, r3 - r2, r4 - r2);
    let unit = |v: Vec3| {
        let l = v.norm();
        (l > crate::math::tol::TINY).then(|| v / l)
    };
    let (Some(n1), Some(n2), Some(n3), Some(n4)) = (
        unit(r13.cross(&r14)),
        unit(r14.cross(&r24)),
        unit(r24.cross(&r23)),
        unit(r23.cross(&r13)),
    ) else {
        return 0.0;
    };
    let asin = |x: Real| x.clamp(-1.0, 1.0).asin();
    let omega = asin(n1.dot(&n2)) + asin(n2.dot(&n3)) + asin(n3.dot(&n4)) + asin(n4.dot(&n1));
    let sign = (r4 - r3).cross(&(r2 - r1)).dot(&r13);
    if sign == 0.0 {
        return 0.0;
    }
    omega.copysign(sign) / (4.0 * PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rod(nodes: &[Vec3]) -> RodState {
        RodState::from_nodes(nodes, &vec![0.0; nodes.len() - 1], &Vec3::z()).unwrap()
    }

    /// A zig-zag of 4 edges whose last edge sweeps across the first, above then below it.
    fn crossing_pair(z: Real) -> RodState {
        rod(&[
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(0.0, 1.0, z),
            Vec3::new(0.0, -1.0, z),
        ])
    }

    #[test]
    fn a_crossing_is_seen_between_two_states_and_a_near_miss_by_distance() {
        let mut m = ContactMonitor::new(4, 0.01);
        assert_eq!(m.observe(&crossing_pair(0.3)), None);
        let c = m.observe(&crossing_pair(-0.3)).expect("crossing");
        assert_eq!(c.edges, (0, 3));
        assert!(c.crossed && (c.distance - 0.3).abs() < 1e-12, "{c:?}");
        // Without the previous state only the distance counts.
        m.reset();
        assert_eq!(m.observe(&crossing_pair(-0.3)), None);
        let c = m.observe(&crossing_pair(-0.005)).expect("contact");
        assert!(!c.crossed && (c.distance - 0.005).abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn lines_meeting_beyond_the_edges_are_not_a_crossing() {
        // The last edge passes under the first one's line at x = 3, outside the edge.
        let at = |z: Real| {
            rod(&[
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(3.0, 2.0, z),
                Vec3::new(3.0, 1.0, z),
                Vec3::new(3.0, -1.0, z),
            ])
        };
        let mut m = ContactMonitor::new(4, 0.01);
        assert_eq!(m.observe(&at(0.3)), None);
        assert_eq!(m.observe(&at(-0.3)), None);
    }

    #[test]
    fn a_loop_slipping_over_the_clamped_end_is_seen() {
        // The last edge sweeps across the line of the clamp's continuation (x < 0).
        let at = |z: Real| {
            rod(&[
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, z),
                Vec3::new(-0.5, 1.0, z),
                Vec3::new(-0.5, -1.0, z),
            ])
        };
        let mut m = ContactMonitor::new(4, 0.01);
        assert_eq!(m.observe(&at(0.2)), None);
        let c = m.observe(&at(-0.2)).expect("crossing");
        assert_eq!(c.edges, (-1, 3));
        assert!(c.crossed);
        assert!(c.to_string().contains("the clamp's continuation"), "{c}");
    }

    #[test]
    fn linking_number_counts_twist_and_jumps_by_two_at_a_crossing() {
        // A straight rod: Lk is its twist.
        let n = 20;
        let nodes: Vec<Vec3> = (0..=n)
            .map(|i| Vec3::new(0.0, 0.0, i as Real / n as Real))
            .collect();
        let theta: Vec<Real> = (0..n)
            .map(|j| 4.0 * PI * j as Real / (n - 1) as Real)
            .collect();
        let st = RodState::from_nodes(&nodes, &theta, &Vec3::x()).unwrap();
        assert!(
            (linking_number(&st) - 2.0).abs() < 1e-9,
            "{}",
            linking_number(&st)
        );
        // An untwisted rod whose edge 4 is pushed through edge 2: the crossing changes the
        // writhe of the continued curve by 2, and Lk with it (the twist is continuous).
        let bent = |x: Real| {
            let mut p: Vec<Vec3> = vec![
                Vec3::new(0.0, 0.0, -0.4),
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(0.5, 0.0, 0.4),
                Vec3::new(0.5, 0.0, -0.2),
                Vec3::new(x, 0.3, 0.1),
                Vec3::new(x, -0.3, 0.1),
                Vec3::new(0.0, 0.0, 0.3),
                Vec3::new(0.0, 0.0, 0.7),
            ];
            p[4].x = x;
            p[5].x = x;
            let th = vec![0.0; p.len() - 1];
            RodState::from_nodes(&p, &th, &Vec3::y()).unwrap()
        };
        // Just before and after the crossing at x = 0.5 (and, for contrast, a step as small
        // away from it: continuous).
        let lk = |x| linking_number(&bent(x));
        let jump = lk(0.501) - lk(0.499);
        let smooth = lk(0.401) - lk(0.399);
        assert!((jump.abs() - 2.0).abs() < 0.02, "{jump}");
        assert!(smooth.abs() < 0.02, "{smooth}");
    }
}
