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
        }
    }

    /// Whether the buffers fit `rod`.
    pub fn fits(&self, rod: &Rod) -> bool {
        self.grad.len() == rod.n_dofs()
    }
}
