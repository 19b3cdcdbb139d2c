//! Discrete Elastic Rods dynamics ([architecture §3](crate::architecture); the seed paper §II.B–C, §III.D):
//! the rod clamped at one end, the other end driven along a ray `(κ, τ, ω) = s·S̄` at finite
//! speed, integrated in time by implicit Euler, the instability seen as a jump of the helix
//! error e.
//!
//! | module | holds |
//! |---|---|
//! | [`presets`] | [`PhysicalRod`] (E, ν, ρ, h, L), the paper's `paper-sim` and `nitinol` rods, the gravito-bending length |
//! | [`centerline`] | [`centerline::Centerline`]: node positions and material frames kept along a run, and their [`centerline::Placement`] on a rig |
//! | [`stepper`] | [`Stepper`]: implicit Euler with lumped masses, Newton on the banded system, gravity, damping, moving clamp |
//! | [`jitter`] | [`Jitter`]: a seeded, smooth random deviation of the imposed end |
//! | [`ray`] | [`simulate_ray`]: the manipulation along a ray, the recorded series and the detected s_dyn |
//! | [`detect`] | [`detect::detect`]: the documented instability rule on the series e(s) |
//!
//! The elastic energies, their gradient and banded Hessian, the LDLᵀ factorization and the
//! clamps are the shared ones of [`crate::rod`]; nothing is re-derived here.
//!
//! ```
//! use helixreach::boundary::der::{critical_s, DerBoundaryParams};
//! use helixreach::directions::Direction;
//! use helixreach::rod::dynamics::{simulate_ray, SimParams};
//! // A fast, coarse run along [1,1,1]/√3 (n = 16, v = 0.5/s): the rod loses the helix a
//! // little after the DER statics s* of the same n, delayed by inertia.
//! let dir = Direction::new(1.0, 1.0, 1.0).unwrap();
//! let p = SimParams { n_edges: 16, dt: 0.02, speed: 0.5, record_ds: 0.02, ..Default::default() };
//! let sim = simulate_ray(&dir, &p, &mut |_| {}).unwrap();
//! let stat = critical_s(&dir, &DerBoundaryParams { n_edges: 16, tol_rel: 1e-4, ..Default::default() })
//!     .unwrap()
//!     .s_star;
//! let delay = sim.s_dyn() / stat - 1.0;
//! assert!(delay > 0.0 && delay < 0.1, "{} vs {stat}", sim.s_dyn());
//! ```

pub mod centerline;
pub mod detect;
pub mod jitter;
pub mod presets;
pub mod ray;
pub mod stepper;
pub mod study;

pub use jitter::Jitter;
pub use presets::{PhysicalRod, Preset};
pub use ray::{simulate_ray, Phase, Sample, SimParams, Simulation, Unload};
pub use stepper::{EndClamp, Stepper, StepperParams};
