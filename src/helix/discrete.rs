//! The discrete helix: n + 1 nodes on the curve, edge tangents, and discrete parallel transport
//! of a frame from edge to edge (the seed paper's construction of the "intermediate" end frame,
//! and the reference frame of Discrete Elastic Rods).
//!
//! # Discrete parallel transport
//! A frame on edge i−1 (tangent a = t_{i−1}) is carried to edge i (tangent b = t_i) by the
//! **minimal rotation** taking a to b (rotation about a × b by the angle between them). The seed
//! paper writes it with the unit binormal b̂ = a×b/|a×b|, which is 0/0 when consecutive tangents
//! are parallel (a straight stretch, κ = 0, or a fine discretization in floating point). Here
//! the rotation is applied in the Rodrigues form that never normalizes the axis:
//!
//! R·d = d + v×d + v×(v×d)/(1 + c),  v = a × b,  c = a·b,
//!
//! which is exact and smooth through v = 0 (parallel tangents: R = I) and loses no digits while
//! 1 + c is not small. For c ≤ −0.9 (turns of more than ≈ 154° per edge, a meaningless
//! discretization but still a defined input) it switches to the product of two reflections,
//! R = S_h·S_a with h = (a + b)/|a + b| and S_x = I − 2xxᵀ, whose error grows only like
//! ε/|a + b|; for exactly antiparallel tangents (|a + b| below 10⁻¹⁵⁰), where the minimal rotation
//! is not unique, it turns by π about the frame's own d1 (made perpendicular to a). After each
//! step the frame is re-orthonormalized (d3 = b exactly, d1 projected and normalized,
//! d2 = d3 × d1), so rounding does not accumulate over many edges.
//!
//! # Convergence
//! The frame on edge i approximates the continuous transported frame at the edge's mid arc
//! length s = (i + ½)/n with error O(1/n²) (tests/helix.rs measures the order).

use super::Helix;
use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3};

/// `n_edges + 1` nodes r(i/n), i = 0..=n, on the centerline (nondimensional, L = 1).
/// `n_edges = 0` gives the single node r(0) = 0.
///
/// ```
/// use helixreach::helix::{discrete, Helix};
/// let h = Helix::new(1.0, 2.0, 0.0).unwrap();
/// let q = discrete::nodes(&h, 10);
/// assert_eq!(q.len(), 11);
/// assert_eq!(q[10], h.position(1.0));
/// ```
pub fn nodes(h: &Helix, n_edges: usize) -> Vec<Vec3> {
    let mut out = vec![Vec3::zeros(); n_edges + 1];
    fill_nodes(h, &mut out);
    out
}

/// Fill `out` with `out.len()` nodes at s = i/(len − 1) (allocation-free form of [`nodes`]).
pub fn fill_nodes(h: &Helix, out: &mut [Vec3]) {
    let n = out.len().saturating_sub(1).max(1) as Real;
    for (i, q) in out.iter_mut().enumerate() {
        *q = h.position(i as Real / n);
    }
}

/// Unit edge tangents t_i = (q_{i+1} − q_i)/|q_{i+1} − q_i|, one per edge. A zero-length or
/// non-finite edge is an error naming the edge.
pub fn edge_tangents(nodes: &[Vec3]) -> Result<Vec<Vec3>> {
    let mut out = Vec::with_capacity(nodes.len().saturating_sub(1));
    for (i, w) in nodes.windows(2).enumerate() {
        let e = w[1] - w[0];
        let len = e.norm();
        if !(len > 0.0 && len.is_finite()) {
            return Err(Error::invalid(
                format!("edge {i}"),
                len,
                "edge length must be finite and > 0",
            ));
        }
        out.push(e / len);
    }
    Ok(out)
}

/// Rotate `d` by the minimal rotation taking the unit vector `a` to the unit vector `b` (see the
/// module docs for the stable forms). `fallback_axis` is used only when `a` and `b` are exactly
/// antiparallel: the rotation is then by π about its component perpendicular to `a` (or any
/// perpendicular axis if that vanishes).
#[inline]
pub fn transport_vector(d: &Vec3, a: &Vec3, b: &Vec3, fallback_axis: &Vec3) -> Vec3 {
    crate::math::parallel_transport(d, a, b, fallback_axis)
}

/// Carry the frame `frame` = [d1 d2 d3] (d3 its tangent) to the unit tangent `t` by the minimal
/// rotation, then re-orthonormalize: the result has d3 = `t` exactly, d1 ⊥ t unit, d2 = t × d1.
///
/// ```
/// use helixreach::helix::discrete::transport_frame;
/// use helixreach::math::{Mat3, Vec3};
/// // Parallel tangents: the frame is unchanged (no 0/0 as in the b = t×t'/|t×t'| form).
/// let q = transport_frame(&Mat3::identity(), &Vec3::z());
/// assert_eq!(q, Mat3::identity());
/// ```
pub fn transport_frame(frame: &Mat3, t: &Vec3) -> Mat3 {
    let a: Vec3 = frame.column(2).into_owned();
    let d1_old: Vec3 = frame.column(0).into_owned();
    let d1 = transport_vector(&d1_old, &a, t, &d1_old);
    let d1 = d1 - t.dot(&d1) * t;
    let d1 = d1 / d1.norm();
    Mat3::from_columns(&[d1, t.cross(&d1), *t])
}

/// Parallel transport of `first` (a frame whose d3 need not equal `tangents[0]`) onto every
/// edge tangent in turn: frame i = transport(frame i−1 (or `first`), t_i). Writes into `out`
/// (cleared first), one frame per tangent.
pub fn transport_along(first: &Mat3, tangents: &[Vec3], out: &mut Vec<Mat3>) {
    out.clear();
    let mut f = *first;
    for t in tangents {
        f = transport_frame(&f, t);
        out.push(f);
    }
}

/// A discretized helix: nodes, unit edge tangents and parallel-transported edge frames.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteHelix {
    /// n + 1 nodes r(i/n) (nondimensional).
    pub nodes: Vec<Vec3>,
    /// n unit edge tangents.
    pub tangents: Vec<Vec3>,
    /// n edge frames [d1 d2 t_i]: the clamp frame (identity, whose d3 is the exact tangent T₀)
    /// transported onto t_0, then edge to edge.
    pub frames: Vec<Mat3>,
}

impl DiscreteHelix {
    /// Discretize `h` with `n_edges` ≥ 1 edges.
    ///
    /// ```
    /// use helixreach::helix::{discrete::DiscreteHelix, Helix};
    /// let h = Helix::new(4.0, 3.0, 0.0).unwrap();
    /// let d = DiscreteHelix::new(&h, 400).unwrap();
    /// // The last edge's frame is close to the continuous transported frame at its midpoint.
    /// let q = h.transported_frame(1.0 - 0.5 / 400.0);
    /// assert!((d.frames[399] - q).norm() < 1e-3);
    /// ```
    pub fn new(h: &Helix, n_edges: usize) -> Result<Self> {
        if n_edges == 0 {
            return Err(Error::invalid("n_edges", 0, "must be >= 1"));
        }
        let nodes = nodes(h, n_edges);
        let tangents = edge_tangents(&nodes)?;
        let mut frames = Vec::with_capacity(n_edges);
        transport_along(&Mat3::identity(), &tangents, &mut frames);
        Ok(DiscreteHelix {
            nodes,
            tangents,
            frames,
        })
    }

    /// The last edge's frame carried onto the exact end tangent T(1) by one more minimal
    /// rotation (comparable with the continuous [`Helix::transported_frame`] at s = 1).
    pub fn end_frame(&self, h: &Helix) -> Mat3 {
        let t_end: Vec3 = h.frenet_frame(1.0).column(2).into_owned();
        let last = self.frames.last().copied().unwrap_or_else(Mat3::identity);
        transport_frame(&last, &t_end)
    }
}
