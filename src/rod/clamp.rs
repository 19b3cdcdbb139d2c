//! Clamped boundary conditions: an end pose (position + material frame) imposed on the first or
//! last edge.
//!
//! A clamp fixes the two nodes of an end edge and its twist angle, so the edge's tangent is the
//! clamp's third director and its material frame is the clamp frame. Where the clamped edge sits
//! relative to the clamp point is a discretization choice ([`ClampPlacement`]):
//!
//! - [`ClampPlacement::Straddle`] (default): the clamped edge is *centred* on the clamp point,
//!   half inside and half outside the elastic rod: `x₀ = p − (ē/2)t`, `x₁ = p + (ē/2)t`. With
//!   `n` edges of length `ē = L/(n−1)`, edge `j` is centred at arc length `s = jē`, so edges 0 and
//!   n−1 sit exactly at the clamps (s = 0 and s = L), the interior nodes `i = 1..n−1` at
//!   `s = (i − ½)ē` are the midpoints of the `n − 1` cells covering `[0, L]`, and the energy
//!   sums are midpoint rules. The clamp tangent and material frame are imposed where the
//!   continuum imposes them, and the discrete boundary is `O(1/n²)` accurate.
//! - [`ClampPlacement::Inside`] (the seed paper): the clamped edge is the first/last edge of a rod
//!   of `n` edges of length `ē = L/n` covering `[0, L]`: `x₀ = p`, `x₁ = p + ē t` (and
//!   `x_n = p_end`, `x_{n−1} = p_end − ē t_end`). The straight clamped edge replaces a curved
//!   piece of rod of length `ē`, which shifts the boundary by `O(1/n)`.
//!
//! The measured orders are in `examples/der_convergence.rs` and `docs/RESULTS.md`.
//!
//! # Time-varying clamps
//! [`impose`] sets the two nodes, re-transports the reference frames ([`RodState::update_reference`])
//! and sets θ of the clamped edge to the angle that turns the (transported) reference director
//! into the clamp's first director, chosen within π of its previous value. Successive calls
//! with slowly varying poses therefore track the total twist continuously (a motor angle ω/c of
//! several turns is reached by continuity, never wrapped to (−π, π]).

use super::state::RodState;
use crate::math::{Mat3, Real, Vec3};

/// Where the clamped end edges sit relative to the clamp points (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ClampPlacement {
    /// Clamped edge centred on the clamp point (`ē = L/(n−1)`, `O(1/n²)`).
    #[default]
    Straddle,
    /// Clamped edge inside the rod, ending at the clamp point (`ē = L/n`, the seed paper, `O(1/n)`).
    Inside,
}

impl ClampPlacement {
    /// Rest edge length for a rod of length `length` with `n` edges.
    pub fn edge_length(self, n: usize, length: Real) -> Real {
        match self {
            ClampPlacement::Straddle => length / (n as Real - 1.0),
            ClampPlacement::Inside => length / n as Real,
        }
    }

    /// Arc length of node `i` (may lie outside `[0, L]` for [`ClampPlacement::Straddle`]).
    pub fn node_arclength(self, n: usize, i: usize, length: Real) -> Real {
        let h = self.edge_length(n, length);
        match self {
            ClampPlacement::Straddle => (i as Real - 0.5) * h,
            ClampPlacement::Inside => i as Real * h,
        }
    }

    /// Arc length of the centre of edge `j`.
    pub fn edge_arclength(self, n: usize, j: usize, length: Real) -> Real {
        let h = self.edge_length(n, length);
        match self {
            ClampPlacement::Straddle => j as Real * h,
            ClampPlacement::Inside => (j as Real + 0.5) * h,
        }
    }
}

/// Which end of the rod a clamp holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// Edge 0 (nodes 0, 1, θ₀).
    Start,
    /// Edge n−1 (nodes n−1, n, θ_{n−1}).
    End,
}

/// The two node positions of the clamped edge for a clamp at point `p` with tangent `t` and
/// rest edge length `h`.
pub fn clamp_nodes(placement: ClampPlacement, end: End, p: &Vec3, t: &Vec3, h: Real) -> [Vec3; 2] {
    match (placement, end) {
        (ClampPlacement::Straddle, _) => [p - 0.5 * h * t, p + 0.5 * h * t],
        (ClampPlacement::Inside, End::Start) => [*p, p + h * t],
        (ClampPlacement::Inside, End::End) => [p - h * t, *p],
    }
}

/// Impose a clamp at `end`: the point `p` (the rod's end point, at arc length 0 or L) and the
/// material frame `frame = [m¹ m² t]` (columns, orthonormal). `h` is the rest length of the
/// clamped edge. Returns `false` (state unchanged in its frames) if an edge degenerates.
pub fn impose(
    state: &mut RodState,
    placement: ClampPlacement,
    end: End,
    p: &Vec3,
    frame: &Mat3,
    h: Real,
) -> bool {
    let n = state.n_edges();
    let t: Vec3 = frame.column(2).into();
    let m1: Vec3 = frame.column(0).into();
    let [a, b] = clamp_nodes(placement, end, p, &t, h);
    let (i0, j) = match end {
        End::Start => (0, 0),
        End::End => (n - 1, n - 1),
    };
    state.set_node(i0, &a);
    state.set_node(i0 + 1, &b);
    if !state.update_reference() {
        return false;
    }
    let th = state.theta_for_director(j, &m1, state.theta(j));
    state.set_theta(j, th);
    true
}
