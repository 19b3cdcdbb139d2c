//! The DER elastic energy `E = E_s + E_b + E_t` of a [`RodState`], its gradient and its banded
//! Hessian (shared by statics and dynamics).
//!
//! - [`stretch`]: `E_s = Σ_{j=0}^{n−1} ½ k_s ē_j (|e_j|/ē_j − 1)²`;
//! - [`bend`]: `E_b = Σ_{i=1}^{n−1} k_b/(2 l̄_i)·(2 tan(φ_i/2))²`;
//! - [`twist`]: `E_t = Σ_{i=1}^{n−1} k_t/(2 l̄_i)·(θ_i − θ_{i−1} + m^ref_i)²`.
//!
//! All three sum over every edge/interior node, including those whose DOFs a boundary condition
//! fixes (their contribution is then constant or couples to free DOFs, as it must).
//!
//! # Contract
//! The state's reference frames must be up to date with `q`
//! ([`RodState::update_reference`] after every change of positions). The gradient and the
//! Hessian are then the exact first and second derivatives, at `q`, of the energy as a function
//! of the DOF vector with reference frames time-parallel transported from `q` — i.e. exactly
//! what a Newton iteration needs. [`energy`] at another `q'` (after `update_reference`) is the
//! value of that same function.
//!
//! # Allocation
//! [`gradient`], [`hessian`] and [`energy_gradient_hessian`] write into caller-owned buffers
//! (a `&mut [Real]` of length `4n+3` and a [`BandedSym`] of that dimension with half-bandwidth
//! [`HALF_BANDWIDTH`]) and allocate nothing: local stencils live on the stack.
//!
//! ```
//! use helixreach::math::Vec3;
//! use helixreach::rod::{energy, Material, Rod, RodState};
//! // A straight, untwisted rod is a zero-energy state with zero gradient.
//! let n = 5;
//! let rod = Rod::uniform(n, 0.2, Material::nondimensional(0.3, 1e4).unwrap()).unwrap();
//! let nodes: Vec<Vec3> = (0..=n).map(|i| Vec3::new(0.0, 0.0, 0.2 * i as f64)).collect();
//! let state = RodState::from_nodes(&nodes, &vec![0.0; n], &Vec3::x()).unwrap();
//! assert!(energy::energy(&rod, &state).abs() < 1e-20);
//! let mut g = vec![1.0; rod.n_dofs()];
//! energy::gradient(&rod, &state, &mut g);
//! assert!(g.iter().all(|v| v.abs() < 1e-9));
//! ```

pub mod bend;
pub mod stretch;
pub mod twist;

use super::banded::{BandedSym, HALF_BANDWIDTH};
use super::params::Rod;
use super::state::RodState;
use crate::math::{Mat3, Real, Vec3};
use bend::EdgePairDerivatives;

/// Total elastic energy (see the module contract).
pub fn energy(rod: &Rod, s: &RodState) -> Real {
    let mat = &rod.material;
    let n = rod.n_edges();
    let mut e = 0.0;
    for j in 0..n {
        e += stretch::edge_energy(&s.edge(j), rod.stretch_rest_length(j), mat.stretch);
    }
    for i in 1..n {
        let l = rod.voronoi_length(i);
        e += bend::node_energy(&s.edge(i - 1), &s.edge(i), 0.5 * mat.bend / l);
        e += twist::node_energy(s.twist(i), 0.5 * mat.twist / l);
    }
    e
}

/// The energy split `(E_s, E_b, E_t)`.
pub fn energy_parts(rod: &Rod, s: &RodState) -> (Real, Real, Real) {
    let mat = &rod.material;
    let n = rod.n_edges();
    let (mut es, mut eb, mut et) = (0.0, 0.0, 0.0);
    for j in 0..n {
        es += stretch::edge_energy(&s.edge(j), rod.stretch_rest_length(j), mat.stretch);
    }
    for i in 1..n {
        let l = rod.voronoi_length(i);
        eb += bend::node_energy(&s.edge(i - 1), &s.edge(i), 0.5 * mat.bend / l);
        et += twist::node_energy(s.twist(i), 0.5 * mat.twist / l);
    }
    (es, eb, et)
}

/// Gradient `∂E/∂q` into `g` (length `4n+3`, overwritten).
pub fn gradient(rod: &Rod, s: &RodState, g: &mut [Real]) {
    assemble(rod, s, Some(g), None);
}

/// Hessian `∂²E/∂q²` into `h` (dimension `4n+3`, half-bandwidth [`HALF_BANDWIDTH`], overwritten).
pub fn hessian(rod: &Rod, s: &RodState, h: &mut BandedSym) {
    assemble(rod, s, None, Some(h));
}

/// Energy, gradient and Hessian in one pass (buffers overwritten); returns the energy.
pub fn energy_gradient_hessian(rod: &Rod, s: &RodState, g: &mut [Real], h: &mut BandedSym) -> Real {
    assemble(rod, s, Some(g), Some(h))
}

/// Add the 3×3 block `m` at local position block `(r, c)` (3×3 offsets `4r`, `4c`) of a
/// row-major `k × k` local matrix.
#[inline]
fn put3(loc: &mut [Real], k: usize, r: usize, c: usize, m: &Mat3, scale: Real) {
    for a in 0..3 {
        for b in 0..3 {
            loc[(4 * r + a) * k + 4 * c + b] += scale * m[(a, b)];
        }
    }
}

/// Scatter edge-pair derivatives (w.r.t. `e⁻ = x_i − x_{i−1}`, `e⁺ = x_{i+1} − x_i`) onto the
/// 11-DOF stencil `[x_{i−1}, θ_{i−1}, x_i, θ_i, x_{i+1}]`, scaled by `scale`.
#[inline]
fn scatter_pair_hessian(loc: &mut [Real; 121], d: &EdgePairDerivatives, scale: Real) {
    let (hmm, hmp, hpp) = (&d.h_mm, &d.h_mp, &d.h_pp);
    let hpm = hmp.transpose();
    let b00 = *hmm;
    let b01 = -hmm + hmp;
    let b02 = -hmp;
    let b11 = hmm - hmp - hpm + hpp;
    let b12 = hmp - hpp;
    let b22 = *hpp;
    let k = 11;
    put3(loc, k, 0, 0, &b00, scale);
    put3(loc, k, 0, 1, &b01, scale);
    put3(loc, k, 1, 0, &b01.transpose(), scale);
    put3(loc, k, 0, 2, &b02, scale);
    put3(loc, k, 2, 0, &b02.transpose(), scale);
    put3(loc, k, 1, 1, &b11, scale);
    put3(loc, k, 1, 2, &b12, scale);
    put3(loc, k, 2, 1, &b12.transpose(), scale);
    put3(loc, k, 2, 2, &b22, scale);
}

/// Node-position gradients `(x_{i−1}, x_i, x_{i+1})` of edge-pair gradients.
#[inline]
fn pair_to_nodes(gm: &Vec3, gp: &Vec3) -> [Vec3; 3] {
    [-gm, gm - gp, *gp]
}

fn assemble(
    rod: &Rod,
    s: &RodState,
    mut g: Option<&mut [Real]>,
    mut h: Option<&mut BandedSym>,
) -> Real {
    let mat = &rod.material;
    let n = rod.n_edges();
    if let Some(g) = g.as_deref_mut() {
        assert_eq!(g.len(), rod.n_dofs());
        g.iter_mut().for_each(|v| *v = 0.0);
    }
    if let Some(h) = h.as_deref_mut() {
        assert!(h.dim() == rod.n_dofs() && h.half_bandwidth() == HALF_BANDWIDTH);
        h.fill_zero();
    }
    let mut total = 0.0;
    // Stretching: 7-DOF stencil [x_j, θ_j, x_{j+1}] at offset 4j (nothing at k_s = 0, the
    // inextensible rod of `rod::inextensible`).
    let stretch_edges = if mat.stretch == 0.0 { 0 } else { n };
    for j in 0..stretch_edges {
        let (e, ge, he) = stretch::edge(&s.edge(j), rod.stretch_rest_length(j), mat.stretch);
        total += e;
        let o = 4 * j;
        if let Some(g) = g.as_deref_mut() {
            for a in 0..3 {
                g[o + a] -= ge[a];
                g[o + 4 + a] += ge[a];
            }
        }
        if let Some(h) = h.as_deref_mut() {
            let mut loc = [0.0; 49];
            put3(&mut loc, 7, 0, 0, &he, 1.0);
            put3(&mut loc, 7, 1, 0, &he, -1.0);
            put3(&mut loc, 7, 1, 1, &he, 1.0);
            h.add_block(o, 7, &loc);
        }
    }
    // Bending and twisting: 11-DOF stencil at offset 4(i−1).
    for i in 1..n {
        let (em, ep) = (s.edge(i - 1), s.edge(i));
        let l = rod.voronoi_length(i);
        let wb = 0.5 * mat.bend / l;
        let wt = 0.5 * mat.twist / l;
        let o = 4 * (i - 1);
        if h.is_none() {
            // Gradient only (line searches): no second derivatives computed.
            let (eb, gbm, gbp) = bend::node_gradient(&em, &ep, wb);
            let m = s.twist(i);
            total += eb + wt * m * m;
            if let Some(g) = g.as_deref_mut() {
                let (tm, tp) = twist::reference_twist_gradient(&em, &ep);
                let c = 2.0 * wt * m;
                let gb = pair_to_nodes(&gbm, &gbp);
                let gt = pair_to_nodes(&tm, &tp);
                for slot in 0..3 {
                    for a in 0..3 {
                        g[o + 4 * slot + a] += gb[slot][a] + c * gt[slot][a];
                    }
                }
                g[o + 3] -= c;
                g[o + 7] += c;
            }
            continue;
        }
        let db = bend::node(&em, &ep, wb);
        let m = s.twist(i);
        total += db.energy + wt * m * m;
        let dm = twist::reference_twist_derivatives(&em, &ep);
        // Gradient of m on the stencil.
        let mut gm = [0.0; 11];
        let gx = pair_to_nodes(&dm.g_m, &dm.g_p);
        for (slot, v) in gx.iter().enumerate() {
            for a in 0..3 {
                gm[4 * slot + a] = v[a];
            }
        }
        gm[3] = -1.0;
        gm[7] = 1.0;
        if let Some(g) = g.as_deref_mut() {
            let gb = pair_to_nodes(&db.g_m, &db.g_p);
            for (slot, v) in gb.iter().enumerate() {
                for a in 0..3 {
                    g[o + 4 * slot + a] += v[a];
                }
            }
            let c = 2.0 * wt * m;
            for (r, v) in gm.iter().enumerate() {
                g[o + r] += c * v;
            }
        }
        if let Some(h) = h.as_deref_mut() {
            let mut loc = [0.0; 121];
            scatter_pair_hessian(&mut loc, &db, 1.0);
            scatter_pair_hessian(&mut loc, &dm, 2.0 * wt * m);
            for r in 0..11 {
                for c in 0..=r {
                    loc[r * 11 + c] += 2.0 * wt * gm[r] * gm[c];
                }
            }
            h.add_block(o, 11, &loc);
        }
    }
    total
}
