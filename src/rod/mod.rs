//! Discrete Elastic Rods ([architecture §3](crate::architecture); Bergou et al. 2008/2010, the seed paper §II.B):
//! energies with analytic gradients and banded Hessians, shared by statics and dynamics.
//!
//! | module | holds |
//! |---|---|
//! | [`params`] | [`Material`] stiffnesses (bend `k_b`, twist `k_t = c·k_b`, stretch `k_s`), [`Rod`] rest geometry |
//! | [`state`] | [`RodState`]: the DOF vector `[x₀, θ₀, x₁, …, x_n]`, reference frames (time-parallel), reference twist |
//! | [`energy`] | `E_s`, `E_b`, `E_t`, gradient, banded Hessian (allocation-free assembly) |
//! | [`banded`] | [`BandedSym`] storage and [`BandedLdlt`] factorization with inertia |
//! | [`clamp`] | clamped boundary conditions from an end pose (fixed or time-varying) |
//! | [`statics`] | Newton equilibrium on the free DOFs and the stability (inertia) test |
//! | [`inextensible`] | the same for the inextensible rod: Newton on the banded KKT system, stability from its inertia |
//! | [`gravity`] | when gravity matters: the gravito-bending length ratio and the criteria |
//! | [`workspace`] | [`Workspace`]: every buffer a Newton iteration needs, sized once per rod |
//!
//! # DOF order and bandwidth
//! Node `i` at `q[4i..4i+3]`, twist θ_j of edge `j` at `q[4j+3]`; every energy stencil spans at
//! most 11 consecutive DOFs, so the Hessian has half-bandwidth [`banded::HALF_BANDWIDTH`] = 10.
//!
//! # For the dynamics
//! Implicit Euler needs, per Newton iteration, `energy::energy_gradient_hessian` on the full DOF
//! vector (add `M/Δt²` to the diagonal of the Hessian and the inertial term to the gradient),
//! then [`BandedLdlt::factor`] on [`Rod::free_range_clamped`] and a solve. Impose the moving
//! end with [`clamp::impose`] (positions + θ_{n−1}, continuous in θ) before each step, and call
//! [`RodState::update_reference`] after every position update.

pub mod banded;
pub mod clamp;
pub mod dynamics;
pub mod energy;
pub mod gravity;
pub mod inextensible;
pub mod params;
pub mod state;
pub mod statics;
pub mod workspace;

pub use banded::{BandedLdlt, BandedSym};
pub use params::{Material, Rod};
pub use state::RodState;
pub use workspace::Workspace;
