//! Buffers for energy assembly, factorization and Newton iterations, sized once per rod.

use super::banded::{BandedLdlt, BandedSym, HALF_BANDWIDTH};
use super::params::Rod;
use super::state::RodState;
use crate::math::Real;

/// Every buffer a Newton iteration on a rod of `n` edges needs (gradient, banded Hessian, its
/// LDLᵀ, step, trial state). Create once with [`Workspace::new`] and reuse: the iteration
/// allocates nothing.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Gradient (length `4n+3`).
    pub grad: Vec<Real>,
    /// Banded Hessian (dimension `4n+3`, half-bandwidth 10).
    pub hess: BandedSym,
    /// LDLᵀ of a principal sub-block of the Hessian.
    pub ldlt: BandedLdlt,
    /// Step on the free DOFs.
    pub step: Vec<Real>,
    /// A trial state for line searches.
    pub trial: Option<RodState>,
    /// A constant external force `F` on every DOF (length `4n+3`), or empty for none: the static
    /// solvers ([`super::statics::solve`], [`super::inextensible::solve`]) add its potential
    /// `−Fᵀq` to the energy (gradient `−F`, Hessian 0), e.g. gravity
    /// ([`Workspace::set_weight`]).
    pub external: Vec<Real>,
}

impl Workspace {
    /// Buffers for `rod`.
    pub fn new(rod: &Rod) -> Self {
        let nd = rod.n_dofs();
        Workspace {
            grad: vec![0.0; nd],
            hess: BandedSym::zeros(nd, HALF_BANDWIDTH),
            ldlt: BandedLdlt::new(nd, HALF_BANDWIDTH),
            step: vec![0.0; nd],
            trial: None,
            external: Vec::new(),
        }
    }

    /// Set [`Workspace::external`] to the lumped weight of `rod`: node `i` carries
    /// `l_i·w` with `l_i = (ē_{i−1} + ē_i)/2` its share of the rest length (half an edge at the
    /// end nodes) and `w` the weight per unit length (nondimensionally `ρA·g·L³/k_b` times the
    /// direction of gravity); twists carry none. `w = 0` clears it. The same lumping as the
    /// dynamics' masses, so a static equilibrium is a rest state of the dynamics.
    pub fn set_weight(&mut self, rod: &Rod, w: &crate::math::Vec3) {
        if *w == crate::math::Vec3::zeros() {
            self.external.clear();
            return;
        }
        let n = rod.n_edges();
        self.external.clear();
        self.external.resize(rod.n_dofs(), 0.0);
        for i in 0..=n {
            let l = 0.5
                * (if i > 0 { rod.rest_length(i - 1) } else { 0.0 }
                    + if i < n { rod.rest_length(i) } else { 0.0 });
            for a in 0..3 {
                self.external[4 * i + a] = l * w[a];
            }
        }
    }

    /// Whether the buffers fit `rod`.
    pub fn fits(&self, rod: &Rod) -> bool {
        self.grad.len() == rod.n_dofs()
    }
}
