//! The configuration of a discrete rod: the DOF vector, the reference frames and the reference
//! twist.
//!
//! # DOF vector
//! `q = [x₀, θ₀, x₁, θ₁, …, θ_{n−1}, x_n]` (length `4n + 3`): node `i` at `q[4i..4i+3]`, the
//! twist of edge `j` at `q[4j+3]`. Edge `e_j = x_{j+1} − x_j`, tangent `t_j = e_j/|e_j|`.
//!
//! # Frames
//! Each edge carries a reference frame `[d¹_j, d²_j, t_j]` (`d²_j = t_j × d¹_j`), and its
//! material frame is the reference frame turned by θ_j about `t_j`:
//! `m¹_j = cos θ_j d¹_j + sin θ_j d²_j`.
//!
//! Reference frames follow the DER convention (Bergou et al. 2010): when the positions change,
//! each `d¹_j` is *time-parallel transported* from the old tangent to the new one
//! ([`RodState::update_reference`]), so the material frame moves with the edge without
//! twisting about it while θ_j stays fixed. The energy is therefore a function of `q` given the
//! reference frames of the last update (the "base"); the gradient and Hessian of
//! [`crate::rod::energy`] are its exact derivatives at the base, so call
//! [`RodState::update_reference`] after every change of `q` (each Newton iterate) before
//! evaluating them.
//!
//! # Reference twist
//! At interior node `i` (`1 ≤ i ≤ n−1`) the reference twist `m^ref_i` is the signed angle about
//! `t_i` from `P_{t_{i−1}→t_i}(d¹_{i−1})` to `d¹_i`, where `P_{a→b}` is the parallel transport
//! (the rotation about `a × b` taking `a` to `b`). It is unwrapped continuously between updates
//! (no jump of 2π), and the discrete twist is `m_i = θ_i − θ_{i−1} + m^ref_i`.
//!
//! # Parallel transport
//! [`parallel_transport`] uses `P_{a→b} v = (a·b) v + (a×b)×v + ((a×b)·v)/(1 + a·b)·(a×b)`,
//! which is smooth through `a = b` (the seed paper's formula divides by `|a×b|` and is undefined
//! there). It is [`crate::math::parallel_transport`] (the crate's one transport); exactly
//! antiparallel tangents have no unique transport and get the rotation by π about the component
//! of x perpendicular to `a`.

use crate::math::{Mat3, Real, Vec3};

/// The first director `d1` is refused when its part normal to the first tangent is below this
/// fraction of its length (parallel to the tangent: no frame can be built from it).
const PARALLEL_D1_REL: Real = 1e-12;

/// `P_{a→b}(v)`: the parallel transport of `v` from unit vector `a` to unit vector `b` (the
/// minimal rotation taking `a` to `b`). See the module docs.
///
/// ```
/// use helixreach::math::Vec3;
/// use helixreach::rod::state::parallel_transport;
/// let (a, b) = (Vec3::z(), Vec3::x());
/// let v = parallel_transport(&Vec3::x(), &a, &b);
/// assert!((v + Vec3::z()).norm() < 1e-15);
/// assert!((parallel_transport(&Vec3::y(), &a, &b) - Vec3::y()).norm() < 1e-15);
/// ```
#[inline]
pub fn parallel_transport(v: &Vec3, a: &Vec3, b: &Vec3) -> Vec3 {
    crate::math::parallel_transport(v, a, b, &Vec3::x())
}

/// Signed angle from `u` to `v` about the unit axis `t` (both ⊥ `t`), in (−π, π].
#[inline]
pub fn signed_angle(u: &Vec3, v: &Vec3, t: &Vec3) -> Real {
    u.cross(v).dot(t).atan2(u.dot(v))
}

/// Wrap an angle into (−π, π].
#[inline]
pub fn wrap_angle(a: Real) -> Real {
    let two_pi = std::f64::consts::TAU;
    let r = a - two_pi * (a / two_pi).round();
    if r <= -std::f64::consts::PI {
        r + two_pi
    } else {
        r
    }
}

/// A rod configuration: DOFs plus reference frames and reference twist (see module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RodState {
    n: usize,
    /// The DOF vector `[x₀, θ₀, x₁, …, x_n]` (length `4n + 3`). After changing positions call
    /// [`RodState::update_reference`].
    pub q: Vec<Real>,
    d1: Vec<Vec3>,
    tangent: Vec<Vec3>,
    ref_twist: Vec<Real>,
}

impl RodState {
    /// A state from node positions (n+1 ≥ 3 points) and edge twists (n angles), with
    /// *space-parallel* reference frames: `d¹_0 = first_d1` (projected onto the plane ⊥ t₀ and
    /// normalized) and `d¹_j = P_{t_{j−1}→t_j}(d¹_{j−1})`, so every reference twist is 0.
    ///
    /// Returns `None` if the lengths disagree, an edge has zero length or `first_d1` is parallel
    /// to the first tangent.
    pub fn from_nodes(nodes: &[Vec3], theta: &[Real], first_d1: &Vec3) -> Option<Self> {
        let n = theta.len();
        if nodes.len() != n + 1 || n < 2 {
            return None;
        }
        let mut q = vec![0.0; 4 * n + 3];
        for (i, x) in nodes.iter().enumerate() {
            q[4 * i..4 * i + 3].copy_from_slice(x.as_slice());
        }
        for (j, th) in theta.iter().enumerate() {
            q[4 * j + 3] = *th;
        }
        let mut tangent = Vec::with_capacity(n);
        for j in 0..n {
            let e = nodes[j + 1] - nodes[j];
            let l = e.norm();
            if l.is_nan() || l <= 0.0 || !l.is_finite() {
                return None;
            }
            tangent.push(e / l);
        }
        let d = first_d1 - tangent[0] * tangent[0].dot(first_d1);
        let dn = d.norm();
        if dn.is_nan() || dn <= PARALLEL_D1_REL * first_d1.norm() {
            return None;
        }
        let mut d1 = Vec::with_capacity(n);
        d1.push(d / dn);
        for j in 1..n {
            let v = parallel_transport(&d1[j - 1], &tangent[j - 1], &tangent[j]);
            d1.push(v.normalize());
        }
        Some(RodState {
            n,
            q,
            d1,
            tangent,
            ref_twist: vec![0.0; n + 1],
        })
    }

    /// Copy `other` into `self`, reusing `self`'s allocations when the sizes match.
    pub fn copy_from(&mut self, other: &RodState) {
        self.n = other.n;
        self.q.clone_from(&other.q);
        self.d1.clone_from(&other.d1);
        self.tangent.clone_from(&other.tangent);
        self.ref_twist.clone_from(&other.ref_twist);
    }

    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.n
    }

    /// Node `i`.
    #[inline]
    pub fn node(&self, i: usize) -> Vec3 {
        Vec3::new(self.q[4 * i], self.q[4 * i + 1], self.q[4 * i + 2])
    }

    /// Set node `i` (then call [`RodState::update_reference`]).
    #[inline]
    pub fn set_node(&mut self, i: usize, x: &Vec3) {
        self.q[4 * i..4 * i + 3].copy_from_slice(x.as_slice());
    }

    /// Twist angle θ_j of edge `j`.
    #[inline]
    pub fn theta(&self, j: usize) -> Real {
        self.q[4 * j + 3]
    }

    /// Set θ_j.
    #[inline]
    pub fn set_theta(&mut self, j: usize, th: Real) {
        self.q[4 * j + 3] = th;
    }

    /// Edge vector `e_j = x_{j+1} − x_j` of the current positions.
    #[inline]
    pub fn edge(&self, j: usize) -> Vec3 {
        self.node(j + 1) - self.node(j)
    }

    /// Tangent of edge `j` at the last reference update.
    #[inline]
    pub fn tangent(&self, j: usize) -> Vec3 {
        self.tangent[j]
    }

    /// First reference director `d¹_j` (at the last reference update).
    #[inline]
    pub fn reference_d1(&self, j: usize) -> Vec3 {
        self.d1[j]
    }

    /// Reference twist at interior node `i` (at the last reference update).
    #[inline]
    pub fn reference_twist(&self, i: usize) -> Real {
        self.ref_twist[i]
    }

    /// Discrete twist `m_i = θ_i − θ_{i−1} + m^ref_i` at interior node `i`.
    #[inline]
    pub fn twist(&self, i: usize) -> Real {
        self.theta(i) - self.theta(i - 1) + self.ref_twist[i]
    }

    /// Material frame `[m¹_j m²_j t_j]` (columns) of edge `j` (at the last reference update).
    pub fn material_frame(&self, j: usize) -> Mat3 {
        let t = self.tangent[j];
        let d1 = self.d1[j];
        let d2 = t.cross(&d1);
        let (s, c) = self.theta(j).sin_cos();
        let m1 = c * d1 + s * d2;
        let m2 = t.cross(&m1);
        Mat3::from_columns(&[m1, m2, t])
    }

    /// The angle θ that gives edge `j` the material first director `m1` (projected ⊥ t_j), chosen
    /// within π of `near` (continuity). Use after [`RodState::update_reference`] to impose a
    /// clamped material frame.
    pub fn theta_for_director(&self, j: usize, m1: &Vec3, near: Real) -> Real {
        let t = self.tangent[j];
        let a = signed_angle(&self.d1[j], m1, &t);
        near + wrap_angle(a - near)
    }

    /// Time-parallel transport the reference frames to the current edge tangents and recompute
    /// the reference twists (unwrapped within π of their previous values). Returns `false` (and
    /// leaves the frames untouched) if an edge has zero or non-finite length.
    pub fn update_reference(&mut self) -> bool {
        for j in 0..self.n {
            let e = self.edge(j);
            let l = e.norm();
            if l.is_nan() || l <= 0.0 || !l.is_finite() {
                return false;
            }
        }
        for j in 0..self.n {
            let t_new = self.edge(j).normalize();
            let d = parallel_transport(&self.d1[j], &self.tangent[j], &t_new);
            // Re-orthonormalize against round-off drift.
            let d = (d - t_new * t_new.dot(&d)).normalize();
            self.d1[j] = d;
            self.tangent[j] = t_new;
        }
        for i in 1..self.n {
            let a = reference_twist_angle(
                &self.d1[i - 1],
                &self.tangent[i - 1],
                &self.d1[i],
                &self.tangent[i],
            );
            let old = self.ref_twist[i];
            self.ref_twist[i] = old + wrap_angle(a - old);
        }
        true
    }
}

/// Signed angle about `t_b` from `P_{t_a→t_b}(d_a)` to `d_b` (in (−π, π]).
#[inline]
pub fn reference_twist_angle(d_a: &Vec3, t_a: &Vec3, d_b: &Vec3, t_b: &Vec3) -> Real {
    let u = parallel_transport(d_a, t_a, t_b);
    signed_angle(&u, d_b, t_b)
}
