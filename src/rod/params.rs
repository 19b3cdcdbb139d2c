//! Material stiffnesses and the rest geometry of a discrete rod.
//!
//! [`Material`] holds the three stiffnesses of the isotropic, naturally straight rod:
//! bending `k_b = EI`, twisting `k_t = GJ` and stretching `k_s = EA`. In the nondimensional
//! setting of the stability boundary (rod length L = 1, [`Material::nondimensional`]) `k_b = 1`,
//! `k_t = c = 1/(1+ν)` and `k_s` is a large penalty that makes the rod nearly inextensible (the
//! continuum reference is inextensible; the relative effect on the equilibrium is `O(F/k_s)`
//! with `F` the axial force, `O(s²)` along a ray). [`Material::circular`] gives the physical
//! values of a solid circular rod for the dynamics: `EI = Eπh⁴/4`, `GJ = EI/(1+ν)`,
//! `EA = Eπh²`.
//!
//! [`Rod`] holds the discretization: `n` edges, their rest lengths `ē_j` and the Voronoi
//! lengths `l̄_i = (ē_{i−1} + ē_i)/2` of the interior nodes `i = 1..n−1`, which weight the
//! bending and twisting energies.

use crate::error::{require_positive, Error, Result};
use crate::math::Real;

/// Stiffnesses of an isotropic, naturally straight rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Bending stiffness `k_b = EI` (N·m², or 1 nondimensionally).
    pub bend: Real,
    /// Twisting stiffness `k_t = GJ` (N·m², or `c = 1/(1+ν)` nondimensionally).
    pub twist: Real,
    /// Stretching stiffness `k_s = EA` (N, or a large nondimensional penalty).
    pub stretch: Real,
}

/// Default nondimensional stretching stiffness `k_s/(k_b/L²)` of [`Material::nondimensional`]:
/// a rod of slenderness h/L = 2·10⁻³ (`k_s = 4/(h/L)²`). Its measured effect on the DER
/// boundary is δs* ≈ 15/k_s (1.4·10⁻⁶ relative along (1, 1, 1)/√3), far below the
/// discretization error at practical n.
pub const DEFAULT_STRETCH: Real = 1e6;

impl Material {
    /// Nondimensional stiffnesses: `k_b = 1`, `k_t = c = 1/(1+ν)`, `k_s = stretch`.
    /// ν must be in (−1, 0.5] and `stretch` finite and > 0.
    ///
    /// ```
    /// let m = helixreach::rod::Material::nondimensional(0.25, 1e6).unwrap();
    /// assert_eq!(m.bend, 1.0);
    /// assert!((m.twist - 0.8).abs() < 1e-15);
    /// assert!(helixreach::rod::Material::nondimensional(-1.0, 1e6).is_err());
    /// ```
    pub fn nondimensional(nu: Real, stretch: Real) -> Result<Self> {
        let c = twist_ratio(nu)?;
        require_positive("stretch", stretch)?;
        Ok(Material {
            bend: 1.0,
            twist: c,
            stretch,
        })
    }

    /// A solid circular rod of Young's modulus `e` (Pa), Poisson ratio `nu` and radius `h` (m).
    pub fn circular(e: Real, nu: Real, h: Real) -> Result<Self> {
        require_positive("youngs_modulus", e)?;
        require_positive("radius", h)?;
        let c = twist_ratio(nu)?;
        let ei = e * std::f64::consts::PI * h.powi(4) / 4.0;
        Ok(Material {
            bend: ei,
            twist: c * ei,
            stretch: e * std::f64::consts::PI * h * h,
        })
    }

    /// Check all three stiffnesses are finite and > 0.
    pub fn validate(&self) -> Result<()> {
        require_positive("bend", self.bend)?;
        require_positive("twist", self.twist)?;
        require_positive("stretch", self.stretch)?;
        Ok(())
    }
}

pub use crate::math::twist_ratio;

/// The discretization of a rod: `n ≥ 2` edges with rest lengths, and the Voronoi lengths of the
/// interior nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Rod {
    n: usize,
    rest: Vec<Real>,
    stretch_rest: Vec<Real>,
    voronoi: Vec<Real>,
    /// The stiffnesses.
    pub material: Material,
}

impl Rod {
    /// A rod of `n_edges` edges all of rest length `edge_length`.
    pub fn uniform(n_edges: usize, edge_length: Real, material: Material) -> Result<Self> {
        require_positive("edge_length", edge_length)?;
        Self::new(vec![edge_length; n_edges], material)
    }

    /// A rod with the given rest edge lengths (at least 2 edges, each finite and > 0).
    pub fn new(rest_lengths: Vec<Real>, material: Material) -> Result<Self> {
        if rest_lengths.len() < 2 {
            return Err(Error::invalid(
                "n_edges",
                rest_lengths.len(),
                "a rod needs at least 2 edges",
            ));
        }
        for &l in &rest_lengths {
            require_positive("rest_length", l)?;
        }
        material.validate()?;
        let n = rest_lengths.len();
        let mut voronoi = vec![0.0; n + 1];
        for i in 1..n {
            voronoi[i] = 0.5 * (rest_lengths[i - 1] + rest_lengths[i]);
        }
        Ok(Rod {
            n,
            stretch_rest: rest_lengths.clone(),
            rest: rest_lengths,
            voronoi,
            material,
        })
    }

    /// Number of edges `n` (nodes `0..=n`).
    pub fn n_edges(&self) -> usize {
        self.n
    }

    /// Length of the DOF vector, `4n + 3`.
    pub fn n_dofs(&self) -> usize {
        4 * self.n + 3
    }

    /// Rest length `ē_j` of edge `j`.
    pub fn rest_length(&self, j: usize) -> Real {
        self.rest[j]
    }

    /// The length at which edge `j` carries no axial force in `E_s` (initially `ē_j`).
    ///
    /// It differs from [`Rod::rest_length`] only when set by [`Rod::set_stretch_rest_length`]:
    /// an augmented-Lagrangian solve (the DER boundary) shifts it so that the penalty force
    /// `k_s(ℓ/ē'_j − 1)` is carried at `ℓ = ē_j`, making the equilibrium inextensible without
    /// a stiff `k_s`. The Voronoi lengths (bending and twisting weights) and the dynamics'
    /// masses keep `ē_j`.
    pub fn stretch_rest_length(&self, j: usize) -> Real {
        self.stretch_rest[j]
    }

    /// Set the stretching rest length of edge `j` (see [`Rod::stretch_rest_length`]); `len`
    /// must be finite and > 0.
    pub fn set_stretch_rest_length(&mut self, j: usize, len: Real) -> Result<()> {
        require_positive("stretch_rest_length", len)?;
        self.stretch_rest[j] = len;
        Ok(())
    }

    /// Reset every stretching rest length to the rest length `ē_j`.
    pub fn reset_stretch_rest_lengths(&mut self) {
        self.stretch_rest.copy_from_slice(&self.rest);
    }

    /// Voronoi length `l̄_i` of interior node `i` (0 at the end nodes).
    pub fn voronoi_length(&self, i: usize) -> Real {
        self.voronoi[i]
    }

    /// DOF index of node `i`'s x coordinate (`4i`).
    #[inline]
    pub fn node_dof(i: usize) -> usize {
        4 * i
    }

    /// DOF index of edge `j`'s twist angle θ_j (`4j + 3`).
    #[inline]
    pub fn twist_dof(j: usize) -> usize {
        4 * j + 3
    }

    /// The free DOFs of a rod clamped at both ends (nodes 0, 1, θ₀ and nodes n−1, n, θ_{n−1}
    /// fixed): the contiguous range `7 .. 4n−4` (θ₁ through θ_{n−2}), of length `4n − 11`.
    /// Contiguity keeps the free Hessian a principal sub-band.
    pub fn free_range_clamped(&self) -> std::ops::Range<usize> {
        7..(4 * self.n - 4)
    }
}
